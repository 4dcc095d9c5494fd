"""The faults job on cubes beyond its memory limit (seismo3d.jobs.faults, issue 19): the block-by-block fault
likelihood and fault surfaces give the same faults as the in-memory run, reused when finished; SEG-Y cubes are read
lazily."""

import csv
import logging

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.jobs.faults import run_faults_job
from seismo3d.seismic.faults.blocks.scan_blocks import resident_memory

# in memory 216 MiB beyond the process (in_memory_bytes); the smallest blocks of the learned likelihood ~92 MiB and of
# the surfaces less (minimum_memory_limit): a 128^3 cube leaves no limit between the two, its halo of 96 traces
SHAPE = (192, 192, 64)


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def cube_npy(tmp_path_factory):
    path = tmp_path_factory.mktemp("cube") / "cube.npy"
    np.save(path, synthetic_cube(SHAPE, seed=2).cube.astype(np.float32))
    return path


@pytest.fixture(scope="module")
def in_memory(cube_npy, tmp_path_factory):
    out = tmp_path_factory.mktemp("mem")
    return run_faults_job(cube_npy, out, memory_limit=64 << 30, progress=False).written


@pytest.mark.slow
def test_cube_beyond_the_limit_gives_the_same_faults(cube_npy, in_memory, tmp_path, caplog):
    limit = resident_memory() + (150 << 20)  # below the in-memory run's need, above the smallest blocks'
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        written = run_faults_job(cube_npy, tmp_path / "out", memory_limit=limit, progress=False).written
    assert written["likelihood"].name == "fault_likelihood.zarr"
    assert "block by block" in caplog.text
    import zarr
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
    limit = resident_memory() + (150 << 20)
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        again = run_faults_job(cube_npy, tmp_path / "out", memory_limit=limit, overwrite=True,
                               progress=False).written
    assert "reusing the finished fault likelihood" in caplog.text
    assert _rows(again["summary"]) == _rows(in_memory["summary"])
    assert _rows(again["points"]) == _rows(in_memory["points"])


@pytest.mark.slow
def test_tight_limit_traces_the_surfaces_block_by_block(cube_npy, in_memory, tmp_path):
    """A limit far below the in-memory surfaces' need (about 76 bytes a sample, 171 MiB here): smaller blocks, the
    same faults and throws."""
    limit = resident_memory() + (130 << 20)  # the learned likelihood's blocks 64 traces wide (3 x 3)
    written = run_faults_job(cube_npy, tmp_path / "out", memory_limit=limit, progress=False).written
    assert _rows(written["summary"]) == _rows(in_memory["summary"])
    assert _rows(written["points"]) == _rows(in_memory["points"])
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "fault_likelihood.zarr", "fault_points.csv", "fault_sticks_charisma.txt", "fault_sticks_iesx.txt",
        "fault_sticks_opendtect.txt",
        "fault_summary.csv", "fault_surfaces.zarr", "fault_surfaces_gocad.ts", "faults.png", "faults.vtp", "run.json"]


@pytest.mark.slow
def test_segy_cube_is_read_lazily(write_segy_cube, tmp_path, caplog):
    """A SEG-Y cube over the limit: read block by block, its likelihood equal to the in-memory one, its volumes
    written as SEG-Y with the input's headers."""
    from seismo3d.seismic.faults.likelihood.learned import LearnedOptions, learned_fault_likelihood

    cube = synthetic_cube((192, 160, 64), seed=5).cube.astype(np.float32)
    path = write_segy_cube(tmp_path / "cube.sgy", cube, sorting="crossline")
    import dask.array  # noqa: F401 - imported by the block run: measured in the process before its limit is set
    import zarr  # noqa: F401
    # the in-memory run needs 180 MiB beside the process: blocks (the learned likelihood's 96 traces wide, 2 x 2)
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        written = run_faults_job(path, tmp_path / "out", memory_limit=resident_memory() + (170 << 20),
                                 progress=False).written
    assert "block by block" in caplog.text
    import zarr
    group = zarr.open_group(str(written["likelihood"]), mode="r")
    reference = learned_fault_likelihood(cube)  # the default likelihood
    diff = np.abs(group["likelihood"][:] - reference.likelihood)
    # equal up to float rounding, except where rounding flips the min_dip mask (the dip within 0.01 deg of it)
    min_dip = LearnedOptions().min_dip
    assert diff[np.abs(reference.dip_deg - min_dip) > 0.01].max() <= 1e-5 and np.count_nonzero(diff > 1e-5) <= 3
    assert list(group["inline"][:]) == list(range(101, 293))
    # the SEG-Y volumes, written block by block with the input's headers, as the in-memory run writes them
    from seismo3d.seismic.io import open_segy, read_segy
    assert np.abs(read_segy(written["likelihood_segy"])[0] - reference.likelihood).max() <= 1e-5
    assert np.array_equal(read_segy(written["dip_segy"])[0], group["dip_deg"][:])
    traced = zarr.open_group(str(written["surfaces_zarr"]), mode="r")
    assert np.array_equal(read_segy(written["votes_segy"])[0], traced["votes"][:])
    with open_segy(written["strike_segy"]) as out, open_segy(path) as src:
        assert out.sorting == src.sorting == "crossline" and out.format == 5
        np.testing.assert_array_equal(out.cdp_x, src.cdp_x)


def test_bad_memory_limit(cube_npy, tmp_path):
    with pytest.raises(InputError, match="memory_limit"):
        run_faults_job(cube_npy, tmp_path / "o", memory_limit="lots", progress=False)
    with pytest.raises(InputError, match="at least 64 MB"):
        run_faults_job(cube_npy, tmp_path / "o", memory_limit=1000, progress=False)


@pytest.mark.slow  # two runs of the demo: ~15 s in memory and ~30 s by blocks on 2 cores
def test_the_demo_by_blocks_writes_what_it_writes_in_memory(tmp_path, monkeypatch, caplog):
    """The 128^3 demo by blocks (the decision made to say so, as `--memory-limit 500MB` does in a fresh process):
    every file byte-identical to the in-memory run's (the picture aside: its grey scale is clipped from its three
    slices when the cube is read lazily), and run.json holds the seconds of each step by either path."""
    import json

    import seismo3d.seismic.blocks.options as block_options

    memory = run_faults_job(None, tmp_path / "memory", demo=True, progress=False)
    monkeypatch.setattr(block_options, "fits_in_memory", lambda *args, **kwargs: False)
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        blocks = run_faults_job(None, tmp_path / "blocks", demo=True, progress=False)
    assert "samples traced block by block" in caplog.text
    assert blocks.written["likelihood"].name == "fault_likelihood.zarr"
    compared = sorted(p.name for p in (tmp_path / "memory").iterdir() if p.name not in ("run.json", "faults.png"))
    assert len(compared) == 13  # the four SEG-Y volumes, the demo's cube and truth, faults.vtp, two CSV, four more
    assert [n for n in compared if (tmp_path / "memory" / n).read_bytes() != (tmp_path / "blocks" / n).read_bytes()] \
        == []
    for result, steps in ((memory, ("fault likelihood", "voting", "fault skins", "throw")),
                          (blocks, ("fault likelihood", "ridges", "votes", "cells", "fault skins, throw and evidence"))):
        seconds = json.loads(result.run_json.read_text())["stage_seconds"]
        assert {"read input", "write outputs", *steps} <= set(seconds) and all(v >= 0 for v in seconds.values())
