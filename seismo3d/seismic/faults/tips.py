"""The tips of kept 2D faults trimmed back to where the fault likelihood holds (:func:`trimmed_tips`,
``FaultTracingOptions.tip_level``), after the evidence (:mod:`~seismo3d.seismic.faults.evidence`) kept them.

Optimal surface voting (:mod:`~seismo3d.seismic.faults.surfaces.voting`) casts each seed's votes along a path of
``2 * half_length_dip + 1`` samples, so a fault's votes, and the skin linked from them, run on past the fault's last
likely sample by up to ``half_length_dip`` samples (30 on a long section), fading: beyond its tip the skin follows the
votes of surfaces through samples where nothing is displaced."""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.ndimage import maximum_filter

from ...errors import InputError

__all__ = ["trimmed_tips"]


_POINT_ARRAYS = ("points", "likelihood", "strike_deg", "dip_deg", "normals")


def trimmed_tips(faults: list, throws: list, likelihood, level: float | None) -> tuple[list, list]:
    """The 2D faults with their ends cut back to the first point, from each end along the sample axis, whose fault
    likelihood (the largest within a trace either side: the faults lie on the ridges of the votes, which may pass a
    trace off the likelihood's own ridge) reaches ``level``; and their throws' per-point arrays cut alike.

    A fault whose likelihood reaches ``level`` nowhere is left whole (the evidence kept it, on its displacement).
    Its throw's values measured over the whole fault (median throw, step, fitness) are left as measured.

    Parameters
    ----------
    faults : list of Fault
        2D faults, points (trace, sample) into ``likelihood``.
    throws : list of FaultThrow
        Their throws, in the same order (per-point arrays in the order of the fault's points).
    likelihood : (n_traces, n_samples) array_like of float, or None
        The fault likelihood they were traced from (the network's probability); None: nothing is trimmed.
    level : float or None
        In [0, 1]; None: nothing is trimmed.

    Returns
    -------
    faults, throws : list
        In the input's order, with the same ids; the points of a trimmed fault (and its throw's per-point values)
        in the order of their samples.

    Raises
    ------
    InputError
        ``likelihood`` is not 2D, ``level`` lies outside [0, 1], or faults and throws differ in number.

    Examples
    --------
    >>> import numpy as np
    >>> from seismo3d.seismic.faults.result import Fault
    >>> lik = np.zeros((8, 40), np.float32); lik[4, 10:30] = 0.9
    >>> pts = np.stack([np.full(40, 4), np.arange(40)], axis=1)
    >>> f = Fault(1, pts, np.ones(40, np.float32), np.full(40, 90, np.float32), np.full(40, 80, np.float32),
    ...           np.tile(np.float32([1, 0]), (40, 1)))
    >>> g = trimmed_tips([f], [None], lik, 0.3)[0][0]
    >>> int(g.points[0, 1]), int(g.points[-1, 1])
    (10, 29)
    """
    if level is None or likelihood is None or not faults:
        return list(faults), list(throws)
    lik = np.asarray(likelihood)
    if lik.ndim != 2:
        raise InputError(f"trimmed_tips needs a 2D likelihood (n_traces, n_samples); got shape {lik.shape}")
    if not 0.0 <= float(level) <= 1.0:
        raise InputError(f"the tip level must be in [0, 1]; got {level!r}")
    if len(faults) != len(throws):
        raise InputError(f"{len(faults)} faults but {len(throws)} throws; pass the throws of these faults")
    near = maximum_filter(lik, size=(3, 1), mode="nearest")
    out_faults, out_throws = [], []
    for f, t in zip(faults, throws):
        n = len(f.points)
        order = np.argsort(f.points[:, -1], kind="stable")
        held = np.nonzero(near[f.points[order, 0], f.points[order, -1]] >= float(level))[0]
        if held.size == 0 or (held[0] == 0 and held[-1] == n - 1):
            out_faults.append(f)
            out_throws.append(t)
            continue
        take = order[held[0]:held[-1] + 1]
        out_faults.append(dataclasses.replace(f, **{name: getattr(f, name)[take] for name in _POINT_ARRAYS}))
        out_throws.append(t if t is None else dataclasses.replace(t, **{
            field.name: getattr(t, field.name)[take] for field in dataclasses.fields(t)
            if isinstance(getattr(t, field.name), np.ndarray) and getattr(t, field.name).shape[:1] == (n,)}))
    return out_faults, out_throws
