import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.errors import InputError
from seismo3d.geometry import backproject_depth, estimate_normals, normals_from_points_image, voxel_downsample


def _sphere(n, rng):
    p = rng.normal(size=(n, 3))
    return p / np.linalg.norm(p, axis=1, keepdims=True)


@pytest.mark.parametrize("radius", [None, 0.2])
def test_sphere_normals_mst_oriented(radius, rng):
    p = _sphere(3000, rng)
    n = estimate_normals(p, k=12, radius=radius, orient="mst")
    dots = np.einsum("ij,ij->i", n, p)
    assert np.all(np.abs(dots) > 0.98)  # radial
    assert np.all(dots > 0)  # consistently outward (the topmost point's normal points up)


def test_viewpoint_orientation(rng):
    xy = rng.uniform(-1, 1, size=(500, 2))
    p = np.c_[xy, 0.1 * xy[:, 0] ** 2]
    n = estimate_normals(p, orient="viewpoint", viewpoint=[0, 0, 5])
    assert np.all(n[:, 2] > 0.9)
    n = estimate_normals(p, orient="viewpoint", viewpoint=[0, 0, -5])
    assert np.all(n[:, 2] < -0.9)


def test_2d_circle_normals(rng):
    t = rng.uniform(0, 2 * np.pi, 400)
    p = np.c_[np.cos(t), np.sin(t)]
    n = estimate_normals(p, k=8)
    assert np.all(np.abs(np.einsum("ij,ij->i", n, p)) > 0.99)


def test_depth_normals_of_a_tilted_plane():
    h, w, f = 60, 80, 100.0
    v, u = np.indices((h, w), dtype=float)
    # plane z = 2 + 0.5 x  (x = (u - cx) z / f)  ->  z = 2 / (1 - 0.5 (u - cx) / f)
    z = 2.0 / (1 - 0.5 * (u - 40) / f)
    pts = backproject_depth(z, (f, f, 40.0, 30.0))
    assert_allclose(pts[..., 2], z)
    n = normals_from_points_image(pts)
    expected = np.array([0.5, 0.0, -1.0]) / np.sqrt(1.25)  # facing the camera
    inner = n[2:-2, 2:-2].reshape(-1, 3)
    assert_allclose(inner, np.broadcast_to(expected, inner.shape), atol=1e-9)
    assert np.isnan(n[0]).all() and np.isnan(n[:, -1]).all()


def test_invalid_depth_is_nan():
    z = np.ones((4, 5))
    z[1, 1] = 0
    z[2, 2] = np.nan
    pts = backproject_depth(z, np.array([[10, 0, 2], [0, 10, 2], [0, 0, 1.0]]))
    assert np.isnan(pts[1, 1]).all() and np.isnan(pts[2, 2]).all() and np.isfinite(pts[0, 0]).all()


def test_voxel_downsample_means(rng):
    p = np.array([[0.1, 0.1, 0.1], [0.2, 0.2, 0.2], [1.5, 0.1, 0.1]])
    out, vals = voxel_downsample(p, 1.0, values=[[1.0], [3.0], [5.0]])
    assert_allclose(out, [[0.15, 0.15, 0.15], [1.5, 0.1, 0.1]])
    assert_allclose(vals, [[2.0], [5.0]])


def test_normals_bad_input():
    with pytest.raises(InputError):
        estimate_normals(np.zeros((2, 3)))
    with pytest.raises(InputError):
        estimate_normals(np.zeros((10, 4)))
    with pytest.raises(InputError, match="viewpoint"):
        estimate_normals(np.random.default_rng(0).normal(size=(10, 3)), orient="viewpoint")
