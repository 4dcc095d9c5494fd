"""Raw 2D sections (big-endian float32, trace after trace, no header) and ASCII line exports (one trace per row).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import DataNotFoundError, InputError

__all__ = ["known_section_shape", "read_ascii_lines", "read_section"]

# (n_traces, n_samples) of the raw sections in the data directory's seismic/sections (see its README).
_SECTION_SHAPES = {
    "campos_gx373": (550, 300),
    "costarica_crf": (500, 180),
    "costarica_gx808": (825, 210),
    "costarica_gx809": (825, 210),
    "f3_f3d75s": (440, 222),
    "teapot_tpd": (357, 315),
    "teapot_tp73": (357, 240),
    "f3_f3d178sub2": (951, 242),
}


def known_section_shape(path) -> tuple | None:
    """The shape of a raw section of the data directory's ``seismic/sections``, known by its file name.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.f32be`` file; only its stem is used (``teapot_tpd.f32be`` -> ``teapot_tpd``).

    Returns
    -------
    tuple of int or None
        ``(n_traces, n_samples)``, or None for a file whose shape :func:`read_section` must be given.
    """
    return _SECTION_SHAPES.get(Path(path).stem)


def read_section(path, *, n_traces=None, n_samples=None) -> np.ndarray:
    """Read a raw 2D section stored as big-endian float32, trace after trace (no header).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.f32be`` file. The shapes of the sections in the data directory's ``seismic/sections`` are known by file
        stem (campos_gx373 550 x 300, costarica_crf 500 x 180, costarica_gx808 / gx809 825 x 210, f3_f3d75s 440 x 222,
        teapot_tpd 357 x 315, teapot_tp73 357 x 240, f3_f3d178sub2 951 x 242); for other files pass the shape.
    n_traces, n_samples : int, optional
        Shape; for an unknown file give at least one, the other is derived from the file size.

    Returns
    -------
    section : (n_traces, n_samples) float32 ndarray
        Axis 0 trace, axis 1 sample (downward).

    Raises
    ------
    DataNotFoundError
        No such file.
    InputError
        Unknown file without a shape, or a shape that does not match the file size.
    """
    path = Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"no section file at {path}; check the path")
    n_values, rem = divmod(path.stat().st_size, 4)
    if rem:
        raise InputError(f"{path.name} has {path.stat().st_size} bytes, not a whole number of float32 values; "
                         "the file is truncated or not raw float32")
    known = _SECTION_SHAPES.get(path.stem)
    if n_traces is None and n_samples is None:
        if known is None:
            raise InputError(f"the shape of {path.name} is unknown; pass n_traces= and/or n_samples= "
                             f"(it holds {n_values} float32 values)")
        n_traces, n_samples = known
    elif n_traces is None or n_samples is None:
        given = int(n_traces if n_traces is not None else n_samples)
        if given <= 0 or n_values % given:
            raise InputError(f"{path.name} holds {n_values} float32 values, not a multiple of {given}; check the shape")
        other = n_values // given
        n_traces, n_samples = (given, other) if n_traces is not None else (other, given)
    n_traces, n_samples = int(n_traces), int(n_samples)
    if n_traces <= 0 or n_samples <= 0 or n_traces * n_samples != n_values:
        raise InputError(f"{path.name} holds {n_values} float32 values but the shape ({n_traces}, {n_samples}) needs "
                         f"{n_traces * n_samples}; check n_traces / n_samples")
    data = np.fromfile(path, dtype=">f4").reshape(n_traces, n_samples)
    return data.astype(np.float32)


def read_ascii_lines(path):
    """Read an ASCII line export: one trace per row, ``inline xline sample_0 sample_1 ...`` (whitespace separated).

    Parameters
    ----------
    path : str or os.PathLike
        E.g. ``f3_inline362.ascii`` (inline 362 of F3, crosslines 300-1250, 463 samples at 4 ms).

    Returns
    -------
    inlines : (n_traces,) int32 ndarray
    xlines : (n_traces,) int32 ndarray
    traces : (n_traces, n_samples) float32 ndarray
        Axis 1 is the sample (downward). The sample interval is not stored in the file.

    Raises
    ------
    DataNotFoundError
        No such file.
    InputError
        Rows of unequal length, non-numeric values, non-integer inline / crossline numbers, or fewer than 3 columns.
    """
    path = Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"no ASCII file at {path}; check the path")
    try:
        table = np.loadtxt(path, dtype=np.float64, ndmin=2)
    except ValueError as exc:
        raise InputError(f"{path.name} is not a table of numbers with equal-length rows ({exc}); expected one trace "
                         "per row: inline, xline, then the samples") from exc
    if table.shape[0] == 0 or table.shape[1] < 3:
        raise InputError(f"{path.name} has {table.shape[1] if table.size else 0} columns; expected inline, xline and "
                         "at least one sample per row")
    ids = table[:, :2]
    if not np.all(ids == np.round(ids)):
        raise InputError(f"the first two columns of {path.name} must be integer inline and crossline numbers")
    return ids[:, 0].astype(np.int32), ids[:, 1].astype(np.int32), table[:, 2:].astype(np.float32)
