"""What a fault must show to be kept: the options of :func:`~seismo3d.seismic.faults.evidence.supported_faults`.

Kept apart from :mod:`~seismo3d.seismic.faults.evidence` (which re-exports :class:`EvidenceOptions`) for length: each
option's docstring records how its default was chosen.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..._validation import check_positive
from ...errors import InputError

__all__ = ["EvidenceOptions"]


@dataclass(frozen=True)
class EvidenceOptions:
    """What a fault must show to be kept (see :func:`supported_faults`).

    One sample is the smallest displacement the data resolves, a correlation of 0.5 is the level where the sides
    hold as much coherent as incoherent energy, a probability of 0.5 is the network's own decision level. The vote
    ratio (0.9 of the upper threshold the hysteresis traced the fault from) and the probability are chosen by
    cross-validation on the five F3 inlines with faults drawn by a person (``benchmarks/faults.py --only f3``:
    ratios 0, 0.75, 0.9, 1, 1.1, probabilities 0.5, 0.6, 0.7 and four sets of network grids, chosen on three inlines,
    scored on the other two, every split); the generated cubes' true faults measure 0.96-1.44.

    Use :meth:`for_likelihood` for the defaults of each fault likelihood (``FaultTracingOptions`` does).

    Attributes
    ----------
    min_throw : float
        Smallest |median throw| of a fault, in samples, at the default sensitivity 0.5 (scaled by
        ``2 ** (1 - 2 * sensitivity)`` like the vote thresholds: twice it at sensitivity 0, half of it at 1). A shift
        under one sample between the sides is not a displacement the data resolves.
    min_correlation_gain : float
        Smallest gain of the sides' median normalised correlation from the throw's shift over no shift
        (``correlation - correlation_unshifted``); 0 asks only that the shifted sides correlate at least as well.
    continuity : float
        Unshifted median correlation of the sides from which the reflectors are taken to continue across the
        candidate; below it the sides do not match without a shift, which is itself evidence of a fault (a throw
        beyond the search, or unlike packages juxtaposed) when ``min_probability`` is None.
    min_vote_ratio : float
        Smallest mean of the fault's thinned votes along it, as a fraction of the upper vote threshold of the run
        (:attr:`FaultEvidence.vote_ratio`); 0 asks nothing. Not scaled by the sensitivity: the thresholds already
        are. Higher keeps fewer faults linked through weak votes (on the F3 inlines: precision 0.50, 0.59, 0.59 at
        0.75, 0.9, 1; recall 0.45, 0.45, 0.42).
    min_probability : float or None
        For a fault likelihood that is a probability (the learned one): the mean likelihood along a fault
        (:attr:`FaultEvidence.mean_likelihood`) from which it is kept without a measured displacement, at the default
        sensitivity (scaled like ``min_throw``); the unshifted mismatch of the sides is then not evidence by itself.
        None (the scan's default, whose likelihood is not a probability): the unshifted mismatch is evidence.
    clear_throw : float or None
        Smallest |median throw| of a *clear* displacement, samples, at the default sensitivity (scaled like
        ``min_throw``): a fault that shows one (with at least ``min_correlation_gain``) and whose mean likelihood
        reaches ``min_probability`` is kept whatever its vote ratio. None, or ``min_probability`` None (the scan):
        every fault must reach ``min_vote_ratio``.
    min_correlation : float or None
        Smallest median correlation of the sides at the throw's shift (:attr:`FaultEvidence.correlation`), asked of
        every fault but a clear and likely one and one the network is sure of (``sure_probability``); None asks
        nothing (the scan's default). Sides that do not look alike at any shift are not two blocks of one layering
        displaced (a migration swing, the edge of a chaotic body). 0.5 is the level where the aligned sides hold as
        much coherent as incoherent energy. Not scaled by the sensitivity (a correlation has no room above 1 to be
        doubled into: scaled like ``min_throw`` it asked 0.71 at sensitivity 0.25, and F3's F1 there fell from 0.431
        to 0.360, the Costa Rica crf section's faults from 11 to 5); the sensitivity moves ``sure_probability``.
        Measured on 2026-11-26 (``tools/dev_fault_scores.py``, the learned likelihood): without it F3 mean P / R /
        F1 0.528 / 0.433 / 0.470 and the Great South Basin 0.797 / 0.865 / 0.829; with it (and ``sure_probability``
        0.75) F3 0.590 / 0.425 / 0.486 and the Great South Basin unchanged. Chosen on F3 (0.4, 0.45, 0.5, 0.55: F1
        0.479, 0.484, 0.486, 0.474); the Great South Basin scores the same at each. At sensitivity 0.25 / 0.75: F3
        F1 0.431 -> 0.434 / 0.437 -> 0.454, the Great South Basin unchanged (0.682 / 0.802). It drops the Volve fault
        dipping across the 1340-1400 ms package unbroken and two of the five migration-swing faults of Penobscot
        crossline 1155.
    sure_probability : float or None
        For a probability (the learned likelihood): the mean likelihood along a fault from which the network alone
        is trusted and ``min_correlation`` is not asked, at the default sensitivity (scaled like ``min_probability``,
        at most 1); None: asked of every fault but a clear and likely one. Small faults of a sample's throw on short
        windows have sides that correlate poorly at any shift (the Great South Basin's 76-sample traces): without
        it ``min_correlation`` drops a fault an interpreter drew on crossline 2600 (mean likelihood 0.91, side
        correlation 0.39; that survey's F1 0.829 -> 0.805). F3 scores the same for every value from 0.70 to 1 (the
        faults ``min_correlation`` drops there have mean likelihoods under 0.70), the Great South Basin for every
        value up to 0.90; 0.75 (odds of 3 to 1) lies inside both.
    flexure_step : float or None
        2D: a fault whose sides match closely at the throw's shift (``correlation`` at least
        ``flexure_correlation``) but less than this fraction of whose throw is a step at the fault
        (:attr:`FaultEvidence.step`, the lag across the fault's zone less the dip of the reflectors right beside it)
        bends the reflectors over several traces: a flexure (drape, drag or fault-propagation fold, monocline), not
        a fault. The throw, read from reflectors carried to the fault along the flatter dip farther out, is then the
        fold's relief, and the fault is dropped whatever its votes and the network's probability (the network,
        trained on offsets, calls a clean flexure a fault: 0.75-0.97 on generated ones). Not scaled by the
        sensitivity (a ratio of two displacements). None: not asked (the scan's default, not measured; 3D faults,
        whose step is not measured, are never dropped by it). Chosen leave-one-survey-out
        (``tools/dev_fault_scores.py``, 2026-11-26; fractions 0.2, 0.3, 0.4, 0.5 at correlations 0.8, 0.85, 0.9,
        0.95): on F3 the best F1 is 0.495 at 0.2 and 0.3 with 0.9 (none: 0.494; precision 0.607 -> 0.617; 0.462 at
        0.5 with 0.8), where the Great South Basin scores 0.829, as without it; the Great South Basin scores 0.829
        everywhere but at 0.5 with 0.8 and 0.85 (0.807) and does not choose. Its faults, one to three samples of
        throw, show steps of 0.4-0.8 of it; generated faults of 2-3 samples 1.0, generated flexures 0.01-0.2; the
        Teapot flexures at traces 72 and 180 0.26 (correlation 0.91-0.92).
    flexure_correlation : float
        The sides' correlation at the throw's shift from which ``flexure_step`` is asked: sides that match that
        well are continuous reflectors whose lags between neighbouring traces are measured reliably (on the F3
        inlines' noisier sides the step of faults a person drew is often under a fifth of their throw).
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

    def __post_init__(self):
        check_positive(self.min_throw, "min_throw", allow_zero=True)
        if not -1.0 <= float(self.min_correlation_gain) <= 2.0:
            raise InputError(f"min_correlation_gain must be in [-1, 2]; got {self.min_correlation_gain!r}")
        if not -1.0 <= float(self.continuity) <= 1.0:
            raise InputError(f"continuity must be a correlation in [-1, 1]; got {self.continuity!r}")
        for name in ("min_vote_ratio",) + (("clear_half_periods",) if self.clear_half_periods is not None else ()):
            check_positive(getattr(self, name), name, allow_zero=True)
        if self.min_probability is not None and not 0.0 <= float(self.min_probability) <= 1.0:
            raise InputError(f"min_probability must be a probability in [0, 1] or None; got {self.min_probability!r}")
        if self.clear_throw is not None:
            check_positive(self.clear_throw, "clear_throw")
        if self.min_correlation is not None and not -1.0 <= float(self.min_correlation) <= 1.0:
            raise InputError(f"min_correlation must be a correlation in [-1, 1] or None; got {self.min_correlation!r}")
        if self.sure_probability is not None and not 0.0 <= float(self.sure_probability) <= 1.0:
            raise InputError(f"sure_probability must be a probability in [0, 1] or None; got "
                             f"{self.sure_probability!r}")
        if self.flexure_step is not None and not 0.0 <= float(self.flexure_step) <= 1.0:
            raise InputError(f"flexure_step must be a fraction in [0, 1] or None; got {self.flexure_step!r}")
        if (gain := self.unseeded_correlation_gain) is not None and not -1.0 <= float(gain) <= 2.0:
            raise InputError(f"unseeded_correlation_gain must be in [-1, 2] or None; got {gain!r}")
        if not -1.0 <= float(self.flexure_correlation) <= 1.0:
            raise InputError(f"flexure_correlation must be a correlation in [-1, 1]; got {self.flexure_correlation!r}")

    @classmethod
    def for_likelihood(cls, likelihood: str) -> "EvidenceOptions":
        """The default evidence for a fault likelihood.

        Parameters
        ----------
        likelihood : {'learned', 'scan'}
            ``'learned'``: the class defaults. ``'scan'``: no vote ratio asked and the unshifted mismatch as evidence
            (``min_vote_ratio=0``, ``min_probability=None``; not ``min_correlation``, ``sure_probability``,
            ``flexure_step``, ``unseeded_correlation_gain``, chosen for the learned one): its likelihood is not a
            probability, and its dense faults on the Costa Rica crf section (against the published OSV image, tolerance
            3: precision 0.847, recall 0.720, 44 faults) fall to recall 0.613 (27 faults) when a vote ratio of 0.9 is
            asked (measured 2026-11-25).

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
                       flexure_step=None, unseeded_correlation_gain=None)
        raise InputError(f"likelihood must be 'learned' or 'scan'; got {likelihood!r}")
