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
    best, best_c = 1.0, -np.inf
    for s2 in np.exp(np.linspace(np.log(lo), np.log(hi), 361)):
        f = freqs[1:] / s2  # moving frequency (cycles per moving sample) in cycles per fixed sample
        ok = f < 0.5
        if ok.sum() < 8:
            continue
        c = np.corrcoef(np.interp(f[ok], freqs, sf), sm[1:][ok])[0, 1]
        if c > best_c:
            best, best_c = float(s2), c
    return best
