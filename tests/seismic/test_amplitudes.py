"""The amplitudes' dead samples (seismo3d.seismic.amplitudes): the rules as options (DeadSampleOptions)."""

import warnings

import numpy as np
import pytest

from seismo3d.errors import InputError, Seismo3dWarning
from seismo3d.seismic.faults import FaultTracingOptions
from seismo3d.seismic.amplitudes import DeadSampleOptions, clean_traces, near_dead_samples


def _section_with_a_gap(gap: int) -> np.ndarray:
    rng = np.random.default_rng(0)
    section = rng.normal(size=(20, 64)).astype(np.float32)
    section[7, 30:30 + gap] = 0.0  # a gap of `gap` zeros in one trace
    return section


def test_the_defaults_are_the_documented_rules():
    opt = DeadSampleOptions()
    assert (opt.run, opt.fill_run, opt.reach, opt.clipped_warning) == (5, 16, (3, 8), 0.05)
    assert FaultTracingOptions().dead == opt


@pytest.mark.parametrize("run, dead", [(5, True), (7, False)])
def test_a_gap_is_dead_when_it_is_as_long_as_the_run(run, dead):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", Seismo3dWarning)
        found = clean_traces(_section_with_a_gap(6), options=DeadSampleOptions(run=run)).dead
    said = [str(w.message) for w in caught if "constant over" in str(w.message)]
    assert said == ([f"0.5% of the samples are constant over {run} or more samples (mutes, gaps, 0 dead traces); "
                     "fault likelihood within 3 traces and 8 samples of them is set to 0"] if dead else [])
    assert found[7, 30:36].all() == dead and np.count_nonzero(found) == (6 if dead else 0)



def _runs_at_least(trace: np.ndarray, run: int) -> np.ndarray:
    """Samples in runs of at least ``run`` equal values of one trace, found one run at a time."""
    inside = np.zeros(trace.shape, bool)
    start = 0
    for k in range(1, trace.size + 1):
        if k == trace.size or trace[k] != trace[start]:
            inside[start:k] = k - start >= run
            start = k
    return inside


def test_the_dead_samples_of_a_cube_are_its_runs_at_a_fill_value_trace_by_trace():
    """Runs at 0 of 3 to 7 samples in a few traces of a cube (and the equal neighbours of one more trace): the dead
    samples are exactly the samples of the runs of 5 or more, whichever traces hold them."""
    rng = np.random.default_rng(3)
    cube = rng.normal(size=(9, 11, 48)).astype(np.float32)
    for (i, j), (k, n) in zip([(0, 0), (2, 5), (4, 10), (8, 3), (8, 4)], [(0, 7), (20, 5), (41, 7), (10, 4), (30, 3)]):
        cube[i, j, k:k + n] = 0.0
    cube[6, 6, 12:18] = cube[6, 6, 12]  # equal samples, not at a fill value: not dead
    expected = np.zeros(cube.shape, bool)
    for i, j in np.ndindex(cube.shape[:2]):
        expected[i, j] = _runs_at_least(cube[i, j], 5) & (cube[i, j] == 0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        found = clean_traces(cube).dead
    assert np.count_nonzero(expected) == 19 and np.array_equal(found, expected)

def test_the_reach_grows_the_dead_samples_by_traces_and_samples():
    dead = np.zeros((20, 64), bool)
    dead[10, 30] = True
    near = near_dead_samples(dead, options=DeadSampleOptions(reach=(2, 5)))
    assert np.count_nonzero(near) == 5 * 11 and near[8:13, 25:36].all()
    assert np.array_equal(near_dead_samples(dead, options=DeadSampleOptions(reach=(0, 0))), dead)


@pytest.mark.parametrize("kwargs", [dict(run=1), dict(fill_run=1.5), dict(reach=(3,)), dict(reach=(-1, 8)),
                                    dict(clipped_warning=1.5)])
def test_bad_rules_are_refused(kwargs):
    with pytest.raises(InputError, match="DeadSampleOptions"):
        DeadSampleOptions(**kwargs)
