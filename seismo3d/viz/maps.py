"""Pictures of RGB-D maps: the TSDF mesh with the camera trajectory and the keyframes (pyvista, off screen).

pyvista is imported inside the functions. Without a display (``DISPLAY`` unset) VTK is pointed at its EGL render
window (Mesa's EGL renders without an X server) by :func:`seismo3d.viz.plotting.new_plotter`, unless
``VTK_DEFAULT_OPENGL_WINDOW`` is already set (e.g. to ``vtkOSOpenGLRenderWindow``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["render_map", "show_map"]


def _frustum(pose, size):
    """Line segments of a small camera pyramid at ``pose`` (camera-to-world), for pyvista."""
    corners = np.array([[0, 0, 0], [-1, -0.75, 1.2], [1, -0.75, 1.2], [1, 0.75, 1.2], [-1, 0.75, 1.2]]) * size
    world = corners @ pose[:3, :3].T + pose[:3, 3]
    segments = [(0, 1), (0, 2), (0, 3), (0, 4), (1, 2), (2, 3), (3, 4), (4, 1)]
    return np.array([[world[a], world[b]] for a, b in segments]).reshape(-1, 3)


def _mesh_polydata(mesh):
    """A TriangleMesh (or a pyvista PolyData, e.g. ``pv.read('mesh.ply')``) as PolyData with normals."""
    import pyvista as pv

    if hasattr(mesh, "n_points"):
        # points and faces only: shading from normals pyvista computes (a PLY's stored normals, made active by the
        # reader, lit the map from behind)
        return pv.PolyData(np.asarray(mesh.points), mesh.faces) if mesh.n_points and mesh.n_cells else None
    if not (len(mesh.vertices) and len(mesh.faces)):
        return None
    faces = np.hstack([np.full((len(mesh.faces), 1), 3, np.int64), mesh.faces]).ravel()
    surf = pv.PolyData(np.asarray(mesh.vertices, dtype=np.float64), faces)
    surf.point_data["Normals"] = mesh.normals
    return surf


def _round_length(extent: float) -> float:
    """A round length (1, 2 or 5 times a power of ten) of about a quarter of ``extent``, for a scale bar."""
    target = max(float(extent), 1e-6) / 4.0
    power = 10.0 ** np.floor(np.log10(target))
    return float(max(step * power for step in (1.0, 2.0, 5.0) if step * power <= target))


def _scale_bar(plotter, vertices, up, forward, right) -> float:
    """A black bar of a round length (:func:`_round_length` of the map's width across the view) on the map's floor
    at its front left, labelled with its length; returns the length in metres. In a perspective view a length
    reads true only at the bar's distance from the camera."""
    import pyvista as pv

    along = vertices @ right
    length = _round_length(float(np.ptp(along)))
    start = (np.min(along) * right + np.min(vertices @ forward) * forward + np.min(vertices @ up) * up)
    end = start + length * right
    plotter.add_mesh(pv.Line(start, end), color="black", line_width=6)
    label = f"{length * 100:g} cm" if length < 1 else f"{length:g} m"
    above = (start + end) / 2 + 0.12 * length * forward  # beyond the bar as the camera sees it: above it
    plotter.add_point_labels(above[None], [label], font_size=14, text_color="black", shape=None,
                             show_points=False, always_visible=True, justification_horizontal="center")
    return length


_LEGEND_PX = 150  # the legend's words start this many pixels left of the window's right edge
_LINE_PX = 24  # ... one above the other, this many pixels apart


def show_map(mesh, trajectory, keyframes=(), *, reference=None, screenshot=None, window_size=(1024, 768),
             jupyter_backend=None, title=None):
    """An RGB-D map: the mesh coloured by height, the camera trajectory (red), the keyframes as small camera
    pyramids (blue), a reference trajectory (green, drawn wider under the red one) and a scale bar on the map's
    floor, seen from above and behind the cameras and zoomed to fill the room above the height bar and the legend
    (:func:`~seismo3d.viz.plotting.fit_camera`).

    Parameters
    ----------
    mesh : TriangleMesh or pyvista.PolyData
        World-frame mesh (metres), e.g. :meth:`seismo3d.mapping.TSDFVolume.extract_mesh`, or ``mesh.ply`` of
        ``seismo3d map`` read with pyvista; may be empty.
    trajectory : (N, 4, 4) array_like
        Camera-to-world poses of the frames.
    keyframes : (K, 4, 4) array_like, optional
        Keyframe poses.
    reference : (M, 4, 4) array_like, optional
        A reference trajectory in the map's frame (e.g. the ground truth moved there by
        :func:`seismo3d.mapping.reference_in_map_frame`).
    screenshot : str or os.PathLike, optional
        Render off screen into this PNG instead of showing the scene.
    window_size : (int, int), optional
    jupyter_backend : str, optional
        See :func:`seismo3d.viz.plotting.finish_scene`.
    title : str, optional

    Returns
    -------
    pyvista.Plotter

    Raises
    ------
    InputError
        Malformed poses.
    """
    import pyvista as pv

    from .plotting import arrange_colour_bars, bar_below, finish_scene, fit_camera, new_plotter

    traj = np.asarray(trajectory, dtype=np.float64).reshape(-1, 4, 4)
    kfs = np.asarray(keyframes, dtype=np.float64).reshape(-1, 4, 4)
    if not (np.all(np.isfinite(traj)) and np.all(np.isfinite(kfs))):
        raise InputError("trajectory and keyframes must be finite (N, 4, 4) poses")
    plotter = new_plotter(off_screen=screenshot is not None, window_size=window_size)
    plotter.set_background("white")
    surf = _mesh_polydata(mesh)
    vertices = np.zeros((0, 3)) if surf is None else np.asarray(surf.points)
    if surf is not None:
        # colour by height along the camera's mean "up" (-y of the cameras)
        up = -traj[:, :3, 1].mean(axis=0) if len(traj) else np.array([0.0, 0.0, 1.0])
        up /= max(np.linalg.norm(up), 1e-12)
        surf.point_data["height (m)"] = vertices @ up
        plotter.add_mesh(surf, scalars="height (m)", cmap="cividis", smooth_shading=True,
                         scalar_bar_args=bar_below("height (m)"))
    size = 0.08
    ref = np.zeros((0, 4, 4)) if reference is None else np.asarray(reference, dtype=np.float64).reshape(-1, 4, 4)
    if len(ref) >= 2:  # under the estimate, wider: where they agree, green edges the red line
        plotter.add_mesh(pv.lines_from_points(ref[:, :3, 3]), color="limegreen", line_width=12)
    if len(traj) >= 2:
        plotter.add_mesh(pv.lines_from_points(traj[:, :3, 3]), color="red", line_width=4)
    if len(kfs):
        seg = np.concatenate([_frustum(p, size) for p in kfs])
        plotter.add_mesh(pv.line_segments_from_points(seg), color="blue", line_width=3)
    room = arrange_colour_bars(plotter)  # the height bar's slot at the bottom, sized to its title and labels
    # the legend as coloured words at the lower right, beside the height bar, the map above both (VTK's legend box
    # cut its longest label off at the window's edge)
    entries = [(name, colour) for name, colour, shown in (("ground truth", "limegreen", len(ref) >= 2),
                                                          ("trajectory", "red", len(traj) >= 2),
                                                          ("keyframes", "blue", len(kfs) > 0)) if shown]
    width, height = (int(v) for v in np.ravel(window_size))
    for n, (name, colour) in enumerate(entries):
        plotter.add_text(name, position=(width - _LEGEND_PX, _LINE_PX * (len(entries) - 1 - n) + 6), font_size=12,
                         color=colour)
    room = (room[0], max(room[1], (_LINE_PX * len(entries) + 12) / height), room[2], room[3])
    if title:
        plotter.add_text(title, font_size=9, color="black")
    # look down on the scene from above and behind the cameras (their mean viewing direction), everything in view
    if len(traj):
        up = -traj[:, :3, 1].mean(axis=0)
        up /= max(np.linalg.norm(up), 1e-12)
        forward = traj[:, :3, 2].mean(axis=0)
        forward -= (forward @ up) * up
        forward /= max(np.linalg.norm(forward), 1e-12)
        centre = vertices.mean(axis=0) if len(vertices) else traj[:, :3, 3].mean(axis=0)
        if len(vertices):
            _scale_bar(plotter, vertices, up, forward, np.cross(forward, up))
        eye = centre + 3.0 * (-0.8 * forward + 1.0 * up)
        plotter.camera_position = [tuple(eye), tuple(centre), tuple(forward)]
        plotter.reset_camera()
    fit_camera(plotter, room)  # the map, its trajectory and its scale bar fill the room the bar and legend leave
    return finish_scene(plotter, screenshot=screenshot, backend=jupyter_backend)


def render_map(mesh, trajectory, keyframes, path, *, window_size=(1280, 960), reference=None, title=None):
    """Render the map mesh, the camera trajectory and the keyframes to a PNG, off screen (:func:`show_map`).

    Parameters
    ----------
    mesh : TriangleMesh
        World-frame mesh (metres), e.g. :meth:`seismo3d.mapping.TSDFVolume.extract_mesh`; may be empty.
    trajectory : (N, 4, 4) array_like
        Camera-to-world poses of the frames, drawn as a red line.
    keyframes : (K, 4, 4) array_like
        Keyframe poses, drawn as small camera pyramids (blue).
    path : str or os.PathLike
        The PNG to write (atomically).
    window_size : (int, int)
        Pixels.
    reference : (M, 4, 4) array_like, optional
        A reference trajectory (already in the map's frame) drawn in green.
    title : str, optional
        A line of text at the top left.

    Returns
    -------
    pathlib.Path
        The written file.

    Raises
    ------
    InputError
        Malformed poses.
    """
    show_map(mesh, trajectory, keyframes, reference=reference, screenshot=path, window_size=window_size, title=title)
    return Path(path)
