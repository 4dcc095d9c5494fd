"""Window sources of seismo3d.seismic.faults.windows: a lazy cube's windows hold the requested traces plus the halo,
clipped at the cube's edges, with the whole cube's amplitudes and slopes over the requested traces."""

import dask.array as da
import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import structure_tensor_orientation
from seismo3d.seismic.attributes import structure_tensor_halo, structure_tensor_slopes
from seismo3d.seismic.faults.windows import ArrayWindows, LazyWindows, cube_windows


@pytest.fixture(scope="module")
def cube():
    return synthetic_cube((48, 40, 32), n_faults=1, seed=2).cube


@pytest.mark.slow
@pytest.mark.parametrize("cache_mb", [0.01, 256.0], ids=["one-tile-cache", "cache"])
@pytest.mark.parametrize("box", [(20, 26, 14, 18), (0, 5, 30, 40), (40, 48, 0, 3), (10, 40, 5, 38)],
                         ids=["inside", "corner", "edge", "tiles"])
def test_lazy_window_equals_whole_cube(cube, box, cache_mb):
    whole = structure_tensor_slopes(cube, float32=True)  # the fault windows' slopes (the tensor in float32)
    source = LazyWindows(da.from_array(cube, chunks=(7, 40, 32)), tile=16, cache_mb=cache_mb)
    assert source.shape == cube.shape and source.halo == structure_tensor_halo()[0]
    i0, i1, j0, j1 = box
    for _ in range(2):  # the second time from the cache (or recomputed after eviction)
        win = source.window(*box)
        a0, b0 = win.origin
        assert (a0, b0) == (i0 // 16 * 16, j0 // 16 * 16)  # tile corners
        assert win.amplitude.shape == (min(-(-i1 // 16) * 16, 48) - a0, min(-(-j1 // 16) * 16, 40) - b0, 32)
        assert win.cube_shape == cube.shape
        sel = (slice(a0, a0 + win.amplitude.shape[0]), slice(b0, b0 + win.amplitude.shape[1]))
        np.testing.assert_array_equal(win.amplitude, cube[sel])
        np.testing.assert_array_equal(win.slope_inline, whole[0][sel])
        np.testing.assert_array_equal(win.slope_xline, whole[1][sel])
    # reads in cube coordinates within the box; beyond the cube's edges clamped as on the whole cube
    il_lo, il_hi = (-0.7 if i0 == 0 else i0), (47.6 if i1 == 48 else i1 - 1.0)
    xl_lo, xl_hi = (-0.4 if j0 == 0 else j0), (39.9 if j1 == 40 else j1 - 1.0)
    il = np.array([il_lo, il_hi, i0 + 0.3, il_hi])
    xl = np.array([xl_lo + 0.5, xl_hi, xl_lo, xl_hi])
    t = np.array([3.2, 31.5, 0.0, 12.0])
    ref = ArrayWindows(cube).window(*box)
    assert ref.origin == (0, 0) and ref.amplitude.shape == cube.shape
    np.testing.assert_array_equal(win.amplitude_at(il, xl, t), ref.amplitude_at(il, xl, t))
    np.testing.assert_array_equal(win.slope_along(il, xl, t, (0.6, 0.8)), ref.slope_along(il, xl, t, (0.6, 0.8)))


def test_sources_and_errors(cube):
    assert isinstance(cube_windows(cube), ArrayWindows)
    assert isinstance(cube_windows(da.from_array(cube)), LazyWindows)
    section = cube_windows(da.from_array(cube[:, 0]))  # a 2D dask section is read whole
    assert isinstance(section, ArrayWindows) and section.shape == (48, 32)
    assert section.window(0, 1, 0, 1).amplitude.shape == (48, 1, 32)
    with pytest.raises(InputError, match="numeric"):
        cube_windows(da.from_array(np.full((8, 8, 8), "a")))
    with pytest.raises(InputError, match="orientation.slopes has shape"):
        cube_windows(da.from_array(cube), structure_tensor_orientation(cube[:, :, :16]))
    with pytest.raises(InputError, match="tile"):
        LazyWindows(da.from_array(cube), tile=0)
    source = LazyWindows(da.from_array(cube), tile=16)
    assert cube_windows(source) is source  # a source made by the caller is used as it is
    with pytest.raises(InputError, match="pass it to the source"):
        cube_windows(source, structure_tensor_orientation(cube))
