"""seismo3d.seismic._kernels: the Gaussian passes against the analytic answer, the closed-form eigenvectors against
numpy's eigh, the binary searches against numpy on generated data."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from seismo3d._progress import reporting_within
from seismo3d.seismic import _kernels


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_gaussian_pass_smooths_and_differentiates_a_sine(axis):
    """Against the analytic answer: a Gaussian of width s scales a sine of wavenumber k by exp(-k^2 s^2 / 2) (the
    3-sigma truncation adds ~1e-3 of relative error), its derivative filter gives the smoothed cosine times k."""
    n, k, sigma = 64, 2 * np.pi / 16, 1.5
    i = np.arange(n, dtype=np.float64)
    shape = [5, 6, 7]
    shape[axis] = n
    line = np.reshape(np.sin(k * i), [n if d == axis else 1 for d in range(3)])
    x = np.broadcast_to(line, shape).astype(np.float32)
    gain = np.exp(-0.5 * (k * sigma) ** 2)
    inner = (slice(None),) * axis + (slice(8, n - 8),)
    smooth = _kernels.gaussian_pass(x, axis, sigma)
    slope = _kernels.gaussian_pass(x, axis, sigma, order=1)
    assert smooth.dtype == slope.dtype == np.float32 and smooth.shape == x.shape
    expected = np.broadcast_to(np.reshape(np.sin(k * i), line.shape), shape)[inner]
    np.testing.assert_allclose(smooth[inner], gain * expected, atol=2e-3)
    expected = np.broadcast_to(np.reshape(np.cos(k * i), line.shape), shape)[inner]
    np.testing.assert_allclose(slope[inner], gain * k * expected, atol=2e-3)
    assert np.array_equal(_kernels.gaussian_pass(x, axis, 0.0), x)  # no filter


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_gaussian_pass_keeps_a_range_of_the_whole_axis_bit_for_bit(axis):
    x = np.random.default_rng(7 + axis).standard_normal((13, 11, 30)).astype(np.float32)
    whole = _kernels.gaussian_pass(x, axis, 2.0, order=1)
    n = x.shape[axis]
    for lo, hi in ((0, n), (0, 3), (4, 9), (n - 2, n), (5, 6)):
        got = _kernels.gaussian_pass(x, axis, 2.0, order=1, keep=(lo, hi))
        assert np.array_equal(got, np.take(whole, np.arange(lo, hi), axis=axis))


@pytest.mark.parametrize("axis", [0, 1, 2])
@pytest.mark.parametrize("order", [0, 1])
def test_gaussian_pass32_is_scipys_pass_within_float32_sums(axis, order):
    """OpenCV's float32 sums against scipy's double ones (gaussian_pass): the same weights, edges and keep."""
    x = np.random.default_rng(11 + axis).standard_normal((17, 19, 41)).astype(np.float32)
    for sigma in (1.0, 2.0, 6.0):
        ref = _kernels.gaussian_pass(x, axis, sigma, order=order)
        got = _kernels.gaussian_pass32(x, axis, sigma, order=order)
        assert got.dtype == np.float32 and got.shape == x.shape
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-6 * float(np.abs(ref).max()))
        kept = _kernels.gaussian_pass32(x, axis, sigma, order=order, keep=(3, 9))
        assert np.array_equal(kept, np.take(got, np.arange(3, 9), axis=axis))
    assert np.array_equal(_kernels.gaussian_pass32(x, axis, 0.0), x)  # no filter


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_gaussian_pass32_of_a_part_is_the_whole_arrays_there_bit_for_bit(axis):
    """An output's arithmetic depends on its sample index only: a part cut along the other axes (a block's traces)
    filtered, or the whole array's filtered, give the same bits (runs by blocks rely on it)."""
    x = np.random.default_rng(5 + axis).standard_normal((60, 70, 333)).astype(np.float32)
    whole = _kernels.gaussian_pass32(x, axis, 2.0, order=1)
    for rows, cols in ((slice(3, 41), slice(7, 66)), (slice(0, 1), slice(69, 70)), (slice(17, 60), slice(0, 9))):
        part = x[rows, cols]
        n = x.shape[axis]
        keep = (rows, cols, slice(0, n))[axis]
        lo, hi = max(keep.start - 6, 0), min(keep.stop + 6, n)  # the part read with the filter's radius
        cut = [rows, cols, slice(None)]
        cut[axis] = slice(lo, hi)
        got = _kernels.gaussian_pass32(x[tuple(cut)], axis, 2.0, order=1, keep=(keep.start - lo, keep.stop - lo))
        assert got.shape == part.shape and np.array_equal(got, whole[rows, cols])


def test_structure_tensor_at_a_core_is_the_whole_tensor_there_bit_for_bit():
    cube = np.random.default_rng(6).standard_normal((30, 26, 50)).astype(np.float32)
    whole = _kernels.structure_tensor(cube, 1.0, (2.0, 6.0), False)
    for core in ((slice(8, 20), slice(9, 17)), (slice(0, 30), slice(0, 26)), (slice(0, 5), slice(24, 26)),
                 (slice(29, 30), slice(0, 1))):
        at = _kernels.structure_tensor_at(cube, 1.0, (2.0, 6.0), core)
        assert all(np.array_equal(a, w[core]) for a, w in zip(at, whole))


def test_eig3_gives_eighs_largest_eigenvector_and_planarity():
    rng = np.random.default_rng(3)
    a = rng.standard_normal((2000, 3, 3))
    t = (a @ a.transpose(0, 2, 1)).astype(np.float32)  # symmetric, positive semi-definite
    vx, vy, vz, planarity = _kernels.eig3(t[:, 0, 0], t[:, 0, 1], t[:, 0, 2], t[:, 1, 1], t[:, 1, 2], t[:, 2, 2])
    values, vectors = np.linalg.eigh(t.astype(np.float64))
    v = vectors[:, :, 2] * np.sign(vectors[:, 2:3, 2])  # the largest, third component >= 0 as eig3's
    np.testing.assert_allclose(np.stack([vx, vy, vz], axis=1), v, atol=2e-5)
    np.testing.assert_allclose(planarity, (values[:, 2] - values[:, 1]) / values[:, 2], atol=1e-6)
    assert np.all(vz >= 0)


def test_eig3_of_an_isotropic_or_zero_tensor_is_vertical_and_not_planar():
    one = np.float32([1.0, 0.0])
    zero = np.zeros(2, np.float32)
    vx, vy, vz, planarity = _kernels.eig3(one, zero, zero, one, zero, one)
    assert np.array_equal(np.stack([vx, vy, vz, planarity]), [[0, 0], [0, 0], [1, 1], [0, 0]])


def test_eig_normals_and_eig_slopes_agree_bit_for_bit():
    cube = np.random.default_rng(4).standard_normal((12, 10, 30)).astype(np.float32)
    t = _kernels.structure_tensor(cube, 1.0, (2.0, 6.0), False)
    normals = np.empty(cube.shape + (3,), np.float32)
    planarity = np.empty(cube.shape, np.float32)
    _kernels.eig_normals(*t, normals, planarity)
    p0 = np.empty(cube.shape, np.float32)
    p1 = np.empty(cube.shape, np.float32)
    _kernels.eig_slopes(*t, _kernels.MAX_SLOPE, p0, p1, True)
    q0, q1 = _kernels.slopes_from_normals(normals)
    assert np.array_equal(p0, q0) and np.array_equal(p1, q1)
    assert np.all((planarity >= 0) & (planarity <= 1))


def test_eig_vectors_are_eig_normals_normals_chunk_by_chunk(monkeypatch):
    """The eigenvectors handed out chunk by chunk (the fault orientation makes its angles of them in the cache) are
    eig_normals' normals, rounded to float32 the same, every element once, whatever the chunks' size."""
    cube = np.random.default_rng(8).standard_normal((12, 10, 30)).astype(np.float32)
    t = _kernels.structure_tensor(cube, 1.0, (2.0, 6.0), False)
    normals = np.empty(cube.shape + (3,), np.float32)
    _kernels.eig_normals(*t, normals, np.empty(cube.shape, np.float32))
    for chunk in (1 << 13, 7):
        monkeypatch.setattr(_kernels, "_EIG_CHUNK", chunk)
        got = np.full((cube.size, 3), np.nan, np.float32)

        def write(part, vx, vy, vz):
            got[part, 0], got[part, 1], got[part, 2] = vx, vy, vz

        _kernels.eig_vectors(*t, write)
        assert np.array_equal(got.view(np.uint32), normals.reshape(-1, 3).view(np.uint32))


def test_eig3_without_planarity_gives_the_same_eigenvectors(monkeypatch):
    """The slopes' eigen-decomposition skips the planarity (two eigenvalues and a cosine): the same bits of the
    eigenvector, and the same slopes whatever the chunks' size."""
    rng = np.random.default_rng(6)
    a = rng.standard_normal((3000, 3, 3))
    t = (a @ a.transpose(0, 2, 1)).astype(np.float32)
    comps = (t[:, 0, 0], t[:, 0, 1], t[:, 0, 2], t[:, 1, 1], t[:, 1, 2], t[:, 2, 2])
    *full, _ = _kernels.eig3(*comps)
    *vectors, planarity = _kernels.eig3(*comps, planarity=False)
    assert planarity is None
    assert all(np.array_equal(u.view(np.uint64), v.view(np.uint64)) for u, v in zip(full, vectors))
    cube = rng.standard_normal((12, 10, 30)).astype(np.float32)
    tensor = _kernels.structure_tensor(cube, 1.0, (2.0, 6.0), False)
    slopes = []
    for chunk in (1 << 13, 7):
        monkeypatch.setattr(_kernels, "_EIG_CHUNK", chunk)
        p0, p1 = np.empty(cube.shape, np.float32), np.empty(cube.shape, np.float32)
        _kernels.eig_slopes(*tensor, _kernels.MAX_SLOPE, p0, p1, True)
        slopes.append(np.stack([p0, p1]).view(np.uint32))
    assert np.array_equal(*slopes)


def test_search_left_and_right_are_numpys_searchsorted():
    rng = np.random.default_rng(5)
    keys = np.sort(rng.integers(0, 50, 200))
    for value in range(-2, 53):
        assert _kernels.search_left(keys, value) == np.searchsorted(keys, value)
        assert _kernels.search_right(keys, value) == np.searchsorted(keys, value, side="right")
    assert _kernels.search_left(keys[:0], 3) == 0 and _kernels.search_right(keys[:0], 3) == 0


def test_search_left_and_right_on_a_traces_picks():
    """As the horizon kernels use them: float picks of one trace (a slice), ties, times outside the picks, a NaN
    pick last (where np.sort puts it)."""
    rng = np.random.default_rng(11)
    for _ in range(2000):
        p = np.sort(rng.integers(0, 6, rng.integers(0, 8)).astype(float))
        if p.size and rng.random() < 0.2:
            p[-1] = np.nan
        times = np.concatenate([rng.normal(size=2), p, rng.normal(size=1)])
        t = float(rng.integers(-1, 7)) + (0.5 if rng.random() < 0.3 else 0.0)
        assert 2 + _kernels.search_left(times[2:2 + p.size], t) == 2 + np.searchsorted(p, t)
        assert _kernels.search_right(times[2:2 + p.size], t) == np.searchsorted(p, t, side="right")



@pytest.mark.parametrize("slab", [1, 7, 9, 64])
def test_structure_tensor_by_slabs_of_inlines_is_the_one_call_s_bits(slab):
    # slabs thinner than the 9 inlines a slab's tensor reads beyond it, a slab that ends at the cube's last inline
    cube = np.random.default_rng(7).standard_normal((40, 26, 50)).astype(np.float32)
    one = _kernels.structure_tensor_at(cube, 1.0, (2.0, 6.0), (slice(None), slice(None)))
    slabs = _kernels.structure_tensor(cube, 1.0, (2.0, 6.0), False, slab=slab)
    assert all(np.array_equal(a, b) for a, b in zip(slabs, one))


def test_structure_tensor_reports_a_line_per_slab_when_its_step_asks(caplog):
    cube = np.random.default_rng(8).standard_normal((40, 12, 30)).astype(np.float32)
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        quiet = _kernels.structure_tensor(cube, 1.0, (2.0, 6.0), False, slab=16)
        assert caplog.messages == []  # no step asks: silent
        with reporting_within("throw"):
            reported = _kernels.structure_tensor(cube, 1.0, (2.0, 6.0), False, slab=16)
    assert caplog.messages == ["throw: 16/40 inline, structure tensor", "throw: 32/40 inline, structure tensor",
                               "throw: 40/40 inline, structure tensor"]
    assert all(np.array_equal(a, b) for a, b in zip(quiet, reported))
