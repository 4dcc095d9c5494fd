"""The fault interpretation of arrays (seismo3d.seismic.faults): trace_faults' result and units, dead samples and
clipped amplitudes (clean_traces), bad arrays."""

import warnings

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError, Seismo3dWarning
from seismo3d.seismic import FaultInterpretation, trace_faults
from seismo3d.seismic.faults import clean_traces


@pytest.fixture(scope="module")
def section():
    return synthetic_cube((160, 96), n_faults=2, seed=3)


def test_trace_faults_units_and_result(section):
    res = trace_faults(section.cube, sample_interval=2.0, sample_unit="m", progress=False)
    assert isinstance(res, FaultInterpretation)
    assert res.sample_unit == "m" and res.sample_interval == 2.0
    assert res.likelihood.shape == res.strike_deg.shape == res.dip_deg.shape == res.thin.shape == (160, 96)
    assert len(res.throws) == len(res.faults) >= 2
    assert [t.fault_id for t in res.throws] == [f.id for f in res.faults]
    assert np.all(res.thin[res.thin > 0] == res.likelihood[res.thin > 0])


@pytest.mark.parametrize("kwargs", [dict(sample_unit="ms"), dict(sample_unit="s", sample_interval=1.0),
                                    dict(sample_interval=4.0), dict(sample_unit="ms", sample_interval=-4.0)])
def test_trace_faults_rejects_bad_units(section, kwargs):
    with pytest.raises(InputError):
        trace_faults(section.cube, progress=False, **kwargs)


@pytest.mark.parametrize("data", [np.zeros((40, 40)), np.full((20, 20, 20), np.nan), np.zeros((4, 5, 6, 7)),
                                  np.array([["a"] * 20] * 20)])
def test_trace_faults_rejects_bad_arrays(data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        with pytest.raises(InputError):
            trace_faults(data, progress=False)


def test_clipped_amplitudes_are_reported():
    # an 8-bit export clips the strong peaks and troughs (most Penobscot section samples sit at 0 or 255); the fault
    # job says so, and says nothing for unclipped data
    cube = synthetic_cube((16, 16, 48), seed=0).cube
    hi = float(np.percentile(np.abs(cube), 80))
    with pytest.warns(Seismo3dWarning, match="clipped amplitudes"):
        clean_traces(np.clip(cube, -hi, hi))
    with warnings.catch_warnings():
        warnings.simplefilter("error", Seismo3dWarning)
        clean_traces(cube)


def test_quantised_runs_are_not_dead_but_fill_values_are():
    # In an 8-bit export, slowly varying amplitudes repeat the same value for a few samples; a run of five 107s on the
    # Penobscot fault at crossline 56 (inlines 1-2) counted as a dead zone and blanked the fault's likelihood on
    # inlines 0-5. Dead samples are runs at a fill value: 0, or a value that fills a whole trace or a long run (the
    # image's grey 127 in a muted top).
    section = np.round(127.5 + 100 * synthetic_cube((40, 96), n_faults=0, seed=2).cube / 3).clip(0, 255)
    section[:, :20] = 127  # a muted top in the image's grey: a fill value
    section[5, 60:65] = 107  # a short run of a live value (quantisation)
    section[8, 50:55] = 127  # a short run of the fill value: a gap
    section[30] = 99  # a dead trace
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        dead = clean_traces(section).dead
    assert dead[:, :20].all() and dead[8, 50:55].all() and dead[30].all()
    assert not dead[5, 55:70].any()
    live = np.ones_like(dead)
    live[:, :20] = live[8, 50:55] = live[30] = False
    assert not dead[live].any()


def test_penobscot_fault_at_crossline_56_is_not_blanked(penobscot):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        dead = clean_traces(penobscot.cube).dead
    assert not dead[:, 50:62, 600:720].any()
    assert dead[:, 10:500, :40].mean() > 0.5  # the muted top (grey 127) is still dead
