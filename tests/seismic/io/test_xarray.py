"""track_horizon on labelled DataArrays (segysak's) gives the results of the numpy values, with the coordinates carried
through; the dimensions of a seismic DataArray are checked."""

import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from seismo3d.errors import InputError

xr = pytest.importorskip("xarray")

from seismo3d.seismic.io.xarray import seismic_axes, track_horizon_xr  # noqa: E402


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


def test_dimensions_are_checked():
    da = xr.DataArray(np.zeros((4, 5)), dims=("sample", "trace"))
    with pytest.raises(InputError, match="sample last"):
        seismic_axes(da)
    with pytest.raises(InputError, match="DataArray"):
        seismic_axes(np.zeros((4, 5)))
