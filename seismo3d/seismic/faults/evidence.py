"""The evidence a fault must show: reflectors displaced across it, and a fault likelihood that holds along it.

A ridge of the fault likelihood is only a discontinuity of the reflectors' lateral continuity; on real data (8-bit
clipping, dim and chaotic intervals, coherent noise, acquisition footprint) most such ridges cross reflectors that
continue unbroken. What makes a discontinuity a fault is a displacement (Hale 2014): the reflectors on the two sides
line up only after a vertical shift, the throw. :func:`fault_evidence` reads that evidence from the throw measurement
(:func:`~seismo3d.seismic.faults.throw.fault_throw`: the shift that best aligns the images of the two sides, and their
correlation with and without that shift) and the strength of the fault along its whole length (its mean thinned votes
against the upper vote threshold, its mean fault likelihood), and :func:`supported_faults` keeps a candidate when

1. its thinned votes reach, on average along it, nearly the upper threshold of the hysteresis that traced it (0.9
   of it: a fault strong only at a few seed samples and linked through weak votes is a chain of noise), and
2. the reflectors are displaced across it (a shift of a sample or more that aligns the sides at least as well as no
   shift), or else, for the learned likelihood (a probability), the network's mean probability along it is at least
   one half; for the scan (not a probability), sides that do not match without a shift (normalised correlation
   below 0.5: a throw beyond the search, or unlike packages juxtaposed);

or, whatever its votes, when two independent measures agree: a clear displacement (a throw of at least ``clear_throw``,
three samples, that aligns the sides at least as well as no shift) and a likely fault (the network's mean probability
along it at least ``min_probability``): the vote ratio is relative to the run's strongest faults, and generated faults
of throw 4.9-6.8 samples and probability 0.63-0.95 beside stronger ones reached 0.71-0.90 of it. Either alone is weak on
real data (F3's periodic reflectors align by chance at 2-6 samples: ``clear_throw`` 2 keeps one such, F1 0.500 -> 0.489;
2.5 to 5 keep the same faults as without the clause).

Whatever else it shows, a 2D fault whose offset is not a step at it (``flexure_step``: the reflectors' lags between
neighbouring traces ramp up to it instead of jumping across it, while its sides match closely at the throw's shift) is a
flexure that bends the reflectors unbroken, and is dropped, as are sides matching with no shift
(``unbroken_correlation``) and a throw within the reflectors' wavelet mostly no step (``drag_half_periods``). A clear
throw of unlike sides with no step must reach their half period (``clear_half_periods``); faults whose votes reach the
upper threshold nowhere are kept on a clear displacement alone (``unseeded_correlation_gain``).

The measures are absolute and dimensionless, the same on every input: a shift in samples (a displacement under one
sample is not resolved by the data), normalised correlations, a probability and a ratio to the run's own threshold. Each
fault also reports how continuous its sides are in themselves (``side_coherence``), to sort and filter on.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..._validation import check_positive
from ...errors import InputError

__all__ = ["EvidenceOptions", "FaultEvidence", "fault_evidence", "sensitivity_factor", "supported_faults"]


def sensitivity_factor(sensitivity: float) -> float:
    """The factor ``2 ** (1 - 2 * sensitivity)`` by which a sensitivity in [0, 1] scales every threshold of the fault
    pipeline (the vote thresholds and the evidence asked for): 2 at 0, 1 at the default 0.5, 1/2 at 1."""
    return 2.0 ** (1.0 - 2.0 * float(sensitivity))


@dataclass(frozen=True)
class EvidenceOptions:
    """What a fault must show to be kept (see :func:`supported_faults`).

    One sample is the smallest displacement the data resolves, a correlation of 0.5 is the level where the sides hold as
    much coherent as incoherent energy, a probability of 0.5 is the network's own decision level. The vote ratio (0.9 of
    the upper threshold the hysteresis traced the fault from) and the probability are chosen by cross-validation on the
    five F3 inlines with faults drawn by a person (``benchmarks/faults.py --only f3``: ratios 0, 0.75, 0.9, 1, 1.1,
    probabilities 0.5, 0.6, 0.7 and four sets of network grids, chosen on three inlines, scored on the other two, every
    split); the generated cubes' true faults measure 0.96-1.44.

    Use :meth:`for_likelihood` for the defaults of each fault likelihood (``FaultTracingOptions`` does).

    Attributes
    ----------
    min_throw : float
        Smallest |median throw| of a fault, in samples, at the default sensitivity 0.5 (scaled by ``2 ** (1 - 2 *
        sensitivity)`` like the vote thresholds: twice it at sensitivity 0, half of it at 1). A shift under one sample
        between the sides is not a displacement the data resolves.
    min_correlation_gain : float
        Smallest gain of the sides' median normalised correlation from the throw's shift over no shift (``correlation -
        correlation_unshifted``); 0 asks only that the shifted sides correlate at least as well.
    continuity : float
        Unshifted median correlation of the sides from which the reflectors are taken to continue across the candidate;
        below it the sides do not match without a shift, which is itself evidence of a fault (a throw beyond the search,
        or unlike packages juxtaposed) when ``min_probability`` is None.
    min_vote_ratio : float
        Smallest mean of the fault's thinned votes along it, as a fraction of the upper vote threshold of the run
        (:attr:`FaultEvidence.vote_ratio`); 0 asks nothing. Not scaled by the sensitivity: the thresholds already are.
        Higher keeps fewer faults linked through weak votes (on the F3 inlines: precision 0.50, 0.59, 0.59 at 0.75, 0.9,
        1; recall 0.45, 0.45, 0.42).
    min_probability : float or None
        For a fault likelihood that is a probability (the learned one): the mean likelihood along a fault
        (:attr:`FaultEvidence.mean_likelihood`) from which it is kept without a measured displacement, at the default
        sensitivity (scaled like ``min_throw``); the unshifted mismatch of the sides is then not evidence by itself.
        None (the scan's default, whose likelihood is not a probability): the unshifted mismatch is evidence.
    clear_throw : float or None
        Smallest |median throw| of a *clear* displacement, samples, at the default sensitivity (scaled like
        ``min_throw``): a fault that shows one (with at least ``min_correlation_gain``) and whose mean likelihood
        reaches ``min_probability`` is kept whatever its vote ratio. None, or ``min_probability`` None (the scan): every
        fault must reach ``min_vote_ratio``.
    min_correlation : float or None
        Smallest median correlation of the sides at the throw's shift (:attr:`FaultEvidence.correlation`), asked of
        every fault but a clear and likely one and one the network is sure of (``sure_probability``); None asks nothing
        (the scan's default). Sides that do not look alike at any shift are not two blocks of one layering displaced (a
        migration swing, the edge of a chaotic body). 0.5 is the level where the aligned sides hold as much coherent as
        incoherent energy. Not scaled by the sensitivity (a correlation has no room above 1 to be doubled into: scaled
        like ``min_throw`` it asked 0.71 at sensitivity 0.25, and F3's F1 there fell from 0.431 to 0.360, the Costa Rica
        crf section's faults from 11 to 5); the sensitivity moves ``sure_probability``. Measured 2026-11-26
        (``tools/dev_fault_scores.py``). Chosen on F3 (0.4, 0.45, 0.5, 0.55:
        F1 0.479, 0.484, 0.486, 0.474); the Great South Basin scores the same at each. At sensitivity 0.25 / 0.75: F3 F1
        0.431 -> 0.434 / 0.437 -> 0.454, the Great South Basin unchanged (0.682 / 0.802).
    sure_probability : float or None
        For a probability (the learned likelihood): the mean likelihood along a fault from which the network alone is
        trusted and ``min_correlation`` is not asked, at the default sensitivity (scaled like ``min_probability``, at
        most 1); None: asked of every fault but a clear and likely one. Small faults of a sample's throw on short
        windows have sides that correlate poorly at any shift (the Great South Basin's 76-sample traces): without it
        ``min_correlation`` drops a fault an interpreter drew on crossline 2600 (mean likelihood 0.91, side correlation
        0.39; that survey's F1 0.829 -> 0.805). F3 scores the same for every value from 0.70 to 1 (the faults
        ``min_correlation`` drops there have mean likelihoods under 0.70), the Great South Basin for every value up to
        0.90; 0.75 (odds of 3 to 1) lies inside both.
    flexure_step : float or None
        2D: a fault whose sides match closely at the throw's shift (``correlation`` at least ``flexure_correlation``)
        but less than this fraction of whose throw is a step at the fault (:attr:`FaultEvidence.step`, the lag across
        the fault's zone less the dip of the reflectors right beside it) bends the reflectors over several traces: a
        flexure (drape, drag or fault-propagation fold, monocline), not a fault. The throw, read from reflectors carried
        to the fault along the flatter dip farther out, is then the fold's relief, and the fault is dropped whatever its
        votes and the network's probability (the network, trained on offsets, calls a clean flexure a fault: 0.75-0.97
        on generated ones). Not scaled by the sensitivity (a ratio of two displacements). None: not asked (the scan's
        default, not measured; 3D faults, whose step is not measured, are never dropped by it). Chosen
        leave-one-survey-out (2026-11-26, fractions 0.2-0.5 at correlations 0.8-0.95): F3's best F1 0.495 at 0.2 and
        0.3 with 0.9 (none: 0.494; 0.462 at 0.5 with 0.8); the Great South Basin 0.829 but at 0.5 with 0.8 and 0.85
        (0.807). Steps: its faults 0.4-0.8 of their throw, generated faults 1.0, generated flexures 0.01-0.2, the Teapot
        flexures at traces 72 and 180 0.26 (correlation 0.91-0.92).
    flexure_correlation : float
        The sides' correlation at the throw's shift from which ``flexure_step`` is asked: sides that match that well are
        continuous reflectors whose lags between neighbouring traces are measured reliably (on the F3 inlines' noisier
        sides the step of faults a person drew is often under a fifth of their throw).
    unseeded_correlation_gain : float or None
        2D: faults whose thinned votes reach the lower hysteresis threshold but nowhere the (run-relative) upper one are
        traced by a second hysteresis from the lower one on the cells the first left, and kept on a clear displacement:
        a throw of ``clear_throw`` gaining at least this correlation (scaled like ``min_throw``). None (the scan's): no
        second pass (never in 3D: it doubled the skins' time on the 18 Penobscot inlines, 17 -> 32 s, for no fault).
        Chosen leave-one-survey-out (``tools/dev_fault_scores.py``, 2026-11-26; 0, 0.1, 0.2, 0.3): F3 F1 0.496 from 0 to
        0.2 (0.495 at 0.3, None); the Great South Basin (0.829 at each) does not choose.
    clear_half_periods : float or None
        A clear throw of sides unlike at its shift (correlation under ``min_correlation``) that is no step at the fault
        (2D: :attr:`FaultEvidence.step` under ``flexure_step`` of it; 3D: not measured) must reach this many half
        periods of the reflectors around it (:attr:`FaultEvidence.half_period`): the correlation of unlike sides
        (crossing events: migration swings) peaks within half a period of any shift. Not scaled by the sensitivity;
        None: not asked. 1, the half period itself: neither dev survey chooses (``tools/dev_fault_scores.py``,
        2026-11-26: F3 F1 0.496, the Great South Basin 0.829 at 0.5, 1 and 1.5).
    unbroken_correlation : float or None
        Sides whose median correlation with no shift (``correlation - correlation_gain``) reaches it are reflectors
        continuing across the candidate, which is dropped whatever its votes and probability. Not scaled by the
        sensitivity; None: not asked. Chosen on F3 (F1 0.438, 0.452, 0.501, 0.496 at 0.8, 0.85, 0.9, 0.95; the Great
        South Basin 0.829 from 0.85; ``tools/dev_fault_scores.py``).
    drag_half_periods : float or None
        A resolved throw (``min_throw``, unscaled) of sides alike at its shift (``min_correlation``: unlike sides read
        no reliable throw) under this many half periods of the reflectors (:attr:`FaultEvidence.half_period`), less than
        ``drag_step`` of which is a step at the fault (2D), bends the reflectors within their wavelet (drag, a migration
        swing): dropped whatever its votes and probability. Not scaled by the sensitivity; None: not asked (3D faults,
        with no step measured, never are). The dev surveys score the same from 0.2 to 0.4 and F3 loses faults a person
        drew at 0.5: 0.3, the middle of that range.
    drag_step : float
        The fraction of the throw a step at the fault must reach for ``drag_half_periods`` not to drop it.
    unbroken_veto : bool
        Drop the faults across which the reflectors continue unbroken (:meth:`FaultEvidence.is_unbroken`: a flexure,
        sides matching unshifted, a drag) whatever their votes and probability. False: those three rules are not
        asked, and such a fault is judged on what else it shows (a fault an interpreter draws where the reflectors
        dim or fracture without a throw). ``seismo3d adapt`` measures on the picks it holds back whether a network
        adapted to a survey traces better with it or without, and records the choice in MODEL
        (:mod:`~seismo3d.seismic.adapted_network`).

    Raises
    ------
    InputError
        A value out of range.
    """

    min_throw: float = 1.0
    min_correlation_gain: float = 0.0
    continuity: float = 0.5
    min_vote_ratio: float = 0.9
    min_probability: float | None = 0.5
    clear_throw: float | None = 3.0
    min_correlation: float | None = 0.5
    sure_probability: float | None = 0.75
    flexure_step: float | None = 0.3
    flexure_correlation: float = 0.9
    unseeded_correlation_gain: float | None = 0.2
    clear_half_periods: float | None = 1.0
    unbroken_correlation: float | None = 0.9
    drag_half_periods: float | None = 0.3
    drag_step: float = 0.5
    unbroken_veto: bool = True

    def __post_init__(self):
        if not isinstance(self.unbroken_veto, (bool, np.bool_)):
            raise InputError(f"unbroken_veto must be True or False; got {self.unbroken_veto!r}")
        for k in ("min_throw", "min_vote_ratio", "drag_step", "clear_half_periods", "drag_half_periods", "clear_throw"):
            if getattr(self, k) is not None:  # a clear throw of 0 would be no displacement
                check_positive(getattr(self, k), k, allow_zero=k != "clear_throw")
        correlations = ("continuity", "min_correlation", "flexure_correlation", "unbroken_correlation")
        for names, low, high, what in ((("min_correlation_gain", "unseeded_correlation_gain"), -1.0, 2.0, "in [-1, 2]"),
                                       (correlations, -1.0, 1.0, "a correlation in [-1, 1]"),
                                       (("min_probability", "sure_probability"), 0.0, 1.0, "a probability in [0, 1]"),
                                       (("flexure_step",), 0.0, 1.0, "a fraction in [0, 1]")):
            for name in names:
                if (value := getattr(self, name)) is not None and not low <= float(value) <= high:
                    raise InputError(f"{name} must be {what} (or None where None is allowed); got {value!r}")

    @classmethod
    def for_likelihood(cls, likelihood: str) -> "EvidenceOptions":
        """The default evidence for a fault likelihood.

        Parameters
        ----------
        likelihood : {'learned', 'scan'}
            ``'learned'``: the class defaults. ``'scan'``: no vote ratio asked and the unshifted mismatch as evidence
            (``min_vote_ratio=0``, ``min_probability=None``; not ``min_correlation``, ``sure_probability``,
            ``flexure_step``, ``unseeded_correlation_gain``, ``unbroken_correlation``, ``drag_half_periods``, chosen
            for the learned one): its likelihood is not a probability, and its dense faults on the Costa Rica crf
            section (against the published OSV image, tolerance 3: precision 0.847, recall 0.720, 44 faults) fall to
            recall 0.613 (27 faults) when a vote ratio of 0.9 is asked (measured 2026-11-25).

        Returns
        -------
        EvidenceOptions

        Raises
        ------
        InputError
            An unknown likelihood.
        """
        if likelihood == "learned":
            return cls()
        if likelihood == "scan":
            return cls(min_vote_ratio=0.0, min_probability=None, min_correlation=None, sure_probability=None,
                       flexure_step=None, unseeded_correlation_gain=None, unbroken_correlation=None,
                       drag_half_periods=None)
        raise InputError(f"likelihood must be 'learned' or 'scan'; got {likelihood!r}")


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
        Median over the fault's points of the smaller of its sides' continuity (the correlation of the mean of a side's
        nearer traces with that of its farther ones, :attr:`~seismo3d.seismic.faults.throw.FaultThrow.side_coherence`),
        in [-1, 1]; NaN if unmeasured. Reported, not asked for: sides not continuous themselves (noise, a chaotic body's
        edge: 0.01 on a generated one) say little of a displacement, but real faults in noisy data have them too (on the
        Costa Rica crf section faults the published OSV result also holds measure below 0.5).
    vote_ratio : float
        Mean of the fault's thinned votes along it over the upper vote threshold of the run that traced it
        (dimensionless; 1: as strong on average as the hysteresis' seeds); NaN when not measured.
    mean_likelihood : float
        Mean fault likelihood along the fault, in [0, 1] (for the learned likelihood: the network's probability);
        NaN when not measured.
    confidence : float
        The score ranking the kept faults, the ones a person would draw first (the ``confidence`` column of the CSVs,
        which ``seismo3d evaluate`` ranks by): the mean likelihood along the fault. Chosen leave-one-survey-out by the
        average precision (AP) of ``seismo3d evaluate`` on the dev surveys' outputs (2026-11-26) among the mean
        likelihood, vote ratio, number of points, |median throw|, the throw's correlation and gain, side coherence, the
        evidence's margin (the sensitivity dropping the fault) and the mean likelihood's products with each: best on
        the Great South Basin (AP 0.782; F3 0.304, 0.008 below F3's best, the product with the sides' coherence, GSB
        0.771); the margin 0.752 and 0.289. NaN until :func:`supported_faults` sets it.
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
        """True when the reflectors continue across the fault: a flexure (:meth:`is_flexure`), sides matching unshifted
        (``unbroken_correlation``) or a throw within their wavelet (``drag_half_periods``); NaN shows nothing. Always
        False when ``options.unbroken_veto`` is off."""
        if not options.unbroken_veto:
            return False
        throw, alike, unbroken = abs(self.median_throw), options.min_correlation, options.unbroken_correlation
        drag = (options.drag_half_periods is not None and throw >= options.min_throw  # unlike sides: no reliable throw
                and (alike is None or self.correlation >= alike) and abs(self.step) < options.drag_step * throw
                and throw < options.drag_half_periods * self.half_period)
        return bool(self.is_flexure(options) or drag
                    or (unbroken is not None and self.correlation - self.correlation_gain >= unbroken))

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
        t, c, c0 = (np.asarray(getattr(throw, name), np.float64)
                    for name in ("throw", "correlation", "correlation_unshifted"))
        coherence = getattr(throw, "side_coherence", None)
        coherence = np.full(t.shape, np.nan) if coherence is None else np.asarray(coherence, np.float64)
        median_throw = float(throw.median_throw)
    except AttributeError as exc:
        raise InputError(f"fault_evidence needs a FaultThrow (see fault_throw); got {type(throw).__name__}") from exc
    measured = np.isfinite(t)
    registered = np.asarray(getattr(throw, "registered", np.zeros(t.shape, bool)), bool)
    once = getattr(throw, "n_patches_measured", -1) == 1 and not registered[measured].any()
    # the interquartile range; unmeasured, or one shift for the whole fault (every 2D fault): no variation to measure
    spread = float(np.subtract(*np.percentile(t[measured], [75, 25]))) if measured.any() and not once else float("nan")
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
    vote_ratios, mean_likelihoods = ([float("nan")] * n if values is None else [float(v) for v in values]
                                     for values in (vote_ratios, mean_likelihoods))
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
