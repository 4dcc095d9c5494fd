"""Generated sections with known horizons shared by the horizon tests (least squares, dynamic programming, cycle
cut)."""

import numpy as np

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic.reflectors import nearest_pick, reflector_picks


def section_and_truth(k=2, seed=3):
    """A 160-trace synthetic section without faults, the polarity of its horizon ``k``, every trace's picks of that
    polarity and the horizon's true picks."""
    syn = synthetic_cube((160, 128), n_faults=0, seed=seed, noise=0.05)
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    picks, offsets = reflector_picks(syn.cube, polarity=pol)
    truth = np.array([nearest_pick(picks, offsets, j, syn.horizons[k][j], 1.0) for j in range(160)])
    assert np.isfinite(truth).all()
    return syn, pol, picks, offsets, truth


def next_cycle(picks, offsets, k, t):
    """The pick after ``t`` on trace ``k`` (one reflector cycle down)."""
    p = picks[offsets[k]:offsets[k + 1]]
    return float(p[np.searchsorted(p, t + 1e-6)])


def random_layers(lateral=(160,), n_samples=160, dip=0.05, seed=5):
    """Traces of one random reflectivity series (so that no two cycles look alike) dipping gently along the last
    lateral axis, convolved with a Ricker wavelet: (prod(lateral), n_samples) float32, their peak picks, and each
    trace's position along the last lateral axis."""
    rng = np.random.default_rng(seed)
    refl = rng.standard_normal(n_samples + 40) * (rng.random(n_samples + 40) < 0.3)
    tt = np.arange(-10, 11)
    wavelet = (1 - 2 * (np.pi * 0.08 * tt) ** 2) * np.exp(-(np.pi * 0.08 * tt) ** 2)
    base = np.convolve(refl, wavelet, mode="same")
    x = np.arange(base.size, dtype=np.float64)
    pos = np.indices(lateral)[-1].ravel()
    traces = np.stack([np.interp(np.arange(n_samples) + 20 - dip * j, x, base) for j in pos]).astype(np.float32)
    picks, offsets = reflector_picks(traces, polarity="peak")
    return traces, picks, offsets, pos
