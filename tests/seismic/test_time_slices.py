"""Blank time slices (seismo3d.seismic.time_slices): found from each slice's extremes over the live traces, filled
along the traces, each slice's own offset and gain then removed, the same in memory and by dask blocks, and done by
trace_faults with a warning."""

import warnings

import dask.array as da
import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import Seismo3dWarning
from seismo3d.seismic import evaluate_faults, fault_labels, trace_faults
from seismo3d.seismic.time_slices import balanced_slices, blank_slices, filled_slices, slice_extremes


def _blanked(cube, rows):
    """The cube with the slices ``rows`` set to its largest and smallest value in turn (8-bit exports' white and
    black images)."""
    out = np.array(cube, dtype=np.float32)
    for k, r in enumerate(rows):
        out[..., r] = out.max() if k % 2 else out.min()
    return out


def test_blank_slices_are_the_constant_ones_between_live_slices():
    rng = np.random.default_rng(0)
    cube = rng.normal(size=(6, 5, 40)).astype(np.float32)
    cube[..., :4] = 0.0                      # a muted top: the dead-sample rules', not a blank slice
    cube[..., 38:] = 0.0                     # padding at the bottom
    cube = _blanked(cube, [10, 11, 25])
    cube[2, 3] = 7.0                         # a dead trace (one value along it) does not keep a slice from being blank
    blank = blank_slices(*slice_extremes(cube))
    assert np.flatnonzero(blank).tolist() == [10, 11, 25]
    assert not blank_slices(*slice_extremes(rng.normal(size=(4, 4, 30)))).any()
    assert not blank_slices(np.zeros(8), np.zeros(8)).any()  # nothing varies: nothing to fill from


def test_filled_slices_interpolate_linearly_along_the_traces():
    rng = np.random.default_rng(1)
    cube = rng.normal(size=(3, 4, 20)).astype(np.float32)
    blank = np.zeros(20, bool)
    blank[[5, 6, 7, 12]] = True
    out = filled_slices(cube, blank)
    for k, w in zip((5, 6, 7), (0.25, 0.5, 0.75)):  # between slices 4 and 8
        np.testing.assert_allclose(out[..., k], (1 - w) * cube[..., 4] + w * cube[..., 8], rtol=1e-6)
    np.testing.assert_allclose(out[..., 12], 0.5 * (cube[..., 11] + cube[..., 13]), rtol=1e-6)
    assert np.array_equal(out[..., ~blank], cube[..., ~blank])
    assert filled_slices(cube, np.zeros(20, bool)) is cube


def _slice_export(cube, blank_rows):
    """A time-slice export of ``cube``: each slice rendered to 8 bits (0-255) by its own smallest and largest value,
    the slices ``blank_rows`` blank (white and black in turn), centred (value - 127.5)."""
    lo = cube.min(axis=tuple(range(cube.ndim - 1)), keepdims=True)
    hi = cube.max(axis=tuple(range(cube.ndim - 1)), keepdims=True)
    out = np.round(255.0 * (cube - lo) / (hi - lo))
    for k, r in enumerate(blank_rows):
        out[..., r] = 255.0 if k % 2 == 0 else 0.0
    return (out - 127.5).astype(np.float32)


def test_balanced_slices_remove_each_slices_offset_and_gain():
    rng = np.random.default_rng(3)
    cube = rng.normal(size=(30, 20, 16)).astype(np.float32)
    gain, offset = rng.uniform(0.2, 5.0, 16).astype(np.float32), rng.uniform(-50, 50, 16).astype(np.float32)
    scaled = cube * gain + offset
    scaled[4, 5] = 9.0                                       # a dead trace: left as it is
    blank = np.zeros(16, bool)
    assert balanced_slices(scaled, blank) is scaled          # no blank slice: no time-slice export, nothing done
    blank[7] = True
    out = balanced_slices(scaled, blank)
    assert np.all(out[4, 5] == 9.0)
    live = np.ones((30, 20), bool)
    live[4, 5] = False
    q25, q75 = np.quantile(out[live], [0.25, 0.75], axis=0)
    np.testing.assert_allclose(out[live].mean(axis=0), 0.0, atol=1e-4)
    np.testing.assert_allclose(q75 - q25, np.median(q75 - q25), rtol=1e-4)  # one spread for every slice
    # each slice a linear map of the original: correlation 1 with it
    assert min(np.corrcoef(out[live][:, k], cube[live][:, k])[0, 1] for k in range(16)) > 0.9999


def test_dask_blocks_find_and_fill_as_in_memory():
    rng = np.random.default_rng(2)
    cube = _blanked(rng.normal(size=(24, 20, 48)), [9, 10, 30])
    lazy = da.from_array(cube, chunks=(8, 7, -1))
    extremes = slice_extremes(lazy)
    assert all(np.array_equal(a, b) for a, b in zip(extremes, slice_extremes(cube)))
    blank = blank_slices(*extremes)
    assert np.flatnonzero(blank).tolist() == [9, 10, 30]
    assert np.array_equal(filled_slices(lazy, blank).compute(), filled_slices(cube, blank))
    np.testing.assert_allclose(balanced_slices(filled_slices(lazy, blank), blank).compute(),
                               balanced_slices(filled_slices(cube, blank), blank), rtol=1e-6, atol=1e-6)


@pytest.mark.slow  # 6 s under load
def test_trace_faults_undoes_a_time_slice_export_with_a_warning_and_keeps_the_faults():
    """A generated section exported as time slices (each rendered to 8 bits by its own range, six of them blank:
    white and black lines across every trace): a warning naming the blank ones, and the faults of the clean section
    (measured: 2 faults, precision 1.0, recall 1.0, as on the clean section; generated 96^3 cubes 0 and 1 exported so:
    0.989 / 0.982 and 0.999 / 0.987)."""
    syn = synthetic_cube((160, 96), n_faults=2, seed=3)
    rows = [20, 21, 22, 45, 60, 75]
    with pytest.warns(Seismo3dWarning, match=r"6 time slices hold one value on every trace \(samples 20, 21, 22"):
        res = trace_faults(_slice_export(syn.cube, rows), progress=False)
    scores = evaluate_faults(fault_labels(res.faults, syn.cube.shape) > 0, syn.fault_labels > 0, tolerance=2)
    assert len(res.faults) == 2 and scores.precision >= 0.95 and scores.recall >= 0.95, scores
    with warnings.catch_warnings():
        warnings.simplefilter("error", Seismo3dWarning)  # no blank slice in the clean section: no warning
        trace_faults(syn.cube, progress=False)
