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
