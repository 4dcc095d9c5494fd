"""The picture of a fault evaluation (``seismo3d evaluate``): people's faults and the traced faults over the seismic
line, and the precision-recall curve over the traced faults' confidence (matplotlib)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._atomic import atomic_path
from ..errors import InputError

__all__ = ["PEOPLE_COLOUR", "TRACED_COLOUR", "plot_fault_evaluation"]

PEOPLE_COLOUR = "#00c8ff"  # people's faults: cyan
TRACED_COLOUR = "#ff3b1f"  # traced faults: red-orange


def plot_fault_evaluation(section, people, traced, *, path, traces=None, samples=None, axis_labels=("trace", "sample"),
                          title=None, curve=None, clip_percentile=99.0, dpi=110) -> Path:
    """Draw people's and the traced fault samples over a seismic line in two colours, beside the precision-recall
    curve, and save a PNG.

    Parameters
    ----------
    section : (n_traces, n_samples) array_like
        Amplitudes, drawn in grey with symmetric limits at the ``clip_percentile`` of ``|amplitude|``.
    people, traced : (n_traces, n_samples) array_like of int
        Fault ids of people's faults (drawn as cyan dots, each id below its deepest sample) and of the traced faults
        (red-orange squares under them, so that a sample both hold shows both; each id above its shallowest sample),
        0 off the faults; a bool mask draws the samples without ids.
    path : str or os.PathLike
        The PNG to write (atomically); its folder must exist.
    traces : (n_traces,) array_like, optional
        Trace labels (inline or crossline numbers); default the trace indices.
    samples : (n_samples,) array_like, optional
        Sample times (ms) or depths; default the sample indices.
    axis_labels : (str, str), optional
        E.g. ``('inline', 'time (ms)')``.
    title : str, optional
        Above the section (e.g. the line and its precision, recall and F1).
    curve : PrecisionRecallCurve, optional
        :attr:`FaultLineScores.curve <seismo3d.seismic.fault_scoring.FaultLineScores.curve>`: drawn in a panel at
        the right, its average precision in the panel's title; none without it.
    clip_percentile : float, optional
    dpi : int, optional

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        Arrays of different shapes, or a section that is not 2D.
    """
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    from .plotting import symmetric_clip

    data = np.asarray(section, dtype=np.float32)
    p_lab, t_lab = np.asarray(people), np.asarray(traced)
    if data.ndim != 2 or p_lab.shape != data.shape or t_lab.shape != data.shape:
        raise InputError(f"section {data.shape}, people {p_lab.shape} and traced {t_lab.shape} must be one "
                         "(n_traces, n_samples) shape")
    p_mask, t_mask = p_lab != 0, t_lab != 0
    x = np.arange(data.shape[0], dtype=np.float64) if traces is None else np.asarray(traces, dtype=np.float64)
    s = np.arange(data.shape[1], dtype=np.float64) if samples is None else np.asarray(samples, dtype=np.float64)
    if x.shape != (data.shape[0],) or s.shape != (data.shape[1],):
        raise InputError("traces and samples must label the section's two axes")
    ratio = data.shape[1] / data.shape[0]  # the section's height over its width, in samples per trace
    width = 14.0 if curve is not None else 11.0
    height = float(np.clip(11.0 * ratio * 2.0, 3.2, 8.0)) + 1.0
    fig = Figure(figsize=(width, height), dpi=dpi, layout="constrained")
    if curve is not None:
        ax, ax_pr = fig.subplots(1, 2, width_ratios=[4.2, 1.0])
    else:
        ax, ax_pr = fig.subplots(), None
    clip = symmetric_clip(data, clip_percentile)
    dx = (x[-1] - x[0]) / max(x.size - 1, 1) if x.size > 1 else 1.0
    ds = (s[-1] - s[0]) / max(s.size - 1, 1) if s.size > 1 else 1.0
    ax.imshow(data.T, cmap="gray", vmin=-clip, vmax=clip, aspect="auto", interpolation="nearest",
              extent=(x[0] - dx / 2, x[-1] + dx / 2, s[-1] + ds / 2, s[0] - ds / 2))
    size = float(np.clip(1800.0 / max(data.shape), 2.0, 14.0))  # marker area (points^2): a sample's size or so
    for lab, colour, marker, area, deepest in ((t_lab, TRACED_COLOUR, "s", 2.2 * size, False),
                                               (p_lab, PEOPLE_COLOUR, "o", size, True)):
        t, k = np.nonzero(lab)
        ax.scatter(x[t], s[k], s=area, c=colour, marker=marker, linewidths=0)
        if lab.dtype != bool:
            _label_faults(ax, lab, x, s, colour, deepest)
    ax.set_xlim(x[0] - dx / 2, x[-1] + dx / 2)
    ax.set_ylim(s[-1] + ds / 2, s[0] - ds / 2)
    ax.set_xlabel(str(axis_labels[0]))
    ax.set_ylabel(str(axis_labels[1]))
    handles = [Line2D([], [], ls="", marker="o", color=PEOPLE_COLOUR, label=f"people's faults ({int(p_mask.sum())} "
                      "samples; ids below)"),
               Line2D([], [], ls="", marker="s", color=TRACED_COLOUR, label=f"traced faults ({int(t_mask.sum())} "
                      "samples; ids above)")]
    fig.legend(handles=handles, loc="outside lower center", ncol=2, fontsize="small", frameon=False)
    if title:
        ax.set_title(title, fontsize="medium", pad=12)
    if ax_pr is not None:
        _draw_curve(ax_pr, curve)
    with atomic_path(Path(path), suffix=".tmp.png") as tmp:
        fig.savefig(tmp)
    return Path(path)


def _label_faults(ax, labels: np.ndarray, x: np.ndarray, s: np.ndarray, colour: str, deepest: bool) -> None:
    """Each fault's id beside its deepest (or shallowest) sample, outlined in black to read over the seismic."""
    from matplotlib import patheffects

    outline = [patheffects.withStroke(linewidth=2.0, foreground="black")]
    for fid in np.unique(labels[labels != 0]):
        t, k = np.nonzero(labels == fid)
        end = int(np.argmax(k) if deepest else np.argmin(k))
        ax.annotate(str(int(fid)), (x[t[end]], s[k[end]]), xytext=(0, -2 if deepest else 2), textcoords="offset points",
                    ha="center", va="top" if deepest else "bottom", fontsize="x-small", color=colour,
                    fontweight="bold", annotation_clip=False, path_effects=outline)


def _draw_curve(ax, curve) -> None:
    """The precision-recall steps, each labelled with the faults taken so far."""
    r = np.concatenate([[0.0], np.asarray(curve.recall)])
    p = np.concatenate([[np.asarray(curve.precision)[0] if len(curve.precision) else 0.0],
                        np.asarray(curve.precision)])
    ax.step(r, p, where="post", color="0.3", lw=1.0)
    ax.plot(curve.recall, curve.precision, "o", color=TRACED_COLOUR, ms=4)
    for n, rr, pp in zip(curve.n_faults, curve.recall, curve.precision):
        ax.annotate(str(int(n)), (rr, pp), textcoords="offset points", xytext=(3, 3), fontsize="x-small")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1.05)
    ax.set_xlabel("recall")
    ax.set_ylabel("precision")
    ax.set_title(f"adding faults by confidence\naverage precision {curve.average_precision:.3f}",
                 fontsize="small")
    ax.grid(alpha=0.3)
