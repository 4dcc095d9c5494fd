"""What the traces of a SEG-Y file are when segyio finds no inline / crossline grid in them.

segyio infers a grid only from a file sorted by inline or crossline with every (inline, crossline) present. Other
files are read as a trace list; :func:`trace_geometry` reads their trace headers to say what they hold, in one
phrase (a 2D or arbitrary line, an unsorted or irregular 3D survey), and whether they are prestack gathers (CDP
gathers: a position repeated with several offsets; shot records: several field records and no position at all).

Trace header fields (SEG-Y rev 1): field record 9-12, CDP 21-24, offset 37-40, CDP X / Y 181-184 / 185-188, and the
inline / crossline bytes given by the caller (rev 1: 189-192 / 193-196).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["TraceGeometry", "trace_geometry", "span"]

_FIELD_RECORD, _CDP, _OFFSET, _CDP_X, _CDP_Y = 9, 21, 37, 181, 185


@dataclass(frozen=True)
class TraceGeometry:
    """What the trace headers of a file without an inline / crossline grid say about its traces.

    Attributes
    ----------
    description : str
        A phrase such as ``'an arbitrary line through inlines 10-50 and crosslines 3-80'``.
    prestack : str or None
        Why the traces are prestack gathers (e.g. ``'4 field records and no CDP numbers or coordinates'``), or None.
    """

    description: str
    prestack: str | None


def span(values) -> str:
    """``'a-b'`` for the range of ``values`` (``'a'`` when they are all equal)."""
    lo, hi = int(np.min(values)), int(np.max(values))
    return f"{lo}" if lo == hi else f"{lo}-{hi}"


def _varies(values: np.ndarray) -> bool:
    return values.size > 1 and bool(np.any(values != values[0]))


def _positions(il, xl, cdp, x, y):
    """(trace positions as an (n, k) array, what they are) from the first header fields that vary; (None, '')."""
    if _varies(il) or _varies(xl):
        return np.column_stack([il, xl]), "inline / crossline"
    if _varies(cdp):
        return cdp[:, None], "CDP"
    if _varies(x) or _varies(y):
        return np.column_stack([x, y]), "coordinate"
    return None, ""


def _describe(il, xl, cdp, n_positions: int) -> str:
    n = il.size
    if _varies(il) and _varies(xl):
        n_il, n_xl = np.unique(il).size, np.unique(xl).size
        lines = f"inlines {span(il)} and crosslines {span(xl)}"
        if n_positions == n == n_il * n_xl:
            return f"a 3D cube of {n_il} inlines x {n_xl} crosslines whose traces are not sorted by inline or crossline"
        if n_positions <= n_il + n_xl:
            return f"an arbitrary line through {lines}"
        return f"an irregular 3D survey: {n_positions} trace positions of the {n_il} x {n_xl} grid of {lines}"
    if _varies(il) or _varies(xl):
        if _varies(il):
            return f"a 2D line along inlines {span(il)} (crossline {span(xl)}) in no sorted order"
        return f"a 2D line along crosslines {span(xl)} (inline {span(il)}) in no sorted order"
    if _varies(cdp):
        return f"a 2D or arbitrary line without inline / crossline numbers (CDP {span(cdp)})"
    return "a 2D line without inline / crossline or CDP numbers"


def trace_geometry(segyfile, iline: int, xline: int) -> TraceGeometry:
    """Describe the traces of a file opened by segyio as a trace list.

    Parameters
    ----------
    segyfile : segyio.SegyFile
        Open, with or without geometry; only its trace headers are read.
    iline, xline : int
        Trace header bytes of the inline and crossline numbers.

    Returns
    -------
    TraceGeometry
        ``prestack`` is set when a position (inline / crossline, else CDP, else coordinates: the first that varies)
        holds several traces and the offsets (bytes 37-40) vary, or when no position varies but the traces belong to
        several field records (bytes 9-12) of several traces each.
    """
    def field(byte):
        return np.asarray(segyfile.attributes(byte)[:], dtype=np.int64)

    il, xl, cdp = field(iline), field(xline), field(_CDP)
    positions, kind = _positions(il, xl, cdp, field(_CDP_X), field(_CDP_Y))
    n = il.size
    prestack = None
    if positions is None:
        records = field(_FIELD_RECORD)
        n_records = np.unique(records).size
        if 1 < n_records < n:
            prestack = f"{n_records} field records (trace header bytes 9-12) and no CDP numbers or coordinates"
        n_positions = n
    else:
        n_positions = np.unique(positions, axis=0).shape[0]
        offsets = field(_OFFSET)
        if n_positions < n and _varies(offsets):
            prestack = (f"{n} traces at {n_positions} {kind} positions with offsets {span(offsets)} (trace header "
                        "bytes 37-40)")
    description = _describe(il, xl, cdp, n_positions)
    if prestack is None and n_positions < n:
        description += f"; {n - n_positions} traces repeat a position"
    return TraceGeometry(description, prestack)


def scale_coordinates(values: np.ndarray, scalars: np.ndarray) -> np.ndarray:
    """Apply SEG-Y coordinate scalars (trace header bytes 71-72): positive multiplies, negative divides, 0 means 1.

    Parameters
    ----------
    values : (...) integer ndarray
        Coordinates as stored in the trace headers (e.g. CDP X, bytes 181-184).
    scalars : (...) integer ndarray
        The scalar of each trace, same shape.

    Returns
    -------
    (...) float64 ndarray
        In the survey's unit (metres or feet, binary header bytes 3255-3256).

    References
    ----------
    SEG-Y rev 1 (SEG Technical Standards Committee, 2002), trace header bytes 71-72.
    """
    s = scalars.astype(np.float64)
    factor = np.ones_like(s)
    factor[s > 0] = s[s > 0]
    factor[s < 0] = 1.0 / -s[s < 0]
    return values.astype(np.float64) * factor
