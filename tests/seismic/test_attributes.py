"""Reflector orientation, semblance, eigen-coherence and discontinuity against constructed ground truth."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic.attributes import (
    ReflectorOrientation,
    discontinuity,
    eigen_coherence,
    section_slopes,
    semblance,
    structure_tensor_halo,
    structure_tensor_orientation,
    structure_tensor_slopes,
)


def _planar(shape, slopes, period=9.0):
    """Plane-wave reflectors: f = sin(2 pi (t - sum_k p_k x_k) / period), slopes p in samples per trace."""
    grids = np.meshgrid(*[np.arange(n, dtype=np.float64) for n in shape], indexing="ij")
    phase = grids[-1] - sum(p * g for p, g in zip(slopes, grids[:-1]))
    return np.sin(2 * np.pi * phase / period).astype(np.float32)


def _interior(a, m=6, vertical=None):
    """Drop ``m`` samples at each lateral edge and ``vertical`` (default ``m``) at the top and bottom."""
    v = m if vertical is None else vertical
    return a[(slice(m, -m),) * (a.ndim - 1) + (slice(v, -v),)]


@pytest.mark.parametrize("slopes", [(0.0, 0.0), (0.4, -0.25), (-1.0, 0.6)])
def test_orientation_3d_recovers_slopes(slopes):
    cube = _planar((32, 30, 72), slopes)
    o = structure_tensor_orientation(cube)
    assert isinstance(o, ReflectorOrientation)
    assert o.normals.shape == cube.shape + (3,) and o.normals.dtype == np.float32
    assert o.slopes.shape == (2,) + cube.shape
    # the vertical tensor smoothing (sigma 6 samples) reaches 18 samples: the top and bottom are clamped edges
    assert_allclose(_interior(o.slopes[0], 8, 20), slopes[0], atol=0.02)
    assert_allclose(_interior(o.slopes[1], 8, 20), slopes[1], atol=0.02)
    assert_allclose(np.linalg.norm(o.normals, axis=-1), 1.0, atol=1e-5)
    assert np.all(o.normals[..., 2] >= 0)
    assert np.median(o.planarity) > 0.9
    true_dip = np.degrees(np.arctan(np.hypot(*slopes)))
    assert_allclose(np.median(o.dip_deg), true_dip, atol=1.0)


@pytest.mark.parametrize("slope", [0.0, 0.3, -0.7])
def test_orientation_2d_recovers_slope(slope):
    section = _planar((40, 72), (slope,))
    o = structure_tensor_orientation(section)
    assert o.slopes.shape == (1, 40, 72) and o.normals.shape == (40, 72, 2)
    assert_allclose(_interior(o.slopes[0], 8, 20), slope, atol=0.02)


@pytest.mark.parametrize("shape", [(21, 17, 64), (33, 64)])
def test_slopes_alone_equal_the_orientations_slopes_bit_for_bit(shape):
    """The throws' slopes-only path (no normals stored) gives the orientation's slopes exactly, on dipping
    reflectors with noise, a dead trace and slopes clipped at 5, in 3D and 2D."""
    rng = np.random.default_rng(7)
    data = _planar(shape, (0.4, -0.3)[:len(shape) - 1]) + 0.3 * rng.standard_normal(shape).astype(np.float32)
    data[10:] = _planar((shape[0] - 10,) + shape[1:], (7.0, 0.0)[:len(shape) - 1], period=40.0)  # steeper than 5
    data[3] = 0.0
    assert np.abs(structure_tensor_slopes(data)).max() == 5.0
    assert np.array_equal(structure_tensor_slopes(data), structure_tensor_orientation(data).slopes)
    assert np.array_equal(structure_tensor_slopes(data, sigma_gradient=1.5, sigma_tensor=(1.0, 3.0)),
                          structure_tensor_orientation(data, sigma_gradient=1.5, sigma_tensor=(1.0, 3.0)).slopes)
    with pytest.raises(InputError):
        structure_tensor_slopes(data, sigma_gradient=0.0)


def test_slopes_of_a_core_equal_the_whole_cubes_bit_for_bit():
    """``core``: the slopes of a block's core from the amplitudes within structure_tensor_halo of it (each smoothing
    pass computing only the lines its later passes read, the tensor eigen-decomposed at the core only, as the ridges
    of a run by blocks take them) are the whole cube's slopes there, bit for bit: inside the cube, at its edges and at
    a corner; a 2D section has no core."""
    rng = np.random.default_rng(5)
    shape = (60, 52, 96)
    data = _planar(shape, (0.4, -0.3)) + 0.3 * rng.standard_normal(shape).astype(np.float32)
    whole = structure_tensor_slopes(data)
    halo = structure_tensor_halo()[0]
    for i0, i1, j0, j1 in [(20, 36, 18, 30), (0, 16, 0, 52), (44, 60, 40, 52)]:
        a0, a1, b0, b1 = max(i0 - halo, 0), min(i1 + halo, shape[0]), max(j0 - halo, 0), min(j1 + halo, shape[1])
        core = (slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0))
        ours = structure_tensor_slopes(data[a0:a1, b0:b1], core=core)
        assert ours.shape == (2, i1 - i0, j1 - j0, shape[2])
        assert np.array_equal(ours, whole[:, i0:i1, j0:j1])
    with pytest.raises(InputError, match="core"):
        structure_tensor_slopes(data[0], core=(slice(0, 4), slice(0, 4)))


def test_planarity_low_on_noise():
    noise = np.random.default_rng(1).standard_normal((24, 24, 24)).astype(np.float32)
    assert np.median(structure_tensor_orientation(noise).planarity) < 0.6


def test_semblance_identical_and_dipping_traces():
    flat = _planar((20, 20, 40), (0.0, 0.0))
    assert_allclose(_interior(semblance(flat), 3), 1.0, atol=1e-4)
    dipping = _planar((20, 20, 40), (0.8, 0.0))
    oriented = _interior(semblance(dipping), 5)
    plain = _interior(semblance(dipping, structure_oriented=False), 5)
    assert np.median(oriented) > 0.97
    assert np.median(plain) < 0.9  # a flat window across dipping reflectors loses coherence


def test_semblance_of_noise_is_about_one_over_j():
    noise = np.random.default_rng(2).standard_normal((40, 40, 60)).astype(np.float32)
    s = semblance(noise, structure_oriented=False, half_samples=10)
    # E[s] for J independent traces is about 1 / J (J = 9)
    assert np.mean(_interior(s, 12)) == pytest.approx(1 / 9, abs=0.03)


def test_eigen_coherence():
    scale = np.where(np.arange(12) % 2 == 0, 1.0, 3.0).astype(np.float32)[:, None, None]  # alternating gains
    scaled = _planar((12, 12, 30), (0.0, 0.0)) * scale
    # traces equal up to a scale factor: one principal component, coherence 1 (semblance is not)
    assert_allclose(_interior(eigen_coherence(scaled, structure_oriented=False), 3), 1.0, atol=1e-5)
    assert np.median(_interior(semblance(scaled, structure_oriented=False), 3)) < 0.85
    noise = np.random.default_rng(3).standard_normal((16, 16, 30)).astype(np.float32)
    assert np.median(eigen_coherence(noise, structure_oriented=False)) < 0.5
    section = _planar((30, 72), (0.5,))
    assert_allclose(_interior(eigen_coherence(section), 5, 20), 1.0, atol=1e-3)


@pytest.mark.parametrize("method", ["semblance", "eigen"])
def test_discontinuity_highlights_faults(method):
    syn = synthetic_cube((200, 100), n_faults=2, seed=4)
    d = discontinuity(syn.cube, method=method)
    assert d.shape == syn.cube.shape and d.dtype == np.float32
    on = syn.fault_labels > 0
    assert np.median(d[on]) > 3 * np.median(d[~on])


def test_bad_input():
    with pytest.raises(InputError, match="NaN"):
        semblance(np.full((8, 8), np.nan))
    with pytest.raises(InputError, match="2D section"):
        structure_tensor_orientation(np.zeros((4, 4, 4, 4)))
    with pytest.raises(InputError, match="at least 3"):
        semblance(np.zeros((2, 10)))
    with pytest.raises(InputError, match="method"):
        discontinuity(np.zeros((8, 8)), method="sobel")
    with pytest.raises(InputError, match="sigma_tensor"):
        structure_tensor_orientation(np.zeros((8, 8)), sigma_tensor=(1, 2, 3))
    with pytest.raises(InputError, match="half_traces"):
        semblance(np.zeros((8, 8)), half_traces=0)


def test_structure_tensor_halo_is_exact_and_tight():
    """A block of a cube with the halo has the whole cube's slopes inside it (bit for bit); one trace less does not."""
    halo, vertical = structure_tensor_halo()
    assert (halo, vertical) == (3 + 6, 3 + 18)  # kernel radii: round(3 sigma) of sigma 1 (gradient), 2 and 6 (tensor)
    cube = np.random.default_rng(0).standard_normal((48, 40, 24)).astype(np.float32)
    whole = structure_tensor_orientation(cube).slopes
    lo, hi = 20, 26  # traces [lo, hi) along both lateral axes
    for h, same in ((halo, True), (halo - 1, False)):
        block = structure_tensor_orientation(cube[lo - h:hi + h, lo - h:hi + h]).slopes[:, h:-h, h:-h]
        assert np.array_equal(block, whole[:, lo:hi, lo:hi]) is same
    # clipped at the cube's edge: the filters clamp there as on the whole cube
    edge = structure_tensor_orientation(cube[:hi + halo, :hi + halo]).slopes[:, :hi, :hi]
    assert np.array_equal(edge, whole[:, :hi, :hi])


@pytest.mark.parametrize("axis", [0, 1])
def test_section_slopes_equal_each_sections_structure_tensor(axis):
    cube = synthetic_cube((16, 21, 60), n_faults=2, seed=1).cube
    got = section_slopes(cube, axis, sigma_tensor=(2.0, 3.0), max_lines=5)  # blocks of 5 sections
    sections = [cube[:, j] for j in range(21)] if axis == 0 else [cube[i] for i in range(16)]
    each = np.stack([structure_tensor_orientation(sec, sigma_tensor=(2.0, 3.0)).slopes[0] for sec in sections],
                    axis=1 if axis == 0 else 0)
    np.testing.assert_array_equal(got, each)
    assert np.abs(got).max() > 0.1  # the faulted cube's reflectors dip


@pytest.mark.parametrize("data, axis, match", [(np.zeros((10, 20)), 0, "cube"),
                                               (np.zeros((4, 5, 20)), 2, "axis must be 0")])
def test_section_slopes_bad_input(data, axis, match):
    with pytest.raises(InputError, match=match):
        section_slopes(data, axis)
