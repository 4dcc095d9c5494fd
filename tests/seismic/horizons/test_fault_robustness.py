"""A horizon tracked across traced faults does not hinge on a rounding-level change of the fault likelihood.

The generated cube 2 of ``benchmarks/horizons.py`` (64 x 64 x 96, 3 faults whose throws, 5.5-6.4 samples, are close to
the reflectors' period of 6.7 samples, so that the horizon's cycle across a fault is ambiguous to a short window): its
faults are traced from the fault likelihood as it is and multiplied by ``1 + 1e-6 * noise`` (each network call's
output; a few seeds, each checked to move some traced fault points), and horizons 1 and 4 are tracked across each set
of faults. Before the cross-fault pairs of the least-squares solve were judged with a margin between cycles and the
dynamic programme's steps expected the faults' jumps, such a change moved whole fault blocks by a cycle: horizon 4
0.095 -> 5.4 samples (median error) when the int8 network's first convolution ran without ONNX Runtime's blocked
layout (a 2e-6 mean change of the probability), horizon 1 81.8 -> 99.0 % of its traces within 2 samples under seed 0's
noise.
"""

import warnings

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic import horizon_errors, trace_faults, track_horizon
from seismo3d.seismic.faults.likelihood.network import FaultNetwork

CUBE = dict(shape=(64, 64, 96), n_faults=3, seed=2)  # benchmarks/horizons.py's cube 2
NOISE_SEEDS = (0, 3)  # seeds whose 1e-6 noise moves traced fault points (checked in the fixture)
# the share of the horizon's live traces (the generator's horizon defined) picked more than half a sample apart, or
# picked in one run and not the other, between the faults traced from the likelihood as it is and perturbed: measured
# at most 0.0xx (horizon 4) on this branch, 0.17 (horizon 1) and 0.96 (horizon 4) before
CHANGED_LIMIT = 0.03


def _perturbed_call(seed):
    """FaultNetwork.__call__ with its output multiplied by 1 + 1e-6 * noise, the noise drawn from ``seed`` for each call
    (the same for a call of the same shape whatever the order of the calls)."""
    call = FaultNetwork.__call__

    def perturbed(self, x):
        p = call(self, x)
        noise = np.random.default_rng(seed).standard_normal(p.shape)
        return (p * (1.0 + 1e-6 * noise)).astype(np.float32)

    return perturbed


@pytest.fixture(scope="module")
def traced():
    """The cube and its faults traced as they are (key None) and under each seed's noise."""
    syn = synthetic_cube(**CUBE)
    faults = {}
    for seed in (None, *NOISE_SEEDS):
        with pytest.MonkeyPatch.context() as mp, warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if seed is not None:
                mp.setattr(FaultNetwork, "__call__", _perturbed_call(seed))
            faults[seed] = trace_faults(syn.cube, progress=False)
    return syn, faults


def _points(faults):
    return [np.asarray(f.points) for f in faults.faults]


def _track(syn, k, faults):
    ref = syn.horizons[k]
    i0 = syn.shape[0] // 2  # the benchmark's seed: the middle inline, the picked trace nearest the middle
    ok = np.nonzero(np.isfinite(ref[i0]))[0]
    j0 = int(ok[np.argmin(np.abs(ok - syn.shape[1] // 2))])
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    return np.asarray(track_horizon(syn.cube, (i0, j0, float(ref[i0, j0])), polarity=pol, faults=faults).times,
                      np.float64)


@pytest.mark.slow
@pytest.mark.parametrize("k", [1, 4])
def test_a_1e6_change_of_the_fault_likelihood_does_not_move_the_horizon(traced, k):
    syn, faults = traced
    ref = syn.horizons[k]
    live = np.isfinite(ref)
    base = _track(syn, k, faults[None])
    for seed in NOISE_SEEDS:
        moved = [p.shape != q.shape or not np.array_equal(p, q) for p, q in zip(_points(faults[seed]),
                                                                               _points(faults[None]))]
        assert len(moved) == len(faults[None].faults) and any(moved), seed  # the noise moves the traced faults
        times = _track(syn, k, faults[seed])
        changed = (np.abs(times - base) > 0.5) | (np.isnan(times) != np.isnan(base))
        assert changed[live].mean() <= CHANGED_LIMIT, (seed, changed[live].mean())
        assert horizon_errors(times, ref).median_abs <= 0.16  # benchmarks/horizons.py's limit
