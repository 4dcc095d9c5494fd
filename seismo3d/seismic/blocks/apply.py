"""One block of a declared step (:class:`~seismo3d.seismic.blocks.plan.BlockStep` with ``inputs`` / ``outputs``): its
inputs read around the block, the step's algorithm called on arrays, the block's core of what it returns written
into the step's output stores, its sparse lists saved, and its marker written last (:func:`apply_block`).

The algorithm knows nothing of stores, memory limits or resumption: it takes arrays (the block grown by the step's
halo) and returns a :class:`BlockOutput`. The same declared steps run on a whole array in memory as one block
(:func:`apply_in_memory`: inputs and outputs in a dict, no marker), which
:class:`~seismo3d.seismic.blocks.executor.MemoryRun` runs behind the interface of the executor's
:class:`~seismo3d.seismic.blocks.executor.BlockRun` (``run_step``, the steps' lists): one run of the steps serves a
cube in memory and a cube by blocks.

Why not :func:`dask.array.map_overlap` to read the blocks? Its halo is cut from the neighbouring chunks (even with
``boundary='none'``), so each block's task depends on its 8 neighbours' whole chunks, each held until the last block
that needs it has run, and its halo is concatenated into a new array: with chunks the size of the blocks, the inputs of
several blocks are held to compute one (dask 2026.8 does not fuse the slices into the reads). On a 768 x 768 x 128
float32 Zarr array in blocks of 128 traces with a halo of 16 (12.5 MiB a block), one worker, a block function holding 3
copies of its block (``benchmarks/block_reads.py``): ``map_overlap`` peaked 260 MiB above the process, dask holding up
to 104 MiB of input arrays between tasks; the same blocks read as dask slices of the region around each (only the chunks
the region crosses, released with the task) 103 MiB, 12 MiB held; :func:`dask.array.map_blocks` whose function slices
its region from the store (``block_info``) 137 MiB, nothing held (glibc's arenas of Zarr's reading threads: 82 MiB with
one arena, ``MALLOC_ARENA_MAX=1``). A step's blocks are planned from a memory limit
(:mod:`~seismo3d.seismic.blocks.plan`), so the executor reads each block's region by slicing (dask for the cube, Zarr
for the stores), and adds what dask lacks: several stores written at once, per-step halos and block sizes, a small
result reduced or gathered per block, and a marker per block after its data so that an interrupted run resumes from the
finished blocks (dask recomputes every block of an interrupted ``to_zarr``).
"""

from __future__ import annotations

import json
import pathlib
from dataclasses import dataclass, field

import numpy as np

from ..._atomic import atomic_path
from .plan import CUBE, BlockStep

__all__ = ["BlockOutput", "BlockPlace", "apply_block", "apply_in_memory", "gather", "load_lists", "save_lists",
           "whole_place", "write_marker"]


@dataclass(frozen=True)
class BlockPlace:
    """Where a block is: its core and the region read around it, trace indices of the cube.

    Attributes
    ----------
    block : (int, int, int, int)
        ``(i0, i1, j0, j1)``: the block's core, the traces it writes (half-open).
    region : (int, int, int, int)
        ``(a0, a1, b0, b1)``: the traces read (the core grown by the step's halo, clipped to the cube, or the step's
        own ``region``).
    """

    block: tuple
    region: tuple

    @property
    def origin(self) -> tuple:
        """``(a0, b0)``: the first inline and crossline of the region read."""
        return self.region[0], self.region[2]

    @property
    def core(self) -> tuple:
        """``(rows, cols)`` slices of the core within the region read."""
        i0, i1, j0, j1 = self.block
        a0, b0 = self.origin
        return slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0)

    @property
    def read(self) -> tuple:
        """``(rows, cols)`` slices of the region read within the cube."""
        a0, a1, b0, b1 = self.region
        return slice(a0, a1), slice(b0, b1)

    @property
    def target(self) -> tuple:
        """``(rows, cols)`` slices of the core within the cube."""
        i0, i1, j0, j1 = self.block
        return slice(i0, i1), slice(j0, j1)


@dataclass(frozen=True, eq=False)
class BlockOutput:
    """What a step's algorithm returns for one block.

    Attributes
    ----------
    arrays : dict
        ``{output name: (m0, m1, ...) ndarray or None}``: over the region read (cut to the core by the executor) or
        over the core; None writes nothing (the store keeps its fill value).
    summary : dict
        A small JSON-serialisable result (counts, sums, a range): the block's marker, reduced by the caller.
    lists : dict
        ``{name: ndarray}``: sparse lists of the block (seed candidates, cells), saved in the step's folder of the
        run (:func:`save_lists`) and read back by later steps or the caller (:func:`load_lists`, :func:`gather`).
    """

    arrays: dict = field(default_factory=dict)
    summary: dict = field(default_factory=dict)
    lists: dict = field(default_factory=dict)


def write_marker(path, payload: dict) -> None:
    """Write a block's marker (its small JSON result) atomically: a marker that exists is complete.

    Parameters
    ----------
    path : str or os.PathLike
        The marker file (:meth:`~seismo3d.seismic.blocks.executor.BlockRun.marker`).
    payload : dict
        JSON-serialisable result of the block, returned again when a resumed run skips it.
    """
    with atomic_path(str(path)) as tmp, open(tmp, "w") as fh:
        json.dump(payload, fh)


def save_lists(folder, block, lists: dict) -> None:
    """Save a block's sparse lists, one ``.npy`` each in ``folder/<i0>-<j0>/``, atomically (a file that exists is
    complete; the block's marker, written after them, says that all are).

    Parameters
    ----------
    folder : str or os.PathLike
        The step's folder of lists.
    block : tuple
        ``(i0, i1, j0, j1)``; items 0 and 2 name the block.
    lists : dict
        ``{name: ndarray}``.
    """
    path = pathlib.Path(folder) / f"{block[0]}-{block[2]}"
    path.mkdir(parents=True, exist_ok=True)
    for name, values in lists.items():
        with atomic_path(str(path / f"{name}.npy")) as tmp, open(tmp, "wb") as fh:
            np.save(fh, np.asarray(values))


def load_lists(folder, block, names, *, mmap_mode=None) -> dict:
    """A block's sparse lists saved by :func:`save_lists`.

    Parameters
    ----------
    folder : str or os.PathLike
    block : tuple
        ``(i0, i1, j0, j1)``.
    names : iterable of str
    mmap_mode : {None, 'r'}
        ``'r'``: memory-mapped, read row by row when indexed (:func:`numpy.load`).

    Returns
    -------
    dict
        ``{name: ndarray}``.
    """
    path = pathlib.Path(folder) / f"{block[0]}-{block[2]}"
    return {name: np.load(path / f"{name}.npy", mmap_mode=mmap_mode) for name in names}


def gather(reader, blocks, names) -> dict:
    """The sparse lists of ``blocks`` concatenated in the blocks' order.

    Parameters
    ----------
    reader : callable
        ``reader(block, names) -> {name: ndarray}``: a block's lists (a run's ``lists_reader``, e.g.
        :func:`load_lists` of the step's folder).
    blocks : list of tuple
    names : iterable of str

    Returns
    -------
    dict
        ``{name: ndarray}``; None for a name when there are no blocks.
    """
    parts = [reader(b, names) for b in blocks]
    return {name: np.concatenate([q[name] for q in parts]) if parts else None for name in names}


def apply_block(window, place: BlockPlace, marker, *, step: BlockStep, paths: dict, lists, args: tuple = ()) -> dict:
    """Run a declared step on one block: read its inputs, call its algorithm, write the core of its outputs, save
    its lists, then its marker.

    Parameters
    ----------
    window : (m0, m1, n_samples) ndarray or None
        The input cube's region (:attr:`BlockPlace.region`), read by dask, when :data:`~seismo3d.seismic.blocks.plan.
        CUBE` is among the step's inputs.
    place : BlockPlace
    marker : str
        The block's marker file.
    step : BlockStep
        Its ``inputs``, ``outputs``, ``function`` and the flags ``place``, ``lazy``, ``trim``, ``combine``.
    paths : dict
        ``{array name: Zarr array path}`` of the run's stores (inputs and outputs).
    lists : str or None
        The step's folder of sparse lists (:func:`save_lists`).
    args : tuple
        Passed to the algorithm after the arrays.

    Returns
    -------
    dict
        The block's summary (also its marker's payload).
    """
    import zarr

    inputs = []
    for name in step.inputs:
        if name == CUBE:
            inputs.append(window)
            continue
        array = zarr.open_array(paths[name], mode="r")
        inputs.append(array if step.lazy else array[place.read])
    del window
    out = _compute(step, place, inputs, args)
    del inputs
    region = (place.region[1] - place.region[0], place.region[3] - place.region[2])
    for name, value in _outputs(step, out):
        if step.trim and tuple(value.shape[:2]) == region:
            value = value[place.core]
        store = zarr.open_array(paths[name], mode="r+")
        if step.combine is not None:
            value = step.combine(value, store[place.target])
        store[place.target] = value
    if out.lists:
        save_lists(lists, place.block, out.lists)
    write_marker(marker, out.summary)
    return out.summary


def whole_place(shape) -> BlockPlace:
    """The one block of a whole array: its core and the region read are all of its first two axes.

    Parameters
    ----------
    shape : tuple of int
        Of the array: ``(n_inlines, n_xlines, ...)`` (a section's ``(n_traces, n_samples)``: the block is then the
        whole section).

    Returns
    -------
    BlockPlace
    """
    n0, n1 = int(shape[0]), int(shape[1])
    return BlockPlace((0, n0, 0, n1), (0, n0, 0, n1))


def apply_in_memory(step: BlockStep, arrays: dict, *args, place: BlockPlace | None = None) -> BlockOutput:
    """Run a declared step on the whole array in memory as one block (:func:`whole_place` of its first input): the
    algorithm of :func:`apply_block` on the same inputs, its outputs set in ``arrays`` (combined with what is there
    when the step declares ``combine``), no marker written and no list saved.

    Parameters
    ----------
    step : BlockStep
        Its ``inputs``, ``outputs``, ``function`` and the flags ``place`` and ``combine`` (its halo is not needed:
        the block is the whole array).
    arrays : dict
        ``{array name: ndarray}``: the step's inputs by their declared names
        (:data:`~seismo3d.seismic.blocks.plan.CUBE` for the amplitudes; an input missing is None to the algorithm,
        as a store no step wrote holds only its fill value); its outputs are set in it by name.
    *args
        Passed to the algorithm after the arrays.
    place : BlockPlace, optional
        The one block and the region it reads, when they are not :func:`whole_place` of the first input (a step on
        another grid than the cube's, e.g. the fault network's: its block is the whole network grid, its region the
        whole cube); the inputs are used whole.

    Returns
    -------
    BlockOutput
        What the algorithm returned: its ``summary`` and ``lists`` (its arrays are in ``arrays``).

    """
    inputs = [arrays.get(name) for name in step.inputs]
    out = _compute(step, whole_place(inputs[0].shape) if place is None else place, inputs, args)
    del inputs
    for name, value in _outputs(step, out):
        arrays[name] = value if step.combine is None or name not in arrays else step.combine(value, arrays[name])
    return out


def _compute(step: BlockStep, place: BlockPlace, inputs: list, args: tuple) -> BlockOutput:
    """The step's algorithm on the block's arrays (the place first when the step asks for it)."""
    return step.function(*((place,) if step.place else ()), *inputs, *args)


def _outputs(step: BlockStep, out: BlockOutput):
    """``(store name, array)`` of each declared output the algorithm returned (None: not written)."""
    for name in step.outputs:
        key, name = (name, name) if isinstance(name, str) else name
        if out.arrays.get(key) is not None:
            yield name, out.arrays[key]
