"""A horizon tracked across traced faults does not hinge on a rounding-level change of the fault likelihood.

The generated cube 2 of ``benchmarks/horizons.py`` (64 x 64 x 96, 3 faults whose throws, 5.5-6.4 samples, are close to
the reflectors' period, about 6.7 samples) has its faults traced three times: with the int8 network's first (float)
convolution in ONNX Runtime's blocked channel layout, without it (the probability moves by 2e-6 on average: a float
sum in another order), and without it with the probability times ``1 + 1e-6 * noise``; its horizon 4 is tracked
across each set of faults from the benchmark's seed. Before the dynamic programme expected a step across a fault to
jump by the fault's throw, it moved a narrow fault block or the rest of the horizon by a cycle depending on which
set it got: median error 0.095 and 5.415 samples, 98.9 % of the live traces apart (this test on main 3f3c253).
"""

import warnings

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic import horizon_errors, trace_faults, track_horizon
from seismo3d.seismic.faults.likelihood import network

CUBE = dict(shape=(64, 64, 96), n_faults=3, seed=2)  # benchmarks/horizons.py's cube 2
HORIZON = 4
# the share of the horizon's live traces (the generator's horizon defined there) picked more than half a sample
# apart, or picked in one run and not in the other, between two of the fault sets: measured at most 0.063 (the two
# layouts; 0.030 and 0.042 against the noise), 0.989 on main 3f3c253
CHANGED_LIMIT = 0.10
MEDIAN_LIMIT = 0.16  # benchmarks/horizons.py's limit (measured 0.067-0.073 here)


def _session(blocked):
    """onnxruntime.InferenceSession with the first convolution's layout forced (blocked or not)."""
    import onnxruntime as ort

    make = ort.InferenceSession

    def session(*args, **kwargs):
        kwargs["disabled_optimizers"] = [] if blocked else ["NchwcTransformer"]
        return make(*args, **kwargs)

    return session


def _noisy(seed):
    """FaultNetwork.__call__ with its output multiplied by 1 + 1e-6 * noise (one generator for the run's calls)."""
    call, rng = network.FaultNetwork.__call__, np.random.default_rng(seed)

    def perturbed(self, x):
        p = call(self, x)
        return (p * (1.0 + 1e-6 * rng.standard_normal(p.shape))).astype(np.float32)

    return perturbed


def _differ(a, b) -> bool:
    """Whether two lists of faults' points differ."""
    return len(a) != len(b) or any(p.shape != q.shape or not np.array_equal(p, q) for p, q in zip(a, b))


@pytest.fixture(scope="module")
def traced():
    """The cube and its faults traced from the three likelihoods."""
    import onnxruntime as ort

    syn = synthetic_cube(**CUBE)
    faults = {}
    for name, blocked, noise in (("blocked", True, None), ("unblocked", False, None), ("unblocked, noise", False, 4)):
        with pytest.MonkeyPatch.context() as mp, warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mp.setattr(ort, "InferenceSession", _session(blocked))
            if noise is not None:
                mp.setattr(network.FaultNetwork, "__call__", _noisy(noise))
            network.load_fault_network.cache_clear()
            faults[name] = trace_faults(syn.cube, progress=False)
        network.load_fault_network.cache_clear()
    return syn, faults


@pytest.mark.slow
def test_a_rounding_level_change_of_the_fault_likelihood_does_not_move_the_horizon(traced):
    syn, faults = traced
    points = {k: [np.asarray(f.points) for f in v.faults] for k, v in faults.items()}
    # the fault sets are not all the same (the test tests): with the cube's network on the 0.7 grid alone (its 96
    # samples leave the 0.5 grid out) the two layouts gave the same faults, the noise other ones
    assert any(_differ(points[a], points[b]) for a, b in (("blocked", "unblocked"), ("unblocked", "unblocked, noise"),
                                                          ("blocked", "unblocked, noise")))
    ref = syn.horizons[HORIZON]
    i0 = syn.shape[0] // 2  # the benchmark's seed: the middle inline, the picked trace nearest the middle
    ok = np.nonzero(np.isfinite(ref[i0]))[0]
    j0 = int(ok[np.argmin(np.abs(ok - syn.shape[1] // 2))])
    pol = "peak" if syn.horizon_polarity[HORIZON] > 0 else "trough"
    times = {k: np.asarray(track_horizon(syn.cube, (i0, j0, float(ref[i0, j0])), polarity=pol, faults=f).times,
                           np.float64) for k, f in faults.items()}
    live = np.isfinite(ref)
    for name, t in times.items():
        assert horizon_errors(t, ref).median_abs <= MEDIAN_LIMIT, name
        for other, u in times.items():
            changed = (np.abs(t - u) > 0.5) | (np.isnan(t) != np.isnan(u))
            assert changed[live].mean() <= CHANGED_LIMIT, (name, other, changed[live].mean())
