"""The last stage: the answer taken from the way that leads, and the consistency check before it is called converged.

The two-way refinement (:mod:`~seismo3d.seismic.volumes.refine`) weighs both ways, and where one volume is aliased
(coarser bins, or resampled without a low-pass) the way that interpolates it is biased: its optimum alone lies up to
7.8 % off in scale on the Volve velocity pairs of ``benchmarks/volumes.py`` and pulls the two-way optimum up to
3.4 % off, while the other way's optimum alone stays within 0.4 %. So the answer is the two-way optimum refined again
on the correlation of **the way that leads it** alone (the larger weight of
:meth:`~seismo3d.seismic.volumes.refine.PairCorrelation.weights_for`: the way that interpolates the less aliased
volume), MOVING onto FIXED (at the moving samples) or FIXED onto MOVING (at the fixed samples). Swapping the
arguments swaps the ways and their weights, so the same physical way leads in either order.

The answer is ``converged`` only when all of these hold, checked in this order (the first that fails is the reason):

1. **overlap**: the registered volumes share at least ``min_fraction`` of the smaller one;
2. **correlation**: the two-way correlation is at least ``min_correlation``;
3. **scales**: the bin scales of both volumes and the vertical scale lie within ``scale_range`` widened by a quarter;
4. **one optimum for both estimates**: the leading way's optimum maps every corner of the moving volume within
   ``max_disagreement`` fixed samples of the two-way optimum, with map rotations within
   ``max_rotation_disagreement`` (the tolerances asked of an answer). A leading way that runs off, or climbs to
   another peak, from the two-way optimum fails here (the answer is then the two-way optimum); their scale
   difference, the biased way's pull, is reported (``scale_disagreement``). The other way is refined alone as well
   and its distance from the answer reported (``other_way_disagreement``): biased where it interpolates an aliased
   volume, it is not asked to agree;
5. **a unique optimum**: the misfit ``1 - correlation`` is at most ``control_ratio`` times that of the best other
   optimum the search led to, when it correlates nearly as well on the coarsest level (it is then refined to full
   resolution in the same way) and ends more than ``max_disagreement`` samples away (a pair that matches equally
   well in two places is not registered);
6. **better than a shifted control**: ... and at most ``control_ratio`` times the smallest misfit of the answer
   displaced along each fixed axis, both ways, by the fixed volume's correlation length along it
   (:func:`control_shifts`: where its autocorrelation, the mean trace left out, falls to ``control_level``; data
   that look alike when shifted, such as flat layers, fix no position). A fixed displacement of 2 samples refused
   right answers on laterally smooth data: on the Parihaka time slices of ``benchmarks/volumes.py --only
   any_grid`` (their mean trace 80 % of the variance, their lateral autocorrelation without it falling to 0.5 only
   3-20 traces away) the misfit was 0.71-0.93 of the controls' on 19 of 100 right answers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import corner_distance, decompose_map, homogeneous_diag
from .options import VolumeOptions
from .pyramid import Sampled, without_mean_trace
from .refine import WAYS, PairCorrelation, refine

__all__ = ["Consistency", "consistency_check", "control_shifts"]


@dataclass(frozen=True, eq=False)
class Consistency:
    """Result of :func:`consistency_check`.

    Attributes
    ----------
    transform : (4, 4) float64 ndarray
        The answer, moving index -> fixed index: the leading way's optimum, or the two-way optimum when the two do
        not share one peak (check 4; then not converged).
    two_way : (4, 4) float64 ndarray
        The two-way optimum it was refined from.
    moving_onto_fixed, fixed_onto_moving : (4, 4) float64 ndarray
        The two one-way registrations refined from the two-way optimum (both as moving index -> fixed index); one
        of them, the leading way's, is ``transform``.
    leading_way : {'forward', 'backward'}
        The way that leads: 'forward' (MOVING onto FIXED) or 'backward' (FIXED onto MOVING).
    correlation : float
        Two-way correlation at the answer (the mean of both ways; -1 for a way without overlap).
    overlap : float
        Fraction of the smaller volume the two share at the answer.
    disagreement : float
        Largest distance between the fixed positions the answer and the two-way optimum give a corner of the moving
        volume, fixed samples.
    rotation_disagreement_deg : float
        Difference of their map rotations, degrees.
    scale_disagreement : float
        Largest relative difference of their per-axis scales (column norms of the index transforms): reported.
    other_way_disagreement : float
        The corner distance of the other way's optimum from the answer (reported, not checked), fixed samples.
    other_way_scale_disagreement : float
        Its scale difference from the answer (reported, not checked).
    runner_up_correlation : float
        Correlation of the best other optimum at full resolution (NaN when every start led to the answer).
    control_correlation : float
        Largest correlation of the shifted controls.
    control_shifts : (3,) float64 ndarray
        Their displacements along the fixed inline, crossline and sample axes, fixed samples
        (:func:`control_shifts`).
    converged : bool
    reason : str
        Why not converged, in one line ('' when converged).
    """

    transform: np.ndarray
    two_way: np.ndarray
    moving_onto_fixed: np.ndarray
    fixed_onto_moving: np.ndarray
    leading_way: str
    correlation: float
    overlap: float
    disagreement: float
    rotation_disagreement_deg: float
    scale_disagreement: float
    other_way_disagreement: float
    other_way_scale_disagreement: float
    runner_up_correlation: float
    control_correlation: float
    control_shifts: np.ndarray
    converged: bool
    reason: str

    def to_dict(self) -> dict:
        """JSON-ready dict of the measures (not the transforms)."""
        return {
            "leading_way": self.leading_way,
            "disagreement": float(self.disagreement),
            "rotation_disagreement_deg": float(self.rotation_disagreement_deg),
            "scale_disagreement": float(self.scale_disagreement),
            "other_way_disagreement": float(self.other_way_disagreement),
            "other_way_scale_disagreement": float(self.other_way_scale_disagreement),
            "runner_up_correlation": None if np.isnan(self.runner_up_correlation) else
            float(self.runner_up_correlation),
            "control_correlation": float(self.control_correlation),
            "control_shifts": np.round(np.asarray(self.control_shifts, dtype=np.float64), 3).tolist(),
        }


def consistency_check(final: PairCorrelation, two_way, runner_up, spacings, opt: VolumeOptions) -> Consistency:
    """The answer and the checks of :mod:`seismo3d.seismic.volumes.check` on a full-resolution two-way optimum.

    Parameters
    ----------
    final : PairCorrelation
        The two-way correlation at full resolution.
    two_way : (4, 4) ndarray
        The two-way optimum, moving index -> fixed index.
    runner_up : (4, 4) ndarray or None
        The best other optimum of the search refined to full resolution, when it correlated nearly as well on the
        coarsest level (else None).
    spacings : (2, 3) array_like
        Fixed and moving spacings (the map rotation and scales are those of the physical coordinates).
    opt : VolumeOptions

    Returns
    -------
    Consistency
        The answer (``transform``), its correlation and overlap, the measures and the verdict.
    """
    sp_f, sp_m = (np.asarray(s, dtype=np.float64) for s in spacings)

    def physical(t):
        return homogeneous_diag(sp_f) @ t @ homogeneous_diag(1.0 / sp_m)

    # MOVING onto FIXED and FIXED onto MOVING, each way's correlation alone, refined from the two-way optimum
    one_way = {way: refine(PairCorrelation(final.fixed, final.moving, final.reparam, opt.n_points, ways=(way,)),
                           two_way, max_iterations=opt.max_iterations, tolerance=opt.tolerance).transform
               for way in WAYS}
    at_two_way = final.evaluate(final.params(two_way), jacobian=False)
    lead = WAYS[int(np.argmax(final.weights_for(1.0 - at_two_way.correlations)))]

    def apart(t, ref):  # corner distance, rotation difference (deg) and largest relative scale difference
        rotation = abs((decompose_map(physical(t)).rotation_deg - decompose_map(physical(ref)).rotation_deg
                        + 180.0) % 360.0 - 180.0)
        scale = float(np.max(np.abs(np.linalg.norm(t[:3, :3], axis=0) / np.linalg.norm(ref[:3, :3], axis=0)
                                    - 1.0)))
        return corner_distance(t, ref, final.moving.shape), float(rotation), scale

    disagreement, rotation, scale = apart(one_way[lead], two_way)
    # the leading way's optimum, unless it left the two-way optimum's peak (then the two-way optimum, not converged)
    shared = disagreement <= opt.max_disagreement and rotation <= opt.max_rotation_disagreement
    answer = one_way[lead] if shared else np.asarray(two_way, dtype=np.float64)
    ev = final.evaluate(final.params(answer), jacobian=False)
    correlation = _mean_correlation(ev.correlations)
    overlap = float(np.max(ev.overlaps))  # the larger way's: of the smaller volume
    other_distance, _, other_scale = apart(one_way[WAYS[1 - WAYS.index(lead)]], answer)
    # the other optimum, when distinct, and the shifted controls
    other = float("nan")
    if runner_up is not None and corner_distance(runner_up, answer, final.moving.shape) > opt.max_disagreement:
        other = _correlation(final, runner_up)
    shifts = control_shifts(final.fixed, level=opt.control_level, max_fraction=opt.max_control_shift)
    control = max(_correlation(final, _shifted(answer, axis, sign * shifts[axis]))
                  for axis in range(3) for sign in (-1.0, 1.0))
    dec = decompose_map(physical(answer))
    scales = np.r_[dec.moving_scales, dec.fixed_scales[:2]]
    reason = _reason(correlation, overlap, scales, (lead, disagreement, rotation), other, (control, shifts), opt)
    return Consistency(answer, np.asarray(two_way, dtype=np.float64), one_way["forward"], one_way["backward"], lead,
                       correlation, overlap, disagreement, rotation, scale, other_distance, other_scale, other,
                       control, shifts, not reason, reason)


def control_shifts(volume: Sampled, *, level: float, max_fraction: float) -> np.ndarray:
    """The displacements of the shifted controls: the correlation length of a volume along each of its axes.

    Along each axis, the normalised autocorrelation of the volume with its mean trace left out (the mean of each
    sample over the live traces: it is the same on every trace, so it correlates at any lateral displacement and
    fixes no map position; :func:`~seismo3d.seismic.volumes.pyramid.without_mean_trace`) is taken at lags of 1, 2,
    ... samples; the shift is the lag at which it first falls to ``level``, interpolated linearly between the two
    lags around it, at least 1 sample and at most ``max_fraction`` of the axis's length (where it never falls that
    far, as along flat layers, the largest: the answer displaced that far still correlates, and it is refused).

    Parameters
    ----------
    volume : Sampled
        The fixed volume at full resolution (normalised amplitudes, 0 on dead traces).
    level : float
        Autocorrelation, in (0, 1), at which the shift is taken.
    max_fraction : float
        Largest shift as a fraction of the axis's length (and at least 1 sample).

    Returns
    -------
    (3,) float64 ndarray
        Shifts along the inline, crossline and sample axes, samples of the volume.

    References
    ----------
    Yilmaz, O. (2001). Seismic Data Analysis. Society of Exploration Geophysicists. doi:10.1190/1.9781560801580
    (the autocorrelation and the width of its central lobe).
    """
    data = without_mean_trace(volume).data.astype(np.float64)
    out = np.empty(3)
    for axis in range(3):
        n = data.shape[axis]
        cap = max(1.0, max_fraction * n)
        out[axis], previous = cap, 1.0
        for lag in range(1, int(np.ceil(cap)) + 1):
            if lag >= n:
                break
            # einsum: no BLAS threads (a threaded dot is far slower on a loaded machine: refine.Evaluation.cost)
            head = np.take(data, np.arange(n - lag), axis=axis).ravel()
            tail = np.take(data, np.arange(lag, n), axis=axis).ravel()
            energy = np.sqrt(np.einsum("i,i->", head, head) * np.einsum("i,i->", tail, tail))
            ac = float(np.einsum("i,i->", head, tail) / energy) if energy > 0 else 0.0
            if ac <= level:  # between lag - 1 (autocorrelation ``previous``) and lag
                out[axis] = min(cap, lag - 1 + (previous - level) / max(previous - ac, 1e-12))
                break
            previous = ac
    return np.maximum(out, 1.0)


def _correlation(pair: PairCorrelation, t_index) -> float:
    """The two-way correlation at a transform (-1 for a way without overlap)."""
    return _mean_correlation(pair.evaluate(pair.params(t_index), jacobian=False).correlations)


def _mean_correlation(correlations) -> float:
    """The mean of the ways' correlations, -1 for a way without overlap."""
    return float(np.mean(np.where(np.isfinite(correlations), correlations, -1.0)))


def _shifted(t_index, axis: int, shift: float) -> np.ndarray:
    """A (4, 4) transform displaced by ``shift`` samples along fixed axis ``axis``."""
    d = np.eye(4)
    d[axis, 3] = shift
    return d @ t_index


def _reason(correlation, overlap, scales, agreement, other, controls, opt: VolumeOptions) -> str:
    """The first check that fails, in one line ('' when all pass)."""
    control, shifts = controls
    lo, hi = opt.scale_range[0] / 1.25, opt.scale_range[1] * 1.25
    lead, disagreement, rotation = agreement
    misfit = 1.0 - correlation
    if overlap < opt.min_fraction:
        return (f"the volumes share only {overlap:.0%} of the smaller one (min_fraction={opt.min_fraction:g}): no "
                "common volume; check that the two cubes cover the same area and time / depth range")
    if correlation < opt.min_correlation:
        return (f"the best map correlates only {correlation:.2f} (min_correlation={opt.min_correlation:g}): the "
                "volumes do not look alike; check that they image the same place")
    if np.any(scales < lo) or np.any(scales > hi):
        return (f"the scales {np.round(scales, 3).tolist()} leave the searched range {opt.scale_range}; check the "
                "spacings, or widen scale_range")
    if disagreement > opt.max_disagreement or rotation > opt.max_rotation_disagreement:
        name = "MOVING onto FIXED" if lead == "forward" else "FIXED onto MOVING"
        return (f"{name} alone, the way that leads, moves away from the two-way optimum: corners "
                f"{_samples(disagreement)} (max {opt.max_disagreement:g}), rotation {rotation:.2f} deg (max "
                f"{opt.max_rotation_disagreement:g}); the two estimates of the map do not share one optimum")
    if np.isfinite(other) and misfit > opt.control_ratio * (1.0 - other):
        return f"another map correlates almost as well ({other:.3f} against {correlation:.3f}): the match is ambiguous"
    if misfit > opt.control_ratio * (1.0 - control):
        return (f"the result correlates {correlation:.3f}, hardly better than shifted by "
                f"{'/'.join(f'{v:.1f}' for v in shifts)} samples along the fixed inline/crossline/sample axes "
                f"({control:.3f}): the data do not fix the position (flat layers, noise, unrelated data)")
    return ""


def _samples(distance: float) -> str:
    """A corner distance for the reason line ('over 1000 samples' for a refinement that ran away)."""
    return "over 1000 samples" if distance > 1000 else f"{distance:.2f} samples"
