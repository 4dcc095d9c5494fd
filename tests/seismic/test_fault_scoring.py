"""Tolerant fault scores on a line (seismo3d.seismic.fault_scoring): exact precision and recall on drawn cases, the
Euclidean tolerance, the fault-by-fault matches, the precision-recall curve and its average precision, the placement of
fault points, and the definition of the project's tools (fault_scores.py) on random masks."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.errors import InputError
from seismo3d.seismic import evaluate_faults
from seismo3d.seismic.fault_scoring import (FaultScoringOptions, SectionFaults, score_fault_line,
                                            tolerant_scores)


def _labels(shape, faults):
    """A label image: fault id k + 1 on the samples of ``faults[k]`` = (trace, first sample, last sample)."""
    out = np.zeros(shape, dtype=np.int64)
    for n, (t, k0, k1) in enumerate(faults, start=1):
        out[t, k0:k1 + 1] = n
    return out


# people: two vertical faults of 10 samples at traces 5 and 30; traced: one 2 traces from the first, one 10 traces from
# both, one 1 trace from the second (each 10 samples)
SHAPE = (40, 20)
PEOPLE = _labels(SHAPE, [(5, 0, 9), (30, 10, 19)])
TRACED = _labels(SHAPE, [(7, 0, 9), (20, 0, 9), (31, 10, 19)])


@pytest.mark.parametrize("tolerance, precision, recall", [(3.0, 2 / 3, 1.0), (2.0, 2 / 3, 1.0), (1.0, 1 / 3, 0.5),
                                                          (0.0, 0.0, 0.0)])
def test_line_scores_on_a_drawn_case(tolerance, precision, recall):
    s = score_fault_line(SectionFaults.from_labels(TRACED), SectionFaults.from_labels(PEOPLE),
                         options=FaultScoringOptions(tolerance=tolerance))
    assert s.precision == pytest.approx(precision, abs=1e-12) and s.recall == pytest.approx(recall, abs=1e-12)
    f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
    assert s.f1 == pytest.approx(f1, abs=1e-12)
    assert (s.n_traced, s.n_people) == (30, 20)


def test_the_tolerance_is_euclidean_in_index_space():
    people, traced = np.zeros((10, 10), bool), np.zeros((10, 10), bool)
    people[5, 5], traced[7, 7] = True, True  # 2 traces and 2 samples apart: 2.83
    assert tolerant_scores(traced, people, 2.82) == (0.0, 0.0, 0.0)
    assert tolerant_scores(traced, people, 2.83) == (1.0, 1.0, 1.0)


def test_fault_by_fault_scores_and_matches():
    s = score_fault_line(SectionFaults.from_labels(TRACED), SectionFaults.from_labels(PEOPLE))
    assert [(f.fault_id, f.n_samples, f.recall, f.matches) for f in s.people] == [(1, 10, 1.0, (1,)),
                                                                                    (2, 10, 1.0, (3,))]
    assert [(f.fault_id, f.n_samples, f.precision, f.matches) for f in s.traced] == [(1, 10, 1.0, (1,)),
                                                                                     (2, 10, 0.0, ()),
                                                                                     (3, 10, 1.0, (2,))]
    assert [(p.people_id, p.traced_id, p.people_near, p.traced_near, p.matched) for p in s.pairs] == [
        (1, 1, 1.0, 1.0, True), (2, 3, 1.0, 1.0, True)]


def test_a_crossing_fault_matches_only_when_enough_of_one_lies_near_the_other():
    """A traced fault crossing a person's fault at a right angle: 7 of its 30 samples lie within 3 samples of it, and
    7 of the person's 10 within 3 of the traced fault; a match at the default fraction (0.5), none at 0.8."""
    people = _labels((40, 40), [(20, 15, 24)])
    traced = np.zeros((40, 40), np.int64)
    traced[5:35, 20] = 1  # a horizontal line across it
    s = score_fault_line(SectionFaults.from_labels(traced), SectionFaults.from_labels(people))
    (pair,) = s.pairs
    assert pair.traced_near == pytest.approx(7 / 30) and pair.people_near == pytest.approx(7 / 10)
    assert pair.matched  # 0.7 of the person's fault lies within 3 samples of it
    strict = score_fault_line(SectionFaults.from_labels(traced), SectionFaults.from_labels(people),
                              options=FaultScoringOptions(match_fraction=0.8))
    assert not strict.pairs[0].matched and strict.traced[0].matches == ()


@pytest.mark.parametrize("confidence, precision, recall, ap", [
    ({1: 0.9, 2: 0.8, 3: 0.7}, [1.0, 0.5, 2 / 3], [0.5, 0.5, 1.0], 0.5 * 1.0 + 0.0 + 0.5 * 2 / 3),
    ({1: 0.9, 2: 0.7, 3: 0.7}, [1.0, 2 / 3], [0.5, 1.0], 0.5 + 0.5 * 2 / 3),  # a tie enters as one step
    ({1: 0.9, 2: np.nan, 3: 0.1}, [1.0, 1.0, 2 / 3], [0.5, 1.0, 1.0], 1.0),  # no confidence: last
    (None, [1.0, 0.5, 2 / 3], [0.5, 0.5, 1.0], 0.5 + 0.5 * 2 / 3),  # none given: by id
])
def test_precision_recall_curve_over_the_confidence(confidence, precision, recall, ap):
    s = score_fault_line(SectionFaults.from_labels(TRACED), SectionFaults.from_labels(PEOPLE), confidence=confidence)
    assert_allclose(s.curve.precision, precision, atol=1e-12)
    assert_allclose(s.curve.recall, recall, atol=1e-12)
    assert s.curve.average_precision == pytest.approx(ap, abs=1e-12)
    assert s.curve.n_faults[-1] == 3
    assert (s.curve.precision[-1], s.curve.recall[-1]) == (s.precision, s.recall)


def test_points_are_placed_by_trace_label_and_nearest_sample():
    labels = np.arange(2531, 1563, -2, dtype=float)  # decreasing inline numbers
    samples = 1000.0 + 4.0 * np.arange(76)
    f = SectionFaults.from_positions([2531, 1565, 2001, 2001], [1000.0, 1300.0, 1002.0, 1006.0], [1, 1, 2, 2],
                                     trace_labels=labels, samples=samples)
    # 1002 ms is half way between samples 0 and 1: to the even one, as round() in dev_fault_scores.py
    assert f.points.tolist() == [[0, 0], [483, 75], [265, 0], [265, 2]]
    with pytest.raises(InputError, match="1 of 1 fault points lie on no trace .* 2000"):
        SectionFaults.from_positions([2000], [1000.0], [1], trace_labels=labels, samples=samples)
    with pytest.raises(InputError, match="beyond the section's samples .* 1302"):
        SectionFaults.from_positions([2001], [1302.0], [1], trace_labels=labels, samples=samples)


def test_masks_and_labels():
    mask = np.zeros((10, 8), np.uint8)
    mask[2, 1:4], mask[3, 4], mask[7, 0:3] = 255, 255, 255  # a diagonal step joins (2, 3) and (3, 4)
    f = SectionFaults.from_mask(mask)
    assert f.ids.tolist() == [1, 2] and f.mask(1).sum() == 4 and f.mask(2).sum() == 3
    assert (f.labels() == SectionFaults.from_labels(f.labels()).labels()).all()
    with pytest.raises(InputError, match="whole numbers >= 0"):
        SectionFaults.from_labels(-mask.astype(int))


def test_errors_name_the_problem():
    with pytest.raises(InputError, match="one shape"):
        tolerant_scores(np.zeros((3, 4), bool), np.zeros((4, 3), bool))
    with pytest.raises(InputError, match="place both on the same line"):
        score_fault_line(SectionFaults.from_labels(TRACED), SectionFaults.from_labels(PEOPLE[:, :10]))
    with pytest.raises(InputError, match="match_fraction"):
        FaultScoringOptions(match_fraction=0.0)
    with pytest.raises(InputError, match="tolerance"):
        FaultScoringOptions(tolerance=-1.0)


def _fault_scores_tool():
    """fault_scores.py of the project's tools (beside the data folder), or None."""
    import os

    data = os.environ.get("SEISMO3D_DATA_DIR")
    path = Path(data).parent / "tools" / "fault_scores.py" if data else None
    if path is None or not path.is_file():
        return None
    spec = importlib.util.spec_from_file_location("fault_scores_tool", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(5))
def test_the_definition_of_the_projects_tools_on_random_masks(seed):
    """fault_scores.tolerant_scores, line for line (imported from the tools folder when it is there, else its four
    lines here), and evaluate_faults' precision and recall."""
    from scipy.ndimage import distance_transform_edt

    rng = np.random.default_rng(seed)
    pred, ref = rng.random((60, 40)) < 0.03, rng.random((60, 40)) < 0.05
    tol = float(rng.uniform(0.5, 4.0))
    p = float((distance_transform_edt(~ref)[pred] <= tol).mean())
    r = float((distance_transform_edt(~pred)[ref] <= tol).mean())
    expected = (p, r, 2 * p * r / (p + r) if p + r else 0.0)
    tool = _fault_scores_tool()
    if tool is not None:
        assert tool.tolerant_scores(pred, ref, tol) == expected
    assert tolerant_scores(pred, ref, tol) == expected
    s = score_fault_line(SectionFaults.from_mask(pred), SectionFaults.from_mask(ref),
                         options=FaultScoringOptions(tolerance=tol))
    assert (s.precision, s.recall, s.f1) == expected
    e = evaluate_faults(pred, ref.astype(int), tolerance=tol)
    assert (e.precision, e.recall) == expected[:2]
