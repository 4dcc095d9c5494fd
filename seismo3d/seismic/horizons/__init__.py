"""Horizon tracking: the horizon result, the tracking options, fault crossings, the least-squares and
dynamic-programming trackers, the cycle-skip cut, and the plain amplitude autotracker.

- :mod:`~seismo3d.seismic.horizons.result`: the horizon result (:class:`Horizon`), seeds, gap filling, text export.
- :mod:`~seismo3d.seismic.horizons.labelled`: a seismic DataArray (:func:`seismo3d.open`) in, seeds in its own
  numbers, the horizon out on its coordinates in its sample unit (:func:`track_horizon`, :func:`autotrack`).
- :mod:`~seismo3d.seismic.horizons.options`: :class:`TrackingOptions`.
- :mod:`~seismo3d.seismic.horizons.fault_crossings`: which faults a horizon step crosses and the jump there.
- :mod:`~seismo3d.seismic.horizons.fault_pairs`: the faults between the least-squares solve's pairs of traces: their
  jumps, and fault zones (a fault's strands) crossed once and left untracked.
- :mod:`~seismo3d.seismic.horizons.tracking`: :func:`track_horizon`; horizon tracking by registering neighbouring
  slices.
- :mod:`~seismo3d.seismic.horizons.lsq`: least-squares horizons from correlations of near and distant traces (the
  default method), the cycle-skip self-check.
- :mod:`~seismo3d.seismic.horizons.correlation`: correlation of trace windows pair by pair (lag search, confidence).
- :mod:`~seismo3d.seismic.horizons.dp`: dynamic programming over candidate picks along each line, swept over inlines
  and crosslines in a cube.
- :mod:`~seismo3d.seismic.horizons.cycle_cut`: regions a cycle off moved by a minimum cut.
- :mod:`~seismo3d.seismic.horizons.autotracker`: the plain amplitude autotracker (the peer).

The function :func:`~seismo3d.seismic.horizons.cycle_cut.cycle_cut` is not re-exported here: its name is its
module's.
"""

from .result import Horizon, as_seeds, check_live_seed, fill_horizon, snap_seeds, write_horizon_text
from .options import TrackingOptions
from .fault_crossings import FaultCrossings, footwall_normals, reliable_throw
from .dp import sample_at, window_ncc, dp_picks, line_slopes, reflector_period, settle_lone_departures
from .correlation import window_correlation, neighbour_confidence
from .cycle_cut import CycleCut, neighbour_cycle, binary_min_cut
from .lsq import (
    PairShifts, LsqHorizon, trace_pairs, pair_shifts, solve_horizon, cycle_skips, pair_agreement, lsq_horizon,
)
from .autotracker import autotrack
from .lateral_check import close_gaps, despike
from .tracking import track_horizon

__all__ = [
    "Horizon", "as_seeds", "check_live_seed", "fill_horizon", "snap_seeds", "write_horizon_text", "TrackingOptions",
    "FaultCrossings", "footwall_normals", "reliable_throw", "sample_at", "window_ncc", "dp_picks", "line_slopes",
    "reflector_period", "settle_lone_departures", "window_correlation", "neighbour_confidence", "CycleCut",
    "neighbour_cycle", "binary_min_cut", "PairShifts", "LsqHorizon", "trace_pairs", "pair_shifts", "solve_horizon",
    "cycle_skips", "pair_agreement", "lsq_horizon", "track_horizon", "despike", "close_gaps", "autotrack",
]
