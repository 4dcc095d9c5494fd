"""The evidence a fault must show: reflectors displaced across it, and a fault likelihood that holds along it.

A ridge of the fault likelihood is only a discontinuity of the reflectors' lateral continuity; on real data (8-bit
clipping, dim and chaotic intervals, coherent noise, acquisition footprint) most such ridges cross reflectors that
continue unbroken. What makes a discontinuity a fault is a displacement (Hale 2014): the reflectors on the two sides
line up only after a vertical shift, the throw. :func:`fault_evidence` reads that evidence from the throw measurement
(:func:`~seismo3d.seismic.faults.throw.fault_throw`: the shift that best aligns the images of the two sides, and their
correlation with and without that shift) and the strength of the fault along its whole length (its mean thinned
votes against the upper vote threshold, its mean fault likelihood), and :func:`supported_faults` keeps a candidate
when

1. its thinned votes reach, on average along it, nearly the upper threshold of the hysteresis that traced it (0.9
   of it: a fault strong only at a few seed samples and linked through weak votes is a chain of noise), and
2. the reflectors are displaced across it (a shift of a sample or more that aligns the sides at least as well as no
   shift), or else, for the learned likelihood (a probability), the network's mean probability along it is at least
   one half; for the scan (not a probability), sides that do not match without a shift (normalised correlation
   below 0.5: a throw beyond the search, or unlike packages juxtaposed);

or, whatever its votes, when two independent measures agree: a clear displacement (a throw of at least
``clear_throw``, three samples, that aligns the sides at least as well as no shift) and a likely fault (the network's
mean probability along it at least ``min_probability``). The vote ratio is relative to the strongest faults of the
run (its thresholds are), so without this a displaced, likely fault beside stronger ones is lost: generated sections
and cubes lost true faults of throw 4.9-6.8 samples, probability 0.63-0.95 and vote ratio 0.71-0.90 to it. Either
measure alone is weak on real data: on the F3 inlines chance alignments of periodic reflectors give throws of 2-6
samples to wrong candidates, and at ``clear_throw`` 2 the clause keeps one of them (mean F1 0.500 -> 0.489); from
2.5 to 5 it keeps the same faults there as without it.

Whatever else it shows, a 2D fault whose offset is not a step at it (``flexure_step``: the reflectors' lags between
neighbouring traces ramp up to it instead of jumping across it, while its sides match closely at the throw's shift) is a
flexure that bends the reflectors unbroken, not a fault, and is dropped; so is one whose sides match with no shift
(``unbroken_correlation``: the reflectors continue across it) and one whose resolved throw is a fraction of the
reflectors' half period and mostly no step at it (``drag_half_periods``: drag, a migration swing). A clear throw of
unlike sides with no step must reach their half period (``clear_half_periods``); faults whose votes reach the upper
threshold nowhere are kept on a clear displacement alone (``unseeded_correlation_gain``).

The measures are absolute and dimensionless, the same on every input: a shift in samples (a displacement under one
sample is not resolved by the data), normalised correlations, a probability and a ratio to the run's own threshold.
Each fault also reports how continuous its sides are in themselves (``side_coherence``), to sort and filter on.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from .evidence_options import EvidenceOptions

__all__ = ["EvidenceOptions", "FaultEvidence", "fault_evidence", "sensitivity_factor", "supported_faults"]


def sensitivity_factor(sensitivity: float) -> float:
    """The factor ``2 ** (1 - 2 * sensitivity)`` by which a sensitivity in [0, 1] scales every threshold of the fault
    pipeline (the vote thresholds and the evidence asked for): 2 at 0, 1 at the default 0.5, 1/2 at 1."""
    return 2.0 ** (1.0 - 2.0 * float(sensitivity))


@dataclass(frozen=True)
class FaultEvidence:
    """The displacement evidence of one fault (see :func:`fault_evidence`).

    Attributes
    ----------
    fault_id : int
        The fault's id.
    median_throw : float
        Median throw over the fault's measured points, samples (positive = hanging wall down); NaN if unmeasured.
    throw_spread : float
        Interquartile range of the throw along the fault, samples: a consistent displacement varies smoothly, a
        chance alignment of periodic reflectors jumps. NaN if unmeasured, or measured once: a fault of one patch
        whose throw was not registered, as a 2D fault spanning fewer than two windows of its throw profile (one
        shift for the whole fault, whose spread of 0 would claim a consistency nothing measured).
    correlation : float
        Median normalised correlation of the two sides at the throw's shift, in [-1, 1]; NaN if unmeasured.
    correlation_gain : float
        ``correlation`` less the sides' median correlation with no shift; NaN if unmeasured.
    measured_fraction : float
        Fraction of the fault's points whose throw was measured, in [0, 1].
    side_coherence : float
        Median over the fault's points of the smaller of its two sides' continuity (the normalised correlation of
        the mean of a side's nearer traces with the mean of its farther ones,
        :attr:`~seismo3d.seismic.faults.throw.FaultThrow.side_coherence`), in [-1, 1]; NaN if unmeasured. Reported,
        not asked for: a mismatch of sides that are not continuous themselves (noise, the edge of a chaotic body:
        0.01 on a generated one) says little of a displacement, but real faults in noisy data have it too: on the
        Costa Rica crf section (``side_coherence`` in the ``fault_summary.csv`` of ``seismo3d faults``) faults that
        the published OSV result also holds measure below 0.5, and asking for 0.5 drops them.
    vote_ratio : float
        Mean of the fault's thinned votes along it over the upper vote threshold of the run that traced it
        (dimensionless; 1: as strong on average as the hysteresis' seeds); NaN when not measured.
    mean_likelihood : float
        Mean fault likelihood along the fault, in [0, 1] (for the learned likelihood: the network's probability);
        NaN when not measured.
    confidence : float
        The score that ranks the kept faults, the ones a person would draw first (the ``confidence`` column of
        ``fault_summary.csv`` and ``fault_points.csv``, which ``seismo3d evaluate`` ranks by): the mean likelihood
        along the fault. Chosen leave-one-survey-out by the average precision (AP) of ``seismo3d evaluate`` on the
        dev surveys' default outputs (2026-11-26), among the mean likelihood, the vote ratio, the number of points,
        the |median throw|, the throw's correlation and its gain, the sides' coherence, the evidence's margin over
        what is asked (the sensitivity at which a fault would be dropped) and products of the mean likelihood with
        each: on the Great South Basin the mean likelihood is best (AP 0.782; its F3 AP 0.304, 0.008 below F3's
        best, the mean likelihood times the sides' coherence: 0.312, whose GSB AP is 0.771); the evidence's margin
        scores 0.752 and 0.289. NaN until :func:`supported_faults` sets it.
    step : float
        2D: the median step at the fault (:attr:`~seismo3d.seismic.faults.result.FaultThrow.step`), samples,
        positive = hanging wall down: about the throw at a fault, a small part of it at a flexure. NaN when not
        measured (3D).
    half_period : float
        The reflectors' half period around the fault (:attr:`FaultThrow.half_period`), samples; NaN: not measured.
    """

    fault_id: int
    median_throw: float
    throw_spread: float
    correlation: float
    correlation_gain: float
    measured_fraction: float
    side_coherence: float = float("nan")
    vote_ratio: float = float("nan")
    mean_likelihood: float = float("nan")
    confidence: float = float("nan")
    step: float = float("nan")
    half_period: float = float("nan")

    def is_flexure(self, options: EvidenceOptions) -> bool:
        """True when the sides match at the throw's shift at least as well as ``flexure_correlation`` and the step at
        the fault is under ``flexure_step`` of the throw; False when ``flexure_step`` is None or either unmeasured."""
        if options.flexure_step is None or not (np.isfinite(self.step) and np.isfinite(self.median_throw)):
            return False
        return bool(self.correlation >= options.flexure_correlation
                    and abs(self.step) < options.flexure_step * abs(self.median_throw))

    def is_unbroken(self, options: EvidenceOptions) -> bool:
        """True when the reflectors continue across the fault: a flexure (:meth:`is_flexure`), sides that match with
        no shift (``unbroken_correlation``), or a throw of alike sides within their wavelet that is no step at the
        fault (``drag_half_periods``, ``drag_step``); unmeasured values (NaN) show nothing."""
        if self.is_flexure(options):
            return True
        if (u := options.unbroken_correlation) is not None and self.correlation - self.correlation_gain >= u:
            return True
        throw, alike = abs(self.median_throw), options.min_correlation  # unlike sides: a throw beyond the search
        return bool(options.drag_half_periods is not None and throw >= options.min_throw
                    and (alike is None or self.correlation >= alike) and abs(self.step) < options.drag_step * throw
                    and throw < options.drag_half_periods * self.half_period)

    def shows_displacement(self, options: EvidenceOptions, sensitivity: float = 0.5) -> bool:
        """True when the sides line up after a shift of at least ``options.min_throw`` samples at least
        ``options.min_correlation_gain`` better than with none (both scaled by the sensitivity in [0, 1])."""
        return self._displaced(options.min_throw, options.min_correlation_gain, sensitivity)

    def is_clear_and_likely(self, options: EvidenceOptions, sensitivity: float = 0.5) -> bool:
        """True when a clear displacement (``clear_throw``, ``min_correlation_gain``, ``clear_half_periods``) and a
        likely fault (``min_probability``) agree; False when either option is None or the mean likelihood unmeasured."""
        if options.clear_throw is None or options.min_probability is None or not np.isfinite(self.mean_likelihood):
            return False
        return (self._clear(options, options.min_correlation_gain, sensitivity)
                and self._reaches(options.min_probability, sensitivity))

    def _reaches(self, probability: float, sensitivity: float) -> bool:
        # the mean likelihood reaches a probability scaled by the sensitivity (at most 1); NaN reaches nothing
        return bool(self.mean_likelihood >= min(1.0, sensitivity_factor(sensitivity) * probability))

    def _sure(self, options: EvidenceOptions, sensitivity: float) -> bool:
        return options.sure_probability is not None and self._reaches(options.sure_probability, sensitivity)

    def _displaced(self, min_throw: float, min_gain: float, sensitivity: float) -> bool:
        factor = sensitivity_factor(sensitivity)
        return bool(np.isfinite(self.median_throw) and np.isfinite(self.correlation_gain)
                    and abs(self.median_throw) >= factor * min_throw
                    and self.correlation_gain >= factor * min_gain)

    def is_clearly_displaced(self, options: EvidenceOptions, sensitivity: float = 0.5) -> bool:
        """What a fault no vote seeded must show: no flexure, a clear throw gaining ``unseeded_correlation_gain``
        (:class:`EvidenceOptions`); always False when it or ``clear_throw`` is None."""
        return (gain := options.unseeded_correlation_gain) is not None and options.clear_throw is not None and \
            not self.is_unbroken(options) and self._clear(options, gain, sensitivity)

    def _clear(self, options: EvidenceOptions, min_gain: float, sensitivity: float) -> bool:
        step = options.flexure_step is not None and abs(self.step) >= options.flexure_step * abs(self.median_throw)
        if (options.clear_half_periods is not None and options.min_correlation is not None and not step  # unlike
                and not self.correlation >= options.min_correlation  # sides, no step (3D: NaN, not asked): a throw
                and abs(self.median_throw) < options.clear_half_periods * self.half_period):  # within their half
            return False  # period is their phase (a NaN half period asks nothing)
        return self._displaced(options.clear_throw, min_gain, sensitivity)

    def supports(self, options: EvidenceOptions, sensitivity: float = 0.5) -> bool:
        """True when the fault shows what ``options`` ask for at ``sensitivity`` in [0, 1]: no flexure, and a clear
        displacement on a likely fault; or votes that hold, and a displacement or a likely fault (the scan: sides
        that do not match without a shift).

        Raises
        ------
        InputError
            ``options`` ask for a vote ratio or a mean likelihood that this evidence did not measure (NaN).
        """
        if not (np.isfinite(self.median_throw) and np.isfinite(self.correlation_gain)):
            return False  # the two sides could not be compared: nothing shows a fault
        if self.is_unbroken(options):
            return False  # the reflectors bend across it or continue, unbroken: whatever the network says
        if self.is_clear_and_likely(options, sensitivity):
            return True  # displaced and likely: a fault beside stronger ones too, whatever its votes
        if options.min_vote_ratio > 0:
            if not np.isfinite(self.vote_ratio):
                raise InputError("this evidence has no vote ratio: measure it (fault_evidence(throw, vote_ratio=...)) "
                                 "or ask EvidenceOptions(min_vote_ratio=0)")
            if self.vote_ratio < options.min_vote_ratio:
                return False  # strong only at its seeds, linked through weak votes
        if (options.min_correlation is not None and not self._sure(options, sensitivity)
                and not self.correlation >= options.min_correlation):
            return False  # the sides look alike at no shift, and the network is not sure: nothing displaced
        if self.shows_displacement(options, sensitivity):
            return True
        if options.min_probability is None:
            return bool(self.correlation - self.correlation_gain < options.continuity)  # no match unshifted
        if not np.isfinite(self.mean_likelihood):
            raise InputError("this evidence has no mean likelihood: measure it (fault_evidence(throw, "
                             "mean_likelihood=...)) or ask EvidenceOptions(min_probability=None)")
        return self._reaches(options.min_probability, sensitivity)


def _median(values: np.ndarray) -> float:
    finite = values[np.isfinite(values)]
    return float(np.median(finite)) if finite.size else float("nan")


def fault_evidence(throw, *, vote_ratio: float = float("nan"),
                   mean_likelihood: float = float("nan")) -> FaultEvidence:
    """The displacement evidence of a fault from its throw measurement.

    Parameters
    ----------
    throw : FaultThrow
        The result of :func:`~seismo3d.seismic.faults.throw.fault_throw` for the fault: ``throw``,
        ``correlation`` and ``correlation_unshifted`` per point.
    vote_ratio : float, optional
        Mean thinned votes along the fault over the run's upper vote threshold (see :func:`supported_faults`).
    mean_likelihood : float, optional
        Mean fault likelihood along the fault.

    Returns
    -------
    FaultEvidence
        Median throw and its interquartile spread (samples), the median correlation of the sides at the throw's
        shift and its gain over no shift, the fraction of points measured, the sides' continuity, and the two
        strengths as given.

    Raises
    ------
    InputError
        ``throw`` lacks the per-point arrays of a ``FaultThrow``.

    References
    ----------
    .. [1] D. Hale, "Fault surfaces and fault throws from 3D seismic images", Geophysics 79(5), O53-O66, 2014,
       doi:10.1190/geo2013-0270.1.
    """
    try:
        t = np.asarray(throw.throw, np.float64)
        c = np.asarray(throw.correlation, np.float64)
        c0 = np.asarray(throw.correlation_unshifted, np.float64)
        coherence = getattr(throw, "side_coherence", None)
        coherence = np.full(t.shape, np.nan) if coherence is None else np.asarray(coherence, np.float64)
        median_throw = float(throw.median_throw)
    except AttributeError as exc:
        raise InputError(f"fault_evidence needs a FaultThrow (see fault_throw); got {type(throw).__name__}") from exc
    measured = np.isfinite(t)
    registered = np.asarray(getattr(throw, "registered", np.zeros(t.shape, bool)), bool)
    once = getattr(throw, "n_patches_measured", -1) == 1 and not registered[measured].any()
    if measured.any() and not once:
        q1, q3 = np.percentile(t[measured], [25, 75])
        spread = float(q3 - q1)
    else:  # unmeasured, or one shift for the whole fault (every 2D fault): no variation to measure
        spread = float("nan")
    return FaultEvidence(fault_id=int(throw.fault_id), median_throw=median_throw, throw_spread=spread,
                         correlation=_median(c), correlation_gain=_median(c - c0),
                         measured_fraction=float(measured.mean()) if t.size else 0.0,
                         side_coherence=_median(coherence), vote_ratio=float(vote_ratio),
                         mean_likelihood=float(mean_likelihood), step=float(getattr(throw, "step", float("nan"))),
                         half_period=float(getattr(throw, "half_period", float("nan"))))


def supported_faults(faults: list, throws: list, *, options: EvidenceOptions | None = None,
                     sensitivity: float = 0.5, vote_ratios=None, mean_likelihoods=None,
                     seeded=None) -> tuple[list, list, list]:
    """Keep the candidates that show what a fault must show; renumber them 1, 2, ... in order.

    A fault is kept when :meth:`FaultEvidence.supports` (see the module's description), a fault no vote seeded when
    :meth:`FaultEvidence.is_clearly_displaced`.

    Parameters
    ----------
    faults : list of Fault
        Fault skins (:func:`~seismo3d.seismic.faults.surfaces.skins.fault_skins`), ids 1, 2, ... in decreasing size.
    throws : list of FaultThrow
        Their throws, in the same order (:func:`~seismo3d.seismic.faults.throw.fault_throws`).
    options : EvidenceOptions, optional
        The evidence asked for (default: the learned likelihood's).
    sensitivity : float, optional
        In [0, 1]: higher keeps faults with smaller displacements (see :class:`EvidenceOptions`).
    vote_ratios, mean_likelihoods : sequence of float, optional
        Per fault, in the same order: its mean thinned votes over the run's upper vote threshold, and its mean fault
        likelihood (:func:`~seismo3d.seismic.faults.steps.faults_from_cells` measures both). Needed when
        ``options`` ask for them.
    seeded : sequence of bool, optional
        Per fault: False for one whose votes reach the upper hysteresis threshold nowhere; default all True.

    Returns
    -------
    faults, throws : list
        The kept faults and their throws, ids renumbered 1, 2, ... in the input's order (decreasing size).
    evidence : list of FaultEvidence
        The kept faults' evidence, with the new ids and their ``confidence``.

    Raises
    ------
    InputError
        ``faults``, ``throws`` and the strengths differ in length or ids; ``options`` ask for a strength not given.
    """
    opt = options or EvidenceOptions()
    n = len(faults)
    if len(throws) != n:
        raise InputError(f"{n} faults but {len(throws)} throws; pass the throws of these faults")
    nan = [float("nan")] * n
    vote_ratios = nan if vote_ratios is None else [float(v) for v in vote_ratios]
    mean_likelihoods = nan if mean_likelihoods is None else [float(v) for v in mean_likelihoods]
    seeded = [True] * n if seeded is None else [bool(v) for v in seeded]
    if len(vote_ratios) != n or len(mean_likelihoods) != n or len(seeded) != n:
        raise InputError(f"{n} faults but {len(vote_ratios)} vote ratios, {len(mean_likelihoods)} mean likelihoods "
                         f"and {len(seeded)} seeded flags; pass one of each per fault")
    kept_faults, kept_throws, kept_evidence = [], [], []
    for fault, throw, ratio, mean, by_seed in zip(faults, throws, vote_ratios, mean_likelihoods, seeded):
        if int(throw.fault_id) != int(fault.id):
            raise InputError(f"throw of fault {throw.fault_id} paired with fault {fault.id}; pass them in one order")
        evidence = fault_evidence(throw, vote_ratio=ratio, mean_likelihood=mean)
        if not (evidence.supports if by_seed else evidence.is_clearly_displaced)(opt, sensitivity):
            continue
        new_id = len(kept_faults) + 1
        kept_faults.append(dataclasses.replace(fault, id=new_id))
        kept_throws.append(dataclasses.replace(throw, fault_id=new_id))
        kept_evidence.append(dataclasses.replace(evidence, fault_id=new_id, confidence=evidence.mean_likelihood))
    return kept_faults, kept_throws, kept_evidence
