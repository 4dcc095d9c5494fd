"""Fault likelihood (seismo3d.seismic.faults.likelihood.scan): orientation against synthetic ground truth, conventions,
options and bad input."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError, Seismo3dWarning
from seismo3d.seismic import FaultScanOptions, fault_likelihood, fault_normals
from seismo3d.seismic.faults.result import fault_strike_dip


def test_normals_match_synthetic_convention():
    syn = synthetic_cube((64, 64, 64), seed=5)
    for plane in syn.faults:
        n = fault_normals(np.array(plane.strike_deg), np.array(plane.dip_deg))
        # ours points into the footwall, the generator's into the hanging wall
        assert_allclose(n, -plane.normal, atol=1e-6)
    n2 = fault_normals(np.array([90.0, 270.0]), np.array([60.0, 60.0]), ndim=2)
    assert_allclose(n2, [[np.sin(np.pi / 3), 0.5], [-np.sin(np.pi / 3), 0.5]], atol=1e-6)
    assert_allclose(np.linalg.norm(fault_normals(np.arange(0, 360, 7.0), np.full(52, 65.0)), axis=-1), 1, atol=1e-6)


def test_strike_dip_is_the_inverse_of_fault_normals():
    strikes, dips = np.array([0.0, 37.5, 145.0, 290.0]), np.array([90.0, 70.0, 55.0, 62.5])
    for n, s, d in zip(fault_normals(strikes, dips), strikes, dips):
        assert fault_strike_dip(n) == pytest.approx((s, d), abs=1e-4)
        assert fault_strike_dip(-n) == pytest.approx((s, d), abs=1e-4)  # either sign
    assert fault_strike_dip(np.array([np.sin(np.pi / 3), 0.5]))[0] == 90.0  # 2D


@pytest.mark.slow  # 2.3 s in the fast lane, whose budget is 60 s
def test_likelihood_orientation_on_single_plane():
    """One planar fault: the likelihood peaks on it with the fault's strike and dip."""
    syn = synthetic_cube((80, 80, 80), n_faults=1, seed=11)
    plane = syn.faults[0]
    fl = fault_likelihood(syn.cube)
    on = syn.fault_labels > 0
    assert np.median(fl.likelihood[on]) > 0.8
    assert np.median(fl.likelihood[~on]) < 0.3
    strong = on & (fl.likelihood > 0.8)
    ang = np.degrees(np.arccos(np.clip(np.abs(fl.normals[strong] @ plane.normal), 0, 1)))
    assert np.median(ang) < 10.0


@pytest.mark.slow
def test_constant_and_incoherent_data():
    fl = fault_likelihood(np.ones((20, 20, 30)))
    assert fl.likelihood.max() == 0.0
    noise = np.random.default_rng(0).standard_normal((30, 30, 40)).astype(np.float32)
    with pytest.warns(Seismo3dWarning, match="no lateral coherence"):
        fault_likelihood(noise)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fault_likelihood(synthetic_cube((32, 32, 48), seed=1).cube)


def test_options_object_and_keywords_agree():
    # the scan's options as a frozen dataclass or as keyword arguments: the same likelihood
    cube = synthetic_cube((32, 32, 48), n_faults=1, seed=4).cube
    a = fault_likelihood(cube, options=FaultScanOptions(dips=(90.0, 70.0), strike_smoothing=3.0))
    b = fault_likelihood(cube, dips=(90.0, 70.0), strike_smoothing=3.0)
    np.testing.assert_array_equal(a.likelihood, b.likelihood)
    assert set(np.unique(a.dip_deg)) <= {70.0, 90.0}
    assert FaultScanOptions().angles()[0].size == 24  # every 15 degrees for the default strike smoothing
    with pytest.raises(InputError, match="unknown keyword argument.*dip_windw"):
        fault_likelihood(cube, dip_windw=10)


def test_bad_input():
    good = np.zeros((10, 10, 10), np.float32)
    bad = good.copy()
    bad[1, 2, 3] = np.nan
    with pytest.raises(InputError, match="NaN"):
        fault_likelihood(bad)
    with pytest.raises(InputError, match="2D section"):
        fault_likelihood(np.zeros(10))
    with pytest.raises(InputError, match="power"):
        fault_likelihood(good, power=3)
    with pytest.raises(InputError, match="dips"):
        fault_likelihood(good, dips=[0.0, 45.0])
    with pytest.raises(InputError, match="power"):
        FaultScanOptions(power=6)
