"""The dimensions of a seismic DataArray are checked (seismo3d.seismic.io.cube.seismic_axes); the horizon tracker on
labelled cubes is tested in tests/seismic/test_horizon_labelled.py."""

import numpy as np
import pytest

from seismo3d.errors import InputError

xr = pytest.importorskip("xarray")

from seismo3d.seismic.io.cube import seismic_axes  # noqa: E402


def test_dimensions_are_checked():
    da = xr.DataArray(np.zeros((4, 5)), dims=("sample", "trace"))
    with pytest.raises(InputError, match="sample last"):
        seismic_axes(da)
    with pytest.raises(InputError, match="DataArray"):
        seismic_axes(np.zeros((4, 5)))
