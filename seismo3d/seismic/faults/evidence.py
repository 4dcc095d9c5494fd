"""The evidence a fault must show: reflectors displaced across it.

A ridge of the fault likelihood is only a discontinuity of the reflectors' lateral continuity; on real data (8-bit
clipping, dim and chaotic intervals, coherent noise, acquisition footprint) most such ridges cross reflectors that
continue unbroken. What makes a discontinuity a fault is a displacement (Hale 2014): the reflectors on the two sides
line up only after a vertical shift, the throw, or they do not line up at all (a large throw beyond the search, a
juxtaposition of unlike packages). :func:`fault_evidence` reads that evidence from the throw measurement
(:func:`~seismo3d.seismic.faults.throw.fault_throw`: the shift that best aligns the images of the two sides, and their
correlation with and without that shift), and :func:`supported_faults` drops the candidates across which the
reflectors continue unbroken: sides that match with no shift (normalised correlation of at least 0.5, as much
coherent as incoherent energy) and that no shift of a sample or more matches better. The measures are absolute and
dimensionless, the same on every input: a shift in samples (a displacement under one sample is not resolved by the
data) and normalised correlations. Each fault also reports how continuous its sides are in themselves
(``side_coherence``), to sort and filter on: along the edge of a chaotic body or in noise nothing matches, the side
itself included.
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

    The defaults are not fitted to data: one sample is the smallest displacement the data resolves, a correlation
    of 0.5 is the level where the sides hold as much coherent as incoherent energy. ``benchmarks/faults.py --only
    f3`` cross-validates a grid of ``min_throw`` and ``min_correlation_gain`` on the five F3 inlines with faults
    drawn by a person (chosen on three inlines, scored on the other two): the choices vary from fold to fold (1 to 3
    samples) and score lower on the held-out inlines than these defaults.

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
        beyond the search, or unlike packages juxtaposed).
    """

    min_throw: float = 1.0
    min_correlation_gain: float = 0.0
    continuity: float = 0.5

    def __post_init__(self):
        check_positive(self.min_throw, "min_throw", allow_zero=True)
        if not -1.0 <= float(self.min_correlation_gain) <= 2.0:
            raise InputError(f"min_correlation_gain must be in [-1, 2]; got {self.min_correlation_gain!r}")
        if not -1.0 <= float(self.continuity) <= 1.0:
            raise InputError(f"continuity must be a correlation in [-1, 1]; got {self.continuity!r}")


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
        chance alignment of periodic reflectors jumps; NaN if unmeasured.
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
    """

    fault_id: int
    median_throw: float
    throw_spread: float
    correlation: float
    correlation_gain: float
    measured_fraction: float
    side_coherence: float = float("nan")

    def supports(self, options: EvidenceOptions, sensitivity: float = 0.5) -> bool:
        """True when the fault shows what ``options`` ask for at ``sensitivity`` in [0, 1]: a displacement, or sides
        that do not match without a shift."""
        factor = sensitivity_factor(sensitivity)
        if not (np.isfinite(self.median_throw) and np.isfinite(self.correlation_gain)):
            return False  # the two sides could not be compared: nothing shows a fault
        if self.correlation - self.correlation_gain < options.continuity:
            return True  # the sides do not match unshifted: a discontinuity
        return (abs(self.median_throw) >= factor * options.min_throw
                and self.correlation_gain >= factor * options.min_correlation_gain)


def _median(values: np.ndarray) -> float:
    finite = values[np.isfinite(values)]
    return float(np.median(finite)) if finite.size else float("nan")


def fault_evidence(throw) -> FaultEvidence:
    """The displacement evidence of a fault from its throw measurement.

    Parameters
    ----------
    throw : FaultThrow
        The result of :func:`~seismo3d.seismic.faults.throw.fault_throw` for the fault: ``throw``,
        ``correlation`` and ``correlation_unshifted`` per point.

    Returns
    -------
    FaultEvidence
        Median throw and its interquartile spread (samples), the median correlation of the sides at the throw's
        shift and its gain over no shift, the fraction of points measured, the sides' continuity.

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
    if measured.any():
        q1, q3 = np.percentile(t[measured], [25, 75])
        spread = float(q3 - q1)
    else:
        spread = float("nan")
    return FaultEvidence(fault_id=int(throw.fault_id), median_throw=median_throw, throw_spread=spread,
                         correlation=_median(c), correlation_gain=_median(c - c0),
                         measured_fraction=float(measured.mean()) if t.size else 0.0,
                         side_coherence=_median(coherence))


def supported_faults(faults: list, throws: list, *, options: EvidenceOptions | None = None,
                     sensitivity: float = 0.5) -> tuple[list, list, list]:
    """Drop the candidates across which the reflectors continue unbroken; renumber the others 1, 2, ... in order.

    A fault is kept when its two sides line up better after a shift of at least ``options.min_throw`` samples than
    with none, or do not match without a shift (:meth:`FaultEvidence.supports`). A candidate whose sides match with
    no shift and no better with one is not a fault, however strong its likelihood.

    Parameters
    ----------
    faults : list of Fault
        Fault skins (:func:`~seismo3d.seismic.faults.skins.fault_skins`), ids 1, 2, ... in decreasing size.
    throws : list of FaultThrow
        Their throws, in the same order (:func:`~seismo3d.seismic.faults.throw.fault_throws`).
    options : EvidenceOptions, optional
        The evidence asked for.
    sensitivity : float, optional
        In [0, 1]: higher keeps faults with smaller displacements (see :class:`EvidenceOptions`).

    Returns
    -------
    faults, throws : list
        The kept faults and their throws, ids renumbered 1, 2, ... in the input's order (decreasing size).
    evidence : list of FaultEvidence
        The kept faults' evidence, with the new ids.

    Raises
    ------
    InputError
        ``faults`` and ``throws`` differ in length or ids.
    """
    opt = options or EvidenceOptions()
    if len(faults) != len(throws):
        raise InputError(f"{len(faults)} faults but {len(throws)} throws; pass the throws of these faults")
    kept_faults, kept_throws, kept_evidence = [], [], []
    for fault, throw in zip(faults, throws):
        if int(throw.fault_id) != int(fault.id):
            raise InputError(f"throw of fault {throw.fault_id} paired with fault {fault.id}; pass them in one order")
        evidence = fault_evidence(throw)
        if not evidence.supports(opt, sensitivity):
            continue
        new_id = len(kept_faults) + 1
        kept_faults.append(dataclasses.replace(fault, id=new_id))
        kept_throws.append(dataclasses.replace(throw, fault_id=new_id))
        kept_evidence.append(dataclasses.replace(evidence, fault_id=new_id))
    return kept_faults, kept_throws, kept_evidence
