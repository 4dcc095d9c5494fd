"""seismo3d.seismic.blocks.memory: the process's bytes the plans of a run by blocks count, rounded so that reruns of
the same command plan the same blocks."""

import dask.array as da
import numpy as np

import seismo3d.seismic.blocks.memory as memory
from seismo3d.seismic.blocks.memory import PROCESS_STEP, process_bytes, worker_baseline
from seismo3d.seismic.blocks.options import ChunkOptions
from seismo3d.seismic.faults.likelihood import learned_blocks
from seismo3d.seismic.faults.likelihood.learned import LearnedOptions

MIB = 1 << 20


def test_the_process_is_counted_in_steps_of_64_mib(monkeypatch):
    for measured, counted in ((430 * MIB, 448 * MIB), (434 * MIB, 448 * MIB), (448 * MIB, 448 * MIB),
                              (448 * MIB + 1, 512 * MIB), (1, PROCESS_STEP)):
        monkeypatch.setattr(memory, "resident_memory", lambda measured=measured: measured)
        assert process_bytes() == process_bytes("threads") == process_bytes("synchronous") == counted
    assert process_bytes("tcp://127.0.0.1:8786") == 256 * MIB  # a distributed worker: assumed


def test_a_run_s_measured_process_is_used_as_given(monkeypatch):
    def no_measure():
        raise AssertionError("measured again")

    monkeypatch.setattr(memory, "resident_memory", no_measure)
    x = da.zeros((96, 64, 50), chunks=(32, 32, -1), dtype=np.float32)
    assert worker_baseline(ChunkOptions(process=300 * MIB), x) == 300 * MIB + 2 * 4 * 32 * 32 * 50


def test_processes_a_few_mib_apart_plan_the_same_blocks(monkeypatch):
    # the demo cube at 680MB: its strike-and-dip blocks were 96 traces below a process of 435 MiB, 64 above, and runs
    # of the command measured 430-434 MiB
    x = da.zeros((128, 128, 128), chunks=(32, 32, -1), dtype=np.float32)
    plans = []
    for measured in (430, 433, 436, 440):
        monkeypatch.setattr(memory, "resident_memory", lambda measured=measured: measured * MIB)
        chunking = ChunkOptions(memory_limit=680 * 10**6)
        plans.append(learned_blocks._plan((128, 128, 128), LearnedOptions(), chunking, worker_baseline(chunking, x)))
    assert all(plan == plans[0] for plan in plans)
