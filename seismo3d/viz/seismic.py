"""A seismic cube in 3D: its geometry, a pyvista grid, and one scene with slices, faults, horizons and likelihood.

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
from .faults import fault_surfaces
from .horizons import horizon_surface
from .plotting import bar_below, finish_scene, new_plotter, symmetric_clip

__all__ = ["CubeGeometry", "cube_geometry", "geometry_of_segy", "seismic_grid", "place_index_mesh", "show_seismic"]

_UNITS = {"ms", "m", "ft", "samples"}
_FAULT_OPACITY = 0.6  # fault surfaces let the slices behind them show


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


def _slice_indices(slices, shape):
    if slices is None:
        return shape[0] // 2, shape[1] // 2, shape[2] // 2
    out = []
    for s, n, name in zip(slices, shape, ("inline", "crossline", "sample")):
        if s is None:
            out.append(None)
            continue
        if not 0 <= int(s) < n:
            raise InputError(f"the {name} slice index {s} is outside 0..{n - 1}; slices are indices, not numbers")
        out.append(int(s))
    if len(out) != 3:
        raise InputError(f"slices must be (inline index, crossline index, sample index); got {slices!r}")
    return tuple(out)


_PLANES = ("inline", "crossline", "time slice")


def _plane(grid, geometry, axis: int, index: int):
    """The plane of the cube's ``axis`` (0 inline, 1 crossline, 2 sample) at the cube's ``index``."""
    ijk = [0, 0, 0]
    ijk[axis] = index
    g = grid_index(geometry, ijk)[axis]
    box = [0, geometry.shape[0] - 1, 0, geometry.shape[1] - 1, 0, geometry.shape[2] - 1]
    box[2 * axis] = box[2 * axis + 1] = g
    return grid.extract_subset(box)


def _add_slices(plotter, grid, geometry, idx, *, cmap, clim, sliders=False):
    """The inline, crossline and time-slice planes (an index None leaves its plane out), with one amplitude colour
    bar at the bottom left; with ``sliders``, one slider per plane moves it (each plane is a named actor that the
    slider's callback replaces)."""
    style = dict(scalars=grid.active_scalars_name, cmap=cmap, clim=clim, show_scalar_bar=False, lighting=False)
    first = True
    for axis, wanted in enumerate(idx):
        if wanted is None:
            continue
        bar = dict(show_scalar_bar=True, scalar_bar_args=bar_below("amplitude", position_x=0.22, width=0.34,
                                                                   fmt="%.3g", n_labels=3)) if first else {}
        plotter.add_mesh(_plane(grid, geometry, axis, wanted), name=_PLANES[axis], **{**style, **bar})
        first = False
        if sliders:
            def move(value, axis=axis):
                plotter.add_mesh(_plane(grid, geometry, axis, int(round(value))), name=_PLANES[axis], **style)

            y = 0.86 - 0.13 * axis
            plotter.add_slider_widget(move, [0, geometry.shape[axis] - 1], value=wanted, title=f"{_PLANES[axis]} index",
                                      fmt="%.0f", pointa=(0.03, y), pointb=(0.25, y), style="modern",
                                      title_height=0.025, slider_width=0.02, tube_width=0.008)


def _toward_viewer(geometry: CubeGeometry) -> np.ndarray:
    """On a single line, one bin toward the viewer of its section (see :func:`_section_normal`): what lifts a mesh
    over the section's plane rather than through it; zero for a cube."""
    if 1 not in geometry.shape[:2]:
        return np.zeros(3)
    along = geometry.axes[0] if geometry.shape[0] > 1 else geometry.axes[1]
    return _section_normal(geometry) * float(np.linalg.norm(along))


def _lift(mesh, geometry: CubeGeometry):
    """A mesh in index space placed in the scene, over a single line's section (:func:`_toward_viewer`)."""
    mesh = place_index_mesh(mesh, geometry)
    mesh.points += _toward_viewer(geometry)
    return mesh


def _add_faults(plotter, faults, throws, geometry, color_by):
    mesh = faults if hasattr(faults, "n_points") else fault_surfaces(list(faults), throws)
    if not mesh.n_points:
        return
    if mesh.n_cells and mesh.n_cells != mesh.n_lines:
        mesh = mesh.smooth_taubin(n_iter=20, pass_band=0.1)  # display only: soften the voxel staircase
    mesh = _lift(mesh, geometry)
    if color_by == "fault_id":
        from matplotlib import colormaps
        from matplotlib.colors import ListedColormap

        top = int(np.max(mesh.point_data["fault_id"]))
        tab10 = colormaps["tab10"]
        colours = ListedColormap([tab10((i - 1) % 10) for i in range(1, top + 1)])  # fault i: tab10 colour i - 1
        plotter.add_mesh(mesh, scalars="fault_id", cmap=colours, clim=(0.5, top + 0.5), n_colors=top,
                         line_width=3, ambient=0.3, opacity=_FAULT_OPACITY,
                         scalar_bar_args=bar_below(f"fault id 1-{top}" + (", colours cycle" if top > 10 else ""),
                                                   position_x=0.6, width=0.35, n_labels=0))
        return
    values = np.asarray(mesh.point_data["throw"], dtype=np.float64)
    if not np.isfinite(values).any():
        raise InputError("color_by='throw' needs measured throws; pass throws= (FaultInterpretation.throws)")
    lim = float(np.nanpercentile(np.abs(values), 98)) or 1.0
    plotter.add_mesh(mesh, scalars="throw", cmap="PuOr_r", clim=(-lim, lim), nan_color="lightgrey",
                     line_width=3, ambient=0.3, opacity=_FAULT_OPACITY,
                     scalar_bar_args=bar_below("throw (samples, + normal)", position_x=0.6, width=0.35))


def _add_horizons(plotter, horizons, geometry):
    surfaces = []
    for h in horizons:
        surf = horizon_surface(h, samples=geometry.samples)
        if surf.n_points:
            surfaces.append(_lift(surf, geometry))
    if not surfaces:
        return
    values = np.concatenate([s.point_data["time_or_depth"] for s in surfaces])
    clim = (float(values.min()), float(values.max()) if values.max() > values.min() else float(values.min()) + 1)
    unit = "" if geometry.sample_unit == "samples" else f" ({geometry.sample_unit})"
    name = {"ms": "time", "m": "depth", "ft": "depth"}.get(geometry.sample_unit, "sample")
    for n, surf in enumerate(surfaces):
        plotter.add_mesh(surf, scalars="time_or_depth", cmap="viridis", clim=clim, show_scalar_bar=n == 0,
                         line_width=5, render_lines_as_tubes=True,  # a horizon on a 2D line is a curve
                         scalar_bar_args={"title": f"horizon\n{name}{unit}", "vertical": True, "fmt": "%.4g",
                                          "position_x": 0.84, "position_y": 0.3, "width": 0.08})


def _add_likelihood(plotter, likelihood, geometry, threshold, max_opacity=0.5):
    grid = seismic_grid(likelihood, geometry, name="fault likelihood")
    if threshold is None:
        values = grid.point_data["fault likelihood"]
        threshold = min(float(np.nanpercentile(values, 95)), 0.99 * float(np.nanmax(values)))
    if not 0 <= threshold < 1:
        raise InputError(f"likelihood_threshold must be in [0, 1); got {threshold!r}")
    # the data raised to the threshold (transparent anyway): VTK sizes its colour table by the data's range over the
    # colour range, and would warn (and lose resolution) for a narrow colour range
    grid.point_data["fault likelihood"] = np.maximum(grid.point_data["fault likelihood"], np.float32(threshold))
    opacity = np.linspace(0.0, max_opacity, 64)  # over [threshold, 1]; transparent below (clamped colour range)
    bar = {"title": "fault\nlikelihood", "vertical": True, "position_x": 0.9, "position_y": 0.3, "fmt": "%.2f"}
    if 1 in geometry.shape[:2]:  # a line: the likelihood is a plane, drawn as one over the section (a volume one
        # voxel thick takes minutes to ray-cast, for the same picture)
        plane = grid.extract_surface(algorithm="dataset_surface")
        plane.points += 0.5 * _toward_viewer(geometry)  # over the seismic, under the faults
        plotter.add_mesh(plane, scalars="fault likelihood", cmap="Greys", clim=(threshold, 1.0), opacity=opacity,
                         lighting=False, scalar_bar_args=bar)
        return
    voxel = float(np.linalg.norm(geometry.axes, axis=1).mean())
    volume = plotter.add_volume(grid, scalars="fault likelihood", cmap="Greys", clim=(threshold, 1.0),
                                opacity=opacity, opacity_unit_distance=voxel, shade=False, scalar_bar_args=bar)
    volume.prop.interpolation_type = "linear"  # trilinear samples: no voxel bricks
    volume.mapper.SetAutoAdjustSampleDistances(False)  # a fixed step of half a voxel: no moire stripes
    volume.mapper.SetSampleDistance(0.5 * float(np.linalg.norm(geometry.axes, axis=1).min()))


def _outline(geometry: CubeGeometry):
    """The cube's 12 edges in the scene."""
    import pyvista as pv

    corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=np.float64)
    corners *= np.maximum(np.array(geometry.shape) - 1, 0)
    edges = [(a, b) for a in range(8) for b in range(a + 1, 8) if np.count_nonzero(corners[a] != corners[b]) == 1]
    lines = np.array([[2, a, b] for a, b in edges], dtype=np.int64).ravel()
    return pv.PolyData(geometry.to_world(corners), lines=lines)


def _add_ticks(plotter, geometry: CubeGeometry) -> None:
    """Labelled ticks on the cube's box: inline and crossline numbers (or map X / Y in the survey's unit when the
    cube is placed by its CDP coordinates) and time or depth, increasing downward, in the data's own values (the
    scene's vertical axis is exaggerated; the labels are not)."""
    corners = geometry.to_world(np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], np.float64)
                                * np.maximum(np.array(geometry.shape) - 1, 0))
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    s = geometry.samples
    name = {"ms": "time", "m": "depth", "ft": "depth"}.get(geometry.sample_unit, "sample")
    unit = "" if geometry.sample_unit == "samples" else f" ({geometry.sample_unit})"
    if geometry.map_unit == "line":
        x_title, y_title = geometry.lateral_names
        x_range = (float(min(geometry.inlines[0], geometry.inlines[-1])),
                   float(max(geometry.inlines[0], geometry.inlines[-1])))
        y_range = (float(min(geometry.xlines[0], geometry.xlines[-1])),
                   float(max(geometry.xlines[0], geometry.xlines[-1])))
    else:
        x_title, y_title = f"X ({geometry.map_unit})", f"Y ({geometry.map_unit})"
        x_range, y_range = (lo[0], hi[0]), (lo[1], hi[1])
    ranges = [*x_range, *y_range, lo[2], hi[2]]
    plotter.show_bounds(bounds=[lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]], axes_ranges=ranges, xtitle=x_title,
                        ytitle=y_title or " ", ztitle=" ", show_zlabels=False, color="black", font_size=10,
                        fmt="%.0f", location="outer", grid=False, ticks="outside", minor_ticks=False)
    # time or depth downward: VTK's axes label only increasing ranges, so the vertical ticks are drawn here, on the
    # box's vertical edge that the camera sees leftmost
    from matplotlib.ticker import MaxNLocator

    camera = plotter.camera
    right = np.cross(np.subtract(camera.focal_point, camera.position), camera.up)
    ends = [(i, j) for i in (0, geometry.shape[0] - 1) for j in (0, geometry.shape[1] - 1)]
    i0, j0 = min(ends, key=lambda e: float(geometry.to_world([[e[0], e[1], 0.0]])[0] @ right))

    values = [v for v in MaxNLocator(nbins=6).tick_values(s.min(), s.max()) if s.min() <= v <= s.max()]
    k = np.interp(values, s if s[-1] >= s[0] else s[::-1], np.arange(s.size) if s[-1] >= s[0]
                  else np.arange(s.size)[::-1])
    edge = geometry.to_world(np.column_stack([np.full_like(k, i0), np.full_like(k, j0), k]))
    labels = [f"{v:g}" for v in values]
    labels[-1] = f"{labels[-1]} {geometry.sample_unit if geometry.sample_unit != 'samples' else ''}".strip()
    labels[0] = f"{name}{unit}  {labels[0]}"
    plotter.add_point_labels(edge, labels, font_size=11, text_color="black", shape=None, show_points=True,
                             point_color="black", point_size=6, always_visible=True, justification_horizontal="right")


def show_seismic(cube, geometry: CubeGeometry | None = None, *, slices=None, faults=None, throws=None,
                 color_faults_by="fault_id", horizons=(), likelihood=None, likelihood_threshold=None,
                 cmap="seismic", clip_percentile=99.0, sliders=False, screenshot=None, window_size=(1024, 768),
                 jupyter_backend=None, camera="iso", title=None):
    """One scene of a seismic cube: inline, crossline and time-slice planes, with faults, horizons and the fault
    likelihood.

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) array_like or None
        Amplitudes, shown with ``cmap`` between ``-c`` and ``c``, ``c`` the ``clip_percentile`` of ``|amplitude|``;
        None for a scene of faults or horizons alone (then ``geometry`` is needed).
    geometry : CubeGeometry, optional
        Default: ``cube_geometry(cube.shape)`` (line indices, sample indices, automatic vertical exaggeration).
    slices : (int or None, int or None, int or None), optional
        Indices of the inline, crossline and sample planes (None leaves one out); default: the middle ones.
    faults : sequence of Fault or pyvista.PolyData, optional
        Faults from :func:`~seismo3d.seismic.trace_faults`, or their surfaces in index space
        (:func:`~seismo3d.viz.fault_surfaces`, ``faults.vtp`` of ``seismo3d faults``).
    throws : sequence of FaultThrow, optional
        For ``color_faults_by='throw'`` with a list of faults.
    color_faults_by : {'fault_id', 'throw'}, optional
    horizons : sequence of Horizon or (n_inlines, n_xlines) array_like, optional
        Horizons in fractional samples (NaN where empty), coloured by time or depth on one shared scale.
    likelihood : (n_inlines, n_xlines, n_samples) array_like, optional
        Fault likelihood in [0, 1], drawn as a semi-transparent volume (transparent below
        ``likelihood_threshold``, rising to 50 % opaque at 1; 20 % when ``faults`` are drawn too, so that their
        colours show through it).
    likelihood_threshold : float, optional
        Default: the likelihood's 95th percentile (the likelihood is high wherever reflectors are weak, so a fixed
        value would fill the cube of some surveys with haze).
    cmap : str, optional
        Matplotlib colour map of the amplitudes (a diverging one: 'seismic', 'RdBu_r', 'gray').
    clip_percentile : float, optional
        In (0, 100].
    sliders : bool, optional
        Add one slider per plane that moves it through the cube (in a window, or in Jupyter with trame; a static
        picture would only show the sliders).
    screenshot : str or os.PathLike, optional
        Render off screen and write this PNG instead of showing the scene.
    window_size : (int, int), optional
    jupyter_backend : str, optional
        See :func:`~seismo3d.viz.plotting.finish_scene` (default trame when installed, else a static image).
    camera : {'iso', 'xz', 'yz', 'xy', 'section'} or camera position, optional
        'section': square to the cube's one inline or crossline (a 2D line), time or depth downward.
    title : str, optional
        Caption; default the geometry's :meth:`~CubeGeometry.describe`.

    Returns
    -------
    pyvista.Plotter
        Shown, or rendered to ``screenshot`` and closed.

    Raises
    ------
    InputError
        Shapes that do not match, slices out of range, an unknown ``color_faults_by``, ``color_faults_by='throw'``
        without throws.
    """
    from .._validation import check_choice

    check_choice(color_faults_by, "color_faults_by", {"fault_id", "throw"})
    if cube is None and geometry is None:
        raise InputError("pass a cube, or a geometry to place faults and horizons without one")
    data = None if cube is None else np.asarray(cube, dtype=np.float32)
    if data is not None and data.ndim != 3:
        raise InputError(f"cube must be (n_inlines, n_xlines, n_samples); got shape {data.shape}")
    geometry = geometry or cube_geometry(data.shape)
    plotter = new_plotter(off_screen=screenshot is not None, window_size=window_size)
    plotter.set_background("white")
    if data is not None:
        grid = seismic_grid(data, geometry)
        clip = symmetric_clip(data, clip_percentile)
        _add_slices(plotter, grid, geometry, _slice_indices(slices, data.shape), cmap=cmap, clim=(-clip, clip),
                    sliders=sliders)
    if faults is not None:
        _add_faults(plotter, faults, throws, geometry, color_faults_by)
    if horizons is not None and len(horizons):
        _add_horizons(plotter, horizons, geometry)
    if likelihood is not None:
        # a fainter haze over fault surfaces, whose colours it would otherwise grey out
        _add_likelihood(plotter, likelihood, geometry, likelihood_threshold,
                        max_opacity=0.5 if faults is None else 0.2)
    plotter.add_mesh(_outline(geometry), color="black")
    plotter.add_text(title or geometry.describe(), font_size=9, color="black")
    x_label, y_label, z_label = geometry.axis_labels()
    plotter.add_axes(xlabel=x_label, ylabel=y_label, zlabel=z_label, color="black")
    if isinstance(camera, str) and camera == "section":
        plotter.view_vector(_section_normal(geometry), viewup=(0.0, 0.0, 1.0))
    else:
        plotter.camera_position = camera
        if isinstance(camera, str):  # room for the tick labels between the box and the colour bars below it
            plotter.camera.zoom(0.88)
            cam = plotter.camera
            up = np.asarray(cam.up, float) / (np.linalg.norm(cam.up) or 1.0)
            lift = 0.07 * float(np.linalg.norm(np.subtract(cam.focal_point, cam.position))) * up
            cam.position, cam.focal_point = tuple(np.subtract(cam.position, lift)), tuple(
                np.subtract(cam.focal_point, lift))  # the camera a little lower: the scene a little higher
    _add_ticks(plotter, geometry)  # after the camera: the time ticks go on the edge it sees leftmost
    return finish_scene(plotter, screenshot=screenshot, backend=jupyter_backend)


def _section_normal(geometry: CubeGeometry) -> np.ndarray:
    """The direction square to a single line's plane, on the side from which its line numbers increase to the right
    (time or depth downward): the camera's position from the plane."""
    along = geometry.axes[0] if geometry.shape[0] > 1 else geometry.axes[1]
    normal = np.cross(geometry.axes[2], along)
    return normal / (np.linalg.norm(normal) or 1.0)
