"""Horizons on a labelled cube: the horizon functions' way from a seismic ``xarray.DataArray`` (:func:`seismo3d.open`,
a segysak Dataset's variable) to the arrays their algorithms take, and back to a horizon on the cube's coordinates.

A DataArray cube is tracked as its values (a grid of a single inline or crossline as its 2D section), from seeds given
in the cube's own numbers (inline, crossline, time or depth; a line: its line number or trace label, time) converted
to index space (:func:`~seismo3d.seismic.io.cube.index_positions`); the horizon comes back with its times in the
cube's sample unit and its confidence, both DataArrays on the cube's lateral dimensions with its line numbers and
``cdp_x`` / ``cdp_y`` (:func:`~seismo3d.seismic.io.cube.on_lateral`).

References
----------
xarray, https://docs.xarray.dev; segysak (T. Hallam), https://segysak.readthedocs.io (dimensions ``iline``, ``xline``,
``twt`` / ``depth``, coordinates ``cdp_x`` / ``cdp_y``).
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from ..io.cube import CubeAxes, index_positions, is_data_array, line_values, on_lateral, samples_at, seismic_axes
from ...errors import SeedError
from .result import Horizon, dead_trace_error, no_pick_error

__all__ = ["HorizonLabels"]


@dataclass(frozen=True, eq=False)
class HorizonLabels:
    """A DataArray input of a horizon function: what is tracked and how the horizon gets the cube's labels back.

    Attributes
    ----------
    cube : xarray.DataArray
        The input cube or line.
    axes : CubeAxes
        Its axes (:func:`~seismo3d.seismic.io.cube.seismic_axes`).
    values : ndarray or dask.array.Array
        Its amplitudes as tracked (read whole by the tracker): (n_inlines, n_xlines, n_samples) or (n_traces,
        n_samples).
    seeds : (n_seeds, values.ndim) float64 ndarray
        The seeds in index space of ``values``.
    given : (n_seeds, cube.ndim) float64 ndarray
        The seeds as given, in the cube's own numbers.
    squeezed : int or None
        The lateral axis of length 1 taken out of a grid of one line.
    """

    cube: object
    axes: CubeAxes
    values: np.ndarray
    seeds: np.ndarray
    given: np.ndarray
    squeezed: int | None

    @classmethod
    def of(cls, data, seeds) -> HorizonLabels | None:
        """None for a plain array; the labels of a seismic DataArray and its seeds in index space.

        Raises
        ------
        InputError
            ``data`` is not a seismic DataArray (:func:`~seismo3d.seismic.io.cube.seismic_axes`), or a seed is not
            on the cube's lines or within its samples (:func:`~seismo3d.seismic.io.cube.index_positions`).
        """
        if not is_data_array(data):
            return None
        axes = seismic_axes(data)
        given = index_positions(data, axes, seeds, what="seed")
        values, squeezed = line_values(data, axes)
        index = given if squeezed is None else np.delete(given, squeezed, axis=1)
        return cls(data, axes, values, index, np.atleast_2d(np.asarray(seeds, dtype=np.float64)), squeezed)

    def label(self, horizon: Horizon) -> Horizon:
        """``horizon`` (tracked on :attr:`values`) on the cube's coordinates: times in its sample unit, confidence,
        seeds as given."""
        unit = self.axes.sample_unit
        times = on_lateral(samples_at(self.cube, self.axes, horizon.times), self.cube, self.axes,
                           squeezed=self.squeezed, name=self.axes.sample,
                           attrs={"units": unit, "polarity": horizon.polarity})
        confidence = on_lateral(horizon.confidence, self.cube, self.axes, squeezed=self.squeezed, name="confidence")
        return Horizon(times, confidence, horizon.polarity, self.given)

    def position(self, index) -> tuple:
        """An index position of :attr:`values` (lateral indices, fractional sample) in the cube's own numbers."""
        index = [float(v) for v in index]
        if self.squeezed is not None:
            index.insert(self.squeezed, 0.0)
        lateral = tuple(float(self.cube.coords[d].values[int(round(v))]) if d in self.cube.coords else float(round(v))
                        for d, v in zip(self.axes.lateral, index[:-1]))
        return (*lateral, float(samples_at(self.cube, self.axes, index[-1])))

    @contextmanager
    def seed_errors(self):
        """Re-raise a :class:`~seismo3d.errors.SeedError` of the tracker (index space) in the cube's own numbers."""
        try:
            yield
        except SeedError as exc:
            seed = self.position(exc.seed)
            nearest = None if exc.nearest is None else self.position(exc.nearest)
            if exc.window is None:
                raise dead_trace_error(seed, nearest) from None
            raise no_pick_error(seed, exc.window, nearest) from None
