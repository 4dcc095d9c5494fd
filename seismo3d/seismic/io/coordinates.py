"""Map coordinates of a survey: the CDP X/Y of the SEG-Y trace headers with their scalar, and the affine map of the
inline / crossline grid, fitted once and checked against every trace.

Every interpretation that leaves seismo3d in map coordinates (fault sticks, fault surfaces, horizon grids and points)
takes its X/Y from a :class:`SurveyCoordinates`: the header coordinates of the trace for a point on a trace, the
grid's :class:`GridMap` between traces. A file whose headers hold no coordinates (CDP X/Y and source X/Y zero on
every trace) falls back to inline / crossline units: X is the inline number and Y the crossline number, and
:attr:`SurveyCoordinates.unit` says so (``'inline/crossline'``), for every output to name.

References
----------
SEG-Y rev 1 (SEG Technical Standards Committee, 2002): trace header bytes 71-72 (coordinate scalar: positive
multiplies, negative divides, 0 means 1), 181-188 (CDP X, CDP Y), 73-80 (source X, Y); binary header bytes 3255-3256
(measurement system: 1 metres, 2 feet).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ...errors import InputError, Seismo3dWarning, SegyGeometryError

__all__ = ["GridMap", "SurveyCoordinates", "LINE_UNITS", "cube_coordinates", "fit_grid_map", "grid_spacing_from_cdp",
           "header_resolution", "survey_coordinates", "read_survey_coordinates"]

LINE_UNITS = "inline/crossline"  # the unit of X / Y when the headers hold no coordinates


@dataclass(frozen=True)
class GridMap:
    """The affine map from inline / crossline numbers to map X / Y: ``xy = origin + inline * inline_vector +
    crossline * crossline_vector``.

    Attributes
    ----------
    origin : (2,) float64 ndarray
        X, Y of inline 0, crossline 0 (an extrapolation; only the map matters), in :attr:`unit`.
    inline_vector, crossline_vector : (2,) float64 ndarray
        Change of X, Y per unit of inline number and of crossline number. A 2D line of a survey (one crossline or
        one inline) fixes only one of them: the other is then the zero vector.
    unit : {'m', 'ft', 'inline/crossline'}
        Unit of X and Y.
    max_residual : float
        Largest distance between a trace's header coordinates and the map, in :attr:`unit`.
    tolerance : float
        The largest residual the fit allowed.
    """

    origin: np.ndarray
    inline_vector: np.ndarray
    crossline_vector: np.ndarray
    unit: str
    max_residual: float = 0.0
    tolerance: float = 0.0

    @classmethod
    def identity(cls) -> "GridMap":
        """The fallback map of a survey without coordinates: X = inline number, Y = crossline number."""
        return cls(np.zeros(2), np.array([1.0, 0.0]), np.array([0.0, 1.0]), LINE_UNITS)

    @property
    def has_coordinates(self) -> bool:
        """False for the inline / crossline fallback."""
        return self.unit != LINE_UNITS

    @property
    def is_line(self) -> bool:
        """True when the map was fitted on a single line (one of the two vectors is zero)."""
        return not (np.any(self.inline_vector) and np.any(self.crossline_vector))

    def to_xy(self, inline, crossline) -> tuple[np.ndarray, np.ndarray]:
        """Map X, Y of inline / crossline numbers (fractional allowed).

        Parameters
        ----------
        inline, crossline : array_like of float, broadcastable
            Inline and crossline numbers.

        Returns
        -------
        x, y : float64 ndarray
            In :attr:`unit`.
        """
        il = np.asarray(inline, dtype=np.float64)
        xl = np.asarray(crossline, dtype=np.float64)
        x = self.origin[0] + il * self.inline_vector[0] + xl * self.crossline_vector[0]
        y = self.origin[1] + il * self.inline_vector[1] + xl * self.crossline_vector[1]
        return x, y

    def to_lines(self, x, y, *, crossline=None, inline=None) -> tuple[np.ndarray, np.ndarray]:
        """Inline / crossline numbers (fractional) of map positions: the inverse of :meth:`to_xy`.

        Parameters
        ----------
        x, y : array_like of float, broadcastable
            In :attr:`unit`.
        crossline, inline : float, optional
            For a map fitted on a single line: the line's fixed crossline (a line along inlines) or inline; the
            position is projected onto the line.

        Returns
        -------
        inline, crossline : float64 ndarray

        Raises
        ------
        InputError
            A map of a single line without the fixed line number.
        """
        d = np.stack([np.asarray(x, dtype=np.float64) - self.origin[0],
                      np.asarray(y, dtype=np.float64) - self.origin[1]], axis=-1)
        a, b = self.inline_vector, self.crossline_vector
        if not self.is_line:
            m = np.linalg.inv(np.column_stack([a, b]))
            lines = d @ m.T
            return lines[..., 0], lines[..., 1]
        if np.any(a):  # a line along inlines of one crossline
            if crossline is None:
                raise InputError("the grid map was fitted on a line along inlines; pass crossline= (the line's "
                                 "crossline number)")
            base = d - float(crossline) * b
            return base @ a / (a @ a), np.full(base.shape[:-1], float(crossline))
        if inline is None:
            raise InputError("the grid map was fitted on a line along crosslines; pass inline= (the line's inline "
                             "number)")
        base = d - float(inline) * a
        return np.full(base.shape[:-1], float(inline)), base @ b / (b @ b)


def header_resolution(scalars: np.ndarray) -> float:
    """The step of SEG-Y coordinates once scaled (SEG-Y rev 1, trace bytes 71-72).

    Parameters
    ----------
    scalars : array_like of int
        The coordinate scalar of each trace.

    Returns
    -------
    float
        The largest step: 1 / |scalar| for a negative scalar, the scalar for a positive one, 1 for 0.
    """
    s = np.asarray(scalars, dtype=np.float64).ravel()
    steps = np.where(s < 0, 1.0 / np.abs(np.where(s < 0, s, -1.0)), np.where(s > 0, s, 1.0))
    return float(steps.max()) if steps.size else 1.0


def fit_grid_map(inline, crossline, x, y, *, unit: str, tolerance: float) -> GridMap:
    """Fit the affine map of a grid's inline / crossline numbers to its traces' X / Y and check every trace.

    Least squares on ``[1, inline, crossline]`` for X and for Y (a single line fits only the varying number).

    Parameters
    ----------
    inline, crossline : (n,) array_like of float
        Inline and crossline numbers of the traces.
    x, y : (n,) array_like of float
        The traces' coordinates (scalar applied), in ``unit``.
    unit : {'m', 'ft'}
    tolerance : float
        Largest allowed distance between a trace and the map, in ``unit`` (e.g. the coordinates' rounding step).

    Returns
    -------
    GridMap

    Raises
    ------
    SegyGeometryError
        Fewer than two distinct traces, or a trace farther than ``tolerance`` from the fitted map (the message names
        the trace: the grid is not regular, or its inline / crossline numbers do not follow its coordinates).
    """
    il = np.asarray(inline, dtype=np.float64).ravel()
    xl = np.asarray(crossline, dtype=np.float64).ravel()
    xy = np.column_stack([np.asarray(x, dtype=np.float64).ravel(), np.asarray(y, dtype=np.float64).ravel()])
    varies = [np.ptp(il) > 0, np.ptp(xl) > 0]
    if not any(varies):
        raise SegyGeometryError("the traces share one inline and one crossline number, so no grid map can be "
                                "fitted; read the file as a trace list")
    columns = [np.ones_like(il)] + [c for c, v in zip((il, xl), varies) if v]
    design = np.column_stack(columns)
    coef, *_ = np.linalg.lstsq(design, xy, rcond=None)
    residual = np.linalg.norm(design @ coef - xy, axis=1)
    worst = int(np.argmax(residual))
    if residual[worst] > tolerance:
        raise SegyGeometryError(
            f"the trace at inline {il[worst]:g}, crossline {xl[worst]:g} lies {residual[worst]:.3g} {unit} from the "
            f"affine map of the inline / crossline grid fitted to all traces (allowed {tolerance:.3g} {unit}): the "
            "grid is not regular or its line numbers do not follow its CDP X/Y; check the header bytes (iline=, "
            "xline=) or read the file as a trace list")
    vectors = iter(coef[1:])
    a = next(vectors) if varies[0] else np.zeros(2)
    b = next(vectors) if varies[1] else np.zeros(2)
    return GridMap(np.asarray(coef[0], dtype=np.float64), np.asarray(a, dtype=np.float64),
                   np.asarray(b, dtype=np.float64), unit, float(residual[worst]), float(tolerance))


@dataclass(frozen=True, eq=False)
class SurveyCoordinates:
    """X / Y of every trace of a survey, and the affine map of its inline / crossline grid.

    Attributes
    ----------
    inline, crossline : float64 ndarray, the survey's lateral shape
        Inline and crossline numbers of every trace: (n_inlines, n_crosslines) for a grid (a 2D line of a survey is
        (n, 1) or (1, n)), (n_traces,) for a trace list (its trace numbers from 1 as inlines, 0 as crosslines when
        the headers hold no line numbers).
    x, y : float64 ndarray, same shape
        Map coordinates of every trace in :attr:`unit` (the scalar of bytes 71-72 applied); without coordinates in
        the headers, the inline and crossline numbers.
    unit : {'m', 'ft', 'inline/crossline'}
        Unit of X and Y; ``'inline/crossline'`` when the headers hold no coordinates.
    grid_map : GridMap or None
        The affine map fitted on every trace; None for a trace list, or a grid whose traces do not follow an affine
        map (:attr:`grid_problem` says why).
    source : str
        Where X / Y come from, in words (for outputs' headers).
    grid_problem : str
        Why :attr:`grid_map` is None ('' otherwise).
    """

    inline: np.ndarray
    crossline: np.ndarray
    x: np.ndarray
    y: np.ndarray
    unit: str
    grid_map: GridMap | None
    source: str
    grid_problem: str = ""

    @property
    def has_coordinates(self) -> bool:
        """False when X / Y are the inline / crossline numbers (no coordinates in the headers)."""
        return self.unit != LINE_UNITS

    @property
    def xy_names(self) -> tuple[str, str]:
        """What X and Y are, in words: ('X (m)', 'Y (m)') or ('inline number', 'crossline number')."""
        if not self.has_coordinates:
            return ("inline number", "crossline number")
        return (f"X ({self.unit})", f"Y ({self.unit})")

    def section(self) -> "SurveyCoordinates":
        """The coordinates of a 2D line of a survey ((n, 1) or (1, n) grid) along its traces, shape (n,); itself
        otherwise."""
        if self.x.ndim != 2 or 1 not in self.x.shape:
            return self
        flat = {k: np.ravel(getattr(self, k)) for k in ("inline", "crossline", "x", "y")}
        return SurveyCoordinates(**flat, unit=self.unit, grid_map=self.grid_map, source=self.source,
                                 grid_problem=self.grid_problem)

    def at(self, positions) -> tuple[np.ndarray, np.ndarray]:
        """X, Y at lateral index positions: the trace's own header coordinates at whole indices, the grid map (or
        linear interpolation along a trace list) between them.

        Parameters
        ----------
        positions : (n, k) array_like of float
            Lateral indices into :attr:`x`'s shape (k = its number of dimensions; extra columns, e.g. the sample,
            are ignored).

        Returns
        -------
        x, y : (n,) float64 ndarray
            In :attr:`unit`.
        """
        p = np.asarray(positions, dtype=np.float64)
        p = p.reshape(-1, p.shape[-1]) if p.ndim > 1 else p.reshape(-1, 1)
        nd = self.x.ndim
        lateral = p[:, :nd]
        whole = np.all(lateral == np.round(lateral), axis=1)
        idx = np.clip(np.round(lateral).astype(np.int64), 0, np.array(self.x.shape) - 1)
        x = self.x[tuple(idx.T)].astype(np.float64)
        y = self.y[tuple(idx.T)].astype(np.float64)
        if not whole.all():
            frac = ~whole
            il, xl = self.lines_at(lateral[frac])
            if self.grid_map is not None:
                x[frac], y[frac] = self.grid_map.to_xy(il, xl)
            else:
                x[frac], y[frac] = self._interpolated(lateral[frac])
        return x, y

    def lines_at(self, positions) -> tuple[np.ndarray, np.ndarray]:
        """Inline and crossline numbers (fractional) at lateral index positions.

        Parameters
        ----------
        positions : (n, k) array_like of float
            As :meth:`at`.

        Returns
        -------
        inline, crossline : (n,) float64 ndarray
        """
        p = np.asarray(positions, dtype=np.float64).reshape(-1, np.shape(positions)[-1] if np.ndim(positions) > 1
                                                            else 1)
        out = []
        for name in ("inline", "crossline"):
            grid = getattr(self, name)
            if grid.ndim == 1:
                out.append(np.interp(p[:, 0], np.arange(grid.size), grid))
                continue
            axis = 0 if name == "inline" else 1
            labels = grid[:, 0] if axis == 0 else grid[0, :]
            out.append(np.interp(p[:, axis], np.arange(labels.size), labels))
        return out[0], out[1]

    def _interpolated(self, lateral: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Linear interpolation of the trace coordinates (a trace list, or a grid without a map)."""
        if self.x.ndim == 1:
            t = np.arange(self.x.size)
            return np.interp(lateral[:, 0], t, self.x), np.interp(lateral[:, 0], t, self.y)
        from scipy.interpolate import RegularGridInterpolator

        axes = (np.arange(self.x.shape[0]), np.arange(self.x.shape[1]))
        out = []
        for values in (self.x, self.y):
            f = RegularGridInterpolator(axes, values, bounds_error=False, fill_value=None)
            out.append(f(lateral[:, :2]))
        return out[0], out[1]


def survey_coordinates(inline, crossline, x=None, y=None, *, unit: str = "m", resolution: float = 1.0,
                       source: str = "CDP X/Y") -> SurveyCoordinates:
    """Coordinates of a survey from arrays: its traces' inline / crossline numbers and X / Y.

    Parameters
    ----------
    inline, crossline : array_like of float, the survey's lateral shape
        (n_inlines, n_crosslines) for a grid (numbers per trace), or (n_traces,) for a trace list.
    x, y : array_like of float, same shape, optional
        Map coordinates with the scalar applied; None (or zero everywhere) for a survey without coordinates, which
        then uses inline / crossline units.
    unit : {'m', 'ft'}
        Unit of ``x`` / ``y``.
    resolution : float
        The step of the stored coordinates (the SEG-Y coordinate scalar's: 0.1 for a scalar of -10); the grid map
        must reproduce every trace within ``max(resolution, 1e-6 * extent)``.
    source : str
        Where X / Y come from, in words.

    Returns
    -------
    SurveyCoordinates

    Warns
    -----
    Seismo3dWarning
        A grid whose traces do not follow an affine map within the tolerance (its :attr:`~SurveyCoordinates.grid_map`
        is then None and positions between traces are interpolated), or a survey without coordinates.
    """
    il = np.asarray(inline, dtype=np.float64)
    xl = np.asarray(crossline, dtype=np.float64)
    if il.shape != xl.shape:
        raise InputError(f"inline {il.shape} and crossline {xl.shape} must have the same shape")
    no_xy = x is None or y is None or (not np.any(np.asarray(x)) and not np.any(np.asarray(y)))
    if no_xy:
        return SurveyCoordinates(il, xl, il.copy(), xl.copy(), LINE_UNITS,
                                 GridMap.identity() if il.ndim == 2 else None,
                                 "inline / crossline numbers (the trace headers hold no CDP X/Y or source X/Y)")
    xa, ya = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    if xa.shape != il.shape or ya.shape != il.shape:
        raise InputError(f"x {xa.shape} and y {ya.shape} must have the shape of inline {il.shape}")
    grid_map, problem = None, "a trace list: X/Y between traces are interpolated along the line"
    if il.ndim == 2:
        extent = float(np.hypot(np.ptp(xa), np.ptp(ya)))
        try:
            grid_map = fit_grid_map(il, xl, xa, ya, unit=unit, tolerance=max(resolution, 1e-6 * extent))
        except SegyGeometryError as exc:
            problem = str(exc)
            warnings.warn(f"{problem}; X/Y between traces are interpolated", Seismo3dWarning, stacklevel=2)
    return SurveyCoordinates(il, xl, xa, ya, unit, grid_map, source, problem)


def read_survey_coordinates(path, *, iline: int = 189, xline: int = 193, ignore_geometry: bool = False,
                            endian=None) -> SurveyCoordinates:
    """Read the trace coordinates of a SEG-Y file and fit its grid map.

    CDP X/Y (trace bytes 181-188), or source X/Y (bytes 73-80) when CDP X/Y are zero on every trace, times the
    coordinate scalar of each trace (bytes 71-72), read through :func:`~seismo3d.seismic.io.open_segy`; the unit
    from the binary header (bytes 3255-3256: 2 feet, otherwise metres).

    Parameters
    ----------
    path : str or os.PathLike
        A SEG-Y cube, a 2D line of a survey, or a file read as a trace list.
    iline, xline, ignore_geometry, endian
        As :func:`~seismo3d.seismic.io.open_segy`.

    Returns
    -------
    SurveyCoordinates
        Shaped (n_inlines, n_crosslines) for a grid, (n_traces,) for a trace list (inline numbers = the header's
        inline numbers, or the trace number from 1 when the headers hold none).

    Raises
    ------
    DataNotFoundError, SegyFormatError, SegyGeometryError
        As :func:`~seismo3d.seismic.io.open_segy`.
    """
    import segyio

    from .segy import open_segy

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)  # the reader of the data says it once
        # read, not mapped: a pass over every trace header would map the whole file into the resident memory
        cube = open_segy(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian, mmap=False)
    with cube:
        f = cube.segyfile
        scalars = np.asarray(f.attributes(segyio.TraceField.SourceGroupScalar)[:])
        unit = "ft" if int(f.bin[segyio.BinField.MeasurementSystem]) == 2 else "m"
        x, y = cube.cdp_x, cube.cdp_y
        cdp = np.any(np.asarray(f.attributes(segyio.TraceField.CDP_X)[:])) or np.any(
            np.asarray(f.attributes(segyio.TraceField.CDP_Y)[:]))
        source = ("CDP X/Y (trace bytes 181-188)" if cdp else "source X/Y (trace bytes 73-80)") + \
            f" with the coordinate scalar of bytes 71-72, {unit}"
        if cube.inlines is not None:
            il, xl = np.meshgrid(cube.inlines.astype(np.float64), cube.xlines.astype(np.float64), indexing="ij")
        else:
            il = np.asarray(f.attributes(cube.iline_byte)[:], dtype=np.float64)
            xl = np.asarray(f.attributes(cube.xline_byte)[:], dtype=np.float64)
            if np.ptp(il) == 0 and np.ptp(xl) == 0:
                il, xl = np.arange(1.0, il.size + 1.0), np.zeros(il.size)
    return survey_coordinates(il, xl, x, y, unit=unit, resolution=header_resolution(scalars), source=source)


def cube_coordinates(cube) -> SurveyCoordinates:
    """The coordinates of a cube opened by :func:`~seismo3d.seismic.io.cube.open_cube` (``seismo3d.open``), from
    its ``cdp_x`` / ``cdp_y`` and line numbers, without reading the file again.

    Parameters
    ----------
    cube : xarray.DataArray
        A cube ``(iline, xline, sample)``, a line of a survey ``(iline | xline, sample)`` with the other line number
        a scalar coordinate, or a trace list ``(trace, sample)`` (its ``iline`` / ``xline`` coordinates per trace
        when the headers hold them, else the trace number from 1 as inlines); ``cdp_x`` / ``cdp_y`` optional, their
        unit and step in the attributes ``xy_unit``, ``xy_resolution`` and ``xy_source``.

    Returns
    -------
    SurveyCoordinates
        (n_inlines, n_crosslines) for a cube, (n_traces,) for a line (its grid map fitted along it) or a trace list;
        in inline / crossline units without ``cdp_x`` / ``cdp_y``.
    """
    dims = cube.dims[:-1]
    xy = (cube.coords["cdp_x"].values, cube.coords["cdp_y"].values) if "cdp_x" in cube.coords else (None, None)
    kwargs = dict(unit=cube.attrs.get("xy_unit", "m") if xy[0] is not None else "m",
                  resolution=float(cube.attrs.get("xy_resolution", 1.0)))
    if "xy_source" in cube.attrs:
        kwargs["source"] = cube.attrs["xy_source"]

    def numbers(name, n):
        return np.asarray(cube.coords[name].values if name in cube.coords else np.arange(n), dtype=np.float64)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)  # the reader of the data says it once
        if len(dims) == 2:
            il, xl = np.meshgrid(numbers(dims[0], cube.shape[0]), numbers(dims[1], cube.shape[1]), indexing="ij")
            return survey_coordinates(il, xl, *xy, **kwargs)
        n = cube.shape[0]
        if dims[0] in ("iline", "xline") and ("xline" if dims[0] == "iline" else "iline") in cube.coords:
            along = numbers(dims[0], n)
            fixed = np.full(n, float(cube.coords["xline" if dims[0] == "iline" else "iline"].values))
            il, xl = (along, fixed) if dims[0] == "iline" else (fixed, along)
            shape = (n, 1) if dims[0] == "iline" else (1, n)
            grid = survey_coordinates(il.reshape(shape), xl.reshape(shape),
                                      *(None if v is None else v.reshape(shape) for v in xy), **kwargs)
            return grid.section()
        if "iline" in cube.coords and cube.coords["iline"].dims == (dims[0],):
            il, xl = numbers("iline", n), numbers("xline", n)
        else:
            il, xl = np.arange(1.0, n + 1.0), np.zeros(n)
        return survey_coordinates(il, xl, *xy, **kwargs)


def grid_spacing_from_cdp(x, y, interval: float, unit: str, source: str) -> tuple:
    """Inline bin, crossline bin and sample interval of a cube from its traces' CDP X / Y, with where each came from.

    Parameters
    ----------
    x, y : (n_inlines, n_crosslines) float ndarray or None
        The traces' CDP X / Y (scalar applied), in the survey's unit; None when the cube has none.
    interval : float
        The sample interval (ms, m or ft); 0 or negative when unknown.
    unit : str
        The sample interval's unit, for the note.
    source : str
        Where the sample interval came from, for the note (e.g. ``'from the binary header'``).

    Returns
    -------
    spacing : (3,) float64 ndarray
        The median distance between neighbouring traces along the inlines and along the crosslines, and the sample
        interval; a bin is 1.0 when the coordinates are missing or do not change along that axis, the interval 1.0
        when unknown.
    note : str
        E.g. ``'bins 25.01 x 25.01 from CDP X/Y, sample interval 4 ms from the binary header'``.
    """
    bins, missing = [1.0, 1.0], []
    for axis in (0, 1):
        d = None
        if x is not None and x.shape[axis] > 1:
            d = np.hypot(np.diff(x, axis=axis), np.diff(y, axis=axis))
            d = float(np.median(d)) if d.size else None
        if d is None or not np.isfinite(d) or d <= 0:
            missing.append("inline" if axis == 0 else "crossline")
        else:
            bins[axis] = d
    dt = float(interval) if interval is not None and interval > 0 else 1.0
    note = f"sample interval {dt:g} {unit} {source}"
    if missing:
        note = f"{' and '.join(missing)} bin unknown (no CDP coordinates), set to 1; " + note
    else:
        note = f"bins {bins[0]:.4g} x {bins[1]:.4g} from CDP X/Y, " + note
    return np.array([bins[0], bins[1], dt]), note
