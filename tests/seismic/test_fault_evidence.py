"""The evidence a fault must show (seismo3d.seismic.faults.evidence): displaced reflectors across it."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import fault_throw, fault_throws, trace_faults
from seismo3d.seismic.faults.evidence import EvidenceOptions, FaultEvidence, fault_evidence, supported_faults


@pytest.mark.parametrize("seed", range(4))
def test_true_faults_show_a_displacement_and_unbroken_layers_do_not(seed):
    """True fault curves of generated sections (throws of 2-8 samples) have the evidence; a vertical line through
    the same section's unbroken layers, far from every fault, has none."""
    syn = synthetic_cube((192, 128), seed=seed, noise=0.1, n_faults=2)
    for tf in syn.faults:
        if tf.throw_samples < 2.0:
            continue
        evidence = fault_evidence(fault_throw(syn.cube, np.argwhere(syn.fault_labels == tf.id)))
        assert abs(evidence.median_throw) >= 1.5, evidence
        assert evidence.correlation_gain > 0.1, evidence  # measured 0.3-0.9
        assert evidence.side_coherence > 0.7, evidence
        assert evidence.supports(EvidenceOptions())
    # a vertical line of samples 30-100 at the trace farthest from every fault sample (20 traces from the edges)
    traces = np.arange(20, 172)
    far = traces[np.argmax(np.min(np.abs(traces[:, None] - np.argwhere(syn.fault_labels > 0)[None, :, 0]), axis=1))]
    line = np.column_stack([np.full(71, far), np.arange(30, 101)])
    evidence = fault_evidence(fault_throw(syn.cube, line))
    assert abs(evidence.median_throw) < 0.5 and abs(evidence.correlation_gain) < 0.02, evidence
    assert not evidence.supports(EvidenceOptions())


def test_unmeasured_fault_has_no_evidence():
    syn = synthetic_cube((64, 64), n_faults=1, seed=0, noise=0.1)
    pts = np.argwhere(syn.fault_labels == 1)
    evidence = fault_evidence(fault_throw(syn.cube, pts[np.argsort(pts[:, 1])[:6]]))
    assert np.isnan(evidence.median_throw) and evidence.measured_fraction == 0.0
    assert not evidence.supports(EvidenceOptions(min_throw=0.0, min_correlation_gain=-1.0))


def _evidence(throw, gain):
    return FaultEvidence(1, throw, 0.0, 0.9, gain, 1.0)


def test_sensitivity_scales_the_throw_asked_for():
    opt = EvidenceOptions(min_throw=1.0, min_correlation_gain=0.0)
    assert not _evidence(0.9, 0.1).supports(opt, 0.5) and _evidence(1.0, 0.1).supports(opt, 0.5)
    assert _evidence(0.5, 0.1).supports(opt, 1.0) and not _evidence(0.49, 0.1).supports(opt, 1.0)
    assert _evidence(-2.0, 0.1).supports(opt, 0.0) and not _evidence(-1.9, 0.1).supports(opt, 0.0)
    assert not _evidence(3.0, -0.01).supports(opt)  # the shift must not correlate worse than no shift


def test_sides_that_do_not_match_unshifted_are_a_discontinuity():
    """Penobscot crossline 1155's large normal fault: its throw is beyond the search (median -0.2 sample measured)
    and its sides correlate 0.46 at best (each side continuous in itself: side coherence 0.89): a discontinuity,
    kept; the same numbers with sides matching (0.9) are unbroken reflectors."""
    opt = EvidenceOptions()
    assert FaultEvidence(1, 0.1, 0.0, 0.41, 0.0, 1.0, 0.89).supports(opt)
    assert not FaultEvidence(1, 0.1, 0.0, 0.9, 0.0, 1.0, 0.89).supports(opt)
    assert not FaultEvidence(1, 0.1, 0.0, 0.41, 0.0, 1.0, 0.89).supports(EvidenceOptions(continuity=0.4))


def test_side_coherence_of_layers_against_noise():
    """A vertical line between layered reflectors and incoherent noise: the sides do not match and the noise side is
    not continuous in itself (side coherence near 0); a line through the layers alone has continuous sides."""
    syn = synthetic_cube((160, 128), n_faults=0, seed=2, noise=0.05)
    data = np.array(syn.cube, dtype=np.float64)
    rng = np.random.default_rng(0)
    data[80:] = rng.normal(0.0, data.std(), data[80:].shape)  # traces 80-159: noise
    boundary = np.column_stack([np.full(81, 80), np.arange(20, 101)])
    layered = np.column_stack([np.full(81, 40), np.arange(20, 101)])
    edge, inside = fault_evidence(fault_throw(data, boundary)), fault_evidence(fault_throw(data, layered))
    assert edge.side_coherence < 0.3 and edge.correlation - edge.correlation_gain < 0.5, edge
    assert inside.side_coherence > 0.8, inside


def test_supported_faults_keeps_order_and_renumbers():
    syn = synthetic_cube((192, 128), seed=1, noise=0.1, n_faults=2)
    result = trace_faults(syn.cube, options=None, progress=False)
    assert result.faults, "the generated faults are traced"
    assert [f.id for f in result.faults] == list(range(1, len(result.faults) + 1))
    assert [t.fault_id for t in result.throws] == [e.fault_id for e in result.evidence] == \
        [f.id for f in result.faults]
    faults, throws = result.faults, result.throws
    # a copy of fault 1 whose throws say "no displacement" (sides matching, 0.9, with and without a shift) is
    # dropped, the others renumbered after it
    matching = np.full_like(throws[0].correlation, 0.9)
    flat = dataclasses.replace(throws[0], throw=np.zeros_like(throws[0].throw), median_throw=0.0,
                               correlation=matching, correlation_unshifted=matching)
    kept, kept_throws, evidence = supported_faults(faults, [flat, *throws[1:]])
    assert [f.id for f in kept] == [t.fault_id for t in kept_throws] == list(range(1, len(faults)))
    assert all(np.array_equal(a.points, b.points) for a, b in zip(kept, faults[1:]))


def test_bad_input():
    syn = synthetic_cube((64, 64), n_faults=1, seed=0, noise=0.1)
    throws = fault_throws(syn.cube, [np.argwhere(syn.fault_labels == 1)])
    with pytest.raises(InputError, match="1 throws"):
        supported_faults([], throws)
    with pytest.raises(InputError, match="FaultThrow"):
        fault_evidence(np.zeros(3))
    with pytest.raises(InputError, match="min_throw"):
        EvidenceOptions(min_throw=-1.0)
    with pytest.raises(InputError, match="min_correlation_gain"):
        EvidenceOptions(min_correlation_gain=3.0)
