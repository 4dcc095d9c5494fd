"""Tests of seismo3d.seismic.blocks.plan: each declared step gets the largest block its bytes allow under the budget
(or its forced side), a step without bytes runs on another step's blocks, and a step of mostly serial kernels trades
halo for idle cores."""

from __future__ import annotations

import pytest

from seismo3d.errors import InputError
from seismo3d.seismic.blocks.options import ChunkOptions
from seismo3d.seismic.blocks.plan import MEMORY_HEADROOM, BlockStep, around, plan_steps


def _plan(steps, budget: int) -> dict:
    """The plan of ``steps`` in blocks of whole 8-trace tiles, one worker, whose block budget is ``budget`` bytes (a
    1 MiB limit, the process holding the rest)."""
    limit = 1 << 20
    return plan_steps(steps, ChunkOptions(memory_limit=limit, tile=8), baseline=limit - round(budget / MEMORY_HEADROOM),
                      what="x")


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
    sizes = _plan(steps[:3], 10_000)
    # a: (96 + 4)^2 = 10000 fits, 104 does not; b: 10 * 24^2 = 5760 fits, 32 does not (10240), below its cap of 48;
    # c: forced
    assert sizes == {"a": 96, "b": 24, "c": 16}
    # d: nothing fits, not even the tile: refused, naming the memory it needs and the limit
    with pytest.raises(InputError, match=r"x needs about 0.93 GiB but the memory limit is 0.00 GiB: raise memory_limit"):
        _plan(steps, 10_000)
    with pytest.raises(InputError, match="BlockStep\\(kind=...\\) must be one of map, reduce, gather"):
        BlockStep("x", "scatter", 0, square, 8)


def test_a_step_without_bytes_is_run_on_another_steps_blocks_not_planned():
    steps = (BlockStep("thin", "reduce", 2, lambda b: b * b, 64), BlockStep("cells", "gather"))
    assert _plan(steps, 1000) == {"thin": 24}  # 24^2 = 576 fits, 32^2 = 1024 does not
    assert around((0, 4, 4, 8), 2, (10, 7)) == (0, 6, 2, 7)  # grown by 2 traces, clipped to the cube


def test_the_held_stages_need_is_their_largest_with_the_items_gathered():
    """Stages after the blocks (HeldStage) are planned by their largest model at the items gathered, not by a block."""
    from seismo3d.seismic.blocks.plan import HeldStage, held_need

    stages = (HeldStage("cells", lambda n: 100 * n), HeldStage("writer", lambda n: 5000 + 10 * n))
    assert held_need(stages, 10) == (5100, "writer")
    assert held_need(stages, 1000) == (100_000, "cells")
    assert held_need((), 1000) == (0, "")
