"""Traced faults scored against people's faults on one seismic line: tolerant precision, recall and F1, the
fault-by-fault matches, and the precision-recall curve over the traced faults' confidence.

The definition is the one the project's real-data fault targets are checked with (``fault_scores.py`` and
``dev_fault_scores.py`` beside the data folder), in a section's index space (trace index, sample index):

- **precision**: the fraction of the traced faults' samples with a sample of people's faults within ``tolerance``
  samples (Euclidean distance in index space, from :func:`scipy.ndimage.distance_transform_edt`);
- **recall**: the fraction of people's fault samples with a traced fault sample within ``tolerance``;
- **F1**: ``2 P R / (P + R)``; all three are 0 when either drawing is empty.

A sample counts once however many faults cross it. Faults are given as :class:`SectionFaults`: the samples each
fault crosses, made from people's fault sticks (:meth:`SectionFaults.from_sticks`, placed as
:mod:`seismo3d.seismic.io.stick_sections` says), a raster mask (:meth:`SectionFaults.from_mask`,
:meth:`SectionFaults.from_labels`) or fault points given by their trace labels and times
(:meth:`SectionFaults.from_positions`, as ``fault_points.csv`` of ``seismo3d faults`` holds them).
:func:`score_fault_line` returns a :class:`FaultLineScores`; the ``seismo3d evaluate`` command
(:mod:`seismo3d.jobs.evaluate`) and the fault benchmark call it, so a user's numbers and the project's are one
computation.

References
----------
.. [1] The tolerant (buffered) precision and recall of thin structures: C. J. van Rijsbergen, *Information
   Retrieval*, 2nd ed., Butterworths, 1979 (precision, recall, F); D. R. Martin, C. C. Fowlkes and J. Malik,
   "Learning to detect natural image boundaries using local brightness, color, and texture cues", IEEE TPAMI 26(5),
   530-549, 2004, doi:10.1109/TPAMI.2004.1273918 (boundary precision and recall within a distance tolerance), as used
   for seismic faults by X. Wu, L. Liang, Y. Shi and S. Fomel, "FaultSeg3D", Geophysics 84(3), IM35-IM45, 2019,
   doi:10.1190/geo2018-0646.1.
.. [2] The average precision of a ranked list, :math:`AP = \\sum_k (R_k - R_{k-1}) P_k`, as
   ``sklearn.metrics.average_precision_score`` computes it (no interpolation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage as ndi

from .._validation import check_positive
from ..errors import InputError
from .io.stick_sections import section_pixels

__all__ = ["FaultLineScores", "FaultPair", "FaultScoringOptions", "PeopleFaultScore", "PrecisionRecallCurve",
           "SectionFaults", "TracedFaultScore", "score_fault_line", "tolerant_scores"]


@dataclass(frozen=True)
class FaultScoringOptions:
    """How :func:`score_fault_line` scores.

    Attributes
    ----------
    tolerance : float
        Largest distance between a traced and a people's fault sample that still matches, in samples (Euclidean in
        the section's index space: one trace = one sample). 3, as the project's targets.
    match_fraction : float
        A traced fault and a person's fault match when at least this fraction of either one's samples lies within
        ``tolerance`` of the other's (in (0, 1]): a traced piece of a person's fault matches it, as does a traced
        fault a person drew as a piece of a longer one; two faults that only cross do not.
    """

    tolerance: float = 3.0
    match_fraction: float = 0.5

    def __post_init__(self):
        check_positive(self.tolerance, "tolerance", allow_zero=True)
        if not 0.0 < float(self.match_fraction) <= 1.0:
            raise InputError(f"match_fraction must be in (0, 1]; got {self.match_fraction!r}")


@dataclass(frozen=True, eq=False)
class SectionFaults:
    """Faults on a 2D section (one inline or crossline, or a 2D array): the samples each fault crosses.

    Attributes
    ----------
    points : (n, 2) int64 ndarray
        (trace index, sample index) of each fault sample; a sample may be listed more than once.
    fault_id : (n,) int64 ndarray
        The fault of each, > 0.
    shape : (int, int)
        The section's (n_traces, n_samples).
    names : dict of int to str
        A name per fault id (default ``'fault <id>'``).
    """

    points: np.ndarray
    fault_id: np.ndarray
    shape: tuple
    names: dict = field(default_factory=dict)

    def __post_init__(self):
        p = np.asarray(self.points)
        if p.ndim != 2 or p.shape[1] != 2 or np.asarray(self.fault_id).shape != (p.shape[0],):
            raise InputError(f"points must be (n, 2) with one fault_id each; got points {p.shape} and fault_id "
                             f"{np.asarray(self.fault_id).shape}")
        if len(self.shape) != 2:
            raise InputError(f"shape must be the section's (n_traces, n_samples); got {self.shape!r}")
        if p.size and (p.min() < 0 or np.any(p.max(axis=0) >= np.asarray(self.shape))):
            raise InputError(f"points lie outside the section of {self.shape[0]} traces x {self.shape[1]} samples")
        if np.any(np.asarray(self.fault_id) <= 0):
            raise InputError("fault ids must be > 0")

    @property
    def ids(self) -> np.ndarray:
        """(k,) int64 ndarray: the fault ids, increasing."""
        return np.unique(np.asarray(self.fault_id, dtype=np.int64))

    def name(self, fault_id: int) -> str:
        """The name of fault ``fault_id``."""
        return self.names.get(int(fault_id), f"fault {int(fault_id)}")

    def mask(self, fault_ids=None) -> np.ndarray:
        """(n_traces, n_samples) bool ndarray: the samples of the faults ``fault_ids`` (default: all)."""
        out = np.zeros(tuple(self.shape), dtype=bool)
        p = np.asarray(self.points, dtype=np.int64)
        if fault_ids is not None:
            p = p[np.isin(self.fault_id, np.atleast_1d(fault_ids))]
        out[p[:, 0], p[:, 1]] = True
        return out

    def labels(self) -> np.ndarray:
        """(n_traces, n_samples) int64 ndarray: the fault id on each fault sample (the largest where faults share
        one), 0 elsewhere."""
        out = np.zeros(tuple(self.shape), dtype=np.int64)
        order = np.argsort(self.fault_id, kind="stable")
        p = np.asarray(self.points, dtype=np.int64)[order]
        out[p[:, 0], p[:, 1]] = np.asarray(self.fault_id, dtype=np.int64)[order]
        return out

    @classmethod
    def from_labels(cls, labels) -> "SectionFaults":
        """Faults of a label image: each nonzero value is one fault's id (:func:`~seismo3d.seismic.fault_labels`).

        Parameters
        ----------
        labels : (n_traces, n_samples) array_like of int
            0 off the faults.

        Returns
        -------
        SectionFaults

        Raises
        ------
        InputError
            Not 2D, or negative values.
        """
        lab = np.asarray(labels)
        if lab.ndim != 2:
            raise InputError(f"labels must be a section's (n_traces, n_samples); got shape {lab.shape}")
        if np.issubdtype(lab.dtype, np.bool_):
            lab = lab.astype(np.int64)
        if np.any(lab < 0) or not np.all(lab == np.round(lab)):
            raise InputError("labels must be whole numbers >= 0 (fault ids, 0 off the faults)")
        t, k = np.nonzero(lab)
        return cls(np.column_stack([t, k]).astype(np.int64), lab[t, k].astype(np.int64), lab.shape)

    @classmethod
    def from_mask(cls, mask) -> "SectionFaults":
        """Faults of a mask: each 8-connected group of nonzero samples is one fault (ids 1.. in the order of
        :func:`scipy.ndimage.label`).

        Parameters
        ----------
        mask : (n_traces, n_samples) array_like
            Nonzero on fault samples.

        Returns
        -------
        SectionFaults

        Raises
        ------
        InputError
            Not 2D.
        """
        m = np.asarray(mask)
        if m.ndim != 2:
            raise InputError(f"mask must be a section's (n_traces, n_samples); got shape {m.shape}")
        labels, _ = ndi.label(m != 0, structure=np.ones((3, 3), dtype=bool))
        return cls.from_labels(labels)

    @classmethod
    def from_sticks(cls, sticks, trace_labels, samples, *, axis: str = "inline") -> "SectionFaults":
        """People's fault sticks on a section, placed on its traces by their line numbers and on its samples by
        their time or depth (:func:`~seismo3d.seismic.io.stick_sections.section_pixels`).

        Parameters
        ----------
        sticks : FaultSticks
            From :func:`~seismo3d.seismic.io.read_fault_sticks`; its faults keep their ids and names.
        trace_labels : (n_traces,) array_like of float
            The section's inline numbers (a crossline: ``axis='inline'``) or crossline numbers (an inline).
        samples : (n_samples,) array_like of float
            The section's sample times (ms) or depths, in the sticks' unit.
        axis : {'inline', 'crossline'}

        Returns
        -------
        SectionFaults

        Raises
        ------
        InputError
            As :func:`~seismo3d.seismic.io.stick_sections.section_pixels`.
        """
        parts = section_pixels(sticks, trace_labels, samples, axis=axis)
        points = np.concatenate([p for _, p in parts] or [np.zeros((0, 2), np.int64)])
        ids = np.concatenate([np.full(len(p), fid, dtype=np.int64) for fid, p in parts] or [np.zeros(0, np.int64)])
        names = {i + 1: str(n) for i, n in enumerate(sticks.names)}
        return cls(points, ids, (np.asarray(trace_labels).size, np.asarray(samples).size), names)

    @classmethod
    def from_positions(cls, trace_label, z, fault_id, *, trace_labels, samples) -> "SectionFaults":
        """Fault points given by their trace's label and their time or depth (``fault_points.csv``), placed on a
        section's traces and samples.

        A point goes to the trace whose label equals its own, and to the nearest sample (``round((z - samples[0]) /
        interval)``, half to even), as ``dev_fault_scores.py`` places them.

        Parameters
        ----------
        trace_label : (n,) array_like of float
            Each point's inline (or crossline) number, or trace index for a section without numbers.
        z : (n,) array_like of float
            Each point's two-way time (ms) or depth, in the unit of ``samples``.
        fault_id : (n,) array_like of int
            Each point's fault, > 0.
        trace_labels : (n_traces,) array_like of float
            The section's label of each trace (its inline numbers for a crossline), increasing or decreasing.
        samples : (n_samples,) array_like of float
            The section's sample positions, evenly spaced and increasing.

        Returns
        -------
        SectionFaults

        Raises
        ------
        InputError
            A point whose label is no trace's, or whose time or depth is beyond the samples by more than half an
            interval (the message gives the first and how many): the points are of another line.
        """
        label = np.asarray(trace_label, dtype=np.float64)
        zz = np.asarray(z, dtype=np.float64)
        fid = np.asarray(fault_id, dtype=np.int64)
        labels = np.asarray(trace_labels, dtype=np.float64)
        s = np.asarray(samples, dtype=np.float64)
        if not (label.shape == zz.shape == fid.shape and label.ndim == 1):
            raise InputError(f"trace_label, z and fault_id must be (n,) arrays of one length; got {label.shape}, "
                             f"{zz.shape}, {fid.shape}")
        if labels.ndim != 1 or labels.size == 0 or s.ndim != 1 or s.size == 0:
            raise InputError("trace_labels and samples must be non-empty (n,) arrays: the section's axes")
        order = np.argsort(labels, kind="stable")
        at = np.clip(np.searchsorted(labels[order], label), 0, labels.size - 1)
        off = labels[order][at] != label
        if np.any(off):
            first = label[np.flatnonzero(off)[0]]
            raise InputError(f"{int(off.sum())} of {label.size} fault points lie on no trace of the section (the "
                             f"first at trace label {first:g}; the section's traces are labelled {labels.min():g}-"
                             f"{labels.max():g}): they are not of this line")
        step = float(s[1] - s[0]) if s.size > 1 else 1.0
        k = np.round((zz - s[0]) / step).astype(np.int64)
        beyond = (k < 0) | (k >= s.size)
        if np.any(beyond):
            first = zz[np.flatnonzero(beyond)[0]]
            raise InputError(f"{int(beyond.sum())} of {zz.size} fault points lie beyond the section's samples (the "
                             f"first at {first:g}; the samples run {s[0]:g}-{s[-1]:g}): they are not of this line")
        return cls(np.column_stack([order[at], k]).astype(np.int64), fid, (labels.size, s.size))


@dataclass(frozen=True)
class PeopleFaultScore:
    """One of people's faults: how much of it the traced faults found.

    Attributes
    ----------
    fault_id : int
    name : str
    n_samples : int
        The section's samples it crosses.
    recall : float
        The fraction of them with a traced fault sample within the tolerance, in [0, 1].
    matches : tuple of int
        The traced faults that match it (:class:`FaultScoringOptions`), by id.
    """

    fault_id: int
    name: str
    n_samples: int
    recall: float
    matches: tuple


@dataclass(frozen=True)
class TracedFaultScore:
    """One traced fault: how much of it people drew.

    Attributes
    ----------
    fault_id : int
    n_samples : int
        The section's samples it crosses.
    precision : float
        The fraction of them with a people's fault sample within the tolerance, in [0, 1].
    confidence : float
        Its confidence as given (NaN when none).
    matches : tuple of int
        People's faults it matches, by id.
    """

    fault_id: int
    n_samples: int
    precision: float
    confidence: float
    matches: tuple


@dataclass(frozen=True)
class FaultPair:
    """A person's fault and a traced fault within the tolerance of each other somewhere.

    Attributes
    ----------
    people_id, traced_id : int
    people_near : float
        The fraction of the person's fault samples within the tolerance of the traced fault's, in [0, 1].
    traced_near : float
        The fraction of the traced fault's samples within the tolerance of the person's fault's, in [0, 1].
    matched : bool
        Either fraction reaches ``match_fraction``.
    """

    people_id: int
    traced_id: int
    people_near: float
    traced_near: float
    matched: bool


@dataclass(frozen=True, eq=False)
class PrecisionRecallCurve:
    """Precision and recall as the traced faults are added from the most confident down.

    Each step takes every fault whose confidence is at least the step's (faults of equal confidence enter together;
    faults without one enter last, together); precision and recall are those of all faults taken so far.

    Attributes
    ----------
    confidence : (k,) float64 ndarray
        The step's confidence, decreasing (NaN for the step of the faults without one).
    fault_ids : tuple of tuple of int
        The faults that enter at each step.
    n_faults : (k,) int64 ndarray
        Faults taken up to each step.
    precision, recall : (k,) float64 ndarray
        In [0, 1]; the last step's are the line's.
    average_precision : float
        :math:`\\sum_k (R_k - R_{k-1}) P_k` with :math:`R_0 = 0` (no interpolation), in [0, 1]; 0 without faults.
    """

    confidence: np.ndarray
    fault_ids: tuple
    n_faults: np.ndarray
    precision: np.ndarray
    recall: np.ndarray
    average_precision: float


@dataclass(frozen=True, eq=False)
class FaultLineScores:
    """Result of :func:`score_fault_line`.

    Attributes
    ----------
    precision, recall, f1 : float
        Of all traced faults against all people's faults, in [0, 1] (module notes).
    tolerance : float
        Samples.
    n_traced, n_people : int
        Fault samples of each drawing (each sample once).
    people : tuple of PeopleFaultScore
        Per person's fault, by id.
    traced : tuple of TracedFaultScore
        Per traced fault, by id.
    pairs : tuple of FaultPair
        Every pair of faults within the tolerance of each other somewhere, matched or not.
    curve : PrecisionRecallCurve
        Over the traced faults' confidence (over their ids, increasing, when none was given).
    """

    precision: float
    recall: float
    f1: float
    tolerance: float
    n_traced: int
    n_people: int
    people: tuple
    traced: tuple
    pairs: tuple
    curve: PrecisionRecallCurve


def tolerant_scores(traced, people, tolerance: float = 3.0, *, border: int = 0) -> tuple:
    """Tolerant precision, recall and F1 of one fault mask against another (the module notes' definition): the one
    computation of the project's fault scores (:func:`seismo3d.seismic.evaluate_faults` calls it).

    Parameters
    ----------
    traced, people : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) array_like of bool
        Fault samples of the traced faults and of people's (or of a generator's labels), one shape.
    tolerance : float
        Samples (Euclidean, index space).
    border : int
        Samples within ``border`` of the first and last sample of the last axis are left out of both fractions
        (they still count as the other mask's neighbours); 0 scores every sample.

    Returns
    -------
    (float, float, float)
        Precision, recall and F1, in [0, 1]; all 0 when either mask is empty, and a fraction is 0 when ``border``
        leaves none of its samples.

    Raises
    ------
    InputError
        Shapes differ, or ``tolerance`` or ``border`` < 0.

    Notes
    -----
    ``fault_scores.tolerant_scores`` of the project's tools, line for line when ``border`` is 0.
    """
    pred, ref = np.asarray(traced, dtype=bool), np.asarray(people, dtype=bool)
    if pred.shape != ref.shape:
        raise InputError(f"traced {pred.shape} and people {ref.shape} must have one shape")
    tol = check_positive(tolerance, "tolerance", allow_zero=True)
    border = int(check_positive(border, "border", allow_zero=True))
    if not pred.any() or not ref.any():
        return 0.0, 0.0, 0.0
    valid = np.ones(pred.shape, dtype=bool)
    if border:
        valid[..., :border] = False
        valid[..., pred.shape[-1] - border:] = False
    scored_pred, scored_ref = pred & valid, ref & valid
    p = float((ndi.distance_transform_edt(~ref)[scored_pred] <= tol).mean()) if scored_pred.any() else 0.0
    r = float((ndi.distance_transform_edt(~pred)[scored_ref] <= tol).mean()) if scored_ref.any() else 0.0
    return p, r, (2 * p * r / (p + r) if p + r else 0.0)


def _near(mask: np.ndarray, tol: float):
    """A function telling, for (m, 2) sample indices, which lie within ``tol`` of ``mask``'s samples: the distance
    transform of a window around them (wide enough that every sample outside it is farther)."""
    t, k = np.nonzero(mask)
    if t.size == 0:
        return lambda q: np.zeros(len(q), dtype=bool)
    pad = int(math.floor(tol)) + 1
    lo = np.maximum([t.min() - pad, k.min() - pad], 0)
    hi = np.minimum([t.max() + pad + 1, k.max() + pad + 1], mask.shape)
    dist = ndi.distance_transform_edt(~mask[lo[0]:hi[0], lo[1]:hi[1]])

    def near(q: np.ndarray) -> np.ndarray:
        inside = np.all((q >= lo) & (q < hi), axis=1)
        out = np.zeros(len(q), dtype=bool)
        out[inside] = dist[q[inside, 0] - lo[0], q[inside, 1] - lo[1]] <= tol
        return out

    return near


def _samples(mask: np.ndarray) -> np.ndarray:
    return np.argwhere(mask)


def _steps(ids, confidence: dict) -> list:
    """(confidence, fault ids) per step of the curve: decreasing confidence, ties together, faults without one last
    (all together); without any confidence, one fault per step by id."""
    if not confidence:
        return [(float("nan"), (i,)) for i in ids]
    conf = {i: float(confidence.get(i, np.nan)) for i in ids}
    known = sorted({c for c in conf.values() if np.isfinite(c)}, reverse=True)
    steps = [(c, tuple(i for i in ids if conf[i] == c)) for c in known]
    unknown = tuple(i for i in ids if not np.isfinite(conf[i]))
    return steps + ([(float("nan"), unknown)] if unknown else [])


def _curve(traced_masks: dict, people_mask: np.ndarray, steps: list, tol: float) -> PrecisionRecallCurve:
    """The precision-recall curve over ``steps`` (:class:`PrecisionRecallCurve`)."""
    union = np.zeros(people_mask.shape, dtype=bool)
    precision, recall, counts = [], [], []
    for _, members in steps:
        for i in members:
            union |= traced_masks[i]
        p, r, _ = tolerant_scores(union, people_mask, tol)
        precision.append(p)
        recall.append(r)
        counts.append((counts[-1] if counts else 0) + len(members))
    p, r = np.asarray(precision, dtype=np.float64), np.asarray(recall, dtype=np.float64)
    ap = float(np.sum(np.diff(np.concatenate([[0.0], r])) * p)) if r.size else 0.0  # ref. [2]
    return PrecisionRecallCurve(np.asarray([c for c, _ in steps], dtype=np.float64), tuple(m for _, m in steps),
                                np.asarray(counts, dtype=np.int64), p, r, ap)


def score_fault_line(traced: SectionFaults, people: SectionFaults, *, confidence=None,
                     options: FaultScoringOptions | None = None) -> FaultLineScores:
    """Score traced faults against people's faults on one seismic line (the definition of the module notes).

    Parameters
    ----------
    traced : SectionFaults
        The traced faults on the section (e.g. ``fault_points.csv`` placed by :meth:`SectionFaults.from_positions`).
    people : SectionFaults
        People's faults on the same section (:meth:`SectionFaults.from_sticks`, :meth:`SectionFaults.from_mask`).
    confidence : dict of int to float, optional
        A confidence per traced fault id (higher: more confident), for the precision-recall curve; faults without
        one (or NaN) enter it last. Default: none (the curve adds the faults by id).
    options : FaultScoringOptions, optional
        The tolerance (3 samples) and the share of a fault that makes a match (0.5).

    Returns
    -------
    FaultLineScores

    Raises
    ------
    InputError
        The two are not on sections of one shape.

    Examples
    --------
    >>> import numpy as np
    >>> people = np.zeros((20, 10), bool); people[5, :] = True              # a vertical fault at trace 5
    >>> traced = np.zeros((20, 10), bool); traced[7, :] = True; traced[15, :5] = True
    >>> s = score_fault_line(SectionFaults.from_mask(traced), SectionFaults.from_mask(people))
    >>> round(s.precision, 4), s.recall, [t.matches for t in s.traced]
    (0.6667, 1.0, [(1,), ()])
    """
    opt = options or FaultScoringOptions()
    tol = float(opt.tolerance)
    if tuple(traced.shape) != tuple(people.shape):
        raise InputError(f"traced faults are on a section of {tuple(traced.shape)} (traces, samples) and people's on "
                         f"one of {tuple(people.shape)}; place both on the same line")
    conf = {int(k): float(v) for k, v in (confidence or {}).items()}
    t_mask, p_mask = traced.mask(), people.mask()
    precision, recall, f1 = tolerant_scores(t_mask, p_mask, tol)
    t_masks = {int(i): traced.mask(i) for i in traced.ids}
    p_masks = {int(j): people.mask(j) for j in people.ids}
    near_traced, near_people = _near(t_mask, tol), _near(p_mask, tol)
    t_near = {i: _near(m, tol) for i, m in t_masks.items()}
    p_samples = {j: _samples(m) for j, m in p_masks.items()}
    pairs = []
    for j, pj in p_samples.items():
        near_j = _near(p_masks[j], tol)
        for i, mi in t_masks.items():
            people_near = float(t_near[i](pj).mean())
            if people_near == 0.0:
                continue  # nowhere within the tolerance of each other (the relation is symmetric)
            traced_near = float(near_j(_samples(mi)).mean())
            pairs.append(FaultPair(j, i, people_near, traced_near,
                                   max(people_near, traced_near) >= opt.match_fraction))
    matched = [pair for pair in pairs if pair.matched]
    people_scores = tuple(PeopleFaultScore(j, people.name(j), len(pj), float(near_traced(pj).mean()),
                                           tuple(p.traced_id for p in matched if p.people_id == j))
                          for j, pj in p_samples.items())
    traced_scores = tuple(TracedFaultScore(i, int(m.sum()), float(near_people(_samples(m)).mean()),
                                           conf.get(i, float("nan")),
                                           tuple(p.people_id for p in matched if p.traced_id == i))
                          for i, m in t_masks.items())
    curve = _curve(t_masks, p_mask, _steps(sorted(t_masks), conf), tol)
    return FaultLineScores(precision, recall, f1, tol, int(t_mask.sum()), int(p_mask.sum()), people_scores,
                           traced_scores, tuple(pairs), curve)
