"""seismo3d._threads.run_threads: every share runs once, on its own thread, and a kernel's error reaches the caller."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from seismo3d._threads import run_threads, task_workers


@pytest.mark.parametrize("n_threads", [1, 2, 3, 5])
def test_every_share_runs_once_with_its_index(n_threads):
    hits = np.zeros(100, np.int64)
    names = set()

    def kernel(t, n, out, step):
        names.add(threading.current_thread().name)
        out[t::n] += step

    run_threads(kernel, n_threads, hits, 1)
    assert np.array_equal(hits, np.ones(100, np.int64))
    assert len(names) == n_threads


def test_an_error_in_a_share_reaches_the_caller():
    def kernel(t, n):
        if t == 1:
            raise ValueError("share 1 failed")

    with pytest.raises(ValueError, match="share 1 failed"):
        run_threads(kernel, 2)


def test_outside_the_main_thread_the_shares_run_in_the_calling_thread():
    hits = np.zeros(10, np.int64)
    names = set()

    def kernel(t, n, out):
        names.add(threading.current_thread().name)
        out[t::n] += 1

    worker = threading.Thread(target=run_threads, args=(kernel, 3, hits), name="block-worker")
    worker.start()
    worker.join()
    assert np.array_equal(hits, np.ones(10, np.int64)) and names == {"block-worker"}


def test_from_any_thread_the_shares_run_on_threads_of_their_own():
    hits = np.zeros(10, np.int64)
    names = set()

    def kernel(t, n, out):
        names.add(threading.current_thread().name)
        out[t::n] += 1

    worker = threading.Thread(target=lambda: run_threads(kernel, 3, hits, from_any_thread=True), name="block-worker")
    worker.start()
    worker.join()
    assert np.array_equal(hits, np.ones(10, np.int64)) and len(names) == 3 and "block-worker" in names


@pytest.mark.parametrize("n_parts", [1, 2, 3, 7])
def test_map_parts_joins_each_parts_result_in_order(n_parts):
    from seismo3d._threads import map_parts

    calls = []
    x = np.arange(5 * 3).reshape(5, 3)
    out = map_parts(lambda part: calls.append(len(part)) or part * 2, x, n_parts)
    assert np.array_equal(out, x * 2) and sum(calls) == 5 and len(calls) == min(n_parts, 5)


def test_task_workers_follow_numbas_thread_count_in_the_main_thread_only():
    import numba

    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        assert task_workers(10) == 1
        if numba.config.NUMBA_NUM_THREADS >= 2:
            numba.set_num_threads(2)
            assert task_workers(10) == 2
            assert task_workers(1) == 1
            assert task_workers(0) == 1
            seen = []
            thread = threading.Thread(target=lambda: seen.append(task_workers(10)))
            thread.start()
            thread.join()
            assert seen == [1]
    finally:
        numba.set_num_threads(before)
