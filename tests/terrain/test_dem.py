"""seismo3d.terrain.dem: GeoTIFF DEMs, nodata, georeferencing, metric pixel sizes."""

import numpy as np
import pytest
import tifffile

from seismo3d.errors import InputError
from seismo3d.terrain import Dem, read_dem, write_dem
from seismo3d.terrain.georef import CoordinateReference, metres_per_degree


def test_dfw(dfw):
    assert dfw.shape == (359, 367) and dfw.crs.is_geographic and dfw.crs.epsg == 4326
    assert dfw.nodata == -32768 and dfw.valid.all()
    assert np.nanmin(dfw.elevation) == 147 and np.nanmax(dfw.elevation) == 298
    # tie point = corner of pixel (0, 0) (PixelIsArea): its centre is half a pixel in
    x, y = dfw.xy(0, 0)
    assert x == pytest.approx(-97.485 + 0.0008333333 / 2) and y == pytest.approx(32.8216667 - 0.0008333333 / 2)
    dy, dx = dfw.pixel_size_m
    m_lat, m_lon = metres_per_degree(dfw.centre_xy[1])
    assert dy == pytest.approx(3 / 3600 * m_lat) and dx == pytest.approx(3 / 3600 * m_lon)
    assert dy == pytest.approx(92.4, abs=0.1) and dx == pytest.approx(78.2, abs=0.1)
    r, c = dfw.rowcol(*dfw.xy(10.25, 20.5))
    assert (r, c) == pytest.approx((10.25, 20.5))


def test_write_read_round_trip(dfw, tmp_path):
    crop = dfw.crop(slice(10, 50), slice(20, 70))
    elevation = crop.elevation.copy()
    elevation[3, 4] = np.nan
    crop = Dem(elevation, crop.affine, crop.crs)
    back = read_dem(write_dem(tmp_path / "crop.tif", crop))
    np.testing.assert_array_equal(np.isnan(back.elevation), np.isnan(elevation))
    np.testing.assert_allclose(back.elevation, elevation)
    np.testing.assert_allclose(back.affine, dfw.affine @ [[1, 0, 20], [0, 1, 10], [0, 0, 1]])
    assert back.crs.epsg == 4326


def test_projected_pixel_is_point_and_rotated(tmp_path):
    feet = CoordinateReference("projected", None, "test", "foot", 0.3048, "foot", 0.3048)
    z = np.arange(30.0).reshape(5, 6)
    path = tmp_path / "pt.tif"
    # PixelIsPoint: the tie point is pixel (0, 0)'s centre
    tifffile.imwrite(path, z.astype(np.float32), extratags=[
        (33550, "d", 3, (3.0, 3.0, 0.0), True), (33922, "d", 6, (0, 0, 0, 1000.0, 2000.0, 0), True),
        (34735, "H", 12, (1, 1, 0, 2, 1024, 0, 1, 1, 1025, 0, 1, 2), True)])
    dem = read_dem(path)
    assert dem.xy(0, 0) == pytest.approx((1000.0, 2000.0)) and dem.nodata is None
    assert dem.pixel_size_m == pytest.approx((3.0, 3.0))  # unknown linear unit: metres
    rotated = Dem(z, np.array([[0.0, 2.0, 10.0], [-2.0, 0.0, 20.0], [0, 0, 1]]), feet)
    back = read_dem(write_dem(tmp_path / "rot.tif", rotated))
    np.testing.assert_allclose(back.affine, rotated.affine)
    assert back.pixel_size_m == pytest.approx((0.6096, 0.6096))


def test_bad_dems(tmp_path):
    path = tmp_path / "nodata.tif"
    tifffile.imwrite(path, np.full((8, 8), -9999, np.int16), extratags=[
        (33550, "d", 3, (1.0, 1.0, 0.0), True), (33922, "d", 6, (0, 0, 0, 0.0, 0.0, 0), True),
        (42113, "s", 0, "-9999", True)])
    with pytest.raises(InputError, match="only nodata"):
        read_dem(path)
    plain = tmp_path / "plain.tif"
    tifffile.imwrite(plain, np.zeros((8, 8), np.float32))
    with pytest.raises(InputError, match="no georeferencing"):
        read_dem(plain)
