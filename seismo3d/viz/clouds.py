"""Point clouds before and after a registration (pyvista) and image matches side by side (matplotlib)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .plotting import finish_scene, new_plotter

__all__ = ["show_point_clouds", "plot_matches"]

_COLOURS = ("tab:orange", "tab:blue", "tab:green", "tab:red", "tab:purple")


def show_point_clouds(clouds, *, labels=None, transforms=None, point_size=2.0, screenshot=None,
                      window_size=(900, 650), jupyter_backend=None, camera="iso", title=None):
    """Point clouds in one scene, one colour each (e.g. a source moved by a registration over its target).

    Parameters
    ----------
    clouds : sequence of (N_i, 3) array_like of float
        Points, in one frame (metres, or any common unit).
    labels : sequence of str, optional
        Legend entries, one per cloud.
    transforms : sequence of (4, 4) array_like or None, optional
        Applied to each cloud before drawing (None leaves one as it is).
    point_size : float, optional
        Pixels.
    screenshot : str or os.PathLike, optional
        Render off screen into this PNG instead of showing the scene.
    window_size : (int, int), optional
    jupyter_backend : str, optional
        See :func:`seismo3d.viz.plotting.finish_scene`.
    camera : str or camera position, optional
    title : str, optional

    Returns
    -------
    pyvista.Plotter

    Raises
    ------
    InputError
        A cloud that is not (N, 3), or labels / transforms of another length than ``clouds``.
    """
    import pyvista as pv

    clouds = [np.asarray(c, dtype=np.float64) for c in clouds]
    if not clouds or any(c.ndim != 2 or c.shape[1] != 3 or c.shape[0] == 0 for c in clouds):
        raise InputError("clouds must be a list of non-empty (N, 3) point arrays")
    for name, seq in (("labels", labels), ("transforms", transforms)):
        if seq is not None and len(seq) != len(clouds):
            raise InputError(f"{name} has {len(seq)} entries for {len(clouds)} clouds; pass one per cloud")
    plotter = new_plotter(off_screen=screenshot is not None, window_size=window_size)
    plotter.set_background("white")
    for n, cloud in enumerate(clouds):
        m = None if transforms is None else transforms[n]
        if m is not None:
            m = np.asarray(m, dtype=np.float64)
            cloud = cloud @ m[:3, :3].T + m[:3, 3]
        plotter.add_mesh(pv.PolyData(cloud), color=_COLOURS[n % len(_COLOURS)], point_size=point_size,
                         render_points_as_spheres=False, label=None if labels is None else str(labels[n]))
    if labels is not None:
        plotter.add_legend(bcolor="white", face="rectangle", loc="lower left", size=(0.3, 0.07 * len(clouds)))
    if title:
        plotter.add_text(title, font_size=9, color="black")
    plotter.camera_position = camera
    return finish_scene(plotter, screenshot=screenshot, backend=jupyter_backend)


def _thin_matches(xy, *, shape, max_matches=80) -> np.ndarray:
    """A spatially even subset of matches: at most one per cell of a grid over the first image, the grid fine
    enough to hold about ``max_matches`` cells, the first match of each cell in the order given kept.

    Parameters
    ----------
    xy : (N, 2) array_like of float
        The matches' pixels in the first image (x right, y down).
    shape : (int, int)
        The first image's height and width, pixels.
    max_matches : int, optional
        At most this many indices are returned (at least 1).

    Returns
    -------
    (M,) int64 ndarray
        Indices into ``xy``, increasing, ``M <= min(N, max_matches)``.

    Raises
    ------
    InputError
        ``max_matches`` < 1.
    """
    if int(max_matches) < 1:
        raise InputError(f"max_matches must be >= 1; got {max_matches!r}")
    p = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    if not p.shape[0]:
        return np.zeros(0, np.int64)
    height, width = (float(v) for v in shape[:2])
    cell = float(np.sqrt(max(height * width, 1.0) / int(max_matches)))
    n_x = max(int(np.ceil(width / cell)), 1)
    cells = (np.clip(p[:, 1] // cell, 0, None) * n_x + np.clip(p[:, 0] // cell, 0, n_x - 1)).astype(np.int64)
    _, first = np.unique(cells, return_index=True)
    return np.sort(first)[: int(max_matches)]


def plot_matches(image1, image2, xy1, xy2, *, correct=None, max_lines=80, title=None, ax=None):
    """Two images side by side with lines between matched points, a readable subset of them: at most one match per
    cell of a grid over the first image (the first one in each cell, in the order given: pass them best first), each
    line in a colour of its own (green where correct and red where not, when ``correct`` is given); the picture says
    how many are drawn of how many.

    Parameters
    ----------
    image1, image2 : (H, W) or (H, W, 3) array_like
        Grey or colour images.
    xy1, xy2 : (N, 2) array_like of float
        Matched pixel coordinates (x right, y down, origin at the centre of the top-left pixel).
    correct : (N,) array_like of bool, optional
        Which matches are correct (e.g. reprojection error under 3 pixels); default: all drawn, coloured in turn.
    max_lines : int, optional
        At most this many matches are drawn, spread over the first image.
    title : str, optional
    ax : matplotlib.axes.Axes, optional
        Where to draw; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``xy1`` and ``xy2`` (and ``correct``) differ in length.
    """
    from matplotlib import colormaps
    from matplotlib.figure import Figure

    a, b = np.asarray(image1), np.asarray(image2)
    p, q = np.asarray(xy1, dtype=np.float64).reshape(-1, 2), np.asarray(xy2, dtype=np.float64).reshape(-1, 2)
    if p.shape != q.shape or (correct is not None and np.asarray(correct).shape != (p.shape[0],)):
        raise InputError(f"xy1 {p.shape}, xy2 {q.shape} and correct must describe the same matches")
    height = max(a.shape[0], b.shape[0])
    pad = [(0, height - a.shape[0]), (0, 0)] + [(0, 0)] * (a.ndim - 2)
    padb = [(0, height - b.shape[0]), (0, 0)] + [(0, 0)] * (b.ndim - 2)
    both = np.concatenate([np.pad(a, pad), np.pad(b, padb)], axis=1)
    if ax is None:
        fig = Figure(figsize=(10, 10 * height / both.shape[1] + 0.8), layout="constrained")
        ax = fig.subplots()
    else:
        fig = ax.figure
    ax.imshow(both, cmap="gray" if both.ndim == 2 else None)
    keep = _thin_matches(p, shape=a.shape, max_matches=max_lines)
    ok = np.ones(p.shape[0], bool) if correct is None else np.asarray(correct, bool)
    tab20 = colormaps["tab20"]
    for m, n in enumerate(keep):
        colour = ("tab:green" if ok[n] else "tab:red") if correct is not None else tab20(m % 20)
        ax.plot([p[n, 0], q[n, 0] + a.shape[1]], [p[n, 1], q[n, 1]], lw=1.0, color=colour, marker="o", ms=3,
                mec="black", mew=0.4)
    ax.set_axis_off()
    drawn = (f"{keep.size} of {p.shape[0]} matches drawn" if keep.size < p.shape[0]
             else f"all {p.shape[0]} matches drawn")
    if keep.size < p.shape[0]:
        drawn += " (at most one per cell of a grid over the left image)"
    ax.set_title(f"{title}\n{drawn}" if title else drawn, fontsize=10)
    return fig
