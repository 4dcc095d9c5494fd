"""Reflectors (seismo3d.seismic.reflectors): picks along traces with known positions, reflector points on a
synthetic cube, reflector slices."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import reflector_picks, reflector_points, structure_tensor_orientation
from seismo3d.seismic.reflectors import ReflectorSlice, nearest_pick, normalise_amplitudes


def test_reflector_picks_peaks_troughs_plateaus_and_zero_crossings():
    t = np.arange(200.0)
    trace = np.cos(2 * np.pi * (t - 10.3) / 20.0)  # peaks at 10.3 + 20 k, troughs at 20.3 + 20 k
    times, offsets = reflector_picks(trace[None, :], polarity="peak")
    assert offsets.tolist() == [0, len(times)]
    np.testing.assert_allclose(times, 10.3 + 20 * np.arange(len(times)), atol=0.02)
    troughs, _ = reflector_picks(trace[None, :], polarity="trough")
    np.testing.assert_allclose(troughs, 20.3 + 20 * np.arange(len(troughs)), atol=0.02)
    rising, _ = reflector_picks(trace[None, :], polarity="zero_rising")  # - above, + below: 5.3 + 20 k
    np.testing.assert_allclose(rising, 5.3 + 20 * np.arange(len(rising)), atol=0.1)
    clipped = np.clip(2 * trace, -1, 1)  # 8-bit style plateaus: the pick is the plateau's centre
    plateau, _ = reflector_picks(clipped[None, :], polarity="peak")
    np.testing.assert_allclose(plateau, 10.3 + 20 * np.arange(len(plateau)), atol=0.5)


def test_reflector_points_lie_on_peaks_with_downward_normals():
    cube = synthetic_cube((32, 32, 64), n_faults=2, seed=1).cube
    points, normals = reflector_points(cube)
    assert len(points) > 1000
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-5)
    assert np.all(normals[:, 2] >= 0)
    i, j, k = np.round(points).astype(int).T
    # the sample nearest each point is a local maximum of the trace smoothed by 1 sample, and a strong one
    smooth = ndi.gaussian_filter1d(cube, 1.0, axis=2)
    assert np.all((smooth[i, j, k] >= smooth[i, j, k - 1]) & (smooth[i, j, k] >= smooth[i, j, k + 1]))
    assert np.median(cube[i, j, k]) > np.median(np.abs(cube))
    # the normals agree with the structure tensor's at those samples
    ref = structure_tensor_orientation(cube).normals[i, j, k]
    assert np.median(np.abs(np.sum(ref * normals, axis=1))) > 0.99
    subset, _ = reflector_points(cube, max_points=500, seed=3)
    assert len(subset) == 500 and len(np.unique(subset, axis=0)) == 500


def test_noise_has_few_reflector_points_and_bad_input_is_refused():
    noise = np.random.default_rng(0).normal(size=(24, 24, 24)).astype(np.float32)
    points, _ = reflector_points(noise)
    assert len(points) < 100
    with pytest.raises(InputError, match="3D"):
        reflector_points(noise[0])
    with pytest.raises(InputError, match="quantile"):
        reflector_points(noise, quantile=1.0)
    with pytest.raises(InputError, match="constant"):
        normalise_amplitudes(np.zeros((10, 10, 10), np.float32))


def test_reflector_slice_snaps_to_its_picks():
    syn = synthetic_cube((60, 96), n_faults=0, seed=3, noise=0.05)
    sl = ReflectorSlice(syn.cube, "peak", (2.0, 2.0))
    times, offsets = reflector_picks(syn.cube, polarity="peak")
    np.testing.assert_array_equal(sl.t, times)
    t = times[offsets[10]]
    assert sl.snap(10, t + 1.0, 1.5) == t and np.isnan(sl.snap(10, t + 1.0, 0.5))
    assert np.isnan(nearest_pick(times, offsets, 10, np.nan, 3.0))
    points, normals = sl.band(5, 9, np.full(5, t), 4.0)
    assert points.shape[1] == 2 and np.all(np.abs(points[:, 1] - t) <= 4.0) and normals.shape == points.shape
    assert sl.window(10, t).shape == (17,)


def test_nearest_reflector_on_the_trace_or_the_nearest_trace_with_picks():
    """On its own trace: the pick nearest in time at any distance; on a trace without picks: the laterally nearest
    trace that has picks; none anywhere: None."""
    from seismo3d.seismic.reflectors import nearest_reflector

    times = np.array([10.0, 40.0, 25.0])
    offsets = np.array([0, 2, 2, 2, 3])  # (2, 2) traces: picks on (0, 0) and (1, 1)
    assert nearest_reflector(times, offsets, (2, 2), (0, 0, 30.0)) == (0.0, 0.0, 40.0)
    assert nearest_reflector(times, offsets, (2, 2), (1, 0, 12.0)) == (0.0, 0.0, 10.0)  # tie (0, 0) / (1, 1): first
    assert nearest_reflector(times, offsets, (2, 2), (0.9, 1.2, 0.0)) == (1.0, 1.0, 25.0)
    assert nearest_reflector(np.zeros(0), np.zeros(3, np.int64), (2,), (0, 5.0)) is None

