"""SE(3) helpers: exp / log round trip, skew matrices."""

import numpy as np

from seismo3d.mapping.lie import exp_se3, log_se3, skew


def test_exp_log_round_trip(rng):
    for _ in range(20):
        delta = np.concatenate([rng.normal(0, 0.5, 3), rng.normal(0, 1.0, 3)])
        m = exp_se3(delta)
        np.testing.assert_allclose(m[:3, :3].T @ m[:3, :3], np.eye(3), atol=1e-12)
        np.testing.assert_allclose(log_se3(m), delta, atol=1e-10)


def test_skew_is_the_cross_product(rng):
    a, b = rng.normal(size=3), rng.normal(size=3)
    np.testing.assert_allclose(skew(a) @ b, np.cross(a, b), atol=1e-12)
