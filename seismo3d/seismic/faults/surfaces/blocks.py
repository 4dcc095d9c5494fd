"""Fault surfaces of a cube larger than memory: the steps of :func:`~seismo3d.seismic.faults.trace_faults` after the
fault likelihood, run block by block on dask from a chunked likelihood, with the same faults as the in-memory run.

``_SurfaceRun`` implements the named steps of :class:`~seismo3d.seismic.faults.steps.SurfaceRun` on blocks;
:func:`~seismo3d.seismic.faults.steps.surface_cells` calls them in the order the run in memory does
(:class:`~seismo3d.seismic.faults.steps.ArrayRun`: the whole array as one block), and
:func:`~seismo3d.seismic.faults.steps.faults_from_cells` makes the faults of the stored cells.

Every step reads what it needs around its block (the halo of its operator) from Zarr work arrays and writes its
block's core, so the result does not depend on where the blocks are cut:

1. **Fill values** of the dead-sample rules (:mod:`~seismo3d.seismic.faults.surfaces.dead_samples`): gathered over every
   block, from the cube's smallest and largest amplitudes.
2. **Ridges**: per block, dead samples and their reach, the likelihood zeroed there (the ``live`` likelihood) and
   its ridges (:func:`~seismo3d.seismic.thin_faults`, halo ``RIDGE_HALO``); the ridge samples above the voting's seed
   threshold are kept as a sparse list of seed candidates.
3. **Seeds**: the candidates of all blocks, taken strongest first by
   :func:`~seismo3d.seismic.faults.surfaces.voting_kernels.greedy_seeds` (a sparse list: a few percent of the samples).
4. **Surfaces, then votes**: each seed's optimal surface once, in the block holding the seed, on the live likelihood
   read with the voting's reach (``VotingOptions.reach``) around it
   (:func:`~seismo3d.seismic.faults.surfaces.voting.seed_surfaces`, stored as the samples each surface passes); then per
   block the votes of the surfaces of the seeds reaching it (:class:`~seismo3d.seismic.faults.surfaces.voting.VoteSum`:
   each seed's votes are summed by the same thread, in the same order, as in memory).
5. **Thinning** of the votes (halo 2), with the count, smallest and largest positive thinned vote per block; then
   their histogram (Otsu's threshold on the same 256 bins as in memory) and, when they are dense, their exact
   quantile: the thresholds of :meth:`~seismo3d.seismic.faults.FaultTracingOptions.thresholds_from`.
6. **Cells**: the thinned votes at or above the lower threshold, gathered as a sparse list, linked into fault skins
   by :func:`~seismo3d.seismic.faults.surfaces.skins.skins_from_cells` (no array of the cube's size).
7. **Throws** read the amplitudes around each fault patch (:func:`~seismo3d.seismic.fault_throws` on the lazy cube).

The steps are declared once (:func:`~seismo3d.seismic.faults.surfaces.block_steps.block_steps`) and run by the
executor of :mod:`seismo3d.seismic.blocks` (:meth:`~seismo3d.seismic.blocks.executor.BlockRun.run_step`): a marker per
finished block in ``OUTPUT.work``, the output assembled in ``OUTPUT.partial`` and renamed when complete.
"""

from __future__ import annotations

import json
import pathlib
from dataclasses import asdict, dataclass

import numpy as np

from ...._atomic import atomic_path
from ....errors import EarlierStoresError, InputError
from ...blocks.executor import SchedulerClient
from ...blocks.memory import default_memory_limit, resident_memory, worker_baseline
from ...blocks.options import ChunkOptions
from ...blocks.plan import lateral_blocks
from ...blocks.stores import StoreRun
from ...blocks.windows import StoredWindows
from ..options import FaultTracingOptions
from ..result import fault_frames
from ..steps import faults_from_cells, surface_cells
from .block_steps import CANDIDATE_BYTES, CELL_BYTES, LIKELIHOOD_INPUTS, RIDGE_HALO, SurfacePlan, block_steps, plan_blocks, smallest_block_bytes
from .thresholds import HISTOGRAM_BINS, QUANTILE_BINS, otsu_of_histogram, quantile_of_window, quantile_window
from .voting_kernels import greedy_seeds

__all__ = ["CANDIDATE_BYTES", "ChunkedFaults", "chunked_fault_surfaces", "RIDGE_HALO", "smallest_block_bytes"]

# the output's arrays, (n_inlines, n_xlines, n_samples) float32 (ChunkedFaults.path)
_OUTPUTS = ("likelihood", "votes", "thin", "vote_strike_deg", "vote_dip_deg", "slope_inline", "slope_xline")


@dataclass(frozen=True, eq=False)
class ChunkedFaults:
    """Result of :func:`chunked_fault_surfaces`.

    Attributes
    ----------
    path : pathlib.Path
        The output Zarr group: ``likelihood`` (the fault likelihood, 0 near dead samples, as
        :attr:`~seismo3d.seismic.faults.FaultInterpretation.likelihood`), ``votes`` (optimal-surface votes),
        ``thin`` (thinned votes at or above the lower threshold, 0 elsewhere), ``vote_strike_deg`` and
        ``vote_dip_deg``, each (n_inlines, n_xlines, n_samples) float32 with dimensions inline, crossline, sample;
        the cells linked into skins as ``cell_points`` (n, 3) int32 and ``cell_values``, ``cell_strike_deg``,
        ``cell_dip_deg`` (n,) float32; attrs ``thresholds``, ``n_seeds``, ``n_cells``, ``saturated_fraction``,
        ``run`` (what was computed) and ``complete``.
    faults : list of Fault
        Fault skins, as :attr:`~seismo3d.seismic.faults.FaultInterpretation.faults`.
    throws : list of FaultThrow
        One per fault.
    evidence : list of FaultEvidence
        One per fault (:func:`~seismo3d.seismic.faults.evidence.supported_faults`: faults without a displacement
        are left out, as in memory).
    thresholds : (float, float)
        Lower and upper thresholds on the thinned votes.
    n_seeds, n_cells : int
        Voting seeds, and thinned-vote samples linked into skins.
    saturated_fraction : float
        Fraction of the live samples (not near dead ones) with a likelihood above ``saturation_level``.
    blocks_computed, blocks_resumed : dict
        Blocks per step computed in this call and found finished by an earlier one.
    seconds : dict
        Wall-clock seconds per step.
    """

    path: pathlib.Path
    faults: list
    throws: list
    evidence: list
    thresholds: tuple
    n_seeds: int
    n_cells: int
    saturated_fraction: float
    blocks_computed: dict
    blocks_resumed: dict
    seconds: dict


def chunked_fault_surfaces(cube, likelihood, output, *, options: FaultTracingOptions | None = None,
                           chunking: ChunkOptions | None = None, progress: bool = False) -> ChunkedFaults:
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

    Returns
    -------
    ChunkedFaults

    Raises
    ------
    InputError
        The cube is not 3D, the likelihood group does not match it, ``output`` exists and is not an unfinished run
        of the same cube and options, or the memory limit is too small for the smallest blocks or for the seed
        candidates and cells.
    UnsupportedDataError
        The likelihood is above ``options.saturation_level`` at more than ``options.max_saturated`` of the live samples (as in memory).

    References
    ----------
    .. [1] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1.
    .. [2] X. Wu and S. Fomel, "Automatic fault interpretation with optimal surface voting", Geophysics 83(5),
       O67-O82, 2018, doi:10.1190/geo2018-0115.1.
    """
    import dask.array as da
    import zarr

    opt = options or FaultTracingOptions()
    if not isinstance(opt, FaultTracingOptions):
        raise InputError(f"options must be a FaultTracingOptions; got {type(opt).__name__}")
    chunking = chunking or ChunkOptions()
    tile = chunking.tile  # an array given in memory: chunks of the run's tile
    x = cube if isinstance(cube, da.Array) else da.from_array(np.asarray(cube), chunks=(tile, tile, -1))
    if x.ndim != 3 or min(x.shape) < 3:
        raise InputError(f"chunked fault surfaces need a 3D cube (n_inlines, n_xlines, n_samples); got shape {x.shape}")
    if len(x.chunks[2]) != 1:
        x = x.rechunk({2: -1})
    if x.dtype != np.float32:
        x = x.astype(np.float32)
    shape = tuple(int(n) for n in x.shape)
    group = zarr.open_group(str(likelihood), mode="r")
    for name in ("likelihood", "strike_deg", "dip_deg"):
        if name not in group or tuple(group[name].shape) != shape:
            raise InputError(f"{likelihood} has no {name!r} array of the cube's shape {shape}; pass the output of "
                             "chunked_fault_likelihood for this cube")
    input_chunk = 4 * max(x.chunks[0]) * max(x.chunks[1]) * shape[2]
    baseline = worker_baseline(chunking, input_chunk)
    plan = plan_blocks(shape, opt, chunking, baseline)
    memory = int(chunking.memory_limit or default_memory_limit())  # the cells' and candidates' checks: less the RSS
    run = _SurfaceRun(pathlib.Path(output), pathlib.Path(likelihood), x, plan, opt, chunking, memory, progress)
    manifest = {"shape": list(shape), "options": json.loads(json.dumps(asdict(opt), default=str)),
                "plan": json.loads(json.dumps(asdict(plan))), "likelihood": str(pathlib.Path(likelihood).resolve()),
                "likelihood_id": group.attrs.get("id")}  # another likelihood written at the same path is not this
    earlier = run.earlier_plan(manifest)
    if earlier is not None:  # resuming: the blocks of the interrupted run
        run.plan = plan = SurfacePlan(**dict(earlier, shape=tuple(earlier["shape"])))
        manifest["plan"] = earlier
    attrs = run.finished(manifest)
    if attrs is None:
        attrs = _surfaces(run, manifest)
    elif attrs["n_cells"] * CELL_BYTES > memory - resident_memory():
        raise InputError(f"{attrs['n_cells']} thinned fault samples need about "
                         f"{attrs['n_cells'] * CELL_BYTES / 2**30:.2f} GiB to link into fault skins, more than the "
                         "memory limit leaves: raise memory_limit")
    lower, upper = (float(v) for v in attrs["thresholds"])
    stored = zarr.open_group(str(run.out), mode="r")
    windows = StoredWindows(x, stored["slope_inline"], stored["slope_xline"])
    faults, throws, evidence = faults_from_cells(_stored_cells(run.out), shape, windows, (lower, upper), opt,
                                                 likelihood=group["likelihood"], progress=progress)
    return ChunkedFaults(run.out, faults, throws, evidence, (lower, upper), int(attrs["n_seeds"]),
                         int(attrs["n_cells"]), float(attrs["saturated_fraction"]), dict(run.computed),
                         dict(run.resumed), dict(run.seconds))


def _surfaces(run: _SurfaceRun, manifest: dict) -> dict:
    """The block steps of a run (skipping the finished blocks of an earlier one) up to the cells, stored with the
    thresholds in the finished output; its attributes."""
    run.start(manifest)
    with SchedulerClient(run.scheduler) as client:
        run.client = client
        found = surface_cells(run, run.opt)
    attrs = {"thresholds": list(found.thresholds), "n_seeds": found.n_seeds, "n_cells": found.n_cells,
             "saturated_fraction": found.saturated_fraction, "run": manifest}
    run.finish(dict(attrs, method="fault surfaces (Hale 2013, Wu & Fomel 2018), seismo3d chunked run"))
    return attrs


def _stored_cells(path: pathlib.Path) -> tuple:
    """(points (n, 3) int64, values, strike_deg, dip_deg (n,) float32) of the cells stored in a finished output."""
    import zarr
    group = zarr.open_group(str(path), mode="r")
    return (group["cell_points"][:].astype(np.int64), group["cell_values"][:], group["cell_strike_deg"][:],
            group["cell_dip_deg"][:])


class _SurfaceRun(StoreRun):
    """One chunked fault-surface run: its steps and their blocks (its stores: :class:`StoreRun`)."""

    def __init__(self, out: pathlib.Path, likelihood: pathlib.Path, x, plan: SurfacePlan, opt: FaultTracingOptions,
                 chunking: ChunkOptions, memory: int, progress: bool):
        super().__init__(out, chunking, progress, outputs=_OUTPUTS)
        self.likelihood, self.plan, self.opt = str(likelihood), plan, opt
        self.x, self.memory = x, memory  # the cube (dask, whole traces) and the memory limit, bytes
        self.steps = {step.name: step for step in block_steps(plan.shape, opt, 0)}

    def finished(self, manifest: dict) -> dict | None:
        """The attributes of the finished output of this same run (blocks aside: they do not change the result), or
        None when there is no output yet.

        Raises
        ------
        InputError
            The output exists but is not the finished output of this run.
        """
        import zarr
        if not self.out.exists():
            return None
        try:
            attrs = dict(zarr.open_group(str(self.out), mode="r").attrs)
        except Exception:  # noqa: BLE001 - anything that is not our Zarr group
            attrs = {}
        run = {k: v for k, v in dict(attrs.get("run") or {}).items() if k != "plan"}
        if attrs.get("complete") is not True or run != {k: v for k, v in manifest.items() if k != "plan"}:
            raise EarlierStoresError(f"output {self.out} already exists and is not the finished output of this "
                                     "cube, likelihood and options; pick another output or delete it", [self.out])
        return attrs

    def start(self, manifest: dict) -> None:
        """Open the work folder with ``manifest``, its folders of sparse lists and its work arrays (the masks near
        dead samples, compressed; the thinned votes before the threshold), and the output arrays."""
        p = self.plan
        self.start_output(manifest, p.shape, p.tile, (("near", "uint8", p.shape[2], True),
                                                      ("thin_raw", "float32", p.shape[2])))
        (self.work / "surfaces").mkdir(exist_ok=True)
        self.arrays.update(zip(LIKELIHOOD_INPUTS, (f"{self.likelihood}/{name}" for name in
                                                   ("likelihood", "strike_deg", "dip_deg"))))

    # -- steps ----------------------------------------------------------------------------------------------------
    def amplitude_range(self, x) -> tuple[float, float]:
        import dask.array as da

        lo, hi = self.saved("amplitude_range", lambda: [float(v) for v in self.reduce_cube((da.min(x), da.max(x)))])
        return lo, hi

    def fill_values(self, x, lo: float, hi: float) -> np.ndarray:
        p = self.plan
        results = self.run_step(self.steps["fill"], lateral_blocks(p.shape, p.dead, p.dead), lo, hi, self.opt.dead,
                                source=x)
        return np.unique(np.concatenate([np.asarray(r["fill"], np.float32) for r in results] +
                                        [np.zeros(1, np.float32)]))

    def ridges(self) -> tuple[int, int]:
        """Dead samples (from the fill values of the whole cube), live likelihood and ridges of every block;
        (saturated live samples, live samples)."""
        x = self.x
        lo, hi = self.amplitude_range(x)
        fill = self.fill_values(x, lo, hi)
        p = self.plan
        results = self.run_step(self.steps["ridges"], lateral_blocks(p.shape, p.ridge, p.ridge), fill, lo, hi,
                                p.shape, self.opt, source=x)
        return sum(r["high"] for r in results), sum(r["live"] for r in results)

    def seeds(self) -> tuple[np.ndarray, np.ndarray]:
        memory = self.memory
        path = self.work / "seeds.npz"
        if not path.exists():
            files = sorted((self.work / "ridges").glob("*.npz"))
            n = sum(int(np.load(f)["values"].size) for f in files)
            if n * CANDIDATE_BYTES > memory - resident_memory():
                raise InputError(f"{n} seed candidates need about {n * CANDIDATE_BYTES / 2**30:.2f} GiB, more than "
                                 "the memory limit leaves: raise memory_limit")
            parts = [np.load(f) for f in files]
            points = np.concatenate([q["points"] for q in parts]) if parts else np.zeros((0, 3), np.int64)
            values = np.concatenate([q["values"] for q in parts]) if parts else np.zeros(0, np.float32)
            angles = np.concatenate([q["angles"] for q in parts]) if parts else np.zeros((0, 2), np.float32)
            del parts
            seeds = greedy_seeds(points, values, self.plan.shape, self.opt.voting.spacing(3))
            keys = np.ravel_multi_index(tuple(points.T), self.plan.shape)
            del points, values
            order = np.argsort(keys)
            at = order[np.searchsorted(keys, np.ravel_multi_index(tuple(seeds.T), self.plan.shape), sorter=order)]
            frames = fault_frames(angles[at, 0], angles[at, 1])
            with atomic_path(str(path)) as tmp, open(tmp, "wb") as fh:
                np.savez(fh, seeds=seeds, frames=frames)
        saved = np.load(path)
        return saved["seeds"], saved["frames"]

    def votes(self, seeds: np.ndarray, frames: np.ndarray) -> None:
        """Each seed's optimal surface once, in the block that holds the seed (the likelihood read with the voting's
        reach around it), then the votes of every block from the surfaces of the seeds reaching it, in id order."""
        p = self.plan
        blocks = lateral_blocks(p.shape, p.vote, p.vote)
        self.run_step(self.steps["surfaces"], blocks, seeds, frames, str(self.work), str(self.partial), p, self.opt)
        self.run_step(self.steps["votes"], blocks, seeds, blocks, str(self.work), str(self.partial), p, self.opt)

    def thresholds(self) -> tuple[float, float]:
        """The thresholds from the thinned votes of every block: their count and range, their histogram (Otsu) and,
        when they are dense, their exact quantile (:mod:`~seismo3d.seismic.faults.surfaces.thresholds`)."""
        p = self.plan
        blocks = lateral_blocks(p.shape, p.thin, p.thin)
        stats = self.run_step(self.steps["thin"], blocks)
        n_values = sum(r["count"] for r in stats)
        n_samples = int(np.prod(p.shape, dtype=np.int64))
        if n_values == 0:
            return self.opt.thresholds_from(1.0, 0, n_samples, None)
        vmin = min(r["min"] for r in stats if r["count"])
        vmax = max(r["max"] for r in stats if r["count"])
        otsu = otsu_of_histogram(self._histogram(blocks, vmin, vmax, HISTOGRAM_BINS, "histogram"), vmin, vmax)
        return self.opt.thresholds_from(otsu, n_values, n_samples,
                                        lambda q: self._quantile(blocks, q, n_values, vmin, vmax))

    def _histogram(self, blocks, vmin, vmax, bins, step) -> np.ndarray:
        results = self.run_step(self.steps[step], blocks, vmin, vmax, bins)
        return np.sum([np.asarray(r["counts"], np.int64) for r in results], axis=0)

    def _quantile(self, blocks, q: float, n: int, vmin: float, vmax: float) -> float:
        """numpy.quantile(values, q) of the positive thinned votes, exactly: the two order statistics it
        interpolates, found by a fine histogram and a pass that gathers the values of their bins."""
        counts = self._histogram(blocks, vmin, vmax, QUANTILE_BINS, "quantile_histogram")
        window = quantile_window(counts, n, q, vmin, vmax)
        results = self.run_step(self.steps["quantile"], blocks, window[3], window[4])
        values = np.concatenate([np.asarray(r["values"], np.float32) for r in results])
        return quantile_of_window(window, sum(r["below"] for r in results), values)

    def cells(self, lower: float) -> int:
        """Thinned votes at or above ``lower`` into the output, and its cells gathered into 1D arrays of the output
        group (``cell_points``, ``cell_values``, ``cell_strike_deg``, ``cell_dip_deg``) in C order (the skins then
        need no sorted copies); their number."""
        import zarr
        p = self.plan
        blocks = lateral_blocks(p.shape, p.thin, p.thin)
        results = self.run_step(self.steps["cells"], blocks, lower)
        n = sum(r["count"] for r in results)
        if n * CELL_BYTES > self.memory - resident_memory():
            raise InputError(f"{n} thinned fault samples need about {n * CELL_BYTES / 2**30:.2f} GiB to link into "
                             "fault skins, more than the memory limit leaves: raise memory_limit")
        group = zarr.open_group(str(self.partial), mode="r+")
        chunk = 1 << 20
        arrays = {"cell_points": ((n, 3), "int32", (chunk, 3)), "cell_values": ((n,), "float32", (chunk,)),
                  "cell_strike_deg": ((n,), "float32", (chunk,)), "cell_dip_deg": ((n,), "float32", (chunk,))}
        out = {k: group.create_array(k, shape=shape, dtype=dtype, chunks=chunks, overwrite=True)
               for k, (shape, dtype, chunks) in arrays.items()}
        start = 0
        for i0 in sorted({b[0] for b in blocks}):  # a row of blocks at a time, its cells in C order (the image's)
            parts = [np.load(self.work / "cells" / f"{b[0]}-{b[2]}.npz") for b in blocks if b[0] == i0]
            row = {k: np.concatenate([q[k] for q in parts]) for k in ("points", "values", "strike", "dip")}
            del parts
            order = np.argsort(np.ravel_multi_index(tuple(row["points"].T), p.shape), kind="stable")
            m = int(order.size)
            if m:
                out["cell_points"][start:start + m] = row["points"][order].astype(np.int32)
                for key, name in (("values", "cell_values"), ("strike", "cell_strike_deg"), ("dip", "cell_dip_deg")):
                    out[name][start:start + m] = row[key][order]
            start += m
        return n
