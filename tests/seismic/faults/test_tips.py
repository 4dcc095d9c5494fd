"""The tips of 2D faults trimmed back to where the network's probability holds
(seismo3d.seismic.faults.tips.trimmed_tips): the voting carries a fault's votes past its tips."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic.faults import FaultTracingOptions, trace_faults
from seismo3d.seismic.faults.result import Fault, FaultThrow
from seismo3d.seismic.faults.tips import trimmed_tips


def _fault(trace: int, samples: np.ndarray, fid: int = 1) -> Fault:
    n = len(samples)
    pts = np.stack([np.full(n, trace), samples], axis=1).astype(np.int64)
    return Fault(fid, pts, np.linspace(0.1, 1.0, n, dtype=np.float32), np.full(n, 90, np.float32),
                 np.full(n, 80, np.float32), np.tile(np.float32([1, 0]), (n, 1)))


def _throw(fid: int, n: int) -> FaultThrow:
    values = np.arange(n, dtype=np.float32)
    return FaultThrow(fid, values, values > 5, values / n, values / (2 * n), 2.0, 0.9, 0.1, n,
                      side_coherence=values + 100)


def test_both_ends_are_cut_back_to_the_probability_and_the_throws_alike():
    lik = np.zeros((10, 60), np.float32)
    lik[4, 12:40] = 0.8          # the fault's likely part, a trace off the skin at trace 5 (the votes' ridge)
    lik[4, 25] = 0.1             # a gap inside it is kept
    samples = np.arange(50)[::-1]  # points in any order
    faults, throws = trimmed_tips([_fault(5, samples)], [_throw(1, 50)], lik, 0.3)
    f, t = faults[0], throws[0]
    assert f.points[:, 1].tolist() == list(range(12, 40))
    assert f.id == 1 and len(f.likelihood) == len(f.normals) == len(f.dip_deg) == 28
    take = 49 - np.arange(12, 40)  # the input positions of samples 12 .. 39
    for name in ("throw", "registered", "correlation", "correlation_unshifted", "side_coherence"):
        assert np.array_equal(getattr(t, name), getattr(_throw(1, 50), name)[take]), name
    assert t.median_throw == 2.0 and t.n_points_used == 50  # measured over the whole fault, left as measured


def test_a_fault_the_probability_reaches_nowhere_or_everywhere_is_left_whole():
    lik = np.zeros((10, 60), np.float32)
    lik[2, :] = 0.9
    whole, nowhere = _fault(2, np.arange(5, 45), 1), _fault(8, np.arange(5, 45), 2)
    faults, throws = trimmed_tips([whole, nowhere], [_throw(1, 40), _throw(2, 40)], lik, 0.3)
    assert faults[0] is whole and faults[1] is nowhere and len(throws) == 2


def test_no_level_or_no_likelihood_trims_nothing_and_bad_input_is_refused():
    f = _fault(2, np.arange(40))
    assert trimmed_tips([f], [None], None, 0.3)[0] == [f]
    assert trimmed_tips([f], [None], np.zeros((5, 40)), None)[0] == [f]
    with pytest.raises(InputError, match="2D likelihood"):
        trimmed_tips([f], [None], np.zeros((5, 1, 40)), 0.3)
    with pytest.raises(InputError, match="level"):
        trimmed_tips([f], [None], np.zeros((5, 40)), 1.5)
    with pytest.raises(InputError, match="throws"):
        trimmed_tips([f], [], np.zeros((5, 40)), 0.3)
    with pytest.raises(InputError, match="tip_level"):
        FaultTracingOptions(tip_level=-0.1)
    assert FaultTracingOptions().tip_level_for(2) == 0.1
    assert FaultTracingOptions().tip_level_for(3) is None
    assert FaultTracingOptions(likelihood="scan").tip_level_for(2) is None


def _gsb_sticks(data_dir, crossline):
    """The Great South Basin line and its interpreter's sticks as fault pixels (as tools/dev_fault_scores.py)."""
    segyio = pytest.importorskip("segyio")
    from skimage.draw import line as draw_line
    d = Path(data_dir) / "seismic" / "gsb_fault_sticks"
    with segyio.open(d / f"gsb_crl_{crossline}.sgy") as f:
        sec = segyio.tools.cube(f)[0].astype(np.float32)
        il, t = np.asarray(f.ilines, float), np.asarray(f.samples, float)
    rows = np.loadtxt(d / f"gsb_crl_{crossline}_faults_opendtect.dat")
    truth = np.zeros(sec.shape, bool)
    for a, b in zip(rows[0::2], rows[1::2]):
        c0, c1 = np.interp([a[6], b[6]], il, np.arange(len(il)))
        r0, r1 = np.interp([a[2], b[2]], t, np.arange(len(t)))
        rr, cc = draw_line(int(round(c0)), int(round(r0)), int(round(c1)), int(round(r1)))
        ok = (rr >= 0) & (rr < sec.shape[0]) & (cc >= 0) & (cc < sec.shape[1])
        truth[rr[ok], cc[ok]] = True
    return sec, truth


@pytest.mark.slow
def test_great_south_basin_faults_stop_where_the_interpreter_stopped_them(data_dir):
    """Measured 2026-11-26: the points within 3 samples of the sticks (precision), 0.824 / 0.770 of the points
    without the trimming, 0.843 / 0.781 with the default's (crosslines 2600 / 2800; 0.855 / 0.801 at 0.3), the same
    16 / 12 faults."""
    from scipy.ndimage import distance_transform_edt
    for crossline in (2600, 2800):
        sec, truth = _gsb_sticks(data_dir, crossline)
        near = distance_transform_edt(~truth) <= 3
        precision, counts = {}, {}
        for level in (None, "default"):
            opt = FaultTracingOptions() if level == "default" else FaultTracingOptions(tip_level=level)
            r = trace_faults(sec, options=opt, progress=False)
            pts = np.concatenate([f.points for f in r.faults])
            precision[level] = np.unique(pts, axis=0).T
            precision[level] = float(near[tuple(precision[level])].mean())
            counts[level] = len(r.faults)
        assert counts[None] == counts["default"]
        assert precision["default"] >= precision[None] + 0.01, (crossline, precision)
