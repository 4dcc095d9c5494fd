"""The preflight of a run over a cube (seismo3d.seismic.blocks.preflight): the size check and the sampled blocks."""

import numpy as np
import pytest

from seismo3d.errors import InputError, UnsupportedDataError
from seismo3d.seismic.blocks.preflight import SampleOptions, check_size, sample_blocks


def test_sample_options_are_checked():
    with pytest.raises(InputError, match="n_blocks"):
        SampleOptions(n_blocks=9)
    with pytest.raises(InputError, match="saturated"):
        SampleOptions(saturated=1.5)
    assert SampleOptions().worth_sampling((400, 400, 500)) and not SampleOptions().worth_sampling((128, 128, 128))


def test_the_sampled_blocks_are_copies_at_the_centre_then_towards_the_corners():
    cube = np.arange(100 * 80 * 300, dtype=np.float32).reshape(100, 80, 300)
    blocks = sample_blocks(cube, SampleOptions(n_blocks=3, traces=32, samples=96))
    assert [b.shape for b in blocks] == [(32, 32, 96)] * 3
    assert blocks[0][0, 0, 0] == cube[34, 24, 102]  # the centre: (100 - 32) / 2, (80 - 32) / 2, (300 - 96) / 2
    assert blocks[1][0, 0, 0] == cube[17, 12, 102] and blocks[2][0, 0, 0] == cube[51, 36, 102]
    blocks[0][:] = -1
    assert cube.min() == 0  # the cube itself is never modified


def test_a_cube_smaller_than_a_block_is_sampled_whole():
    cube = np.ones((20, 10, 40), np.float32)
    assert [b.shape for b in sample_blocks(cube, SampleOptions(n_blocks=1))] == [(20, 10, 40)]


def test_data_too_small_is_refused_with_what_it_needs():
    check_size((64, 40, 100), min_traces=(32, 8), min_samples=32, task="the run", spans="its windows")
    with pytest.raises(UnsupportedDataError, match="20 x 6 traces of 100 samples: the run needs at least 32 traces "
                                                   "along one lateral axis and 8 along the other"):
        check_size((20, 6, 100), min_traces=(32, 8), min_samples=32, task="the run", spans="its windows")
    with pytest.raises(UnsupportedDataError, match="needs at least 32 traces, and 32 samples"):
        check_size((64, 10), min_traces=(32, 8), min_samples=32, task="the run", spans="its windows")
