"""Pictures and meshes of faults: PNG slices (matplotlib), VTK fault surfaces and a 3D scene (pyvista).

Coordinates of the meshes and scenes are index space with the vertical axis pointing *up*: a fault point at
(inline index i, crossline index j, sample k) is at ``(i, j, -k)`` (2D sections: ``(trace, 0, -k)``), so that VTK
viewers (ParaView, pyvista) show the cube right side up and with one voxel per unit on every axis. The inline /
crossline numbers and times or depths travel as point arrays when ``axes`` is given.

matplotlib and pyvista are imported inside the functions, so importing this module is cheap.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._atomic import atomic_path
from ..errors import InputError
from .fault_meshes import fault_surfaces
from .plotting import axis_values

__all__ = ["plot_fault_slices", "show_faults"]


# --------------------------------------------------------------------------------------------------------------------
# helpers


def _fault_points(faults_or_thin, shape):
    """(points (n, ndim) int64, ids (n,) int32) from a list of Fault or a thinned array (> 0 on faults, id 1)."""
    if isinstance(faults_or_thin, (list, tuple)):
        if not faults_or_thin:
            return np.zeros((0, len(shape)), np.int64), np.zeros(0, np.int32)
        pts = np.concatenate([np.asarray(f.points, dtype=np.int64) for f in faults_or_thin])
        ids = np.concatenate([np.full(f.points.shape[0], f.id, np.int32) for f in faults_or_thin])
    else:
        arr = np.asarray(faults_or_thin)
        if arr.shape != tuple(shape):
            raise InputError(f"the thinned faults have shape {arr.shape} but the cube {tuple(shape)}; pass "
                             "thin_faults(...) of this cube or its list of faults")
        pts = np.argwhere(arr > 0).astype(np.int64)
        ids = np.ones(pts.shape[0], np.int32)
    if pts.size and (pts.shape[1] != len(shape) or pts.min() < 0 or np.any(pts.max(0) >= np.array(shape))):
        raise InputError(f"fault points do not fit the cube of shape {tuple(shape)}; pass the faults of this cube")
    return pts, ids


def _check_axes(axes, shape):
    if axes is None:
        return [np.arange(n, dtype=np.float64) for n in shape]
    if len(axes) != len(shape):
        raise InputError(f"axes must hold one 1D array per axis of the cube ({len(shape)}); got {len(axes)}")
    out = []
    for a, n in zip(axes, shape):
        a = np.asarray(a, dtype=np.float64).ravel()
        if a.size != n:
            raise InputError(f"an axis annotation has {a.size} values but the cube axis has {n}")
        out.append(a)
    return out


def _is_lazy_cube(a) -> bool:
    """A 3D array read slice by slice (dask, Zarr) rather than whole."""
    return not isinstance(a, np.ndarray) and hasattr(a, "shape") and hasattr(a, "__getitem__") and len(a.shape) == 3


def _read(a) -> np.ndarray:
    return np.asarray(a, dtype=np.float32)


def _symmetric_limits(data: np.ndarray, percentile: float) -> dict:
    """vmin / vmax at the ``percentile`` of the absolute amplitude of (at most a million of) the finite samples."""
    flat = data.reshape(-1)
    finite = np.isfinite(flat)
    step = max(1, data.size // 1_000_000)
    # every step-th finite sample; when all are finite, a strided view instead of a copy of the whole cube
    clip = _clip(flat[::step] if finite.all() else flat[finite][::step], percentile)
    return {"vmin": -clip, "vmax": clip}


def _clip(values: np.ndarray, percentile: float) -> float:
    c = float(np.percentile(np.abs(values), percentile)) if values.size else 1.0
    return c if c > 0 else 1.0


def _most_faulted(coord: np.ndarray, n: int, *, margin: float = 0.0) -> int:
    lo, hi = int(margin * n), n - int(margin * n)
    counts = np.bincount(coord, minlength=n)[lo:hi] if coord.size else np.zeros(max(hi - lo, 1))
    return lo + int(np.argmax(counts)) if counts.any() else n // 2


def _colors(ids: np.ndarray):
    from matplotlib import colormaps

    cmap = colormaps["tab10"]
    return cmap((ids - 1) % 10)


_FEW_FAULTS = 10  # up to this many values, the colour scale spans all of them
# zlib level of the PNG (Pillow's default: 6): the same pixels; on faults.png of a 256^3 cube (1650 x 1034 pixels)
# encoded in 0.09 CPU s instead of 0.19, 730 KB instead of 684 (level 1: 0.07 s, 771 KB)
_PNG_COMPRESSION = 3


def _value_range(finite: np.ndarray) -> tuple[float, float]:
    """The colour range of the faults' values: from the least to the largest, so that the colours spread over the
    values the faults have (the mean likelihood of a run's faults spans a tenth of [0, 1]); with more than
    :data:`_FEW_FAULTS` values, the 5th to the 95th percentile, so that a few extreme faults (a throw read across a
    cycle skip) do not squeeze the others into one colour."""
    if not finite.size:
        return 0.0, 1.0
    if finite.size <= _FEW_FAULTS:
        return float(finite.min()), float(finite.max())
    return float(np.percentile(finite, 5)), float(np.percentile(finite, 95))


class _FaultColours:
    """Colours of the fault points: by id (10 colours, cycled), or by a value per fault on one colour scale."""

    def __init__(self, ids: np.ndarray, fault_values, label):
        from matplotlib import colormaps
        from matplotlib.cm import ScalarMappable
        from matplotlib.colors import ListedColormap, Normalize

        self.label = self.quantity = label
        self.clipped, self.extend, self.single = False, "neither", None
        if fault_values is None or not ids.size:  # no faults: no colour bar to draw
            self.rgba, self.mappable = _colors(ids), None
            return
        values = {int(k): float(v) for k, v in dict(fault_values).items()}
        missing = sorted(set(np.unique(ids).tolist()) - set(values))
        if missing:
            raise InputError(f"fault_values has no value for faults {missing[:5]}; give one per fault id")
        per_point = np.array([values[int(i)] for i in ids], np.float64)
        finite = np.array([v for v in values.values() if np.isfinite(v)])
        lo, hi = _value_range(finite)
        # one value (one fault, or faults alike): a narrow scale centred on it, its bar labelled with that value only
        # (a span of 1 above it drew a confidence bar up to 1.9)
        self.single = lo if hi <= lo else None
        half = 0.05 * abs(lo) if hi <= lo and lo != 0 else 0.5
        norm = Normalize(vmin=lo - half, vmax=lo + half) if hi <= lo else Normalize(vmin=lo, vmax=hi)
        below = bool(finite.size and finite.min() < norm.vmin)
        self.clipped = bool(finite.size and finite.max() > norm.vmax)  # the bar then says so, with an arrow
        self.extend = {(False, False): "neither", (True, False): "min", (False, True): "max"}.get(
            (below, self.clipped), "both")
        # viridis without its darkest fifth: the least value's lines stay visible on grey seismic and their casing
        cmap = ListedColormap(colormaps["viridis"](np.linspace(0.2, 1.0, 256))).with_extremes(bad="0.6")
        self.rgba = cmap(norm(np.ma.masked_invalid(per_point)))
        self.mappable = ScalarMappable(norm=norm, cmap=cmap)
        if below or self.clipped:
            # two lines: one beside the short bar of a section picture would run into the bar below it
            self.label = (f"{label}\nclipped at the 5th-95th pct; values {finite.min():.3g} to {finite.max():.3g}")

    def title(self) -> str:
        return "faults, coloured by id" if self.mappable is None else f"faults, coloured by {self.quantity}"

    def bar(self, fig, ax) -> None:
        if self.mappable is not None:
            bar = fig.colorbar(self.mappable, ax=ax, shrink=0.8, extend=self.extend)
            if self.single is not None:
                bar.set_ticks([self.single], labels=[f"{self.single:.3g}"])
            bar.set_label(self.label, fontsize=8)


# --------------------------------------------------------------------------------------------------------------------
# PNG


def _live_window(data: np.ndarray) -> tuple[slice, slice]:
    """Traces and samples of a section worth drawing: without the dead (constant) traces at its sides and the rows
    at its top and bottom where fewer than 2 % of the samples are live (mutes, padding)."""
    live = np.abs(np.diff(data, axis=1, prepend=data[:, :1])) > 0
    traces = np.nonzero(live.any(axis=1))[0]
    rows = np.nonzero(live.mean(axis=0) >= 0.02)[0]
    if traces.size < 2 or rows.size < 2:
        return slice(None), slice(None)
    return slice(int(traces[0]), int(traces[-1]) + 1), slice(int(rows[0]), int(rows[-1]) + 1)


def _dot(n_h, width_in) -> dict:
    """Scatter style of isolated fault samples: dots about a cell wide, at least 4 pt^2, with a dark rim."""
    cell_pt = 72.0 * width_in / max(n_h, 1)
    return dict(s=float(np.clip(cell_pt ** 2, 4.0, 16.0)), linewidths=0.3, edgecolors="black", marker="o")


def _draw_faults(ax, cells, h_axis, v_axis, rgba, ids, *, gap: float = 3.0) -> None:
    """Faults over a slice as lines an interpreter reads: each fault's samples ordered along the fault's main
    direction and joined (broken where consecutive samples are more than ``gap`` cells apart), drawn in the fault's
    colour over a dark casing so that they stand out on grey; samples without a neighbour as dots.

    ``cells``: (n, 2) positions in cells (horizontal, vertical index); ``h_axis``, ``v_axis``: the values of the
    panel's axes at each index (inline numbers, times, ...); ``rgba``: (n, 4) colours; ``ids``: (n,) fault ids."""
    from matplotlib.collections import LineCollection

    segments, colours, lone = [], [], []
    cells = np.asarray(cells, dtype=np.float64)
    values = np.column_stack([axis_values(h_axis, cells[:, 0]), axis_values(v_axis, cells[:, 1])])
    for fid in np.unique(ids):
        sel = np.nonzero(ids == fid)[0]
        p = cells[sel]
        if p.shape[0] < 2:
            lone.extend(sel.tolist())
            continue
        c = p - p.mean(axis=0)
        _, _, vt = np.linalg.svd(c, full_matrices=False)
        order = np.argsort(c @ vt[0], kind="stable")
        p, idx = p[order], sel[order]
        breaks = np.nonzero(np.hypot(*np.diff(p, axis=0).T) > gap)[0] + 1
        for run in np.split(np.arange(p.shape[0]), breaks):
            if run.size < 2:
                lone.extend(idx[run].tolist())
                continue
            segments.append(values[idx[run]])
            colours.append(rgba[idx[run[0]]])
    if segments:
        ax.add_collection(LineCollection(segments, colors="black", linewidths=3.0, alpha=0.55, zorder=3))
        ax.add_collection(LineCollection(segments, colors=colours, linewidths=1.6, zorder=4))
    if lone:
        lone = np.asarray(lone)
        ax.scatter(values[lone, 0], values[lone, 1], c=rgba[lone], zorder=5, **_dot(50, 4.5))


def _extent(h, v) -> tuple:
    """imshow extent of an image whose columns are at the values ``h`` and rows at ``v`` (downward)."""
    dh = (h[-1] - h[0]) / max(h.size - 1, 1) / 2 if h.size > 1 else 0.5
    dv = (v[-1] - v[0]) / max(v.size - 1, 1) / 2 if v.size > 1 else 0.5
    return (h[0] - dh, h[-1] + dh, v[-1] + dv, v[0] - dv)


def _section_figure(data, fl, pts, ids, colours, ax_vals, axis_labels, seis, like, dpi):
    """The 2D figure: the section, the faults over it and the likelihood, cropped to the live data and drawn with
    about one sample per trace (a tall section side by side, a wide one one above the other), so that dips show."""
    from matplotlib.figure import Figure

    tr, sm = _live_window(data)
    data = data[tr, sm]
    fl = None if fl is None else fl[tr, sm]
    h_vals, v_vals = ax_vals[0][tr], ax_vals[1][sm]
    if pts.size:
        keep = ((pts[:, 0] >= (tr.start or 0)) & (pts[:, 0] < (tr.stop or data.shape[0] + 1))
                & (pts[:, 1] >= (sm.start or 0)) & (pts[:, 1] < (sm.stop or data.shape[1] + 1)))
        pts, rgba, ids = pts[keep], colours.rgba[keep], ids[keep]
    n_panels = 3 if fl is not None else 2
    ratio = data.shape[1] / max(data.shape[0], 1)  # samples per trace
    tall = ratio > 1.0
    if tall:
        width = 5.0
        height = float(np.clip(width * ratio, 5.0, 14.0))
        fig = Figure(figsize=(width * n_panels + 1.2, height + 1.0), dpi=dpi, layout="constrained")
        axs = fig.subplots(1, n_panels, sharex=True, sharey=True, squeeze=False)[0]
    else:
        width = 11.0
        height = float(np.clip(width * ratio, 2.2, 6.0))
        fig = Figure(figsize=(width + 1.2, height * n_panels + 1.0), dpi=dpi, layout="constrained")
        axs = fig.subplots(n_panels, 1, sharex=True, sharey=True, squeeze=False)[:, 0]
    ext = _extent(h_vals, v_vals)
    for a in axs[:2]:
        a.imshow(data.T, extent=ext, **seis)
    axs[0].set_title("seismic")
    axs[1].set_title(colours.title())
    if pts.size:
        _draw_faults(axs[1], pts, ax_vals[0], ax_vals[1], rgba, ids)
    colours.bar(fig, axs[1])
    if fl is not None:
        im = axs[2].imshow(fl.T, extent=ext, **like)
        axs[2].set_title("fault likelihood")
        fig.colorbar(im, ax=axs[2], shrink=0.8, label="fault likelihood")
    for a in axs:
        a.set_xlabel(str(axis_labels[0]))
    axs[0].set_ylabel(str(axis_labels[1]))
    if not tall:
        for a in axs[1:]:
            a.set_ylabel(str(axis_labels[1]))
    return fig


def _slice_title(sample_label: str, value: float) -> str:
    """'time slice 204 ms' from the sample axis' label 'time (ms)' ('sample slice 51' for 'sample')."""
    name, _, unit = sample_label.partition(" (")
    unit = unit.rstrip(")")
    return f"{name} slice {value:g}" + (f" {unit}" if unit else "")


def plot_fault_slices(cube, faults, *, path, likelihood=None, axes=None, axis_labels=None, slices=None, title=None,
                      clip_percentile=99.0, dpi=110, fault_values=None, value_label="value") -> Path:
    """Draw faults over slices of the seismic and save a PNG.

    3D: an inline, a crossline and a time (depth) slice, by default those crossing the most fault samples; 2D: the
    section without and with the faults, cropped to its live traces and samples and drawn with about one sample per
    trace so that fault dips show (tall sections side by side, wide ones one above the other). Seismic in grey,
    symmetric colour limits at the ``clip_percentile`` of the absolute amplitude; faults as lines over a dark casing
    (each fault's samples joined along it; lone samples as dots) coloured by fault id (10 colours, cycled), or by
    ``fault_values`` on one colour scale (viridis without its darkest fifth, from the least value to the largest;
    with more than 10 faults from the 5th to the 95th percentile; grey for NaN) with its colour bar, which says
    when it clips (arrows, and the least and largest values). Panel titles name the slice only; the colouring is in
    the figure's title. With ``likelihood``, a row of the same slices of the fault likelihood is added below.

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes; a 3D dask or Zarr array is read only on the three slices drawn (their amplitudes set the
        colour limits), for cubes larger than memory.
    faults : list of Fault or array_like of the cube's shape
        Linked faults (:func:`~seismo3d.seismic.fault_skins`) or thinned faults (> 0 on faults, drawn as one
        colour).
    path : str or os.PathLike
        PNG file to write (atomically); its folder must exist.
    likelihood : array_like of the cube's shape, optional
        Fault likelihood in [0, 1], drawn in a second row (a dask or Zarr array is read on the slices only).
    axes : sequence of 1D array_like, optional
        Annotation of each axis, e.g. (inline numbers, crossline numbers, times in ms); default: indices.
    slices : (int, int, int), optional
        Indices (not numbers) of the inline, crossline and sample of the 3D slices; default: the most faulted ones.
    axis_labels : sequence of str, optional
        Name of each axis, e.g. ('inline', 'crossline', 'time (ms)'); default: ('inline', 'crossline', 'sample') in
        3D, ('trace', 'sample') in 2D.
    title : str, optional
    clip_percentile : float, optional
        Percentile of the absolute amplitude used as the colour limit, in (0, 100].
    dpi : int, optional
    fault_values : mapping of int to float, optional
        A value per fault id to colour the faults by (e.g. the |median throw| in ms, the evidence of
        ``fault_summary.csv``); default: colours by id.
    value_label : str, optional
        The colour bar's label for ``fault_values``, e.g. '|median throw| (ms)'.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    InputError
        Wrong shapes, a folder that does not exist, slices out of range, or a fault without a value in
        ``fault_values``.
    """
    from matplotlib.figure import Figure

    lazy = _is_lazy_cube(cube)
    data = cube if lazy else np.asarray(cube, dtype=np.float32)
    if data.ndim not in (2, 3):
        raise InputError(f"cube must be a 2D section or a 3D cube; got shape {data.shape}")
    if not 0 < clip_percentile <= 100:
        raise InputError(f"clip_percentile must be in (0, 100]; got {clip_percentile!r}")
    shape = tuple(int(n) for n in data.shape)
    pts, ids = _fault_points(faults, shape)
    colours = _FaultColours(ids, fault_values, value_label)
    ax_vals = _check_axes(axes, shape)
    if axis_labels is None:
        axis_labels = ("inline", "crossline", "sample") if data.ndim == 3 else ("trace", "sample")
    if len(axis_labels) != data.ndim:
        raise InputError(f"axis_labels must name each of the {data.ndim} axes; got {axis_labels!r}")
    sample_label = str(axis_labels[-1])
    fl = None
    if likelihood is not None:
        fl = likelihood if _is_lazy_cube(likelihood) else np.asarray(likelihood, dtype=np.float32)
        if tuple(fl.shape) != shape:
            raise InputError(f"likelihood has shape {tuple(fl.shape)} but the cube {shape}")
    seis = dict(cmap="gray", aspect="auto", interpolation="bilinear")
    like = dict(cmap="magma", vmin=0.0, vmax=1.0, aspect="auto", interpolation="nearest")

    if data.ndim == 2:
        seis.update(_symmetric_limits(data, clip_percentile))
        fig = _section_figure(data, fl, pts, ids, colours, ax_vals, axis_labels, seis, like, dpi)
    else:
        if slices is None:
            slices = (_most_faulted(pts[:, 0], shape[0]), _most_faulted(pts[:, 1], shape[1]),
                      _most_faulted(pts[:, 2], shape[2], margin=0.1))
        slices = tuple(int(s) for s in slices)
        if len(slices) != 3 or any(not 0 <= s < n for s, n in zip(slices, shape)):
            raise InputError(f"slices must be 3 indices within the cube's shape {shape}; got {slices}")
        i, j, k = slices
        il, xl, tz = ax_vals
        il_name, xl_name = str(axis_labels[0]), str(axis_labels[1])
        n_rows = 2 if fl is not None else 1
        fig = Figure(figsize=(15, 1.0 + 4.2 * n_rows), dpi=dpi, layout="constrained")
        axs = fig.subplots(n_rows, 3, squeeze=False)
        panels = [  # (slice of the array, horizontal axis values, vertical values, mask of points, h, v columns)
            (lambda a: _read(a[i]).T, xl, tz, pts[:, 0] == i if pts.size else None, 1, 2,
             f"{il_name} {il[i]:g}", xl_name, sample_label),
            (lambda a: _read(a[:, j]).T, il, tz, pts[:, 1] == j if pts.size else None, 0, 2,
             f"{xl_name} {xl[j]:g}", il_name, sample_label),
            (lambda a: _read(a[:, :, k]), xl, il, pts[:, 2] == k if pts.size else None, 1, 0,
             _slice_title(sample_label, tz[k]), xl_name, il_name),
        ]
        cuts = [p[0](data) for p in panels]  # a lazy cube is read only here: three slices
        seis.update(_symmetric_limits(np.concatenate([c.ravel() for c in cuts]) if lazy else data, clip_percentile))
        for c, (cut, h, v, sel, hc, vc, name, hl, vl) in enumerate(panels):
            ext = _extent(h, v)
            a = axs[0, c]
            a.imshow(cuts[c], extent=ext, **seis)
            if sel is not None and sel.any():
                _draw_faults(a, pts[sel][:, [hc, vc]], ax_vals[hc], ax_vals[vc], colours.rgba[sel], ids[sel])
            a.set_title(name)  # short: the three panels' titles must not run into each other
            a.set_xlabel(hl)
            a.set_ylabel(vl)
            if fl is not None:
                b = axs[1, c]
                im = b.imshow(cut(fl), extent=ext, **like)
                b.set_title(f"fault likelihood, {name}")
                b.set_xlabel(hl)
                b.set_ylabel(vl)
        colours.bar(fig, axs[0, :].tolist())
        if fl is not None:
            fig.colorbar(im, ax=axs[1, :].tolist(), shrink=0.8, label="fault likelihood")
    n_f = len(np.unique(ids)) if ids.size else 0
    how = "" if data.ndim == 2 or not n_f else f", {colours.title().removeprefix('faults, ')}"
    fig.suptitle(f"{title + ': ' if title else ''}{n_f} fault{'' if n_f == 1 else 's'}{how}")
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", pil_kwargs={"compress_level": _PNG_COMPRESSION})
    return path


# --------------------------------------------------------------------------------------------------------------------
# VTK


# --------------------------------------------------------------------------------------------------------------------
# 3D scene


def show_faults(cube, faults, *, throws=None, slices=None, color_by="fault_id", screenshot=None,
                window_size=(1024, 768)):
    """A 3D scene of the cube (three orthogonal slices) and its fault surfaces, for notebooks; the camera zoomed so
    that the cube fills the room above its colour bar (:func:`~seismo3d.viz.plotting.fit_camera`).

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) array_like
        Seismic amplitudes (a 2D section is shown as a single slice with fault curves).
    faults : sequence of Fault
    throws : sequence of FaultThrow, optional
        Needed for ``color_by='throw'``.
    slices : (int, int, int), optional
        Indices of the inline, crossline and sample slices; default: the middle of the cube.
    color_by : {'fault_id', 'throw', 'likelihood'}, optional
    screenshot : str or os.PathLike, optional
        Render off screen (no window needed) and write the picture to this PNG (atomically) instead of showing it.
    window_size : (int, int), optional
        Pixels.

    Returns
    -------
    pyvista.Plotter
        The scene. Without ``screenshot`` it has been shown (:func:`~seismo3d.viz.plotting.finish_scene`: inline
        in Jupyter, a window elsewhere); with it, it has been rendered off screen and closed.

    Raises
    ------
    InputError
        Wrong shapes or an unknown ``color_by``, a ``window_size`` that is not two pixel counts, or a
        ``screenshot`` in a folder that does not exist.
    """
    import pyvista as pv

    from .._validation import check_choice
    from .plotting import arrange_colour_bars, bar_below, finish_scene, fit_camera, new_plotter

    check_choice(color_by, "color_by", {"fault_id", "throw", "likelihood"})
    data = np.asarray(cube, dtype=np.float32)
    if data.ndim == 2:
        data = data[:, None, :]
    if data.ndim != 3:
        raise InputError(f"cube must be a 2D section or a 3D cube; got shape {data.shape}")
    ni, nj, nk = data.shape
    grid = pv.ImageData(dimensions=data.shape, origin=(0.0, 0.0, -(nk - 1.0)))  # z up: sample k at z = -k
    grid.point_data["amplitude"] = np.ascontiguousarray(data[:, :, ::-1]).ravel(order="F")
    if slices is None:
        slices = (ni // 2, nj // 2, nk // 2)
    i, j, k = (int(s) for s in slices)
    clip = _clip(data[:: max(1, ni // 64), :: max(1, nj // 64)].ravel(), 99.0)
    plotter = new_plotter(off_screen=screenshot is not None, window_size=window_size)
    shown = [grid] if nj == 1 else grid.slice_orthogonal(x=float(i), y=float(j), z=-float(k))
    for block in shown:
        if block is not None and block.n_points:
            plotter.add_mesh(block, scalars="amplitude", cmap="gray", clim=(-clip, clip), show_scalar_bar=False)
    mesh = fault_surfaces(faults, throws)
    if mesh.n_cells and data.shape[1] > 1:
        mesh = mesh.smooth_taubin(n_iter=20, pass_band=0.1)  # display only: soften the voxel staircase
    if mesh.n_points:
        if color_by == "fault_id":
            n_ids = int(np.unique(mesh.point_data["fault_id"]).size)
            plotter.add_mesh(mesh, scalars="fault_id", cmap="tab10", categories=True, line_width=3,
                             scalar_bar_args=bar_below("fault id", fmt="%.0f", n_labels=min(n_ids, 10)))
        else:
            plotter.add_mesh(mesh, scalars=color_by, cmap="viridis", line_width=3, nan_opacity=0.3,
                             scalar_bar_args=bar_below(color_by))
    room = arrange_colour_bars(plotter)  # the fault bar's slot at the bottom, sized to its title and labels
    plotter.add_axes(xlabel="inline", ylabel="crossline", zlabel="sample (down)", color="black")
    plotter.camera_position = "xz" if nj == 1 else "iso"
    fit_camera(plotter, room)  # the cube fills the room the bar leaves
    return finish_scene(plotter, screenshot=screenshot)
