""":func:`~seismo3d.seismic.faults.trace_faults` on a cube beyond the memory limit: the same checks and steps, run
block by block on dask into two resumable Zarr stores of a work folder.

The checks are those of the run in memory, from the same functions: the data's size; the memory the run needs and
the data judged from a sample of blocks (not seismic amplitudes, no lateral coherence:
:func:`~seismo3d.seismic.faults.blocks.preflight.judge_sample`), before any pass over the whole cube; its NaN / inf
samples (read as 0, with the same warning), constant data, clipped amplitudes and dead samples (the same refusal and
warnings, from passes over the blocks); then the fault likelihood
(:func:`~seismo3d.seismic.faults.blocks.scan_blocks.chunked_fault_likelihood` or the learned one) into
``fault_likelihood.zarr`` and the fault surfaces
(:func:`~seismo3d.seismic.faults.blocks.surface_blocks.chunked_fault_surfaces`: dead samples, saturation, ridges,
voting, thinning, thresholds, skins, throws, evidence) into ``fault_surfaces.zarr``. A finished likelihood of the same
source is reused; an unfinished one resumes.
"""

from __future__ import annotations

import pathlib
import time
import uuid

import numpy as np

from ...._progress import LOGGER
from ....errors import EarlierStoresError, InputError
from ...blocks.executor import release_memory
from ...io.zarr_store import consolidate
from ..checks import check_size
from ..surfaces.dead_samples import (
    DeadSampleOptions, check_varies, clipped_count, dead_samples, fill_values, warn_clipped, warn_dead,
    warn_non_finite,
)
from ..result import FaultInterpretation
from ..options import FaultTracingOptions
from .learned_blocks import chunked_learned_likelihood
from ...blocks.options import ChunkOptions
from .scan_blocks import chunked_fault_likelihood
from ...blocks.memory import in_memory_bytes, resident_memory, size_text, worker_baseline
from .surface_blocks import chunked_fault_surfaces
from .preflight import judge_sample, minimum_memory_limit

__all__ = ["LIKELIHOOD_STORE", "SURFACES_STORE", "check_block_run", "finite_cube", "trace_faults_by_blocks"]

LIKELIHOOD_STORE = "fault_likelihood.zarr"
SURFACES_STORE = "fault_surfaces.zarr"
_TILE = 32  # traces a side of the chunks of an array given in memory


def trace_faults_by_blocks(cube, opt: FaultTracingOptions, *, sample_interval: float, sample_unit: str,
                           memory_limit: int, work_dir, scheduler=None, source: str = "cube", coords=None,
                           progress: bool = True) -> FaultInterpretation:
    """Trace the faults of a 3D cube block by block (called by :func:`~seismo3d.seismic.faults.trace_faults`).

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) dask.array.Array or array_like
        Amplitudes, samples along the last axis (e.g. ``open_lazy(path).data``).
    opt : FaultTracingOptions
    sample_interval : float
    sample_unit : str
    memory_limit : int
        Bytes.
    work_dir : str or os.PathLike
        Existing folder of the Zarr stores ``fault_likelihood.zarr`` and ``fault_surfaces.zarr``.
    scheduler : str, optional
        ``dask.distributed`` scheduler address; default the local threads.
    source : str
        Name of the input, recorded in the stores (a likelihood of another source is not reused).
    coords : dict, optional
        Coordinates of the likelihood store (``inline``, ``crossline``, ``sample``, ``sample_unit``).
    progress : bool

    Returns
    -------
    FaultInterpretation
        Its arrays are Zarr arrays of the stores (``stores``).

    Raises
    ------
    InputError
        Constant data, a memory limit too small (the message names one that works), or stores of another input in
        ``work_dir``.
    UnsupportedDataError
        As :func:`~seismo3d.seismic.faults.trace_faults`.
    """
    import dask.array as da
    import zarr

    x = cube if isinstance(cube, da.Array) else da.from_array(np.asarray(cube), chunks=(_TILE, _TILE, -1))
    shape = tuple(int(n) for n in x.shape)
    check_size(shape, opt)
    x = check_block_run(_whole_traces(x), source, memory_limit, scheduler, opt)
    work_dir = pathlib.Path(work_dir)
    if not work_dir.is_dir():
        raise InputError(f"cannot write the fault stores into {work_dir}: it is not a folder; create it first")
    path = work_dir / LIKELIHOOD_STORE
    started = time.perf_counter()
    chunking = ChunkOptions(memory_limit=memory_limit, scheduler=scheduler)
    if path.exists():  # a finished likelihood of an earlier run of the same input: reused
        group = zarr.open_group(str(path), mode="r")
        if (group.attrs.get("source") != source or tuple(group["likelihood"].shape) != shape
                or group.attrs.get("likelihood", "scan") != opt.likelihood):
            raise EarlierStoresError(f"{path} holds the fault likelihood of another input; pick another output "
                                     "folder (-o) or delete it", [path])
        LOGGER.info("%s: reusing the finished fault likelihood in %s", source, path)
    else:
        held = resident_memory()
        LOGGER.info("%s: %d x %d x %d samples need about %.2f GiB in memory besides this process (%.2f GiB), more "
                    "than the memory limit of %.2f GiB allows: fault likelihood block by block into %s", source,
                    *shape, in_memory_bytes(shape) / 2**30, held / 2**30, memory_limit / 2**30, path.name)
        if opt.likelihood == "learned":
            chunked_learned_likelihood(x, path, options=opt.learned, coords=coords, progress=progress,
                                       chunking=chunking)
        else:
            chunked_fault_likelihood(x, path, options=opt.scan, coords=coords, progress=progress, chunking=chunking)
        # "id": this store, told apart from a later one at the same path (fault_surfaces.zarr records whose it is)
        zarr.open_group(str(path), mode="r+").attrs.update({"source": source, "likelihood": opt.likelihood,
                                                            "id": uuid.uuid4().hex})
        consolidate(path)
    seconds = {"fault likelihood": time.perf_counter() - started}
    started = time.perf_counter()
    surfaces = chunked_fault_surfaces(x, path, work_dir / SURFACES_STORE, options=opt, chunking=chunking,
                                      progress=progress)
    seconds.update(surfaces.seconds)  # the block steps computed in this call
    seconds["fault skins, throw and evidence"] = time.perf_counter() - started - sum(surfaces.seconds.values())
    zarr.open_group(str(surfaces.path), mode="r+").attrs["source"] = source
    consolidate(surfaces.path)
    LOGGER.info("%s: %d faults from %d seeds and %d thinned fault samples (thresholds %.3f, %.3f)", source,
                len(surfaces.faults), surfaces.n_seeds, surfaces.n_cells, *surfaces.thresholds)
    scan = zarr.open_group(str(path), mode="r")
    traced = zarr.open_group(str(surfaces.path), mode="r")
    return FaultInterpretation(likelihood=traced["likelihood"], strike_deg=scan["strike_deg"],
                               dip_deg=scan["dip_deg"], votes=traced["votes"], thin=traced["thin"],
                               thresholds=surfaces.thresholds, faults=surfaces.faults, throws=surfaces.throws,
                               evidence=surfaces.evidence, sample_interval=float(sample_interval),
                               sample_unit=sample_unit, stores={"likelihood": path, "surfaces": surfaces.path},
                               step_seconds=seconds)


def _whole_traces(x):
    """The lazy cube as float32 chunks of whole traces."""
    if len(x.chunks[2]) != 1:
        x = x.rechunk({2: -1})
    return x.astype(np.float32)


def finite_cube(x, dead: DeadSampleOptions | None = None):
    """The cube with NaN / inf read as 0 (warned, as in memory); constant data refused, clipped amplitudes and dead
    samples warned about (:mod:`~seismo3d.seismic.faults.surfaces.dead_samples`), from three passes over the blocks (the
    dead samples need the fill values of the whole cube).

    Parameters
    ----------
    x : (n_inlines, n_xlines, n_samples) float32 dask.array.Array
        Chunks of whole traces.
    dead : DeadSampleOptions, optional
        What counts as a dead sample (default
        :class:`~seismo3d.seismic.faults.surfaces.dead_samples.DeadSampleOptions`).

    Returns
    -------
    dask.array.Array
        ``x``, or ``x`` with its NaN / inf samples read as 0.

    Raises
    ------
    InputError
        Every sample equal (NaN read as 0).

    Warns
    -----
    Seismo3dWarning
        NaN / inf, clipped or dead samples (:func:`~seismo3d.seismic.faults.surfaces.dead_samples.clean_traces`'
        warnings).
    """
    import dask
    import dask.array as da

    finite = da.isfinite(x)
    cleaned = da.where(finite, x, np.float32(0.0))
    n_bad, lo, hi = dask.compute(da.sum(~finite), da.min(cleaned), da.max(cleaned))
    n = int(np.prod(x.shape, dtype=np.int64))
    warn_non_finite(int(n_bad), n)
    check_varies(float(lo), float(hi))
    x = cleaned if n_bad else x
    lo, hi = np.float32(lo), np.float32(hi)
    parts = [dask.delayed(_clipped_and_fills)(b, lo, hi, dead) for b in x.to_delayed().ravel()]
    parts = dask.compute(*parts)
    warn_clipped(sum(p[0] for p in parts), n - int(np.prod(x.shape[:-1], dtype=np.int64)), options=dead)
    fill = np.unique(np.concatenate([p[1] for p in parts]))
    counts = dask.compute(*[dask.delayed(_dead_counts)(b, fill, lo, hi, dead) for b in x.to_delayed().ravel()])
    warn_dead(sum(d[0] for d in counts), n, sum(d[1] for d in counts), options=dead)
    return x


def _clipped_and_fills(block, lo, hi, dead) -> tuple:
    """(clipped samples, fill values) of a block of whole traces."""
    block = np.asarray(block, np.float32)
    return clipped_count(block, lo, hi), fill_values(block, lo, hi, options=dead)


def _dead_counts(block, fill, lo, hi, options) -> tuple[int, int]:
    """(dead samples, dead traces) of a block of whole traces."""
    dead = dead_samples(np.asarray(block, np.float32), fill, lo, hi, options=options)
    return int(np.count_nonzero(dead)), int(np.count_nonzero(dead.all(axis=-1)))


def check_block_run(x, name: str, limit: int, scheduler, options: FaultTracingOptions):
    """Before any block of a run by blocks: the memory its smallest blocks need (at once); the data judged from a
    sample of blocks (not seismic amplitudes, no lateral coherence: the refusals of the run in memory, in seconds);
    the memory the seed candidates the sample predicts need; then the data's NaN, constant, clipped and dead samples
    (:func:`finite_cube`, passes over the whole cube).

    Parameters
    ----------
    x : (n_inlines, n_xlines, n_samples) dask.array.Array
    name : str
        The input, for messages.
    limit : int
        Memory limit, bytes.
    scheduler : str or None
    options : FaultTracingOptions

    Returns
    -------
    dask.array.Array
        ``x`` with NaN / inf read as 0 (:func:`finite_cube`).

    Raises
    ------
    UnsupportedDataError
        The sample refuses the data.
    InputError
        ``limit`` below what the run needs (the message names the smallest limit that works), or constant data.
    """
    shape = tuple(int(n) for n in x.shape)
    chunks = x.chunks

    def baseline() -> int:  # the process as it is now, and the input chunks a block reads
        return worker_baseline(ChunkOptions(memory_limit=limit, scheduler=scheduler),
                               4 * max(chunks[0]) * max(chunks[1]) * shape[2])

    _check_limit(name, shape, limit, minimum_memory_limit(shape, baseline=baseline(), options=options),
                 " for its smallest blocks alone")
    LOGGER.info("%s: judging the data from a sample of blocks", name)
    sample = judge_sample(x, options=options)  # before the passes over the whole cube: a refusal in seconds
    release_memory()  # the sample's arrays, before the process is measured again
    need = minimum_memory_limit(shape, baseline=baseline(), options=options, sample=sample)
    _check_limit(name, shape, limit, need, f" (with the ~{sample.candidates(shape)} seed candidates a sample "
                                           "of its blocks predicts)")
    return finite_cube(x, options.dead)


def _check_limit(name: str, shape: tuple, limit: int, need: int, why: str) -> None:
    """InputError naming the smallest memory limit that works when ``limit`` is below ``need``."""
    if need <= limit:
        return
    held = resident_memory()
    raise InputError(f"{name}: a block-by-block run of its {shape[0]} x {shape[1]} x {shape[2]} samples needs a "
                     f"memory limit of at least {size_text(need)}{why}, more than the {size_text(limit)} given "
                     f"(this process alone holds {size_text(held)}); pass memory_limit='{size_text(need)}' or more")
