"""A seismic cube's geometry in a 3D scene, and its amplitudes as a pyvista grid.

Geometry (:class:`CubeGeometry`): sample ``(i, j, k)`` (inline index, crossline index, sample index) sits at
``origin + i * axes[0] + j * axes[1] + k * axes[2]``. With CDP X/Y in the trace headers the two lateral axes are the
survey's bin vectors in its map unit (fitted to the headers by least squares) and the vertical axis is the sample
interval in the same unit (a depth cube: metres or feet; a time cube: two-way time converted at ``velocity``,
2000 m/s by default, i.e. 1 m per ms), pointing *down*. Without coordinates the lateral axes step one unit per line
(x = inline number, y = crossline number) and one sample is one unit down. The vertical axis is then multiplied by the
vertical exaggeration (by default the one that makes the cube's height half its longer side).

Faults and horizons from :mod:`seismo3d.seismic` are in index space; :meth:`CubeGeometry.to_world` places them.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, Seismo3dWarning

__all__ = ["CubeGeometry", "cube_geometry", "geometry_of_segy", "grid_index", "place_index_mesh", "seismic_grid"]


_UNITS = {"ms", "m", "ft", "samples"}


@dataclass(frozen=True, eq=False)
class CubeGeometry:
    """Where the samples of a seismic cube sit in a 3D scene (see the module's docstring).

    Attributes
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    inlines, xlines : (n_inlines,), (n_xlines,) float64 ndarray
        Inline and crossline numbers.
    samples : (n_samples,) float64 ndarray
        Times or depths of the samples, in ``sample_unit``.
    sample_unit : {'ms', 'm', 'ft', 'samples'}
    origin : (3,) float64 ndarray
        Scene position of sample (0, 0, 0).
    axes : (3, 3) float64 ndarray
        Row ``d``: the scene step of one index step along axis ``d`` (inline, crossline, sample); row 2 points down
        (negative z) and includes the vertical exaggeration.
    map_unit : str
        Unit of the lateral scene coordinates: the survey's ('m' or 'ft') with CDP X/Y, 'line' without.
    vertical_exaggeration : float
        Factor applied to the vertical axis.
    lateral_names : (str, str)
        What numbers the two lateral axes: ``('inline', 'crossline')``, or ``('trace', '')`` for a trace list (one
        section, traces numbered in file order; ``inlines`` then holds the trace numbers).
    """

    shape: tuple
    inlines: np.ndarray
    xlines: np.ndarray
    samples: np.ndarray
    sample_unit: str
    origin: np.ndarray
    axes: np.ndarray
    map_unit: str
    vertical_exaggeration: float
    lateral_names: tuple = ("inline", "crossline")

    def to_world(self, ijk) -> np.ndarray:
        """Scene coordinates of index-space positions.

        Parameters
        ----------
        ijk : (n, 3) array_like of float
            Inline, crossline and sample indices (fractional allowed).

        Returns
        -------
        (n, 3) float64 ndarray
        """
        ijk = np.asarray(ijk, dtype=np.float64).reshape(-1, 3)
        return self.origin + ijk @ self.axes

    def axis_labels(self) -> tuple[str, str, str]:
        """Names of the scene's x, y and z axes for the orientation widget: inline / crossline (line numbers) or
        easting / northing (CDP X/Y, in ``map_unit``), and 'up' (the widget's z arrow points up, the way time or
        depth decreases)."""
        if self.map_unit == "line":
            return self.lateral_names[0], self.lateral_names[1], "up"
        return f"X ({self.map_unit})", f"Y ({self.map_unit})", "up"

    def describe(self) -> str:
        """One line: the lines, the sample range and the vertical exaggeration (used as the scene's caption)."""
        il, xl, s = self.inlines, self.xlines, self.samples
        unit = "" if self.sample_unit == "samples" else f" {self.sample_unit}"
        name = {"ms": "time", "m": "depth", "ft": "depth"}.get(self.sample_unit, "sample")
        first, second = self.lateral_names
        lines = f"{first}s {il[0]:g}-{il[-1]:g}" + (f", {second}s {xl[0]:g}-{xl[-1]:g}" if second else "")
        return (f"{lines}, {name} {s[0]:g}-{s[-1]:g}{unit} (down), vertical exaggeration "
                f"{self.vertical_exaggeration:.2g}")


def _axis(values, n: int, name: str) -> np.ndarray:
    if values is None:
        return np.arange(n, dtype=np.float64)
    values = np.asarray(values, dtype=np.float64).ravel()
    if values.size != n:
        raise InputError(f"{name} has {values.size} values but the cube has {n} along that axis; pass the cube's "
                         f"own {name}")
    return values


def _step(values: np.ndarray) -> float:
    return float(np.median(np.diff(values))) if values.size > 1 else 1.0


def _bin_vectors(cdp_x, cdp_y, shape):
    """Origin (x, y) and bin vectors along inline / crossline index fitted to CDP X/Y, or None when they are not a
    regular grid (residual over a quarter bin)."""
    x = np.asarray(cdp_x, dtype=np.float64)
    y = np.asarray(cdp_y, dtype=np.float64)
    if x.shape != shape[:2] or y.shape != shape[:2]:
        raise InputError(f"cdp_x and cdp_y must be (n_inlines, n_xlines) = {shape[:2]} grids; got {x.shape}, "
                         f"{y.shape}")
    ii, jj = np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij")
    design = np.column_stack([np.ones(ii.size), ii.ravel(), jj.ravel()])
    coef, *_ = np.linalg.lstsq(design, np.column_stack([x.ravel(), y.ravel()]), rcond=None)
    residual = np.abs(design @ coef - np.column_stack([x.ravel(), y.ravel()])).max()
    bins = [np.linalg.norm(coef[d]) for d in (1, 2) if shape[d - 1] > 1]
    if not bins or min(bins) == 0 or residual > 0.25 * min(bins):
        return None
    return coef[0], coef[1], coef[2]


def cube_geometry(shape, *, inlines=None, xlines=None, samples=None, sample_unit="samples", cdp_x=None, cdp_y=None,
                  map_unit="m", vertical_exaggeration=None, velocity=2000.0,
                  lateral_names=("inline", "crossline")) -> CubeGeometry:
    """The scene geometry of a cube from its line numbers, samples and (optionally) CDP coordinates.

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    inlines, xlines : 1D array_like, optional
        Line numbers; default 0, 1, 2, ...
    samples : (n_samples,) array_like, optional
        Times or depths; default the sample indices.
    sample_unit : {'ms', 'm', 'ft', 'samples'}, optional
    cdp_x, cdp_y : (n_inlines, n_xlines) array_like, optional
        Trace coordinates (e.g. :attr:`seismo3d.seismic.SeismicCube.cdp_x`). Used when they form a regular grid;
        otherwise a :class:`~seismo3d.errors.Seismo3dWarning` says so and the lines are used.
    map_unit : {'m', 'ft'}, optional
        Unit of ``cdp_x`` / ``cdp_y``.
    vertical_exaggeration : float, optional
        Multiplies the vertical axis; default: the cube's height becomes half its longer lateral side.
    velocity : float, optional
        For a time cube shown with map coordinates: the velocity (m/s or ft/s) converting two-way time to depth.
    lateral_names : (str, str), optional
        What numbers the lateral axes (see :attr:`CubeGeometry.lateral_names`).

    Returns
    -------
    CubeGeometry

    Raises
    ------
    InputError
        A shape that is not 3D, axes of the wrong length, an unknown unit or a non-positive exaggeration.
    """
    shape = tuple(int(n) for n in shape)
    if len(shape) != 3 or min(shape) < 1:
        raise InputError(f"a cube geometry needs (n_inlines, n_xlines, n_samples); got {shape}")
    if sample_unit not in _UNITS:
        raise InputError(f"sample_unit must be one of {sorted(_UNITS)}; got {sample_unit!r}")
    il, xl = _axis(inlines, shape[0], "inlines"), _axis(xlines, shape[1], "xlines")
    s = _axis(samples, shape[2], "samples")
    dt = abs(_step(s)) or 1.0
    lateral = None
    if cdp_x is not None and cdp_y is not None:
        lateral = _bin_vectors(cdp_x, cdp_y, shape)
        if lateral is None:
            warnings.warn("the CDP X/Y coordinates do not form a regular grid; the scene uses inline / crossline "
                          "numbers instead", Seismo3dWarning, stacklevel=2)
    if lateral is not None:
        (x0, y0), a_i, a_j = lateral
        origin = np.array([x0, y0, 0.0])
        a_i, a_j = np.append(a_i, 0.0), np.append(a_j, 0.0)
        per_sample = dt * velocity / 2000.0 if sample_unit == "ms" else dt
        unit = map_unit
    else:
        origin = np.array([il[0], xl[0], 0.0])
        a_i, a_j = np.array([_step(il), 0.0, 0.0]), np.array([0.0, _step(xl), 0.0])
        per_sample, unit = 1.0, "line"
    if vertical_exaggeration is None:
        side = max(np.linalg.norm(a_i) * (shape[0] - 1), np.linalg.norm(a_j) * (shape[1] - 1), 1.0)
        vertical_exaggeration = float(f"{0.5 * side / (per_sample * max(shape[2] - 1, 1)):.2g}")
    if not np.isfinite(vertical_exaggeration) or vertical_exaggeration <= 0:
        raise InputError(f"vertical_exaggeration must be > 0; got {vertical_exaggeration!r}")
    down = np.array([0.0, 0.0, -per_sample * vertical_exaggeration])
    origin[2] = s[0] / dt * down[2]  # the first sample's time or depth, counted in samples, downward
    for a in (il, xl, s):
        a.setflags(write=False)
    return CubeGeometry(shape=shape, inlines=il, xlines=xl, samples=s, sample_unit=sample_unit, origin=origin,
                        axes=np.vstack([a_i, a_j, down]), map_unit=unit,
                        vertical_exaggeration=float(vertical_exaggeration), lateral_names=tuple(lateral_names))


def geometry_of_segy(segy, *, vertical_exaggeration=None, velocity=2000.0) -> CubeGeometry:
    """:func:`cube_geometry` of an open SEG-Y cube (line numbers, samples, unit and CDP X/Y from its headers).

    Parameters
    ----------
    segy : seismo3d.seismic.SeismicCube
        From :func:`~seismo3d.seismic.open_segy`, opened with geometry (not as a trace list), still open.
    vertical_exaggeration, velocity : float, optional
        As :func:`cube_geometry`.

    Returns
    -------
    CubeGeometry

    Raises
    ------
    SegyGeometryError
        The cube was opened as a trace list.
    """
    segy.require_geometry("a 3D scene")
    unit = "ft" if int(segy.segyfile.bin[3255]) == 2 else "m"  # binary header bytes 3255-3256: measurement system
    return cube_geometry(segy.shape, inlines=segy.inlines, xlines=segy.xlines, samples=segy.samples,
                         sample_unit=segy.sample_unit, cdp_x=segy.cdp_x, cdp_y=segy.cdp_y, map_unit=unit,
                         vertical_exaggeration=vertical_exaggeration, velocity=velocity)


def seismic_grid(values, geometry: CubeGeometry, *, name="amplitude"):
    """A cube as a pyvista ImageData placed by ``geometry`` (rotated with the survey, time or depth downward).

    Parameters
    ----------
    values : (n_inlines, n_xlines, n_samples) array_like
        Amplitudes (or any attribute of the cube: fault likelihood, ...).
    geometry : CubeGeometry
    name : str, optional
        Name of the point array.

    Returns
    -------
    pyvista.ImageData
        Dimensions ``geometry.shape``; point arrays ``name`` (float32), ``inline``, ``crossline`` and
        ``time_or_depth`` (float32, in the geometry's units). The grid stores its axes as a proper rotation, so the
        sample axis (and sometimes the crossline axis) run reversed in it: :func:`grid_index` converts indices.

    Raises
    ------
    InputError
        ``values`` does not have the geometry's shape.
    """
    import pyvista as pv

    data = np.asarray(values, dtype=np.float32)
    if data.shape != geometry.shape:
        raise InputError(f"the values have shape {data.shape} but the geometry {geometry.shape}; build the geometry "
                         "from the same cube")
    flip_j, flip_k = _flips(geometry)
    axes = geometry.axes * np.array([1.0, -1.0 if flip_j else 1.0, -1.0 if flip_k else 1.0])[:, None]
    first = np.array([0, geometry.shape[1] - 1 if flip_j else 0, geometry.shape[2] - 1 if flip_k else 0])
    spacing = np.linalg.norm(axes, axis=1)
    spacing[spacing == 0] = 1.0
    grid = pv.ImageData(dimensions=geometry.shape, spacing=spacing, origin=geometry.to_world(first)[0],
                        direction_matrix=(axes / spacing[:, None]).T)
    ii, jj, kk = np.meshgrid(geometry.inlines, geometry.xlines, geometry.samples, indexing="ij")
    order = (slice(None), slice(None, None, -1 if flip_j else 1), slice(None, None, -1 if flip_k else 1))
    for label, arr in ((name, data), ("inline", ii), ("crossline", jj), ("time_or_depth", kk)):
        grid.point_data[label] = np.asarray(arr[order], dtype=np.float32).ravel(order="F")
    grid.set_active_scalars(name)
    return grid


def _flips(geometry: CubeGeometry) -> tuple[bool, bool]:
    """Whether a grid stores the crossline and sample axes reversed: VTK's volume rendering needs a proper rotation
    (determinant > 0) as the grid's direction, so the downward sample axis is stored upward and, if the inline and
    crossline bins then turn the wrong way, the crosslines reversed."""
    flip_k = geometry.axes[2, 2] < 0
    up = geometry.axes * np.array([1.0, 1.0, -1.0 if flip_k else 1.0])[:, None]
    return bool(np.linalg.det(up) < 0), bool(flip_k)


def grid_index(geometry: CubeGeometry, ijk) -> tuple[int, int, int]:
    """The grid's own (i, j, k) of the cube's sample (i, j, k): see :func:`seismic_grid`, which may store the
    crossline and sample axes reversed.

    Parameters
    ----------
    geometry : CubeGeometry
    ijk : (int, int, int)
        Inline, crossline and sample indices of the cube.

    Returns
    -------
    (int, int, int)
    """
    flip_j, flip_k = _flips(geometry)
    i, j, k = (int(v) for v in ijk)
    return i, geometry.shape[1] - 1 - j if flip_j else j, geometry.shape[2] - 1 - k if flip_k else k


def place_index_mesh(mesh, geometry: CubeGeometry):
    """A copy of a mesh in index space with z up (points ``(i, j, -k)``, as :func:`~seismo3d.viz.fault_surfaces`
    and :func:`~seismo3d.viz.horizon_surface` make them) moved into the scene of ``geometry``.

    Parameters
    ----------
    mesh : pyvista.DataSet
    geometry : CubeGeometry

    Returns
    -------
    pyvista.DataSet
        The same cells and arrays at scene coordinates.
    """
    out = mesh.copy()
    if out.n_points:
        p = np.asarray(out.points, dtype=np.float64)
        out.points = geometry.to_world(np.column_stack([p[:, 0], p[:, 1], -p[:, 2]]))
    return out
