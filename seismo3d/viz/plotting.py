"""Where a pyvista scene is drawn: a window, Jupyter (trame or a static image) or a PNG rendered off screen.

Off-screen rendering needs no display. VTK's wheels (>= 9.4) choose the OpenGL back end when the first render window
is made: X11 when ``DISPLAY`` is set, otherwise EGL (Mesa's ``libEGL`` with a software or GPU driver), or OSMesa
when ``VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow``. A slim Debian/Ubuntu image renders through EGL with
``apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1 libgl1`` (Mesa's llvmpipe draws on the CPU), or
through OSMesa with ``libosmesa6`` alone. Without a display :func:`new_plotter` asks for EGL directly, so that VTK does
not first try (and warn about) an X server.

In Jupyter a scene is interactive through trame when it is installed (``pip install "seismo3d[notebook]"``), and a
static picture otherwise (which is also what a notebook saved with its outputs shows on a code host).
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

import numpy as np

from .._atomic import atomic_path
from ..errors import InputError

__all__ = ["jupyter_backend", "new_plotter", "finish_scene", "symmetric_clip", "bar_below", "axis_values"]

_WINDOW_ENV = "VTK_DEFAULT_OPENGL_WINDOW"


def jupyter_backend() -> str:
    """The pyvista Jupyter back end seismo3d uses: ``'trame'`` when trame, trame-vtk and trame-vuetify are installed
    (interactive), ``'static'`` otherwise (a picture).

    Returns
    -------
    {'trame', 'static'}
    """
    needed = ("trame", "trame_vtk", "trame_vuetify")
    return "trame" if all(importlib.util.find_spec(name) is not None for name in needed) else "static"


def new_plotter(*, off_screen: bool, window_size=(1024, 768)):
    """A pyvista Plotter; through EGL when there is no display (off screen, or a Jupyter picture).

    Parameters
    ----------
    off_screen : bool
        Render into memory (for :func:`finish_scene` with ``screenshot``).
    window_size : (int, int), optional
        Width and height in pixels.

    Returns
    -------
    pyvista.Plotter

    Raises
    ------
    InputError
        ``window_size`` is not two positive integers.
    """
    import pyvista as pv

    size = [int(v) for v in np.ravel(window_size)]
    if len(size) != 2 or min(size) < 16:
        raise InputError(f"window_size must be (width, height) in pixels, each >= 16; got {window_size!r}")
    if not os.environ.get("DISPLAY") and not os.environ.get(_WINDOW_ENV):
        os.environ[_WINDOW_ENV] = "vtkEGLRenderWindow"  # no X server to try first (see the module's docstring)
    return pv.Plotter(off_screen=off_screen, window_size=size)


def finish_scene(plotter, *, screenshot=None, backend=None):
    """Show a scene, or render it off screen into a PNG.

    Parameters
    ----------
    plotter : pyvista.Plotter
        From :func:`new_plotter` (``off_screen=True`` when ``screenshot`` is given).
    screenshot : str or os.PathLike, optional
        PNG to write (atomically; its folder must exist). The plotter is closed afterwards.
    backend : {'trame', 'static', 'client', 'server', 'html', 'none'}, optional
        pyvista's Jupyter back end; default :func:`jupyter_backend`. Ignored outside Jupyter (a window opens).

    Returns
    -------
    pyvista.Plotter
        ``plotter``.

    Raises
    ------
    InputError
        The PNG's folder does not exist.
    """
    if screenshot is None:
        plotter.show(jupyter_backend=backend or jupyter_backend())
        return plotter
    path = Path(screenshot)
    if not (path.parent if str(path.parent) else Path(".")).is_dir():
        raise InputError(f"cannot write {path}: folder {path.parent} does not exist; create it first")
    img = plotter.screenshot(return_img=True)
    plotter.close()
    from matplotlib.image import imsave

    with atomic_path(path) as tmp:
        imsave(tmp, np.ascontiguousarray(img), format="png")
    return plotter


def symmetric_clip(values, percentile: float = 99.0) -> float:
    """Colour limit of a seismic display: the ``percentile`` of the absolute amplitude (at most 10^6 samples read).

    Parameters
    ----------
    values : array_like
        Amplitudes (NaN and inf ignored).
    percentile : float, optional
        In (0, 100].

    Returns
    -------
    float
        A positive limit ``c``: show amplitudes in ``[-c, c]`` (1.0 for all-zero or empty input).

    Raises
    ------
    InputError
        ``percentile`` outside (0, 100].
    """
    if not 0 < percentile <= 100:
        raise InputError(f"clip_percentile must be in (0, 100]; got {percentile!r}")
    flat = np.asarray(values).ravel()
    flat = flat[:: max(1, flat.size // 1_000_000)]
    flat = np.abs(flat[np.isfinite(flat)])
    c = float(np.percentile(flat, percentile)) if flat.size else 0.0
    return c if c > 0 else 1.0


def bar_below(title: str, **options) -> dict:
    """``scalar_bar_args`` of pyvista's horizontal colour bar at the bottom of a scene, its title clear of the tick
    labels (VTK draws both above the bar: the title's trailing newline lifts it a line).

    Parameters
    ----------
    title : str
        The quantity and its unit, e.g. ``'elevation (m)'``.
    **options
        Other ``scalar_bar_args`` (``fmt``, ``n_labels``, ...).

    Returns
    -------
    dict
    """
    return {"title": f"{title}\n", **options}


def axis_values(axis: np.ndarray, index) -> np.ndarray:
    """The values of an axis (inline numbers, times, ...) at fractional indices, linear between its samples.

    Parameters
    ----------
    axis : (n,) ndarray
        The axis' values at indices 0 .. n - 1.
    index : array_like of float
        Fractional indices.

    Returns
    -------
    float64 ndarray, the shape of ``index``
    """
    return np.interp(np.asarray(index, dtype=np.float64), np.arange(axis.size), axis)
