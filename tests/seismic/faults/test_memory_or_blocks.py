"""trace_faults runs in memory or block by block (issue 30): the library decides from the cube's size and the memory
limit, and both runs give the same refusals and warnings, from the same check functions."""

import re
import warnings

import numpy as np
import pytest

import seismo3d.seismic.faults.pipeline as pipeline
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError, Seismo3dWarning, UnsupportedDataError
from seismo3d.seismic.blocks.options import BlockRunOptions
from seismo3d.seismic.blocks.memory import fits_in_memory, in_memory_bytes, parse_memory_limit
from seismo3d.seismic.faults import trace_faults


class _Likelihood(Exception):
    """Raised where the fault likelihood would start: every check before it has passed."""


def _stop(*args, **kwargs):
    raise _Likelihood


@pytest.fixture(scope="module")
def seismic():
    return synthetic_cube((64, 64, 64), seed=1).cube.astype(np.float32)


def _nan(cube):
    out = cube.copy()
    out[10:14, 20:24, 30:40] = np.nan
    return out, (None, r"data has 160 NaN or inf samples \(0\.1%\); they are read as 0")


def _tiny(cube):
    return cube[:20, :6].copy(), (UnsupportedDataError, r"the data has 20 x 6 traces of 64 samples: fault tracing "
                                                        r"needs at least 32 traces")


def _velocity(cube):
    depth = np.linspace(1500.0, 4500.0, cube.shape[2], dtype=np.float32)
    lateral = np.linspace(0.0, 50.0, cube.shape[0], dtype=np.float32)[:, None, None]
    return (depth + lateral) * np.ones(cube.shape, np.float32), (UnsupportedDataError,
                                                                 r"this is not seismic amplitude data")


def _clipped(cube):
    return np.clip(cube, -0.3 * cube.max(), 0.3 * cube.max()), (None, r"sit at the data's smallest or largest "
                                                                      r"value: clipped amplitudes")


def _blank(cube):
    out = cube.copy()
    out[..., [20, 21, 40]] = [out.max(), out.min(), out.max()]  # blank images of a time-slice export
    return out, (None, r"3 time slices hold one value on every trace \(samples 20, 21, 40; 0 the first\)")


def _constant(cube):
    return np.full(cube.shape, 3.0, np.float32), (InputError, r"every sample has the same value")


@pytest.mark.slow  # 1.0-2.5 s per input in the fast lane, whose budget is 60 s
@pytest.mark.parametrize("case", [_nan, _tiny, _velocity, _clipped, _blank, _constant], ids=lambda f: f.__name__[1:])
def test_both_runs_give_the_same_refusal_or_warning(case, seismic, tmp_path, monkeypatch):
    """The in-memory run and the run by blocks (forced) of the same array: the same exception and message, or the
    same warning before the likelihood starts (where the test stops both runs)."""
    data, (error, message) = case(seismic)
    for module, name in ((pipeline, "run_likelihood"), (pipeline, "chunked_fault_likelihood"),
                         (pipeline, "chunked_learned_likelihood")):
        monkeypatch.setattr(module, name, _stop)
    outcomes = []
    for in_memory in (True, False):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", Seismo3dWarning)
            with pytest.raises(error or _Likelihood) as raised:
                trace_faults(data, blocks=BlockRunOptions(in_memory=in_memory, work_dir=tmp_path), progress=False)
        texts = sorted(str(w.message) for w in caught if issubclass(w.category, Seismo3dWarning))
        outcomes.append((raised.type, str(raised.value), texts))
    if error is None:
        assert any(re.search(message, t) for t in outcomes[0][2]), outcomes[0][2]
    else:
        assert re.search(message, outcomes[0][1]), outcomes[0][1]
    # the same refusal and the same warnings; a refusal's figures may differ where the block run judges a sample
    assert outcomes[0][0] == outcomes[1][0] and outcomes[0][2] == outcomes[1][2]
    assert re.search(message, outcomes[1][1] if error else " ".join(outcomes[1][2]))


def test_the_memory_decision():
    """fits_in_memory: the in-memory need (160 MiB and 24 bytes a float32 sample) against the limit less what the
    process holds; 2D sections always fit; limits parsed as the commands take them."""
    # the peaks of `seismo3d faults` beyond the process that decides, measured (/usr/bin/time, 2026-11-26): the need
    # covers each, by at most 30 % (the 128^3 demo, 192^3 generated, 18 x 512 x 1536 Penobscot inlines; MiB)
    for measured_shape, peak in (((128, 128, 128), 319), ((192, 192, 192), 627), ((18, 512, 1536), 1441)):
        assert peak << 20 <= in_memory_bytes(measured_shape) <= 1.3 * (peak << 20)
    shape = (256, 256, 256)
    need = in_memory_bytes(shape)
    assert fits_in_memory(shape, need + (100 << 20), held=100 << 20)
    assert not fits_in_memory(shape, need + (100 << 20), held=(100 << 20) + 1)
    assert fits_in_memory((100_000, 2000), "100MB", held=0)
    assert parse_memory_limit("500MB") == 500 * 10 ** 6 and parse_memory_limit(1 << 30) == 1 << 30
    with pytest.raises(InputError, match="at least 64 MB"):
        fits_in_memory(shape, "1MB")


@pytest.mark.slow  # the sample of blocks judged first (its scan): 30-50 s on 2 shared cores
def test_a_memory_limit_too_small_for_the_blocks_is_refused_before_any(seismic, monkeypatch, tmp_path):
    """trace_faults(memory_limit=...) below what the cube's run in memory needs goes by blocks; below what its blocks
    need, it is refused before any block, naming a limit that works."""
    monkeypatch.setattr(pipeline, "chunked_learned_likelihood", _stop)
    with pytest.raises(InputError, match=r"needs a memory limit of at least .*; pass memory_limit='[\d.]+[MG]B' or more"):
        trace_faults(seismic, memory_limit="100MB", blocks=BlockRunOptions(work_dir=tmp_path), progress=False)
    assert not any(tmp_path.iterdir())


@pytest.mark.slow  # two fault runs of a 48 x 56 x 48 cube, one by blocks
def test_a_labelled_cube_gives_one_result_type_in_memory_and_by_blocks(write_segy_cube, tmp_path):
    """seismo3d.open's lazy cube traced in memory and by (forced) blocks: the same FaultInterpretation, its volumes
    DataArrays on the cube's coordinates (numpy-backed, then dask over the Zarr stores), equal, the same faults
    (benchmarks/fault_blocks.py --only labelled_cube: the same at 192 x 160 x 128 under a memory limit)."""
    import dask.array as da
    import xarray as xr

    import seismo3d
    from seismo3d.seismic import FaultInterpretation

    path = write_segy_cube(tmp_path / "cube.sgy", synthetic_cube((48, 56, 48), seed=2).cube.astype(np.float32))
    cube = seismo3d.open(path)
    in_memory = trace_faults(cube, progress=False)
    by_blocks = trace_faults(cube, blocks=BlockRunOptions(in_memory=False, work_dir=tmp_path), progress=False)
    assert type(in_memory) is type(by_blocks) is FaultInterpretation and by_blocks.stores
    assert by_blocks.sample_unit == "ms" and by_blocks.sample_interval == 4.0
    for name in ("likelihood", "strike_deg", "dip_deg", "votes", "thin"):
        a, b = getattr(in_memory, name), getattr(by_blocks, name)
        assert isinstance(a, xr.DataArray) and isinstance(b, xr.DataArray) and a.dims == b.dims == cube.dims
        assert isinstance(a.data, np.ndarray) and isinstance(b.data, da.Array)
        for c in ("iline", "xline", "twt", "cdp_x", "cdp_y"):
            np.testing.assert_array_equal(b[c].values, cube[c].values)
            np.testing.assert_array_equal(a[c].values, cube[c].values)
        np.testing.assert_allclose(b.values, a.values, atol=1e-5, rtol=0)
    assert len(in_memory.faults) == len(by_blocks.faults) > 0
    for f, g in zip(in_memory.faults, by_blocks.faults):
        np.testing.assert_array_equal(f.points, g.points)


def test_a_run_by_blocks_plans_from_the_process_its_refusal_measured(seismic, monkeypatch, tmp_path):
    """The process is measured once, after the sample (the refusal's), and each stage plans from it (the surfaces
    from it grown by the likelihood stage): a process that moves between the stages moves no plan."""
    from seismo3d.seismic.blocks import memory
    from seismo3d.seismic.faults.preflight import CubeSample

    sizes = iter(range(300 << 20, 1000 << 20, 40 << 20))  # 40 MiB more at each measurement
    monkeypatch.setattr(memory, "resident_memory", lambda: next(sizes))
    monkeypatch.setattr(pipeline, "judge_sample", lambda *a, **k: CubeSample(3, 1, 0.1, 0.0))
    seen = {}

    def likelihood(x, path, *, chunking, **kwargs):
        seen["likelihood"] = chunking.process
        raise _Likelihood

    monkeypatch.setattr(pipeline, "chunked_learned_likelihood", likelihood)
    with pytest.raises(_Likelihood):
        trace_faults(seismic, memory_limit="2GB", blocks=BlockRunOptions(work_dir=tmp_path, in_memory=False),
                     progress=False)
    assert seen["likelihood"] == 320 << 20  # 300 MiB measured by the refusal, rounded up to a multiple of 64 MiB


class _Interrupted(Exception):
    """Raised right after the fault likelihood's store is renamed into place: a run interrupted there."""


@pytest.mark.slow
def test_a_likelihood_store_renamed_into_place_holds_its_id(seismic, monkeypatch, tmp_path):
    """A run interrupted right after the likelihood's store is renamed into place leaves a store that records its
    input and its id (written before the rename): the next run reuses it, and its surfaces record that id."""
    import os

    import zarr

    from seismo3d.seismic.blocks import memory
    from seismo3d.seismic.faults.preflight import CubeSample

    # the process measured at 300 MiB: the plan under 2 GB does not depend on what the test process holds (a pytest
    # worker of the whole suite held 1.9 GB, and the run was refused)
    monkeypatch.setattr(memory, "resident_memory", lambda: 300 << 20)
    monkeypatch.setattr(pipeline, "judge_sample", lambda *a, **k: CubeSample(3, 1, 0.1, 0.0))
    rename = os.replace

    def interrupted(src, dst):
        rename(src, dst)
        if str(src).endswith(pipeline.LIKELIHOOD_STORE + ".partial"):
            raise _Interrupted

    blocks = BlockRunOptions(work_dir=tmp_path, in_memory=False)
    monkeypatch.setattr(os, "replace", interrupted)
    with pytest.raises(_Interrupted):
        trace_faults(seismic, memory_limit="2GB", blocks=blocks, progress=False)
    monkeypatch.setattr(os, "replace", rename)
    attrs = zarr.open_group(str(tmp_path / pipeline.LIKELIHOOD_STORE), mode="r").attrs
    assert attrs["source"] == "cube" and attrs["likelihood"] == "learned" and len(attrs["id"]) == 32
    seen = {}

    def surfaces(x, likelihood, output, **kwargs):
        seen["likelihood_id"] = zarr.open_group(str(likelihood), mode="r").attrs.get("id")  # what they record
        raise _Likelihood

    monkeypatch.setattr(pipeline, "chunked_learned_likelihood", _stop)  # reused: not computed again
    monkeypatch.setattr(pipeline, "chunked_fault_surfaces", surfaces)
    with pytest.raises(_Likelihood):
        trace_faults(seismic, memory_limit="2GB", blocks=blocks, progress=False)
    assert seen["likelihood_id"] == attrs["id"]
