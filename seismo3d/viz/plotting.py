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

__all__ = ["jupyter_backend", "new_plotter", "finish_scene", "symmetric_clip", "bar_below", "arrange_colour_bars",
           "fit_camera", "axis_values"]

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


_BAR_PX = 18  # thickness of a colour bar's colour strip, in pixels
_PAD_PX = 6  # between a bar's strip, its tick labels and its title, and between two bars' slots, in pixels
_BAR_LENGTH = 0.45  # a vertical bar's height, as a fraction of the window's
_MAX_SLOT = 0.4  # a horizontal bar's slot's width at most, as a fraction of the window's (one bar: not a row)


def _text_size(prop, text: str) -> tuple[int, int]:
    """Width and height in pixels of ``text`` drawn with the VTK text property ``prop`` (VTK's own measure)."""
    from vtkmodules.vtkRenderingCore import vtkTextRenderer

    box = [0, 0, 0, 0]
    if not text.strip() or not vtkTextRenderer().GetBoundingBox(prop, text, box, 72):
        return 0, 0
    return box[1] - box[0] + 1, box[3] - box[2] + 1


def _tick_labels(actor) -> list[str]:
    """The tick labels VTK draws on a colour bar: its number of labels, evenly over its lookup table's range, in its
    label format."""
    if not actor.GetDrawTickLabels():
        return []
    lo, hi = actor.GetLookupTable().GetRange()
    return [actor.GetLabelFormat() % v for v in np.linspace(lo, hi, actor.GetNumberOfLabels())]


def _fit_tick_labels(bar, length_px: float) -> None:
    """Fewer tick labels on a horizontal bar whose labels would run into each other along its ``length_px`` long
    strip: the most of a subset of its labels' values (every 2nd, 4th, ... of them, ends kept) that leaves a gap of
    3/4 of the labels' font size (an em) between neighbours (VTK draws them at their font size, evenly from end to
    end)."""
    first, prop = bar.GetNumberOfLabels(), bar.GetLabelTextProperty()
    for n in (k for k in range(first, 1, -1) if (first - 1) % (k - 1) == 0):
        bar.SetNumberOfLabels(n)
        widest = max((_text_size(prop, t)[0] for t in _tick_labels(bar)), default=0)
        if length_px / (n - 1) >= widest + 0.75 * prop.GetFontSize():
            return


def arrange_colour_bars(plotter, *, left: float = 0.22, right: float = 0.99, bottom: float = 0.02,
                        vertical_bottom: float = 0.3) -> tuple[float, float, float, float]:
    """Give every colour bar of a scene its own slot, sized to hold its strip, tick labels and title.

    Vertical bars stand side by side at the right of the window, from ``right`` leftward; horizontal bars share one
    row at the bottom, from ``left`` toward ``right``, each at most 40 % of the window's width (left of ``left``
    stays free for the orientation widget). Each slot is measured with VTK's text renderer at the bars' font sizes,
    so that neighbouring bars' titles and labels do not run into each other (pyvista places each bar alone: two
    vertical bars at its default positions overlap).
    Fonts are made smaller when the vertical bars would take over 30 % of the window's width, or the bottom row
    over 20 % of its height; a horizontal bar keeps fewer of its tick labels (every 2nd, 4th, ..., its ends kept)
    when they would run into each other along its strip. The slots follow ``vtkScalarBarActor``'s layout with
    unconstrained font sizes (pyvista's): a vertical bar's title above its strip and labels right of it, a
    horizontal bar's labels and then its title above its strip, the strip ``BarRatio`` of the slot's thickness.

    Parameters
    ----------
    plotter : pyvista.Plotter
        A scene whose colour bars are all added (``plotter.scalar_bars``), not yet rendered.
    left, right : float, optional
        Viewport fractions (0 at the window's left, 1 at its right) the bars keep within.
    bottom : float, optional
        Viewport fraction of the bottom row's lower edge.
    vertical_bottom : float, optional
        Viewport fraction of the vertical bars' lower edge.

    Returns
    -------
    (x_min, y_min, x_max, y_max) : tuple of float
        The part of the viewport the bars leave to the scene: left of the vertical bars, above the bottom row.
    """
    width, height = (int(v) for v in plotter.window_size)
    bars = list(plotter.scalar_bars.values())
    vertical = [b for b in bars if b.GetOrientation() == 1]
    horizontal = [b for b in bars if b.GetOrientation() == 0]
    for bar in bars:
        if not bar.GetDrawTickLabels():  # no label actors at all: VTK lifts the title by their height even unseen
            bar.SetNumberOfLabels(0)
    for bar in horizontal:  # VTK measures a horizontal bar's labels before it centres them on their values, and the
        # first render draws them as measured (left-aligned at their values): centred from the start, every render
        # draws them alike (vtkScalarBarActor::ConfigureTicks, VTK 9)
        bar.GetLabelTextProperty().SetJustificationToCentered()

    def vertical_px(bar):  # the slot's width: the strip and its labels beside it, or the title above it if wider
        labels = max((_text_size(bar.GetLabelTextProperty(), t)[0] for t in _tick_labels(bar)), default=0)
        return max(_text_size(bar.GetTitleTextProperty(), bar.GetTitle())[0], _BAR_PX + _PAD_PX + labels) + _PAD_PX

    def horizontal_px(bar):  # the slot's height, its end labels' width: strip, labels above it, title above them
        sizes = np.array([_text_size(bar.GetLabelTextProperty(), t) for t in _tick_labels(bar)] or [(0, 0)])
        title_h = _text_size(bar.GetTitleTextProperty(), bar.GetTitle())[1]
        return _BAR_PX + int(sizes[:, 1].max()) + title_h + 2 * _PAD_PX, int(sizes[:, 0].max())

    scale = min(1.0, 0.3 * width / max(sum(vertical_px(b) for b in vertical), 1),
                0.2 * height / max(max((horizontal_px(b)[0] for b in horizontal), default=0), 1))
    if scale < 1:  # a small window: smaller text rather than a squeezed scene
        for bar in bars:
            for prop in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty(), bar.GetAnnotationTextProperty()):
                prop.SetFontSize(max(6, int(prop.GetFontSize() * scale)))
    x_max = right
    for bar in vertical:
        w = vertical_px(bar)
        x_max -= w / width
        bar.SetPosition(x_max, vertical_bottom)
        bar.SetWidth(w / width)
        bar.SetHeight(_BAR_LENGTH)
        bar.SetBarRatio(_BAR_PX / w)
    y_max = bottom
    if horizontal:
        slot = min((right - left) / len(horizontal), _MAX_SLOT)
        for n, bar in enumerate(horizontal):
            h, label_w = horizontal_px(bar)
            inset = (label_w / 2 + _PAD_PX) / width  # the end labels are centred on the strip's ends
            _fit_tick_labels(bar, (slot - 2 * inset) * width)
            bar.SetPosition(left + n * slot + inset, bottom)
            bar.SetWidth(slot - 2 * inset)
            bar.SetHeight(h / height)
            bar.SetBarRatio(_BAR_PX / h)
            y_max = max(y_max, bottom + h / height)
    return 0.0, y_max, x_max, 1.0


def _scene_points(renderer) -> np.ndarray:
    """The (N, 3) world points of every visible 3D actor of ``renderer`` (the eight corners of the bounds of a volume
    or of a dataset without explicit points); text and other 2D actors are left out."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkDataSet, vtkPointSet
    from vtkmodules.vtkRenderingCore import vtkActor, vtkVolume

    def corners(b):
        return np.array([[x, y, z] for x in b[:2] for y in b[2:4] for z in b[4:]], dtype=np.float64)

    found = []
    props = renderer.GetViewProps()
    for n in range(props.GetNumberOfItems()):
        prop = props.GetItemAsObject(n)
        if not prop.GetVisibility():
            continue
        if isinstance(prop, vtkVolume):
            found.append(corners(prop.GetBounds()))
            continue
        mapper = prop.GetMapper() if isinstance(prop, vtkActor) else None
        fed = mapper is not None and mapper.GetNumberOfInputPorts() and mapper.GetNumberOfInputConnections(0)
        data = mapper.GetInputDataObject(0, 0) if fed else None
        if not isinstance(data, vtkDataSet) or not data.GetNumberOfPoints():
            continue
        if not isinstance(data, vtkPointSet):
            found.append(corners(prop.GetBounds()))
            continue
        matrix = np.array([[prop.GetMatrix().GetElement(i, j) for j in range(4)] for i in range(4)])
        xyz = vtk_to_numpy(data.GetPoints().GetData()).astype(np.float64, copy=False)
        found.append(xyz @ matrix[:3, :3].T + matrix[:3, 3])
    return np.concatenate(found) if found else np.zeros((0, 3))


def _viewport_fractions(renderer, points: np.ndarray) -> np.ndarray:
    """Where the camera of ``renderer`` draws world ``points`` (N, 3): (N, 2) fractions of the window (0 at its lower
    left corner, 1 at its upper right); points behind the camera left out."""
    camera = renderer.GetActiveCamera()
    m = camera.GetCompositeProjectionTransformMatrix(renderer.GetTiledAspectRatio(), -1, 1)
    matrix = np.array([[m.GetElement(i, j) for j in range(4)] for i in range(4)])
    clip = points @ matrix[:, :3].T + matrix[:, 3]
    clip = clip[clip[:, 3] > 0]
    ndc = clip[:, :2] / clip[:, 3:]
    x0, y0, x1, y1 = renderer.GetViewport()
    return np.column_stack([x0 + (ndc[:, 0] + 1) / 2 * (x1 - x0), y0 + (ndc[:, 1] + 1) / 2 * (y1 - y0)])


def fit_camera(plotter, room, *, points=None, margin_px=(20, 20, 20, 20), max_margin=(0.1, 0.08),
               steps: int = 4) -> None:
    """Zoom and pan a scene's camera, its viewing direction kept, so that the scene fills the room the colour bars
    leave (:func:`arrange_colour_bars`).

    The points are projected through the camera; the zoom (the view angle, or the parallel scale) scales the
    picture about its centre, and a pan (camera and focal point moved together, square to the view) centres it in
    the room. Under a perspective a pan also changes the picture a little, hence a few steps of both.

    Parameters
    ----------
    plotter : pyvista.Plotter
        A scene with its camera's direction set (``camera_position``, ``view_vector``).
    room : (x_min, y_min, x_max, y_max) tuple of float
        Viewport fractions (0 at the window's lower left corner, 1 at its upper right) the scene may fill, e.g. what
        :func:`arrange_colour_bars` returns.
    points : (N, 3) array_like, optional
        World points to bring into the room (the corners of a seismic cube's box); default: the points of every
        visible mesh and the corners of every volume in the scene (text and other 2D actors left out).
    margin_px : (int, int, int, int), optional
        Pixels kept free inside the room at its left, bottom, right and top (for tick numbers, axis titles, a
        caption).
    max_margin : (float, float), optional
        The margins at most these fractions of the window's width and height (a small window: the scene first).
    steps : int, optional
        Rounds of zoom and pan.

    Raises
    ------
    InputError
        A room that is not inside the window or has no area.
    """
    x0, y0, x1, y1 = (float(v) for v in room)
    if not (0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1):
        raise InputError(f"room must be (x_min, y_min, x_max, y_max) fractions of the window, 0 <= min < max <= 1; "
                         f"got {tuple(room)!r}")
    renderer, camera = plotter.renderer, plotter.renderer.GetActiveCamera()
    xyz = _scene_points(renderer) if points is None else np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if not len(xyz):
        return
    width, height = (int(v) for v in plotter.window_size)
    left, bottom, right, top = (min(px / size, cap) for px, size, cap in
                                zip(margin_px, (width, height) * 2, tuple(max_margin) * 2))
    x0, x1, y0, y1 = x0 + left, x1 - right, y0 + bottom, y1 - top
    renderer.ResetCameraClippingRange()
    for _ in range(steps):
        uv = _viewport_fractions(renderer, xyz)
        lo, hi = uv.min(axis=0), uv.max(axis=0)
        camera.Zoom(float(min((x1 - x0) / max(hi[0] - lo[0], 1e-9), (y1 - y0) / max(hi[1] - lo[1], 1e-9))))
        uv = _viewport_fractions(renderer, xyz)
        shift = np.array([(x0 + x1) / 2, (y0 + y1) / 2]) - (uv.min(axis=0) + uv.max(axis=0)) / 2
        # the world step of that shift on the screen, measured at the focal point's depth
        renderer.SetWorldPoint(*camera.GetFocalPoint(), 1.0)
        renderer.WorldToDisplay()
        fx, fy, fz = renderer.GetDisplayPoint()
        renderer.SetDisplayPoint(fx - shift[0] * width, fy - shift[1] * height, fz)
        renderer.DisplayToWorld()
        w = np.array(renderer.GetWorldPoint())
        step = w[:3] / w[3] - np.asarray(camera.GetFocalPoint())
        camera.SetPosition(*np.add(camera.GetPosition(), step))
        camera.SetFocalPoint(*np.add(camera.GetFocalPoint(), step))
    renderer.ResetCameraClippingRange()


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
