"""BlockRunOptions (seismo3d.seismic.blocks.options): the options of trace_faults' run by blocks, checked when made,
and the memory decision they apply."""

import pytest

from seismo3d.errors import InputError
from seismo3d.seismic import BlockRunOptions, trace_faults
from seismo3d.seismic.blocks.memory import in_memory_bytes


@pytest.mark.parametrize("kwargs, match", [
    ({"memory_limit": "lots"}, r"BlockRunOptions\(memory_limit=...\).*not a size"),
    ({"memory_limit": 1000}, r"BlockRunOptions\(memory_limit=...\).*at least 64 MB"),
    ({"in_memory": "yes"}, r"BlockRunOptions\(in_memory=...\)"),
    ({"work_dir": 3}, r"BlockRunOptions\(work_dir=...\)"),
    ({"scheduler": 8786}, r"BlockRunOptions\(scheduler=...\)"),
    ({"source": 3}, r"BlockRunOptions\(source=...\)"),
    ({"coords": [1, 2]}, r"BlockRunOptions\(coords=...\)"),
])
def test_bad_options_are_refused_when_made(kwargs, match):
    with pytest.raises(InputError, match=match):
        BlockRunOptions(**kwargs)


def test_the_decision():
    shape = (256, 256, 256)
    need = in_memory_bytes(shape)
    assert BlockRunOptions(memory_limit="2GB").limit == 2 * 10 ** 9
    assert not BlockRunOptions(memory_limit=need // 2).in_memory_for(shape)  # half the need: by blocks
    assert BlockRunOptions(memory_limit=need // 2, in_memory=True).in_memory_for(shape)  # forced
    assert not BlockRunOptions(memory_limit=64 << 30, in_memory=False).in_memory_for(shape)  # forced
    assert BlockRunOptions(memory_limit=need // 2).in_memory_for(shape, has_likelihood=True)
    assert BlockRunOptions(memory_limit=need // 2, in_memory=False).in_memory_for((100_000, 2000))  # 2D


def test_trace_faults_takes_only_block_run_options():
    with pytest.raises(InputError, match=r"trace_faults\(blocks=...\) must be a BlockRunOptions"):
        trace_faults([[0.0] * 8] * 8, blocks={"in_memory": True}, progress=False)
    with pytest.raises(InputError, match=r"trace_faults\(memory_limit=...\): .*at least 64 MB"):
        trace_faults([[0.0] * 8] * 8, memory_limit="1MB", progress=False)  # refused before any work
