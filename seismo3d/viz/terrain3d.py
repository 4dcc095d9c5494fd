"""A DEM in 3D (pyvista): the surface coloured by elevation, with lineaments and a planned path draped over it.

Coordinates are metres east and north of the DEM's centre (:attr:`seismo3d.terrain.Dem.metric_axes`, which also turns
the degrees of a geographic DEM into metres) and elevation in metres times the vertical exaggeration.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .plotting import arrange_colour_bars, finish_scene, fit_camera, new_plotter

__all__ = ["terrain_exaggeration", "terrain_surface_mesh", "show_terrain"]


def _metric(dem, rows, cols):
    """Metres east and north of the DEM's centre of (fractional) pixel indices."""
    h, w = dem.shape
    axes = dem.metric_axes  # (east, north) per (column step, row step)
    dc, dr = np.asarray(cols, np.float64) - (w - 1) / 2.0, np.asarray(rows, np.float64) - (h - 1) / 2.0
    return axes[0, 0] * dc + axes[0, 1] * dr, axes[1, 0] * dc + axes[1, 1] * dr


def terrain_exaggeration(dem) -> float:
    """A vertical exaggeration that shows the relief without inventing mountains: the relief at most a 40th of the
    DEM's longer side, the factor between 1 and 5 (two significant digits). A gentle DEM (151 m over 30 km) gets
    5x, a rugged one 1x.

    Parameters
    ----------
    dem : seismo3d.terrain.DEM
        Elevations in metres with metre pixel sizes (:func:`seismo3d.terrain.read_dem`).

    Returns
    -------
    float
        The factor, in [1, 5].
    """
    z = dem.elevation_m[dem.valid]
    relief = float(np.ptp(z)) if z.size else 0.0
    dy, dx = dem.pixel_size_m
    side = max(dy * (dem.shape[0] - 1), dx * (dem.shape[1] - 1))
    if relief <= 0:
        return 1.0
    return float(np.clip(float(f"{side / 40.0 / relief:.2g}"), 1.0, 5.0))


def terrain_surface_mesh(dem, *, vertical_exaggeration=1.0):
    """A DEM as a pyvista StructuredGrid in metres about its centre, cells without elevation removed.

    Parameters
    ----------
    dem : seismo3d.terrain.Dem
    vertical_exaggeration : float, optional

    Returns
    -------
    pyvista.UnstructuredGrid or pyvista.StructuredGrid
        Point array ``elevation`` (m, float32); a StructuredGrid when every cell has an elevation.

    Raises
    ------
    InputError
        A DEM without any elevation, or a non-positive exaggeration.
    """
    import pyvista as pv

    if not vertical_exaggeration > 0:
        raise InputError(f"vertical_exaggeration must be > 0; got {vertical_exaggeration!r}")
    z = dem.elevation_m
    valid = np.isfinite(z)
    if not valid.any():
        raise InputError("the DEM has no elevation (every cell is nodata); pass another raster")
    rows, cols = np.meshgrid(np.arange(dem.shape[0]), np.arange(dem.shape[1]), indexing="ij")
    east, north = _metric(dem, rows, cols)
    filled = np.where(valid, z, np.nanmin(z))
    grid = pv.StructuredGrid(east, north, filled * vertical_exaggeration)
    grid.point_data["elevation"] = filled.astype(np.float32).ravel(order="F")
    if valid.all():
        return grid
    grid.point_data["valid"] = valid.astype(np.uint8).ravel(order="F")
    return grid.threshold(0.5, scalars="valid")


def _draped(dem, rows, cols, exaggeration, lift):
    """Points along pixel positions, at the DEM's elevation (bilinear) plus ``lift`` metres (before exaggeration)."""
    from scipy.ndimage import map_coordinates

    z = dem.elevation_m
    filled = np.where(np.isfinite(z), z, np.nanmin(z))
    height = map_coordinates(filled, [rows, cols], order=1, mode="nearest")
    east, north = _metric(dem, rows, cols)
    return np.column_stack([east, north, (height + lift) * exaggeration])


def _polyline(points_per_line):
    import pyvista as pv

    pts = np.concatenate(points_per_line)
    cells, start = [], 0
    for p in points_per_line:
        cells.append(np.concatenate([[len(p)], np.arange(start, start + len(p))]))
        start += len(p)
    return pv.PolyData(pts, lines=np.concatenate(cells).astype(np.int64))


_LEGEND_SIZE = (0.22, 0.14)  # the legend's box at the upper left, as fractions of the window


def show_terrain(dem, *, lineaments=None, path=None, vertical_exaggeration=None, screenshot=None,
                 window_size=(1024, 768), jupyter_backend=None, camera=None, title=None):
    """A DEM in 3D with its lineaments and a planned path draped over the surface.

    Parameters
    ----------
    dem : seismo3d.terrain.Dem
        From :func:`~seismo3d.terrain.read_dem`; coloured by elevation (m).
    lineaments : seismo3d.terrain.Lineaments, optional
        From :func:`~seismo3d.terrain.extract_lineaments` of the same DEM: red lines on the surface.
    path : seismo3d.terrain.GridPath or (K, 2) array_like of int, optional
        A planned path (:func:`~seismo3d.terrain.astar`) as (row, col) cells: a black line, start and goal marked
        (green, red).
    vertical_exaggeration : float, optional
        Default: the relief at most a 40th of the DEM's longer side, the factor between 1 and 5 (stated in the
        picture's title).
    screenshot : str or os.PathLike, optional
        Render off screen into this PNG instead of showing the scene.
    window_size : (int, int), optional
    jupyter_backend : str, optional
        See :func:`seismo3d.viz.plotting.finish_scene`.
    camera : str or camera position, optional
        Default: from the south, looking north and down at about 35 degrees, zoomed so that the terrain fills the
        room the colour bar and the legend leave (:func:`~seismo3d.viz.plotting.fit_camera`); a camera given is
        kept as it is.
    title : str, optional
        Caption; default the DEM's size, relief and the exaggeration.

    Returns
    -------
    pyvista.Plotter

    Raises
    ------
    InputError
        A DEM without elevation, path cells outside the DEM.
    """
    ve = terrain_exaggeration(dem) if vertical_exaggeration is None else float(vertical_exaggeration)
    surface = terrain_surface_mesh(dem, vertical_exaggeration=ve)
    z = dem.elevation_m[dem.valid]
    dy, dx = dem.pixel_size_m
    lift = 0.01 * float(np.ptp(z)) + 0.5  # lines just above the surface (metres, before exaggeration)
    plotter = new_plotter(off_screen=screenshot is not None, window_size=window_size)
    plotter.set_background("white")
    # the colour bar upright on the right: at the bottom it hid the goal of paths ending in a near corner
    plotter.add_mesh(surface, scalars="elevation", cmap="gist_earth", smooth_shading=True,
                     scalar_bar_args={"title": "elevation\n(m)", "fmt": "%.0f", "vertical": True})
    if lineaments is not None and len(lineaments):
        lines = []
        for r0, c0, r1, c1 in lineaments.segments_px:
            n = max(2, int(np.hypot(r1 - r0, c1 - c0)) + 1)
            lines.append(_draped(dem, np.linspace(r0, r1, n), np.linspace(c0, c1, n), ve, lift))
        plotter.add_mesh(_polyline(lines), color="red", line_width=3, label="lineaments")
    if path is not None:
        import pyvista as pv

        cells = np.asarray(getattr(path, "cells", path), dtype=np.float64).reshape(-1, 2)
        if cells.size and (cells.min() < 0 or np.any(cells.max(axis=0) > np.array(dem.shape) - 1)):
            raise InputError(f"path cells lie outside the DEM's {dem.shape} grid; pass a path planned on this DEM")
        line = _draped(dem, cells[:, 0], cells[:, 1], ve, lift)
        plotter.add_mesh(_polyline([line]), color="black", line_width=5, label="planned path")
        radius = 0.012 * max(dy * dem.shape[0], dx * dem.shape[1])
        plotter.add_mesh(pv.Sphere(radius=radius, center=line[0]), color="limegreen", label="start")
        plotter.add_mesh(pv.Sphere(radius=radius, center=line[-1]), color="crimson", label="goal")
    room = arrange_colour_bars(plotter)  # the elevation bar's slot at the right, sized to its title and labels
    if lineaments is not None or path is not None:  # the legend above the terrain
        plotter.add_legend(bcolor="white", face="rectangle", loc="upper left", size=_LEGEND_SIZE)
        room = (room[0], room[1], room[2], min(room[3], 1 - _LEGEND_SIZE[1] - 0.01))
    width_km = dx * (dem.shape[1] - 1) / 1000.0
    height_km = dy * (dem.shape[0] - 1) / 1000.0
    plotter.add_text(title or (f"DEM {width_km:.1f} x {height_km:.1f} km, relief {np.ptp(z):.0f} m, vertical "
                               f"exaggeration {ve:.2g}x"), font_size=9, color="black", position="upper_right")
    plotter.add_axes(xlabel="east (m)", ylabel="north (m)", zlabel="up", color="black")
    if camera is None:
        side = max(dx * dem.shape[1], dy * dem.shape[0])
        top = float(np.nanmax(z)) * ve
        plotter.camera_position = [(0.0, -1.3 * side, top + 0.9 * side), (0.0, 0.0, float(np.nanmin(z)) * ve),
                                   (0.0, 0.0, 1.0)]
        fit_camera(plotter, room)  # the terrain fills the room the bar and the legend leave
    else:
        plotter.camera_position = camera
    return finish_scene(plotter, screenshot=screenshot, backend=jupyter_backend)
