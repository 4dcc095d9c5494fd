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
    unbroken_correlation : float or None
        Sides whose median correlation with no shift (``correlation - correlation_gain``) reaches it are reflectors that
        continue across the candidate unbroken: it is dropped whatever its votes and the network's probability (the
        network calls the edge of a dim or noisy patch in continuous layering a fault). Not scaled by the sensitivity;
        None: not asked. Chosen on F3 (the candidates of a ``tools/dev_fault_scores.py`` run re-scored by its scorer for
        each value, 2026-11-26; 0.8, 0.85, 0.9, 0.95: F1 0.438, 0.452, 0.501, 0.496; 0.9 confirmed by a run of the
        script: P / R / F1 0.615 / 0.423 / 0.496 -> 0.630 / 0.423 / 0.501): 0.9 drops the two short faults of inline 200
        at crosslines 552-556 and 600-604 through continuous layering (unshifted correlations 0.95 and 0.92), and
        nothing a person drew (the closest: 0.88, the large fault of inline 200); the Great South Basin scores 0.829
        from 0.85 up and drops none, nor do the real sections of ``seismo3d faults``' golden set.
    drag_half_periods : float or None
        A resolved throw (at least ``min_throw``, unscaled) of sides alike at its shift (``correlation`` at least
        ``min_correlation``: unlike sides read no reliable throw, as a large fault's beyond the search) under this many
        half periods of the reflectors around the fault (:attr:`FaultEvidence.half_period`) of which less than
        ``drag_step`` is a step at the fault (2D: :attr:`FaultEvidence.step`) bends the reflectors within their own
        wavelet, not a break: drag beside a larger fault, a migration swing crossing dipping events. Dropped whatever
        its votes and probability. Not scaled by the sensitivity; None: not asked (3D faults, whose step is not
        measured, never are). Neither dev survey chooses (``tools/dev_fault_scores.py``'s candidates re-scored,
        2026-11-26, with ``unbroken_correlation`` 0.9: F3 0.630 / 0.423 / 0.501 and the Great South Basin 0.797 / 0.865
        / 0.829 at 0.2, 0.25, 0.3, 0.35 and 0.4; its faults of one to three samples step 0.46-1.3 of their throw); from
        0.5 F3 loses faults a person drew (inline 400, crosslines 214-239 and 416-433: 0.42-0.44 half periods, steps
        0.07-0.33 of their throw; F1 0.473). The value is set on the golden real sections, not across surveys: 0.25
        drops Penobscot crossline 1155's migration-swing fault at inlines 1380-1450, 3700-4350 ms (throw -1.5 samples,
        0.21 half period, step 0.34 of it, sides correlating 0.64) and teapot_tpd's short unseeded fault at traces
        161-163 (-3 samples, 0.24 half period), and keeps teapot_tp73's small fault with visible steps at traces 324-330
        (0.31 half period, which 0.35 drops); 0.2 drops neither. A small margin on both sides.
    drag_step : float
        The fraction of the throw that a step at the fault must reach for ``drag_half_periods`` not to drop it: 0.5,
        half the throw (from 0.4 to 0.5 the same faults on the dev surveys and the golden sections; 0.3 keeps the
        Penobscot swing, whose step is 0.34 of its throw).
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
    drag_half_periods: float | None = 0.25
    drag_step: float = 0.5

    def __post_init__(self):
        check_positive(self.min_throw, "min_throw", allow_zero=True)
        if not -1.0 <= float(self.min_correlation_gain) <= 2.0:
            raise InputError(f"min_correlation_gain must be in [-1, 2]; got {self.min_correlation_gain!r}")
        if not -1.0 <= float(self.continuity) <= 1.0:
            raise InputError(f"continuity must be a correlation in [-1, 1]; got {self.continuity!r}")
        for name in ("min_vote_ratio", "drag_step") + tuple(n for n in ("clear_half_periods", "drag_half_periods")
                                                          if getattr(self, n) is not None):
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
        if self.unbroken_correlation is not None and not -1.0 <= float(self.unbroken_correlation) <= 1.0:
            raise InputError(f"unbroken_correlation must be a correlation in [-1, 1] or None; got "
                             f"{self.unbroken_correlation!r}")
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
            ``flexure_step``, ``unseeded_correlation_gain``, ``unbroken_correlation``, ``drag_half_periods``, chosen
            for the learned one): its likelihood is not a
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
                       flexure_step=None, unseeded_correlation_gain=None, unbroken_correlation=None,
                       drag_half_periods=None)
        raise InputError(f"likelihood must be 'learned' or 'scan'; got {likelihood!r}")
