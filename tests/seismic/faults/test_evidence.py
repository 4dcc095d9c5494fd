"""The evidence a fault must show (seismo3d.seismic.faults.evidence): displaced reflectors across it, votes that
hold along it, a likely fault."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import fault_throw, fault_throws, trace_faults
from seismo3d.seismic.faults import FaultTracingOptions
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
        assert evidence.shows_displacement(EvidenceOptions())
    # a vertical line of samples 30-100 at the trace farthest from every fault sample (20 traces from the edges)
    traces = np.arange(20, 172)
    far = traces[np.argmax(np.min(np.abs(traces[:, None] - np.argwhere(syn.fault_labels > 0)[None, :, 0]), axis=1))]
    line = np.column_stack([np.full(71, far), np.arange(30, 101)])
    evidence = fault_evidence(fault_throw(syn.cube, line))
    assert abs(evidence.median_throw) < 0.5 and abs(evidence.correlation_gain) < 0.02, evidence
    assert not evidence.shows_displacement(EvidenceOptions())
    assert not evidence.supports(EvidenceOptions.for_likelihood("scan"))  # and its sides match unshifted


@pytest.mark.slow
def test_throw_spread_is_measured_only_where_the_throw_is_measured_more_than_once():
    """A section's fault is one patch: its throw is one shift, so its spread is unknown (NaN, a blank cell in
    fault_summary.csv), not a consistency of 0. A 3D fault of several patches has its spread measured."""
    syn = synthetic_cube((192, 128), seed=0, noise=0.1, n_faults=2)
    tf = max(syn.faults, key=lambda f: abs(f.throw_samples))
    thr = fault_throw(syn.cube, np.argwhere(syn.fault_labels == tf.id))
    assert thr.n_patches_measured == 1 and np.isfinite(thr.median_throw)
    evidence = fault_evidence(thr)
    assert np.isfinite(evidence.median_throw) and np.isnan(evidence.throw_spread), evidence
    cube = synthetic_cube((96, 96, 96), seed=1, noise=0.1, n_faults=1)
    thr = fault_throw(cube.cube, np.argwhere(cube.fault_labels == 1))
    assert thr.n_patches_measured >= 2
    evidence = fault_evidence(thr)
    # one fault of constant throw: its patches agree within a sample
    assert np.isfinite(evidence.throw_spread) and 0.0 <= evidence.throw_spread < 1.0, evidence


def test_unmeasured_fault_has_no_evidence():
    syn = synthetic_cube((64, 64), n_faults=1, seed=0, noise=0.1)
    pts = np.argwhere(syn.fault_labels == 1)
    evidence = fault_evidence(fault_throw(syn.cube, pts[np.argsort(pts[:, 1])[:6]]))
    assert np.isnan(evidence.median_throw) and evidence.measured_fraction == 0.0
    assert not evidence.supports(EvidenceOptions(min_throw=0.0, min_correlation_gain=-1.0))


def _evidence(throw, gain, *, vote_ratio=1.0, mean_likelihood=0.0):
    return FaultEvidence(1, throw, 0.0, 0.8, gain, 1.0, vote_ratio=vote_ratio, mean_likelihood=mean_likelihood)


def test_sensitivity_scales_the_throw_asked_for():
    opt = EvidenceOptions(min_throw=1.0, min_correlation_gain=0.0, min_correlation=None)
    assert not _evidence(0.9, 0.1).supports(opt, 0.5) and _evidence(1.0, 0.1).supports(opt, 0.5)
    assert _evidence(0.5, 0.1).supports(opt, 1.0) and not _evidence(0.49, 0.1).supports(opt, 1.0)
    assert _evidence(-2.0, 0.1).supports(opt, 0.0) and not _evidence(-1.9, 0.1).supports(opt, 0.0)
    assert not _evidence(3.0, -0.01).supports(opt)  # the shift must not correlate worse than no shift


def test_sides_that_do_not_match_unshifted_are_a_discontinuity_for_the_scan():
    """Penobscot crossline 1155's large normal fault: its throw is beyond the search (median -0.2 sample measured)
    and its sides correlate 0.46 at best (each side continuous in itself: side coherence 0.89): for the scan (its
    likelihood no probability) a discontinuity, kept; the same numbers with sides matching (0.9) are unbroken
    reflectors. For the learned likelihood the mismatch alone is not enough: the network's mean probability along
    the fault decides (on a generated section without faults, a chaotic body's edge: no match unshifted, probability
    0.26), and with sides that do not look alike at any shift (0.41 < ``min_correlation``) only a probability the
    network is sure of (``sure_probability``) keeps it."""
    scan = EvidenceOptions.for_likelihood("scan")
    assert scan == EvidenceOptions(min_vote_ratio=0.0, min_probability=None, min_correlation=None,
                                   sure_probability=None, flexure_step=None, unseeded_correlation_gain=None,
                                   unbroken_correlation=None, drag_half_periods=None)
    assert FaultEvidence(1, 0.1, 0.0, 0.41, 0.0, 1.0, 0.89).supports(scan)
    assert not FaultEvidence(1, 0.1, 0.0, 0.9, 0.0, 1.0, 0.89).supports(scan)
    assert not FaultEvidence(1, 0.1, 0.0, 0.41, 0.0, 1.0, 0.89).supports(dataclasses.replace(scan, continuity=0.4))
    learned = EvidenceOptions.for_likelihood("learned")
    assert learned == EvidenceOptions()
    mismatch = FaultEvidence(1, 0.1, 0.0, 0.41, 0.0, 1.0, 0.89, vote_ratio=1.9)
    assert not dataclasses.replace(mismatch, mean_likelihood=0.26).supports(learned)
    assert not dataclasses.replace(mismatch, mean_likelihood=0.69).supports(learned)
    assert dataclasses.replace(mismatch, mean_likelihood=0.8).supports(learned)
    assert dataclasses.replace(mismatch, mean_likelihood=0.69).supports(dataclasses.replace(learned,
                                                                                           min_correlation=None))
    with pytest.raises(InputError, match="likelihood"):
        EvidenceOptions.for_likelihood("semblance")


def test_votes_must_hold_along_the_fault():
    """A fault whose mean thinned votes stay under 0.9 of the upper threshold is dropped, however displaced; the
    ratio is not scaled by the sensitivity (the thresholds are), and 0 asks nothing."""
    opt = EvidenceOptions()
    assert _evidence(3.0, 0.5, vote_ratio=0.9).supports(opt)
    assert not _evidence(3.0, 0.5, vote_ratio=0.89).supports(opt)
    assert not _evidence(3.0, 0.5, vote_ratio=0.89).supports(opt, 1.0)
    assert _evidence(3.0, 0.5, vote_ratio=0.1).supports(EvidenceOptions(min_vote_ratio=0.0))
    with pytest.raises(InputError, match="vote ratio"):
        _evidence(3.0, 0.5, vote_ratio=float("nan")).supports(opt)
    assert _evidence(3.0, 0.5, vote_ratio=float("nan")).supports(EvidenceOptions(min_vote_ratio=0.0))


def test_a_likely_fault_needs_no_measured_displacement():
    """With the learned likelihood a fault without a resolved throw is kept when the network's mean probability
    along it reaches 0.5 (scaled by the sensitivity like the throw); a displaced fault needs no probability."""
    opt = EvidenceOptions()
    assert not _evidence(0.2, 0.0, mean_likelihood=0.49).supports(opt)
    assert _evidence(0.2, 0.0, mean_likelihood=0.5).supports(opt)
    assert _evidence(0.2, 0.0, mean_likelihood=0.3).supports(opt, 1.0)  # 0.25 asked at sensitivity 1
    assert not _evidence(0.2, 0.0, mean_likelihood=0.99).supports(opt, 0.0)  # min(1, 1.0) asked at sensitivity 0
    assert _evidence(2.0, 0.1, mean_likelihood=0.0).supports(opt)
    with pytest.raises(InputError, match="mean likelihood"):
        _evidence(0.2, 0.0, mean_likelihood=float("nan")).supports(opt)
    for bad in (-0.1, 1.5):
        with pytest.raises(InputError, match="min_probability"):
            EvidenceOptions(min_probability=bad)
    with pytest.raises(InputError, match="min_vote_ratio"):
        EvidenceOptions(min_vote_ratio=-1.0)


def test_a_clear_throw_on_a_likely_fault_needs_no_vote_ratio():
    """A throw of at least 3 samples that aligns the sides, on a fault whose mean probability reaches 0.5, is kept
    whatever its vote ratio (the generated section of seed 3's faults of throw 6.7 / 6.8: vote ratio 0.71 / 0.90);
    either alone is not (chance alignments of periodic reflectors on real data); both scale with the sensitivity;
    the scan (no probability) and ``clear_throw=None`` never use it."""
    opt = EvidenceOptions()
    assert opt.clear_throw == 3.0
    assert _evidence(-3.0, 0.0, vote_ratio=0.1, mean_likelihood=0.5).supports(opt)
    assert not _evidence(2.9, 0.5, vote_ratio=0.1, mean_likelihood=0.9).supports(opt)  # throw under 3
    assert not _evidence(6.0, 0.5, vote_ratio=0.1, mean_likelihood=0.49).supports(opt)  # not likely
    assert not _evidence(6.0, -0.01, vote_ratio=0.1, mean_likelihood=0.9).supports(opt)  # the shift aligns worse
    assert _evidence(1.5, 0.0, vote_ratio=0.1, mean_likelihood=0.25).supports(opt, 1.0)  # half of both asked
    assert not _evidence(5.9, 0.0, vote_ratio=0.1, mean_likelihood=0.9).supports(opt, 0.0)  # twice the throw
    assert not _evidence(6.0, 0.5, vote_ratio=0.1, mean_likelihood=0.9).supports(EvidenceOptions(clear_throw=None))
    no_probability = EvidenceOptions(min_vote_ratio=0.5, min_probability=None)  # the scan's rule, votes asked
    assert not _evidence(6.0, 0.5, vote_ratio=0.1, mean_likelihood=0.9).supports(no_probability)
    for bad in (0.0, -1.0):
        with pytest.raises(InputError, match="clear_throw"):
            EvidenceOptions(clear_throw=bad)


def test_sides_must_look_alike_at_the_throw():
    """min_correlation (0.5 by default for the learned likelihood): a fault whose sides correlate under 0.5 at its
    throw's shift is dropped, unless clear and likely, or the network is sure of it (mean likelihood at least
    sure_probability, 0.75, scaled by the sensitivity like min_probability; the correlation is not scaled); the
    scan's defaults ask nothing."""
    opt = EvidenceOptions()
    assert (opt.min_correlation, opt.sure_probability) == (0.5, 0.75)
    weak = dataclasses.replace(_evidence(1.5, 0.2, mean_likelihood=0.7), correlation=0.45)
    assert not weak.supports(opt)
    assert weak.supports(EvidenceOptions(min_correlation=None))
    small = dataclasses.replace(weak, median_throw=1.2)  # under the clear throw at sensitivity 1 too (1.5)
    assert not small.supports(dataclasses.replace(opt, sure_probability=None), 1.0)  # 0.5 asked at every sensitivity
    assert weak.supports(opt, 1.0)  # sure from 0.375 at sensitivity 1
    assert dataclasses.replace(weak, correlation=0.5).supports(opt)
    assert dataclasses.replace(weak, mean_likelihood=0.75).supports(opt)  # the network is sure of it
    assert not dataclasses.replace(weak, mean_likelihood=0.9).supports(EvidenceOptions(sure_probability=None))
    assert not dataclasses.replace(weak, mean_likelihood=0.9).supports(opt, 0.0)  # sure at 1.0 only, at sensitivity 0
    clear = dataclasses.replace(_evidence(4.0, 0.2, mean_likelihood=0.6), correlation=0.2)
    assert clear.supports(opt)  # a clear throw on a likely fault
    scan = EvidenceOptions.for_likelihood("scan")
    assert scan.min_correlation is None and scan.sure_probability is None
    for bad in (-1.5, 1.5):
        with pytest.raises(InputError, match="min_correlation"):
            EvidenceOptions(min_correlation=bad)
        with pytest.raises(InputError, match="sure_probability"):
            EvidenceOptions(sure_probability=bad)


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
    ratios = [e.vote_ratio for e in result.evidence]
    means = [0.0] + [e.mean_likelihood for e in result.evidence[1:]]  # and the network does not call it a fault
    kept, kept_throws, evidence = supported_faults(faults, [flat, *throws[1:]], vote_ratios=ratios,
                                                   mean_likelihoods=means)
    assert [f.id for f in kept] == [t.fault_id for t in kept_throws] == list(range(1, len(faults)))
    assert all(np.array_equal(a.points, b.points) for a, b in zip(kept, faults[1:]))
    assert [e.vote_ratio for e in evidence] == ratios[1:] and [e.mean_likelihood for e in evidence] == means[1:]
    with pytest.raises(InputError, match="vote ratios"):
        supported_faults(faults, throws, vote_ratios=ratios[1:], mean_likelihoods=means)


def test_the_strengths_are_those_along_the_traced_faults():
    """Each fault's vote ratio is its mean thinned votes over the run's upper threshold, its mean likelihood the
    likelihood's mean over its points."""
    syn = synthetic_cube((192, 128), seed=1, noise=0.1, n_faults=2)
    every = FaultTracingOptions(evidence=EvidenceOptions(min_vote_ratio=0.0, min_probability=0.0))
    result = trace_faults(syn.cube, options=every, progress=False)
    assert result.faults
    for f, e in zip(result.faults, result.evidence):
        assert e.vote_ratio == pytest.approx(float(np.mean(f.likelihood)) / result.thresholds[1], rel=1e-6)
        assert e.mean_likelihood == pytest.approx(float(result.likelihood[tuple(f.points.T)].mean()), rel=1e-6)


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


def test_a_flexure_is_not_a_fault_whatever_the_network_says():
    """flexure_step (0.3 with flexure_correlation 0.9 by default for the learned likelihood): a 2D fault whose sides
    match closely at its throw (correlation >= 0.9) but under 0.3 of whose throw is a step at the fault bends the
    reflectors, unbroken; it is dropped even when clear, likely and voted for. An unmeasured step (3D), noisier sides
    and the scan's defaults ask nothing."""
    opt = EvidenceOptions()
    assert (opt.flexure_step, opt.flexure_correlation) == (0.3, 0.9)

    def bent(step, correlation=0.92, throw=-4.0):
        return dataclasses.replace(_evidence(throw, 0.8, vote_ratio=1.5, mean_likelihood=0.97), step=step,
                                   correlation=correlation)

    assert bent(-1.0).is_flexure(opt) and not bent(-1.0).supports(opt)  # the Teapot flexures: 0.26 of the throw
    assert not bent(-1.3).is_flexure(opt) and bent(-1.3).supports(opt)  # a step of 0.33 of the throw
    assert not bent(-1.0, correlation=0.89).is_flexure(opt) and bent(-1.0, correlation=0.89).supports(opt)
    assert bent(float("nan")).supports(opt)  # a 3D fault, its step not measured
    assert bent(-1.0).supports(EvidenceOptions(flexure_step=None))
    assert EvidenceOptions.for_likelihood("scan").flexure_step is None
    assert fault_evidence(SimpleNamespace(fault_id=1, throw=np.ones(3), correlation=np.ones(3),
                                          correlation_unshifted=np.zeros(3), median_throw=1.0, step=0.25)).step == 0.25
    for bad in ({"flexure_step": -0.1}, {"flexure_step": 1.5}, {"flexure_correlation": 1.5}):
        with pytest.raises(InputError, match=next(iter(bad))):
            EvidenceOptions(**bad)


def test_a_fault_no_vote_seeded_is_kept_on_a_clear_displacement_alone():
    """A fault whose votes reach the upper threshold nowhere (``seeded`` False, traced by the second hysteresis) is
    kept on a clear throw (at least clear_throw, 3) whose shift gains at least unseeded_correlation_gain (0.2) of
    the sides' correlation, whatever its votes and probability; not on a likely fault with a small throw, nor on a
    flexure; both scale with the sensitivity; the scan and ``unseeded_correlation_gain=None`` never keep one."""
    opt = EvidenceOptions()
    assert opt.unseeded_correlation_gain == 0.2
    assert EvidenceOptions.for_likelihood("scan").unseeded_correlation_gain is None
    weak = {"vote_ratio": 0.5, "mean_likelihood": 0.34}  # generated seed 31000018's fault of throw -9, gain 0.50
    assert _evidence(-9.0, 0.5, **weak).is_clearly_displaced(opt)
    assert not _evidence(2.9, 0.5, **weak).is_clearly_displaced(opt)  # throw under 3
    assert not _evidence(-9.0, 0.19, **weak).is_clearly_displaced(opt)  # the shift gains too little
    assert not _evidence(1.0, 0.5, vote_ratio=0.5, mean_likelihood=0.95).is_clearly_displaced(opt)  # only likely
    assert _evidence(1.5, 0.1, **weak).is_clearly_displaced(opt, 1.0)  # half of both asked
    assert not _evidence(5.9, 0.4, **weak).is_clearly_displaced(opt, 0.0)  # twice both
    flexure = dataclasses.replace(_evidence(-9.0, 0.5, **weak), correlation=0.95, step=-0.5)
    assert not flexure.is_clearly_displaced(opt)
    assert not _evidence(-9.0, 0.5, **weak).is_clearly_displaced(EvidenceOptions(unseeded_correlation_gain=None))
    with pytest.raises(InputError, match="unseeded_correlation_gain"):
        EvidenceOptions(unseeded_correlation_gain=3.0)


def test_supported_faults_asks_unseeded_faults_for_a_clear_displacement():
    """supported_faults keeps an unseeded fault only on a clear displacement, a seeded one on the usual evidence."""
    syn = synthetic_cube((192, 128), seed=1, noise=0.1, n_faults=2)
    result = trace_faults(syn.cube, progress=False)
    assert len(result.faults) >= 2
    faults, throws = result.faults[:2], result.throws[:2]
    small = dataclasses.replace(throws[1], throw=np.ones_like(throws[1].throw), median_throw=1.0)
    ratios, means = [1.5, 1.5], [0.9, 0.9]  # both strong and likely: kept when seeded
    assert len(supported_faults(faults, [throws[0], small], vote_ratios=ratios, mean_likelihoods=means)[0]) == 2
    kept, _, evidence = supported_faults(faults, [throws[0], small], vote_ratios=ratios, mean_likelihoods=means,
                                         seeded=[True, False])
    assert [f.id for f in kept] == [1] and np.array_equal(kept[0].points, faults[0].points)
    with pytest.raises(InputError, match="seeded"):
        supported_faults(faults, throws, vote_ratios=ratios, mean_likelihoods=means, seeded=[True])


@pytest.mark.slow
def test_a_fault_beside_stronger_ones_is_traced_from_the_lower_threshold():
    """Generated section 31000018 (never trained on): its fault of throw 8.5 samples crossing a stronger one has
    thinned votes above the lower hysteresis threshold but nowhere above the upper one (the network's mean
    probability along it 0.34); the second hysteresis traces it and its clear displacement (measured -9 samples,
    correlation gain 0.50) keeps it. Without the second pass no fault lies along its lower part."""
    from seismo3d.data.synthetic_sections import synthetic_fault_section
    from seismo3d.seismic import fault_labels

    sec = synthetic_fault_section((256, 256), seed=31_000_018)
    part = np.zeros(sec.faults.shape, bool)
    part[145:185, 165:215] = sec.faults[145:185, 165:215]  # the weak fault's lower part, away from the others
    assert part.sum() > 100

    def covered(options):
        labels = fault_labels(trace_faults(sec.section, options=options, progress=False).faults, part.shape) > 0
        near = np.zeros_like(labels)
        for dx in range(-2, 3):
            near |= np.roll(labels, dx, axis=0)
        return float(near[part].mean())

    assert covered(None) > 0.95  # measured 0.98
    assert covered(FaultTracingOptions(evidence=EvidenceOptions(unseeded_correlation_gain=None))) < 0.05  # 0


def test_a_clear_throw_of_unlike_sides_must_reach_their_half_period():
    """clear_half_periods (1 by default): a clear throw whose sides correlate under min_correlation (0.5) at its shift
    and which is no step at the fault (2D: a step under flexure_step, 0.3, of the throw; 3D: not measured) is evidence
    only when it reaches the half period of the reflectors around the fault (the correlation of unlike sides peaks
    within half a period of any shift). Penobscot crossline 1155's faults along migration swings at 4300-5400 ms
    (throw 4.84 samples, correlation 0.37, step -0.25, half period about 6) are then not clear; its large fault (13.9
    samples, correlation 0.41, half period about 5; 12.98 and 0.32 before its 2D throw search reached 32 samples) is; a Costa Rica crf fault (3.81 samples, correlation 0.36, step
    2.84, half period about 6) is a step; sides that look alike, an unmeasured half period and None ask nothing."""
    opt = EvidenceOptions()
    assert opt.clear_half_periods == 1.0

    def fault(throw, correlation, gain, half, ml=0.68, vr=1.7, step=float("nan")):
        return FaultEvidence(1, throw, float("nan"), correlation, gain, 1.0, vote_ratio=vr, mean_likelihood=ml,
                             half_period=half, step=step)

    swing = fault(4.84, 0.37, 0.57, 6.0)
    assert not swing.is_clear_and_likely(opt) and not swing.supports(opt)  # 3D: no step measured
    assert not fault(4.84, 0.37, 0.57, 6.0, step=-0.25).supports(opt)
    assert fault(3.81, 0.36, 0.58, 6.0, ml=0.73, vr=1.43, step=2.84).supports(opt)  # a step at the fault
    assert fault(12.98, 0.32, 0.12, 5.0, ml=0.69).supports(opt)
    assert fault(13.9, 0.41, 0.32, 5.0, ml=0.69).supports(opt)
    assert fault(4.84, 0.6, 0.57, 6.0).supports(opt)  # sides alike at the shift: not asked
    assert fault(4.84, 0.37, 0.57, float("nan")).supports(opt)  # not measured
    assert swing.supports(EvidenceOptions(clear_half_periods=None))
    assert fault(3.1, 0.37, 0.57, 6.0).supports(EvidenceOptions(clear_half_periods=0.5))
    unseeded = fault(4.84, 0.37, 0.57, 6.0, ml=0.3, vr=0.5)
    assert not unseeded.is_clearly_displaced(opt) and fault(6.1, 0.37, 0.57, 6.0).is_clearly_displaced(opt)
    with pytest.raises(InputError, match="clear_half_periods"):
        EvidenceOptions(clear_half_periods=-1.0)


def test_half_period_of_the_reflectors_around_a_fault():
    """The lag of the first trough of the traces' mean autocorrelation: 6 samples for a cosine of period 12, the
    same from a section, a cube and a window source of either; read about the points only."""
    from seismo3d.seismic.faults.windows import cube_windows
    from seismo3d.seismic.faults.reflector_period import half_period

    t = np.arange(200)
    rng = np.random.default_rng(0)
    section = np.cos(2 * np.pi * t / 12.0)[None, :] * (1 + 0.1 * rng.normal(size=(40, 1))) + 0.01 * rng.normal(
        size=(40, 200))
    points = np.array([[18, 50], [20, 120], [22, 150]])
    value = half_period(section, points)
    assert value == pytest.approx(6.0, abs=0.2)
    assert half_period(cube_windows(section), points) == pytest.approx(value, abs=1e-9)
    cube = np.repeat(section[:, None, :], 5, axis=1)
    points3 = np.array([[18, 2, 50], [20, 2, 120], [22, 2, 150]])
    assert half_period(cube, points3) == pytest.approx(value, rel=1e-6)
    assert np.isnan(half_period(section, np.array([[20, 10], [20, 11]])))  # two samples: no trough
    far = section.copy()
    far[:10] = np.cos(2 * np.pi * t / 30.0)  # other traces, beyond the points' margin, do not count
    assert half_period(far, points) == pytest.approx(value, abs=1e-9)


def _measured(throw, step, correlation, gain, half_period, vote_ratio, mean_likelihood):
    return FaultEvidence(1, throw, float("nan"), correlation, gain, 1.0, vote_ratio=vote_ratio,
                         mean_likelihood=mean_likelihood, step=step, half_period=half_period)


def test_sides_that_match_unshifted_are_unbroken():
    """unbroken_correlation (0.9): sides whose correlation with no shift reaches it continue across the candidate,
    which is dropped whatever its votes and probability. The values are those measured on F3 inline 200 (the dev
    script's SEG-Y): two short faults through continuous layering at crosslines 552-556 and 600-604 (unshifted
    correlations 0.95 and 0.92, the second with a probability the network is sure of, 0.77), and the large fault a
    person drew at crosslines 560-640 (0.88), kept."""
    opt = EvidenceOptions()
    assert opt.unbroken_correlation == 0.9
    short = _measured(0.5, 0.71, 0.95, 0.0, 2.7, 0.97, 0.50)
    sure = _measured(-0.2, -0.21, 0.92, 0.0, 3.5, 1.31, 0.77)
    large = _measured(-0.15, 0.36, 0.88, 0.0, 2.7, 1.96, 0.82)
    assert short.is_unbroken(opt) and sure.is_unbroken(opt) and not large.is_unbroken(opt)
    assert not short.supports(opt) and not sure.supports(opt) and large.supports(opt)
    loose = EvidenceOptions(unbroken_correlation=None)
    assert short.supports(loose) and sure.supports(loose)
    assert not EvidenceOptions.for_likelihood("scan").unbroken_correlation
    with pytest.raises(InputError, match="unbroken_correlation"):
        EvidenceOptions(unbroken_correlation=1.5)


def test_a_throw_within_the_wavelet_that_is_no_step_is_drag():
    """drag_half_periods (0.3) and drag_step (0.5): a resolved throw of alike sides under 0.3 half periods of the
    reflectors, less than half of which is a step at the fault, bends the reflectors within their wavelet and is
    dropped. Measured values: Penobscot crossline 1155's migration-swing fault at inlines 1380-1450 (throw -1.5
    samples, step -0.51, half period 7.3) and teapot_tpd's short fault at traces 161-163, which no vote seeded (throw
    -3, step -1.02, half period 12.6), dropped; kept: a Great South Basin fault an interpreter drew (throw 1.08, step
    0.83: a step), an F3 one a person drew on inline 400 (throw 1.5, step 0.5, half period 3.4: 0.44 of it),
    teapot_tp73's small fault at traces 324-330 (-1.21, step -0.02, half period 3.9: 0.31 of it), and crossline
    1155's large fault above 1060 ms whose throw is beyond the search (1.03 read, sides correlating 0.36: unlike);
    3D (no step) never."""
    opt = EvidenceOptions()
    assert (opt.drag_half_periods, opt.drag_step) == (0.3, 0.5)
    tp73 = _measured(-1.21, -0.02, 0.54, 0.10, 3.9, 0.92, 0.52)
    beyond = _measured(1.03, -0.16, 0.36, 0.06, 3.7, 2.26, 0.85)
    assert tp73.supports(opt) and beyond.supports(opt) and not tp73.supports(EvidenceOptions(drag_half_periods=0.35))
    assert beyond.is_unbroken(EvidenceOptions(drag_half_periods=0.3, min_correlation=None))
    swing = _measured(-1.5, -0.51, 0.64, 0.14, 7.3, 1.66, 0.65)
    unseeded = _measured(-3.0, -1.02, 0.92, 0.86, 12.6, 0.53, 0.44)
    gsb = _measured(1.08, 0.83, 0.93, 0.42, 3.9, 1.53, 0.89)
    f3 = _measured(1.5, 0.5, 0.76, 0.09, 3.4, 1.33, 0.55)
    assert swing.is_unbroken(opt) and not swing.supports(opt)
    assert unseeded.is_unbroken(opt) and not unseeded.is_clearly_displaced(opt)
    assert gsb.supports(opt) and f3.supports(opt)
    off = EvidenceOptions(drag_half_periods=None)
    assert swing.supports(off) and unseeded.is_clearly_displaced(off)
    assert _measured(-1.5, float("nan"), 0.64, 0.14, 7.3, 1.66, 0.65).supports(opt)  # 3D: no step measured
    assert _measured(0.9, 0.0, 0.7, 0.1, 7.3, 1.66, 0.65).supports(opt)  # under a sample: not a resolved throw
    with pytest.raises(InputError, match="drag_step"):
        EvidenceOptions(drag_step=-0.1)


def test_the_unbroken_veto_switched_off_judges_such_faults_on_what_else_they_show():
    """unbroken_veto (on by default): off, none of is_unbroken's three rules drops a fault (what seismo3d adapt
    records in a MODEL whose network learned faults without a throw); each such fault is then judged like any other.
    The values of the tests above: F3's short fault through continuous layering (sides matching unshifted), the
    Teapot flexure (step 0.25 of the throw), Penobscot's migration swing (drag) and teapot_tpd's unseeded drag."""
    on, off = EvidenceOptions(), EvidenceOptions(unbroken_veto=False)
    assert on.unbroken_veto is True
    short = _measured(0.5, 0.71, 0.95, 0.0, 2.7, 0.97, 0.50)
    flexure = dataclasses.replace(_evidence(-4.0, 0.8, vote_ratio=1.5, mean_likelihood=0.97), step=-1.0,
                                  correlation=0.92)
    swing = _measured(-1.5, -0.51, 0.64, 0.14, 7.3, 1.66, 0.65)
    unseeded = _measured(-3.0, -1.02, 0.92, 0.86, 12.6, 0.53, 0.44)
    for fault in (short, flexure, swing, unseeded):
        assert fault.is_unbroken(on) and not fault.is_unbroken(off)
    assert not any(f.supports(on) for f in (short, flexure, swing))
    assert all(f.supports(off) for f in (short, flexure, swing))  # votes, likelihood and throw all hold
    assert not unseeded.is_clearly_displaced(on) and unseeded.is_clearly_displaced(off)
    weak = _measured(0.5, 0.71, 0.95, 0.0, 2.7, 0.5, 0.30)  # votes under 0.9 of the threshold: dropped either way
    assert not weak.supports(off)
    with pytest.raises(InputError, match="unbroken_veto must be True or False"):
        EvidenceOptions(unbroken_veto="off")
