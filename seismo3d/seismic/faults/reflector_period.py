"""The half period of the reflectors around a fault (:func:`half_period`): the shift that aligns them in opposite
polarity. The evidence (:mod:`~seismo3d.seismic.faults.evidence`, ``clear_half_periods``, ``drag_half_periods``)
compares a fault's throw with it (:attr:`~seismo3d.seismic.faults.result.FaultThrow.half_period`): a throw within the
reflectors' wavelet may be their phase, not a displacement."""

from __future__ import annotations

import numpy as np

from ..traces import parabolic_offset

__all__ = ["half_period"]


def half_period(data, points, *, margin: int = 4, max_traces: int = 64) -> float:
    """The half period of the reflectors around a fault: the lag of the first trough of the mean autocorrelation of
    the traces around its points over the samples it spans (the shift that aligns the reflectors in opposite
    polarity), refined by a parabola through the trough.

    Parameters
    ----------
    data : ndarray or window source
        The amplitudes, 2D ``(n_traces, n_samples)`` or 3D, or a window source of
        :mod:`~seismo3d.seismic.faults.windows` (``window(i0, i1, j0, j1)``): the same traces either way.
    points : (n, ndim) array_like of int
        The fault's points, the sample last.
    margin : int
        Traces read beyond the points' extent on each lateral axis.
    max_traces : int
        Most traces read along each lateral axis, about the middle of that extent (the period varies slowly along a
        fault; a large 3D fault's box would be a large read).

    Returns
    -------
    float
        Samples; NaN when the autocorrelation has no trough (fewer than 4 samples, constant traces).
    """
    p = np.asarray(points, np.int64)
    lo, hi = p.min(axis=0), p.max(axis=0)
    box = []
    for axis in range(p.shape[1] - 1):
        a, b = int(lo[axis]) - margin, int(hi[axis]) + margin + 1
        if b - a > max_traces:
            a = (a + b - max_traces) // 2
            b = a + max_traces
        box += [max(a, 0), b]
    if len(box) == 2:  # a section: (trace, 0, sample)
        box += [0, 1]
    if hasattr(data, "window"):
        win = data.window(*box)
        (o0, o1), amp = win.origin, win.amplitude
    else:
        (o0, o1), amp = (0, 0), (data[:, None, :] if data.ndim == 2 else data)
    traces = np.asarray(amp[box[0] - o0:box[1] - o0, box[2] - o1:box[3] - o1, int(lo[-1]):int(hi[-1]) + 1],
                        np.float64).reshape(-1, int(hi[-1] - lo[-1]) + 1)
    n = traces.shape[1]
    if n < 4 or not traces.size:
        return float("nan")
    traces = traces - traces.mean(axis=1, keepdims=True)
    spectrum = np.fft.rfft(traces, 2 * n)
    ac = np.fft.irfft((spectrum * spectrum.conj()).real.sum(axis=0), 2 * n)[:n]
    d = np.diff(ac)
    trough = np.flatnonzero((d[:-1] < 0) & (d[1:] >= 0))
    if ac[0] <= 0 or not trough.size:
        return float("nan")
    k = int(trough[0]) + 1
    return float(k + parabolic_offset(-ac[k - 1], -ac[k], -ac[k + 1]))
