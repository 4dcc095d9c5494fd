import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.errors import InputError, RegistrationError
from seismo3d.geometry import apply_transform, make_transform, rotation_about_axis, rotation_matrix
from seismo3d.registration import ransac


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("model", ["rigid", "similarity", "axis_scaled", "affine"])
def test_ransac_with_60_percent_outliers(d, model, rng):
    rot = rotation_matrix(130) if d == 2 else rotation_about_axis([1, -2, 0.5], 130)
    lin = {"rigid": rot, "similarity": 2.0 * rot, "axis_scaled": rot * [0.5, 2.0, 1.3][:d],
           "affine": rot * [0.5, 2.0, 1.3][:d] + 0.2 * np.eye(d)[::-1]}[model]
    truth = make_transform(lin, rng.normal(size=d))
    x = rng.uniform(-5, 5, size=(200, d))
    y = apply_transform(truth, x) + rng.normal(scale=0.01, size=(200, d))
    bad = rng.choice(200, 120, replace=False)
    y[bad] = rng.uniform(-10, 10, size=(120, d))
    res = ransac(x, y, model=model, threshold=0.05, seed=3)
    inl = res.info["inliers"]
    good = np.setdiff1d(np.arange(200), bad)
    assert inl[good].mean() > 0.97 and inl[bad].mean() < 0.03
    assert_allclose(res.transform, truth, atol=0.02)


def test_ransac_is_deterministic(rng):
    x = rng.normal(size=(50, 3))
    y = x + 1.0
    y[:20] = rng.normal(size=(20, 3))
    a = ransac(x, y, threshold=0.1, seed=5)
    b = ransac(x, y, threshold=0.1, seed=5)
    assert_allclose(a.transform, b.transform, atol=0)
    assert a.n_iterations == b.n_iterations


def test_ransac_no_consensus(rng):
    with pytest.raises(RegistrationError, match="RANSAC found no"):
        ransac(rng.normal(size=(30, 3)), rng.normal(size=(30, 3)), threshold=1e-4, max_trials=200)


def test_ransac_too_few_matches():
    with pytest.raises(InputError, match="at least 4"):
        ransac(np.zeros((3, 3)), np.zeros((3, 3)), model="affine", threshold=0.1)
