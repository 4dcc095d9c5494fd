"""Fault strike and dip from the structure tensor of a likelihood: a run by blocks gets the whole cube's bits."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from seismo3d._progress import reporting_within
from seismo3d.errors import InputError
from seismo3d.seismic.faults.likelihood.orientation import orientation_from_likelihood


@pytest.mark.parametrize("sample_step", [1, 2, 3])
def test_fault_orientation_of_a_core_equals_the_whole_cubes_bit_for_bit(sample_step):
    """``core``: the strike and dip of a block's core from the likelihood within the smoothing's halo of it (scipy's
    Gaussian passes cropped to the core's lines after each axis, the tensor eigen-decomposed at the core only, as the
    orientation of a run by blocks takes them) are the whole cube's there, bit for bit: inside the cube, at its
    edges and at a corner; a 2D image has no core."""
    rng = np.random.default_rng(6)
    shape = (60, 52, 96)
    likelihood = rng.random(shape, dtype=np.float32) * (rng.random(shape) > 0.6)
    strike, dip = orientation_from_likelihood(likelihood, sigma=2.0, sample_step=sample_step)
    halo = 9  # ceil(4 sigma) + 1: the Gaussian's radius and the gradient's neighbour
    for i0, i1, j0, j1 in [(20, 36, 18, 30), (0, 16, 0, 52), (44, 60, 40, 52)]:
        a0, a1, b0, b1 = max(i0 - halo, 0), min(i1 + halo, shape[0]), max(j0 - halo, 0), min(j1 + halo, shape[1])
        core = (slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0))
        s, d = orientation_from_likelihood(likelihood[a0:a1, b0:b1], sigma=2.0, core=core, sample_step=sample_step)
        assert s.shape == d.shape == (i1 - i0, j1 - j0, shape[2]) and s.dtype == d.dtype == np.float32
        assert np.array_equal(s, strike[i0:i1, j0:j1]) and np.array_equal(d, dip[i0:i1, j0:j1])
    with pytest.raises(InputError, match="core"):
        orientation_from_likelihood(likelihood[0], core=(slice(0, 4), slice(0, 4)))
    for bad in (0, 1.5, True):
        with pytest.raises(InputError, match="sample_step"):
            orientation_from_likelihood(likelihood, sample_step=bad)


@pytest.mark.parametrize("shape", [(7, 9), (3, 5, 4), (40, 3, 17)])
def test_gradient_is_numpys_bit_for_bit(shape):
    """The orientation's gradient, written without numpy's temporaries, is ``np.gradient``'s: central differences
    halved inside, one-sided differences at both ends, float32, also on axes of 3 samples."""
    from seismo3d.seismic.faults.likelihood.orientation import _gradient

    likelihood = np.random.default_rng(2).random(shape, dtype=np.float32)
    for axis, expected in enumerate(np.gradient(likelihood)):
        got = _gradient(likelihood, axis)
        assert got.dtype == np.float32 and np.array_equal(got.view(np.uint32), expected.view(np.uint32))


def test_orientation_of_a_dipping_plane_on_every_second_sample():
    """A fault plane of strike 30 and dip 60 degrees (index space): its strike and dip within 1.5 degrees at its
    samples (measured 1.26 for the strike: the central differences' bias on a plane 1.5 samples wide), and the tensor
    eigen-decomposed on every second sample (held over the next) within 0.1 degree of every sample's."""
    strike_true, dip_true = 30.0, 60.0
    phi, theta = np.radians(strike_true), np.radians(dip_true)
    normal = np.array([np.sin(theta) * np.sin(phi), -np.sin(theta) * np.cos(phi), np.cos(theta)])  # the convention
    grid = np.stack(np.meshgrid(*(np.arange(n, dtype=np.float64) for n in (48, 48, 64)), indexing="ij"), axis=-1)
    distance = (grid - np.array([24.0, 24.0, 32.0])) @ normal
    likelihood = np.exp(-0.5 * (distance / 1.5) ** 2).astype(np.float32)
    on = (likelihood > 0.5) & (grid[..., 2] > 8) & (grid[..., 2] < 56)
    on[:8], on[-8:], on[:, :8], on[:, -8:] = False, False, False, False  # away from the cube's edges
    assert on.sum() > 1000
    (strike1, dip1), (strike2, dip2) = (orientation_from_likelihood(likelihood, sigma=2.0, sample_step=k)
                                        for k in (1, 2))
    assert np.abs(dip1[on] - dip_true).max() < 1.5 and np.abs(strike1[on] - strike_true).max() < 1.5
    assert np.abs(dip2[on] - dip1[on]).max() < 0.1 and np.abs(strike2[on] - strike1[on]).max() < 0.1


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


def test_orientation_reports_its_stages_when_its_step_asks_and_only_then(caplog):
    """In a run in memory (the step's executor asks: ``reporting_within``) the orientation logs a line as each of its
    four stages begins, under the step's name; called otherwise (a run by blocks, or directly) it logs nothing, and the
    strike and dip are the same bits either way."""
    likelihood = np.random.default_rng(3).random((20, 18, 24), dtype=np.float32)
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        quiet = orientation_from_likelihood(likelihood)
        assert caplog.messages == []
        with reporting_within("fault orientation"):
            reported = orientation_from_likelihood(likelihood)
    assert caplog.messages == ["fault orientation: gradient (1/4)", "fault orientation: structure tensor (2/4)",
                               "fault orientation: fault normals (3/4)", "fault orientation: strike and dip (4/4)"]
    assert all(np.array_equal(a, b) for a, b in zip(quiet, reported))


@pytest.mark.slow
@pytest.mark.parametrize("sample_step", [1, 2, 3])
def test_strike_and_dip_are_nan_exactly_below_the_floor_and_every_samples_above_it(sample_step):
    """``floor``: strike and dip are NaN at the samples whose likelihood is below it and, at every other sample, the
    bits of the orientation of every sample (``floor=0``, the tensor decomposed everywhere), in a cube, in a block's
    core (the floor tested on the core's samples) and in a 2D image."""
    rng = np.random.default_rng(7)
    shape = (40, 36, 61)  # an odd number of samples: the last kept sample holds itself only
    likelihood = (rng.random(shape, dtype=np.float32) ** 4).astype(np.float32)
    core = (slice(9, 25), slice(9, 27))
    for floor in (0.05, 0.5, 1.0):
        below = likelihood < np.float32(floor)
        assert 0 < below.mean() <= 1
        for image, crop, at in ((likelihood, None, (slice(None), slice(None))), (likelihood[:34, :36], core, core),
                                (likelihood[:, 0], None, (slice(None),))):
            every = orientation_from_likelihood(image, sample_step=sample_step, core=crop)
            got = orientation_from_likelihood(image, sample_step=sample_step, core=crop, floor=floor)
            under = image[at] < np.float32(floor)
            for a, b in zip(got, every):
                assert a.dtype == np.float32 and a.shape == b.shape
                assert np.isnan(a[under]).all() and np.isfinite(b).all()
                assert np.array_equal(a[~under].view(np.uint32), b[~under].view(np.uint32))
    for bad in (-0.1, 1.5):
        with pytest.raises(InputError, match="floor"):
            orientation_from_likelihood(likelihood, floor=bad)
