"""The steps after the fault likelihood on an array in memory: the whole array as the one block of a run.

:class:`ArrayRun` implements the named steps of :class:`~seismo3d.seismic.faults.steps.SurfaceRun` on
numpy arrays, 2D or 3D; :func:`~seismo3d.seismic.faults.trace_faults` calls them through
:func:`~seismo3d.seismic.faults.steps.surface_cells`, the sequence the run by blocks
(:mod:`~seismo3d.seismic.faults.blocks.surface_blocks`) calls on each block with its halo.
"""

from __future__ import annotations

import numpy as np

from ..options import FaultTracingOptions
from ..surfaces.skins import image_cells
from ..surfaces.ridges import live_likelihood, ridges, thin_votes, without_dead_edges
from ..surfaces.voting import image_seeds, seed_votes

__all__ = ["ArrayRun"]


class ArrayRun:
    """The steps of :class:`~seismo3d.seismic.faults.steps.SurfaceRun` on arrays in memory.

    Parameters
    ----------
    likelihood, strike_deg, dip_deg : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Fault likelihood (set to 0 near dead samples, in place), strike and dip (degrees).
    near_dead : bool ndarray of the same shape, or None
        Samples near dead ones (:func:`~seismo3d.seismic.faults.surfaces.dead_samples.near_dead_samples`).
    opt : FaultTracingOptions
    progress : bool
        Progress of the voting over its seeds.

    Attributes
    ----------
    likelihood, strike_deg, dip_deg : ndarray
        As given (the likelihood 0 near dead samples after :meth:`ridges`).
    fault_votes : FaultVotes
        After :meth:`votes`: the votes (0 near dead samples) and the orientation of their best surfaces.
    thin : ndarray
        After :meth:`thresholds`; 0 below the lower threshold after :meth:`cells`.
    cell_arrays : tuple
        After :meth:`cells`: (points, values, strike_deg, dip_deg) of the cells.
    """

    def __init__(self, likelihood: np.ndarray, strike_deg: np.ndarray, dip_deg: np.ndarray, near_dead,
                 opt: FaultTracingOptions, *, progress: bool = False):
        self.likelihood, self.strike_deg, self.dip_deg = likelihood, strike_deg, dip_deg
        self.near_dead, self.opt, self.progress = near_dead, opt, progress
        self._ridges = None
        self.fault_votes = None
        self.thin = None
        self.cell_arrays = None

    def ridges(self) -> tuple[int, int]:
        """The likelihood set to 0 near dead samples (in place) and its ridges, the seed candidates.

        Returns
        -------
        (int, int)
            Live samples with a likelihood above 0.9, and live samples (for the saturation refusal).
        """
        high, live = live_likelihood(self.likelihood, self.near_dead)
        self._ridges = ridges(self.likelihood, self.strike_deg, self.dip_deg, self.opt.voting.seed_threshold)
        return high, live

    def seeds(self) -> tuple[np.ndarray, np.ndarray]:
        """The voting seeds of the ridges, strongest first
        (:func:`~seismo3d.seismic.faults.surfaces.voting.image_seeds`).

        Returns
        -------
        seeds : (k, 3) int64 ndarray
            Sample indices (a section's as (trace, 0, sample)).
        frames : (k, 3, 3) float64 ndarray
            Their fault frames.
        """
        seeds, frames = image_seeds(self._ridges, self.strike_deg, self.dip_deg, self.opt.voting)
        self._ridges = None
        return seeds, frames

    def votes(self, seeds: np.ndarray, frames: np.ndarray) -> None:
        """The seeds' optimal-surface votes over the whole array
        (:func:`~seismo3d.seismic.faults.surfaces.voting.seed_votes`), 0 near dead samples, in :attr:`fault_votes`.

        Parameters
        ----------
        seeds : (k, 3) int64 ndarray
        frames : (k, 3, 3) float64 ndarray
        """
        self.fault_votes = seed_votes(self.likelihood, seeds, frames, options=self.opt.voting, progress=self.progress)
        without_dead_edges(self.fault_votes.votes, self.near_dead)

    def thresholds(self) -> tuple[float, float]:
        """The votes thinned (:attr:`thin`) and their thresholds, by numpy and scikit-image
        (:meth:`~seismo3d.seismic.faults.FaultTracingOptions.thresholds`).

        Returns
        -------
        (float, float)
            Lower and upper thresholds.
        """
        self.thin = thin_votes(self.fault_votes.votes, self.fault_votes.strike_deg, self.fault_votes.dip_deg)
        return self.opt.thresholds(self.thin)

    def cells(self, lower: float) -> int:
        """The thinned votes below ``lower`` set to 0; the rest as cells in :attr:`cell_arrays`.

        Parameters
        ----------
        lower : float
            Lower threshold.

        Returns
        -------
        int
            Number of cells.
        """
        self.thin[self.thin < lower] = 0.0
        self.cell_arrays = image_cells(self.thin, self.fault_votes.strike_deg, self.fault_votes.dip_deg, lower)
        return int(len(self.cell_arrays[0]))
