"""Tests of seismo3d.seismic.blocks: block tasks on a dask.distributed cluster use the worker's share of the
host's cores for their numba kernels, and leave the worker's setting as it was."""

from __future__ import annotations

import os

import numba
import pytest

from seismo3d.seismic.blocks import BlockRun, kernel_threads, run_block


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
