"""Fault planes in index space: a plane's unit normal from its strike and dip and back (conventions of
:mod:`~seismo3d.seismic.faults.likelihood`)."""

from __future__ import annotations

import numpy as np

from ...errors import InputError

__all__ = ["fault_normals", "fault_strike_dip"]


def fault_strike_dip(normal) -> tuple[float, float]:
    """Strike and dip of a fault normal (the inverse of :func:`fault_normals`).

    Parameters
    ----------
    normal : (3,) or (2,) array_like of float
        A unit fault normal, (inline, xline, sample) or (trace, sample) components, of either sign.

    Returns
    -------
    strike_deg : float
        Degrees in [0, 360) (90 or 270 in 2D; module conventions).
    dip_deg : float
        Degrees in [0, 90].
    """
    n = np.asarray(normal, dtype=np.float64)
    if n[-1] < 0:
        n = -n
    dip = np.degrees(np.arccos(np.clip(n[-1], 0.0, 1.0)))
    if n.shape[0] == 2:
        strike = 90.0 if n[0] >= 0 else 270.0
    else:
        strike = np.degrees(np.arctan2(n[0], -n[1])) % 360.0
    return float(strike), float(dip)


def fault_normals(strike_deg, dip_deg, *, ndim: int = 3) -> np.ndarray:
    """Unit fault normals from strike and dip.

    Parameters
    ----------
    strike_deg, dip_deg : array_like of float
        Strike in degrees [0, 360) and dip in degrees (0, 90], same shape (module conventions, index space).
    ndim : {2, 3}, optional
        3 for cube normals (inline, xline, sample); 2 for section normals (trace, sample).

    Returns
    -------
    (*strike_deg.shape, ndim) float32 ndarray
        ``(sin(dip) sin(strike), -sin(dip) cos(strike), cos(dip))``, or its (trace, sample) components in 2D.

    Raises
    ------
    InputError
        If the shapes differ or ``ndim`` is not 2 or 3.
    """
    phi = np.radians(np.asarray(strike_deg, dtype=np.float64))
    theta = np.radians(np.asarray(dip_deg, dtype=np.float64))
    if phi.shape != theta.shape:
        raise InputError(f"strike_deg {phi.shape} and dip_deg {theta.shape} must have the same shape")
    if ndim not in (2, 3):
        raise InputError(f"ndim must be 2 or 3; got {ndim!r}")
    st = np.sin(theta)
    comps = [st * np.sin(phi), -st * np.cos(phi), np.cos(theta)]
    if ndim == 2:
        comps = [comps[0], comps[2]]
    return np.stack(comps, axis=-1).astype(np.float32)


# --------------------------------------------------------------------------------------------------------------------
