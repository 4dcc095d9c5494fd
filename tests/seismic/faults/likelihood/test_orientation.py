"""Fault strike and dip from the structure tensor of a likelihood: a run by blocks gets the whole cube's bits."""

from __future__ import annotations

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic.faults.likelihood.orientation import orientation_from_likelihood


def test_fault_orientation_of_a_core_equals_the_whole_cubes_bit_for_bit():
    """``core``: the strike and dip of a block's core from the likelihood within the smoothing's halo of it (scipy's
    Gaussian passes cropped to the core's lines after each axis, the tensor eigen-decomposed at the core only, as the
    orientation of a run by blocks takes them) are the whole cube's there, bit for bit: inside the cube, at its
    edges and at a corner; a 2D image has no core."""
    rng = np.random.default_rng(6)
    shape = (60, 52, 96)
    likelihood = rng.random(shape, dtype=np.float32) * (rng.random(shape) > 0.6)
    strike, dip = orientation_from_likelihood(likelihood, sigma=2.0)
    halo = 9  # ceil(4 sigma) + 1: the Gaussian's radius and the gradient's neighbour
    for i0, i1, j0, j1 in [(20, 36, 18, 30), (0, 16, 0, 52), (44, 60, 40, 52)]:
        a0, a1, b0, b1 = max(i0 - halo, 0), min(i1 + halo, shape[0]), max(j0 - halo, 0), min(j1 + halo, shape[1])
        core = (slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0))
        s, d = orientation_from_likelihood(likelihood[a0:a1, b0:b1], sigma=2.0, core=core)
        assert s.shape == d.shape == (i1 - i0, j1 - j0, shape[2]) and s.dtype == d.dtype == np.float32
        assert np.array_equal(s, strike[i0:i1, j0:j1]) and np.array_equal(d, dip[i0:i1, j0:j1])
    with pytest.raises(InputError, match="core"):
        orientation_from_likelihood(likelihood[0], core=(slice(0, 4), slice(0, 4)))


def test_orientation_of_a_dipping_line():
    # a fault line dipping 60 degrees towards +trace: normal (sin 60, -cos 60) up to sign -> strike 90, dip 60
    img = np.zeros((120, 120), np.float32)
    z = np.arange(120)
    x = (40 + z / np.tan(np.radians(60))).round().astype(int)
    img[x, z] = 1.0
    from scipy.ndimage import gaussian_filter
    img = gaussian_filter(img, 1.5)
    strike, dip = orientation_from_likelihood(img, sigma=2.0)
    on = img > 0.5 * img.max()
    assert abs(np.median(dip[on]) - 60.0) < 3.0
    assert (strike[on] == 270.0).mean() > 0.9  # dips towards +trace: strike 270 (module conventions)
