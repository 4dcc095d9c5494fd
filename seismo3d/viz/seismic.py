"""A seismic cube in 3D: one pyvista scene with slices, faults, horizons and likelihood (:func:`show_seismic`).

The cube's geometry and grid are :mod:`seismo3d.viz.geometry`'s (:class:`~seismo3d.viz.geometry.CubeGeometry`):
faults and horizons from :mod:`seismo3d.seismic` are in index space and placed by it.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .fault_meshes import fault_surfaces
from .geometry import CubeGeometry, cube_geometry, grid_index, place_index_mesh, seismic_grid
from .horizons import horizon_surface
from .plotting import arrange_colour_bars, bar_below, finish_scene, fit_camera, new_plotter, symmetric_clip

__all__ = ["show_seismic"]

_FAULT_OPACITY = 0.6  # fault surfaces let the slices behind them show


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
        bar = dict(show_scalar_bar=True,
                   scalar_bar_args=bar_below("amplitude", fmt="%.3g", n_labels=3)) if first else {}
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
                                                   n_labels=0))
        return
    values = np.asarray(mesh.point_data["throw"], dtype=np.float64)
    if not np.isfinite(values).any():
        raise InputError("color_by='throw' needs measured throws; pass throws= (FaultInterpretation.throws)")
    lim = float(np.nanpercentile(np.abs(values), 98)) or 1.0
    plotter.add_mesh(mesh, scalars="throw", cmap="PuOr_r", clim=(-lim, lim), nan_color="lightgrey",
                     line_width=3, ambient=0.3, opacity=_FAULT_OPACITY,
                     scalar_bar_args=bar_below("throw (samples, + normal)"))


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
                         scalar_bar_args={"title": f"horizon\n{name}{unit}", "vertical": True, "fmt": "%.4g"})


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
    bar = {"title": "fault\nlikelihood", "vertical": True, "fmt": "%.2f"}
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


def _corners(geometry: CubeGeometry) -> np.ndarray:
    """The (8, 3) corners of the cube in index space."""
    corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=np.float64)
    return corners * np.maximum(np.array(geometry.shape) - 1, 0)


# pixels kept around the box (left, bottom, right, top): the time or depth numbers at its left, the lateral numbers
# and axis titles below and right of it, the caption's line and half a time number above it
_LABEL_ROOM = (80, 45, 45, 30)
_MAX_ROOM = (0.1, 0.08)  # ... at most these viewport fractions (a small window: the box first)


def _outline(geometry: CubeGeometry):
    """The cube's 12 edges in the scene."""
    import pyvista as pv

    corners = _corners(geometry)
    edges = [(a, b) for a in range(8) for b in range(a + 1, 8) if np.count_nonzero(corners[a] != corners[b]) == 1]
    lines = np.array([[2, a, b] for a, b in edges], dtype=np.int64).ravel()
    return pv.PolyData(geometry.to_world(corners), lines=lines)


def _lateral_ticks(plotter, lo, hi, ranges, eye, right) -> None:
    """Round numbers along the two lateral edges of the box's bottom nearest the camera (inline / crossline numbers
    or map X / Y), at most 6 a side and none within 8 % of the edge's ends, so that the two rows of numbers do not
    meet at the corner they share; a tick on the edge, its number a little outside the box."""
    from matplotlib.ticker import MaxNLocator

    near = [hi[d] if abs(eye[d] - hi[d]) < abs(eye[d] - lo[d]) else lo[d] for d in (0, 1)]  # the front edges
    span = np.subtract(hi, lo)
    for axis, (first, last) in enumerate(ranges):
        other = 1 - axis
        if last <= first or span[axis] <= 0:
            continue
        margin = 0.08 * (last - first)
        values = [v for v in MaxNLocator(nbins=6, steps=[1, 2, 2.5, 5, 10]).tick_values(first, last)
                  if first + margin <= v <= last - margin]
        if not values:
            continue
        points = np.zeros((len(values), 3))
        points[:, axis] = lo[axis] + (np.array(values) - first) / (last - first) * span[axis]
        points[:, other], points[:, 2] = near[other], lo[2]
        plotter.add_points(points.copy(), color="black", point_size=6, render_points_as_spheres=False)  # the ticks
        outward = np.zeros(3)
        outward[other] = 1.0 if near[other] == hi[other] else -1.0
        points += outward * 0.04 * max(span[other], 1e-9)
        leftward = float(outward @ right) < 0  # the numbers end at the tick on the left of the picture
        plotter.add_point_labels(points, [f"{v:.0f}" for v in values], font_size=10, text_color="black",
                                 shape=None, show_points=False, always_visible=True,
                                 justification_horizontal="right" if leftward else "left")


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
    # the box and the axes' titles by VTK; the numbers drawn here (below): VTK labels both ends of every axis, and
    # the two lateral axes meet at the box's front corner, where their end labels ran into each other
    plotter.show_bounds(bounds=[lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]], axes_ranges=ranges, xtitle=x_title,
                        ytitle=y_title or " ", ztitle=" ", show_xlabels=False, show_ylabels=False,
                        show_zlabels=False, color="black", font_size=10, location="outer", grid=False, ticks=None,
                        minor_ticks=False)
    from matplotlib.ticker import MaxNLocator

    camera = plotter.camera
    right = np.cross(np.subtract(camera.focal_point, camera.position), camera.up)
    _lateral_ticks(plotter, lo, hi, (x_range, y_range), np.asarray(camera.position, float), right)
    # time or depth downward: VTK's axes label only increasing ranges, so the vertical ticks are drawn here, on the
    # box's vertical edge that the camera sees leftmost
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
    free = arrange_colour_bars(plotter)  # every bar its own slot: amplitude, faults or throw below; the rest right
    plotter.add_text(title or geometry.describe(), font_size=9, color="black")
    x_label, y_label, z_label = geometry.axis_labels()
    plotter.add_axes(xlabel=x_label, ylabel=y_label, zlabel=z_label, color="black")
    if isinstance(camera, str) and camera == "section":
        plotter.view_vector(_section_normal(geometry), viewup=(0.0, 0.0, 1.0))
    else:
        plotter.camera_position = camera
    if isinstance(camera, str):  # the box, with room for its tick labels, where the colour bars leave room
        fit_camera(plotter, free, points=geometry.to_world(_corners(geometry)), margin_px=_LABEL_ROOM,
                   max_margin=_MAX_ROOM)
    _add_ticks(plotter, geometry)  # after the camera: the time ticks go on the edge it sees leftmost
    return finish_scene(plotter, screenshot=screenshot, backend=jupyter_backend)


def _section_normal(geometry: CubeGeometry) -> np.ndarray:
    """The direction square to a single line's plane, on the side from which its line numbers increase to the right
    (time or depth downward): the camera's position from the plane."""
    along = geometry.axes[0] if geometry.shape[0] > 1 else geometry.axes[1]
    normal = np.cross(geometry.axes[2], along)
    return normal / (np.linalg.norm(normal) or 1.0)
