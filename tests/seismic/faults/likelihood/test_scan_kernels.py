"""The scan's kernels (seismo3d.seismic.faults.likelihood.scan_kernels): the smoothing along strike against a box
filter of scipy, and the results of both kernels the same bits on any number of threads (shares of run_threads)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from seismo3d.seismic.faults.likelihood.scan_kernels import exponential_coefficient, scan_dip, smooth_strike


@pytest.fixture(scope="module")
def terms():
    rng = np.random.default_rng(4)
    sn = rng.random((37, 23, 29), dtype=np.float32)
    return sn, sn + rng.random(sn.shape, dtype=np.float32)  # numerator <= denominator


def test_smooth_strike_at_strike_slope_zero_is_two_box_passes(terms):
    """At ``alpha`` 0 the staircase lines are the rows along the last axis: two passes of a box of half-width 2, zero
    outside (scipy's ``uniform_filter1d`` times its width), to float32 rounding."""
    x = terms[0]
    out = np.empty_like(x)
    smooth_strike(x, 0.0, 2, 0, 2, out)
    once = ndi.uniform_filter1d(x.astype(np.float64), 5, axis=2, mode="constant") * 5
    twice = ndi.uniform_filter1d(once, 5, axis=2, mode="constant") * 5
    np.testing.assert_allclose(out, twice, rtol=1e-5, atol=1e-5)


@pytest.mark.parametrize("slope", [0.0, 0.37, -1.6])
def test_scan_kernels_give_the_same_bits_on_any_number_of_threads(terms, slope):
    """Each output sample is written by one share: 1, 2, 3 and 7 threads give the same bits (a block's ``origin``
    and core ``b0`` included)."""
    sn, sd = terms
    runs = []
    for n_threads in (1, 2, 3, 7):
        smoothed = np.empty_like(sn)
        smooth_strike(sn, slope, 2, 5, n_threads, smoothed)
        key = np.zeros(sn.shape[:2] + (20,), np.int32)
        for k, beta in enumerate((slope, -0.5 * slope + 0.2)):
            scan_dip(smoothed, sd, beta, exponential_coefficient(3.0), np.int32(k), 2, 1e-30, n_threads, key, 4)
        runs.append((smoothed, key))
    assert np.count_nonzero(runs[0][1]) > 0.9 * runs[0][1].size
    for smoothed, key in runs[1:]:
        assert np.array_equal(smoothed, runs[0][0]) and np.array_equal(key, runs[0][1])
