"""The network grids (seismo3d.seismic.faults.likelihood.network_grid): a block's grid is the whole cube's."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic.faults.likelihood.network_grid import to_network_grid


def test_network_grid_alignment_per_axis():
    block = np.random.default_rng(0).standard_normal((40, 40, 16)).astype(np.float32)
    _, first = to_network_grid(block, 0.7, origin=(13, 13), align=(1, 8))
    assert first == (10, 16, 0)  # ceil(13 * 0.7) = 10; the first multiple of 8 at or after 9.1
    with pytest.raises(InputError, match="align"):
        to_network_grid(block, 0.7, origin=(13, 13), align=(1, 8, 8))
