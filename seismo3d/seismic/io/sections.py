"""Raw 2D sections (big-endian float32, trace after trace, no header) and ASCII line exports (one trace per row).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import DataNotFoundError, InputError

__all__ = ["known_section_shape", "read_ascii_lines", "read_section", "trace_length_correlations"]

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
        Unknown file without a shape, a shape that does not match the file size, or a shape whose neighbouring
        traces do not look alike while another shape of the file makes them look alike as a seismic section's do
        (e.g. the numbers of traces and samples swapped; :func:`trace_length_correlations`).
    """
    path = Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"no section file at {path}; check the path")
    n_values, rem = divmod(path.stat().st_size, 4)
    if rem:
        raise InputError(f"{path.name} has {path.stat().st_size} bytes, not a whole number of float32 values; "
                         "the file is truncated or not raw float32")
    known = _SECTION_SHAPES.get(path.stem)
    n_samples_given = n_samples is not None
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
    values = np.fromfile(path, dtype=">f4").astype(np.float32)
    if (n_traces, n_samples) != known:  # a shape the caller gave: checked against what the values say
        _check_trace_length(values, n_samples, path.name, given="n_samples" if n_samples_given else "n_traces")
    return values.reshape(n_traces, n_samples)


# A read is refused when its neighbouring traces correlate less than half as well as at another trace length of the
# file that makes them correlate at least this well (measured on the data folder's sections: right reads 0.79-0.97,
# the swapped shape within +-0.07; chosen on campos_gx373 and costarica_gx808, seen on the F3 and Teapot sections).
_NEIGHBOUR_CORRELATION = 0.5


def trace_length_correlations(values, *, min_traces: int = 8, min_samples: int = 32) -> dict:
    """How well neighbouring traces of a raw section correlate at each trace length its values allow.

    A section stored trace after trace and read with its own trace length has neighbouring traces that look alike
    (reflectors continue from trace to trace: correlation 0.8-0.97 on the data folder's sections); read with
    another length (e.g. its numbers of traces and samples swapped), the samples side by side come from other times
    of other traces and hardly correlate (within +-0.07 there).

    Parameters
    ----------
    values : (n,) array_like of float
        The file's values in their order.
    min_traces, min_samples : int
        The fewest traces and the fewest samples per trace a length is tried with (fault tracing needs 32 samples:
        :class:`~seismo3d.seismic.faults.options.FaultTracingOptions` ``min_samples``; shorter lags would measure
        the wavelet along a trace, not neighbouring traces).

    Returns
    -------
    dict of int to float
        Trace length (a divisor of ``n``) -> the normalised autocorrelation of the values at that lag (sample k of
        a trace with sample k of the next; 1 for identical neighbours, about 0 for unrelated ones).

    References
    ----------
    Wiener-Khinchin theorem: the autocorrelation as the inverse FFT of the power spectrum, zero-padded to at least
    ``2 n`` values so that no lag wraps around; each lag's sum divided by its number of products (the unbiased
    estimate) and by the variance (J. S. Bendat and A. G. Piersol, *Random Data: Analysis and Measurement
    Procedures*, Wiley, 4th ed., 2010, the correlation estimates computed through the FFT).
    """
    from scipy import fft

    x = np.asarray(values, dtype=np.float64).ravel()
    n = x.size
    divisors = {d for k in range(1, int(np.sqrt(n)) + 1) if n % k == 0 for d in (k, n // k)}
    lengths = sorted(m for m in divisors if min_samples <= m <= n // min_traces)
    if not lengths:
        return {}
    x = np.where(np.isfinite(x), x, 0.0)
    x -= x.mean()
    size = fft.next_fast_len(2 * n, real=True)  # zero-padded: no wrap-around
    ac = fft.irfft(np.abs(fft.rfft(x, size)) ** 2, size)[:n]
    if ac[0] <= 0:
        return {m: 0.0 for m in lengths}
    return {m: float(ac[m] / (n - m) / (ac[0] / n)) for m in lengths}


def _check_trace_length(values, n_samples: int, name: str, *, given: str) -> None:
    """InputError when the section's traces read as ``n_samples`` long do not look like neighbours while another
    length makes them (:func:`trace_length_correlations`), e.g. its numbers of traces and samples swapped."""
    r = trace_length_correlations(values)
    if n_samples not in r:
        return
    best = max(r, key=r.get)
    if r[best] < _NEIGHBOUR_CORRELATION or r[n_samples] >= r[best] / 2:
        return
    n = len(values)
    fix = f"n_samples={best}" if given == "n_samples" else f"n_traces={n // best}"
    raise InputError(f"{name} read as {n // n_samples} traces of {n_samples} samples has neighbouring traces that do "
                     f"not look alike (correlation {r[n_samples]:.2f}), while read as {n // best} traces of {best} "
                     f"samples they do ({r[best]:.2f}), as a seismic section's traces do; pass {fix}")


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
