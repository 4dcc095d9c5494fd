"""The vertical scale of the search: where the mean trace spectra of the two volumes agree.

A change of sample rate stretches the spectrum, and the wavelet is common to both volumes, so the ratio of the sample
intervals is the stretch that makes the mean amplitude spectra of their traces agree best. The search uses it as the
vertical scale of its candidate maps; the refinement then fits it with the rest.
"""

from __future__ import annotations

import numpy as np

__all__ = ["trace_spectrum", "vertical_scale"]


def trace_spectrum(v, n_fft: int) -> np.ndarray:
    """Mean amplitude spectrum ((n_fft // 2 + 1,) float64) of the live traces of a cube (at most 4000, evenly
    picked), Hann-windowed."""
    tr = v.reshape(-1, v.shape[2])
    tr = tr[np.ptp(tr, axis=1) > 0]
    if len(tr) > 4000:
        tr = tr[np.linspace(0, len(tr) - 1, 4000).astype(int)]
    tr = tr - tr.mean(axis=1, keepdims=True)
    return np.abs(np.fft.rfft(tr * np.hanning(tr.shape[1]), n=n_fft, axis=1)).mean(axis=0)


def vertical_scale(fixed, moving, lo: float, hi: float) -> float:
    """Sample-rate ratio (moving sample in fixed samples) in [lo, hi] where the mean trace spectra agree best (361
    log-spaced candidates): a change of sample rate stretches the spectrum, and the wavelet is common to both.

    Parameters
    ----------
    fixed, moving : (n0, n1, n2) float32 ndarray
        The two volumes (normalised amplitudes).
    lo, hi : float
        The range searched.

    Returns
    -------
    float
    """
    n_fft = int(2 ** np.ceil(np.log2(4 * max(fixed.shape[2], moving.shape[2]))))
    freqs = np.fft.rfftfreq(n_fft)
    sf, sm = trace_spectrum(fixed, n_fft), trace_spectrum(moving, n_fft)
    stretches = np.exp(np.linspace(np.log(lo), np.log(hi), 361))
    # every candidate at once: the fixed spectrum read at each moving frequency (cycles per moving sample, in cycles
    # per fixed sample), correlated with the moving spectrum over the frequencies below the fixed Nyquist
    f = freqs[1:][None, :] / stretches[:, None]
    ok = f < 0.5
    a = np.where(ok, np.interp(f, freqs, sf), 0.0)
    b = np.where(ok, sm[1:][None, :], 0.0)
    n = ok.sum(axis=1)
    nn = np.maximum(n, 1)
    a_c = np.where(ok, a - (a.sum(axis=1) / nn)[:, None], 0.0)
    b_c = np.where(ok, b - (b.sum(axis=1) / nn)[:, None], 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = (a_c * b_c).sum(axis=1) / np.sqrt((a_c ** 2).sum(axis=1) * (b_c ** 2).sum(axis=1))
    c = np.where((n >= 8) & np.isfinite(c), c, -np.inf)  # fewer than 8 frequencies: not a candidate
    return float(stretches[int(np.argmax(c))]) if np.isfinite(c).any() else 1.0
