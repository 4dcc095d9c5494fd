"""Fault surfaces: the steps of :func:`~seismo3d.seismic.faults.trace_faults` after the likelihood, declared once
(:func:`block_steps`) and run once (:class:`SurfaceRun`, in the order of
:func:`~seismo3d.seismic.faults.steps.surface_cells`) by either executor: block by block from a chunked likelihood
into Zarr stores (:func:`chunked_fault_surfaces`, the executor of :mod:`seismo3d.seismic.blocks`), or on the whole
array in memory as one block (:func:`memory_surface_run`, :class:`~seismo3d.seismic.blocks.executor.MemoryRun`), so
the faults do not depend on how the cube was run. Each step reads its block with its halo and writes the core; its
algorithm on a block is beside the one it runs:

ridges and seed candidates (``ridges.ridge_block``, the dead samples from the cube's
:class:`~seismo3d.seismic.amplitudes.CubeAmplitudes`), each seed's surface
once (``voting.surface_block``) and the votes of the surfaces reaching a block in id order (``voting.vote_block``),
thinning (``ridges.thin_block``) and thresholds from histograms (:mod:`seismo3d.seismic.blocks.statistics`), cells
(``ridges.cell_block``) linked into skins with their throws (:func:`~seismo3d.seismic.faults.steps.faults_from_cells`).
A section runs as a cube of one crossline (its ridges and thinning in 2D).
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass

import numba
import numpy as np

from ...._progress import no_progress
from ....errors import InputError
from ...blocks.executor import MemoryRun, trace_cube
from ...blocks.memory import resident_memory, size_text, worker_baseline
from ...blocks.options import ChunkOptions
from ...blocks.plan import (
    CUBE, BlockStep, HeldStage, held_need, lateral_blocks, plan_steps, smallest_need,
)
from ...blocks.statistics import streamed_otsu, streamed_quantile
from ...blocks.stores import StoreRun
from ..windows import StoredWindows
from ..options import FaultTracingOptions
from ..result import ChunkedFaults, fault_frames
from ..steps import faults_from_cells, surface_cells
from ...amplitudes import CubeAmplitudes, fill_values, finite_cube
from .ridges import RIDGE_HALO, THIN_HALO, amplitude_halo, cell_block, ridge_block, thin_block
from .voting import surface_block, vote_block
from .voting_kernels import greedy_seeds

__all__ = ["CANDIDATE_BYTES", "CELLS_PER_CANDIDATE", "ChunkedFaults", "SURFACE_BATCH_BYTES", "SurfacePlan",
           "SurfaceRun", "block_steps", "chunked_fault_surfaces", "held_stages", "memory_surface_run", "plan_blocks",
           "smallest_block_bytes"]

# the output's arrays, (n_inlines, n_xlines, n_samples) float32 (ChunkedFaults.path)
_OUTPUTS = ("likelihood", "votes", "thin", "vote_strike_deg", "vote_dip_deg", "slope_inline", "slope_xline")
# Bytes of working memory per sample of a block (incl. halo): amplitudes, their reflector slopes and the dead-sample
# masks (per sample of the amplitudes read); likelihood, strike, dip, the ranking image and its smoothing passes,
# ridges (per sample of the likelihood read); the voting's core (votes, strongest surface and its seed per numba
# thread; the summed votes, strike, dip) and its input; the thinning of the votes.
# (tracemalloc peaks on 96-trace blocks of 512 samples: ridges 44 per sample of the likelihood's halo block, amplitudes
# included; voting 32 per core sample with 2 threads besides the input, 8 + 12 per thread; thinning 41)
_DEAD_BYTES = 12
_RIDGE_BYTES = 48
_VOTE_CORE_BYTES = 12
_VOTE_THREAD_BYTES = 12  # per numba thread: its votes, strongest surface and seed (each thread its own arrays)
_VOTE_HALO_BYTES = 4
# Surfaces of seeds read back at once by a block of the voting (voting.vote_block: the others in later batches,
# in id order).
SURFACE_BATCH_BYTES = 16 << 20
_THIN_BYTES = 44
# Bytes per seed candidate while they are gathered and sorted
CANDIDATE_BYTES = 80  # points, values, angles (36), the sort keys, order and sorted copy
# The fault likelihood's arrays the ridges read (the run's stores' names of the likelihood group's arrays)
LIKELIHOOD_INPUTS = ("fault_likelihood", "fault_strike_deg", "fault_dip_deg")


@dataclass(frozen=True)
class SurfacePlan:
    """Block sizes (traces a side) of the steps of a run by blocks, and the voting's reach."""

    shape: tuple
    tile: int
    ridge: int    # block sizes (traces a side) of the steps
    vote: int
    thin: int
    reach: int    # a voting box's reach from its seed


def block_steps(shape, opt: FaultTracingOptions, cap: int) -> tuple:
    """The block steps of the fault surfaces, declared once in their order: algorithm, halo, inputs and outputs and
    (those planned by :func:`~seismo3d.seismic.blocks.plan.plan_steps`) the bytes of a block of ``b`` traces a side.

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    opt : FaultTracingOptions
    cap : int
        Largest side of a block, traces.

    Returns
    -------
    tuple of BlockStep
        ``'ridges'``, ``'surfaces'``, ``'thin'`` (planned: ``ridge``, ``vote``, ``thin`` of :class:`SurfacePlan`),
        ``'votes'``, ``'cells'``.
    """
    nt = shape[2]
    reach = opt.voting.reach(shape)
    threads = numba.get_num_threads()
    halo = amplitude_halo(opt)

    def ridge_bytes(b):
        return (b + 2 * halo) ** 2 * nt * _DEAD_BYTES + (b + 2 * RIDGE_HALO) ** 2 * nt * _RIDGE_BYTES

    # the surfaces of a block's seeds: at most one seed per (spacing + 1)^3 samples (greedy_seeds keeps them more
    # than spacing apart), each (2 rw + 1) x (2 rv + 1) offsets of 3 int8, its vote (float64) and normal (3 float32)
    _, rv, rw = opt.voting.box(shape)
    per_seed = (2 * rw + 1) * (2 * rv + 1) * 3 * (1 if reach < 127 else 2) + 20
    surface_density = per_seed / (opt.voting.spacing(3) + 1) ** 3  # bytes per sample of a block's core

    def vote_bytes(b):
        surfaces = (b + 2 * reach) ** 2 * nt * _VOTE_HALO_BYTES + b * b * nt * surface_density
        votes = b * b * nt * (_VOTE_CORE_BYTES + _VOTE_THREAD_BYTES * threads) + SURFACE_BATCH_BYTES
        return int(max(surfaces, votes))

    def thin_bytes(b):
        return (b + 2 * THIN_HALO) ** 2 * nt * _THIN_BYTES

    return (# the amplitudes read with their halo, the likelihood (read by slicing) with the ridges'
            BlockStep("ridges", "gather", halo, ridge_bytes, cap, function=ridge_block, label="fault ridges",
                      inputs=(CUBE, *LIKELIHOOD_INPUTS), place=True, lazy=True,
                      outputs=("slope_inline", "slope_xline", "likelihood", "near")),
            BlockStep("surfaces", "gather", reach, vote_bytes, cap, function=surface_block, label="fault surfaces",
                      inputs=("likelihood",), place=True),
            # threads=False: the votes are summed per numba thread (voting.VoteSum), so a block's kernel keeps the
            # process's threads, as the in-memory run; lazy: the mask near dead samples is read at the core only
            BlockStep("votes", "map", reach, function=vote_block, label="fault voting", threads=False,
                      inputs=("near",), outputs=("votes", "vote_strike_deg", "vote_dip_deg"), place=True, lazy=True),
            BlockStep("thin", "reduce", THIN_HALO, thin_bytes, cap, function=thin_block, label="thinning",
                      inputs=("votes", "vote_strike_deg", "vote_dip_deg"), outputs=("thin_raw",), place=True),
            BlockStep("cells", "gather", function=cell_block, label="fault cells",
                      inputs=("thin_raw", "vote_strike_deg", "vote_dip_deg"), outputs=("thin",), place=True))


# The stages after the blocks (held_stages): their peak beyond the process as the surfaces' plan counts it (the
# process the run's refusal measured, with STAGE_GROWTH for what the earlier stages leave in it), a fixed part and a
# part per fault cell. Measured by benchmarks/post_block_memory.py (the process's VmHWM reset at each stage's start,
# a fresh process per cube) on generated SEG-Y cubes run by blocks; MiB beyond the process + 64 MiB:
#                                cells    linked into skins   throws, half periods, evidence
#   160 x 160 x 256, 4 faults   159,443         27, 27                  106, 125
#   224 x 224 x 192, 8 faults   356,131         60, 63                  125, 110
#   128 x 256 x 320, 2 faults    92,339         11, 1                   129, 106
# (two runs each, the first under the limit the refusal named before these models, the second under the one it names
# with them). The cells read from the store (36 bytes each) peak below the skins. The skins take 200 bytes a cell
# (30, 68 and 18 MiB there; their links kept as a CSR array of int32, and the merge's queries of the k-d tree a
# bounded number of pairs each); the throws 144 MiB and 48 bytes a cell (151, 160, 148): their windows of amplitudes
# and slopes, not the cells, make most of it. On the 400 x 400 x 500 cube of benchmarks/fault_paths.py --only target
# (683,362 cells) the skins peak 99 MiB above the cells they read, 230 MiB beyond the process, where the plan counts
# 232 (benchmarks/post_block_memory.py --cube 400,400,500,mosaic --limit 1GB).
_SKINS_PER_CELL = 200
_THROW_FIXED, _THROW_PER_CELL = 144 << 20, 48
# Cells per seed candidate the preflight's sample predicts (CubeSample.candidates): the cells (thinned votes at or
# above the lower threshold) were 0.54, 0.67 and 0.70 of the candidates predicted on the cubes above. The prediction
# is a sample's: on the Parihaka cube (256 x 128 x 128) the sample found no candidate, and 17,419 cells were linked;
# on the 400 x 400 x 500 cube of benchmarks/fault_paths.py --only target 683,362 cells came of 381,222 candidates
# predicted (1.79 a candidate); the cells counted after the blocks are checked again (chunked_fault_surfaces).
CELLS_PER_CANDIDATE = 0.75


def held_stages(shape) -> tuple:
    """The stages of the fault surfaces after their blocks, which hold the cells and what is made of them whole
    (:func:`~seismo3d.seismic.faults.steps.faults_from_cells`), with their memory models (the module's notes): the
    cells linked into fault skins, and the skins' throws, evidence and tips.

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)`` (the models measured on cubes of 192 to 320 samples a trace).

    Returns
    -------
    tuple of HeldStage
        Their ``held_bytes(cells)``: bytes beyond the process as the surfaces' plan counts it.
    """
    return (HeldStage("linking the fault cells into skins", lambda cells: _SKINS_PER_CELL * cells),
            HeldStage("the throws and evidence", lambda cells: _THROW_FIXED + _THROW_PER_CELL * cells))


def smallest_block_bytes(shape, options: FaultTracingOptions, tile: int) -> int:
    """Bytes the largest step of :func:`chunked_fault_surfaces` needs with its smallest blocks (one ``tile`` a side),
    on top of the process itself: what ``memory_limit`` must leave for it (before the headroom).

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    options : FaultTracingOptions
    tile : int
        Traces a side of the smallest block (:attr:`~seismo3d.seismic.blocks.options.ChunkOptions.tile`).

    Returns
    -------
    int
    """
    return smallest_need(block_steps(tuple(int(n) for n in shape), options, int(tile)), tile)


def plan_blocks(shape, opt: FaultTracingOptions, chunking: ChunkOptions, baseline: int) -> SurfacePlan:
    """The largest blocks of each of :func:`block_steps` (multiples of ``chunking.tile``, at most ``chunking.block`` or
    512 traces a side) whose bytes fit the budget a memory limit leaves, by the executor's planner
    (:func:`~seismo3d.seismic.blocks.plan.plan_steps`).

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    opt : FaultTracingOptions
    chunking : ChunkOptions
        Memory limit (default half of the RAM), tile, largest block and workers.
    baseline : int
        Bytes the process holds before its blocks (:func:`~seismo3d.seismic.blocks.memory.worker_baseline`).

    Returns
    -------
    SurfacePlan

    Raises
    ------
    InputError
        The smallest blocks of a step need more than the budget (the message says by how much).
    """
    n0, n1, nt = shape
    steps = block_steps(shape, opt, int(chunking.block) if chunking.block else min(max(n0, n1), 512))
    sizes = plan_steps(steps, chunking, baseline=baseline,
                       what=f"a chunked run of the fault surfaces of a {n0} x {n1} x {nt} cube")
    return SurfacePlan((n0, n1, nt), int(chunking.tile), sizes["ridges"], sizes["surfaces"], sizes["thin"],
                       opt.voting.reach(shape))


def chunked_fault_surfaces(cube, likelihood, output, *, options: FaultTracingOptions | None = None,
                           chunking: ChunkOptions | None = None, progress: bool = False,
                           amplitudes: CubeAmplitudes | None = None, attrs: dict | None = None,
                           after: tuple = ()) -> ChunkedFaults:
    """Fault votes, thinned faults, fault skins and throws of a 3D cube larger than memory, block by block.

    The method and the defaults are those of :func:`~seismo3d.seismic.faults.trace_faults` after its first step
    (dead samples, ridges, optimal surface voting, thinning, Otsu thresholds, fault skins, throws; Hale 2013, Wu &
    Fomel 2018); every step runs on blocks with the halo its operator needs (module notes), so the faults are those
    of the in-memory run on the same likelihood.

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) dask.array.Array or array_like
        Amplitudes (e.g. ``open_lazy(path).data``), finite, samples along the last axis.
    likelihood : str or os.PathLike
        Zarr group of :func:`~seismo3d.seismic.faults.likelihood.scan_blocks.chunked_fault_likelihood` of this cube (arrays
        ``likelihood``, ``strike_deg``, ``dip_deg``).
    output : str or os.PathLike
        Output Zarr group, created. When it is the finished output of the same run (cube shape, likelihood, options)
        it is reused: only the skins and throws are computed again; when ``output + '.partial'`` and
        ``output + '.work'`` hold an unfinished run of it, the run resumes, skipping the finished blocks.
    options : FaultTracingOptions, optional
        Sensitivity, voting, skins and thresholds (defaults of :func:`~seismo3d.seismic.faults.trace_faults`).
    chunking : ChunkOptions, optional
        Memory limit, tile and the dask scheduler; each step sizes its blocks to the limit, at most ``block``
        traces a side when it is given.
    progress : bool
        Report progress per block and per fault.
    amplitudes : CubeAmplitudes, optional
        The cube's smallest and largest amplitude and its fill values, when measured already
        (:func:`~seismo3d.seismic.amplitudes.finite_cube`); default: measured here by it (passes over the cube).
    attrs : dict, optional
        More attributes of the output group (JSON-serialisable, e.g. the input's name), written with the others
        before it is renamed into place.
    after : tuple of HeldStage, optional
        Stages after this run that hold its results whole (e.g. the faults job's writers), checked with its own
        stages after the blocks (:func:`held_stages`) once the cells are counted.

    Returns
    -------
    ChunkedFaults

    Raises
    ------
    InputError
        The cube is not 3D, the likelihood group does not match it, ``output`` exists and is not an unfinished run
        of the same cube and options, or the memory limit is too small for the blocks, seed candidates, or the
        stages after the blocks with the cells counted (the message names the limit that works; the finished
        blocks are kept, and a run under it resumes them).
    UnsupportedDataError
        The likelihood is above ``options.saturation_level`` at more than ``options.max_saturated`` of the live
        samples (as in memory).

    References
    ----------
    .. [1] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1.
    .. [2] X. Wu and S. Fomel, "Automatic fault interpretation with optimal surface voting", Geophysics 83(5),
       O67-O82, 2018, doi:10.1190/geo2018-0115.1.
    """
    import zarr

    opt = options or FaultTracingOptions()
    if not isinstance(opt, FaultTracingOptions):
        raise InputError(f"options must be a FaultTracingOptions; got {type(opt).__name__}")
    chunking = chunking or ChunkOptions()
    x = trace_cube(cube, "chunked fault surfaces", chunks=(chunking.tile, chunking.tile, -1), dtype=np.float32)
    shape = tuple(int(n) for n in x.shape)
    group = zarr.open_group(str(likelihood), mode="r")
    for name in ("likelihood", "strike_deg", "dip_deg"):
        if name not in group or tuple(group[name].shape) != shape:
            raise InputError(f"{likelihood} has no {name!r} array of the cube's shape {shape}; pass the output of "
                             "chunked_fault_likelihood for this cube")
    baseline = worker_baseline(chunking, x)
    plan = plan_blocks(shape, opt, chunking, baseline)
    if amplitudes is None:
        x, amplitudes = finite_cube(x, opt.dead)
    memory = chunking.limit  # the candidates' check: less the RSS
    held = _HeldCheck(chunking.limit, baseline, held_stages(shape) + tuple(after))  # the cells' check
    store = StoreRun(pathlib.Path(output), chunking, progress, outputs=_OUTPUTS)
    # another likelihood written at the same path is not this one (its id)
    manifest = store.manifest_for(shape, opt, plan, likelihood=str(pathlib.Path(likelihood).resolve()),
                             likelihood_id=group.attrs.get("id"))
    # resuming: its blocks (the plan of an older run had more steps)
    kept = {k: v for k, v in manifest["plan"].items() if k in SurfacePlan.__dataclass_fields__}
    plan = SurfacePlan(**dict(kept, shape=tuple(kept["shape"])))
    done = store.finished_output(manifest, "cube, likelihood and options")
    if done is None:  # the block steps up to the cells (a resumed run skips the finished blocks)
        # the work arrays (the masks near dead samples, compressed; the thinned votes before the threshold), the
        # output arrays, and the likelihood's arrays the ridges read
        store.start_output(manifest, plan.shape, plan.tile, (("near", "uint8", plan.shape[2], True),
                                                             ("thin_raw", "float32", plan.shape[2])))
        store.arrays.update(zip(LIKELIHOOD_INPUTS, (f"{likelihood}/{name}" for name in
                                                    ("likelihood", "strike_deg", "dip_deg"))))
        with store.scheduled():
            run = SurfaceRun(store, x, plan, opt, shape, amplitudes, memory=memory, held=held)
            found = surface_cells(run, opt)
            # the cells gathered into 1D arrays of the output group, in C order (the skins then need no sorted copies)
            store.write_gathered("cells", run.blocks("cells"), {
                "points": ("cell_points", "int32"), "values": ("cell_values", "float32"),
                "strike": ("cell_strike_deg", "float32"), "dip": ("cell_dip_deg", "float32")}, found.n_cells)
        done = {"thresholds": list(found.thresholds), "n_seeds": found.n_seeds, "n_cells": found.n_cells,
                "saturated_fraction": found.saturated_fraction, "run": manifest}
        store.finish(dict(done, **(attrs or {}),
                          method="fault surfaces (Hale 2013, Wu & Fomel 2018), seismo3d chunked run"))
    else:
        held(int(done["n_cells"]))
    lower, upper = (float(v) for v in done["thresholds"])
    stored = zarr.open_group(str(store.out), mode="r")
    windows = StoredWindows(x, stored["slope_inline"], stored["slope_xline"])
    cells = (stored["cell_points"][:].astype(np.int64), stored["cell_values"][:], stored["cell_strike_deg"][:],
             stored["cell_dip_deg"][:])
    bar = no_progress()  # the seconds of the skins, the throw and the evidence
    faults, throws, evidence = faults_from_cells(cells, shape, windows, (lower, upper), opt,
                                                 likelihood=group["likelihood"], bar=bar, progress=progress)
    bar.stop()
    store.seconds.update({name: round(t, 2) for name, t in bar.seconds.items()})
    return ChunkedFaults(store.out, faults, throws, evidence, (lower, upper), int(done["n_seeds"]),
                         int(done["n_cells"]), float(done["saturated_fraction"]), dict(store.computed),
                         dict(store.resumed), dict(store.seconds))


@dataclass(frozen=True)
class _HeldCheck:
    """The stages after the blocks checked with the cells counted: refused when the process as the plan counts it
    and the largest stage's model (:func:`~seismo3d.seismic.blocks.plan.held_need`) exceed the limit."""

    limit: int
    baseline: int
    stages: tuple

    def __call__(self, n_cells: int) -> None:
        held, name = held_need(self.stages, n_cells)
        need = self.baseline + held
        if need > self.limit:
            raise InputError(f"the {n_cells} thinned fault samples (fault cells) need about {size_text(need)} in "
                             f"{name} beside this process ({size_text(self.baseline)}), more than the memory limit "
                             f"of {size_text(self.limit)}: pass memory_limit='{size_text(need * 21 // 20)}' (the "
                             "finished blocks are kept and resumed)")


def memory_surface_run(cube: np.ndarray, likelihood: np.ndarray, strike_deg: np.ndarray, dip_deg: np.ndarray,
                       opt: FaultTracingOptions, *, progress: bool = False) -> SurfaceRun:
    """The run of the fault surfaces on arrays in memory: the steps of :func:`block_steps` on one block, the whole
    array (:class:`~seismo3d.seismic.blocks.executor.MemoryRun`).

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Amplitudes, finite (:func:`~seismo3d.seismic.amplitudes.clean_traces`).
    likelihood, strike_deg, dip_deg : float32 ndarrays of the cube's shape
        Fault likelihood, strike and dip (degrees); the likelihood is set to 0 near dead samples by the ridges (in
        place when it is C-contiguous; :meth:`SurfaceRun.volume` ``('likelihood')`` in any case).
    opt : FaultTracingOptions
    progress : bool, optional
        Report each step (its label, one block) as :class:`~seismo3d.seismic.blocks.executor.MemoryRun` does.

    Returns
    -------
    SurfaceRun
        To run with :func:`~seismo3d.seismic.faults.steps.surface_cells`; its cells
        (:meth:`SurfaceRun.cells_found`) and volumes (:meth:`SurfaceRun.volume`) after.
    """
    image = tuple(int(n) for n in cube.shape)
    shape = image if len(image) == 3 else (image[0], 1, image[1])  # a section: a cube of one crossline
    arrays = dict(zip(LIKELIHOOD_INPUTS, (a.reshape(shape) for a in (likelihood, strike_deg, dip_deg))))
    side = max(shape[:2])
    plan = SurfacePlan(shape, side, side, side, side, opt.voting.reach(image))
    x = np.asarray(cube).reshape(shape)
    lo, hi = float(x.min()), float(x.max())  # the whole array's, as finite_cube measures a cube by blocks
    amplitudes = CubeAmplitudes(lo, hi, tuple(float(v) for v in fill_values(x, lo, hi, options=opt.dead)))
    return SurfaceRun(MemoryRun(shape, arrays=arrays, progress=progress), x, plan, opt, image, amplitudes,
                      slopes=False)


class SurfaceRun:
    """The fault surfaces' steps (:func:`block_steps`) run by an executor, in the order of
    :func:`~seismo3d.seismic.faults.steps.surface_cells`: by blocks into Zarr stores
    (:class:`~seismo3d.seismic.blocks.stores.StoreRun`, :func:`chunked_fault_surfaces`) or on the whole array in
    memory as one block (:class:`~seismo3d.seismic.blocks.executor.MemoryRun`, :func:`memory_surface_run`).

    Parameters
    ----------
    run : StoreRun or MemoryRun
        The executor: ``run_step``, ``saved``, ``saved_arrays``, ``step_lists``, ``lists_reader``, ``gathered_lists``
        and ``arrays`` (and a store run's ``reduce_cube``).
    cube : (n_inlines, n_xlines, n_samples) dask.array.Array or ndarray
        Amplitudes (a section's as a cube of one crossline).
    plan : SurfacePlan
        Block sides of the steps (a run in memory: the whole array).
    opt : FaultTracingOptions
    image_shape : tuple of int
        Of the image, 2D for a section.
    memory : int, optional
        The memory limit, bytes: seed candidates that need more than it leaves are refused (a run by blocks); None:
        not checked (a run in memory, sized before the run).
    held : callable, optional
        ``held(n_cells)``: refuses cells whose stages after the blocks need more than the memory limit (a run by
        blocks); None: not checked.
    slopes : bool
        Keep the reflector slopes for the throws (a run by blocks, whose throws read them from its stores).
    amplitudes : CubeAmplitudes
        The cube's smallest and largest amplitude and its fill values, measured before the run
        (:func:`~seismo3d.seismic.amplitudes.finite_cube` by blocks, :func:`~seismo3d.seismic.amplitudes.fill_values`
        in memory).
    """

    def __init__(self, run, cube, plan: SurfacePlan, opt: FaultTracingOptions, image_shape,
                 amplitudes: CubeAmplitudes, *, memory=None, held=None, slopes: bool = True):
        self.run, self.x, self.plan, self.opt = run, cube, plan, opt
        self.image_shape = tuple(int(n) for n in image_shape)
        self.memory, self.held, self.slopes, self.amplitudes = memory, held, slopes, amplitudes
        self.steps = {step.name: step for step in block_steps(plan.shape, opt, 0)}

    def blocks(self, step: str) -> list:
        """The blocks of the step named ``step`` (the cells' are the thinning's)."""
        p = self.plan
        side = {"ridges": p.ridge, "surfaces": p.vote, "votes": p.vote}.get(step, p.thin)
        return lateral_blocks(p.shape, side, side)

    def ridges(self) -> tuple[int, int]:
        """Dead samples (from the fill values of the whole cube), live likelihood and ridges of every block;
        (saturated live samples, live samples)."""
        a = self.amplitudes
        lo, hi, fill = float(a.lo), float(a.hi), np.asarray(a.fill, np.float32)
        results = self.run.run_step(self.steps["ridges"], self.blocks("ridges"), fill, lo, hi, self.image_shape,
                                    self.opt, self.slopes, source=self.x)
        return sum(r["high"] for r in results), sum(r["live"] for r in results)

    def seeds(self) -> tuple[np.ndarray, np.ndarray]:
        """The seeds among the ridges' candidates, strongest first (:func:`greedy_seeds`), with their frames; kept
        by a resumed run."""
        saved = self.run.saved_arrays("seeds", self._seeds)
        return saved["seeds"], saved["frames"]

    def _seeds(self) -> dict:
        shape = self.plan.shape
        blocks = sorted(self.blocks("ridges"), key=lambda b: f"{b[0]}-{b[2]}")  # as the files sort
        if self.memory is not None:
            n = sum(self.run.step_lists("ridges", b, ("values",), mmap_mode="r")["values"].size for b in blocks)
            if n * CANDIDATE_BYTES > self.memory - resident_memory():
                raise InputError(f"{n} seed candidates need about {n * CANDIDATE_BYTES / 2**30:.2f} GiB, more than "
                                 "the memory limit leaves: raise memory_limit")
        found = self.run.gathered_lists("ridges", blocks, ("points", "values", "angles"))
        points, angles = found["points"], found["angles"]
        seeds = greedy_seeds(points, found.pop("values"), shape, self.opt.voting.spacing(len(self.image_shape)))
        keys = np.ravel_multi_index(tuple(points.T), shape)
        del points, found
        order = np.argsort(keys)
        at = order[np.searchsorted(keys, np.ravel_multi_index(tuple(seeds.T), shape), sorter=order)]
        return {"seeds": seeds, "frames": fault_frames(angles[at, 0], angles[at, 1])}

    def votes(self, seeds: np.ndarray, frames: np.ndarray) -> None:
        """Each seed's optimal surface once, in the block that holds the seed (the likelihood read with the voting's
        reach around it), then the votes of every block from the surfaces of the seeds reaching it, in id order."""
        blocks = self.blocks("votes")
        self.run.run_step(self.steps["surfaces"], blocks, seeds, frames, self.image_shape, self.opt.voting)
        surfaces = self.run.lists_reader("surfaces", mmap_mode="r")  # taken along by each block's task
        self.run.run_step(self.steps["votes"], blocks, seeds, blocks, surfaces, self.image_shape, self.opt.voting,
                          SURFACE_BATCH_BYTES)

    def thresholds(self) -> tuple[float, float]:
        """The thresholds from the thinned votes of every block: Otsu's threshold of the positive ones and, when they
        are dense, their exact quantile (:meth:`~seismo3d.seismic.faults.FaultTracingOptions.thresholds_from`). In
        memory the libraries' on the values (:meth:`~seismo3d.seismic.faults.FaultTracingOptions.thresholds`); by
        blocks dask reductions over the store's chunks, which equal them
        (:mod:`~seismo3d.seismic.blocks.statistics`)."""
        stats = self.run.run_step(self.steps["thin"], self.blocks("thin"), self.image_shape)
        thin = self.run.arrays["thin_raw"]  # an array in memory, or a Zarr store's path
        if isinstance(thin, np.ndarray):
            return self.opt.thresholds(thin)
        import dask.array as da

        n_values = sum(r["count"] for r in stats)
        n_samples = int(np.prod(self.plan.shape, dtype=np.int64))
        if n_values == 0:
            return self.opt.thresholds_from(1.0, 0, n_samples, None)
        vmin = min(r["min"] for r in stats if r["count"])
        vmax = max(r["max"] for r in stats if r["count"])
        values = da.from_zarr(thin)
        return self.opt.thresholds_from(streamed_otsu(self.run, values, vmin, vmax), n_values, n_samples,
                                        lambda q: streamed_quantile(self.run, values, q, n_values, vmin, vmax))

    def cells(self, lower: float) -> int:
        """Thinned votes at or above ``lower`` kept (``thin``), the others set to 0, and its cells listed per
        block; their number."""
        n = sum(r["count"] for r in self.run.run_step(self.steps["cells"], self.blocks("cells"), lower))
        if self.held is not None:
            self.held(n)
        return n

    def cells_found(self) -> tuple:
        """(points (n, 3) int64, values, strike_deg, dip_deg (n,) float32) of the cells, the blocks' in their
        order (C order for one block)."""
        found = self.run.gathered_lists("cells", self.blocks("cells"), ("points", "values", "strike", "dip"))
        return tuple(found[name] for name in ("points", "values", "strike", "dip"))

    def volume(self, name: str):
        """The array ``name`` of the run (``'votes'``, ``'thin'``, ...) in the image's shape (a section's 2D)."""
        array = self.run.arrays[name]
        return array.reshape(self.image_shape) if len(self.image_shape) == 2 else array

