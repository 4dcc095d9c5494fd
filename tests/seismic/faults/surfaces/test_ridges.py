"""Fault surfaces (seismo3d.seismic.faults.surfaces.ridges): thinning and linking against synthetic ground truth, real
sections, bad input. The five 128^3 cubes are traced once per session (tests/conftest.py, shared with the throw
tests)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage as ndi

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import (
    Fault, FaultLikelihood, SkinOptions, evaluate_faults, fault_labels, fault_likelihood, thin_faults,
    trace_faults,
)
from seismo3d.seismic.faults.surfaces.ridges import live_likelihood

SEEDS = (0, 1, 2, 3, 4)


def _trace(cube):
    res = trace_faults(cube, progress=False)
    return FaultLikelihood(res.likelihood, res.strike_deg, res.dip_deg), res.thin, res.faults


@pytest.fixture(scope="module")
def traced_2d():
    out = {}
    for seed in SEEDS:
        syn = synthetic_cube((256, 128), seed=seed)
        out[seed] = (syn, *_trace(syn.cube))
    return out


# --------------------------------------------------------------------------------------------------------------------
# accuracy on synthetic data (the acceptance criteria)


@pytest.mark.slow
@pytest.mark.parametrize("seed", SEEDS)
def test_3d_precision_recall(traced_cube, seed):
    c = traced_cube(seed)
    syn, fl, thin, faults = c.syn, c.likelihood, c.thin, c.faults
    assert isinstance(fl, FaultLikelihood)
    assert fl.likelihood.shape == syn.cube.shape and fl.likelihood.dtype == np.float32
    assert 0.0 <= fl.likelihood.min() and fl.likelihood.max() <= 1.0
    assert np.all((thin == 0) | (thin == c.votes))
    linked = fault_labels(faults, syn.cube.shape) > 0
    scores = evaluate_faults(linked, syn.fault_labels, tolerance=2)
    p, r = scores.precision, scores.recall
    print(f"3D seed {seed}: fault skins precision {p:.3f} recall {r:.3f}")  # the table of the notes (pytest -s)
    assert p >= 0.90 and r >= 0.90, (p, r)  # the target


@pytest.mark.slow
@pytest.mark.parametrize("seed", SEEDS)
def test_3d_fault_orientation(traced_cube, seed):
    """Each true fault is found as one dominant linked fault whose mean normal is within 8 degrees of the truth."""
    c = traced_cube(seed)
    syn, faults = c.syn, c.faults
    dist, nearest = ndi.distance_transform_edt(syn.fault_labels == 0, return_indices=True)
    for plane in syn.faults:
        best = 0
        angle = None
        for f in faults:
            idx = tuple(f.points.T)
            near_id = syn.fault_labels[tuple(nearest[(slice(None),) + idx])]
            on = (near_id == plane.id) & (dist[idx] <= 2)
            if on.sum() > best:
                best = int(on.sum())
                part = Fault(0, f.points[on], f.likelihood[on], f.strike_deg[on], f.dip_deg[on], f.normals[on])
                angle = np.degrees(np.arccos(min(1.0, abs(float(part.mean_normal @ plane.normal)))))
        n_true = int(np.count_nonzero(syn.fault_labels == plane.id))
        assert best >= 0.5 * n_true, (plane.id, best, n_true)
        assert angle <= 8.0, (plane.id, angle)  # measured: 0.5-5.7 degrees


@pytest.mark.slow
@pytest.mark.parametrize("seed", SEEDS)
def test_2d_precision_recall(traced_2d, seed):
    syn, fl, thin, faults = traced_2d[seed]
    assert fl.likelihood.shape == syn.cube.shape
    assert set(np.unique(fl.strike_deg[np.isfinite(fl.strike_deg)])) <= {90.0, 270.0}
    assert all(f.points.shape[1] == 2 and f.normals.shape[1] == 2 for f in faults)
    linked = fault_labels(faults, syn.cube.shape) > 0
    linked_scores = evaluate_faults(linked, syn.fault_labels, tolerance=2)
    thin_scores = evaluate_faults(thin > 0, syn.fault_labels, tolerance=2)
    p, r = linked_scores.precision, linked_scores.recall
    p_thin, r_thin = thin_scores.precision, thin_scores.recall
    print(f"2D seed {seed}: linked precision {p:.3f} recall {r:.3f}; thinned {p_thin:.3f} / {r_thin:.3f}")
    assert p >= 0.85 and r >= 0.90, (p, r)  # measured: precision 0.89-1.00, recall 0.97-1.00
    assert r_thin >= 0.90, r_thin  # the thinned votes above the lower threshold, before the skins drop short ones


def test_2d_dip_direction_and_angle(traced_2d):
    """Strike 270 = the fault deepens toward increasing trace index (the synthetic's convention), dip within 5 deg."""
    syn, _, _, faults = traced_2d[0]
    dist, nearest = ndi.distance_transform_edt(syn.fault_labels == 0, return_indices=True)
    for plane in syn.faults:
        on = [f for f in faults if np.mean(syn.fault_labels[tuple(nearest[(slice(None),) + tuple(f.points.T)])]
                                           == plane.id) > 0.9]
        assert on, plane
        big = max(on, key=lambda f: f.size)
        assert big.mean_strike_deg == pytest.approx(plane.strike_deg)
        assert big.mean_dip_deg == pytest.approx(plane.dip_deg, abs=5.0)


@pytest.mark.slow  # 3.3 s in the fast lane, whose budget is 60 s
def test_no_faults_in_unfaulted_cube():
    syn = synthetic_cube((80, 80, 80), n_faults=0, seed=3)
    fl, thin, faults = _trace(syn.cube)
    assert faults == []
    assert np.count_nonzero(thin) < 0.001 * thin.size
    assert np.median(fl.likelihood) < 0.3


# --------------------------------------------------------------------------------------------------------------------
# building blocks


def test_fault_labels_paint_each_fault_with_its_id():
    points = np.argwhere(np.ones((1, 20, 20), bool)) + [10, 5, 5]  # a 400-sample vertical plane at inline 10
    plane = Fault(1, points, np.full(400, 0.9), np.full(400, 90.0), np.full(400, 90.0), np.tile([1.0, 0, 0], (400, 1)))
    small = Fault(2, np.array([[20, 3, 3]]), np.ones(1), np.zeros(1), np.ones(1), np.ones((1, 3)))
    labels = fault_labels([plane, small], (30, 30, 30))
    assert np.count_nonzero(labels == 1) == 400 and labels[10, 10, 10] == 1 and labels[20, 3, 3] == 2
    assert np.count_nonzero(labels) == 401


def test_thin_faults_is_one_sample_wide():
    syn = synthetic_cube((256, 128), n_faults=1, seed=7)
    fl = fault_likelihood(syn.cube)
    thin = thin_faults(fl.likelihood, fl.strike_deg, fl.dip_deg)
    rows = [np.count_nonzero(thin[:, t]) for t in range(20, 108)]
    assert np.median(rows) == 1
    assert np.all((thin == 0) | (thin == fl.likelihood))
    # fixed thresholds are honoured
    assert np.count_nonzero(thin_faults(fl.likelihood, fl.strike_deg, fl.dip_deg, threshold=1.0)) == 0


@pytest.mark.slow
def test_ridges_above_a_floor_are_those_of_the_whole_ranking_image():
    """The ridges computed only around the samples above a floor (the seed threshold, a fixed lower threshold) are
    those of the ranking image computed everywhere, bit for bit, in 3D and 2D; and thin_faults' fixed thresholds
    keep what the hysteresis of the whole ridge image keeps."""
    from skimage.filters import apply_hysteresis_threshold

    from seismo3d.seismic.faults.surfaces.ridges import ridge_image, ridges

    syn = synthetic_cube((32, 32, 72), n_faults=2, seed=3)
    fl = fault_likelihood(syn.cube)
    for like, strike, dip in ((fl.likelihood, fl.strike_deg, fl.dip_deg),
                              (fl.likelihood[:, 16], fl.strike_deg[:, 16], fl.dip_deg[:, 16])):
        everywhere = ridge_image(like, strike, dip)
        for floor in (0.0, 0.3, 0.6):
            above = everywhere > floor
            assert 0 < np.count_nonzero(above) < like.size // 5
            assert np.array_equal(np.where(above, everywhere, 0), np.where(above, ridges(like, strike, dip, floor), 0))
            assert not np.any(ridges(like, strike, dip, floor)[like <= floor])
        for lo, hi in ((0.3, 0.3), (0.2, 0.6)):
            keep = apply_hysteresis_threshold(everywhere, lo, hi) & (everywhere > 0)
            assert np.array_equal(thin_faults(like, strike, dip, threshold=(lo, hi)), np.where(keep, like, 0))


@pytest.mark.parametrize("shape", [(9, 7, 11), (6, 1, 13), (1, 1, 5), (2, 3, 1)])
def test_mask_grown_by_a_sample_is_scipys_maximum_filter(shape):
    """The mask of the samples the ridge test reads (_grown) is scipy's 3 x 3 x 3 maximum filter with clamped
    edges, also on axes of one or two samples (a section as a cube of one crossline)."""
    from seismo3d.seismic.faults.surfaces.ridges import _grown

    mask = np.random.default_rng(sum(shape)).random(shape) > 0.85
    assert np.array_equal(_grown(mask), ndi.maximum_filter(mask, size=3, mode="nearest"))


@pytest.mark.slow
def test_ridges_without_strike_and_dip_below_the_orientation_floor():
    """Strike and dip NaN (the learned likelihood's below its orientation floor): where the ridges do not read them
    (away from the samples above the seed threshold) the ridges are those of the finite orientation, bit for bit; a
    sample without them is no ridge, at any floor; inf is refused."""
    from seismo3d.seismic.faults.surfaces.ridges import ridge_image, ridges

    syn = synthetic_cube((32, 32, 72), n_faults=2, seed=3)
    fl = fault_likelihood(syn.cube)
    seed = float(np.quantile(fl.likelihood, 0.97))  # a seed threshold with few samples above it
    read = ndi.maximum_filter(fl.likelihood > seed, size=3)  # where the ridges above the seed threshold read them
    unknown = ~ndi.binary_dilation(read, iterations=2)
    assert 0.3 < unknown.mean() < 0.95
    strike, dip = (np.where(unknown, np.nan, a).astype(np.float32) for a in (fl.strike_deg, fl.dip_deg))
    assert np.array_equal(ridges(fl.likelihood, strike, dip, seed), ridges(fl.likelihood, fl.strike_deg,
                                                                             fl.dip_deg, seed))
    everywhere = ridge_image(fl.likelihood, strike, dip)
    assert not everywhere[unknown].any() and everywhere[~unknown].any()
    with pytest.raises(InputError, match="inf"):
        ridges(fl.likelihood, np.where(unknown, np.inf, fl.strike_deg), fl.dip_deg, seed)


def test_bad_input():
    good = np.zeros((10, 10, 10), np.float32)
    with pytest.raises(InputError, match="same shape"):
        thin_faults(good, good, good[:5])
    with pytest.raises(InputError, match="threshold"):
        thin_faults(good, good, good, threshold=(0.8, 0.2))
    with pytest.raises(InputError, match="outside"):
        fault_labels([Fault(1, np.array([[0, 0, 12]]), np.ones(1), np.zeros(1), np.ones(1), np.ones((1, 3)))],
                     good.shape)


# --------------------------------------------------------------------------------------------------------------------
# real data: runs, no accuracy claim (see the PNG check in benchmarks/faults.py and the report)

_SECTIONS = {"costarica_gx808": (825, 210), "campos_gx373": (550, 300)}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(_SECTIONS))
def test_real_sections_run(name):
    root = os.environ.get("SEISMO3D_DATA_DIR")
    if not root:
        pytest.skip("SEISMO3D_DATA_DIR is not set")
    path = Path(root) / "seismic" / "sections" / f"{name}.f32be"
    section = np.fromfile(path, ">f4").reshape(_SECTIONS[name])
    fl, thin, faults = _trace(section)
    assert fl.likelihood.shape == section.shape
    # both sections show dozens of faults; the counts are broad sanity bounds, not accuracy claims
    assert 10 <= len(faults) <= 400
    assert all(f.size >= SkinOptions().smallest(section.shape) for f in faults)
    assert np.count_nonzero(thin) < 0.15 * thin.size  # thinned votes: 12 % on the densely faulted gx808


def test_live_likelihood_counts_the_saturated_live_samples_of_the_core_above_the_level():
    fl = np.array([[0.95, 0.5, 0.91], [0.2, 0.99, 0.85]], np.float32)
    near = np.array([[False, False, True], [False, False, False]])
    high, live = live_likelihood(fl, near, level=0.9)
    assert (high, live) == (2, 5) and fl[0, 2] == 0.0  # 0.95 and 0.99; the sample near dead ones is zeroed
    assert live_likelihood(fl.copy(), None, level=0.8) == (3, 6)
    assert live_likelihood(fl.copy(), None, (slice(1, 2),), level=0.8) == (2, 3)  # the core: the second trace


# --------------------------------------------------------------------------------------------------------------------
# the ridges of a block's core (a run by blocks): the same bits as the ridges of its whole region, cropped

# blocks (i0, i1, j0, j1) of a 40 x 36 cube: inside, at an edge, at two edges, at a corner, one trace wide
_BLOCKS = [(14, 26, 12, 24), (0, 12, 10, 22), (28, 40, 0, 36), (30, 40, 26, 36), (20, 21, 35, 36)]


@pytest.fixture(scope="module")
def scanned_cube():
    syn = synthetic_cube((40, 36, 64), n_faults=3, seed=2)
    fl = fault_likelihood(syn.cube)
    rng = np.random.default_rng(8)
    # strikes and dips of every kind, shallow ones included (their average along the dip reads far across)
    strike = rng.uniform(0, 360, fl.likelihood.shape).astype(np.float32)
    dip = rng.uniform(0.001, 90, fl.likelihood.shape).astype(np.float32)
    return syn.cube, fl, strike, dip


def _regions(shape, halo):
    for i0, i1, j0, j1 in _BLOCKS:
        a0, a1, b0, b1 = max(i0 - halo, 0), min(i1 + halo, shape[0]), max(j0 - halo, 0), min(j1 + halo, shape[1])
        yield (slice(a0, a1), slice(b0, b1)), (slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0))


@pytest.mark.slow
def test_ridges_of_a_core_are_those_of_the_whole_region_bit_for_bit(scanned_cube):
    """``core``: the average along the dip and the ridge test at the core only (the Gaussian over the region) give
    the ridges of the whole region at the core, bit for bit, inside the cube, at its edges and at a corner, for the
    scan's and random (shallow) orientations, every floor, and the thinning's settings (no smoothing)."""
    from seismo3d.seismic.faults.surfaces.ridges import RIDGE_HALO, THIN_HALO, ridge_image, ridges, thin_votes

    _, fl, strike, dip = scanned_cube
    for st, dp in ((fl.strike_deg, fl.dip_deg), (strike, dip)):
        for region, core in _regions(fl.likelihood.shape, RIDGE_HALO):
            like, s, d = fl.likelihood[region], st[region], dp[region]
            for floor in (-1.0, 0.0, 0.3):
                whole = ridge_image(like, s, d, floor=floor)[core]
                ours = ridge_image(like, s, d, floor=floor, core=core)
                assert ours.shape == whole.shape and ours.dtype == np.float32
                assert np.array_equal(ours, whole)
            assert np.array_equal(ridges(like, s, d, 0.3, core=core), ridges(like, s, d, 0.3)[core])
            assert np.count_nonzero(ridges(like, s, d, 0.3, core=core)) > 0
            for sigma, along in ((0.0, 0), (1.5, 0), (0.0, 4)):
                assert np.array_equal(ridge_image(like, s, d, floor=0.0, sigma=sigma, dip_smoothing=along, core=core),
                                      ridge_image(like, s, d, floor=0.0, sigma=sigma, dip_smoothing=along)[core])
        for region, core in _regions(fl.likelihood.shape, THIN_HALO):
            whole = thin_votes(fl.likelihood[region], st[region], dp[region])[core]
            assert np.array_equal(ridge_image(fl.likelihood[region], st[region], dp[region], floor=0.0, sigma=0.0,
                                              dip_smoothing=0, core=core), whole)


def test_a_bad_core_of_the_ridges_is_an_input_error(scanned_cube):
    from seismo3d.seismic.faults.surfaces.ridges import ridge_image, ridges

    _, fl, _, _ = scanned_cube
    like, st, dp = fl.likelihood, fl.strike_deg, fl.dip_deg
    for bad in [(slice(0, 4),), (slice(0, 4), slice(0, 4), slice(0, 4)), (slice(0, 4, 2), slice(0, 4)),
                (slice(4, 4), slice(0, 4)), (slice(0, 41), slice(0, 4)), (slice(-4, None), slice(0, 4)),
                (slice(0, 4.0), slice(0, 4)), [slice(0, 4), slice(0, 4)], (0, slice(0, 4)), "core"]:
        with pytest.raises(InputError, match="core"):
            ridges(like, st, dp, 0.3, core=bad)
    with pytest.raises(InputError, match="core"):  # a 2D section has no core
        ridge_image(like[:, 0], st[:, 0], dp[:, 0], core=(slice(0, 4), slice(0, 1)))


@pytest.mark.slow
def test_ridge_block_is_the_whole_regions_ridges_and_slopes_at_its_core(scanned_cube):
    """A block of the ridges step (dead traces and a mute in the cube) returns at its core what the region's
    functions return cropped there: the slopes, the live likelihood, the mask near dead samples and the seed
    candidates of the whole region's ridges."""
    from seismo3d.seismic.amplitudes import dead_samples, fill_values, near_dead_samples
    from seismo3d.seismic.attributes import structure_tensor_slopes
    from seismo3d.seismic.blocks.apply import BlockPlace
    from seismo3d.seismic.faults import FaultTracingOptions
    from seismo3d.seismic.faults.surfaces.ridges import RIDGE_HALO, amplitude_halo, ridge_block, ridges

    cube, fl, _, _ = scanned_cube
    cube = cube.astype(np.float32)
    cube[3:9, 20:24] = 0.0  # dead traces
    cube[:, :, :6] = 0.0  # a mute
    opt = FaultTracingOptions()
    lo, hi = float(cube.min()), float(cube.max())
    fill = np.union1d(fill_values(cube, lo, hi, options=opt.dead), [0.0]).astype(np.float32)
    halo = amplitude_halo(opt)
    n_near = 0
    for i0, i1, j0, j1 in _BLOCKS:
        n0, n1 = cube.shape[:2]
        a0, a1, b0, b1 = max(i0 - halo, 0), min(i1 + halo, n0), max(j0 - halo, 0), min(j1 + halo, n1)
        rows, cols = slice(a0, a1), slice(b0, b1)
        place = BlockPlace((i0, i1, j0, j1), (a0, a1, b0, b1))
        like = fl.likelihood.copy()
        out = ridge_block(place, cube[rows, cols], like, fl.strike_deg, fl.dip_deg, fill, lo, hi, cube.shape, opt)
        # the reference: the region's functions, cropped to the core
        r = (slice(max(i0 - RIDGE_HALO, 0), min(i1 + RIDGE_HALO, cube.shape[0])),
             slice(max(j0 - RIDGE_HALO, 0), min(j1 + RIDGE_HALO, cube.shape[1])))
        core = (slice(i0 - r[0].start, i1 - r[0].start), slice(j0 - r[1].start, j1 - r[1].start))
        near = near_dead_samples(dead_samples(cube[rows, cols], fill, lo, hi, options=opt.dead), options=opt.dead)
        near = near[r[0].start - a0:r[0].stop - a0, r[1].start - b0:r[1].stop - b0]
        live = np.where(near, 0, fl.likelihood[r]).astype(np.float32)
        ridge = ridges(live, fl.strike_deg[r], fl.dip_deg[r], opt.voting.seed_threshold)[core]
        points = np.argwhere(ridge > opt.voting.seed_threshold)
        assert np.array_equal(out.arrays["likelihood"], live[core])
        assert np.array_equal(out.arrays["near"].view(bool), near[core])
        assert np.array_equal(np.stack([out.arrays["slope_inline"], out.arrays["slope_xline"]]),
                              structure_tensor_slopes(cube, float32=True)[:, i0:i1, j0:j1])
        assert np.array_equal(out.lists["points"], points + [i0, j0, 0])
        assert np.array_equal(out.lists["values"], ridge[tuple(points.T)])
        n_near += np.count_nonzero(near[core])
    assert n_near > 0
