"""The consistency check before a volume registration is called converged (seismo3d.seismic.volumes.check): a result
that the way leading it, refined on its own, moves away from is not converged (right results pass it: the asserts on
reg.check in test_registration.py)."""

import os

import numpy as np
import pytest

from seismo3d.seismic import register_volumes
from seismo3d.seismic.volumes import registration


@pytest.fixture(scope="module")
def f3_pair(data_dir):
    from seismo3d.seismic import read_segy

    f3_crop = read_segy(os.path.join(data_dir, "seismic", "f3_crop.sgy"))[0]
    return f3_crop, np.ascontiguousarray(f3_crop[4:, 4:, 5:])  # a copy 4 inlines, 4 crosslines and 5 samples in


def test_a_result_off_the_leading_ways_optimum_is_not_converged(f3_pair, monkeypatch):
    # the refinement's answer stretched by 3 % along the moving inlines (as a two-way optimum pulled off by the biased
    # way would be): the way that leads, refined alone from it, goes back to its own optimum
    fixed, moving = f3_pair
    refine_down = registration._refine_down

    def stretched(*args, **kwargs):
        t_index, pair = refine_down(*args, **kwargs)
        return t_index @ np.diag([1.03, 1.0, 1.0, 1.0]), pair

    monkeypatch.setattr(registration, "_refine_down", stretched)
    reg = register_volumes(fixed, moving)
    assert not reg.converged
    assert "the way that leads the result, moves away from it" in reg.reason and "\n" not in reg.reason
    assert reg.check.scale_disagreement > 0.01, reg.check.to_dict()
