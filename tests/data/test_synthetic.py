"""Tests of the synthetic faulted-cube generator against its own ground truth."""


import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from seismo3d.data.synthetic import FaultPlane, SyntheticCube, ricker, synthetic_cube
from seismo3d.errors import InputError


@pytest.fixture(scope="module")
def syn3():
    return synthetic_cube((64, 64, 64), n_faults=3, seed=3, noise=0.1)


@pytest.fixture(scope="module")
def syn2():
    return synthetic_cube((160, 96), n_faults=3, seed=1, noise=0.1)


def _ncc(a, b):
    a = a - a.mean(-1, keepdims=True)
    b = b - b.mean(-1, keepdims=True)
    return (a * b).sum(-1) / np.sqrt((a * a).sum(-1) * (b * b).sum(-1))


def _straddle(points, normal_lat, step, lat_shape):
    """Lateral grid points at +-step along the horizontal fault normal; mask of those inside the grid."""
    nh = normal_lat / np.linalg.norm(normal_lat)
    a = np.rint(points + step * nh).astype(int)
    b = np.rint(points - step * nh).astype(int)
    hi = np.array(lat_shape)
    ok = (a >= 0).all(1) & (a < hi).all(1) & (b >= 0).all(1) & (b < hi).all(1)
    return a, b, ok


def test_determinism_per_seed():
    a = synthetic_cube((48, 40, 56), n_faults=2, seed=7)
    b = synthetic_cube((48, 40, 56), n_faults=2, seed=7)
    c = synthetic_cube((48, 40, 56), n_faults=2, seed=8)
    assert_array_equal(a.cube, b.cube)
    assert_array_equal(a.fault_labels, b.fault_labels)
    assert_array_equal(a.fault_throw, b.fault_throw)  # NaN == NaN in assert_array_equal
    assert_array_equal(a.horizons, b.horizons)
    assert [f.strike_deg for f in a.faults] == [f.strike_deg for f in b.faults]
    assert not np.array_equal(a.cube, c.cube)


@pytest.mark.parametrize("shape", [(40, 48, 64), (128, 64)])
def test_shapes_and_dtypes(shape):
    s = synthetic_cube(shape, n_faults=2, seed=0, n_horizons=4)
    assert isinstance(s, SyntheticCube)
    assert s.shape == shape
    for name, dtype in [("cube", np.float32), ("clean", np.float32), ("fault_labels", np.int16),
                        ("fault_throw", np.float32), ("rgt", np.float32)]:
        arr = getattr(s, name)
        assert arr.shape == shape and arr.dtype == dtype, name
    assert s.horizons.dtype == np.float32 and s.horizons.shape == (4, *shape[:-1])
    assert s.horizon_polarity.shape == (4,) and set(s.horizon_polarity.tolist()) <= {-1, 1}
    assert len(s.faults) == 2 and all(isinstance(f, FaultPlane) for f in s.faults)
    assert [f.id for f in s.faults] == [1, 2]
    assert set(np.unique(s.fault_labels).tolist()) == {0, 1, 2}
    assert np.all(np.isfinite(s.cube))


def test_noise_level_and_unit_clean():
    s = synthetic_cube((48, 48, 48), n_faults=1, seed=2, noise=0.3)
    assert_allclose(s.clean.std(), 1.0, rtol=1e-4)
    assert_allclose((s.cube - s.clean).std(), 0.3, rtol=0.02)
    quiet = synthetic_cube((48, 48, 48), n_faults=1, seed=2, noise=0.0)
    assert_array_equal(quiet.cube, quiet.clean)


def test_fault_plane_conventions(syn3):
    for f in syn3.faults:
        assert_allclose(np.linalg.norm(f.normal), 1.0, atol=1e-12)
        assert 55.0 <= f.dip_deg <= 80.0 and 0.0 <= f.strike_deg < 360.0
        assert_allclose(-f.normal[2], np.cos(np.deg2rad(f.dip_deg)), atol=1e-12)  # normal points up, into the HW
        assert_allclose(f.strike_vector @ f.normal, 0.0, atol=1e-12)
        dip_dir = np.array([-np.sin(np.deg2rad(f.strike_deg)), np.cos(np.deg2rad(f.strike_deg))])
        assert_allclose(f.normal[:2], np.sin(np.deg2rad(f.dip_deg)) * dip_dir, atol=1e-12)  # right-hand rule
        assert_allclose(f.slip_vector @ f.normal, 0.0, atol=1e-12)  # dip-slip lies in the plane
        assert 3.0 <= f.throw_samples <= 8.0
        ext = np.array(syn3.shape) - 1.0
        assert np.all((f.point >= 0.25 * ext) & (f.point <= 0.75 * ext))  # middle half of the cube


@pytest.mark.parametrize("kind", ["normal", "reverse"])
def test_hanging_wall_moves_by_the_throw(kind):
    """RGT across the fault at one depth: the hanging wall holds shallower RGT for a normal fault, deeper for a
    reverse one; a flat-layered cube (max_dip tiny) makes the vertical separation equal the throw."""
    s = synthetic_cube((64, 64, 64), n_faults=1, seed=11, reverse_fraction=1.0 if kind == "reverse" else 0.0,
                       max_dip=0.01)
    (f,) = s.faults
    assert f.kind == kind
    pts = np.argwhere(s.fault_labels == 1)
    pts = pts[(pts[:, 2] > 12) & (pts[:, 2] < 52)]
    hw, fw, ok = _straddle(pts[:, :2], f.normal[:2], 4, s.shape[:2])
    z = pts[ok, 2]
    diff = s.rgt[hw[ok, 0], hw[ok, 1], z] - s.rgt[fw[ok, 0], fw[ok, 1], z]
    throw = s.fault_throw[tuple(pts[ok].T)]
    sign = -1.0 if kind == "normal" else 1.0
    assert_allclose(np.median(sign * diff / throw), 1.0, atol=0.05)


def test_labels_are_one_voxel_thick(syn3):
    labels = syn3.fault_labels
    youngest = syn3.faults[-1]  # never overwritten and never displaced
    a = int(np.argmax(np.abs(youngest.normal)))
    # analytic: on every line along axis a, the one voxel whose centre is within [-0.5, 0.5) of the plane
    others = [i for i in range(3) if i != a]
    g = np.meshgrid(*[np.arange(syn3.shape[i]) for i in others], indexing="ij")
    xa = youngest.point[a] - sum((gi - youngest.point[i]) * youngest.normal[i] for gi, i in zip(g, others)) / \
        youngest.normal[a]
    k = np.floor(xa + 0.5).astype(int)
    inside = (k >= 0) & (k < syn3.shape[a])
    counts = np.moveaxis(labels == youngest.id, a, -1).sum(-1)
    assert np.mean(counts[inside] == 1) > 0.999
    assert np.all(counts[~inside] == 0)
    for f in syn3.faults:
        # older faults are cut and offset by younger ones: each piece is one voxel thick along the axis, so labelled
        # voxels of one fault are (almost) never adjacent along it; the offset pieces may overlap in projection
        a = int(np.argmax(np.abs(f.normal)))
        m = np.moveaxis(labels == f.id, a, -1)
        adjacent = (m[..., 1:] & m[..., :-1]).sum() / m.sum()
        assert adjacent < (1e-9 if f is youngest else 0.03), f.id


def test_throw_ground_truth(syn3):
    on = syn3.fault_labels > 0
    assert np.all(np.isfinite(syn3.fault_throw[on])) and np.all(np.isnan(syn3.fault_throw[~on]))
    assert syn3.fault_throw[on].min() >= 3.0 and syn3.fault_throw[on].max() <= 8.0


def test_labels_sit_on_data_discontinuities(syn3):
    """Traces 3 voxels either side of a labelled fault correlate far worse than traces 3 voxels apart elsewhere,
    and horizons jump by about the throw across each fault."""
    from scipy.ndimage import distance_transform_edt

    c = syn3.clean
    w = np.arange(-6, 7)
    far = np.argwhere(distance_transform_edt(syn3.fault_labels == 0) > 8)
    for f in syn3.faults:
        pts = np.argwhere(syn3.fault_labels == f.id)
        pts = pts[(pts[:, 2] >= 8) & (pts[:, 2] < 56)]
        a, b, ok = _straddle(pts[:, :2], f.normal[:2], 3, c.shape[:2])
        z = pts[ok, 2][:, None] + w
        rows = np.arange(z.shape[0])[:, None]
        across = np.median(_ncc(c[a[ok, 0], a[ok, 1]][rows, z], c[b[ok, 0], b[ok, 1]][rows, z]))
        q = far[(far[:, 2] >= 8) & (far[:, 2] < 56)]
        a2, b2, ok2 = _straddle(q[:, :2], f.normal[:2], 3, c.shape[:2])
        z2 = q[ok2, 2][:, None] + w
        rows2 = np.arange(z2.shape[0])[:, None]
        elsewhere = np.median(_ncc(c[a2[ok2, 0], a2[ok2, 1]][rows2, z2], c[b2[ok2, 0], b2[ok2, 1]][rows2, z2]))
        assert elsewhere > 0.85 and across < 0.6, (f.id, across, elsewhere)

        # horizon jump across the fault, at fault voxels near each horizon
        jumps = []
        for h in syn3.horizons:
            near = np.abs(h[a[ok, 0], a[ok, 1]] - pts[ok, 2]) < 4
            jumps.append(np.abs(h[a[ok, 0], a[ok, 1]] - h[b[ok, 0], b[ok, 1]])[near])
        jumps = np.concatenate(jumps)
        jumps = jumps[np.isfinite(jumps)]
        throw = np.median(syn3.fault_throw[syn3.fault_labels == f.id])
        assert jumps.size > 20
        assert_allclose(np.median(jumps), throw, rtol=0.25)


@pytest.mark.parametrize("seed", [0, 3])
def test_horizons_sit_on_reflector_extrema(seed):
    s = synthetic_cube((64, 64, 96), n_faults=3, seed=seed)
    nz = s.shape[-1]
    assert np.all(np.diff(np.nanmean(s.horizons, axis=(1, 2))) > 5)  # shallow to deep, well apart
    w = np.arange(-3, 4)
    for h, pol in zip(s.horizons, s.horizon_polarity):
        ok = np.isfinite(h)
        assert ok.mean() > 0.8
        k = np.rint(h[ok]).astype(int)
        traces = s.clean[ok] * pol
        vals = np.take_along_axis(traces, np.clip(k[:, None] + w, 0, nz - 1), axis=1)
        peak = k + w[np.argmax(vals, axis=1)]
        assert np.mean(np.abs(peak - h[ok]) <= 1.0) > 0.98


def test_horizon_rgt_levels(syn3):
    nz = syn3.shape[-1]
    for h, level in zip(syn3.horizons, syn3.horizon_rgt):
        ok = np.flatnonzero(np.isfinite(h.ravel()))[::7]
        pos = h.ravel()[ok]
        traces = syn3.rgt.reshape(-1, nz)[ok]
        k0 = np.floor(pos).astype(int)
        frac = pos - k0
        val = traces[np.arange(ok.size), k0] * (1 - frac) + traces[np.arange(ok.size), np.minimum(k0 + 1, nz - 1)] * frac
        assert_allclose(val, level, atol=1e-3)


def test_2d_section(syn2):
    s = syn2
    assert s.cube.shape == (160, 96) and s.horizons.shape[1:] == (160,)
    for f in s.faults:
        assert f.point.shape == (2,) and f.normal.shape == (2,) and f.strike_deg in (90.0, 270.0)
        assert f.throw_gradient == 0.0
        m = s.fault_labels == f.id  # one voxel thick along axis 0 (the axis most perpendicular to the fault)
        assert (m[1:] & m[:-1]).sum() <= 0.03 * m.sum()
    young = s.fault_labels == s.faults[-1].id
    assert np.all(young.sum(axis=0) == 1)  # the youngest fault crosses every sample row once
    # horizons jump across each fault by about its throw
    for f in s.faults:
        pts = np.argwhere(s.fault_labels == f.id)
        jumps = []
        for h in s.horizons:
            for x, z in pts:
                if 3 <= x < 157 and abs(h[x] - z) < 3:
                    jumps.append(abs(h[x + 3] - h[x - 3]))
        jumps = np.asarray(jumps)
        jumps = jumps[np.isfinite(jumps)]
        if jumps.size >= 3:
            assert_allclose(np.median(jumps), f.throw_samples, rtol=0.3)


def test_no_faults_gives_flat_labels():
    s = synthetic_cube((32, 32, 48), n_faults=0, seed=0)
    assert s.faults == () and not s.fault_labels.any() and np.all(np.isnan(s.fault_throw))
    assert np.isfinite(s.horizons).all()


@pytest.mark.parametrize("shape", [(128,), (8, 64, 64), (4, 64), (16, 16, 16, 16), "abc", (32.5, 32), None])
def test_bad_shapes(shape):
    with pytest.raises(InputError):
        synthetic_cube(shape)


@pytest.mark.parametrize("kwargs", [dict(n_faults=-1), dict(n_faults=1.5), dict(max_throw=2.0), dict(noise=-0.1),
                                    dict(peak_frequency=0.6), dict(reverse_fraction=1.5), dict(max_dip=60.0),
                                    dict(seed=-3), dict(max_throw=20.0)])
def test_bad_parameters(kwargs):
    with pytest.raises(InputError):
        synthetic_cube((32, 32, 64), **kwargs)


def test_ricker():
    w = ricker(0.15)
    assert w.size == 2 * 10 + 1 and w[10] == 1.0 and np.argmax(w) == 10
    assert_allclose(w, w[::-1])
    # zero crossings at t = +-1 / (pi f sqrt(2))
    t0 = 1 / (np.pi * 0.15 * np.sqrt(2))
    assert w[10 + int(np.floor(t0))] > 0 > w[10 + int(np.ceil(t0))]

