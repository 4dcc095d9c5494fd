"""Tests of seismo3d.seismic.blocks.executor: block tasks on a dask.distributed cluster use the worker's share of the
host's cores for their numba kernels, and leave the worker's setting as it was."""

from __future__ import annotations

import os

import numba
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic.blocks.executor import BlockRun, kernel_threads, run_block
from seismo3d.seismic.blocks.plan import BlockStep, plan_steps


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


def test_serial_step_blocks_trade_halo_for_idle_cores(monkeypatch):
    from seismo3d.seismic.blocks import plan as blocks

    monkeypatch.setattr(blocks, "usable_cores", lambda: 2)
    mib = 1 << 20

    def block_bytes(side):  # 1 MiB per trace of a block with 9 traces of halo
        return (side + 18) ** 2 * mib

    step = blocks.BlockStep("orientation", "reduce", 9, block_bytes, 256)

    # room for one block of 96 or two of 64 (each within half the budget): (82 / 64)^2 / 2 < (114 / 96)^2
    limit = int(2 * 82 ** 2 * mib / blocks.MEMORY_HEADROOM) + 1
    assert blocks.serial_step_blocks(step, limit=limit, baseline=0, workers=1, scheduler=None, tile=32) == (2, 64)
    # a third of that: one block of 32 (50^2 MiB) or two of 32 (each over half the budget: not allowed)
    small = int(50 ** 2 * mib / blocks.MEMORY_HEADROOM) + 1
    assert blocks.serial_step_blocks(step, limit=small, baseline=0, workers=1, scheduler=None, tile=32) == (1, 32)
    # a cluster runs the blocks its workers take: the count asked for
    cluster = "tcp://127.0.0.1:8786"
    assert blocks.serial_step_blocks(step, limit=limit, baseline=0, workers=1, scheduler=cluster, tile=32) == (1, 96)
    # two blocks at once asked for: never fewer
    assert blocks.serial_step_blocks(step, limit=limit, baseline=0, workers=2, scheduler=None, tile=32) == (2, 64)


def test_the_plan_gives_each_step_its_largest_block_that_fits_or_its_forced_side():
    def square(b):  # bytes of a block of b traces a side with a halo of 2
        return (b + 4) ** 2

    steps = (BlockStep("a", "map", 2, square, 512), BlockStep("b", "reduce", 0, lambda b: 10 * b * b, 48),
             BlockStep("c", "gather", 2, square, 512, fixed=16), BlockStep("d", "map", 0, lambda b: 10**9, 512))
    sizes = plan_steps(steps, tile=8, budget=10_000)
    # a: (96 + 4)^2 = 10000 fits, 104 does not; b: 10 * 24^2 = 5760 fits, 32 does not (10240), below its cap of 48;
    # c: forced; d: nothing fits, so the tile (the caller refuses it)
    assert sizes == {"a": 96, "b": 24, "c": 16, "d": 8}
    with pytest.raises(InputError, match="BlockStep\\(kind=...\\) must be one of map, reduce, gather"):
        BlockStep("x", "scatter", 0, square, 8)


def test_a_saved_result_is_computed_once_and_read_back_by_a_resumed_run(tmp_path):
    calls = []

    def compute():
        calls.append(1)
        return [0.5, 2.0]

    run = BlockRun(tmp_path / "work")
    run.open({"shape": [4, 4, 4]}, "the work folder")
    assert run.saved("scale", compute) == [0.5, 2.0]
    resumed = BlockRun(tmp_path / "work")
    assert resumed.saved("scale", compute) == [0.5, 2.0] and calls == [1]  # read back, not computed again
    assert (tmp_path / "work" / "scale.json").read_text() == "[0.5, 2.0]"
