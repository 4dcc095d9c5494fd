"""The steps after the fault likelihood are one sequence run by one executor (issues 30, 75): surface_cells calls the
named steps of the one run of the fault surfaces (SurfaceRun, on the whole array as one block in memory: MemoryRun) in
their order, and that run gives what the whole-image functions give."""

import numpy as np
import pytest

import seismo3d.seismic.faults.steps as surface_steps
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic.faults.surfaces.blocks import memory_surface_run
from seismo3d.seismic.faults import (
    FaultTracingOptions, fault_likelihood, fault_skins, thin_faults, trace_faults, vote_faults,
)
from seismo3d.seismic.faults.surfaces.skins import skins_from_cells
from seismo3d.seismic.faults.steps import surface_cells

STEPS = ["ridges", "seeds", "votes", "thresholds", "cells"]


@pytest.fixture(scope="module")
def cube():
    return synthetic_cube((40, 40, 48), seed=2).cube.astype(np.float32)


def _recording(monkeypatch):
    """Record the steps surface_cells calls, on which run class and executor."""
    calls = []
    original = surface_steps.surface_cells

    def recorded(run, opt, bar=None):
        for name in STEPS:
            method = getattr(run, name)

            def step(*args, _name=name, _method=method):
                calls.append((type(run).__name__, type(run.run).__name__, _name))
                return _method(*args)
            setattr(run, name, step)
        return original(run, opt, bar)

    monkeypatch.setattr("seismo3d.seismic.faults.pipeline.surface_cells", recorded)
    return calls


@pytest.mark.parametrize("ndim", [pytest.param(3, marks=pytest.mark.slow), 2])
def test_the_run_in_memory_is_the_whole_image_functions(cube, ndim):
    """The run in memory (the declared block steps on one block, the whole array) through surface_cells gives the
    votes, thinned votes and skins of vote_faults and fault_skins on the whole image (the composition the run in
    memory had before the sequence was shared)."""
    data = cube if ndim == 3 else cube[:, 20, :]
    opt = FaultTracingOptions()
    fl = fault_likelihood(data, options=opt.scan, progress=False)
    run = memory_surface_run(data, fl.likelihood.copy(), fl.strike_deg, fl.dip_deg, opt)
    found = surface_cells(run, opt)
    assert run.run.computed == {name: 1 for name in ("ridges", "surfaces", "votes", "thin", "cells")}

    seeds = thin_faults(fl.likelihood, fl.strike_deg, fl.dip_deg, threshold=0.0)
    votes = vote_faults(fl.likelihood, fl.strike_deg, fl.dip_deg, seeds, options=opt.voting)
    thin = thin_faults(votes.votes, votes.strike_deg, votes.dip_deg, threshold=0.0, sigma=0.0, dip_smoothing=0)
    lower, upper = opt.thresholds(thin)
    thin[thin < lower] = 0.0
    assert found.thresholds == (lower, upper)
    assert found.n_seeds == votes.n_seeds > 0
    np.testing.assert_array_equal(run.volume("votes"), votes.votes)
    np.testing.assert_array_equal(run.volume("vote_strike_deg"), votes.strike_deg)
    np.testing.assert_array_equal(run.volume("thin"), thin)
    skins = fault_skins(thin, votes.strike_deg, votes.dip_deg, lower=lower, upper=upper, options=opt.skins)
    faults = skins_from_cells(*run.cells_found(), shape=data.shape, lower=lower, upper=upper, options=opt.skins)
    assert len(skins) > 0 and [f.points.tolist() for f in faults] == [f.points.tolist() for f in skins]


def test_the_run_in_memory_calls_the_one_sequence(cube, monkeypatch):
    """trace_faults in memory goes through surface_cells, which calls the named steps in their order (the run by
    blocks goes through it too: test_chunked_faults.test_blocks_give_the_in_memory_faults)."""
    calls = _recording(monkeypatch)
    trace_faults(cube[:, 20, :], progress=False)
    assert calls == [("SurfaceRun", "MemoryRun", s) for s in STEPS]
