"""The one result type every registration in seismo3d returns."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["RegistrationResult"]


@dataclass(frozen=True)
class RegistrationResult:
    """Outcome of a registration (ICP, fused ICP, RANSAC or a closed-form fit).

    Attributes
    ----------
    transform : (d+1, d+1) float64 ndarray
        Homogeneous transform mapping source coordinates into target coordinates.
    fitness : float
        Fraction of source points that have a correspondence within the final maximum correspondence distance
        (for RANSAC: the inlier fraction of the matches), in [0, 1].
    inlier_rmse : float
        Root-mean-square Euclidean distance between corresponding points over those inliers, in the points' unit.
    n_iterations : int
        Iterations run over all stages of the distance schedule.
    converged : bool
        True when the last update fell below the tolerance *and* the geometry constrains every degree of freedom
        (``degenerate`` is False).
    min_eigenvalue : float
        Smallest eigenvalue of the final normal matrix ``J^T W J / sum(W)``, computed in a frame centred on the
        target and scaled to unit RMS radius so that rotation, scale and translation columns are commensurate.
        Near zero means the data does not constrain some direction (e.g. a plane slides in its own plane).
    degenerate : bool
        True when ``min_eigenvalue`` is below the degeneracy threshold; a
        :class:`~seismo3d.errors.DegenerateGeometryWarning` was issued.
    info : dict
        Method-specific extras (e.g. ``n_feature_inliers``, ``energy``, per-stage iteration counts). ICP and fused
        ICP add ``tolerance_met``: the last update fell below the tolerance, whatever ``degenerate`` says (a caller
        with other evidence for the degenerate direction, such as feature matches, can judge the fit itself).
    """

    transform: np.ndarray
    fitness: float
    inlier_rmse: float
    n_iterations: int
    converged: bool
    min_eigenvalue: float = float("nan")
    degenerate: bool = False
    info: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """JSON-ready dict: ``transform`` as a nested list plus the scalar fields."""
        return {
            "transform": np.asarray(self.transform).tolist(),
            "fitness": float(self.fitness),
            "inlier_rmse": float(self.inlier_rmse),
            "n_iterations": int(self.n_iterations),
            "converged": bool(self.converged),
            "min_eigenvalue": float(self.min_eigenvalue),
            "degenerate": bool(self.degenerate),
        }
