"""Horizons in and out as map grids and points, through xtgeo: IRAP ASCII and binary, ZMAP+, and x y z points.

A tracked horizon (two-way time or depth per inline / crossline) leaves as a regular map grid laid on the survey's
inline / crossline grid by its affine map (:class:`~seismo3d.seismic.io.coordinates.GridMap`): origin at the first
inline and crossline, columns along inlines, rows along crosslines, the grid's rotation and spacing from the map
(:func:`horizon_surface`, :func:`write_horizon_grids`). Picks come back in from any of those files, or from
seismo3d's own ``inline xline time`` rows, as :class:`HorizonPicks` (:func:`read_horizon_picks`), e.g. as the seeds
of ``seismo3d horizon --seed-file``.

ZMAP+ has no rotation: xtgeo writes a rotated grid resampled onto an unrotated one (bilinear, over the rotated grid's
bounding box), so a ZMAP+ file of a rotated survey holds interpolated values at other nodes; IRAP holds the grid
as is. The ZMAP+ file's first comment line (``!``) says what X / Y are (a unit and the headers they come from, or
inline / crossline numbers for a survey without coordinates); IRAP and x y z files have no place for it.

xtgeo is imported inside the functions (it takes seconds to import); install it with ``pip install xtgeo``.

References
----------
xtgeo, ``RegularSurface`` (Equinor), https://xtgeo.readthedocs.io: ``to_file(fformat='irap_ascii' | 'irap_binary' |
'zmap_ascii')``, ``Points.to_file(fformat='xyz')``.
ZMAP+ grid format (Landmark ZMAP, ``@`` header, node values column-major from the top-left), read also by zmapio.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..._atomic import atomic_path
from ...errors import DataNotFoundError, InputError, MissingDependencyError
from .coordinates import SurveyCoordinates

__all__ = ["GRID_FORMATS", "HorizonPicks", "horizon_surface", "read_horizon_picks", "write_horizon_grids",
           "require_xtgeo"]

# format -> (xtgeo fformat, file suffix)
GRID_FORMATS = {"irap_ascii": ("irap_ascii", ".fgr"), "irap_binary": ("irap_binary", ".gri"),
                "zmap": ("zmap_ascii", ".zmap"), "xyz": ("xyz", ".xyz")}


def require_xtgeo():
    """Import xtgeo, or raise with the install hint.

    Returns
    -------
    module

    Raises
    ------
    MissingDependencyError
        xtgeo is not installed (``pip install "seismo3d[interchange]"``); an ``ImportError``.
    """
    try:
        import xtgeo
    except ImportError as exc:  # xtgeo is in the interchange extra
        raise MissingDependencyError("horizon grids (IRAP, ZMAP+, xyz) need xtgeo, which is not installed: pip "
                                     "install \"seismo3d[interchange]\" (or pip install xtgeo)") from exc
    return xtgeo


def _regular(values: np.ndarray, name: str) -> float:
    steps = np.diff(np.asarray(values, dtype=np.float64))
    if steps.size == 0:
        raise InputError(f"a horizon map grid needs at least two {name}s; write a 2D line's horizon as points "
                         "(format 'xyz')")
    if not np.allclose(steps, steps[0]):
        raise InputError(f"the {name} numbers are not evenly spaced, so the horizon is not a regular map grid; "
                         "write it as points (format 'xyz')")
    return float(steps[0])


def horizon_surface(times, inlines, xlines, coordinates: SurveyCoordinates, *, name: str = "horizon"):
    """A horizon on the survey's grid as an ``xtgeo.RegularSurface`` in map coordinates.

    Parameters
    ----------
    times : (n_inlines, n_xlines) array_like of float
        Two-way time or depth of the horizon at every trace (NaN where it was not tracked: masked).
    inlines, xlines : (n_inlines,), (n_xlines,) array_like of int
        The grid's inline and crossline numbers, evenly spaced.
    coordinates : SurveyCoordinates
        The survey's coordinates, with a grid map (:func:`~seismo3d.seismic.io.coordinates.read_survey_coordinates`);
        without coordinates the grid is in inline / crossline units (X = inline, Y = crossline number).
    name : str, optional

    Returns
    -------
    xtgeo.RegularSurface
        ``ncol`` = n_inlines (columns along inlines), ``nrow`` = n_xlines, ``xinc`` / ``yinc`` the distances
        between neighbouring inlines / crosslines, ``rotation`` of the inline axis (degrees anticlockwise from X),
        ``yflip`` 1 (a left-handed grid is written with its crosslines reversed), ``ilines`` / ``xlines`` set.

    Raises
    ------
    InputError
        A grid of one line or unevenly spaced lines, a survey without a grid map, or a grid whose inline and
        crossline axes are not square to each other (not a regular map grid: write points instead).
    """
    xtgeo = require_xtgeo()
    t = np.asarray(times, dtype=np.float64)
    il, xl = np.asarray(inlines, dtype=np.float64), np.asarray(xlines, dtype=np.float64)
    if t.shape != (il.size, xl.size):
        raise InputError(f"times {t.shape} must be (n_inlines, n_xlines) = ({il.size}, {xl.size})")
    d_il, d_xl = _regular(il, "inline"), _regular(xl, "crossline")
    gm = coordinates.grid_map
    if gm is None or gm.is_line:
        raise InputError("the survey has no grid map of inlines and crosslines "
                         f"({coordinates.grid_problem or 'a single line'}); write the horizon as points")
    u, v = gm.inline_vector * d_il, gm.crossline_vector * d_xl
    cos = float(u @ v) / float(np.linalg.norm(u) * np.linalg.norm(v))
    if abs(cos) > 1e-3:
        raise InputError(f"the inline and crossline axes meet at {np.degrees(np.arccos(cos)):.2f} degrees, not 90, so "
                         "the horizon is not a regular map grid; write it as points (format 'xyz')")
    values = np.ma.masked_invalid(t)
    if u[0] * v[1] - u[1] * v[0] < 0:  # left-handed: reverse the crosslines so that yflip = 1
        xl, values = xl[::-1], values[:, ::-1]
    x0, y0 = gm.to_xy(il[0], xl[0])
    rotation = float(np.degrees(np.arctan2(u[1], u[0]))) % 360.0
    return xtgeo.RegularSurface(ncol=il.size, nrow=xl.size, xinc=float(np.linalg.norm(u)),
                                yinc=float(np.linalg.norm(v)), xori=float(x0), yori=float(y0), yflip=1,
                                rotation=rotation, values=values, ilines=il.astype(np.int32),
                                xlines=xl.astype(np.int32), name=name)


def write_horizon_grids(stem, times, inlines, xlines, coordinates: SurveyCoordinates, *,
                        formats=("irap_ascii", "irap_binary", "zmap", "xyz"), name: str = "horizon") -> dict:
    """Write a horizon as map grids and points through xtgeo, each file atomically.

    Parameters
    ----------
    stem : str or os.PathLike
        Path without suffix; each format appends its own (``.fgr``, ``.gri``, ``.zmap``, ``.xyz``).
    times : (n_inlines, n_xlines) or (n_traces,) array_like of float
        The horizon (NaN where not tracked); a 2D line's (n_traces,) horizon can only be written as ``'xyz'``.
    inlines, xlines : array_like of int
        The grid's lines; for a 2D line, its traces' inline and crossline numbers (n_traces,) each.
    coordinates : SurveyCoordinates
        Of the same grid (a line's: :meth:`~SurveyCoordinates.section`).
    formats : iterable of {'irap_ascii', 'irap_binary', 'zmap', 'xyz'}
        ``'xyz'``: the tracked traces as ``X Y Z`` rows (xtgeo ``Points``), X / Y of each trace's own header.
    name : str, optional

    Returns
    -------
    dict of str to pathlib.Path
        The files written, by format.

    Raises
    ------
    InputError
        An unknown format, or a grid format for a 2D line or a grid that is not a regular map grid (see
        :func:`horizon_surface`).
    """
    xtgeo = require_xtgeo()
    formats = tuple(formats)
    unknown = set(formats) - set(GRID_FORMATS)
    if unknown:
        raise InputError(f"unknown horizon format(s) {sorted(unknown)}; use {', '.join(GRID_FORMATS)}")
    t = np.asarray(times, dtype=np.float64)
    stem = Path(stem)
    written = {}
    grids = [f for f in formats if f != "xyz"]
    if grids and t.ndim != 2:
        raise InputError(f"a 2D line's horizon is not a map grid; write it as points (formats=('xyz',)), not {grids}")
    surface = horizon_surface(t, inlines, xlines, coordinates, name=name) if grids else None
    for fmt in formats:
        fformat, suffix = GRID_FORMATS[fmt]
        path = stem.with_name(stem.name + suffix)
        with atomic_path(path, suffix=".tmp" + suffix) as tmp:
            if fmt == "xyz":
                ok = np.isfinite(t)
                if t.ndim == 2:
                    idx = np.argwhere(ok)
                else:
                    idx = np.flatnonzero(ok)[:, None]
                x, y = coordinates.at(idx)
                xtgeo.Points(np.column_stack([x, y, t[ok]])).to_file(tmp, fformat="xyz")
            else:
                surface.to_file(tmp, fformat=fformat)
                if fmt == "zmap":  # ZMAP+ has comment lines: say what X / Y are
                    tmp.write_text(f"! seismo3d: X, Y {_xy_words(coordinates)}\n" + tmp.read_text())
        written[fmt] = path
    return written


def _xy_words(coordinates: SurveyCoordinates) -> str:
    if not coordinates.has_coordinates:
        return "are inline and crossline numbers (the SEG-Y headers hold no coordinates)"
    return f"in {coordinates.unit}, from {coordinates.source}"


@dataclass(frozen=True, eq=False)
class HorizonPicks:
    """Horizon picks read from a file: map positions (and inline / crossline numbers where known) with a time or
    depth.

    Attributes
    ----------
    x, y : (n,) float64 ndarray
        Map coordinates (NaN for seismo3d's ``inline xline time`` rows, which have none).
    z : (n,) float64 ndarray
        Two-way time or depth, as in the file.
    inline, crossline : (n,) float64 ndarray
        Line numbers (from the file, or from X / Y through the survey's grid map); NaN where unknown.
    source_format : {'irap_ascii', 'irap_binary', 'zmap', 'xyz', 'lines'}
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    inline: np.ndarray
    crossline: np.ndarray
    source_format: str

    @property
    def n_picks(self) -> int:
        return int(self.z.size)

    def with_lines(self, coordinates: SurveyCoordinates) -> "HorizonPicks":
        """The picks with inline / crossline numbers from their X / Y through the survey's grid map.

        Parameters
        ----------
        coordinates : SurveyCoordinates
            With a grid map (a 3D survey, or a 2D line of one: the picks are then projected onto the line).

        Returns
        -------
        HorizonPicks

        Raises
        ------
        InputError
            A survey without a grid map.
        """
        if np.all(np.isfinite(self.inline)) and np.all(np.isfinite(self.crossline)):
            return self
        gm = coordinates.grid_map
        if gm is None:
            raise InputError("the survey has no grid map, so map picks cannot be placed on its lines "
                             f"({coordinates.grid_problem})")
        fixed = {}
        if gm.is_line:
            if np.any(gm.inline_vector):
                fixed["crossline"] = float(np.ravel(coordinates.crossline)[0])
            else:
                fixed["inline"] = float(np.ravel(coordinates.inline)[0])
        il, xl = gm.to_lines(self.x, self.y, **fixed)
        return HorizonPicks(self.x, self.y, self.z, np.asarray(il, dtype=np.float64),
                            np.asarray(xl, dtype=np.float64), self.source_format)


def _format_of(path: Path) -> str:
    suffix = path.suffix.lower()
    by_suffix = {".fgr": "irap_ascii", ".irap": "irap_ascii", ".irapasc": "irap_ascii", ".gri": "irap_binary",
                 ".irapbin": "irap_binary", ".zmap": "zmap", ".zmp": "zmap", ".xyz": "xyz", ".pts": "xyz"}
    if suffix in by_suffix:
        return by_suffix[suffix]
    first = path.read_bytes()[:4096].lstrip()[:1]
    return "zmap" if first in (b"!", b"@") else "lines"


def read_horizon_picks(path, *, format: str | None = None) -> HorizonPicks:
    """Read horizon picks: an IRAP ASCII / binary or ZMAP+ grid or x y z points through xtgeo, or seismo3d's
    ``inline xline time`` rows.

    Parameters
    ----------
    path : str or os.PathLike
    format : {'irap_ascii', 'irap_binary', 'zmap', 'xyz', 'lines'}, optional
        Default from the suffix (``.fgr``, ``.gri``, ``.zmap``, ``.xyz``); other text files are read as
        ``inline xline time`` rows (``#`` comments allowed; commas or white space).

    Returns
    -------
    HorizonPicks
        Every defined grid node (masked nodes left out) or row.

    Raises
    ------
    DataNotFoundError
        No such file.
    InputError
        A file the format's reader cannot read, or rows that are not three numbers.
    """
    path = Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"no horizon file at {path}; check the path")
    fmt = format or _format_of(path)
    nan = lambda n: np.full(n, np.nan)  # noqa: E731
    if fmt == "lines":
        try:
            rows = np.loadtxt(path, ndmin=2, comments="#", delimiter="," if path.suffix.lower() == ".csv" else None)
        except ValueError as exc:
            raise InputError(f"{path.name} is not a table of numbers ({exc}); pass 'inline xline time' rows, or an "
                             "IRAP (.fgr, .gri), ZMAP+ (.zmap) or x y z (.xyz) file") from None
        if rows.shape[1] != 3:
            raise InputError(f"{path.name} has {rows.shape[1]} columns; 'inline xline time' rows have 3")
        n = rows.shape[0]
        return HorizonPicks(nan(n), nan(n), rows[:, 2].copy(), rows[:, 0].copy(), rows[:, 1].copy(), "lines")
    if fmt not in GRID_FORMATS:
        raise InputError(f"format={fmt!r} is not a horizon format; use {', '.join(GRID_FORMATS)} or 'lines'")
    xtgeo = require_xtgeo()
    try:
        if fmt == "xyz":
            xyz = xtgeo.points_from_file(path, fformat="xyz").get_dataframe().to_numpy(dtype=np.float64)[:, :3]
            n = xyz.shape[0]
            return HorizonPicks(xyz[:, 0].copy(), xyz[:, 1].copy(), xyz[:, 2].copy(), nan(n), nan(n), "xyz")
        surf = xtgeo.surface_from_file(path, fformat=GRID_FORMATS[fmt][0])
    except Exception as exc:  # noqa: BLE001 - xtgeo's readers raise assorted errors on a damaged file
        raise InputError(f"{path.name} cannot be read as {fmt} by xtgeo ({exc}); check the file and its format")
    x, y, z = (np.ma.filled(np.ma.asarray(a), np.nan).astype(np.float64) for a in surf.get_xyz_values())
    ok = np.isfinite(z)
    n = int(ok.sum())  # the grid files hold no line numbers: the picks are placed by X / Y (HorizonPicks.with_lines)
    return HorizonPicks(x[ok], y[ok], z[ok], nan(n), nan(n), fmt)
