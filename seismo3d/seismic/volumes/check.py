"""The consistency check before a registration is called converged.

A result is ``converged`` only when all of these hold, checked in this order (the first that fails is the reason):

1. **overlap**: the registered volumes share at least ``min_fraction`` of the smaller one;
2. **correlation**: the two-way correlation is at least ``min_correlation``;
3. **scales**: the bin scales of both volumes and the vertical scale lie within ``scale_range`` widened by a quarter;
4. **the leading way agrees**: the result is refined again from itself on the correlation of one way alone, the way
   that leads it (the larger weight of :meth:`~seismo3d.seismic.volumes.refine.PairCorrelation.weights_for` at the
   result: the way that interpolates the less aliased volume), MOVING onto FIXED (at the moving samples) or FIXED onto
   MOVING (at the fixed samples); it must map every corner of the moving volume within ``max_disagreement`` fixed
   samples of the result, with rotation and scales within ``max_rotation_disagreement`` and
   ``max_scale_disagreement``. A result the two-way cost reached between the two ways' optima, pulled off by the
   biased way, fails here. The other way is refined alone as well and its distance reported
   (``other_way_disagreement``): it is biased where it interpolates an aliased volume (up to 7.8 % in scale on the
   Volve pairs of ``benchmarks/volumes.py``), so it is not asked to agree;
5. **a unique optimum**: the misfit ``1 - correlation`` is at most ``control_ratio`` times that of the best other
   optimum the search led to, when it correlates nearly as well on the coarsest level (it is then refined to full
   resolution in the same way) and ends more than ``max_disagreement`` samples away (a pair that matches equally
   well in two places is not registered);
6. **better than a shifted control**: ... and at most ``control_ratio`` times the smallest misfit of the result
   displaced by ``control_shift`` samples along each fixed axis, both ways (data that look alike when shifted, such
   as flat layers or noise, fix no position).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import corner_distance, decompose_map, homogeneous_diag
from .options import VolumeOptions
from .refine import PairCorrelation, refine

__all__ = ["Consistency", "consistency_check"]


@dataclass(frozen=True, eq=False)
class Consistency:
    """Result of :func:`consistency_check`.

    Attributes
    ----------
    moving_onto_fixed, fixed_onto_moving : (4, 4) float64 ndarray
        The two one-way registrations refined from the result (both as moving index -> fixed index).
    leading_way : {'forward', 'backward'}
        The way that leads the result: 'forward' (MOVING onto FIXED) or 'backward' (FIXED onto MOVING).
    disagreement : float
        Largest distance between the fixed positions the leading way and the result give a corner of the moving
        volume, fixed samples.
    rotation_disagreement_deg : float
        Difference of their map rotations, degrees.
    scale_disagreement : float
        Largest relative difference of their per-axis scales (column norms of the index transforms).
    other_way_disagreement : float
        The same corner distance for the other way (reported, not checked), fixed samples.
    other_way_scale_disagreement : float
        The same scale difference for the other way (reported, not checked).
    runner_up_correlation : float
        Correlation of the best other optimum at full resolution (NaN when every start led to the result).
    control_correlation : float
        Largest correlation of the shifted controls.
    converged : bool
    reason : str
        Why not converged, in one line ('' when converged).
    """

    moving_onto_fixed: np.ndarray
    fixed_onto_moving: np.ndarray
    leading_way: str
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
        """JSON-ready dict of the measures (not the two transforms)."""
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


def consistency_check(final: PairCorrelation, t_index, correlation: float, overlap: float, runner_up, spacings,
                      opt: VolumeOptions) -> Consistency:
    """The checks of :mod:`seismo3d.seismic.volumes.check` on a full-resolution result.

    Parameters
    ----------
    final : PairCorrelation
        The two-way correlation at full resolution.
    t_index : (4, 4) ndarray
        The result, moving index -> fixed index.
    correlation, overlap : float
        Its two-way correlation, and the fraction of the smaller volume the two share.
    runner_up : (4, 4) ndarray or None
        The best other optimum of the search refined to full resolution, when it correlated nearly as well on the
        coarsest level (else None).
    spacings : (2, 3) array_like
        Fixed and moving spacings (the map rotation and scales are those of the physical coordinates).
    opt : VolumeOptions

    Returns
    -------
    Consistency
    """
    sp_f, sp_m = (np.asarray(s, dtype=np.float64) for s in spacings)

    def physical(t):
        return homogeneous_diag(sp_f) @ t @ homogeneous_diag(1.0 / sp_m)

    # MOVING onto FIXED and FIXED onto MOVING, each way's correlation alone, refined from the result; the way that
    # leads the result must stay on it
    ways = ("forward", "backward")
    one_way = {way: refine(PairCorrelation(final.fixed, final.moving, final.reparam, opt.n_points, ways=(way,)),
                           t_index, max_iterations=opt.max_iterations, tolerance=opt.tolerance).transform
               for way in ways}
    lead = ways[int(np.argmax(final.weights_for(1.0 - final.evaluate(final.params(t_index)).correlations)))]
    other_way = ways[1 - ways.index(lead)]

    def apart(t):  # corner distance, rotation difference (deg) and largest relative scale difference from the result
        rotation = abs((decompose_map(physical(t)).rotation_deg - decompose_map(physical(t_index)).rotation_deg
                        + 180.0) % 360.0 - 180.0)
        scale = float(np.max(np.abs(np.linalg.norm(t[:3, :3], axis=0) / np.linalg.norm(t_index[:3, :3], axis=0)
                                    - 1.0)))
        return corner_distance(t, t_index, final.moving.shape), float(rotation), scale

    disagreement, rotation, scale = apart(one_way[lead])
    other_distance, _, other_scale = apart(one_way[other_way])
    # the other optimum, when distinct, and the shifted controls
    other = float("nan")
    if runner_up is not None and corner_distance(runner_up, t_index, final.moving.shape) > opt.max_disagreement:
        other = _correlation(final, runner_up)
    control = max(_correlation(final, _shifted(t_index, axis, sign * opt.control_shift))
                  for axis in range(3) for sign in (-1.0, 1.0))
    dec = decompose_map(physical(t_index))
    scales = np.r_[dec.moving_scales, dec.fixed_scales[:2]]
    reason = _reason(correlation, overlap, scales, (lead, disagreement, rotation, scale), other, control, opt)
    return Consistency(one_way["forward"], one_way["backward"], lead, disagreement, rotation, scale, other_distance,
                       other_scale, other, control, not reason, reason)


def _correlation(pair: PairCorrelation, t_index) -> float:
    """The two-way correlation at a transform (-1 for a way without overlap)."""
    c = pair.evaluate(pair.params(t_index)).correlations
    return float(np.mean(np.where(np.isfinite(c), c, -1.0)))


def _shifted(t_index, axis: int, shift: float) -> np.ndarray:
    """A (4, 4) transform displaced by ``shift`` samples along fixed axis ``axis``."""
    d = np.eye(4)
    d[axis, 3] = shift
    return d @ t_index


def _reason(correlation, overlap, scales, agreement, other, control, opt: VolumeOptions) -> str:
    """The first check that fails, in one line ('' when all pass)."""
    lo, hi = opt.scale_range[0] / 1.25, opt.scale_range[1] * 1.25
    lead, disagreement, rotation, scale = agreement
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
    if (disagreement > opt.max_disagreement or rotation > opt.max_rotation_disagreement
            or scale > opt.max_scale_disagreement):
        name = "MOVING onto FIXED" if lead == "forward" else "FIXED onto MOVING"
        return (f"{name} alone, the way that leads the result, moves away from it: corners {disagreement:.2f} "
                f"samples (max {opt.max_disagreement:g}), rotation {rotation:.2f} deg (max "
                f"{opt.max_rotation_disagreement:g}), scales {100 * scale:.1f} % (max "
                f"{100 * opt.max_scale_disagreement:g} %)")
    if np.isfinite(other) and misfit > opt.control_ratio * (1.0 - other):
        return f"another map correlates almost as well ({other:.3f} against {correlation:.3f}): the match is ambiguous"
    if misfit > opt.control_ratio * (1.0 - control):
        return (f"the result correlates {correlation:.3f}, hardly better than shifted by {opt.control_shift:g} "
                f"samples ({control:.3f}): the data do not fix the position (flat layers, noise, unrelated data)")
    return ""
