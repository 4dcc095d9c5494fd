import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

from seismo3d.errors import InputError
from seismo3d.geometry import (
    apply_transform, compose, decompose_axis_scaled, invert, make_transform, nearest_rotation, rotation_about_axis,
    rotation_error_deg, rotation_matrix, translation_error,
)


@pytest.mark.parametrize("d", [2, 3])
def test_compose_invert_apply(d, rng):
    a = make_transform(rng.normal(size=(d, d)) + 3 * np.eye(d), rng.normal(size=d))
    b = make_transform(rng.normal(size=(d, d)) + 3 * np.eye(d), rng.normal(size=d))
    p = rng.normal(size=(20, d))
    assert_allclose(apply_transform(compose(a, b), p), apply_transform(a, apply_transform(b, p)), atol=1e-12)
    assert_allclose(compose(a, invert(a)), np.eye(d + 1), atol=1e-12)


@pytest.mark.parametrize("angle", [0.5, 15.0, 90.0, 179.0])
def test_rotation_error_3d(angle, rng):
    r0 = Rotation.random(random_state=1).as_matrix()
    r1 = rotation_about_axis(rng.normal(size=3), angle) @ r0
    t = rng.normal(size=3)
    err = rotation_error_deg(make_transform(r1, t), make_transform(r0, t + [0.3, 0.4, 0.0]))
    assert err == pytest.approx(angle, abs=1e-7)
    assert translation_error(make_transform(r1, t), make_transform(r0, t + [0.3, 0.4, 0.0])) == pytest.approx(0.5)


def test_rotation_error_2d_ignores_scale():
    a = make_transform(rotation_matrix(30) * [2.0, 0.5], [0, 0])
    assert rotation_error_deg(a, make_transform(rotation_matrix(-10), [0, 0])) == pytest.approx(40.0)


def test_decompose_axis_scaled(rng):
    r = Rotation.random(random_state=4).as_matrix()
    s = np.array([0.3, 1.0, 3.0])
    rr, ss, tt = decompose_axis_scaled(make_transform(r * s, [1, 2, 3]))
    assert_allclose(rr, r, atol=1e-12)
    assert_allclose(ss, s, atol=1e-12)
    assert_allclose(tt, [1, 2, 3])


def test_nearest_rotation_is_proper():
    m = np.diag([1.0, 1.0, -1.0])  # a reflection
    r = nearest_rotation(m)
    assert np.linalg.det(r) == pytest.approx(1.0)


@pytest.mark.parametrize("bad", [np.eye(3)[:2], np.full((4, 4), np.nan), np.ones((4, 4))])
def test_bad_transforms(bad):
    with pytest.raises(InputError):
        apply_transform(bad, np.zeros((1, 3)))


def test_dimension_mismatch():
    with pytest.raises(InputError, match=r"\(N, 3\)"):
        apply_transform(np.eye(4), np.zeros((5, 2)))
