"""Evaluation against ground truth (seismo3d.seismic.evaluation): fault scores, horizon errors, registration errors,
on hand-made cases with known answers."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic import FaultScores, HorizonErrors, evaluate_faults, horizon_errors, registration_errors


def test_evaluate_faults():
    lab = np.zeros((40, 40), np.int16)
    lab[20, :] = 1
    pred = np.zeros((40, 40), bool)
    pred[22, :] = True
    assert evaluate_faults(pred, lab, tolerance=2) == FaultScores(1.0, 1.0)
    assert evaluate_faults(pred, lab, tolerance=1) == FaultScores(0.0, 0.0)
    pred[0, :10] = True
    scores = evaluate_faults(pred, lab, tolerance=2)
    assert scores.precision == pytest.approx(40 / 50) and scores.recall == 1.0
    assert evaluate_faults(np.zeros_like(pred), lab) == FaultScores(0.0, 0.0)
    assert evaluate_faults(pred, np.zeros_like(lab)).recall == 1.0
    # border leaves the first and last samples of the last axis out
    pred2 = np.zeros((40, 40), bool)
    pred2[0, :3] = True
    pred2[22, 3:37] = True
    assert evaluate_faults(pred2, lab, border=3).precision == 1.0
    with pytest.raises(InputError, match="same shape"):
        evaluate_faults(pred, lab[:5])


def test_horizon_errors():
    reference = np.array([10.0, 11.0, 12.0, np.nan, 14.0, -1.0])  # NaN and negative: no reference pick
    times = np.array([10.5, 14.0, np.nan, 3.0, 14.0, 9.0])
    e = horizon_errors(times, reference)
    assert isinstance(e, HorizonErrors)
    assert e.n == 4 and e.coverage == 0.75  # trace 2 is a miss
    assert e.median_abs == pytest.approx(0.5)  # errors 0.5, 3.0, 0.0
    assert e.within_2 == 0.5 and e.within_5 == 0.75
    with pytest.raises(InputError, match="same shape"):
        horizon_errors(np.zeros(3), np.zeros(4))


def test_registration_errors():
    truth = np.eye(4)
    est = np.diag([1.01, 1.0, 1.0, 1.0])
    est[2, 3] = 0.25
    err = registration_errors(est, truth, (11, 11, 11))
    np.testing.assert_allclose(err.scale_pct, [1.0, 0.0, 0.0], atol=1e-9)
    assert err.max_scale_pct == pytest.approx(1.0)
    assert err.rotation_deg == pytest.approx(0.0)
    assert err.centre_error == pytest.approx(np.hypot(0.05, 0.25))
    assert err.corner_error == pytest.approx(np.hypot(0.1, 0.25))  # corner inline 10: 0.1 off, all 0.25 deeper
    with pytest.raises(InputError, match="moving_shape"):
        registration_errors(est, truth, (11, 11))


def test_fault_line_coverage_of_one_fault_and_of_pieces():
    """A fault drawn along the line covers it; two pieces cover it together but each holds only its own part; a
    fault farther than the tolerance covers nothing; bad input is refused."""
    from seismo3d.seismic import fault_line_coverage

    labels = np.zeros((60, 101), np.int32)
    labels[22, :60] = 1  # 2 traces off the line (20, 0) -> (20, 50) -> (20, 100)
    labels[17, 60:] = 2  # 3 traces off it
    labels[55, :] = 3  # parallel and far
    line = [(20, 0), (20, 50), (20, 100)]
    c = fault_line_coverage(labels, line, tolerance=4)
    assert c.covered == pytest.approx(1.0) and c.one_fault == pytest.approx(60 / 101) and c.fault_id == 1
    assert c.n_faults == 2
    c = fault_line_coverage(labels, line, tolerance=2.5)
    assert c.covered == pytest.approx(60 / 101) and c.n_faults == 1
    assert fault_line_coverage(np.zeros((5, 5), int), [(1, 0), (1, 4)]).fault_id == 0
    with pytest.raises(InputError, match="samples increasing"):
        fault_line_coverage(labels, [(10, 50), (40, 10)])
    with pytest.raises(InputError, match="section"):
        fault_line_coverage(labels[None], [(10, 0), (40, 100)])


def test_f1_is_the_harmonic_mean_of_precision_and_recall():
    from seismo3d.seismic.evaluation import FaultScores

    assert FaultScores(0.5, 1.0).f1 == pytest.approx(2 / 3)
    assert FaultScores(0.0, 0.0).f1 == 0.0


def test_the_plain_peer_finds_a_vertical_break_of_the_layers():
    """1 - semblance is high where the layers are offset and the skeleton of it lies on the break."""
    from seismo3d.seismic.evaluation import plain_semblance, semblance_skeleton

    t = np.arange(200)
    left = np.sin(2 * np.pi * t / 16.0)
    section = np.vstack([np.tile(left, (50, 1)), np.tile(np.roll(left, 5), (50, 1))]).astype(np.float32)
    s = plain_semblance(section)
    assert s.shape == section.shape and s.dtype == np.float32
    assert np.all(s[:45] > 0.999) and np.all(s[55:] > 0.999)  # flat layers: semblance 1
    assert np.median(s[49:51, 10:190]) < 0.9  # the traces beside the break
    skeleton = semblance_skeleton(section, 0.05)
    assert skeleton.dtype == bool and skeleton[:, 10:190].any(axis=1)[48:52].any()
    assert not skeleton[:40].any() and not skeleton[60:].any()
