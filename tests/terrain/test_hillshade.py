"""seismo3d.terrain.hillshade: exact on planes, azimuth conventions, multidirectional weights."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.terrain import aspect_deg, hillshade, hillshades, multidirectional_hillshade, slope_deg, terrain_gradient


def plane(shape=(20, 30), *, east=0.0, north=0.0, spacing=(2.0, 3.0)):
    """Heights of z = east * x + north * y on a north-up grid (rows run south)."""
    rows, cols = np.mgrid[0:shape[0], 0:shape[1]].astype(float)
    return east * cols * spacing[1] + north * (-rows * spacing[0])


def test_plane_gradient_slope_aspect():
    z = plane(east=0.1, north=-0.2)
    g = terrain_gradient(z, (2.0, 3.0))
    np.testing.assert_allclose(g.east, 0.1, atol=1e-12)
    np.testing.assert_allclose(g.north, -0.2, atol=1e-12)
    np.testing.assert_allclose(slope_deg(z, (2.0, 3.0)), np.degrees(np.arctan(np.hypot(0.1, 0.2))))
    # rising to the east and to the south: it faces (downhill) west-north-west
    np.testing.assert_allclose(aspect_deg(z, (2.0, 3.0)), np.degrees(np.arctan2(-0.1, 0.2)) % 360)


def test_hillshade_faces_the_light():
    z = plane(east=-0.5)  # falls to the east: faces east (aspect 90)
    lit = hillshade(z, (2.0, 3.0), azimuth_deg=90.0, altitude_deg=45.0)
    away = hillshade(z, (2.0, 3.0), azimuth_deg=270.0, altitude_deg=45.0)
    s = np.arctan(0.5)
    np.testing.assert_allclose(lit, np.cos(np.pi / 4) * np.cos(s) + np.sin(np.pi / 4) * np.sin(s))
    np.testing.assert_allclose(away, np.cos(np.pi / 4) * np.cos(s) - np.sin(np.pi / 4) * np.sin(s))
    np.testing.assert_allclose(hillshade(z, (2.0, 3.0), altitude_deg=90.0), np.cos(s))  # zenith: cos(slope)
    stack = hillshades(z, (2.0, 3.0), azimuths=(90.0, 270.0))
    np.testing.assert_allclose(stack, [lit, away])


def test_multidirectional_weights_follow_the_aspect():
    z = plane(east=-0.3)  # faces east: weight cos^2(90 - 270) = 1 for the 270 light, cos^2(90 - 360) = 0 for 360
    md = multidirectional_hillshade(z, (1.0, 1.0), azimuths=(270.0, 360.0))
    np.testing.assert_allclose(md, hillshade(z, (1.0, 1.0), azimuth_deg=270.0))
    flat = np.zeros((10, 10))
    np.testing.assert_allclose(multidirectional_hillshade(flat, (1.0, 1.0)), np.cos(np.radians(45.0)))


def test_rotated_axes_and_nodata():
    z = plane(east=0.2, north=0.1, spacing=(1.0, 1.0))
    # the same terrain on a raster whose columns run north and rows run east
    zt = z.T[::-1].copy()
    g = terrain_gradient(zt, [[0.0, -1.0], [-1.0, 0.0]])  # a column step goes 1 m south, a row step 1 m west
    np.testing.assert_allclose(g.east, 0.2, atol=1e-12)
    np.testing.assert_allclose(g.north, 0.1, atol=1e-12)
    z2 = z.copy()
    z2[5, 5] = np.nan
    assert np.isnan(slope_deg(z2, (1.0, 1.0))[5, 4]) and np.isfinite(slope_deg(z2, (1.0, 1.0))[0, 0])
    with pytest.raises(InputError, match="altitude_deg"):
        hillshade(z, (1.0, 1.0), altitude_deg=0.0)
    with pytest.raises(InputError, match="spacing"):
        slope_deg(z, (0.0, 1.0))
