"""Starts of the volume registration (seismo3d.seismic.volumes.starts): the masked FFT correlation against a direct
computation, and the anisotropy grid."""

import numpy as np
import pytest

from seismo3d.seismic.volumes.starts import MaskedNCC, anisotropies


def test_masked_ncc_equals_the_direct_correlation_at_every_shift():
    rng = np.random.default_rng(0)
    fixed = rng.normal(size=(7, 6, 8))
    img = rng.normal(size=(4, 3, 5))
    mask = (rng.random(img.shape) > 0.3).astype(np.float64)
    ncc, origin = MaskedNCC(fixed)(img, mask, min_overlap=12)
    checked = 0
    for k in np.ndindex(ncc.shape):
        shift = np.array(k) - origin  # fixed[x + shift] pairs with img[x]
        pairs = [(fixed[tuple(x + shift)], img[x]) for x in np.ndindex(img.shape)
                 if mask[x] and np.all(np.array(x) + shift >= 0) and np.all(np.array(x) + shift < fixed.shape)]
        if len(pairs) < 12:
            assert ncc[k] == -np.inf
            continue
        a, b = np.array(pairs).T
        assert ncc[k] == pytest.approx(np.corrcoef(a, b)[0, 1], abs=1e-9)
        checked += 1
    assert checked > 50


def test_anisotropies_cover_the_scale_range_in_sqrt2_steps():
    assert anisotropies("rigid", 0.5, 2.0) == (1.0,)
    a = np.array(anisotropies("axis_scaled", 0.5, 2.0))
    np.testing.assert_allclose(a, 2.0 ** np.arange(-2.0, 2.5, 0.5))
