import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.errors import DegenerateGeometryWarning, InputError, RegistrationError
from seismo3d.geometry import (
    apply_transform, estimate_normals, make_transform, perturb, rotation_about_axis, rotation_error_deg, rotation_matrix,
    translation_error,
)
from seismo3d.registration import fast_icp, icp


def _wavy_surface(n, rng, extent=1.0):
    xy = rng.uniform(-extent, extent, size=(n, 2))
    z = 0.3 * np.sin(3 * xy[:, 0]) * np.cos(2 * xy[:, 1]) + 0.2 * xy[:, 0] ** 2
    return np.c_[xy, z]


def _about_centroid(rot, points):
    c = points.mean(axis=0)
    return make_transform(rot, c - rot @ c)


@pytest.fixture(scope="module")
def bunny(data_dir):
    from seismo3d.data import load_bunny

    pair = load_bunny()
    return pair, estimate_normals(pair.target, k=16, orient="none")


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_bunny_point_to_plane_from_15_degrees(bunny, seed):
    """Real Stanford bunny scans: from ground truth perturbed by 15 degrees, end within 0.2 deg and 1 mm."""
    pair, normals = bunny
    rng = np.random.default_rng(seed)
    truth = pair.transform
    init = perturb(truth, 15.0, centre=apply_transform(truth, pair.source).mean(axis=0), rng=rng)
    assert rotation_error_deg(init, truth) == pytest.approx(15.0)
    res = icp(pair.source, pair.target, target_normals=normals, init=init)
    assert rotation_error_deg(res.transform, truth) < 0.14  # measured 0.089 deg, limit 1.5x
    assert translation_error(res.transform, truth) < 1.4e-4  # measured 9.0e-5, limit 1.5x
    assert res.converged and not res.degenerate
    assert res.fitness > 0.91 and res.inlier_rmse < 7e-4  # measured 0.944 and 4.5e-4: limits 3 points less, 1.5x


def _model_truth(model):
    rot = rotation_about_axis([0.3, 1.0, 0.2], 8.0)
    lin = {"rigid": rot, "similarity": 1.1 * rot, "axis_scaled": rot * [1.15, 0.9, 1.05],
           "affine": rot * [1.1, 0.95, 1.0] + 0.03 * np.array([[0, 1, 0], [0, 0, 1], [1, 0, 0]])}[model]
    return make_transform(lin, [0.05, -0.03, 0.02])


@pytest.mark.parametrize("model", ["rigid", "similarity", "axis_scaled", "affine"])
def test_point_to_plane_models_on_resampled_surface(model, rng):
    """Source and target sample the same surface at different points: point-to-plane is exact to ~1e-4."""
    target = _wavy_surface(6000, rng)
    normals = estimate_normals(target, k=12, orient="none")
    truth = _model_truth(model)
    world = _wavy_surface(4000, rng, extent=0.8)
    source = apply_transform(np.linalg.inv(truth), world)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DegenerateGeometryWarning)  # a shallow surface weakly constrains affine
        res = icp(source, target, model=model, target_normals=normals, max_distance=(0.2, 0.05, 0.02))
    # measured 6.3e-5 (rigid) to 1.3e-4 (similarity), limit 1.5x the worst
    assert np.sqrt(np.mean(np.sum((apply_transform(res.transform, source) - world) ** 2, axis=1))) < 2e-4


@pytest.mark.parametrize("model", ["rigid", "similarity", "axis_scaled", "affine"])
def test_point_to_point_models_with_exact_correspondences(model, rng):
    """Point-to-point ICP converges to the exact transform when the source points are target points.

    (With different samples it stalls near the point spacing and slides slowly along the surface: the weakness the
    paper's point-to-plane and fused terms address; see benchmarks/registration.py.)
    """
    target = _wavy_surface(6000, rng)
    truth = _model_truth(model)
    world = target[rng.choice(len(target), 3000, replace=False)]
    source = apply_transform(np.linalg.inv(truth), world)
    res = icp(source, target, method="point_to_point", model=model, max_distance=(0.2, 0.05, 0.02),
              max_iterations=200, tolerance=1e-10)
    assert np.abs(apply_transform(res.transform, source) - world).max() < 1e-6


@pytest.mark.parametrize("model", ["rigid", "similarity", "axis_scaled", "affine"])
def test_2d_point_to_plane(model, rng):
    t = np.sort(rng.uniform(0, 2 * np.pi, 3000))
    target = np.c_[np.cos(t) * (1 + 0.3 * np.cos(3 * t)), np.sin(t) * (1 + 0.2 * np.sin(2 * t))]
    normals = estimate_normals(target, k=10, orient="none")
    lin = {"rigid": rotation_matrix(20), "similarity": 0.9 * rotation_matrix(20),
           "axis_scaled": rotation_matrix(20) * [1.1, 0.9], "affine": rotation_matrix(20) @ [[1.1, 0.1], [0, 0.9]]}[model]
    truth = make_transform(lin, [0.1, -0.05])
    s = np.sort(rng.uniform(0, 2 * np.pi, 2000))
    src_world = np.c_[np.cos(s) * (1 + 0.3 * np.cos(3 * s)), np.sin(s) * (1 + 0.2 * np.sin(2 * s))]
    source = apply_transform(np.linalg.inv(truth), src_world)
    res = icp(source, target, model=model, target_normals=normals, max_distance=(0.5, 0.1, 0.03))
    # measured 6.1e-7 (rigid) to 2.2e-6 (affine), limit 1.5x the worst
    assert np.abs(apply_transform(res.transform, source) - src_world).max() < 3.4e-6


def test_plane_is_reported_degenerate(rng):
    xy = rng.uniform(-1, 1, size=(2000, 2))
    plane = np.c_[xy, np.zeros(2000)]
    normals = np.tile([0.0, 0.0, 1.0], (2000, 1))
    with pytest.warns(DegenerateGeometryWarning, match="does not constrain"):
        res = icp(plane + [0.02, 0.0, 0.01], plane, target_normals=normals, max_distance=0.1)
    assert res.degenerate and not res.converged
    assert res.min_eigenvalue < 1e-6


def test_well_posed_is_not_degenerate(rng):
    target = _wavy_surface(3000, rng)
    with warnings.catch_warnings():
        warnings.simplefilter("error", DegenerateGeometryWarning)
        res = icp(target, target, target_normals=estimate_normals(target, orient="none"), max_distance=0.05)
    assert not res.degenerate and res.converged
    assert_allclose(res.transform, np.eye(4), atol=1e-9)


def test_fast_icp_baseline_recovers_small_motion(rng):
    target = _wavy_surface(5000, rng)
    truth = _about_centroid(rotation_about_axis([1, 0, 0], 3.0), target)
    source = apply_transform(np.linalg.inv(truth), target)
    res = fast_icp(source, target, n_samples=1000)
    assert rotation_error_deg(res.transform, truth) < 0.3 and translation_error(res.transform, truth) < 0.01


@pytest.mark.parametrize("kwargs,match", [
    (dict(source=np.zeros((0, 3))), "at least"),
    (dict(source=np.zeros((10, 4))), r"\(N, 2\) or \(N, 3\)"),
    (dict(source=np.full((10, 3), np.nan)), "NaN"),
    (dict(source=np.zeros((10, 2))), "same dimension"),
    (dict(target_normals=None), "target_normals"),
    (dict(target_normals=np.zeros((5, 3))), "one normal per target point"),
    (dict(max_distance=-1.0), "max_distance"),
    (dict(method="point_to_line"), "method"),
    (dict(kernel="l1"), "kernel"),
    (dict(init=np.eye(3)), r"\(4, 4\)"),
])
def test_bad_input(kwargs, match, rng):
    target = _wavy_surface(100, rng)
    args = dict(source=target, target=target, target_normals=estimate_normals(target, orient="none"))
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        icp(args.pop("source"), args.pop("target"), **args)


def test_no_overlap_is_a_registration_error(rng):
    target = _wavy_surface(200, rng)
    with pytest.raises(RegistrationError, match="max_distance"):
        icp(target + 100.0, target, target_normals=estimate_normals(target, orient="none"), max_distance=0.1)
