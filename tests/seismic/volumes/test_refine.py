"""The refinement of the volume registration (seismo3d.seismic.volumes.refine): the two-way correlation's Jacobian
(with either gradient) against finite differences, its symmetry in the two volumes, and convergence from a start a
few samples off."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from seismo3d.errors import InputError
from seismo3d.seismic.volumes.model import N_AFFINE, Reparam, corner_distance, map_matrix
from seismo3d.seismic.volumes.pyramid import Sampled
from seismo3d.seismic.volumes.refine import PairCorrelation, refine


@pytest.fixture(scope="module")
def smooth_pair():
    """A smooth random volume and a copy of it through a known map (cubic resampling): (fixed, moving, truth)."""
    rng = np.random.default_rng(1)
    field = ndi.gaussian_filter(rng.normal(size=(40, 40, 48)), 3.0).astype(np.float32)
    truth = np.eye(4)
    truth[:3, :3] = map_matrix(10.0, (1.1, 0.9), 1.05)
    truth[:3, 3] = (6.0, 5.0, 4.0)
    grid = np.indices((24, 24, 30)).reshape(3, -1).astype(np.float64)
    moving = ndi.map_coordinates(field, truth[:3, :3] @ grid + truth[:3, 3:], order=3).reshape(24, 24, 30)
    return (Sampled(field, np.ones((40, 40), bool), (1, 1, 1), 2.0),
            Sampled(moving.astype(np.float32), np.ones((24, 24), bool), (1, 1, 1), 2.0), truth)


@pytest.mark.parametrize("gradient", ["central", "spline"])
@pytest.mark.parametrize("way", ["forward", "backward"])
def test_the_jacobian_matches_finite_differences(smooth_pair, way, gradient):
    # each way's points all inside the other volume (the Jacobian leaves out how the edge taper's weights change)
    fixed, moving, truth = smooth_pair
    if way == "forward":  # the small moving volume's samples, the large field interpolated
        pair = PairCorrelation(fixed, moving, Reparam("affine", None, None), 3000, ways=(way,), gradient=gradient)
        start = truth.copy()
    else:  # the small volume's samples again, as the fixed one, with the large field interpolated through the inverse
        pair = PairCorrelation(moving, fixed, Reparam("affine", None, None), 3000, ways=(way,), gradient=gradient)
        start = np.linalg.inv(truth)
    start[:3, 3] += (0.7, -0.4, 0.5)
    q = pair.params(start)
    ev = pair.evaluate(q)
    assert np.all(pair.evaluate(q).overlaps > 0.99)
    errors = []
    for k in range(N_AFFINE):
        h = 1e-4 * max(1.0, abs(q[k]))
        dq = np.zeros(N_AFFINE)
        dq[k] = h
        numeric = (pair.evaluate(q + dq).residuals - pair.evaluate(q - dq).residuals) / (2 * h)
        errors.append(np.linalg.norm(ev.jacobian[:, k] - numeric) / np.linalg.norm(numeric))
    # 'central': central differences of the volume, linear between samples, not the spline's own derivative:
    # 4.3-6.4 % off on this smooth volume (a missing or wrong term of the Jacobian is tens of per cent); 'spline':
    # the derivative of the spline values themselves: 0.4-1.1e-4 off (the finite differences' own error; limit 3e-4)
    limit = 0.08 if gradient == "central" else 3e-4
    assert max(errors) <= limit, errors


def test_an_unknown_gradient_or_way_is_refused(smooth_pair):
    fixed, moving, _ = smooth_pair
    with pytest.raises(InputError, match="gradient='exact' is not supported"):
        PairCorrelation(fixed, moving, Reparam("affine", None, None), 3000, gradient="exact")
    with pytest.raises(InputError, match="ways='both' is not supported"):
        PairCorrelation(fixed, moving, Reparam("affine", None, None), 3000, ways=("both",))


def test_the_two_way_correlation_does_not_change_when_the_volumes_swap_roles(smooth_pair):
    fixed, moving, truth = smooth_pair
    t = truth.copy()
    t[:3, 3] += (0.3, 0.2, -0.4)
    there = PairCorrelation(fixed, moving, Reparam("affine", None, None), n_points=10**6)
    back = PairCorrelation(moving, fixed, Reparam("affine", None, None), n_points=10**6)
    c1 = there.evaluate(there.params(t)).correlations
    c2 = back.evaluate(back.params(np.linalg.inv(t))).correlations
    np.testing.assert_allclose(c1, c2[::-1], atol=1e-9)


def test_refine_converges_from_a_start_a_few_samples_and_degrees_off(smooth_pair):
    fixed, moving, truth = smooth_pair
    start = np.eye(4)
    start[:3, :3] = map_matrix(14.0, (1.0, 1.0), 1.0)
    start[:3, 3] = truth[:3, 3] + (1.5, -1.0, 1.0)
    pair = PairCorrelation(fixed, moving, Reparam("affine", None, None), n_points=20000)
    r = refine(pair, start, max_iterations=30, tolerance=0.001)
    assert r.converged
    assert corner_distance(r.transform, truth, moving.shape) < 0.05
    assert r.correlation > 0.999


def test_the_way_that_interpolates_the_less_aliased_volume_leads(smooth_pair):
    # the field and every second sample of it: at equal misfits, the way interpolating the field (forward, with the
    # field fixed) weighs high_frequency ratio ** 4 (about 60) times the way interpolating the aliased copy; the
    # weights swap with the volumes
    fixed = smooth_pair[0]
    coarse = Sampled(np.ascontiguousarray(fixed.data[::2, ::2, ::2]), fixed.live[::2, ::2], (2, 2, 2), 2.0)
    there = PairCorrelation(fixed, coarse, Reparam("affine", None, None), 1000)
    back = PairCorrelation(coarse, fixed, Reparam("affine", None, None), 1000)
    there.weigh_ways([0.01, 0.01])
    back.weigh_ways([0.01, 0.01])
    ratio = (coarse.high_frequency / fixed.high_frequency) ** 4
    assert there.way_weights[0] / there.way_weights[1] == pytest.approx(ratio)
    assert ratio > 10.0
    np.testing.assert_allclose(back.way_weights, there.way_weights[::-1])
    there.weigh_ways([0.01, 0.04])  # a way with four times the misfit weighs four times less
    assert there.way_weights[0] / there.way_weights[1] == pytest.approx(4 * ratio)


def test_a_trial_without_its_jacobian_costs_the_same(smooth_pair):
    # the refinement's trial steps sample only the values; the Jacobian asked for afterwards reuses them
    fixed, moving, truth = smooth_pair
    pair = PairCorrelation(fixed, moving, Reparam("affine", None, None), 3000)
    q = pair.params(truth) + 0.05
    fresh = PairCorrelation(fixed, moving, Reparam("affine", None, None), 3000).evaluate(q)
    trial = pair.evaluate(q, jacobian=False)
    assert trial.jacobian is None
    full = pair.evaluate(q)
    np.testing.assert_array_equal(trial.residuals, fresh.residuals)
    np.testing.assert_array_equal(full.jacobian, fresh.jacobian)
    assert trial.cost == fresh.cost
