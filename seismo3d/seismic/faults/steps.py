"""The steps of :func:`~seismo3d.seismic.faults.trace_faults` after the fault likelihood, each on a whole array or on
a block with the halo its operator needs.

The run in memory calls them on the whole array; the run by blocks
(:mod:`~seismo3d.seismic.faults.pipeline_blocks`) calls the same functions on each block read with its halo and keeps
the block's core. Halos (traces) are in :mod:`~seismo3d.seismic.faults.surface_plan`.
"""

from __future__ import annotations

import numpy as np

from .surfaces import check_fault_arrays, ridge_image

__all__ = ["live_likelihood", "ridges", "thin_votes", "without_dead_edges"]


def live_likelihood(likelihood: np.ndarray, near_dead, core=None) -> tuple[int, int]:
    """Set the likelihood next to dead samples to 0 (the edge of a dead zone is not a fault), in place; count the
    saturated and the live samples of ``core`` for :func:`~seismo3d.seismic.faults.checks.check_saturation`.

    Parameters
    ----------
    likelihood : float32 ndarray
        Fault likelihood of an array or of a block with its halo; modified.
    near_dead : bool ndarray of the same shape, or None
        Samples near dead ones (:func:`~seismo3d.seismic.faults.dead_samples.near_dead_samples`); None: none.
    core : tuple of slice, optional
        The block's core within ``likelihood`` (default: all of it).

    Returns
    -------
    (int, int)
        Live samples of the core with a likelihood above 0.9, and live samples of the core.
    """
    core = core or (slice(None),)
    if near_dead is not None:
        likelihood[near_dead] = 0.0
    values = likelihood[core] if near_dead is None else likelihood[core][~near_dead[core]]
    return int(np.count_nonzero(values > 0.9)), int(values.size)


def ridges(likelihood: np.ndarray, strike_deg: np.ndarray, dip_deg: np.ndarray, floor: float = 0.0) -> np.ndarray:
    """The ridges of the fault likelihood (non-maximum suppression across the fault, smoothed): the voting's seed
    candidates.

    Parameters
    ----------
    likelihood, strike_deg, dip_deg : ndarray, one shape, float32
        The (live) fault likelihood, its strike and dip in degrees.
    floor : float
        Ridge samples with a likelihood at or below it are left out (0): pass the voting's seed threshold, the
        only ridges used (:attr:`~seismo3d.seismic.faults.VotingOptions.seed_threshold`); the ridges above it are
        those of :func:`~seismo3d.seismic.thin_faults` with ``threshold=0``, computed on their neighbourhood only.

    Returns
    -------
    ndarray of the likelihood's shape, float32
        The likelihood on its ridge samples above ``floor``, 0 elsewhere. Halo: ``RIDGE_HALO`` traces.
    """
    fl, st, dp = check_fault_arrays(likelihood, strike_deg, dip_deg)
    return ridge_image(fl, st, dp, floor=float(floor))


def without_dead_edges(votes: np.ndarray, near_dead) -> np.ndarray:
    """The votes set to 0 near dead samples, in place: voting surfaces bridge gaps, but a fault is not drawn across
    dead traces. ``near_dead``: bool array of the votes' shape, or None (nothing to do)."""
    if near_dead is not None:
        votes[near_dead] = 0.0
    return votes


def thin_votes(votes: np.ndarray, strike_deg: np.ndarray, dip_deg: np.ndarray) -> np.ndarray:
    """The votes thinned to 1-sample-wide faults (no smoothing: the votes are smooth already).

    Halo: ``THIN_HALO`` traces. Arrays of one shape, float32; returns the thinned votes, float32 (0 off the faults).
    """
    fv, st, dp = check_fault_arrays(votes, strike_deg, dip_deg)
    return ridge_image(fv, st, dp, floor=0.0, sigma=0.0, dip_smoothing=0)

