"""People's fault sticks placed on a 2D section: the one placement used wherever sticks meet a section's traces and
samples (:meth:`FaultSticks.section_lines <seismo3d.seismic.io.fault_sticks.FaultSticks.section_lines>`,
:meth:`~seismo3d.seismic.io.fault_sticks.FaultSticks.section_mask` and the fault scores of
:mod:`seismo3d.seismic.fault_scoring`).

Each node is placed on the traces by its inline (or crossline) number and on the samples by its two-way time or
depth, linearly between the section's own (``numpy.interp``: a node beyond the section is clamped to its edge), then
rounded to the nearest trace and sample (half to even); consecutive nodes of a stick, in the file's order, are joined
by straight lines of samples (Bresenham, :func:`skimage.draw.line`). The order matters: a Bresenham line drawn
backwards may differ by a sample where it passes midway between two, and the file's order is the order of the
reference computation the project's fault scores are checked with (``dev_fault_scores.py``: "sticks drawn as straight
lines between each pair of rows, placed on traces by inline number and on samples by time"). Until issue 54 the
sticks were drawn from their shallow end down, which differed from it by 6 and 8 samples on the two Great South Basin
lines.

A 3D survey's sticks are picked on some of its inlines and crosslines: :func:`picked_sections` finds the line each
stick lies on (the inline or crossline number its nodes share), so that the picked lines can be taken out of the cube
as sections and the sticks placed on them as above.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import InputError

__all__ = ["PickedSection", "picked_sections", "section_nodes", "section_pixels"]


def section_nodes(sticks, trace_labels, samples, *, axis: str = "inline") -> list:
    """The nodes of each stick in a section's index space, in the file's order.

    Parameters
    ----------
    sticks : FaultSticks
        People's fault sticks (:func:`~seismo3d.seismic.io.fault_sticks.read_fault_sticks`).
    trace_labels : (n_traces,) array_like of float
        The section's inline (or crossline) number of each trace, monotonic.
    samples : (n_samples,) array_like of float
        Its sample axis (two-way time in ms, or depth), in the sticks' ``z_unit``, increasing.
    axis : {'inline', 'crossline'}
        Which number labels the traces: 'inline' for a crossline (a line along inlines).

    Returns
    -------
    list of (int, (k, 2) float64 ndarray)
        Per stick, in stick order: its fault id and its nodes as (trace index, fractional sample index).

    Raises
    ------
    InputError
        ``axis`` not 'inline' or 'crossline', or sticks without numbers along it (NaN).
    """
    if axis not in ("inline", "crossline"):
        raise InputError(f"axis must be 'inline' or 'crossline'; got {axis!r}")
    labels = np.asarray(trace_labels, dtype=np.float64)
    order = np.argsort(labels)
    s = np.asarray(samples, dtype=np.float64)
    along = sticks.inline if axis == "inline" else sticks.crossline
    if np.isnan(along).any():
        raise InputError(f"some stick nodes have no {axis} number, so they cannot be placed on the section's traces; "
                         "read the sticks with the survey's coordinates (read_fault_sticks(path, coordinates=...))")
    out = []
    for fid, nodes in sticks.sticks():
        t = np.interp(along[nodes], labels[order], np.arange(labels.size, dtype=np.float64)[order])
        k = np.interp(sticks.z[nodes], s, np.arange(s.size, dtype=np.float64))
        out.append((fid, np.column_stack([t, k])))
    return out


def section_pixels(sticks, trace_labels, samples, *, axis: str = "inline") -> list:
    """The samples of a 2D section that each stick crosses (the placement of the module notes).

    Parameters
    ----------
    sticks, trace_labels, samples, axis
        As :func:`section_nodes`.

    Returns
    -------
    list of (int, (m, 2) int64 ndarray)
        Per stick, in stick order: its fault id and the (trace index, sample index) of the samples it crosses on the
        section (those beyond it dropped; a node shared by two segments listed twice).

    Raises
    ------
    InputError
        As :func:`section_nodes`.
    """
    from skimage.draw import line as draw_line

    n_traces, n_samples = np.asarray(trace_labels).size, np.asarray(samples).size
    out = []
    for fid, nodes in section_nodes(sticks, trace_labels, samples, axis=axis):
        v = np.round(nodes).astype(np.int64)
        parts = [np.zeros((0, 2), dtype=np.int64)]
        for (t0, k0), (t1, k1) in zip(v[:-1], v[1:]):
            rr, cc = draw_line(t0, k0, t1, k1)
            ok = (rr >= 0) & (rr < n_traces) & (cc >= 0) & (cc < n_samples)
            parts.append(np.column_stack([rr[ok], cc[ok]]).astype(np.int64))
        out.append((fid, np.concatenate(parts)))
    return out


@dataclass(frozen=True)
class PickedSection:
    """A line of a 3D survey that fault sticks were picked on (:func:`picked_sections`).

    Attributes
    ----------
    fixed : {'inline', 'crossline'}
        Which number the line keeps: ``'inline'`` for an inline (its traces labelled by crossline numbers).
    number : float
        Its inline (or crossline) number, one of the survey's.
    index : int
        Its position among the survey's inlines (or crosslines).
    nodes : (k,) int64 ndarray
        The stick nodes on it (indices into the sticks' node arrays), in stick order.
    """

    fixed: str
    number: float
    index: int
    nodes: np.ndarray

    @property
    def axis(self) -> str:
        """Which number labels the section's traces: the other one."""
        return "crossline" if self.fixed == "inline" else "inline"


def picked_sections(sticks, inlines, crosslines, samples=None) -> list:
    """The inlines and crosslines of a 3D survey that fault sticks were picked on, each with its sticks.

    A stick lies on an inline when the inline numbers of its nodes differ by less than a quarter of the survey's
    inline spacing and their mean is within a quarter spacing of one of the survey's inlines (the same for
    crosslines). A stick that lies on both (its nodes on one trace) goes to the line that other sticks were picked
    on, the inline when none or both were.

    Parameters
    ----------
    sticks : FaultSticks
        With inline and crossline numbers on every node (read with the survey's coordinates when the file holds X / Y
        only: :func:`~seismo3d.seismic.io.fault_sticks.read_fault_sticks`).
    inlines, crosslines : (n,) array_like of float
        The survey's inline and crossline numbers, each at least two, strictly monotonic.
    samples : (n_samples,) array_like of float, optional
        The survey's sample axis in the sticks' ``z_unit``: a stick none of whose nodes is within it (by half a
        sample interval) is refused.

    Returns
    -------
    list of PickedSection
        Inlines first, then crosslines, each in increasing number.

    Raises
    ------
    InputError
        No sticks; nodes without inline / crossline numbers; a stick on neither one inline nor one crossline (the
        message names it and its numbers); a stick on a line number between two of the survey's or beyond them; a
        stick wholly above or below ``samples``.
    """
    grid = {"inline": np.asarray(inlines, dtype=np.float64), "crossline": np.asarray(crosslines, dtype=np.float64)}
    if sticks.n_nodes == 0:
        raise InputError("the fault-stick file holds no stick; pass the sticks picked on the survey's lines")
    numbers = {"inline": sticks.inline, "crossline": sticks.crossline}
    if any(np.isnan(v).any() for v in numbers.values()):
        raise InputError("some stick nodes have no inline / crossline number; read the sticks with the survey's "
                         "coordinates (read_fault_sticks(path, coordinates=...)) to place them by their X / Y")
    spacing = {k: float(np.min(np.abs(np.diff(v)))) if v.size > 1 else 1.0 for k, v in grid.items()}
    names = dict(enumerate(sticks.names, start=1))
    placed, both = [], []
    for number, (fid, nodes) in enumerate(sticks.sticks(), start=1):
        what = f"stick {number} (of fault {names.get(fid, fid)!r})"
        _check_times(sticks.z[nodes], samples, what, sticks.z_unit)
        on = {k: float(np.mean(numbers[k][nodes])) for k in grid
              if np.ptp(numbers[k][nodes]) < 0.25 * spacing[k]}
        if not on:
            span = ", ".join(f"{k}s {np.min(numbers[k][nodes]):g}-{np.max(numbers[k][nodes]):g}" for k in grid)
            raise InputError(f"{what} is on no single inline or crossline ({span}): fault sticks are picked on the "
                             "survey's inlines and crosslines; leave out sticks of arbitrary lines or time slices")
        lines = {k: _grid_index(v, grid[k], spacing[k], what, k) for k, v in on.items()}
        (both if len(lines) == 2 else placed).append((lines, nodes))
    chosen = {(k, i) for lines, _ in placed for k, i in lines.items()}
    groups = {}
    for lines, nodes in placed + both:
        if len(lines) == 2:
            crossline_only = ("crossline", lines["crossline"]) in chosen and ("inline", lines["inline"]) not in chosen
            lines = {"crossline": lines["crossline"]} if crossline_only else {"inline": lines["inline"]}
        (fixed, index), = lines.items()
        groups.setdefault((fixed, index), []).append(nodes)
    order = sorted(groups, key=lambda key: (key[0] != "inline", grid[key[0]][key[1]]))
    return [PickedSection(k, float(grid[k][i]), int(i), np.concatenate(groups[(k, i)])) for k, i in order]


def _grid_index(value: float, grid: np.ndarray, spacing: float, what: str, name: str) -> int:
    """The index of the survey's line ``value`` is on, or an InputError saying where it falls instead."""
    i = int(np.argmin(np.abs(grid - value)))
    if abs(grid[i] - value) < 0.25 * spacing:
        return i
    lo, hi = float(np.min(grid)), float(np.max(grid))
    if value < lo - 0.25 * spacing or value > hi + 0.25 * spacing:
        raise InputError(f"{what} is on {name} {value:g}, outside the survey's {name}s {lo:g}-{hi:g}; pass the sticks "
                         "picked on this survey (or the cube they were picked on)")
    below, above = np.max(grid[grid < value]), np.min(grid[grid > value])
    raise InputError(f"{what} is on {name} {value:g}, between the survey's {name}s {below:g} and {above:g}: move it "
                     f"onto a {name} of the survey (its {name}s are {lo:g}-{hi:g} every {spacing:g})")


def _check_times(z: np.ndarray, samples, what: str, unit: str) -> None:
    """A stick with a node within the samples (by half an interval), or an InputError."""
    if samples is None:
        return
    s = np.asarray(samples, dtype=np.float64)
    half = 0.5 * float(np.median(np.diff(s))) if s.size > 1 else 0.5
    if np.all((z < s[0] - half) | (z > s[-1] + half)):
        raise InputError(f"{what} lies at {np.min(z):g}-{np.max(z):g} {unit}, outside the survey's samples "
                         f"{s[0]:g}-{s[-1]:g} {unit}; pass sticks picked in this survey's time (or depth)")
