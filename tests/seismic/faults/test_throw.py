"""Fault throw by registration (seismo3d.seismic.faults.throw) against the ground truth of synthetic cubes and sections.

Issue 3, Must show: "throw within 1 sample (median absolute error) for faults with throw >= 3 samples" on 128^3
synthetic cubes with noise, seeds 0-4, through the whole detection chain; plus the same measured on the TRUE fault
voxels (throw accuracy independent of detection) and on 2D sections. Errors are against the *signed* true throw
(positive for normal faults, negative for reverse ones), so a wrong hanging-wall side counts as an error.

Per-fault numbers are printed (``pytest -s``).

Limits: the measured worst over the seeds / cases each test runs, times 1.5 (the inputs are generated with fixed seeds,
so the margin covers float and library differences, and a 2x regression fails), written beside each assertion as
"measured X, limit Y". Where the issue set a target (issue 3: median within 1 sample), it is asserted too.
"""

import dataclasses
import logging
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial import cKDTree

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import (
    FaultThrow, ThrowOptions, fault_likelihood, fault_skins, fault_throw, fault_throws, structure_tensor_orientation,
    thin_faults,
)
from seismo3d.seismic.faults.throw import hanging_wall_normals

SEEDS = range(5)
TOL = 2.0  # voxels: a detected point is compared with the nearest true fault voxel within this distance


def _signed_truth(syn):
    """Signed true throw at the fault voxels (+ normal, - reverse), the voxel coordinates and their fault ids."""
    pts = np.argwhere(syn.fault_labels > 0)
    ids = syn.fault_labels[tuple(pts.T)].astype(np.int64)
    sign = np.array([0] + [1.0 if f.kind == "normal" else -1.0 for f in syn.faults])
    return pts, ids, syn.fault_throw[tuple(pts.T)] * sign[ids]


def _true_faults(syn):
    """The true fault voxels of each fault as Fault-like inputs, with the true plane normal."""
    out = []
    for f in syn.faults:
        pts = np.argwhere(syn.fault_labels == f.id)
        out.append(SimpleNamespace(id=f.id, points=pts, normals=np.tile(f.normal, (len(pts), 1))))
    return out


def _errors_detected(syn, faults, results):
    """Per detected fault: (matched true id, |est - true| at points near voxels of that fault with |throw| >= 3).

    A detected fault is matched to the true fault holding the majority of the labelled voxels within TOL of its
    points; unmatched faults (no labelled voxel within TOL) are left out.
    """
    pts, ids, truth = _signed_truth(syn)
    tree = cKDTree(pts)
    out = []
    for f, r in zip(faults, results):
        d, j = tree.query(f.points, k=1, distance_upper_bound=TOL)
        near = np.isfinite(d)
        if not near.any():
            continue
        tid = int(np.bincount(ids[j[near]]).argmax())
        own = cKDTree(pts[ids == tid])
        d2, j2 = own.query(f.points, k=1, distance_upper_bound=TOL)
        ok = np.isfinite(d2)
        true = truth[ids == tid][j2[ok]]
        est = r.throw[ok].astype(np.float64)
        sel = np.abs(true) >= 3.0
        err = np.abs(est[sel] - true[sel])
        out.append((f, tid, np.where(np.isfinite(err), err, np.inf)))  # unmeasured points count as misses
    return out


@pytest.fixture(params=SEEDS, ids=lambda s: f"seed{s}")
def chain(request, traced_cube):
    """A 128^3 synthetic cube (noise 0.1), its detected faults and its reflector orientation (traced once per session,
    shared with tests/seismic/faults/surfaces/test_ridges.py)."""
    c = traced_cube(request.param)
    return request.param, c.syn, c.faults, c.orientation


@pytest.mark.slow
def test_detected_faults_throw_within_one_sample(chain):
    seed, syn, faults, orientation = chain
    results = fault_throws(syn.cube, faults, orientation=orientation)
    assert len(results) == len(faults) and all(isinstance(r, FaultThrow) for r in results)
    matched = _errors_detected(syn, faults, results)
    pooled = np.concatenate([e for _, _, e in matched])
    for f, tid, e in matched:
        r = results[f.id - 1]
        print(f"seed {seed} detected fault {f.id} ({f.size} pts) -> true {tid}: {e.size} pts, median |err| "
              f"{np.median(e) if e.size else np.nan:.2f} samples, median throw {r.median_throw:+.2f}, registered "
              f"{r.registered.mean():.2f}, fitness {r.fitness:.2f}")
    print(f"seed {seed} pooled median |err| {np.median(pooled):.3f} samples over {pooled.size} points")
    # every true fault is found and measured over most of its length
    assert {tid for _, tid, e in matched if e.size > 5000} == {f.id for f in syn.faults}
    assert pooled.size > 0.6 * np.count_nonzero(syn.fault_labels)
    assert np.median(pooled) <= 1.0  # Must show (issue 3's target)
    assert np.median(pooled) <= 0.12  # measured 0.033-0.079 over seeds 0-4, limit 1.5x the worst
    for f, tid, e in matched:
        if e.size >= 5000:  # the main faults, each on its own
            assert np.median(e) <= 0.3, (f.id, tid)  # measured 0.012-0.20 (seed 0 fault 3), limit 1.5x the worst
            assert results[f.id - 1].registered.mean() > 0.5  # the registration engine did the work, not the fallback
            assert results[f.id - 1].fitness > 0.6


@pytest.mark.slow
def test_true_fault_voxels_throw(chain):
    """Throw measured on the labelled fault voxels: accuracy independent of fault detection."""
    seed, syn, _, orientation = chain
    faults = _true_faults(syn)
    results = fault_throws(syn.cube, faults, orientation=orientation)
    pooled = []
    for f, tf, r in zip(faults, syn.faults, results):
        true = syn.fault_throw[tuple(f.points.T)] * (1.0 if tf.kind == "normal" else -1.0)
        err = np.abs(r.throw - true)
        assert np.isfinite(err).mean() > 0.95
        err = np.where(np.isfinite(err), err, np.inf)
        pooled.append(err)
        print(f"seed {seed} true fault {tf.id} ({tf.kind}, throw {np.median(true):+.2f}): median |err| "
              f"{np.median(err):.3f}, 90th pct {np.percentile(err, 90):.2f} samples, "
              f"registered {r.registered.mean():.2f}")
        assert np.median(err) <= 0.27  # measured 0.017-0.174 (seed 0 fault 3), limit 1.5x the worst
        assert np.sign(r.median_throw) == np.sign(np.median(true))  # hanging-wall side and sign convention
        assert r.fault_id == tf.id and r.throw.shape == (len(f.points),) and r.throw.dtype == np.float32
    pooled = np.concatenate(pooled)
    print(f"seed {seed} true voxels pooled median |err| {np.median(pooled):.3f}")
    assert np.median(pooled) <= 0.13  # measured 0.028-0.083, limit 1.5x the worst


@pytest.mark.slow
def test_bare_point_array_estimates_normals():
    """A plain (n, 3) array of fault points is accepted; its normals come from PCA."""
    syn = synthetic_cube((64, 64, 96), n_faults=1, seed=2, noise=0.1)
    pts = np.argwhere(syn.fault_labels == 1)
    res = fault_throw(syn.cube, pts)
    true = syn.fault_throw[tuple(pts.T)] * (1.0 if syn.faults[0].kind == "normal" else -1.0)
    assert res.fault_id == 0
    assert np.nanmedian(np.abs(res.throw - true)) <= 0.19  # measured 0.123, limit 1.5x


@pytest.mark.slow
def test_large_throw_no_cycle_skip():
    """Throws of 8-13 samples, beyond a reflector period (~6.7 samples): the correlation start avoids cycle skipping."""
    syn = synthetic_cube((96, 96, 128), seed=1, noise=0.1, max_throw=16)
    faults = _true_faults(syn)
    results = fault_throws(syn.cube, faults)
    big = 0
    for f, tf, r in zip(faults, syn.faults, results):
        true = syn.fault_throw[tuple(f.points.T)] * (1.0 if tf.kind == "normal" else -1.0)
        big += np.median(np.abs(true)) > 10
        assert np.nanmedian(np.abs(r.throw - true)) <= 0.12  # measured 0.042-0.074, limit 1.5x the worst
    assert big >= 1  # the case exercised: one fault throws 13 samples


# --- 2D sections ----------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(6))
def test_sections(seed):
    """2D sections: the true fault curves and the detected faults (correlation shift + parabolic refinement)."""
    syn = synthetic_cube((192, 128), seed=seed, noise=0.1)
    orientation = structure_tensor_orientation(syn.cube)
    # true fault voxels as bare (n, 2) point arrays
    results = fault_throws(syn.cube, [np.argwhere(syn.fault_labels == f.id) for f in syn.faults],
                           orientation=orientation)
    for tf, r in zip(syn.faults, results):
        true = tf.throw_samples * (1.0 if tf.kind == "normal" else -1.0)
        print(f"section seed {seed} true fault {tf.id}: throw {true:+.2f}, estimate {r.median_throw:+.2f}")
        assert abs(r.median_throw - true) <= 0.37  # measured 0.002-0.247 (seed 3), limit 1.5x the worst
        assert not r.registered.any() and r.n_points_used == 0  # 2D: no registration, correlation only
    # detected faults
    fl = fault_likelihood(syn.cube)
    thin = thin_faults(fl.likelihood, fl.strike_deg, fl.dip_deg)
    lower = float(np.min(thin[thin > 0]))  # every thinned sample, linked into fault skins
    faults = fault_skins(thin, fl.strike_deg, fl.dip_deg, lower=lower, upper=lower)
    matched = _errors_detected(syn, faults, fault_throws(syn.cube, faults, orientation=orientation))
    pooled = np.concatenate([e for _, _, e in matched])
    print(f"section seed {seed}: detected pooled median |err| {np.median(pooled):.3f} over {pooled.size} points")
    assert pooled.size > 0.5 * np.count_nonzero(syn.fault_labels)
    assert np.median(pooled) <= 0.18  # measured 0.022-0.118 over seeds 0-5, limit 1.5x the worst


@pytest.mark.parametrize("seed", [0, 3, 5])
def test_section_profile_in_windows(seed):
    """A section's throw profile from windows down the fault (48 samples, so that the 128-sample faults span several):
    the shifts chosen together stay on the true throw, without the cycle skip of a reflector period."""
    syn = synthetic_cube((192, 128), seed=seed, noise=0.1)
    faults = [np.argwhere(syn.fault_labels == f.id) for f in syn.faults]
    results = fault_throws(syn.cube, faults, profile_window=48)
    for tf, r in zip(syn.faults, results):
        true = tf.throw_samples * (1.0 if tf.kind == "normal" else -1.0)
        print(f"section seed {seed} true fault {tf.id}: throw {true:+.2f}, profile median {r.median_throw:+.2f}, "
              f"{r.n_patches_measured} windows, median error {np.nanmedian(np.abs(r.throw - true)):.2f}, "
              f"worst point {np.nanmax(np.abs(r.throw - true)):.2f}")
        assert r.n_patches_measured >= 5
        err = np.abs(r.throw - true)
        # measured: median 0.01-0.39 and worst 0.18-1.10 (seed 5 fault 1, whose deepest windows cross another fault)
        assert np.nanmedian(err) <= 0.5 and np.nanmax(err) <= 1.5



@pytest.mark.parametrize("seed", [1, 2])
def test_section_throw_bounded_by_the_fault_length(seed):
    """A 2D fault searches throws up to a tenth of its extent (profile_max_throw_per_length, displacement-length
    scaling): a 36-sample piece of a fault throwing 4.3-7.6 samples searches 3 and does not claim the throw; with a
    third of it searched the piece reads its true throw (measured within 0.19 sample)."""
    syn = synthetic_cube((192, 128), seed=seed, noise=0.1)
    for tf in syn.faults:
        points = np.argwhere(syn.fault_labels == tf.id)
        piece = points[(points[:, 1] >= 40) & (points[:, 1] < 76)]  # 36 samples of a fault spanning all 128
        true = tf.throw_samples * (1.0 if tf.kind == "normal" else -1.0)
        bounded = fault_throws(syn.cube, [piece])[0].median_throw
        loose = fault_throws(syn.cube, [piece], profile_max_throw_per_length=1 / 3)[0].median_throw
        assert abs(bounded) <= 3 + 0.5 and abs(bounded - true) >= 2.0, (tf.id, true, bounded)
        assert abs(loose - true) <= 0.3, (tf.id, true, loose)  # measured 0.02-0.19

@pytest.mark.slow
@pytest.mark.parametrize("seed", [2, 3])
def test_section_throw_beyond_20_samples_on_a_tall_fault(seed):
    """A 2D fault searches up to a tenth of its extent and half the profile window (32 samples), not 20: generated
    faults 224-383 samples tall throwing 20.8-28.0 samples read within 0.1 sample of it at the median, within a sample
    everywhere; with the former bound (20 samples, a third of the window) they read a cycle skip or the bound (6.64
    for 27.95, 1.81 for 21.35, -20.00 for -20.83). Penobscot crossline 1155's large fault read 51 ms near 1500 ms
    under it, against 104-108 ms by hand (tests/seismic/faults/test_pipeline.py)."""
    syn = synthetic_cube((192, 384), seed=seed, noise=0.1, max_throw=30, n_faults=2)
    faults = [np.argwhere(syn.fault_labels == f.id) for f in syn.faults]
    tall = [k for k, tf in enumerate(syn.faults) if tf.throw_samples > 20]
    assert tall  # the case exercised: seed 2 throws 27.95 and 21.35 samples, seed 3 -20.83
    now, before = fault_throws(syn.cube, faults), fault_throws(syn.cube, faults, max_throw=20, profile_max_shift=1 / 3)
    for k in tall:
        true = syn.faults[k].throw_samples * (1.0 if syn.faults[k].kind == "normal" else -1.0)
        assert abs(now[k].median_throw - true) <= 0.1  # measured 0.01-0.05
        assert np.nanmax(np.abs(now[k].throw - true)) <= 1.0  # measured 0.20-0.65
        assert abs(before[k].median_throw - true) >= 0.5, (true, before[k].median_throw)


def test_sign_convention_normal_and_reverse():
    """Positive throw = hanging wall down (normal fault), negative = hanging wall up (reverse fault)."""
    for frac, sign in ((0.0, 1.0), (1.0, -1.0)):
        syn = synthetic_cube((128, 96), n_faults=2, seed=11, noise=0.05, reverse_fraction=frac)
        for tf in syn.faults:
            r = fault_throw(syn.cube, np.argwhere(syn.fault_labels == tf.id))
            assert np.sign(r.median_throw) == sign
            assert abs(r.median_throw - sign * tf.throw_samples) <= 0.3  # measured 0.015-0.196, limit 1.5x


# --- edge cases and bad input ---------------------------------------------------------------------------------------

def test_unmeasurable_fault_gives_nan_not_error():
    """A fault too short to correlate gives NaN throw (and NaN summary values), without raising."""
    syn = synthetic_cube((64, 64), n_faults=1, seed=0, noise=0.1)
    pts = np.argwhere(syn.fault_labels == 1)
    short = pts[np.argsort(pts[:, 1])[:6]]  # 6 samples of the fault: shorter than the correlation window
    res = fault_throw(syn.cube, short)
    assert np.all(np.isnan(res.throw)) and np.isnan(res.median_throw) and np.isnan(res.fitness)
    assert not res.registered.any() and res.n_points_used == 0


def test_empty_fault_list():
    syn = synthetic_cube((32, 32), n_faults=1, seed=0)
    assert fault_throws(syn.cube, []) == []


def test_progress_says_the_cubes_reflector_slopes_are_prepared_before_the_first_fault(caplog):
    """With ``progress`` (a log: stderr is not a terminal under pytest), an in-memory cube's throws first say that
    its structure tensor is under way where the faults are, with a line per part of it, then count the faults; a
    section has no such preparation."""
    syn = synthetic_cube((32, 32, 48), n_faults=1, seed=2)
    pts = np.argwhere(syn.fault_labels == 1)
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        fault_throws(syn.cube, [pts], progress=True)
    assert caplog.messages == ["throw: 0/1 fault, reflector slopes: the structure tensor where the faults are",
                               "throw: 1/1 part, structure tensor", "throw: 1/1 fault"]
    caplog.clear()
    section = synthetic_cube((64, 48), n_faults=1, seed=2)
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        fault_throws(section.cube, [np.argwhere(section.fault_labels == 1)], progress=True)
    assert caplog.messages == ["throw: 1/1 fault"]


def _fields(result: FaultThrow) -> list:
    """Every field of a throw as bytes (NaN equal to NaN, -0.0 apart from 0.0)."""
    return [np.asarray(getattr(result, f.name)).tobytes() for f in dataclasses.fields(result)]


@pytest.mark.slow
def test_the_patches_on_threads_give_the_throws_of_one_thread_bit_for_bit():
    """The patches of an in-memory cube measured on numba's thread count of threads (2) give the throws measured in
    the calling thread (1), every field the same bits, in the faults' order."""
    import numba

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("needs NUMBA_NUM_THREADS >= 2")
    syn = synthetic_cube((64, 64, 64), n_faults=2, seed=3, noise=0.1)
    faults = [np.argwhere(syn.fault_labels == k) for k in (2, 1)]
    before = numba.get_num_threads()
    try:
        runs = []
        for n in (1, 2):
            numba.set_num_threads(n)
            runs.append(fault_throws(syn.cube, faults, patch_traces=12.0))
    finally:
        numba.set_num_threads(before)
    assert sum(r.n_patches_measured for r in runs[0]) >= 4
    assert [_fields(r) for r in runs[0]] == [_fields(r) for r in runs[1]]


@pytest.mark.slow
def test_an_interrupt_while_the_patches_run_on_threads_stops_them(monkeypatch):
    """A Ctrl-C (KeyboardInterrupt) in the calling thread while the patches are measured on threads reaches the
    caller, the patches not started are not measured, and no thread of the pool is left."""
    import threading

    import numba

    from seismo3d.seismic.faults import throw as throw_module

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("needs NUMBA_NUM_THREADS >= 2")
    syn = synthetic_cube((64, 64, 64), n_faults=2, seed=3, noise=0.1)
    faults = [np.argwhere(syn.fault_labels == k) for k in (2, 1)]
    measured, measure = [], throw_module._measure_patch

    def slow(*args):
        measured.append(1)
        return measure(*args)

    def interrupted(*args, **kwargs):  # the calling thread, as it assembles the first fault
        raise KeyboardInterrupt

    monkeypatch.setattr(throw_module, "_measure_patch", slow)
    monkeypatch.setattr(throw_module, "_measure", interrupted)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(2)
        with pytest.raises(KeyboardInterrupt):
            fault_throws(syn.cube, faults, patch_traces=4.0)
    finally:
        numba.set_num_threads(before)
    assert len(measured) < sum(len(throw_module._fault_setup(syn.cube.shape, f, ThrowOptions(patch_traces=4.0))
                                   .patches) for f in faults)
    assert not [t for t in threading.enumerate() if t.name.startswith("seismo3d-throw")]


@pytest.mark.parametrize("kwargs, match", [
    ({"max_throw": 40}, "max_throw"),
    ({"max_throw": 0}, "max_throw"),
    ({"side_traces": (3, 2)}, "side_traces"),
    ({"side_traces": 2}, "side_traces"),
    ({"patch_traces": -1}, "patch_traces"),
    ({"profile_window": 20}, "profile_window"),
    ({"profile_step": 0}, "profile_step"),
    ({"profile_smoothness": -1.0}, "profile_smoothness"),
    ({"profile_max_throw_per_length": 0.0}, "profile_max_throw_per_length"),
    ({"profile_max_shift": 0.0}, "profile_max_shift"),
    ({"profile_max_shift": 1.5}, "profile_max_shift"),
])
def test_bad_options(kwargs, match):
    syn = synthetic_cube((64, 64), n_faults=1, seed=0)
    with pytest.raises(InputError, match=match):
        fault_throw(syn.cube, np.argwhere(syn.fault_labels == 1), **kwargs)


def test_options_object_and_keywords_agree():
    syn = synthetic_cube((64, 64), n_faults=1, seed=3, noise=0.0)
    pts = np.argwhere(syn.fault_labels == 1)
    a = fault_throw(syn.cube, pts, options=ThrowOptions(side_traces=(3, 7), max_throw=8))
    b = fault_throw(syn.cube, pts, side_traces=(3, 7), max_throw=8)
    np.testing.assert_array_equal(a.throw, b.throw)
    with pytest.raises(InputError, match="ThrowOptions"):
        fault_throw(syn.cube, pts, options={"max_throw": 8})


def test_hanging_wall_normals_share_one_side():
    n = np.tile([np.sin(np.radians(70.0)), 0.0, np.cos(np.radians(70.0))], (9, 1))
    flip = np.where(np.arange(9) % 2 == 0, -1.0, 1.0)[:, None]
    out = hanging_wall_normals(n * flip)
    np.testing.assert_allclose(out, np.tile(-n[0], (9, 1)))  # all upward, into the hanging wall


def test_bad_faults_and_orientation():
    syn = synthetic_cube((64, 64), n_faults=1, seed=0)
    pts = np.argwhere(syn.fault_labels == 1)
    with pytest.raises(InputError, match="outside"):
        fault_throw(syn.cube, pts + [100, 0])
    with pytest.raises(InputError, match=r"\(N, 2\)"):
        fault_throw(syn.cube, np.zeros((10, 3)))  # 3D points for a 2D section
    with pytest.raises(InputError, match="Fault"):
        fault_throw(syn.cube, "fault")
    with pytest.raises(InputError, match="one normal per point"):
        fault_throw(syn.cube, SimpleNamespace(points=pts, normals=np.ones((3, 2))))
    other = structure_tensor_orientation(syn.cube[:32])
    with pytest.raises(InputError, match="orientation"):
        fault_throw(syn.cube, pts, orientation=other)
    bad = syn.cube.copy()
    bad[3, 3] = np.nan
    with pytest.raises(InputError, match="NaN"):
        fault_throw(bad, pts)


# --- the step at a fault against a flexure --------------------------------------------------------------------------

def layered_section(shift, *, n_traces=192, n_samples=160, seed=0, noise=0.05):
    """A section of flat layers (random reflectivity, Ricker 0.15 cycles/sample) lying ``shift(x)`` samples deeper at
    trace x: a fault for a jump of ``shift``, a flexure for a smooth ramp. (n_traces, n_samples) float32."""
    from seismo3d.data.synthetic import ricker

    rng = np.random.default_rng(seed)
    pad = 40
    reflectivity = rng.standard_normal(n_samples + 2 * pad) * (rng.random(n_samples + 2 * pad) < 0.35)
    trace = np.convolve(reflectivity, ricker(0.15), mode="same")
    z = np.arange(n_samples, dtype=np.float64)
    out = np.stack([np.interp(z - shift(x) + pad, np.arange(trace.size), trace) for x in range(n_traces)])
    out += noise * out.std() * rng.standard_normal(out.shape)
    return out.astype(np.float32)


def small_fault(throw, x0=96, dip=0.1):
    """Layers dipping ``dip`` samples per trace, offset by ``throw`` samples from trace ``x0`` on."""
    return lambda x: dip * x + throw * (x >= x0)


def flexure(relief, half_width, x0=96, dip=0.1):
    """Layers dipping ``dip`` samples per trace, bent down by ``relief`` samples over about ``2 half_width`` traces
    around ``x0`` (a tanh monocline: a drape or drag fold, no fault)."""
    return lambda x: dip * x + relief * 0.5 * (1.0 + np.tanh((x - x0) / half_width))


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_step_of_a_small_fault_is_its_throw_and_of_a_flexure_a_small_part_of_it(seed):
    """A 2D fault's step (the lag across its zone less the dip of the traces right beside it) is its throw: 2-3
    samples measured within 0.06; a flexure's throw, read from layers carried along the flatter dip farther out, is
    its relief (3.1-3.9 samples) while its step is at most a fifth of that (measured 0.01-0.21)."""
    line = np.column_stack([np.full(140, 96), np.arange(10, 150)])
    for throw in (2.0, 3.0):
        r = fault_throws(layered_section(small_fault(throw), seed=seed), [line])[0]
        assert abs(r.median_throw - throw) <= 0.1 and abs(r.step - throw) <= 0.15, (throw, r.median_throw, r.step)
    for relief, half_width in ((8.0, 6.0), (6.0, 4.0), (4.0, 3.0)):
        r = fault_throws(layered_section(flexure(relief, half_width), seed=seed), [line])[0]
        assert abs(r.median_throw) >= 2.5 and abs(r.step) <= 0.25 * abs(r.median_throw), (relief, r.median_throw,
                                                                                           r.step)
    with pytest.raises(InputError, match="step_traces"):
        fault_throws(layered_section(small_fault(2.0), seed=seed), [line], step_traces=0)
