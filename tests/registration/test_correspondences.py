"""Correspondence strategies of the ICP engine: the KD-tree default is today's behaviour; projective association."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from seismo3d.errors import InputError
from seismo3d.geometry import rotation_error_deg, translation_error
from seismo3d.registration import ICPOptions, fused_icp, icp
from seismo3d.registration.correspondences import NearestNeighbourCorrespondences, ProjectiveCorrespondences

K = (200.0, 200.0, 79.5, 59.5)  # 160 x 120 pixels


def _organised_surface():
    """A wavy surface seen by a pinhole camera: points image (120, 160, 3), its normals, and the valid mask."""
    fx, fy, cx, cy = K
    v, u = np.indices((120, 160), dtype=np.float64)
    x0, y0 = (u - cx) / fx, (v - cy) / fy
    # depth of the surface z = 2 + 0.15 sin(3x) cos(2y) along each ray, by fixed-point iteration
    z = np.full_like(u, 2.0)
    for _ in range(30):
        z = 2.0 + 0.15 * np.sin(3 * x0 * z) * np.cos(2 * y0 * z)
    pts = np.stack([x0 * z, y0 * z, z], axis=-1)
    from seismo3d.geometry import normals_from_points_image

    nrm = normals_from_points_image(pts)
    valid = np.isfinite(nrm).all(axis=-1)
    return pts, nrm, valid


def _motion(angle_deg=2.0, shift=(0.02, -0.01, 0.03)):
    m = np.eye(4)
    m[:3, :3] = Rotation.from_rotvec(np.radians(angle_deg) * np.array([0.3, 1.0, 0.2]) / np.linalg.norm(
        [0.3, 1.0, 0.2])).as_matrix()
    m[:3, 3] = shift
    return m


def test_default_strategy_is_the_kd_tree(rng):
    pts = rng.normal(size=(800, 3))
    truth = _motion()
    src = (pts - truth[:3, 3]) @ truth[:3, :3]  # inverse motion: icp should find `truth`
    a = icp(src, pts, method="point_to_point", max_distance=(1.0, 0.3, 0.1))
    b = icp(src, pts, method="point_to_point", max_distance=(1.0, 0.3, 0.1),
            correspondences=NearestNeighbourCorrespondences())
    c = icp(src, pts, method="point_to_point", options=ICPOptions(max_distance=(1.0, 0.3, 0.1), correspondences=None))
    np.testing.assert_array_equal(a.transform, b.transform)
    np.testing.assert_array_equal(a.transform, c.transform)
    assert ICPOptions().correspondences == NearestNeighbourCorrespondences()
    assert rotation_error_deg(a.transform, truth) < 1e-6


def test_projective_icp_recovers_a_camera_motion():
    pts, nrm, valid = _organised_surface()
    truth = _motion()
    tgt, tn = pts[valid], nrm[valid]
    # the source: the target surface seen from the moved camera (points in that camera's frame)
    src = (tgt - truth[:3, 3]) @ truth[:3, :3]
    strategy = ProjectiveCorrespondences.from_mask(K, valid)
    result = icp(src, tgt, target_normals=tn, max_distance=(0.1, 0.03, 0.01), correspondences=strategy)
    assert rotation_error_deg(result.transform, truth) < 0.05 and translation_error(result.transform, truth) < 1e-3
    assert result.fitness > 0.9
    # the same strategy as a field of ICPOptions: the same result
    same = icp(src, tgt, target_normals=tn, options=ICPOptions(max_distance=(0.1, 0.03, 0.01),
                                                               correspondences=strategy))
    np.testing.assert_array_equal(same.transform, result.transform)


@pytest.mark.filterwarnings("ignore::seismo3d.errors.DegenerateGeometryWarning")
def test_projective_fused_icp_takes_features():
    pts, nrm, valid = _organised_surface()
    truth = _motion(20.0, (0.1, 0.05, -0.05))  # too far for dense ICP alone: the RANSAC start reaches it
    tgt, tn = pts[valid], nrm[valid]
    src = (tgt - truth[:3, 3]) @ truth[:3, :3]
    pick = np.arange(0, len(tgt), 97)
    strategy = ProjectiveCorrespondences.from_mask(K, valid)
    result = fused_icp(src, tgt, target_normals=tn, source_features=src[pick], target_features=tgt[pick],
                       max_distance=(0.1, 0.03, 0.01), correspondences=strategy)
    assert result.info["start"] == "ransac"
    assert rotation_error_deg(result.transform, truth) < 0.05 and translation_error(result.transform, truth) < 1e-3


def test_query_semantics():
    pts, nrm, valid = _organised_surface()
    tgt = pts[valid]
    index = ProjectiveCorrespondences.from_mask(K, valid).index(tgt)
    behind = np.array([[0.0, 0.0, -1.0]])
    outside = np.array([[50.0, 0.0, 1.0]])
    on = tgt[:1] + [0.0, 0.0, 0.001]
    dist, idx = index.query(np.vstack([behind, outside, on]), 0.01)
    assert np.isinf(dist[:2]).all() and (idx[:2] == len(tgt)).all()
    assert dist[2] == pytest.approx(0.001, abs=1e-9) and idx[2] == 0


def test_projective_refuses_a_downsampled_target():
    pts, nrm, valid = _organised_surface()
    strategy = ProjectiveCorrespondences.from_mask(K, valid)
    with pytest.raises(InputError, match="organised"):
        icp(pts[valid][::2], pts[valid], target_normals=nrm[valid], voxel_size=0.05, correspondences=strategy)
    with pytest.raises(InputError, match="pixel_index"):
        ProjectiveCorrespondences(K, np.zeros((3, 3)))
    with pytest.raises(InputError, match="correspondences"):
        icp(pts[valid], pts[valid], target_normals=nrm[valid], correspondences="projective")
    with pytest.raises(InputError, match="correspondences"):
        ICPOptions(correspondences="projective")


def test_compiled_plane_system_equals_numpy(rng):
    """The rigid 3D point-to-plane normal equations of the compiled pass equal the numpy accumulation."""
    from seismo3d.geometry import make_transform, rotation_about_axis
    from seismo3d.registration import _solver
    from seismo3d.registration.kernels import robust_weights

    n, m = 500, 400
    src, dst = rng.normal(size=(n, 3)), rng.normal(size=(m, 3))
    nrm = rng.normal(size=(m, 3))
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    idx = rng.integers(0, m + 1, size=n)  # m: no correspondence
    tf = make_transform(rotation_about_axis([0.1, -0.2, 0.3], 20.0), [0.5, 0.0, -1.0])
    moved = _solver.moved_points(src, tf)
    np.testing.assert_allclose(moved, src @ tf[:3, :3].T + tf[:3, 3], rtol=1e-13, atol=1e-13)
    ok = idx < m
    for kernel in ("none", "huber", "tukey", "cauchy"):
        h, g, count = _solver.plane_system_rigid3(moved, tf[:3, 3], dst, nrm, idx, kernel, 0.7, 0.25)
        p, q, nn = src[ok], dst[idx[ok]], nrm[idx[ok]]
        w = robust_weights(np.einsum("ij,ij->i", nn, moved[ok] - q), kernel, 0.7)
        h_ref, g_ref = _solver.normal_matrix([(p, nn, q, w, 0.25)], "rigid", tf)
        assert count == ok.sum()
        np.testing.assert_allclose(h, h_ref, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(g, g_ref, rtol=1e-10, atol=1e-12)


def test_compiled_plane_system_and_query_do_not_depend_on_the_threads(rng):
    """The correspondences and the normal equations are computed in parallel over a fixed split of the points (64
    chunks, summed in chunk order): one thread and every thread give the same bits."""
    import numba

    from seismo3d.geometry.voxel_hash import VoxelHashIndex
    from seismo3d.registration import _solver

    src, dst = rng.normal(size=(20000, 3)), rng.normal(size=(15000, 3))
    nrm = rng.normal(size=(15000, 3))
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    index = VoxelHashIndex(dst, 0.3)
    runs = []
    for threads in (1, numba.config.NUMBA_NUM_THREADS):
        before = numba.get_num_threads()
        numba.set_num_threads(threads)
        try:
            dist, idx = index.query(src, 0.3)
            h, g, count = _solver.plane_system_rigid3(src, np.zeros(3), dst, nrm, idx, "huber", 0.1, 1.0)
        finally:
            numba.set_num_threads(before)
        runs.append((dist, idx, h, g, count))
    assert 0 < runs[0][4] < len(src)
    for a, b in zip(*runs):
        np.testing.assert_array_equal(a, b)
