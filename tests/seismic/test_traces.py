"""Trace primitives (seismo3d.seismic.traces): parabolic peaks, windows, NCC and the lag search, against known
answers."""

import numpy as np
import pytest

from seismo3d.seismic.traces import ncc, ncc_lag_search, parabolic_offset, subsample_peak, waveform


def test_parabolic_offset_finds_the_vertex_of_a_parabola():
    for vertex in (-0.4, -0.1, 0.0, 0.25, 0.49):
        y = -((np.arange(-1, 2) - vertex) ** 2)  # samples of a parabola peaking at `vertex`
        assert parabolic_offset(*y) == pytest.approx(vertex)
    assert parabolic_offset(0.0, 1.0, 0.0) == 0.0
    assert parabolic_offset(1.0, 0.0, 1.0) == 0.0  # a minimum: no offset
    assert parabolic_offset(0.0, 2.0, 3.0) == 0.5  # the vertex 1.5 samples on: clipped to half a sample
    y32 = np.array([[0.2, 1.0, 0.6]], np.float32).T
    assert parabolic_offset(*y32).dtype == np.float32  # the input's precision


def test_subsample_peak_and_the_lag_search_recover_a_known_shift():
    scores = np.array([0.1, 0.5, 0.9, 0.8, np.nan])
    assert subsample_peak(scores, 2) == pytest.approx(parabolic_offset(0.5, 0.9, 0.8))
    assert subsample_peak(scores, 3) == 0.0 and subsample_peak(scores, 0) == 0.0  # next to NaN, at the end
    t = np.arange(200.0)
    trace = np.cos(2 * np.pi * t / 23.0) * np.exp(-(((t - 100) / 30) ** 2))
    for shift in (-3.3, 0.0, 2.6):
        half, max_lag = 12, 6
        reference = waveform(trace, 100.0, half)
        signal = waveform(trace, 100.0 - shift, half + max_lag)  # the event lies `shift` samples later
        assert ncc_lag_search(reference, signal, max_lag) == pytest.approx(shift, abs=0.1)
    assert ncc_lag_search(np.full(5, np.nan), np.full(9, np.nan), 2) == 0.0


def test_ncc_and_waveform():
    a = np.array([1.0, 2.0, 3.0, np.nan, 5.0, 6.0])
    assert ncc(a, 2 * a + 1) == pytest.approx(1.0)
    assert ncc(a, -a) == pytest.approx(-1.0)
    assert ncc(a[:4], a[:4]) != ncc(a[:4], a[:4])  # fewer than 5 finite samples: NaN
    assert ncc(np.ones(6), a) == 0.0  # constant window
    w = waveform(np.arange(10.0), 2.5, 3)
    np.testing.assert_allclose(w[1:], np.arange(0.5, 6.0))  # 2.5 - 2 ... 2.5 + 3
    assert np.isnan(w[0])  # before the trace
