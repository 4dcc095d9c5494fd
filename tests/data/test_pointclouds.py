"""Tests of seismo3d.data.pointclouds: format round trips, hand-made PLY variants, clear errors, bunny ground truth."""

from __future__ import annotations

import os

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from scipy.spatial import cKDTree

from seismo3d.data import load_bunny, read_points, write_points
from seismo3d.errors import DataIntegrityError, InputError

FORMATS = (".ply", ".xyz", ".txt", ".csv", ".npy")


@pytest.fixture(scope="module")
def bunny():
    if not os.environ.get("SEISMO3D_DATA_DIR"):
        pytest.skip("SEISMO3D_DATA_DIR is not set")
    return load_bunny()


def _points(n: int, d: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    # values that need all 17 significant digits, plus large and tiny magnitudes
    return rng.normal(size=(n, d)) * np.array([1e-3, 1.0, 4.5e5][:d]) + np.array([0.1, -7.0, 6.1e6][:d])


@pytest.mark.parametrize("suffix", FORMATS)
@pytest.mark.parametrize("d", [2, 3])
def test_round_trip_is_exact(tmp_path, suffix, d):
    points = _points(257, d)
    path = write_points(tmp_path / f"cloud{suffix}", points)
    back = read_points(path)
    assert back.dtype == np.float64 and back.shape == (257, d)
    assert_array_equal(back, points)
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"cloud{suffix}"]  # no temporary file left


@pytest.mark.parametrize("suffix", FORMATS)
def test_round_trip_empty_and_single(tmp_path, suffix):
    for points in (np.empty((0, 3)), np.array([[1.5, -2.0, 3.25]])):
        path = write_points(tmp_path / f"cloud{suffix}", points)
        if suffix in (".xyz", ".txt", ".csv") and len(points) == 0:
            with pytest.raises(DataIntegrityError, match="no numeric rows"):
                read_points(path)
        else:
            assert_array_equal(read_points(path, ndim=3), points)


def test_write_overwrites_atomically_and_keeps_file_on_error(tmp_path):
    path = tmp_path / "cloud.ply"
    write_points(path, _points(10, 3))
    write_points(path, _points(20, 3, seed=1))
    assert_array_equal(read_points(path), _points(20, 3, seed=1))
    bad = _points(5, 3)
    bad[2, 1] = np.nan
    with pytest.raises(InputError, match="NaN"):
        write_points(path, bad)
    assert_array_equal(read_points(path), _points(20, 3, seed=1))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cloud.ply"]


def test_ply_keeps_double_coordinates(tmp_path):
    # UTM coordinates at centimetre precision: float32 would be off by up to 0.25 m at these northings
    points = np.array([[500000.123456, 5000000.654321, 12.3456789], [500001.5, 5000001.25, -3.0]])
    assert_array_equal(read_points(write_points(tmp_path / "utm.ply", points)), points)


def test_written_ply_is_read_by_open3d(tmp_path):
    o3d = pytest.importorskip("open3d")
    points = _points(100, 3)
    path = write_points(tmp_path / "cloud.ply", points)
    cloud = o3d.io.read_point_cloud(str(path))
    assert_array_equal(np.asarray(cloud.points), points)


def _write_binary_ply(path, order: str):
    """A PLY with a fixed-size element before the vertices, float32 xyz + uchar colour, and faces after."""
    vertex = np.dtype([("x", order + "f4"), ("y", order + "f4"), ("z", order + "f4"),
                       ("red", "u1"), ("green", "u1"), ("blue", "u1")])
    data = np.zeros(4, dtype=vertex)
    data["x"], data["y"], data["z"] = [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.5]
    data["red"] = 255
    camera = np.array([(1.0, 2.0)], dtype=[("fx", order + "f8"), ("fy", order + "f8")])
    fmt = "binary_little_endian" if order == "<" else "binary_big_endian"
    header = (f"ply\r\nformat {fmt} 1.0\r\ncomment made by hand\r\nobj_info test\r\n"
              "element camera 1\r\nproperty double fx\r\nproperty double fy\r\n"
              "element vertex 4\r\nproperty float x\r\nproperty float32 y\r\nproperty float z\r\n"
              "property uchar red\r\nproperty uchar green\r\nproperty uint8 blue\r\n"
              "element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n")
    faces = np.array([3], "u1").tobytes() + np.array([0, 1, 2], order + "i4").tobytes()
    path.write_bytes(header.encode() + camera.tobytes() + data.tobytes() + faces)
    return np.stack([data["x"], data["y"], data["z"]], axis=1).astype(np.float64)


@pytest.mark.parametrize("order", ["<", ">"])
def test_read_binary_ply_with_extra_elements_and_properties(tmp_path, order):
    expected = _write_binary_ply(tmp_path / "hand.ply", order)
    assert_array_equal(read_points(tmp_path / "hand.ply"), expected)


def test_read_ascii_ply_with_properties_and_faces(tmp_path):
    path = tmp_path / "hand.ply"
    path.write_text("ply\nformat ascii 1.0\ncomment c\nelement vertex 3\nproperty float nx\nproperty float x\n"
                    "property float y\nproperty float z\nproperty uchar red\nelement face 1\n"
                    "property list uchar int vertex_indices\nend_header\n"
                    "9 1 2 3 255\n9 4 5 6 0\n9 -7.5 8e-3 1e2 10\n3 0 1 2\n")
    # the properties are declared float: the values are float32's, as the file says (then float64)
    expected = np.array([[1, 2, 3], [4, 5, 6], [-7.5, 8e-3, 1e2]], np.float32)
    assert_array_equal(read_points(path), expected)
    assert_array_equal(read_points(path, ndim=2), expected[:, :2])


@pytest.mark.parametrize("ascii_format", [True, False])
def test_truncated_ply_raises_integrity_error(tmp_path, ascii_format):
    path = tmp_path / "cut.ply"
    if ascii_format:
        path.write_text("ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                        "property float z\nend_header\n1 2 3\n4 5 6\n")
    else:
        write_points(path, _points(100, 3))
        path.write_bytes(path.read_bytes()[:-100])
    with pytest.raises(DataIntegrityError, match="truncated"):
        read_points(path)


@pytest.mark.parametrize("content, message", [
    (b"not a ply\n", "PLY header .*expected 'ply'"),
    (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "PLY header .*end-of-file"),
    (b"ply\nformat binary_middle_endian 1.0\nend_header\n", "PLY header .*binary_middle_endian"),
    (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n1\n", "PLY header .*quad"),
    (b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nend_header\n1 2\n1 a\n",
     "malformed"),
])
def test_corrupt_ply(tmp_path, content, message):
    path = tmp_path / "bad.ply"
    path.write_bytes(content)
    with pytest.raises(DataIntegrityError, match=message):
        read_points(path)


def test_ply_without_coordinates(tmp_path):
    path = tmp_path / "mesh.ply"
    path.write_text("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n")
    with pytest.raises(InputError, match="no 'vertex' element"):
        read_points(path)
    path.write_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty float z\nend_header\n1\n")
    with pytest.raises(InputError, match="'x' and 'y'"):
        read_points(path)


def test_text_with_header_comments_and_extra_columns(tmp_path):
    path = tmp_path / "scan.xyz"
    path.write_text("// exported by a scanner\nX Y Z Intensity R G B\n# units: m\n"
                    "1.0 2.0 3.0 0.5 255 0 0\n\n4 5 6 0.25 0 255 0\n# trailing comment\n")
    assert_array_equal(read_points(path), [[1, 2, 3], [4, 5, 6]])
    assert_array_equal(read_points(path, ndim=2), [[1, 2], [4, 5]])
    csv = tmp_path / "scan.csv"
    csv.write_text("x,y,z,label\n1.5,2.5,3.5,7\n-1,-2,-3,8\n")
    assert_array_equal(read_points(csv), [[1.5, 2.5, 3.5], [-1, -2, -3]])
    two = tmp_path / "map.txt"
    two.write_text("easting\tnorthing\n10\t20\n30\t40\n")
    assert read_points(two).shape == (2, 2)
    with pytest.raises(InputError, match="ndim=3"):
        read_points(two, ndim=3)


def test_text_errors(tmp_path):
    one = tmp_path / "one.txt"
    one.write_text("1\n2\n3\n")
    with pytest.raises(InputError, match="2 or 3 coordinate columns"):
        read_points(one)
    ragged = tmp_path / "ragged.xyz"
    ragged.write_text("1 2 3\n4 5\n")
    with pytest.raises(DataIntegrityError, match="malformed row"):
        read_points(ragged)
    words = tmp_path / "words.xyz"
    words.write_text("1 2 3\n4 five 6\n")
    with pytest.raises(DataIntegrityError):
        read_points(words)


def test_npy_errors(tmp_path):
    np.save(tmp_path / "cube.npy", np.zeros((2, 3, 4)))
    with pytest.raises(InputError, match=r"\(2, 3, 4\)"):
        read_points(tmp_path / "cube.npy")
    write_points(tmp_path / "cut.npy", _points(100, 3))
    (tmp_path / "cut.npy").write_bytes((tmp_path / "cut.npy").read_bytes()[:500])
    with pytest.raises(DataIntegrityError, match="corrupt or truncated"):
        read_points(tmp_path / "cut.npy")
    np.save(tmp_path / "objects.npy", np.array([[object()] * 3], dtype=object), allow_pickle=True)
    with pytest.raises(DataIntegrityError, match="pickle"):
        read_points(tmp_path / "objects.npy")


def test_unsupported_extension_and_missing_file(tmp_path):
    with pytest.raises(InputError, match="unsupported point-cloud extension '.las'"):
        read_points(tmp_path / "cloud.las")
    with pytest.raises(InputError, match="unsupported"):
        write_points(tmp_path / "cloud.pcd", _points(3, 3))
    with pytest.raises(FileNotFoundError):  # DataNotFoundError is one
        read_points(tmp_path / "missing.ply")
    with pytest.raises(InputError, match="ndim"):
        read_points(tmp_path / "missing.ply", ndim=4)
    with pytest.raises(InputError, match=r"\(N, 2\) or \(N, 3\)"):
        write_points(tmp_path / "cloud.ply", np.zeros((3, 4)))


@pytest.mark.slow
def test_bunny_shapes_and_transform(bunny):
    assert bunny.source.shape == (40097, 3) and bunny.target.shape == (40256, 3)
    assert bunny.source.dtype == bunny.target.dtype == bunny.transform.dtype == np.float64
    # metres: the bunny is about 15 cm across
    extent = np.ptp(bunny.target, axis=0)
    assert np.all(extent > 0.05) and np.all(extent < 0.25)
    rotation = bunny.transform[:3, :3]
    assert_allclose(rotation @ rotation.T, np.eye(3), atol=1e-6)
    assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-6)
    assert_array_equal(bunny.transform[3], [0, 0, 0, 1])
    angle = np.degrees(np.arccos((np.trace(rotation) - 1) / 2))
    assert 25.0 < angle < 50.0  # "bun045" is a nominal 45 degree turn; bun.conf registers 34.3 degrees
    assert not bunny.source.flags.writeable


@pytest.mark.slow
def test_bunny_ground_truth_by_nearest_neighbour_residuals(bunny):
    tree = cKDTree(bunny.target)

    def residuals(transform):
        moved = bunny.source @ transform[:3, :3].T + transform[:3, 3]
        return tree.query(moved)[0]

    aligned = residuals(bunny.transform)
    overlap = aligned < 2e-3  # points of bun045 that bun000 also saw
    assert overlap.mean() > 0.8  # measured 0.94
    assert np.median(aligned[overlap]) < 0.5e-3  # measured 0.33 mm
    assert np.median(aligned) < 0.5e-3
    # the test can fail: no transform, or the other quaternion convention, leaves centimetre residuals
    assert np.median(residuals(np.eye(4))) > 5e-3
    wrong = bunny.transform.copy()
    wrong[:3, :3] = wrong[:3, :3].T
    assert np.median(residuals(wrong)) > 5e-3
