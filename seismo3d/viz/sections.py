"""A 2D seismic line as an interpreter reads it (matplotlib): the section with its trace numbers and time or depth
on labelled axes, a stated vertical exaggeration, faults drawn as lines over it and a horizon as a curve.

``seismo3d render`` draws a single line (a 2D line of a survey, a trace list) with :func:`plot_section` rather than
as a plane in a 3D scene, which squashed a deep section into a band without ticks.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._atomic import atomic_path
from ..errors import InputError
from .plotting import symmetric_clip

__all__ = ["section_exaggeration", "plot_section", "plot_volume_registration"]

_NAMES = {"ms": "time", "m": "depth", "ft": "depth", "samples": "sample"}


def section_exaggeration(n_traces: int, trace_spacing, vertical_extent, *, target_ratio: float = 0.55) -> float:
    """A vertical exaggeration that makes a section about ``target_ratio`` as tall as it is wide, rounded to a
    round number (1, 1.5, 2, 3, 4, 5, 8, 10, ...).

    Parameters
    ----------
    n_traces : int
        Traces along the section.
    trace_spacing : float or None
        Distance between neighbouring traces (m or ft); None when unknown (then one trace counts as one unit).
    vertical_extent : float
        Height of the section in the same unit (a time section: its two-way time converted to depth, e.g. at
        2000 m/s, 1 m per ms).
    target_ratio : float, optional
        Wanted height / width of the drawn section.

    Returns
    -------
    float
        At least 1 (a section is never squashed), at most 20.
    """
    width = max(n_traces - 1, 1) * float(trace_spacing or 1.0)
    raw = target_ratio * width / max(float(vertical_extent), 1e-9)
    steps = np.array([1, 1.5, 2, 3, 4, 5, 8, 10, 15, 20], dtype=np.float64)
    return float(steps[np.argmin(np.abs(np.log(steps / np.clip(raw, 1.0, 20.0))))])


def _fault_segments(faults, n_traces: int, values: str | None = None):
    """(fault id, (n, 2) fractional trace index / sample index ordered along the fault, (n,) values of the point
    array ``values`` in the same order, or None) of a 2D faults mesh in index space (points ``(trace, 0, -sample)``,
    polylines: :func:`~seismo3d.viz.fault_surfaces`, ``faults.vtp``)."""
    if faults is None or not faults.n_points:
        return []
    p = np.asarray(faults.points, dtype=np.float64)
    ids = np.asarray(faults.point_data["fault_id"]) if "fault_id" in faults.point_data else np.ones(len(p), int)
    point_values = None if values is None else np.asarray(faults.point_data[values], dtype=np.float64)
    lines = np.asarray(faults.lines, dtype=np.int64)
    out, at = [], 0
    while at < lines.size:
        n = int(lines[at])
        idx = lines[at + 1: at + 1 + n]
        at += n + 1
        if n >= 2:
            seg, order = _smooth(np.column_stack([p[idx, 0], -p[idx, 2]]))
            if np.all((seg[:, 0] >= -0.5) & (seg[:, 0] <= n_traces - 0.5)):
                out.append((int(ids[idx[0]]), seg, None if point_values is None else point_values[idx][order]))
    return out


def _smooth(points: np.ndarray, window: int = 9):
    """A fault's samples ordered along its main direction and averaged over ``window`` neighbours: one clean line
    where the samples of a braided stretch zigzag across it (display only); and the order."""
    c = points - points.mean(axis=0)
    _, _, vt = np.linalg.svd(c, full_matrices=False)
    order = np.argsort(c @ vt[0], kind="stable")
    points = points[order]
    w = min(window, points.shape[0])
    if w < 3:
        return points, order
    kernel = np.ones(w) / w
    pad = np.pad(points, ((w // 2, w - 1 - w // 2), (0, 0)), mode="edge")
    return np.column_stack([np.convolve(pad[:, d], kernel, mode="valid") for d in range(2)]), order


def plot_section(section, *, path, traces=None, samples=None, trace_name="trace", sample_unit="samples",
                 trace_spacing=None, velocity=2000.0, vertical_exaggeration=None, faults=None, sticks=None,
                 horizon=None, title=None, clip_percentile=99.0, values="amplitude", width=11.0, dpi=120,
                 color_by="fault_id"):
    """Draw one seismic line with labelled axes, a stated vertical exaggeration, faults as lines and a horizon, and
    save a PNG.

    Parameters
    ----------
    section : (n_traces, n_samples) array_like
        Amplitudes, trace after trace.
    path : str or os.PathLike
        PNG to write (atomically); its folder must exist.
    traces : (n_traces,) array_like, optional
        Trace labels along the section (inline or crossline numbers); default 1, 2, ... (file order).
    samples : (n_samples,) array_like, optional
        Times or depths of the samples; default the sample indices.
    trace_name : str, optional
        What labels the traces: 'inline', 'crossline' or 'trace'.
    sample_unit : {'ms', 'm', 'ft', 'samples'}, optional
    trace_spacing : float, optional
        Distance between traces in metres (or feet), from the CDP X/Y of the headers; None when unknown (the
        aspect is then stated per trace, not as an exaggeration).
    velocity : float, optional
        m/s (or ft/s) converting two-way time to depth for the exaggeration of a time section.
    vertical_exaggeration : float, optional
        Default: :func:`section_exaggeration` (the section about half as tall as wide, reflectors at their dips
        times the exaggeration).
    faults : pyvista.PolyData, optional
        2D fault curves in index space (``faults.vtp`` of ``seismo3d faults`` on a line), drawn as lines coloured
        by fault id over a dark casing.
    sticks : pyvista.PolyData, optional
        People's fault sticks in the same index space (:func:`seismo3d.jobs.interchange.sticks_mesh`), drawn in one
        style of their own (white dashes over a dark casing, named in a legend) so that they are told apart from the
        traced faults.
    horizon : (n_traces,) array_like of float, optional
        Horizon in fractional samples (NaN where empty), drawn as a curve.
    title : str, optional
        First line of the title; the second states the lines, the range and the exaggeration.
    clip_percentile : float, optional
        Amplitude colour limit: this percentile of ``|amplitude|``, in (0, 100]; the colour bar says it clips.
    values : {'amplitude', 'fault likelihood', 'none'}, optional
        What ``section`` holds: amplitudes (grey, symmetric limits), a fault likelihood in [0, 1] (drawn when no
        seismic is at hand), or nothing to draw (a blank section under faults or a horizon).
    width : float, optional
        Largest width of the picture in inches. The picture follows the section's shape (its exaggeration) so that
        the section fills it: a wide section this wide with the height it needs; a section taller than wide with
        its colour bars below it, in a picture at most 4 times as tall as ``width``, narrower than ``width`` where
        the exaggeration makes the section a strip.
    dpi : int, optional
    color_by : {'fault_id', 'throw'}, optional
        Colour of the fault lines: a colour per fault, or each point's throw (``faults.vtp``'s point array
        ``throw``, in samples, drawn in the sample unit: + where the hanging wall moved down) on a diverging scale
        to the 98th percentile of |throw|, with its colour bar.

    Returns
    -------
    str
        The caption: lines, time or depth range and the exaggeration as stated on the picture.

    Raises
    ------
    InputError
        A section that is not 2D, axes of the wrong length, a non-positive exaggeration, a missing folder, or
        ``color_by='throw'`` with faults that carry no measured throw.
    """
    import textwrap

    from matplotlib import colormaps
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure

    from .._validation import check_choice

    check_choice(color_by, "color_by", {"fault_id", "throw"})
    if color_by == "throw" and faults is not None and faults.n_points and not (
            "throw" in faults.point_data and np.isfinite(np.asarray(faults.point_data["throw"], float)).any()):
        raise InputError("color_by='throw' needs faults with measured throws (faults.vtp's point array 'throw'); "
                         "colour them by fault id instead")
    data = np.asarray(section, dtype=np.float32)
    if data.ndim != 2 or min(data.shape) < 2:
        raise InputError(f"section must be (n_traces, n_samples) with at least 2 of each; got shape {data.shape}")
    n_tr, n_s = data.shape
    traces = np.arange(1, n_tr + 1, dtype=np.float64) if traces is None else np.asarray(traces, np.float64).ravel()
    samples = np.arange(n_s, dtype=np.float64) if samples is None else np.asarray(samples, np.float64).ravel()
    if traces.size != n_tr or samples.size != n_s:
        raise InputError(f"traces and samples must have {n_tr} and {n_s} values (the section's shape); got "
                         f"{traces.size} and {samples.size}")
    path = Path(path)
    if not (path.parent if str(path.parent) else Path(".")).is_dir():
        raise InputError(f"cannot write {path}: folder {path.parent} does not exist; create it first")
    dt = abs(float(np.median(np.diff(samples)))) or 1.0
    per_unit = velocity / 2000.0 if sample_unit == "ms" else 1.0  # depth per time or depth unit (m per ms)
    height = (samples[-1] - samples[0]) * per_unit
    if vertical_exaggeration is None:
        vertical_exaggeration = section_exaggeration(n_tr, trace_spacing, height)
    if not np.isfinite(vertical_exaggeration) or vertical_exaggeration <= 0:
        raise InputError(f"vertical_exaggeration must be > 0; got {vertical_exaggeration!r}")
    step = abs(float(np.median(np.diff(traces)))) or 1.0
    width_units = abs(traces[-1] - traces[0]) or 1.0
    if trace_spacing:
        # data aspect (screen length of one vertical unit over one horizontal unit): VE x depth per unit / distance
        # per trace label
        aspect = vertical_exaggeration * per_unit / (float(trace_spacing) / step)
    else:  # no distance between traces: no exaggeration to speak of; drawn about half as tall as wide
        aspect = 0.55 * width_units / (abs(samples[-1] - samples[0]) or 1.0)
    ratio = abs(aspect * (samples[-1] - samples[0]) / width_units)  # the section's height over its width
    n_bars = (values != "none") + (color_by == "throw" and faults is not None and faults.n_points > 0)
    layout = _figure_size(ratio, width, colour_bars=n_bars)
    heading_width = layout.heading_width
    caption = _caption(traces, samples, trace_name, sample_unit, trace_spacing, vertical_exaggeration, velocity)
    n_head = len(textwrap.wrap(f"{title + ' ' if title else ''}{caption}", width=heading_width)) + bool(title)
    below = _BAR_H * n_bars if layout.bars_below else 0.0
    fig = Figure(figsize=(layout.width, layout.box_height + _MARGIN_H + below + 0.22 * n_head), dpi=dpi,
                 layout="constrained")
    # below a tall section: the bar's thickness and gap in inches (matplotlib counts them in the section's height)
    def bar_style() -> dict:
        if not layout.bars_below:
            return dict(shrink=0.7, pad=0.01)
        from matplotlib.ticker import MaxNLocator

        return dict(location="bottom", shrink=0.9, fraction=0.2 / layout.box_height, pad=0.4 / layout.box_height,
                    aspect=12, ticks=MaxNLocator(nbins=4))

    ax = fig.subplots()
    dh = step / 2
    extent = (traces[0] - dh if traces[-1] >= traces[0] else traces[0] + dh,
              traces[-1] + dh if traces[-1] >= traces[0] else traces[-1] - dh,
              samples[-1] + dt / 2, samples[0] - dt / 2)
    if values == "amplitude":
        clip = symmetric_clip(data, clip_percentile)
        im = ax.imshow(data.T, extent=extent, cmap="gray_r", vmin=-clip, vmax=clip, interpolation="bilinear",
                       aspect=aspect)
        fig.colorbar(im, ax=ax, extend="both", label=f"amplitude (clipped at {clip_percentile:g}th pct)",
                     **bar_style())
    elif values == "fault likelihood":
        im = ax.imshow(data.T, extent=extent, cmap="Greys", vmin=0.0, vmax=1.0, interpolation="nearest",
                       aspect=aspect)
        fig.colorbar(im, ax=ax, label="fault likelihood (no seismic drawn)", **bar_style())
    elif values == "none":
        ax.set_xlim(extent[0], extent[1])
        ax.set_ylim(extent[2], extent[3])
        ax.set_aspect(aspect)
    else:
        raise InputError(f"values must be one of 'amplitude', 'fault likelihood', 'none'; got {values!r}")
    segments = _fault_segments(faults, n_tr, values="throw" if color_by == "throw" else None)
    if segments:
        lines = [np.column_stack([np.interp(s[:, 0], np.arange(n_tr), traces),
                                  np.interp(s[:, 1], np.arange(n_s), samples)]) for _, s, _ in segments]
        ax.add_collection(LineCollection(lines, colors="black", linewidths=3.4, alpha=0.6, zorder=3))
        if color_by == "throw":
            colours = _add_throw_lines(fig, ax, lines, [v for _, _, v in segments], dt, sample_unit, bar_style())
        else:
            tab10 = colormaps["tab10"]
            colours = [tab10((fid - 1) % 10) for fid, _, _ in segments]
            ax.add_collection(LineCollection(lines, colors=colours, linewidths=2.0, zorder=4))
    people = _fault_segments(sticks, n_tr)
    if people:
        from matplotlib.lines import Line2D

        lines = [np.column_stack([np.interp(s[:, 0], np.arange(n_tr), traces),
                                  np.interp(s[:, 1], np.arange(n_s), samples)]) for _, s, _ in people]
        ax.add_collection(LineCollection(lines, colors="black", linewidths=3.6, alpha=0.7, zorder=5))
        ax.add_collection(LineCollection(lines, colors="white", linewidths=1.8, linestyles=(0, (4, 2)), zorder=6))
        handles = [Line2D([], [], color="white", lw=1.8, ls=(0, (4, 2)), path_effects=_casing(),
                          label=f"given fault sticks ({len(people)})")]
        if segments:
            handles.append(Line2D([], [], color=colours[0], lw=2.0, path_effects=_casing(),
                                  label=f"traced faults ({len({fid for fid, _, _ in segments})})"))
        fig.legend(handles=handles, loc="lower center", ncol=2, fontsize=9, frameon=False)  # hides none of it
    if horizon is not None:
        h = np.asarray(horizon, dtype=np.float64).ravel()
        if h.size != n_tr:
            raise InputError(f"horizon must have one value per trace ({n_tr}); got {h.size}")
        ax.plot(traces, np.interp(h, np.arange(n_s), samples, left=np.nan, right=np.nan), color="#ffcc00",
                lw=2.2, zorder=5, path_effects=_casing())
    name = _NAMES.get(sample_unit, "sample")
    unit = "" if sample_unit == "samples" else f" ({sample_unit})"
    ax.set_xlabel(trace_name)
    ax.set_ylabel(f"{name}{unit}")
    ax.xaxis.set_ticks_position("both")
    ax.tick_params(top=True, labeltop=True)
    n_faults = len({fid for fid, _, _ in segments})
    extra = f", {n_faults} fault{'' if n_faults == 1 else 's'}" if segments else ""
    extra += " coloured by throw" if segments and color_by == "throw" else ""
    extra += f", {len(people)} given fault sticks" if people else ""
    fig.suptitle(f"{title + chr(10) if title else ''}{textwrap.fill(caption + extra, width=heading_width)}",
                 fontsize=10)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    return caption


def plot_volume_registration(fixed, moving, moving_on_fixed, *, path, inline=None, xlines=None, samples=None,
                             sample_unit="samples", inline_number=None, title=None, clip_percentile=99.0, dpi=110):
    """Draw a sub-volume registration on one inline: the fixed volume, the moving volume as read (the same inline
    index, before registration) and the moving volume resampled onto the fixed grid, side by side, and save a PNG.

    Parameters
    ----------
    fixed, moving_on_fixed : (n_inlines, n_xlines, n_samples) array_like
        The fixed volume and the moving one resampled onto its grid
        (:func:`seismo3d.seismic.resample_volume` with the registration's ``transform_index``); NaN outside.
    moving : (n_inlines', n_xlines', n_samples') array_like
        The moving volume as read.
    path : str or os.PathLike
        PNG to write (atomically); its folder must exist.
    inline : int, optional
        Inline index drawn (default the middle one; the moving volume's is clipped to its own range).
    xlines, samples : 1D array_like, optional
        The fixed grid's crossline numbers and times or depths (default indices); the moving volume is drawn on
        its own indices.
    sample_unit : {'ms', 'm', 'ft', 'samples'}, optional
    inline_number : float, optional
        The fixed inline's number, for the titles (default its index).
    title : str, optional
    clip_percentile : float, optional
        Amplitude colour limit, the same for the three panels: this percentile of the fixed volume's
        ``|amplitude|``.
    dpi : int, optional

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    InputError
        Volumes that are not 3D, grids that do not match, an inline out of range or a missing folder.
    """
    from matplotlib.figure import Figure

    a, b, c = (np.asarray(v, dtype=np.float32) for v in (fixed, moving, moving_on_fixed))
    if a.ndim != 3 or b.ndim != 3 or c.shape != a.shape:
        raise InputError(f"fixed and moving_on_fixed must be 3D volumes of one shape and moving 3D; got {a.shape}, "
                         f"{b.shape}, {c.shape}")
    path = Path(path)
    if not (path.parent if str(path.parent) else Path(".")).is_dir():
        raise InputError(f"cannot write {path}: folder {path.parent} does not exist; create it first")
    i = a.shape[0] // 2 if inline is None else int(inline)
    if not 0 <= i < a.shape[0]:
        raise InputError(f"inline must be an index in [0, {a.shape[0] - 1}]; got {inline!r}")
    xl = np.arange(a.shape[1], dtype=np.float64) if xlines is None else np.asarray(xlines, np.float64).ravel()
    tz = np.arange(a.shape[2], dtype=np.float64) if samples is None else np.asarray(samples, np.float64).ravel()
    clip = symmetric_clip(a, clip_percentile)
    name = _NAMES.get(sample_unit, "sample")
    unit = "" if sample_unit == "samples" else f" ({sample_unit})"
    number = f"{inline_number:g}" if inline_number is not None else f"index {i}"
    fig = Figure(figsize=(12, 4.6), dpi=dpi, layout="constrained")
    axs = fig.subplots(1, 3)
    style = dict(cmap="gray_r", vmin=-clip, vmax=clip, aspect="auto", interpolation="bilinear")
    dx, dt = (abs(xl[1] - xl[0]) if xl.size > 1 else 1.0) / 2, (abs(tz[1] - tz[0]) if tz.size > 1 else 1.0) / 2
    extent = (xl[0] - dx, xl[-1] + dx, tz[-1] + dt, tz[0] - dt)
    axs[0].imshow(a[i].T, extent=extent, **style)
    axs[0].set_title(f"fixed, inline {number}")
    j = min(i, b.shape[0] - 1)
    axs[1].imshow(b[j].T, aspect="auto", cmap="gray_r", vmin=-clip, vmax=clip, interpolation="bilinear")
    axs[1].set_title(f"moving as read, its inline index {j}")
    axs[1].set_xlabel("crossline index")
    axs[1].set_ylabel("sample index")
    im = axs[2].imshow(c[i].T, extent=extent, **style)
    axs[2].set_title(f"moving registered onto fixed, inline {number}")
    for ax in (axs[0], axs[2]):
        ax.set_xlabel("crossline")
        ax.set_ylabel(f"{name}{unit}")
    fig.colorbar(im, ax=axs.tolist(), shrink=0.8, extend="both",
                 label=f"amplitude (clipped at {clip_percentile:g}th pct)")
    if title:
        fig.suptitle(title, fontsize=10)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    return path


_MARGIN_W = 1.3  # inches beside the section: the time axis' label and ticks
_BAR_W = 1.2  # inches of a colour bar beside the section, with its label
_BAR_H = 1.0  # inches of a colour bar below a tall section, with its label
_MARGIN_H = 1.8  # inches above and below the section: the trace axis' ticks (top and bottom) and label
_MAX_TALL = 4.0  # a tall section's picture at most this many times as tall as ``width``


@dataclass(frozen=True)
class _Layout:
    """The picture's size around a section (inches): its width, the section's height, the colour bars below the
    section rather than beside it (a tall section), and the title's wrapping width in characters."""

    width: float
    box_height: float
    bars_below: bool
    heading_width: int


def _figure_size(ratio: float, width: float, *, colour_bars: int) -> _Layout:
    """A picture the section fills, its shape following the section's (``ratio``: the section's height over its
    width, from the exaggeration). A wide section is as wide as ``width`` allows, its colour bars beside it, the
    height what the section needs. A tall one (ratio > 1) has its colour bars below it and is as wide as a picture
    up to :data:`_MAX_TALL` times ``width`` tall allows (at most ``width``): narrower than ``width`` when the
    exaggeration makes it a strip, so that no margin of white is left beside it."""
    width = float(width)
    if ratio <= 1.0:
        box_w = max(width - _MARGIN_W - _BAR_W * colour_bars, 1.0)
        return _Layout(width, box_w * ratio, False, max(30, int(width * 11)))
    room = _MAX_TALL * width - _MARGIN_H - _BAR_H * colour_bars
    box_w = max(min(width - _MARGIN_W, room / ratio), 0.2)
    fig_w = min(max(box_w + _MARGIN_W, 3.0), width)  # room for a title of a few short lines
    return _Layout(fig_w, box_w * ratio, True, max(24, int(fig_w * 11)))


def _caption(traces, samples, trace_name, sample_unit, trace_spacing, vertical_exaggeration, velocity):
    """The caption: the lines, the time or depth range and the exaggeration."""
    name = _NAMES.get(sample_unit, "sample")
    if trace_spacing:
        how = f"vertical exaggeration {vertical_exaggeration:g}x"
        if sample_unit == "ms":
            how += f" (time as depth at {velocity:g} m/s)"
    else:
        how = "no trace spacing in the headers: no vertical exaggeration, drawn to fit"
    span = f"{samples[0]:g}-{samples[-1]:g}" + ("" if sample_unit == "samples" else f" {sample_unit}")
    return f"{trace_name}s {traces[0]:g}-{traces[-1]:g}, {name} {span}, {how}"


def _add_throw_lines(fig, ax, lines, throws, dt: float, sample_unit: str, bar_style: dict) -> list:
    """Fault lines coloured point by point by their throw (``faults.vtp``'s ``throw``, samples; converted to the
    sample unit), on a diverging scale symmetric about 0 to the 98th percentile of |throw| (as the 3D scene), with
    its colour bar; grey where a throw was not measured. Returns a colour for the legend."""
    from matplotlib import colormaps
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize

    scale = dt if sample_unit != "samples" else 1.0
    values = [np.asarray(v, dtype=np.float64) * scale for v in throws]
    finite = np.concatenate([v[np.isfinite(v)] for v in values]) if values else np.zeros(0)
    lim = float(np.percentile(np.abs(finite), 98)) if finite.size else 1.0
    norm = Normalize(-(lim or 1.0), lim or 1.0)
    cmap = colormaps["PuOr_r"].with_extremes(bad="0.6")
    segments, per_segment = [], []
    for line, v in zip(lines, values):
        segments.extend(np.stack([line[:-1], line[1:]], axis=1))
        per_segment.append(0.5 * (v[:-1] + v[1:]))
    collection = LineCollection(segments, cmap=cmap, norm=norm, linewidths=2.0, zorder=4)
    collection.set_array(np.ma.masked_invalid(np.concatenate(per_segment)))
    ax.add_collection(collection)
    unit = "samples" if sample_unit == "samples" else sample_unit
    clipped = bool(finite.size and np.abs(finite).max() > lim)
    bar = fig.colorbar(collection, ax=ax, extend="both" if clipped else "neither", **bar_style)
    bar.set_label(f"throw ({unit}, + normal)" + (f"\nclipped at 98th pct, max {np.abs(finite).max():.3g}"
                                                   if clipped else ""), fontsize=8)
    return [cmap(norm(lim))]


def _casing():
    from matplotlib import patheffects

    return [patheffects.Stroke(linewidth=4.0, foreground="black", alpha=0.7), patheffects.Normal()]
