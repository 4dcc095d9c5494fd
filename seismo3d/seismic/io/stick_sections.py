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
"""

from __future__ import annotations

import numpy as np

from ...errors import InputError

__all__ = ["section_nodes", "section_pixels"]


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
