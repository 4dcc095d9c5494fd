"""Scores of terrain results against ground truth: lineaments against known scarps, transforms against known
motions."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry import rotation_error_deg
from .lineaments import Lineaments

__all__ = ["LineamentEvaluation", "evaluate_lineaments", "TransformErrors", "transform_errors"]


@dataclass(frozen=True)
class LineamentEvaluation:
    """How detected lineaments match known scarps.

    Attributes
    ----------
    n_scarps : int
        Known scarps.
    n_found : int
        Scarps covered over at least ``coverage`` of their whole trace by lineaments lying on it with azimuth within
        the tolerance.
    n_found_visible : int
        The same over the middle two thirds of each trace, where a scarp of :func:`synthetic_scarp_dem` keeps at least
        half its largest offset (its cosine taper closes it towards the tips).
    n_lineaments : int
        Lineaments detected.
    n_false : int
        Lineaments whose middle is not within the distance tolerance of any scarp's trace with a strike within twice
        the azimuth tolerance.
    """

    n_scarps: int
    n_found: int
    n_found_visible: int
    n_lineaments: int
    n_false: int

    @property
    def recall(self) -> float:
        """n_found / n_scarps."""
        return self.n_found / self.n_scarps if self.n_scarps else float("nan")

    @property
    def recall_visible(self) -> float:
        """n_found_visible / n_scarps."""
        return self.n_found_visible / self.n_scarps if self.n_scarps else float("nan")


def _angle_diff(a, b):
    return np.abs((np.asarray(a) - b + 90.0) % 180.0 - 90.0)


def _pixel_azimuth(segments):
    """Compass azimuth in [0, 180) of (row0, col0, row1, col1) segments on a north-up square-pixel grid."""
    return np.mod(np.degrees(np.arctan2(segments[:, 3] - segments[:, 1], -(segments[:, 2] - segments[:, 0]))), 180)


def _coverage(segments, az, a, b, azimuth, distance_px, azimuth_deg):
    """Fraction of the trace a-b covered by segments lying on it (both ends within distance) with close azimuth."""
    length = np.linalg.norm(b - a)
    u = (b - a) / length
    n = np.array([-u[1], u[0]])
    p0, p1 = segments[:, :2] - a, segments[:, 2:] - a
    on = (np.abs(p0 @ n) <= distance_px) & (np.abs(p1 @ n) <= distance_px) & (_angle_diff(az, azimuth) <= azimuth_deg)
    t = np.sort(np.column_stack([p0 @ u, p1 @ u])[on], axis=1)
    covered, reach = 0.0, 0.0
    for lo, hi in sorted(map(tuple, np.clip(t, 0.0, length))):
        lo = max(lo, reach)
        if hi > lo:
            covered += hi - lo
            reach = hi
    return covered / length


def evaluate_lineaments(lineaments: Lineaments, scarps, *, azimuth_deg: float = 5.0, distance_px: float = 3.0,
                        coverage: float = 0.5) -> LineamentEvaluation:
    """Match lineaments to known scarps (on a north-up grid of square pixels).

    Parameters
    ----------
    lineaments : Lineaments
        Detected, pixel end points used.
    scarps : sequence
        Objects with ``row0, col0, row1, col1, azimuth_deg`` (e.g. :class:`seismo3d.data.terrain.Scarp`).
    azimuth_deg : float
        Largest azimuth difference of a lineament that finds a scarp, degrees.
    distance_px : float
        Largest distance of a finding lineament's ends from the scarp's line, pixels.
    coverage : float
        Fraction of the trace (or of its middle two thirds) that the finding lineaments must cover.

    Returns
    -------
    LineamentEvaluation
    """
    segs = lineaments.segments_px
    az = _pixel_azimuth(segs)
    found = visible = 0
    true_line = np.zeros(len(segs), bool)
    mids = 0.5 * (segs[:, :2] + segs[:, 2:])
    for s in scarps:
        a, b = np.array([s.row0, s.col0]), np.array([s.row1, s.col1])
        found += _coverage(segs, az, a, b, s.azimuth_deg, distance_px, azimuth_deg) >= coverage
        m = 0.5 * (a + b)
        visible += _coverage(segs, az, m + (a - m) * 2 / 3, m + (b - m) * 2 / 3, s.azimuth_deg, distance_px,
                             azimuth_deg) >= coverage
        length = np.linalg.norm(b - a)
        u = (b - a) / length
        q = mids - a
        near = (np.abs(q @ np.array([-u[1], u[0]])) <= distance_px) & (q @ u >= -distance_px) & \
               (q @ u <= length + distance_px)
        true_line |= near & (_angle_diff(az, s.azimuth_deg) <= 2 * azimuth_deg)
    return LineamentEvaluation(len(scarps), int(found), int(visible), len(segs), int(np.count_nonzero(~true_line)))


@dataclass(frozen=True)
class TransformErrors:
    """Errors of an estimated transform against the truth, over a set of points.

    Attributes
    ----------
    rotation_deg : float
        Angle of the rotation between the two (degrees).
    centroid : float
        Distance between the two images of the points' centroid (the points' unit).
    max_displacement : float
        Largest distance between the two images of any point (the points' unit).
    """

    rotation_deg: float
    centroid: float
    max_displacement: float


def transform_errors(estimate, truth, points) -> TransformErrors:
    """Rotation error and displacement errors of ``estimate`` against ``truth`` on ``points``.

    The translation part of a transform in large projected coordinates mixes with its rotation (a 0.01 degree
    rotation about the CRS origin is a 150 ft translation 849,000 ft away), so translation is measured where it
    matters: at the points.

    Parameters
    ----------
    estimate, truth : (4, 4) array_like
    points : (N, 3) array_like

    Returns
    -------
    TransformErrors
    """
    e = np.asarray(estimate, dtype=np.float64)
    t = np.asarray(truth, dtype=np.float64)
    p = np.asarray(points, dtype=np.float64)
    centre = p.mean(axis=0)
    # differences of the two images, computed about the centroid (no cancellation of large coordinates)
    d = (p - centre) @ (e[:3, :3] - t[:3, :3]).T
    offset = (e[:3, :3] - t[:3, :3]) @ centre + e[:3, 3] - t[:3, 3]
    return TransformErrors(rotation_error_deg(e, t), float(np.linalg.norm(offset)),
                           float(np.max(np.linalg.norm(d + offset, axis=1))))
