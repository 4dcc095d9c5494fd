"""The fault likelihood and the faults job by blocks equal them in memory: the claims too long for the suite (issue 58).

Run: ``python benchmarks/fault_blocks.py [--only learned_blocks,network_grid,job_limit,segy_lazy,demo_blocks,
demo_interchange,labelled_cube] [--check]``

Each section asserts what a test of the suite asserted before it moved here (each over ~20 s of a worker, so the
suite keeps a smaller version of each claim, named below); ``--check`` exits 1 when one assertion failed, and the
sections run on generated cubes (no data folder needed):

- ``learned_blocks``: the learned likelihood by forced blocks equals it in memory on a grid of 0.7 (232 x 236 x 32,
  blocks of 96) and on three grids, 0.5, 0.7 and 1 (120 x 128 x 32, blocks of 96): every step in more than one block,
  the likelihood within 1e-5 except where rounding flips the min_dip mask (at most 3 samples), strike and dip within
  0.5 deg where the likelihood is over 0.5 (from ``tests/seismic/faults/likelihood/test_learned.py``
  ``test_blocks_equal_the_in_memory_likelihood``, which keeps the data's own grid, 72 x 80 x 48);
- ``network_grid``: a block of the 0.7 network grid, its origin off the pooling grid, run as the run by blocks runs
  it (the network step on the region it reads, both directions, then their probability on the block's traces),
  equals the whole cube's probability within 1e-5
  (``test_a_block_on_the_whole_cubes_network_grid_equals_the_whole_cube``);
- ``job_limit``: the faults job on a 192 x 192 x 64 cube under a limit between the smallest blocks' need and the
  in-memory need, both the job's own decision in the process as it stands (:func:`_limits`: a third of the way from
  the limit the job's refusal names to the limit above which it runs in memory): block by block, likelihood within
  1e-5 and votes within 1e-6 of the in-memory run, the same summary and points, reused when run again; under the
  limit the refusal names (an eighth of the way): smaller blocks, the same faults, the same eleven files
  (``tests/jobs/test_faults_chunked.py``, which keeps a 48 x 56 x 40 cube with the blocks forced);
- ``segy_lazy``: a 192 x 160 x 128 crossline-sorted SEG-Y cube over the limit (a third of the way, as in
  ``job_limit``) read block by block, its likelihood
  equal to the in-memory one, its volumes written as SEG-Y with the input's headers (``test_segy_cube_is_read_lazily``,
  which keeps a 40 x 48 x 40 SEG-Y cube with the blocks forced);
- ``demo_blocks``: the 128^3 demo by forced blocks writes every file byte-identical to the in-memory run's (the
  picture and run.json aside), run.json with each step's seconds
  (``test_the_demo_by_blocks_writes_what_it_writes_in_memory``);
- ``demo_interchange``: the demo's interchange files in inline / crossline units, its TSurf files (one per fault) read
  back by xtgeo equal to faults.vtp, its sticks a few fault points each (on every 10th line), a horizon's IRAP / ZMAP+
  grids equal to its text rows (``tests/jobs/test_interchange.py`` keeps a 48 x 56 x 48 cube, without coordinates
  and on a rotated map grid: ``test_every_fault_surface_read_by_xtgeo``, ``test_small_cube_sticks_and_grids``).
- ``labelled_cube``: a 192 x 160 x 128 SEG-Y cube with CDP X/Y opened by ``seismo3d.open`` (lazy, dims iline, xline,
  twt, cdp_x / cdp_y), traced by ``trace_faults(cube)`` and by ``trace_faults(cube, memory_limit=...)`` under a limit
  between the smallest blocks' need and the in-memory need: one result type, the volumes DataArrays on the cube's
  coordinates (numpy-backed, then dask over the stores), equal within 1e-5, the same faults
  (``tests/seismic/faults/test_memory_or_blocks.py`` keeps a 48 x 56 x 48 cube with the blocks forced).
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import json
import logging
import pathlib
import re
import sys
import tempfile
import time
import traceback
import warnings

import numpy as np

from seismo3d.data.synthetic import synthetic_cube, write_segy_cube


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


class _Log(logging.Handler):
    """The seismo3d logger's messages at INFO, as pytest's caplog gathers them."""

    def __init__(self):
        super().__init__(logging.INFO)
        self.messages = []

    def emit(self, record):
        self.messages.append(record.getMessage())

    @property
    def text(self):
        return "\n".join(self.messages)


@contextlib.contextmanager
def _log():
    logger = logging.getLogger("seismo3d")
    handler, level = _Log(), logger.level
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    try:
        yield handler
    finally:
        logger.removeHandler(handler)
        logger.setLevel(level)


def _limits(path, shape, tmp: pathlib.Path, **job) -> tuple[int, int]:
    """The faults job's own memory decision on ``path`` in this process as it stands: the limit its refusal names
    (the smallest blocks and the seed candidates, with the refusal's 5 %), and the limit above which it runs in
    memory (the process and :func:`~seismo3d.seismic.blocks.memory.in_memory_bytes`), bytes. Asked again before each
    run: the process grows by up to ~180 MiB over a run by blocks, and a limit a fixed size beyond it sat on the
    decision's edge (refused at 'the 710MB given' in one run of four)."""
    from seismo3d.errors import InputError
    from seismo3d.jobs.faults import run_faults_job
    from seismo3d.seismic.blocks.memory import in_memory_bytes, parse_memory_limit, resident_memory

    out = pathlib.Path(tempfile.mkdtemp(prefix="refused_", dir=tmp))
    try:  # the smallest limit accepted: the job refuses it, naming the one that works
        run_faults_job(path, out, memory_limit=64 << 20, progress=False, overwrite=True, **job)
    except InputError as exc:
        named = re.search(r"memory_limit='([^']+)'", str(exc))
        assert named, f"the refusal names no limit: {exc}"
    else:
        raise AssertionError("the faults job ran under a 64 MB memory limit: no refusal to derive limits from")
    return parse_memory_limit(named.group(1)), resident_memory() + in_memory_bytes(shape)


def _limit_between(path, shape, tmp: pathlib.Path, fraction: float, **job) -> int:
    """A limit ``fraction`` of the way from the one the job's refusal names to the in-memory edge (:func:`_limits`),
    bytes; printed with both edges."""
    smallest, in_memory = _limits(path, shape, tmp, **job)
    assert smallest < in_memory, (smallest, in_memory)
    limit = smallest + int((in_memory - smallest) * fraction)
    print(f"  limits: refused below {smallest / 2**20:.0f} MiB, in memory from {in_memory / 2**20:.0f} MiB: "
          f"{limit / 2**20:.0f} MiB ({fraction:.3g} of the way)")
    return limit


def learned_blocks(tmp: pathlib.Path) -> None:
    from seismo3d.seismic.blocks.options import ChunkOptions
    from seismo3d.seismic.faults.likelihood.learned_blocks import chunked_learned_likelihood
    from seismo3d.seismic.faults.likelihood.learned import LearnedOptions, learned_fault_likelihood

    for k, (resample, shape, block) in enumerate([
        # a grid of 0.7: network blocks of 80 network traces, origins off its pooling grid, the halo along the
        # sections inside the cube at the end of block 0-80 and at the start of block 80-160 (of 163 and 166)
        (0.7, (232, 236, 32), 96),
        # the default's three grids (0.5, 0.7, 1), their mean: blocks of 48, 80 and 96 network traces
        ((0.5, 0.7, 1.0), (120, 128, 32), 96),
    ]):
        cube = synthetic_cube(shape, seed=2, noise=0.1).cube
        opt = LearnedOptions(cube_resample=resample, min_grid_samples=0)  # every grid, on traces of 32 samples too
        mem = learned_fault_likelihood(cube, options=opt)
        run = chunked_learned_likelihood(cube, tmp / f"l{k}.zarr", options=opt,
                                         chunking=ChunkOptions(block=block, scheduler="synchronous"))
        steps = [f"network_{d}_{g}" for g in range(len(opt.cube_resample)) for d in ("inline", "crossline")]
        assert set(run.blocks_computed) == set(steps) | {"orientation"}, run.blocks_computed
        assert min(run.blocks_computed[step] for step in steps + ["orientation"]) > 1, run.blocks_computed
        out = run.open()
        # equal up to float rounding, except where the dip sits on min_dip and rounding flips the dip mask (1 sample
        # of 1.75 M at resample 0.7, its dip 40.0015 deg)
        diff = np.abs(out["likelihood"][:] - mem.likelihood)
        on_the_mask_edge = np.abs(mem.dip_deg - opt.min_dip) <= 0.01
        print(f"  resample {resample}, {shape}: likelihood diff off the mask edge "
              f"{diff[~on_the_mask_edge].max():.2e}, {np.count_nonzero(diff > 1e-5)} samples over 1e-5")
        assert diff[~on_the_mask_edge].max() <= 1e-5 and np.count_nonzero(diff > 1e-5) <= 3
        live = mem.likelihood > 0.5  # where there is a fault, its orientation is the same
        strike = np.abs(out["strike_deg"][:] - mem.strike_deg)[live]
        assert np.minimum(strike, 360 - strike).max() <= 0.5
        assert np.abs(out["dip_deg"][:] - mem.dip_deg)[live].max() <= 0.5


def network_grid(tmp: pathlib.Path) -> None:
    import math

    from seismo3d.seismic.blocks.apply import BlockPlace
    from seismo3d.seismic.faults.likelihood.learned import (
        LearnedOptions, amplitude_scale, fault_probability, network_block, network_probability, network_region,
        whole_plan,
    )

    # a block of the 0.7 network grid, its origin away from 0 on both axes and not a multiple of the pooling grid,
    # run as the run by blocks runs it (network_block on the region network_region reads, for each direction, then
    # network_probability on the block's input traces): it equals the whole cube's probability up to float rounding.
    # The cube's 32 samples are 23 on the 0.7 grid, fewer than the default min_grid_samples (which would run the grid
    # of 1 instead): the check lowers it so that the 0.7 grid it names is the grid it runs
    opt = LearnedOptions(cube_resample=0.7, min_grid_samples=16)
    assert opt.grids(32, 3) == (0.7,)
    cube = synthetic_cube((232, 236, 32), seed=4, noise=0.1).cube
    scale = amplitude_scale(cube)
    whole = fault_probability(cube, options=opt, scale=scale)
    plan = whole_plan(cube.shape, opt)
    grid = tuple(plan["grids"][0]["network_shape"])
    i0, i1, j0, j1 = 100, 132, 107, 129  # input traces; the network samples either side of them:
    block = (math.floor(i0 * 0.7), math.floor((i1 - 1) * 0.7) + 2, math.floor(j0 * 0.7), math.floor((j1 - 1) * 0.7) + 2)
    assert block[0] % 8 and block[2] % 8, block  # off the pooling grid (8)
    networks = []
    for axis in (0, 1):
        a0, a1, b0, b1 = region = network_region(block, axis, cube.shape, 0.7)
        assert a0 > 0 and b0 > 0 and a1 < cube.shape[0] and b1 < cube.shape[1], region  # inside the cube
        probability = np.zeros(grid, np.float32)
        out = network_block(BlockPlace(block, region), cube[a0:a1, b0:b1], axis, opt, 0.7, scale, grid[axis])
        probability[block[0]:block[1], block[2]:block[3]] = out.arrays["probability"]
        networks.append(probability)
    diff = np.abs(network_probability(plan, networks, (i0, i1, j0, j1)) - whole[i0:i1, j0:j1]).max()
    print(f"  block core against the whole cube: {diff:.2e}")
    assert diff <= 1e-5


def job_limit(tmp: pathlib.Path) -> None:
    import dask.array  # noqa: F401 - imported by the block run: in the process before its limit is measured
    import zarr

    from seismo3d.jobs.faults import run_faults_job

    # 128 samples a trace: with the stages after the blocks in the plan (their fixed parts: the throws' windows, the
    # picture) the smallest limit by blocks of a 192 x 192 x 64 cube rose above its in-memory edge (1.10 GB named
    # against 1.07 GB) once the cube's network ran on two grids; a 128^3 cube leaves no limit between the two either
    shape = (192, 192, 128)
    cube_npy = tmp / "cube.npy"
    np.save(cube_npy, synthetic_cube(shape, seed=2).cube.astype(np.float32))
    in_memory = run_faults_job(cube_npy, tmp / "mem", memory_limit=64 << 30, progress=False).written

    # beyond the limit: below the in-memory run's need, above the smallest blocks' (a third of the way: ~65 MiB
    # above the limit the refusal names, ~190 MiB below the in-memory edge)
    limit = _limit_between(cube_npy, shape, tmp, 1 / 3)
    with _log() as caplog:
        written = run_faults_job(cube_npy, tmp / "out", memory_limit=limit, progress=False).written
    assert written["likelihood"].name == "fault_likelihood.zarr"
    assert "block by block" in caplog.text
    group = zarr.open_group(str(written["likelihood"]), mode="r")
    reference = np.load(in_memory["likelihood"])
    assert np.abs(group["likelihood"][:] - reference).max() <= 1e-5
    traced = zarr.open_group(str(written["surfaces_zarr"]), mode="r")
    assert np.abs(traced["votes"][:] - np.load(in_memory["votes"])).max() <= 1e-6
    assert _rows(written["summary"]) == _rows(in_memory["summary"])
    assert _rows(written["points"]) == _rows(in_memory["points"])
    assert written["figure"].stat().st_size > 10_000
    # run again into the same folder (overwrite=True: it holds this run's results): the finished likelihood is
    # reused, the same faults come out
    limit = _limit_between(cube_npy, shape, tmp, 1 / 3)
    with _log() as caplog:
        again = run_faults_job(cube_npy, tmp / "out", memory_limit=limit, overwrite=True, progress=False).written
    assert "reusing the finished fault likelihood" in caplog.text
    assert _rows(again["summary"]) == _rows(in_memory["summary"])
    assert _rows(again["points"]) == _rows(in_memory["points"])

    # a limit far below the in-memory surfaces' need, an eighth of the way from the limit the refusal names (~30
    # MiB above it): smaller blocks, the same faults and throws
    limit = _limit_between(cube_npy, shape, tmp, 1 / 8)
    written = run_faults_job(cube_npy, tmp / "tight", memory_limit=limit, progress=False).written
    assert _rows(written["summary"]) == _rows(in_memory["summary"])
    assert _rows(written["points"]) == _rows(in_memory["points"])
    assert sorted(p.name for p in (tmp / "tight").iterdir()) == [
        "fault_likelihood.zarr", "fault_points.csv", "fault_sticks_charisma.txt", "fault_sticks_iesx.txt",
        "fault_sticks_opendtect.txt", "fault_sticks_rms.pol",
        "fault_summary.csv", "fault_surfaces.zarr", "fault_surfaces_gocad", "faults.png", "faults.vtp", "run.json"]
    print(f"  {len(_rows(in_memory['summary']))} faults, the same in memory, by blocks, again and under a tighter limit")


def segy_lazy(tmp: pathlib.Path) -> None:
    """A SEG-Y cube over the limit: read block by block, its likelihood equal to the in-memory one, its volumes
    written as SEG-Y with the input's headers."""
    import dask.array  # noqa: F401 - imported by the block run: measured in the process before its limit is set
    import zarr

    from seismo3d.jobs.faults import run_faults_job
    from seismo3d.seismic.faults.likelihood.learned import LearnedOptions, learned_fault_likelihood
    from seismo3d.seismic.io import open_segy, read_segy

    cube = synthetic_cube((192, 160, 128), seed=5).cube.astype(np.float32)
    path = write_segy_cube(tmp / "cube.sgy", cube, sorting="crossline")
    # the reference first: the process then holds the network's session and the kernels, as the suite's did when
    # this was its test (run alone, the limit below was too small for the surfaces' blocks)
    reference = learned_fault_likelihood(cube)  # the default likelihood
    # the in-memory run needs 520 MiB beside the process: blocks, a third of the way from the refusal's limit (128
    # samples a trace: at 64 the stages after the blocks, the throws' window and the picture, left no limit between
    # the refusal's and the in-memory run's)
    limit = _limit_between(path, cube.shape, tmp, 1 / 3)
    with _log() as caplog:
        written = run_faults_job(path, tmp / "out", memory_limit=limit, progress=False).written
    assert "block by block" in caplog.text
    group = zarr.open_group(str(written["likelihood"]), mode="r")
    diff = np.abs(group["likelihood"][:] - reference.likelihood)
    # equal up to float rounding, except where rounding flips the min_dip mask (the dip within 0.01 deg of it)
    min_dip = LearnedOptions().min_dip
    assert diff[np.abs(reference.dip_deg - min_dip) > 0.01].max() <= 1e-5 and np.count_nonzero(diff > 1e-5) <= 3
    assert list(group["inline"][:]) == list(range(101, 293))
    # the SEG-Y volumes, written block by block with the input's headers, as the in-memory run writes them
    assert np.abs(read_segy(written["likelihood_segy"])[0] - reference.likelihood).max() <= 1e-5
    # strike and dip not computed (NaN in the store: the likelihood below its orientation floor) are 0 in SEG-Y
    assert np.array_equal(read_segy(written["dip_segy"])[0], np.nan_to_num(group["dip_deg"][:], nan=0.0))
    traced = zarr.open_group(str(written["surfaces_zarr"]), mode="r")
    assert np.array_equal(read_segy(written["votes_segy"])[0], traced["votes"][:])
    with open_segy(written["strike_segy"]) as out, open_segy(path) as src:
        assert out.sorting == src.sorting == "crossline" and out.format == 5
        np.testing.assert_array_equal(out.cdp_x, src.cdp_x)
    print(f"  likelihood diff off the mask edge {diff[np.abs(reference.dip_deg - min_dip) > 0.01].max():.2e}")


def demo_blocks(tmp: pathlib.Path) -> None:
    """The 128^3 demo by blocks (the decision made to say so, as `--memory-limit 500MB` does in a fresh process):
    every file byte-identical to the in-memory run's (the picture aside: its grey scale is clipped from its three
    slices when the cube is read lazily), and run.json holds the seconds of each step by either path."""
    import seismo3d.seismic.blocks.options as block_options
    from seismo3d.jobs.faults import run_faults_job

    memory = run_faults_job(None, tmp / "memory", demo=True, progress=False)
    fits = block_options.fits_in_memory
    block_options.fits_in_memory = lambda *args, **kwargs: False
    try:
        with _log() as caplog:
            blocks = run_faults_job(None, tmp / "blocks", demo=True, progress=False)
    finally:
        block_options.fits_in_memory = fits
    assert "samples traced block by block" in caplog.text
    assert blocks.written["likelihood"].name == "fault_likelihood.zarr"
    compared = sorted(p.name for p in (tmp / "memory").iterdir() if p.name not in ("run.json", "faults.png"))
    assert len(compared) == 14, compared  # 4 SEG-Y volumes, the demo's cube and truth, faults.vtp, 2 CSVs, 4 stick
    # files and the TSurf folder
    files = []  # every file, the TSurf folder's one per fault among them
    for name in compared:
        path = tmp / "memory" / name
        files += [str(p.relative_to(tmp / "memory")) for p in sorted(path.rglob("*")) if p.is_file()] \
            if path.is_dir() else [name]
    differ = [n for n in files if (tmp / "memory" / n).read_bytes() != (tmp / "blocks" / n).read_bytes()]
    assert differ == [], differ
    by_blocks = ("fault likelihood", "ridges", "votes", "cells", "fault skins", "throw", "evidence")
    for result, steps in ((memory, ("fault likelihood", "voting", "fault skins", "throw")), (blocks, by_blocks)):
        seconds = json.loads(result.run_json.read_text())["stage_seconds"]
        assert {"read input", "write outputs", *steps} <= set(seconds) and all(v >= 0 for v in seconds.values())
    print(f"  {len(files)} files byte-identical, {memory.n_faults} faults")


def _peak_seed(path, il, xl):
    import segyio

    from seismo3d.seismic import reflector_picks

    with segyio.open(str(path)) as f:
        trace = f.iline[il][list(f.xlines).index(xl)]
        samples = np.asarray(f.samples)
    peaks, _ = reflector_picks(trace[None], polarity="peak")
    k = int(round(float(peaks[len(peaks) // 2])))
    return (il, xl, float(samples[k]))


def demo_interchange(tmp: pathlib.Path) -> None:
    """The demo cube has no coordinates: every interchange file says inline / crossline units; the TSurf read back
    by xtgeo is the faults.vtp mesh, the sticks read back are fault points, a few a stick."""
    import pyvista as pv
    import xtgeo
    from numpy.testing import assert_allclose

    from seismo3d.jobs.faults import run_faults_job
    from seismo3d.jobs.horizon import run_horizon_job
    from seismo3d.seismic.io.fault_sticks import read_fault_sticks

    job = run_faults_job(None, tmp / "demo", demo=True, progress=False)
    points = _rows(job.written["points"])
    assert {r["xy_unit"] for r in points} == {"inline/crossline"}
    assert all(float(r["x"]) == float(r["inline"]) and float(r["y"]) == float(r["crossline"]) for r in points)
    sticks = read_fault_sticks(job.written["sticks_opendtect"])
    assert sticks.xy_unit == "inline/crossline" and sticks.n_faults == job.n_faults
    assert sticks.n_nodes < len(points) / 10 and {(int(a), int(b), round(z, 3)) for a, b, z in zip(
        sticks.inline, sticks.crossline, sticks.z)} <= {(int(r["inline"]), int(r["crossline"]),
                                                         round(float(r["time_or_depth"]), 3)) for r in points}
    files = sorted(pathlib.Path(job.written["surfaces_tsurf"]).glob("*.ts"))
    vtp = pv.read(job.written["surfaces"])
    assert len(files) == job.n_faults  # a TSurf file per fault, each read by xtgeo
    n_vertices = n_triangles = 0
    for path in files:
        assert 'AXIS_UNIT "none" "none" "ms"' in path.read_text()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # xtgeo: 'uncommon AXIS_UNIT combination'
            surf = xtgeo.triangulated_surface_from_file(path, fformat="tsurf")
        n_vertices += surf.num_vertices
        n_triangles += surf.num_triangles
        # vertices: (inline, crossline, time) of fault points: whole lines, times on the 4 ms samples
        assert_allclose(surf.vertices[:, :2], np.round(surf.vertices[:, :2]))
        assert_allclose(surf.vertices[:, 2] % 4.0, 0.0, atol=1e-3)
    assert n_vertices == vtp.n_points and n_triangles == vtp.n_cells
    # a horizon of the demo cube as IRAP / ZMAP+ grids (unrotated, X / Y = line numbers), read back by xtgeo
    demo = job.written["input"]
    horizon = run_horizon_job(demo, [_peak_seed(demo, 64, 64)], tmp / "h.txt", faults=False, maps=True,
                              progress=False)
    rows = np.loadtxt(tmp / "h.txt", ndmin=2)
    truth = np.full((128, 128), np.nan)
    truth[rows[:, 0].astype(int) - 1, rows[:, 1].astype(int) - 1] = rows[:, 2]
    for fmt in ("irap_ascii", "irap_binary", "zmap"):
        surf = xtgeo.surface_from_file(horizon.maps[fmt])
        assert (surf.ncol, surf.nrow, surf.xori, surf.yori, surf.rotation) == (128, 128, 1.0, 1.0, 0.0)
        values = np.ma.filled(surf.values, np.nan)
        assert np.array_equal(np.isnan(values), np.isnan(truth))
        assert_allclose(values, truth, atol=5e-4, equal_nan=True)  # the text rows' 3 decimals
    print(f"  {job.n_faults} faults, {n_vertices} TSurf vertices, {n_triangles} triangles; horizon grids 128 x 128")


def labelled_cube(tmp: pathlib.Path) -> None:
    """seismo3d.open's cube traced in memory and by blocks: one result type, on the cube's coordinates, equal."""
    import dask.array as da
    import xarray as xr

    import seismo3d
    from seismo3d.seismic import FaultInterpretation, trace_faults
    from seismo3d.seismic.blocks.memory import in_memory_bytes, resident_memory, size_text
    from seismo3d.seismic.blocks.options import BlockRunOptions

    shape = (192, 160, 128)
    path = write_segy_cube(tmp / "cube.sgy", synthetic_cube(shape, seed=0).cube.astype(np.float32))
    cube = seismo3d.open(path)
    assert isinstance(cube.data, da.Array) and cube.dims == ("iline", "xline", "twt")
    assert {"cdp_x", "cdp_y"} <= set(cube.coords) and cube.attrs["sample_interval"] == 4.0
    started = time.perf_counter()
    in_memory = trace_faults(cube, progress=False)
    memory_seconds = time.perf_counter() - started
    # between the blocks' need (~100 MB beyond the process) and the run in memory's (160 MiB + 24 x the cube)
    limit = resident_memory() + (300 << 20)
    assert 300 << 20 < in_memory_bytes(shape)
    started = time.perf_counter()
    with _log() as caplog:
        by_blocks = trace_faults(cube, memory_limit=limit, blocks=BlockRunOptions(work_dir=tmp), progress=False)
    blocks_seconds = time.perf_counter() - started
    assert "block by block" in caplog.text and by_blocks.stores
    assert type(in_memory) is type(by_blocks) is FaultInterpretation
    diffs = {}
    for name in ("likelihood", "strike_deg", "dip_deg", "votes", "thin"):
        a, b = getattr(in_memory, name), getattr(by_blocks, name)
        assert isinstance(a, xr.DataArray) and isinstance(b, xr.DataArray) and a.dims == b.dims == cube.dims
        assert isinstance(a.data, np.ndarray) and isinstance(b.data, da.Array)
        for c in ("iline", "xline", "twt", "cdp_x", "cdp_y"):
            assert np.array_equal(a[c].values, cube[c].values) and np.array_equal(b[c].values, cube[c].values)
        # strike and dip are NaN below the likelihood's orientation floor: at the same samples both ways
        same_nan = np.array_equal(np.isnan(a.values), np.isnan(b.values))
        diffs[name] = float(np.nanmax(np.abs(a.values - b.values), initial=0.0)) if same_nan else float("inf")
    assert diffs["likelihood"] <= 1e-5 and diffs["votes"] <= 1e-5, diffs
    assert len(in_memory.faults) == len(by_blocks.faults) > 0
    for f, g in zip(in_memory.faults, by_blocks.faults):
        assert np.array_equal(f.points, g.points)
    print(f"  {len(in_memory.faults)} faults, the same in memory ({memory_seconds:.0f} s) and by blocks under "
          f"{size_text(limit)} ({blocks_seconds:.0f} s); largest differences "
          + ", ".join(f"{k} {v:.1e}" for k, v in diffs.items()))


SECTIONS = {
    "learned_blocks": learned_blocks,
    "network_grid": network_grid,
    "job_limit": job_limit,
    "segy_lazy": segy_lazy,
    "demo_blocks": demo_blocks,
    "demo_interchange": demo_interchange,
    "labelled_cube": labelled_cube,
}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default=",".join(SECTIONS), help="sections, comma-separated (default: all)")
    ap.add_argument("--check", action="store_true", help="exit 1 when an assertion of a section failed")
    args = ap.parse_args(argv)
    names = args.only.split(",")
    unknown = [n for n in names if n not in SECTIONS]
    if unknown:
        ap.error(f"unknown section(s) {', '.join(unknown)}: {', '.join(SECTIONS)}")
    results = []
    for name in names:
        print(f"{name}:", flush=True)
        start = time.perf_counter()
        with tempfile.TemporaryDirectory(prefix=f"fault_blocks_{name}_") as tmp:
            try:
                SECTIONS[name](pathlib.Path(tmp))
                ok = True
            except AssertionError:
                traceback.print_exc()
                ok = False
        results.append((name, ok, time.perf_counter() - start))
        print(f"  {'passed' if ok else 'FAILED'} in {results[-1][2]:.0f} s", flush=True)
    print(f"\n{'section':18s} {'result':>6s} {'s':>6s}")
    for name, ok, seconds in results:
        print(f"{name:18s} {'passed' if ok else 'FAILED':>6s} {seconds:6.0f}")
    failed = [name for name, ok, _ in results if not ok]
    return 1 if failed and args.check else 0


if __name__ == "__main__":
    sys.exit(main())
