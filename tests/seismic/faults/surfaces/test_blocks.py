"""Chunked fault surfaces (seismo3d.seismic.faults.surfaces.blocks): voting, thinning, thresholds, skins and
throws
block by block give the faults of the in-memory run, on a cube with dead traces and a mute; resumable; refusals."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import zarr

import seismo3d.seismic.faults.surfaces.blocks as chunked_faults
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic.faults.surfaces import voting
from seismo3d.seismic.faults.surfaces.blocks import chunked_fault_surfaces
from seismo3d.seismic.blocks.options import ChunkOptions
from seismo3d.seismic.faults.likelihood.scan_blocks import chunked_fault_likelihood
from seismo3d.seismic.faults.result import FaultLikelihood
from seismo3d.seismic.faults.steps import surface_cells
from seismo3d.seismic.faults import FaultTracingOptions, trace_faults

pytestmark = pytest.mark.slow

BLOCKS = ChunkOptions(block=64, strip=64, scheduler="synchronous")


@pytest.fixture(scope="module")
def cube():
    """Faulted, with sides that are not multiples of the blocks, 4 dead traces and a mute over the top 10 samples."""
    data = synthetic_cube((136, 120, 96), seed=5).cube.astype(np.float32)
    data[70:74, 40:44, :] = 0.0
    data[:, :, :10] = 0.0
    return data


@pytest.fixture(scope="module")
def likelihood(cube, tmp_path_factory):
    path = tmp_path_factory.mktemp("likelihood") / "fl.zarr"
    chunked_fault_likelihood(cube, path, chunking=BLOCKS)
    return path


def _reference(cube, likelihood, options=None):
    group = zarr.open_group(str(likelihood), mode="r")
    fl = FaultLikelihood(group["likelihood"][:], group["strike_deg"][:], group["dip_deg"][:])
    with pytest.warns(Warning):  # the dead samples are reported
        return trace_faults(cube, likelihood=fl, options=options, progress=False)


@pytest.fixture(scope="module")
def reference(cube, likelihood):
    return _reference(cube, likelihood)


def _assert_same_faults(result, reference):
    group = zarr.open_group(str(result.path), mode="r")
    assert np.array_equal(group["votes"][:], reference.votes)
    assert np.array_equal(group["thin"][:], reference.thin)
    assert result.thresholds == reference.thresholds
    assert len(result.faults) == len(reference.faults) >= 2
    for mine, theirs in zip(result.faults, reference.faults):
        assert mine.id == theirs.id
        assert np.array_equal(mine.points, theirs.points)
        assert np.array_equal(mine.likelihood, theirs.likelihood)
    for mine, theirs in zip(result.throws, reference.throws):
        np.testing.assert_allclose(mine.throw, theirs.throw, atol=1e-4, equal_nan=True)


def test_blocks_give_the_in_memory_faults(cube, likelihood, reference, tmp_path, monkeypatch):
    """Blocks of 64 x 64 traces (3 x 2 blocks, partial ones at the far edges; the voting halo reaches across
    several), through the sequence of steps the run in memory calls (steps.surface_cells): votes and thinned
    votes equal to the bit, the same thresholds, skins and throws."""
    runs = []

    def recorded(run, opt, bar=None):
        runs.append((type(run).__name__, type(run.run).__name__))
        return surface_cells(run, opt, bar)
    monkeypatch.setattr(chunked_faults, "surface_cells", recorded)
    result = chunked_fault_surfaces(cube, likelihood, tmp_path / "surfaces.zarr", chunking=BLOCKS)
    assert runs == [("SurfaceRun", "StoreRun")]  # the run in memory's, on the executor by blocks
    assert result.blocks_computed["votes"] == 6 and result.blocks_computed["ridges"] == 6
    assert sum(result.blocks_resumed.values()) == 0
    # the seconds of every step: the block steps, then the skins, the throw and the evidence (run.json's)
    assert {"ridges", "surfaces", "votes", "thin", "cells", "fault skins", "throw", "evidence"} <= set(
        result.seconds) and all(v >= 0 for v in result.seconds.values())
    assert result.n_cells == int(np.count_nonzero(reference.thin))
    _assert_same_faults(result, reference)
    assert not (tmp_path / "surfaces.zarr.work").exists() and not (tmp_path / "surfaces.zarr.partial").exists()
    assert zarr.open_group(str(result.path), mode="r").attrs["complete"] is True
    group = zarr.open_group(str(result.path), mode="r")
    assert not np.any(group["votes"][71:73, 41:43])  # the dead traces and the mute hold no votes
    assert np.array_equal(group["likelihood"][:], reference.likelihood)  # zeroed near dead samples, as in memory
    # the finished output of the same run is reused: no block computed again, the same faults
    again = chunked_fault_surfaces(cube, likelihood, tmp_path / "surfaces.zarr", chunking=BLOCKS)
    assert sum(again.blocks_computed.values()) == 0
    _assert_same_faults(again, reference)


def test_dense_faults_take_the_exact_quantile(cube, likelihood, reference, tmp_path, monkeypatch):
    """With a fault fraction so small that the lower threshold comes from the quantile of the thinned votes, the
    quantile equals numpy's on the whole cube, computed over the store's chunks (dask reductions: a histogram, then
    the values of its bin)."""
    monkeypatch.setattr(chunked_faults, "streamed_otsu", _counted(chunked_faults.streamed_otsu, calls := []))
    options = FaultTracingOptions(max_fault_fraction=0.02)
    dense = _reference(cube, likelihood, options)
    assert dense.thresholds[0] > reference.thresholds[0] + 1e-3  # the quantile raised the lower threshold
    reference = dense
    result = chunked_fault_surfaces(cube, likelihood, tmp_path / "dense.zarr", options=options, chunking=BLOCKS)
    _assert_same_faults(result, reference)
    assert len(calls) == 1


def _counted(function, calls: list):
    """``function``, each call appended to ``calls``."""
    def counted(*args, **kwargs):
        calls.append(1)
        return function(*args, **kwargs)
    return counted


def test_resume_after_an_interrupted_run(cube, likelihood, reference, tmp_path, monkeypatch):
    """A run stopped in the seeds' surfaces, then one stopped in the voting, leave no output that looks finished;
    each rerun skips the finished blocks, and the last gives the same faults."""

    def interrupted_at(original, call):
        calls = {"n": 0}

        def run(*args, **kwargs):
            calls["n"] += 1
            if calls["n"] == call:
                raise KeyboardInterrupt
            return original(*args, **kwargs)
        return run

    out = tmp_path / "surfaces.zarr"
    monkeypatch.setattr(voting, "seed_surfaces", interrupted_at(voting.seed_surfaces, 3))
    with pytest.raises(KeyboardInterrupt):
        chunked_fault_surfaces(cube, likelihood, out, chunking=BLOCKS)
    assert not out.exists() and (tmp_path / "surfaces.zarr.partial").exists()
    monkeypatch.undo()

    class Interrupted(voting.VoteSum):
        votes = interrupted_at(voting.VoteSum.votes, 3)

    monkeypatch.setattr(voting, "VoteSum", Interrupted)
    with pytest.raises(KeyboardInterrupt):
        chunked_fault_surfaces(cube, likelihood, out, chunking=BLOCKS)
    assert not out.exists()
    monkeypatch.undo()
    result = chunked_fault_surfaces(cube, likelihood, out, chunking=BLOCKS)
    assert result.blocks_resumed["ridges"] == 6 and result.blocks_computed["ridges"] == 0
    assert result.blocks_resumed["surfaces"] == 6 and result.blocks_computed["surfaces"] == 0
    assert result.blocks_resumed["votes"] == 2 and result.blocks_computed["votes"] == 4
    _assert_same_faults(result, reference)


def test_cells_too_many_for_the_stages_after_the_blocks_are_refused_then_resumed(cube, likelihood, reference,
                                                                                 tmp_path):
    """Cells that outnumber what the limit holds in the stages after the blocks (here a writer of 8 MiB a cell) are
    refused once counted, naming the limit they need; the blocks are kept, and the run under that limit resumes them
    all and gives the same faults."""
    import re

    from seismo3d.seismic.blocks.memory import parse_memory_limit
    from seismo3d.seismic.blocks.plan import HeldStage

    writer = HeldStage("a writer", lambda cells: cells << 23)
    out = tmp_path / "surfaces.zarr"
    with pytest.raises(InputError, match=r"thinned fault samples \(fault cells\) need about \S+ in a writer") as exc:
        chunked_fault_surfaces(cube, likelihood, out, chunking=BLOCKS, after=(writer,))
    limit = parse_memory_limit(re.search(r"pass memory_limit='(\S+)'", str(exc.value)).group(1))
    result = chunked_fault_surfaces(cube, likelihood, out, chunking=dataclasses.replace(BLOCKS, memory_limit=limit),
                                    after=(writer,))
    assert result.blocks_computed["votes"] == result.blocks_computed["cells"] == 0 < result.blocks_resumed["cells"]
    assert limit >= result.n_cells << 23
    _assert_same_faults(result, reference)


def test_refusals(cube, likelihood, tmp_path):
    out = tmp_path / "surfaces.zarr"
    out.mkdir()
    with pytest.raises(InputError, match="already exists"):
        chunked_fault_surfaces(cube, likelihood, out, chunking=BLOCKS)
    with pytest.raises(InputError, match="no 'likelihood' array of the cube's shape"):
        chunked_fault_surfaces(cube[:, :100], likelihood, tmp_path / "other.zarr", chunking=BLOCKS)
    with pytest.raises(InputError, match="raise memory_limit"):
        chunked_fault_surfaces(cube, likelihood, tmp_path / "small.zarr",
                               chunking=dataclasses.replace(BLOCKS, memory_limit=1 << 20))
    with pytest.raises(InputError, match="FaultTracingOptions"):
        chunked_fault_surfaces(cube, likelihood, tmp_path / "bad.zarr", options="defaults")
