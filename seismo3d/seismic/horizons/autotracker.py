"""The plain amplitude autotracker: the peer of horizon tracking by registration.

The seeded autotracking of interpretation software (no registration), the peer of
:func:`~seismo3d.seismic.track_horizon` in the tests and benchmarks.
"""

from __future__ import annotations

from collections import deque

import numpy as np

from ..._validation import as_seismic, check_choice, check_int
from ...errors import InputError
from ..reflectors import POLARITIES, nearest_pick, reflector_picks
from .labelled import HorizonLabels
from .result import Horizon, as_seeds, check_live_seed

__all__ = ["autotrack"]


def autotrack(data, seed, *, polarity: str = "peak", window: int = 3) -> Horizon:
    """Plain amplitude autotracker: follow the same-polarity extremum trace by trace (the peer of
    :func:`~seismo3d.seismic.track_horizon`).

    From the seed, each neighbouring trace (4-neighbours in 3D, in breadth-first order) takes the extremum of
    ``polarity`` nearest to its neighbour's pick within ``+-window`` samples; a trace with none is left empty and
    the search does not continue through it. This is the seeded autotracking of interpretation software, without
    any registration.

    Parameters
    ----------
    data : xarray.DataArray or (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, zero-mean. Must be finite. A seismic DataArray as :func:`track_horizon` takes it, or a
        plain array.
    seed : (ndim,) array_like of float
        Seed pick, snapped to the nearest extremum within ``window`` samples: in the cube's own numbers for a
        DataArray (inline, crossline, time), in index space for a plain array.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        The event followed (see :func:`~seismo3d.seismic.reflector_picks`).
    window : int
        Search half-window, samples.

    Returns
    -------
    Horizon
        ``times`` float32 fractional samples (NaN where empty), ``confidence`` 1 where picked. For a DataArray
        ``data``: on its coordinates, times in its sample unit, as :func:`track_horizon` gives them.

    Raises
    ------
    InputError
        Bad ``data``, a seed outside the data, on a dead trace or with no extremum within ``window``.
    """
    labels = HorizonLabels.of(data, seed)
    if labels is not None:  # a labelled cube: tracked as its values, the horizon on its coordinates
        with labels.seed_errors():
            return labels.label(autotrack(labels.values, labels.seeds, polarity=polarity, window=window))
    check_choice(polarity, "polarity", POLARITIES)
    arr = as_seismic(data)
    seeds = as_seeds(seed, arr.shape)
    if len(seeds) != 1:
        raise InputError(f"autotrack takes one seed; got {len(seeds)}")
    window = check_int(window, "window", minimum=1)
    check_live_seed(arr, seeds[0])
    picks, offsets = reflector_picks(arr.reshape(-1, arr.shape[-1]), polarity=polarity)
    lat = arr.shape[:-1]
    times = np.full(lat, np.nan)

    def snap(k, t):
        return nearest_pick(picks, offsets, k, t, window)

    start = tuple(int(round(v)) for v in seeds[0][:-1])
    t0 = snap(int(np.ravel_multi_index(start, lat)), seeds[0][-1])
    if not np.isfinite(t0):
        raise InputError(f"seed {tuple(seeds[0])} has no {polarity} within {window} samples; move it onto the event")
    times[start] = t0
    queue = deque([start])
    steps = [(1,), (-1,)] if len(lat) == 1 else [(1, 0), (-1, 0), (0, 1), (0, -1)]
    while queue:
        p = queue.popleft()
        for d in steps:
            q = tuple(a + b for a, b in zip(p, d))
            if any(v < 0 or v >= s for v, s in zip(q, lat)) or np.isfinite(times[q]):
                continue
            t = snap(int(np.ravel_multi_index(q, lat)), times[p])
            if np.isfinite(t):
                times[q] = t
                queue.append(q)
    conf = np.where(np.isfinite(times), 1.0, np.nan)
    return Horizon(times.astype(np.float32), conf.astype(np.float32), polarity, seeds)
