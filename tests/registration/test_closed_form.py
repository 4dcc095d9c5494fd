import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation
from skimage.transform import EuclideanTransform, SimilarityTransform

from seismo3d.errors import InputError
from seismo3d.geometry import apply_transform, make_transform, rotation_about_axis, rotation_matrix
from seismo3d.registration import fit_axis_scaled, fit_transform, min_points

MODELS = ["rigid", "similarity", "axis_scaled", "affine"]


def _random_transform(model, d, angle, rng):
    r = rotation_matrix(angle) if d == 2 else rotation_about_axis(rng.normal(size=3), angle)
    lin = {
        "rigid": r,
        "similarity": r * rng.uniform(0.3, 3.0),
        "axis_scaled": r * rng.uniform(0.3, 3.0, size=d),
        "affine": r * rng.uniform(0.3, 3.0, size=d) + 0.3 * rng.normal(size=(d, d)),
    }[model]
    return make_transform(lin, rng.normal(scale=10, size=d))


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("angle", [0.0, 37.0, 120.0, 179.0, 180.0])
def test_exact_recovery_noise_free(d, model, angle, rng):
    truth = _random_transform(model, d, angle, rng)
    x = rng.normal(scale=5, size=(40, d))
    est = fit_transform(x, apply_transform(truth, x), model=model)
    assert_allclose(est, truth, atol=1e-9)


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("scales", [(0.3, 3.0, 1.0), (3.0, 0.3, 2.0), (0.5, 0.5, 2.5)])
def test_axis_scales_extremes_recovered(d, scales, rng):
    truth = make_transform((rotation_matrix(170) if d == 2 else rotation_about_axis([1, 2, 3], 175))
                           * np.array(scales[:d]), [1.0, -2.0, 3.0][:d])
    x = rng.uniform(-10, 10, size=(30, d))
    assert_allclose(fit_axis_scaled(x, apply_transform(truth, x)), truth, atol=1e-9)


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("model,peer", [("rigid", EuclideanTransform), ("similarity", SimilarityTransform)])
def test_noisy_fit_matches_scikit_image_umeyama(d, model, peer, rng):
    truth = _random_transform(model, d, 60.0, rng)
    x = rng.normal(scale=3, size=(200, d))
    y = apply_transform(truth, x) + rng.normal(scale=0.2, size=(200, d))
    ref = peer.from_estimate(x, y)  # scikit-image's Umeyama
    assert ref
    assert_allclose(fit_transform(x, y, model=model), ref.params, atol=1e-9)


@pytest.mark.parametrize("d", [2, 3])
def test_noisy_affine_satisfies_normal_equations(d, rng):
    # (scikit-image's AffineTransform minimises an algebraic error, so it is no peer for least squares)
    x = rng.normal(scale=3, size=(200, d))
    w = rng.uniform(0.5, 2.0, size=200)
    y = apply_transform(_random_transform("affine", d, 60.0, rng), x) + rng.normal(scale=0.2, size=(200, d))
    resid = apply_transform(fit_transform(x, y, model="affine", weights=w), x) - y
    design = np.c_[x, np.ones(len(x))]
    assert_allclose(design.T @ (resid * w[:, None]), 0.0, atol=1e-9)


def test_rigid_matches_scipy_align_vectors_weighted(rng):
    x = rng.normal(size=(50, 3))
    w = rng.uniform(0.1, 2.0, size=50)
    y = x @ Rotation.random(random_state=7).as_matrix().T + rng.normal(scale=0.05, size=(50, 3))
    est = fit_transform(x, y, model="rigid", weights=w)
    wn = w / w.sum()
    rot, _ = Rotation.align_vectors(y - wn @ y, x - wn @ x, weights=w)
    assert_allclose(est[:3, :3], rot.as_matrix(), atol=1e-9)


@pytest.mark.parametrize("d", [2, 3])
def test_axis_scaled_noisy_is_a_minimum(d, rng):
    truth = _random_transform("axis_scaled", d, 100.0, rng)
    x = rng.normal(scale=3, size=(300, d))
    y = apply_transform(truth, x) + rng.normal(scale=0.3, size=(300, d))

    def energy(m):
        return float(np.sum((apply_transform(m, x) - y) ** 2))

    est = fit_axis_scaled(x, y)
    e = energy(est)
    # Between the nested families: affine <= axis_scaled <= similarity.
    assert energy(fit_transform(x, y, model="affine")) <= e + 1e-9
    assert e <= energy(fit_transform(x, y, model="similarity")) + 1e-9
    # And no small perturbation of R, S or t lowers it.
    r, s = est[:d, :d] / np.linalg.norm(est[:d, :d], axis=0), np.linalg.norm(est[:d, :d], axis=0)
    for k in range(50):
        dr = rotation_matrix(rng.normal(scale=0.2)) if d == 2 else rotation_about_axis(rng.normal(size=3), 0.2)
        pert = make_transform(dr @ r * (s * np.exp(rng.normal(scale=1e-3, size=d))), est[:d, d] + 1e-3 * rng.normal(size=d))
        assert energy(pert) >= e - 1e-9


def test_zero_weight_ignores_outlier(rng):
    x = rng.normal(size=(20, 3))
    truth = _random_transform("rigid", 3, 45.0, rng)
    y = apply_transform(truth, x)
    y[0] += 100.0
    w = np.ones(20)
    w[0] = 0.0
    assert_allclose(fit_transform(x, y, weights=w), truth, atol=1e-9)


@pytest.mark.parametrize("src,dst,match", [
    (np.zeros((0, 3)), np.zeros((0, 3)), "at least"),
    (np.zeros((5, 4)), np.zeros((5, 4)), r"\(N, 2\) or \(N, 3\)"),
    (np.full((5, 3), np.nan), np.zeros((5, 3)), "NaN"),
    (np.zeros((5, 3)), np.zeros((6, 3)), "paired"),
    (np.eye(3)[:2], np.eye(3)[:2], "at least 3"),
])
def test_bad_input(src, dst, match):
    with pytest.raises(InputError, match=match):
        fit_transform(src, dst, model="rigid")


@pytest.mark.parametrize("model", ["axis_scaled", "affine"])
def test_coplanar_source_rejected_for_3d_scales(model, rng):
    x = np.c_[rng.normal(size=(10, 2)), np.zeros(10)]
    with pytest.raises(InputError, match="coplanar"):
        fit_transform(x, x, model=model)


def test_unknown_model():
    with pytest.raises(InputError, match="model"):
        fit_transform(np.zeros((4, 3)), np.zeros((4, 3)), model="projective")


def test_min_points():
    assert [min_points(m, 3) for m in MODELS] == [3, 3, 4, 4]
    assert [min_points(m, 2) for m in MODELS] == [2, 2, 3, 3]
