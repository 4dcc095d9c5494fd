"""Levels of the volume registration (seismo3d.seismic.volumes.pyramid): the envelope, what each level holds for
seismic amplitudes, clipped amplitudes and a smooth property, the decimation factors, and sampling."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from seismo3d.data import synthetic_cube
from seismo3d.seismic.volumes.pyramid import (Sampled, build_level, envelope, from_level, level_factors, level_kind,
                                              smoothing_measures, to_level)


@pytest.mark.parametrize("n", [64, 65])
def test_envelope_is_the_modulus_of_scipys_analytic_signal(n):
    from scipy.signal import hilbert

    v = np.random.default_rng(0).normal(size=(3, 4, n)).astype(np.float32)
    live = np.ones((3, 4), bool)
    live[0, 0] = False
    e = envelope(v, live)
    np.testing.assert_allclose(e[live], np.abs(hilbert(v, axis=2))[live], atol=1e-5)
    assert e[0, 0, 0] == pytest.approx(e[live].mean())  # dead traces hold the live mean


def _kinds(volumes, factors=(2, 4, 8), envelopes=True):
    """What the levels decimated by ``factors`` hold for these volumes (as register_volumes decides)."""
    live = np.ones(volumes[0].shape[:2], bool)
    out, finer = [], "amplitude"
    for f in factors:
        measures = [smoothing_measures(v, envelope(v, live) if envelopes else None, live, f) for v in volumes]
        finer = level_kind(measures, finer, keep_amplitude=0.35, min_contrast=0.25, min_amplitude=0.1)
        if finer is None:
            break
        out.append(finer)
    return out


def test_levels_hold_amplitudes_then_the_envelope_and_stop_where_nothing_survives():
    cube = synthetic_cube((16, 16, 128), n_faults=0, seed=2).cube
    kinds = _kinds([cube])
    assert kinds[0] == "amplitude" and kinds[-1] == "envelope"
    # a smooth property (a trend along the traces) keeps its amplitudes at every level
    trend = np.broadcast_to(np.linspace(-3.0, 3.0, 128), (16, 16, 128)) + 0.1 * cube
    assert _kinds([trend], envelopes=False) == ["amplitude"] * 3
    # clipped amplitudes: a flat envelope, and their smoothing soon keeps too little: the decimation stops
    clipped = np.sign(cube)
    assert "envelope" not in _kinds([clipped]) and len(_kinds([clipped])) < 3
    # both volumes hold the same kind: the clipped one holds the other back
    assert _kinds([cube, clipped]) == _kinds([clipped, cube]) == _kinds([clipped])


def test_level_factors_keep_enough_traces_and_samples():
    assert level_factors((160, 160, 130), min_lateral=16, min_vertical=9, max_factor=8) == (8, 8, 8)
    assert level_factors((23, 40, 75), min_lateral=16, min_vertical=9, max_factor=8) == (1, 2, 8)  # 20 traces, 9.4
    assert level_factors((23, 40, 70), min_lateral=16, min_vertical=9, max_factor=8) == (1, 2, 4)  # 8.75 < 9
    assert level_factors((23, 40, 70), min_lateral=16, min_vertical=8, max_factor=8) == (1, 2, 8)


def test_a_level_maps_transforms_to_full_resolution_and_samples_with_weights():
    cube = synthetic_cube((24, 24, 40), n_faults=0, seed=1).cube
    live = np.ones((24, 24), bool)
    live[:, :4] = False  # dead traces
    level = build_level(cube, live, (2, 2, 2), taper=2.0)
    assert isinstance(level, Sampled) and level.shape == (12, 12, 20)
    t = np.eye(4)
    t[:3, 3] = (4.0, -2.0, 6.0)
    np.testing.assert_allclose(from_level(to_level(t, level, level), level, level), t)
    pts = np.array([[6.0, 6.0, 10.0], [6.0, 0.5, 10.0], [6.0, 6.0, -3.0]]).T  # inside, dead traces, outside
    s = level.sample(pts)
    assert s.weights[0] == pytest.approx(1.0)
    assert s.weights[1] == 0.0 and s.weights[2] == 0.0
    assert s.values[0] == pytest.approx(level.data[6, 6, 10], abs=1e-5)


def test_high_frequency_grows_when_a_volume_is_sampled_coarser_without_a_low_pass():
    rng = np.random.default_rng(1)
    field = ndi.gaussian_filter(rng.normal(size=(48, 48, 48)), 2.0).astype(np.float32)
    live = np.ones((48, 48), bool)
    fine = Sampled(field, live, (1, 1, 1), 2.0).high_frequency
    coarse = Sampled(np.ascontiguousarray(field[::2, ::2, ::2]), live[::2, ::2], (2, 2, 2), 2.0).high_frequency
    noise = Sampled(rng.normal(size=(24, 24, 24)).astype(np.float32), live[:24, :24], (1, 1, 1), 2.0).high_frequency
    # measured 0.035 and 0.097 (every second sample of a Gaussian-smoothed field aliases); white noise spreads its
    # power evenly, 0.4 of it above 0.3 cycles per sample along each of the three axes: 1.2
    assert coarse > 2.0 * fine
    assert noise == pytest.approx(1.2, abs=0.1)


def test_spline_gradients_are_the_derivative_of_the_interpolated_values():
    # the closed-form gradient against a central difference (+-1e-3 samples) of scipy's own cubic B-spline
    # interpolation, out to half a sample beyond the edges (mode 'mirror')
    from seismo3d.seismic.volumes._spline import spline_gradients

    rng = np.random.default_rng(0)
    data = rng.normal(size=(12, 9, 20))
    # float32 coefficients, as the pyramid's; the reference reads the same values in float64 (map_coordinates would
    # return float32, whose rounding the +-1e-3 difference divides by 2e-3)
    coefficients = ndi.spline_filter(data, order=3, mode="mirror").astype(np.float32)
    exact = coefficients.astype(np.float64)
    pts = np.stack([rng.uniform(-0.5, n - 0.5, 2000) for n in data.shape])
    h = 1e-3
    difference = np.stack([(ndi.map_coordinates(exact, pts + h * e[:, None], order=3, prefilter=False,
                                                mode="mirror")
                            - ndi.map_coordinates(exact, pts - h * e[:, None], order=3, prefilter=False,
                                                  mode="mirror")) / (2 * h) for e in np.eye(3)])
    np.testing.assert_allclose(spline_gradients(coefficients, pts), difference, atol=1e-5)


def test_spline_and_linear_values_are_scipys_interpolations():
    # the refinement's one-pass kernels against scipy.ndimage.map_coordinates, the reference they replace, out to
    # half a sample beyond the edges (cubic: mode 'mirror'; linear: mode 'nearest', the coordinates clamped)
    from seismo3d.seismic.volumes._spline import linear_values, spline_values

    rng = np.random.default_rng(1)
    data = rng.normal(size=(3, 12, 9, 20)).astype(np.float32)
    coefficients = ndi.spline_filter(data[0], order=3, output=np.float32, mode="mirror")
    pts = np.stack([rng.uniform(-0.5, n - 0.5, 2000) for n in data.shape[1:]])
    pts[:, :8] = [[-0.5, 11.5, 0, 0, 5.0, 5.0, 0, 11], [0, 0, -0.5, 8.5, 3.0, 3.0, 0, 8], [0, 0, 0, 0, -0.5, 19.5, 0, 19]]
    cubic = ndi.map_coordinates(coefficients.astype(np.float64), pts, order=3, prefilter=False, mode="mirror")
    np.testing.assert_allclose(spline_values(coefficients, pts), cubic, rtol=0, atol=1e-12)
    linear = np.stack([ndi.map_coordinates(v.astype(np.float64), pts, order=1, mode="nearest") for v in data])
    np.testing.assert_allclose(linear_values(data, pts), linear, rtol=0, atol=1e-12)
