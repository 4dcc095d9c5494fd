"""The consistency check before a volume registration is called converged (seismo3d.seismic.volumes.check): a result
that the way leading it, refined on its own, moves away from is not converged; a right one is."""

import os

import numpy as np
import pytest

from seismo3d.data import resampled_pair
from seismo3d.seismic import register_volumes, registration_errors
from seismo3d.seismic.volumes import registration


@pytest.fixture(scope="module")
def f3_pair(data_dir):
    from seismo3d.seismic import read_segy

    f3_crop = read_segy(os.path.join(data_dir, "seismic", "f3_crop.sgy"))[0]
    # a copy on a grid rotated 12 degrees with bins 1.25 / 0.8 and a vertical scale of 1.1 (issue 33's pair)
    return resampled_pair(f3_crop, f3_crop.shape, scales=(1.25, 0.8, 1.1), angle_deg=12.0, offset=(0.3, 1.2, 1.5),
                          moving_fraction=1.0)


def test_a_right_result_passes_and_reports_both_ways(f3_pair):
    fixed, moving, truth = f3_pair
    reg = register_volumes(fixed, moving)
    assert reg.converged, reg.reason
    assert registration_errors(reg.transform_index, truth, moving.shape).max_scale_pct <= 1.0
    check = reg.check
    assert check.leading_way in ("forward", "backward")
    # measured (both orders): the leading way does not move from the result (0.00 samples, 0.0 %): limits the
    # refinement's own stopping step (VolumeOptions.tolerance, 0.02 samples) and 0.1 %; the other way 0.026-0.029
    # samples and 0.19-0.20 % away, limits 1.5x
    assert check.disagreement <= 0.02 and check.scale_disagreement <= 0.001, check.to_dict()
    assert check.other_way_disagreement <= 0.045 and check.other_way_scale_disagreement <= 0.003, check.to_dict()
    assert {"leading_way", "other_way_disagreement", "other_way_scale_disagreement"} <= set(check.to_dict())


def test_a_result_off_the_leading_ways_optimum_is_not_converged(f3_pair, monkeypatch):
    # the refinement's answer stretched by 3 % along the moving inlines (as a two-way optimum pulled off by the biased
    # way would be): the way that leads, refined alone from it, goes back to its own optimum
    fixed, moving, _ = f3_pair
    refine_down = registration._refine_down

    def stretched(*args, **kwargs):
        t_index, pair = refine_down(*args, **kwargs)
        return t_index @ np.diag([1.03, 1.0, 1.0, 1.0]), pair

    monkeypatch.setattr(registration, "_refine_down", stretched)
    reg = register_volumes(fixed, moving)
    assert not reg.converged
    assert "the way that leads the result, moves away from it" in reg.reason and "\n" not in reg.reason
    assert reg.check.scale_disagreement > 0.01, reg.check.to_dict()
