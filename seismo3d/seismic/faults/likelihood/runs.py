"""The one driver of both fault likelihoods (the scan and the network), in memory (:func:`likelihood_in_memory`: the
declared steps on one block, the whole cube) and by blocks (:func:`likelihood_by_blocks`): the output Zarr group
and its work folder (:class:`~seismo3d.seismic.blocks.stores.StoreRun`), the manifest that a resumed run must match,
the plan of an interrupted run kept, the dask scheduler, the likelihood's declared steps run in their order, the
coordinates and the saturated fraction written, and the output renamed into place when complete.

Each likelihood writes its steps once, as a function of a run (:func:`~seismo3d.seismic.faults.likelihood.scan.
run_scan`, :func:`~seismo3d.seismic.faults.likelihood.learned.run_learned`): given a
:class:`~seismo3d.seismic.blocks.stores.StoreRun` and the blocks of a memory plan it runs by blocks (here); given a
:class:`~seismo3d.seismic.blocks.executor.MemoryRun` and the plan of one block, the whole cube, it runs in memory
(:func:`~seismo3d.seismic.faults.likelihood.scan.fault_likelihood`,
:func:`~seismo3d.seismic.faults.likelihood.learned.learned_fault_likelihood`).
"""

from __future__ import annotations

import pathlib
from collections.abc import Callable

from ...blocks.executor import MemoryRun
from ...blocks.options import ChunkOptions
from ...blocks.stores import StoreRun
from ..result import ChunkedLikelihood

__all__ = ["likelihood_by_blocks", "likelihood_in_memory"]


def likelihood_in_memory(x, *, opt, plan: dict, steps: Callable, section: bool = False, progress: bool = False,
                         **kwargs) -> tuple:
    """Run a fault likelihood's declared steps in memory, each on one block, the whole cube
    (:class:`~seismo3d.seismic.blocks.executor.MemoryRun`).

    Parameters
    ----------
    x : (n_inlines, n_xlines, n_samples) float32 ndarray
        The amplitudes; a section as ``(n_traces, 1, n_samples)`` with ``section``.
    opt : dataclass
        The likelihood's options.
    plan : dict
        The plan of one block, the whole cube (the likelihood's ``whole_plan``).
    steps : callable
        ``steps(run, x, opt, plan, **kwargs) -> float``: the likelihood's steps in their order, returning the
        saturated fraction (as for :func:`likelihood_by_blocks`).
    section : bool
        ``x`` is a section: the results are returned as ``(n_traces, n_samples)``.
    progress : bool
        Report progress per step.
    **kwargs
        Passed to ``steps``.

    Returns
    -------
    likelihood, strike_deg, dip_deg : float32 ndarray
        Of ``x``'s shape (a section's without its crossline axis).
    saturated : float
        The saturated fraction ``steps`` returned.
    """
    run = MemoryRun(x.shape, progress=progress)
    saturated = steps(run, x, opt, plan, **kwargs)
    arrays = [run.arrays.pop(name) for name in ("likelihood", "strike_deg", "dip_deg")]
    return (*(a[:, 0] if section else a for a in arrays), saturated)


def likelihood_by_blocks(x, output, *, opt, plan: dict, steps: Callable, start: Callable, method: str,
                         chunking: ChunkOptions, coords: dict | None = None, progress: bool = False,
                         manifest: dict | None = None, attrs: dict | None = None) -> ChunkedLikelihood:
    """Run a fault likelihood's declared steps block by block into a Zarr group, resumably.

    Parameters
    ----------
    x : (n_inlines, n_xlines, n_samples) dask.array.Array
        The amplitudes, chunks of whole traces
        (:func:`~seismo3d.seismic.blocks.executor.trace_cube`).
    output : str or os.PathLike
        Output Zarr group, created; ``OUTPUT.partial`` and ``OUTPUT.work`` of an unfinished run of the same cube,
        options and method are resumed.
    opt : dataclass
        The likelihood's options (recorded in the manifest).
    plan : dict
        The blocks planned under the memory limit (``shape``, ``tile`` and the likelihood's sides); an unfinished
        run's plan replaces it, so that a resumed run keeps its blocks.
    steps : callable
        ``steps(run, x, opt, plan) -> float``: the likelihood's steps in their order, returning the saturated
        fraction.
    start : callable
        ``start(run, manifest, plan)``: the output and the work arrays
        (:meth:`~seismo3d.seismic.blocks.stores.StoreRun.start_output`).
    method : str
        Written in the output's attributes.
    chunking : ChunkOptions
        The dask scheduler and the blocks computed at once.
    coords : dict, optional
        ``inline``, ``crossline``, ``sample`` coordinates (and ``sample_unit``) written beside the arrays.
    progress : bool
        Report progress per block.
    manifest : dict, optional
        More entries of the manifest (what a resumed run must match besides the shape, options and plan).
    attrs : dict, optional
        More attributes of the output group (JSON-serialisable, e.g. the input's name and the store's id), written
        with the others before it is renamed into place: a store that exists holds all of them.

    Returns
    -------
    ChunkedLikelihood

    Raises
    ------
    InputError
        ``output`` exists, or the scheduler cannot be reached.
    EarlierStoresError
        The work folder holds an unfinished run of another cube or other options.
    """
    shape = tuple(int(n) for n in x.shape)
    out = pathlib.Path(output)
    run = StoreRun(out, chunking, progress)
    manifest = run.manifest_for(shape, opt, plan, **(manifest or {}))
    plan = manifest["plan"]  # resuming: the interrupted run's blocks
    start(run, manifest, plan)
    with run.scheduled():
        saturated = steps(run, x, opt, plan)
    run.describe(coords, {"method": method, "saturated_fraction": saturated})
    run.finish(attrs)
    return ChunkedLikelihood(out, shape, dict(run.computed), dict(run.resumed), saturated, dict(run.seconds))
