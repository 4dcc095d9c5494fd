"""Tests of seismo3d.seismic.blocks.executor: a declared step runs on every block not finished yet, each read with its
halo; block tasks on a dask.distributed cluster use the worker's share of the host's cores for their numba kernels, and
leave the worker's setting as it was."""

from __future__ import annotations

import os

import numba
import numpy as np
import pytest

from seismo3d.seismic.blocks.apply import BlockOutput
from seismo3d.seismic.blocks.executor import BlockRun, kernel_threads, release_memory, run_block
from seismo3d.seismic.blocks.plan import CUBE, BlockStep, lateral_blocks


def _kernel_thread_count(_block):
    return numba.get_num_threads()


def test_run_block_without_a_share_leaves_numba_alone():
    assert run_block(_kernel_thread_count, None, 0) == numba.get_num_threads()


@pytest.mark.slow
def test_block_tasks_share_the_cores_between_workers(tmp_path):
    distributed = pytest.importorskip("distributed")
    cores = len(os.sched_getaffinity(0))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as lc, \
            distributed.Client(lc) as client:
        share = kernel_threads(client)
        assert list(share.values()) == [max(1, cores // 2)]  # one host, two worker threads
        run = BlockRun(tmp_path / "work")
        run.client = client
        tasks = [run.task(_kernel_thread_count, b) for b in range(4)]
        assert all(t.key.startswith("kernel_thread_count-") for t in tasks)
        assert client.compute(tasks, sync=True) == [min(max(1, cores // 2), numba.config.NUMBA_NUM_THREADS)] * 4
        kept = client.compute([run.task(_kernel_thread_count, 0, threads=False)], sync=True)
        assert kept == [numba.config.NUMBA_NUM_THREADS]  # the process's threads: restored after the tasks above


def test_a_saved_result_is_computed_once_and_read_back_by_a_resumed_run(tmp_path):
    calls = []

    def compute():
        calls.append(1)
        return [0.5, 2.0]

    run = BlockRun(tmp_path / "work")
    run.open({"shape": [4, 4, 4]})
    assert run.saved("scale", compute) == [0.5, 2.0]
    resumed = BlockRun(tmp_path / "work")
    assert resumed.saved("scale", compute) == [0.5, 2.0] and calls == [1]  # read back, not computed again
    assert (tmp_path / "work" / "scale.json").read_text() == "[0.5, 2.0]"


def _core_sum(place, window, offset):
    """The sum of a block's core (cut from its window) plus ``offset``, and the window's extent."""
    return BlockOutput(summary={"sum": float(window[place.core].sum()) + offset, "window": list(window.shape[:2])})


def test_run_step_reads_each_block_with_its_halo_and_skips_the_finished_ones(tmp_path):
    da = pytest.importorskip("dask.array")
    cube = np.arange(10 * 7 * 3, dtype=np.float32).reshape(10, 7, 3)
    step = BlockStep("sums", "reduce", 2, function=_core_sum, label="sums", inputs=(CUBE,), place=True)
    blocks = lateral_blocks(cube.shape, 4, 4)  # 3 x 2 blocks, the last ones clipped
    run = BlockRun(tmp_path / "work", scheduler="synchronous")
    run.open({"shape": list(cube.shape)})
    results = run.run_step(step, blocks, 0.5, source=da.from_array(cube, chunks=(5, 7, 3)))
    expected = [float(cube[i0:i1, j0:j1].sum()) + 0.5 for i0, i1, j0, j1 in blocks]
    assert [r["sum"] for r in results] == expected
    # the windows: each block grown by 2 traces, clipped to the cube (10 x 7 traces)
    assert [r["window"] for r in results] == [[6, 6], [6, 5], [8, 6], [8, 5], [4, 6], [4, 5]]
    assert run.computed == {"sums": 6} and run.resumed == {"sums": 0} and "sums" in run.seconds

    (tmp_path / "work" / "done" / "sums-4-0.json").unlink()  # as if interrupted before that block's marker
    again = BlockRun(tmp_path / "work", scheduler="synchronous")
    results = again.run_step(step, blocks, 0.5, source=da.from_array(cube, chunks=(5, 7, 3)))
    assert again.computed == {"sums": 1} and again.resumed == {"sums": 5}
    assert sorted(r["sum"] for r in results) == sorted(expected)  # the computed block first, then the finished ones
    assert results[0]["sum"] == expected[2]


def test_release_memory_starts_no_process(monkeypatch):
    # called after every block: a child process (ctypes.util.find_library runs /sbin/ldconfig -p) forks a process
    # the size of the blocks, block after block
    import subprocess

    def refuse(*args, **kwargs):
        raise AssertionError(f"release_memory started a process: {args[:1]}")

    monkeypatch.setattr(subprocess, "Popen", refuse)
    monkeypatch.setattr(os, "fork", refuse)
    release_memory()
    release_memory()
