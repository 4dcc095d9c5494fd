"""Chunked fault likelihood (seismo3d.seismic.faults.likelihood.scan_blocks): equal to the in-memory scan block by block,
resumable after a killed run, within its memory limit, on the threaded and the distributed scheduler."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import fault_likelihood
from seismo3d.seismic.blocks.options import ChunkOptions
from seismo3d.seismic.faults.likelihood.scan_blocks import chunked_fault_likelihood


@pytest.fixture(scope="module")
def cube():
    """A faulted cube whose sides are not multiples of the blocks (partial blocks at the far edges)."""
    return synthetic_cube((112, 80, 72), seed=3).cube.astype(np.float32)


@pytest.fixture(scope="module")
def reference(cube):
    return fault_likelihood(cube)


def _assert_same(result, reference):
    arrays = result.open()
    fl = arrays["likelihood"][:]
    assert fl.shape == reference.likelihood.shape
    assert np.abs(fl - reference.likelihood).max() <= 1e-5
    # the best plane may differ only where two planes tie to the likelihood's 20-bit quantum
    assert np.mean(arrays["strike_deg"][:] != reference.strike_deg) < 1e-4
    assert np.mean(arrays["dip_deg"][:] != reference.dip_deg) < 1e-4


@pytest.mark.slow  # 3.1 s with its fixture in the fast lane, whose budget is 60 s
def test_blocks_equal_the_whole_cube(cube, reference, tmp_path):
    """Blocks of 32 x 32 traces, scan strips of 32: every block boundary inside the cube, the result unchanged."""
    out = tmp_path / "fl.zarr"
    result = chunked_fault_likelihood(cube, out, chunking=ChunkOptions(block=32, strip=32))
    assert result.blocks_computed == {"amplitudes": 1, "balance": 1, "semblance": 12, "scan_inline": 3,
                                      "scan_crossline": 4, "decode": 12}
    assert sum(result.blocks_resumed.values()) == 0
    _assert_same(result, reference)
    # an output that exists is complete, and the work folder is gone
    assert not (tmp_path / "fl.zarr.partial").exists() and not (tmp_path / "fl.zarr.work").exists()
    xr = pytest.importorskip("xarray")
    ds = xr.open_zarr(out)
    assert ds["likelihood"].dims == ("inline", "crossline", "sample")
    assert ds.sizes == {"inline": 112, "crossline": 80, "sample": 72}


@pytest.mark.slow  # 2.5 s with its setup in the fast lane, whose budget is 60 s
def test_lazy_dask_input_with_coordinates(cube, reference, tmp_path):
    da = pytest.importorskip("dask.array")
    lazy = da.from_array(cube, chunks=(16, 80, 72))
    coords = {"inline": np.arange(1001, 1113), "crossline": np.arange(2001, 2081),
              "sample": np.arange(72) * 4.0, "sample_unit": "ms"}
    result = chunked_fault_likelihood(lazy, tmp_path / "fl.zarr", coords=coords,
                                      chunking=ChunkOptions(block=64, strip=64, workers=2))
    _assert_same(result, reference)
    import zarr
    group = zarr.open_group(str(tmp_path / "fl.zarr"), mode="r")
    assert group["inline"][0] == 1001 and group["sample"][-1] == 284.0
    assert group["sample"].attrs["units"] == "ms"
    assert group.attrs["complete"] is True


@pytest.mark.slow
def test_refusals(cube, tmp_path):
    with pytest.raises(InputError, match="3D cube"):
        chunked_fault_likelihood(cube[:, :, 0], tmp_path / "a.zarr")
    (tmp_path / "b.zarr").mkdir()
    with pytest.raises(InputError, match="already exists"):
        chunked_fault_likelihood(cube, tmp_path / "b.zarr")
    with pytest.raises(InputError, match="raise memory_limit"):
        chunked_fault_likelihood(np.zeros((64, 64, 20000), np.float32), tmp_path / "c.zarr",
                                 chunking=ChunkOptions(memory_limit=300 << 20))
    with pytest.raises(InputError, match="multiple of tile"):
        ChunkOptions(block=40)
    with pytest.raises(InputError, match="scheduler"):
        ChunkOptions(scheduler="my-cluster")
    bad = cube.copy()
    bad[3, 4, 5] = np.nan
    with pytest.raises(InputError, match="NaN"):
        chunked_fault_likelihood(bad, tmp_path / "d.zarr")
    assert not (tmp_path / "a.zarr").exists() and not (tmp_path / "c.zarr").exists()


@pytest.mark.slow  # 3.2 s in the fast lane, whose budget is 60 s
def test_memory_budget_is_the_block_size(tmp_path):
    """A lower memory limit gives smaller blocks (more of them) and the same likelihood."""
    syn = synthetic_cube((128, 128, 64), seed=4).cube.astype(np.float32)
    psutil = pytest.importorskip("psutil")
    tight = int(psutil.Process().memory_info().rss) + (80 << 20)  # 80 MiB beyond what this process holds already
    small = chunked_fault_likelihood(syn, tmp_path / "small.zarr", chunking=ChunkOptions(memory_limit=tight))
    large = chunked_fault_likelihood(syn, tmp_path / "large.zarr", chunking=ChunkOptions(memory_limit=4 << 30))
    assert small.blocks_computed["semblance"] > large.blocks_computed["semblance"] == 1
    assert np.abs(small.open()["likelihood"][:] - large.open()["likelihood"][:]).max() <= 1e-5


_RUN = textwrap.dedent("""
    import sys, numpy as np
    from seismo3d.data.synthetic import synthetic_cube
    from seismo3d.seismic.faults.likelihood.scan_blocks import ChunkOptions, chunked_fault_likelihood
    cube = synthetic_cube((112, 80, 72), seed=3).cube.astype(np.float32)
    r = chunked_fault_likelihood(cube, sys.argv[1], chunking=ChunkOptions(block=32, strip=32, scheduler="synchronous"))
    print(r.blocks_computed, r.blocks_resumed)
""")


@pytest.mark.slow
def test_resume_after_a_killed_run(reference, tmp_path):
    """Kill the run (SIGKILL) once some semblance blocks are done; the rerun computes only the others."""
    out = tmp_path / "fl.zarr"
    done = tmp_path / "fl.zarr.work" / "done"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.Popen([sys.executable, "-c", _RUN, str(out)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None:
        if done.is_dir() and len([p for p in done.iterdir() if p.suffix == ".json"]) >= 4:
            break
        time.sleep(0.05)
    assert proc.poll() is None, proc.communicate()[1].decode()[-2000:]
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    finished = len([p for p in done.iterdir() if p.suffix == ".json"])
    assert finished >= 4
    assert not out.exists()  # the killed run left nothing that looks finished
    assert (tmp_path / "fl.zarr.partial").exists()
    # the same run again resumes
    result = chunked_fault_likelihood(_cube(), out, chunking=ChunkOptions(block=32, strip=32))
    resumed = sum(result.blocks_resumed.values())
    assert resumed == finished
    assert sum(result.blocks_computed.values()) + resumed == 1 + 1 + 12 + 3 + 4 + 12
    _assert_same(result, reference)


def _cube():
    return synthetic_cube((112, 80, 72), seed=3).cube.astype(np.float32)


def test_other_run_in_the_way_is_refused(cube, tmp_path):
    work = tmp_path / "fl.zarr.work"
    work.mkdir()
    (work / "manifest.json").write_text(json.dumps({"shape": [1, 2, 3]}))
    with pytest.raises(InputError, match="unfinished run of another cube"):
        chunked_fault_likelihood(cube, tmp_path / "fl.zarr")


@pytest.mark.slow
def test_distributed_scheduler(cube, reference, tmp_path):
    """The same run on a dask.distributed cluster (2 worker processes), by its address."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as lc:
        result = chunked_fault_likelihood(cube, tmp_path / "fl.zarr",
                                          chunking=ChunkOptions(block=32, strip=32, scheduler=lc.scheduler_address))
    _assert_same(result, reference)
    with pytest.raises(InputError, match="cannot reach the dask scheduler"):
        chunked_fault_likelihood(cube, tmp_path / "x.zarr", chunking=ChunkOptions(scheduler="tcp://127.0.0.1:9"))
