"""Evaluation against ground truth: fault detection scores, an interpreted fault line's coverage, the offsets of
people's horizons across traced faults (the true throw), horizon errors and sub-volume registration errors.

The fault measures are computed beside a plain peer any interpreter knows, a skeleton of 1 - semblance
(:func:`semblance_skeleton`, Marfurt 1998, thinned by scikit-image).

Each function compares a result with a reference (labelled fault samples, a fault line an interpreter sees, people's
or a generator's horizon picks, a known resampling transform) and returns a small frozen dataclass of the measures;
the benchmarks print them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from .._validation import check_positive
from ..errors import InputError
from ..geometry.transforms import apply_transform, as_transform, rotation_error_deg
from .fault_scoring import tolerant_scores

__all__ = ["FaultScores", "FaultLineCoverage", "HorizonErrors", "HorizonOffsets", "RegistrationErrors",
           "evaluate_faults", "fault_line_coverage", "horizon_errors", "horizon_offsets", "plain_semblance",
           "registration_errors", "semblance_skeleton"]


@dataclass(frozen=True)
class FaultScores:
    """Result of :func:`evaluate_faults`.

    Attributes
    ----------
    precision : float
        Fraction of predicted fault samples with a labelled fault sample within the tolerance, in [0, 1].
    recall : float
        Fraction of labelled fault samples with a predicted one within the tolerance, in [0, 1].
    """

    precision: float
    recall: float

    @property
    def f1(self) -> float:
        """The harmonic mean of precision and recall, 0 when both are 0."""
        total = self.precision + self.recall
        return 2.0 * self.precision * self.recall / total if total else 0.0


@dataclass(frozen=True)
class HorizonErrors:
    """Result of :func:`horizon_errors` (samples).

    Attributes
    ----------
    n : int
        Traces with a reference pick.
    coverage : float
        Fraction of them tracked (NaN when ``n`` is 0).
    median_abs : float
        Median absolute error over the tracked ones, samples (NaN when none).
    within_2, within_5 : float
        Fraction of the ``n`` traces tracked within 2 and 5 samples; untracked traces count as failures.
    """

    n: int
    coverage: float
    median_abs: float
    within_2: float
    within_5: float


@dataclass(frozen=True, eq=False)
class RegistrationErrors:
    """Result of :func:`registration_errors`.

    Attributes
    ----------
    rotation_deg : float
        Angle of the rotation between the rotational parts of the estimate and the truth, degrees.
    scale_pct : (3,) float64 ndarray
        Relative error of each moving axis's scale, %.
    max_scale_pct : float
        The largest of them, %.
    centre_error : float
        Distance between the fixed positions the two transforms give the moving volume's centre, fixed index units
        (traces and samples).
    corner_error : float
        The largest such distance over the moving volume's 8 corner samples, fixed index units: it bounds the error
        of every moving sample's position.
    """

    rotation_deg: float
    scale_pct: np.ndarray
    max_scale_pct: float
    centre_error: float
    corner_error: float


def evaluate_faults(thin_mask, labels, *, tolerance=3.0, border=0) -> FaultScores:
    """Precision and recall of thinned faults against labelled fault samples: the tolerant scores of
    :func:`~seismo3d.seismic.fault_scoring.tolerant_scores` (the project's one fault scoring), on a label image.

    A predicted sample is correct when a labelled sample lies within ``tolerance`` samples of it (Euclidean
    distance in index space, from :func:`scipy.ndimage.distance_transform_edt`); recall is the fraction of labelled
    samples with a predicted sample within ``tolerance``.

    Parameters
    ----------
    thin_mask : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like of bool
        Predicted fault samples (e.g. ``thin_faults(...) > 0``).
    labels : array_like of int, same shape
        Ground truth: > 0 on fault samples.
    tolerance : float, optional
        Distance in samples within which a prediction matches; the default, 3 samples, is the tolerance of every fault
        score the project reports (``seismo3d evaluate``, :func:`seismo3d.seismic.fault_scoring.tolerant_scores`).
    border : int, optional
        Samples within ``border`` of the top or bottom of the sample axis are left out of both scores. The default 0
        scores everything: the likelihood stays valid up to the top and bottom (the windows along dip are one-sided
        and clipped there), and on the 128^3 synthetic cubes leaving 5 samples out changes precision and recall of
        the linked faults by at most 0.012, so there is no reason to hide the edges.

    Returns
    -------
    FaultScores
        ``precision`` and ``recall`` in [0, 1]; precision is 0 when nothing is predicted, recall is 1 when there are
        no labels (left by ``border``).

    Raises
    ------
    InputError
        If the shapes differ.
    """
    pred = np.asarray(thin_mask).astype(bool)
    lab = np.asarray(labels) > 0
    if pred.shape != lab.shape:
        raise InputError(f"thin_mask {pred.shape} and labels {lab.shape} must have the same shape")
    precision, recall, _ = tolerant_scores(pred, lab, tolerance, border=border)
    border = int(border)
    if not lab[..., border:max(lab.shape[-1] - border, 0)].any():  # nothing to find: nothing missed
        recall = 1.0
    return FaultScores(precision=precision, recall=recall)


@dataclass(frozen=True)
class FaultLineCoverage:
    """Result of :func:`fault_line_coverage`.

    Attributes
    ----------
    covered : float
        Fraction of the line's samples with a point of any fault within the tolerance, in [0, 1].
    one_fault : float
        The largest fraction of the line's samples that one fault id holds within the tolerance, in [0, 1].
    fault_id : int
        That fault's id (0: no fault near the line).
    n_faults : int
        Number of fault ids with a point within the tolerance of the line.
    """

    covered: float
    one_fault: float
    fault_id: int
    n_faults: int


def fault_line_coverage(labels, line, *, tolerance=10.0) -> FaultLineCoverage:
    """How much of a fault line that an interpreter sees on a section the traced faults follow, and whether one
    fault follows it or several pieces do.

    The line runs through its vertices (trace, sample), straight between them, one point per sample from the first
    vertex's sample to the last's; a line sample is covered by a fault whose points lie on that sample within
    ``tolerance`` traces of the line.

    Parameters
    ----------
    labels : (n_traces, n_samples) array_like of int
        Fault ids of a section (:func:`~seismo3d.seismic.fault_labels`), 0 off the faults.
    line : (k, 2) array_like of float, k >= 2
        Vertices (trace index, sample index) of the interpreted fault, samples increasing.
    tolerance : float, optional
        Largest distance along the section between the line and a fault point on the same sample, traces.

    Returns
    -------
    FaultLineCoverage
        Fractions in [0, 1] of the line's samples; 0 where the line lies outside the section.

    Raises
    ------
    InputError
        ``labels`` is not 2D, ``line`` is not (k, 2) with k >= 2 and samples increasing, or ``tolerance`` < 0.
    """
    lab = np.asarray(labels)
    vertices = np.asarray(line, dtype=np.float64)
    if lab.ndim != 2:
        raise InputError(f"labels must be a section's (n_traces, n_samples) fault ids; got shape {lab.shape}")
    if vertices.ndim != 2 or vertices.shape[0] < 2 or vertices.shape[1] != 2 or np.any(np.diff(vertices[:, 1]) <= 0):
        raise InputError("line must be (k, 2) vertices (trace, sample), k >= 2, samples increasing; got "
                         f"{vertices.tolist()!r}")
    tolerance = check_positive(tolerance, "tolerance", allow_zero=True)
    samples = np.arange(int(np.ceil(vertices[0, 1])), int(np.floor(vertices[-1, 1])) + 1)
    traces = np.interp(samples, vertices[:, 1], vertices[:, 0])
    counts: dict = {}
    covered = 0
    for k, x in zip(samples, traces):
        if not 0 <= k < lab.shape[1]:
            continue
        lo, hi = max(int(np.ceil(x - tolerance)), 0), min(int(np.floor(x + tolerance)), lab.shape[0] - 1)
        ids = set(lab[lo:hi + 1, k].tolist()) - {0} if lo <= hi else set()
        covered += bool(ids)
        for fid in ids:
            counts[fid] = counts.get(fid, 0) + 1
    n = max(samples.size, 1)
    fid = max(counts, key=counts.get) if counts else 0
    return FaultLineCoverage(covered=covered / n, one_fault=counts.get(fid, 0) / n, fault_id=int(fid),
                             n_faults=len(counts))


@dataclass(frozen=True)
class HorizonOffsets:
    """Result of :func:`horizon_offsets`: one row per crossing of a fault and a horizon.

    Attributes
    ----------
    fault_id : (m,) int64 ndarray
        The fault's id.
    horizon : (m,) int64 ndarray
        The horizon's index (row of ``horizons``).
    trace, sample : (m,) float64 ndarray
        Where the fault crosses the horizon: the fault's trace index there and the sample midway between the
        horizon's two sides.
    offset : (m,) float64 ndarray
        The horizon's vertical offset across the fault, samples: its depth on the hanging-wall side less its depth
        on the footwall side, each side extrapolated to the fault's trace; positive when the hanging wall moved down
        (the sign convention of :class:`~seismo3d.seismic.FaultThrow`).
    point : (m,) int64 ndarray
        Index (into ``points``) of the fault point nearest the crossing, where a measured throw is read.
    """

    fault_id: np.ndarray
    horizon: np.ndarray
    trace: np.ndarray
    sample: np.ndarray
    offset: np.ndarray
    point: np.ndarray

    def __len__(self) -> int:
        return int(self.fault_id.size)


def horizon_offsets(points, fault_ids, hanging_wall, horizons, *, near=3, far=12, tolerance=2.0) -> HorizonOffsets:
    """The offsets of picked horizons across the faults of a section: the true throw where a fault cuts a horizon.

    At each fault point (trace ``x``, sample ``t``), the fault's zone is the traces of its points within 1 sample of
    ``t`` (every strand). Each side's horizon picks ``near..far`` traces beyond the zone's edge are fitted by a line
    (least squares over the traces with a pick, at least half of them) and extrapolated to ``x``: the horizon's
    depth on that side at the fault, free of the horizon's own dip. The fault crosses the horizon at the point whose
    sample is nearest the middle of the two sides' depths, if within half their difference plus ``tolerance``; the
    offset there is the hanging-wall side's depth less the footwall side's.

    Parameters
    ----------
    points : (n, 2) array_like of float
        Fault points (trace index, sample index) of one section, as ``fault_points.csv`` of ``seismo3d faults``.
    fault_ids : (n,) array_like of int
        The fault of each point.
    hanging_wall : mapping of int to {+1, -1}
        For each fault id, the side of its hanging wall: +1 toward increasing trace index (a fault dipping toward
        increasing trace), -1 toward decreasing trace. Faults missing from it are skipped.
    horizons : (k, n_traces) array_like of float
        People's horizon picks, samples per trace, NaN where absent.
    near, far : int, optional
        Nearest and farthest traces beyond the fault zone's edge whose picks give each side's depth.
    tolerance : float, optional
        Samples beyond the two sides' depths within which a fault point counts as crossing the horizon.

    Returns
    -------
    HorizonOffsets
        One row per (fault, horizon) crossing, ordered by fault id then horizon; empty when none.

    Raises
    ------
    InputError
        ``points`` is not (n, 2), ``fault_ids`` not (n,), ``horizons`` not 2D, ``1 <= near <= far`` fails or
        ``tolerance`` < 0.

    Notes
    -----
    A second fault within ``far`` traces of the zone adds its offset to the one measured. Offsets are in the
    picks' own resolution: a horizon smoothed over a fault by its interpreter shows its throw smeared over the side
    traces (its line fit then holds part of the throw).
    """
    pts = np.asarray(points, dtype=np.float64)
    ids = np.asarray(fault_ids)
    picks = np.asarray(horizons, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InputError(f"points must be (n, 2) fault points (trace, sample); got shape {pts.shape}")
    if ids.shape != (pts.shape[0],):
        raise InputError(f"fault_ids must be one id per point, shape ({pts.shape[0]},); got shape {ids.shape}")
    if picks.ndim != 2:
        raise InputError(f"horizons must be (k, n_traces) picks in samples; got shape {picks.shape}")
    near, far = int(near), int(far)
    if not 1 <= near <= far:
        raise InputError(f"near and far must satisfy 1 <= near <= far traces; got near={near}, far={far}")
    tolerance = check_positive(tolerance, "tolerance", allow_zero=True)
    n_traces = picks.shape[1]
    d = np.arange(near, far + 1, dtype=np.float64)
    rows: list = []
    for fid in np.unique(ids):
        if int(fid) not in hanging_wall:
            continue
        hw = 1.0 if hanging_wall[int(fid)] > 0 else -1.0
        sel = np.nonzero(ids == fid)[0]
        x, t = pts[sel, 0], pts[sel, 1]
        lo, hi = _zone_edges(x, t)
        for k in range(picks.shape[0]):
            sides = [_side_depth(picks[k], edge, sign, d, x, n_traces) for edge, sign in ((lo, -1.0), (hi, 1.0))]
            left, right = sides
            mid = 0.5 * (left + right)
            gap = np.abs(t - mid) - 0.5 * np.abs(right - left)
            ok = np.isfinite(gap) & (gap <= tolerance)
            if not ok.any():
                continue
            i = int(np.argmin(np.where(ok, np.abs(t - mid), np.inf)))
            rows.append((int(fid), k, x[i], mid[i], hw * (right[i] - left[i]), int(sel[i])))
    cols = list(zip(*rows)) if rows else [()] * 6
    return HorizonOffsets(fault_id=np.asarray(cols[0], np.int64), horizon=np.asarray(cols[1], np.int64),
                          trace=np.asarray(cols[2], np.float64), sample=np.asarray(cols[3], np.float64),
                          offset=np.asarray(cols[4], np.float64), point=np.asarray(cols[5], np.int64))


def _zone_edges(x: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Smallest and largest trace of the fault's points within 1 sample of each point's sample."""
    rows = np.rint(t).astype(np.int64)
    r0 = rows.min()
    lo = np.full(rows.max() - r0 + 3, np.inf)
    hi = np.full(lo.size, -np.inf)
    for dr in (0, 1, 2):
        np.minimum.at(lo, rows - r0 + dr, x)
        np.maximum.at(hi, rows - r0 + dr, x)
    return lo[rows - r0 + 1], hi[rows - r0 + 1]


def _side_depth(pick: np.ndarray, edge: np.ndarray, sign: float, d: np.ndarray, x: np.ndarray,
                n_traces: int) -> np.ndarray:
    """Each point's horizon depth on one side (``sign`` -1: decreasing trace), the least-squares line through the
    picks ``d`` traces beyond ``edge`` evaluated at the point's trace ``x``; NaN with picks on under half of them."""
    xs = np.rint(edge[:, None] + sign * d[None, :])
    inside = (xs >= 0) & (xs <= n_traces - 1)
    h = np.where(inside, pick[np.clip(xs, 0, n_traces - 1).astype(np.int64)], np.nan)
    w = np.isfinite(h)
    cnt = w.sum(axis=1)
    xm = np.where(w, xs, 0.0).sum(axis=1) / np.maximum(cnt, 1)
    hm = np.where(w, h, 0.0).sum(axis=1) / np.maximum(cnt, 1)
    dx = np.where(w, xs - xm[:, None], 0.0)
    slope = (dx * np.where(w, h - hm[:, None], 0.0)).sum(axis=1) / np.maximum((dx * dx).sum(axis=1), 1e-12)
    depth = hm + slope * (x - xm)
    return np.where(cnt >= 0.5 * d.size, depth, np.nan)


def horizon_errors(times, reference) -> HorizonErrors:
    """Compare tracked horizon times with reference picks (e.g. an interpreter's), in samples.

    Parameters
    ----------
    times, reference : array_like of float, same shape
        Horizon times in samples; NaN (or negative, in ``reference``) where absent. Traces without a reference
        pick are not counted; traces with a reference pick but no tracked pick count as misses.

    Returns
    -------
    HorizonErrors
        ``n``, ``coverage``, ``median_abs``, ``within_2``, ``within_5`` (see :class:`HorizonErrors`).

    Raises
    ------
    InputError
        Shapes differ.
    """
    t = np.asarray(times, np.float64)
    r = np.asarray(reference, np.float64)
    if t.shape != r.shape:
        raise InputError(f"times {t.shape} and reference {r.shape} must have the same shape")
    ref_ok = np.isfinite(r) & (r >= 0)
    n = int(ref_ok.sum())
    err = np.abs(t[ref_ok] - r[ref_ok])
    tracked = np.isfinite(err)
    return HorizonErrors(
        n=n,
        coverage=float(tracked.mean()) if n else np.nan,
        median_abs=float(np.median(err[tracked])) if tracked.any() else np.nan,
        within_2=float(np.mean(np.where(tracked, err, np.inf) <= 2)) if n else np.nan,
        within_5=float(np.mean(np.where(tracked, err, np.inf) <= 5)) if n else np.nan,
    )


def registration_errors(estimate, truth, moving_shape) -> RegistrationErrors:
    """Errors of an estimated index-space transform against the true one: rotation, per-axis scale, centre position.

    Parameters
    ----------
    estimate, truth : (4, 4) array_like of float
        Moving-index to fixed-index transforms (e.g. ``VolumeRegistration.transform_index`` and the transform
        returned by :func:`seismo3d.data.resampled_pair`).
    moving_shape : tuple of 3 int
        Shape of the moving volume; the translation error is measured at its centre.

    Returns
    -------
    RegistrationErrors
        ``rotation_deg``, ``scale_pct``, ``max_scale_pct``, ``centre_error``, ``corner_error`` (see
        :class:`RegistrationErrors`).

    Raises
    ------
    InputError
        Malformed transforms or shape.
    """
    e = as_transform(estimate, "estimate", dims=(3,))
    g = as_transform(truth, "truth", dims=(3,))
    shape = np.asarray(moving_shape, dtype=np.float64)
    if shape.shape != (3,):
        raise InputError(f"moving_shape must be 3 ints; got {moving_shape!r}")
    pct = 100.0 * np.abs(np.linalg.norm(e[:3, :3], axis=0) / np.linalg.norm(g[:3, :3], axis=0) - 1.0)
    centre = ((shape - 1.0) / 2.0)[None]
    corners = np.array(np.meshgrid(*[[0.0, n - 1.0] for n in shape], indexing="ij")).reshape(3, -1).T
    return RegistrationErrors(
        rotation_deg=float(rotation_error_deg(e, g)),
        scale_pct=pct,
        max_scale_pct=float(pct.max()),
        centre_error=float(np.linalg.norm(apply_transform(e, centre) - apply_transform(g, centre))),
        corner_error=float(np.linalg.norm(apply_transform(e, corners) - apply_transform(g, corners), axis=1).max()),
    )


def plain_semblance(data, half_samples: int = 4) -> np.ndarray:
    """Semblance over 3 x 3 traces (3 in 2D) and ``2 * half_samples + 1`` flat samples: the plain peer's attribute.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, samples along the last axis.
    half_samples : int
        Half the window's length, samples.

    Returns
    -------
    semblance : float32 ndarray, same shape
        In [0, 1] (1 where the window holds no energy); edges by nearest padding (scipy's uniform filters).

    References
    ----------
    .. [1] K. J. Marfurt, R. L. Kirlin, S. L. Farmer and M. S. Bahorich, "3-D seismic attributes using a
       semblance-based coherency algorithm", Geophysics 63(4), 1150-1165, 1998, doi:10.1190/1.1444415.
    """
    f = np.asarray(data, dtype=np.float32)
    lateral = (3,) * (f.ndim - 1) + (1,)
    n_tr = 3 ** (f.ndim - 1)
    n = 2 * int(half_samples) + 1
    trace_sum = ndi.uniform_filter(f, size=lateral, mode="nearest") * n_tr
    energy_sum = ndi.uniform_filter(f * f, size=lateral, mode="nearest") * n_tr
    num = ndi.uniform_filter1d(trace_sum * trace_sum, n, axis=-1, mode="nearest")
    den = n_tr * ndi.uniform_filter1d(energy_sum, n, axis=-1, mode="nearest")
    return np.where(den > 0, num / np.maximum(den, 1e-30), 1.0).astype(np.float32)


def semblance_skeleton(section, threshold: float) -> np.ndarray:
    """The plain peer of the fault scores: 1 - :func:`plain_semblance` above ``threshold``, skeletonised.

    Parameters
    ----------
    section : (n_traces, n_samples) array_like
        A seismic section.
    threshold : float
        On 1 - semblance, in [0, 1] (the benchmarks take a quantile of it, the best single one over a survey).

    Returns
    -------
    (n_traces, n_samples) bool ndarray
        The 1-sample-wide skeleton (scikit-image's ``skeletonize``).
    """
    from skimage.morphology import skeletonize

    return skeletonize((1.0 - plain_semblance(section)) > threshold)
