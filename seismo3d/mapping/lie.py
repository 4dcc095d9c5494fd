"""SE(3) helpers of the mapping filter and graph: exponential and logarithm maps and the adjoint.

Tangent vectors are ``(rotation (rad), translation (m))``, rotation first, as in gtsam's Pose3 and the engine's
Gauss-Newton parametrisation (:mod:`seismo3d.registration`). The logarithm's translation part is the plain
translation of the relative transform (a "pose difference" on SO(3) x R^3), which is what the filter's and the
graph's small-perturbation models use: ``T exp(delta)`` with ``exp(delta) = [Exp(w), v]``.

References
----------
Sola, J., Deray, J., Atchuthan, D. (2018). A micro Lie theory for state estimation in robotics. arXiv:1812.01537.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

__all__ = ["exp_se3", "log_se3", "skew"]


def skew(v) -> np.ndarray:
    """(3, 3) cross-product matrix ``[v]x`` of a 3-vector."""
    x, y, z = np.asarray(v, dtype=np.float64)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def exp_se3(delta) -> np.ndarray:
    """(4, 4) transform ``[Exp(w), v]`` of a tangent vector ``delta = (w, v)`` (6,), radians and metres."""
    d = np.asarray(delta, dtype=np.float64).reshape(6)
    out = np.eye(4)
    out[:3, :3] = Rotation.from_rotvec(d[:3]).as_matrix()
    out[:3, 3] = d[3:]
    return out


def log_se3(transform) -> np.ndarray:
    """(6,) tangent vector ``(Log(R), t)`` of a (4, 4) rigid transform (inverse of :func:`exp_se3`)."""
    m = np.asarray(transform, dtype=np.float64)
    return np.concatenate([Rotation.from_matrix(m[:3, :3]).as_rotvec(), m[:3, 3]])
