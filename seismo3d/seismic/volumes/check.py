"""The consistency check before a registration is called converged.

A result is ``converged`` only when all of these hold, checked in this order (the first that fails is the reason):

1. **overlap**: the registered volumes share at least ``min_fraction`` of the smaller one;
2. **correlation**: the two-way correlation is at least ``min_correlation``;
3. **scales**: the bin scales of both volumes and the vertical scale lie within ``scale_range`` widened by a quarter;
4. **both ways agree**: MOVING registered onto FIXED (the correlation at the moving samples alone) and FIXED registered
   onto MOVING (at the fixed samples alone), each refined on its own from the result, map every corner of the
   moving volume within ``max_disagreement`` fixed samples of each other, with rotations and scales within
   ``max_rotation_disagreement`` and ``max_scale_disagreement``: each volume's samples support the same map;
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
        The two one-way registrations (both as moving index -> fixed index).
    disagreement : float
        Largest distance between the fixed positions the two give a corner of the moving volume, fixed samples.
    rotation_disagreement_deg : float
        Difference of their map rotations, degrees.
    scale_disagreement : float
        Largest relative difference of their per-axis scales (column norms of the index transforms).
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
    disagreement: float
    rotation_disagreement_deg: float
    scale_disagreement: float
    runner_up_correlation: float
    control_correlation: float
    converged: bool
    reason: str

    def to_dict(self) -> dict:
        """JSON-ready dict of the measures (not the two transforms)."""
        return {
            "disagreement": float(self.disagreement),
            "rotation_disagreement_deg": float(self.rotation_disagreement_deg),
            "scale_disagreement": float(self.scale_disagreement),
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

    # MOVING onto FIXED and FIXED onto MOVING, each way's correlation alone, refined from the result
    forward, backward = (refine(PairCorrelation(final.fixed, final.moving, final.reparam, opt.n_points, ways=(way,)),
                                t_index, max_iterations=opt.max_iterations, tolerance=opt.tolerance).transform
                         for way in ("forward", "backward"))
    disagreement = corner_distance(forward, backward, final.moving.shape)
    rotation = abs((decompose_map(physical(forward)).rotation_deg - decompose_map(physical(backward)).rotation_deg
                    + 180.0) % 360.0 - 180.0)
    scale = float(np.max(np.abs(np.linalg.norm(forward[:3, :3], axis=0) / np.linalg.norm(backward[:3, :3], axis=0)
                                - 1.0)))
    # the other optimum, when distinct, and the shifted controls
    other = float("nan")
    if runner_up is not None and corner_distance(runner_up, t_index, final.moving.shape) > opt.max_disagreement:
        other = _correlation(final, runner_up)
    control = max(_correlation(final, _shifted(t_index, axis, sign * opt.control_shift))
                  for axis in range(3) for sign in (-1.0, 1.0))
    dec = decompose_map(physical(t_index))
    scales = np.r_[dec.moving_scales, dec.fixed_scales[:2]]
    reason = _reason(correlation, overlap, scales, (disagreement, rotation, scale), other, control, opt)
    return Consistency(forward, backward, disagreement, float(rotation), scale, other, control, not reason, reason)


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
    disagreement, rotation, scale = agreement
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
        return (f"MOVING onto FIXED and FIXED onto MOVING disagree: corners {disagreement:.2f} samples apart (max "
                f"{opt.max_disagreement:g}), rotations {rotation:.2f} deg apart, scales {100 * scale:.1f} %")
    if np.isfinite(other) and misfit > opt.control_ratio * (1.0 - other):
        return f"another map correlates almost as well ({other:.3f} against {correlation:.3f}): the match is ambiguous"
    if misfit > opt.control_ratio * (1.0 - control):
        return (f"the result correlates {correlation:.3f}, hardly better than shifted by {opt.control_shift:g} "
                f"samples ({control:.3f}): the data do not fix the position (flat layers, noise, unrelated data)")
    return ""
