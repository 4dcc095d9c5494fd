"""trace_faults and track_horizon on labelled DataArrays (seismo3d's, segysak's, convert's Zarr) give the results of
the numpy values, with the coordinates carried through."""

import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from seismo3d.errors import InputError

xr = pytest.importorskip("xarray")

from seismo3d.seismic.io.xarray import (  # noqa: E402
    open_seismic_dataarray, seismic_axes, trace_faults_xr, track_horizon_xr,
)


@pytest.fixture(scope="module")
def section():
    from seismo3d.data.synthetic import synthetic_cube

    return synthetic_cube((128, 96), seed=1).cube


def test_trace_faults_on_a_dataarray_equals_numpy(section):
    from seismo3d.seismic import trace_faults

    dt = 4.0
    ref = trace_faults(section, sample_interval=dt, sample_unit="ms", progress=False)
    inlines = np.arange(2001, 2001 + 2 * section.shape[0], 2)
    da = xr.DataArray(section[:, None, :], dims=("inline", "crossline", "sample"),
                      coords={"inline": inlines, "crossline": [7], "sample": ("sample", 500 + dt * np.arange(96),
                                                                              {"units": "ms"}),
                              "cdp_x": (("inline", "crossline"), 1000.0 + 12.5 * inlines[:, None]),
                              "cdp_y": (("inline", "crossline"), 5000.0 + 0.0 * inlines[:, None])})
    out = trace_faults_xr(da)
    got = out.interpretation
    assert len(got.faults) == len(ref.faults) > 0
    for a, b in zip(got.faults, ref.faults):
        assert_array_equal(a.points, b.points)
    assert_array_equal(out.volumes["likelihood"].values[:, 0, :], ref.likelihood)
    assert out.volumes["likelihood"].dims == ("inline", "crossline", "sample")
    assert_array_equal(out.volumes["cdp_x"].values, da["cdp_x"].values)
    assert_array_equal(out.volumes["inline"].values, inlines)
    assert got.sample_unit == "ms" and got.sample_interval == dt


@pytest.mark.slow  # 9 s on 2 shared cores
def test_track_horizon_on_segysak_dataset_equals_numpy(data_dir):
    """F3 opened by segysak's xarray engine (dims iline / xline / samples, its cdp_x / cdp_y), tracked from a seed in
    its own coordinates, equals the tracker on the numpy cube with the seed in index space."""
    pytest.importorskip("segysak")
    from seismo3d.data import fetch
    from seismo3d.seismic import track_horizon

    path = fetch("seismic/f3_crop.sgy")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xr.open_dataset(path, dim_byte_fields={"iline": 189, "xline": 193},
                             extra_byte_fields={"cdp_x": 181, "cdp_y": 185}).load()
    da = ds.set_coords(["cdp_x", "cdp_y"])["data"]  # segysak keeps them as variables of the Dataset
    axes = seismic_axes(da)
    assert axes.lateral == ("iline", "xline") and axes.sample == "samples" and axes.sample_unit == "ms"
    k = 30
    seed = (120, 880, float(da["samples"][k]))
    labelled = track_horizon_xr(da, [seed], polarity="peak")
    ref = track_horizon(np.asarray(da.values, dtype=np.float32), [(9.0, 5.0, float(k))], polarity="peak")
    assert_allclose(labelled["sample_index"].values, ref.times, equal_nan=True)
    samples = da["samples"].values.astype(float)
    expected = np.interp(np.nan_to_num(ref.times), np.arange(samples.size), samples)
    assert_allclose(labelled["time_or_depth"].values, np.where(np.isfinite(ref.times), expected, np.nan),
                    equal_nan=True)
    assert labelled["time_or_depth"].dims == ("iline", "xline")
    assert_array_equal(labelled["cdp_x"].values, ds["cdp_x"].values)  # segysak's coordinates carried through
    with pytest.raises(InputError, match="not a iline"):
        track_horizon_xr(da, [(99, 880, 100.0)])


def test_open_segy_and_convert_zarr(data_dir, tmp_path):
    """open_seismic_dataarray of F3's SEG-Y and of its `seismo3d convert` Zarr store: the same labelled cube."""
    from seismo3d.data import fetch
    from seismo3d.jobs.convert import run_convert_job

    path = fetch("seismic/f3_crop.sgy")
    da = open_seismic_dataarray(path)
    assert da.dims == ("inline", "crossline", "sample") and da.shape == (23, 18, 75)
    assert da.attrs["xy_unit"] == "m" and da["sample"].attrs["units"] == "ms"
    assert float(da["cdp_x"][0, 0]) == pytest.approx(620197.2)
    run_convert_job(path, tmp_path / "f3.zarr", progress=False)
    dz = open_seismic_dataarray(tmp_path / "f3.zarr")
    assert dz.dims == da.dims
    assert_array_equal(dz.values, da.values)
    assert_allclose(dz["cdp_x"].values, da["cdp_x"].values)
    assert_array_equal(dz["inline"].values, da["inline"].values)


def test_dimensions_are_checked():
    da = xr.DataArray(np.zeros((4, 5)), dims=("sample", "trace"))
    with pytest.raises(InputError, match="sample last"):
        seismic_axes(da)
    with pytest.raises(InputError, match="DataArray"):
        seismic_axes(np.zeros((4, 5)))
