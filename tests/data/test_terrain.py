"""seismo3d.data.terrain: generated scarps, scan pairs and moved grids match their stated truth."""

import numpy as np
import pytest

from scipy import ndimage

from seismo3d.data.terrain import cut_scan_pair, moved_grid, synthetic_occupancy, synthetic_scarp_dem
from seismo3d.errors import InputError


def test_scarp_dem_reproducible_and_scarps_where_stated():
    a = synthetic_scarp_dem((128, 128), n_scarps=3, seed=4)
    b = synthetic_scarp_dem((128, 128), n_scarps=3, seed=4)
    np.testing.assert_array_equal(a.elevation, b.elevation)
    assert len(a.scarps) == 3
    for s in a.scarps:
        assert 0 <= s.azimuth_deg < 180
        # the strike's azimuth matches the trace's direction (north = -row, east = +col)
        az = np.degrees(np.arctan2(s.col1 - s.col0, -(s.row1 - s.row0))) % 180
        assert az == pytest.approx(s.azimuth_deg, abs=1e-6)
    # the height steps across the middle of a scarp by about its height
    s = a.scarps[0]
    mid = np.array([(s.row0 + s.row1) / 2, (s.col0 + s.col1) / 2])
    u = np.array([s.row1 - s.row0, s.col1 - s.col0]) / s.length_px
    right = np.array([u[1], -u[0]])  # (row, col) of the raised side
    hi = a.elevation[tuple(np.round(mid + 3 * right).astype(int))]
    lo = a.elevation[tuple(np.round(mid - 3 * right).astype(int))]
    assert hi - lo > 0.5 * s.height
    with pytest.raises(InputError):
        synthetic_scarp_dem((32, 32))


def test_cut_scan_pair_truth():
    rng = np.random.default_rng(0)
    pts = np.column_stack([rng.uniform(0, 100, 2000), rng.uniform(0, 50, 2000), rng.uniform(0, 5, 2000)])
    pair = cut_scan_pair(pts, angle_deg=15, translation=(3, 4, 0), noise=0.0, overlap=0.3, seed=1)
    back = pair.source @ pair.transform[:3, :3].T + pair.transform[:3, 3]
    part = pts[pts[:, 0] > 35.0]
    np.testing.assert_allclose(np.sort(back[:, 0]), np.sort(part[:, 0]), atol=1e-9)
    assert pair.target[:, 0].max() < 65.0 + 1e-9
    np.testing.assert_allclose(pair.transform @ pair.motion, np.eye(4), atol=1e-12)


def test_moved_grid_truth_on_a_plane():
    rows, cols = np.mgrid[0:80, 0:90].astype(float)
    dy, dx = 2.0, 3.0
    z = 0.1 * cols * dx - 0.05 * (-rows * dy)  # z = 0.1 x - 0.05 y
    mg = moved_grid(z, (dy, dx), crop=(slice(20, 60), slice(25, 65)), angle_deg=30.0, shift=(4.0, -2.0), order=1)
    # a moved cell q shows the original terrain at T q (T: the truth, metres about the crop centre)
    r, c = 10, 12
    qx, qy = (c - 19.5) * dx, -(r - 19.5) * dy
    p = mg.transform @ [qx, qy, 0.0, 1.0]
    orig_c, orig_r = 25 + 19.5 + p[0] / dx, 20 + 19.5 - p[1] / dy
    expected = 0.1 * orig_c * dx - 0.05 * (-orig_r * dy)
    assert mg.elevation[r, c] == pytest.approx(expected, abs=1e-9)


def test_synthetic_occupancy_fraction_and_query():
    t = synthetic_occupancy((120, 100), spacing=(30.0, 25.0), free_fraction=0.7, seed=3)
    np.testing.assert_array_equal(t.free, synthetic_occupancy((120, 100), free_fraction=0.7, seed=3).free)
    assert t.free.shape == (120, 100) and t.spacing == (30.0, 25.0)
    assert t.free.mean() == pytest.approx(0.7, abs=0.005)
    labels, n = ndimage.label(t.free, structure=np.ones((3, 3), bool))
    sizes = np.bincount(labels.ravel())[1:]
    assert labels[t.start] == labels[t.goal] == 1 + np.argmax(sizes)  # both in the largest free region
    region = np.argwhere(labels == labels[t.start])
    assert sum(t.start) == region.sum(axis=1).min()  # the region's cell nearest the top-left corner
    assert (119 - t.goal[0]) + (99 - t.goal[1]) == ((119 - region[:, 0]) + (99 - region[:, 1])).min()
    with pytest.raises(InputError, match="free_fraction"):
        synthetic_occupancy(free_fraction=1.0)
    with pytest.raises(InputError, match="shape"):
        synthetic_occupancy((8, 100))
