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
   displaced by ``control_shift`` samples along each fixed axis, both ways (data that look alike when shifted, such
   as flat layers or noise, fix no position).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import corner_distance, decompose_map, homogeneous_diag
from .options import VolumeOptions
from .refine import WAYS, PairCorrelation, refine

__all__ = ["Consistency", "consistency_check"]


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
    control = max(_correlation(final, _shifted(answer, axis, sign * opt.control_shift))
                  for axis in range(3) for sign in (-1.0, 1.0))
    dec = decompose_map(physical(answer))
    scales = np.r_[dec.moving_scales, dec.fixed_scales[:2]]
    reason = _reason(correlation, overlap, scales, (lead, disagreement, rotation), other, control, opt)
    return Consistency(answer, np.asarray(two_way, dtype=np.float64), one_way["forward"], one_way["backward"], lead,
                       correlation, overlap, disagreement, rotation, scale, other_distance, other_scale, other,
                       control, not reason, reason)


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


def _reason(correlation, overlap, scales, agreement, other, control, opt: VolumeOptions) -> str:
    """The first check that fails, in one line ('' when all pass)."""
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
        return (f"the result correlates {correlation:.3f}, hardly better than shifted by {opt.control_shift:g} "
                f"samples ({control:.3f}): the data do not fix the position (flat layers, noise, unrelated data)")
    return ""


def _samples(distance: float) -> str:
    """A corner distance for the reason line ('over 1000 samples' for a refinement that ran away)."""
    return "over 1000 samples" if distance > 1000 else f"{distance:.2f} samples"
