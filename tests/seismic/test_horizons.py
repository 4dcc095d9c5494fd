"""Horizon tracking: picks, tracking against ground truth (generator, people's picks), the peer, I/O, bad input."""

import dataclasses
import functools
import warnings

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import (
    Horizon, autotrack, fill_horizon, horizon_errors, reflector_picks, trace_faults, track_horizon, write_horizon_text,
)


def test_reflector_picks_peaks_troughs_plateaus_and_zero_crossings():
    t = np.arange(200.0)
    trace = np.cos(2 * np.pi * (t - 10.3) / 20.0)  # peaks at 10.3 + 20 k, troughs at 20.3 + 20 k
    times, offsets = reflector_picks(trace[None, :], polarity="peak")
    assert offsets.tolist() == [0, len(times)]
    np.testing.assert_allclose(times, 10.3 + 20 * np.arange(len(times)), atol=0.02)
    troughs, _ = reflector_picks(trace[None, :], polarity="trough")
    np.testing.assert_allclose(troughs, 20.3 + 20 * np.arange(len(troughs)), atol=0.02)
    rising, _ = reflector_picks(trace[None, :], polarity="zero_rising")  # - above, + below: 5.3 + 20 k
    np.testing.assert_allclose(rising, 5.3 + 20 * np.arange(len(rising)), atol=0.1)
    clipped = np.clip(2 * trace, -1, 1)  # 8-bit style plateaus: the pick is the plateau's centre
    plateau, _ = reflector_picks(clipped[None, :], polarity="peak")
    np.testing.assert_allclose(plateau, 10.3 + 20 * np.arange(len(plateau)), atol=0.5)


def _seed_on(ref, i0=None):
    if ref.ndim == 1:
        ok = np.nonzero(np.isfinite(ref))[0]
        j0 = int(ok[np.argmin(np.abs(ok - ref.size // 2))])
        return (j0, float(ref[j0]))
    ok = np.nonzero(np.isfinite(ref[i0]))[0]
    j0 = int(ok[np.argmin(np.abs(ok - ref.shape[1] // 2))])
    return (i0, j0, float(ref[i0, j0]))


@pytest.mark.parametrize("seed", [0, 1])
def test_track_2d_section_without_faults_follows_true_horizons(seed):
    syn = synthetic_cube((160, 128), n_faults=0, seed=seed, noise=0.2)
    for k in range(syn.horizons.shape[0]):
        ref = syn.horizons[k]
        pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
        hz = track_horizon(syn.cube, _seed_on(ref), polarity=pol)
        e = horizon_errors(hz.times, ref)
        assert e["median_abs"] <= 0.3, (k, e)
        assert e["within_2"] >= 0.97, (k, e)


@functools.lru_cache(maxsize=None)  # traced once per test session: several tests read these cubes, none modify them
def _faulted(seed):
    syn = synthetic_cube((64, 64, 96), n_faults=3, seed=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        faults = trace_faults(syn.cube, progress=False)
    return syn, faults


@pytest.fixture(scope="module")
def faulted():
    return _faulted(0)


# the synthetic section of benchmarks/horizons.py prints these horizons (point-to-plane, cube seeds 0-2): all 18 at
# medians 0.05-0.16 samples, 57-98 % of each horizon's traces within 2 samples. Before the crossing test used each
# fault's local plane, cube 0 horizon 1 (seeded where two faults cross) was 5.4 samples off.
@pytest.mark.parametrize("cube_seed", [0, 1, 2])
def test_track_3d_across_faults_median_error_within_one_sample(cube_seed):
    syn, faults = _faulted(cube_seed)
    medians, within_2 = [], []
    for k in range(syn.horizons.shape[0]):
        ref = syn.horizons[k]
        pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
        hz = track_horizon(syn.cube, _seed_on(ref, syn.shape[0] // 2), polarity=pol, faults=faults, features=None)
        e = horizon_errors(hz.times, ref)
        medians.append(e["median_abs"])
        within_2.append(e["within_2"])
    assert np.all(np.isfinite(medians)) and np.max(medians) <= 1.0, medians
    assert np.mean(within_2) >= 0.80, within_2


def test_fault_throw_makes_the_jump(faulted):
    # the horizon that crosses faults: without fault input the tracker follows the wrong reflector
    syn, faults = faulted
    k = 2
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    seed = _seed_on(ref, syn.shape[0] // 2)
    with_faults = horizon_errors(track_horizon(syn.cube, seed, polarity=pol, faults=faults, features=None).times, ref)
    without = horizon_errors(track_horizon(syn.cube, seed, polarity=pol, features=None).times, ref)
    assert with_faults["median_abs"] <= 1.0
    assert without["median_abs"] > 3.0


def test_plain_autotracker_on_a_clean_section_and_its_bfs_in_3d():
    syn = synthetic_cube((16, 40, 64), n_faults=0, seed=3, noise=0.0)
    k = 1
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    hz = autotrack(syn.cube, _seed_on(ref, 8), polarity=pol)
    assert hz.coverage == 1.0
    assert horizon_errors(hz.times, ref)["median_abs"] <= 0.2


def test_low_confidence_picks_are_empty_and_fill_is_explicit():
    syn = synthetic_cube((120, 96), n_faults=0, seed=2, noise=0.1)
    cube = syn.cube.copy()
    cube[60:64] = np.random.default_rng(0).standard_normal((4, cube.shape[1])).astype(np.float32)  # noise traces
    k = 2
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    hz = track_horizon(cube, (30, float(ref[30])), polarity=pol, min_confidence=0.6)
    assert np.isnan(hz.times[60:64]).sum() >= 2  # the noise traces are not guessed
    assert np.isfinite(hz.times[70:]).mean() > 0.9  # ... and tracking goes on beyond them
    filled = fill_horizon(hz)
    assert np.isfinite(filled.times[1:-1]).all()
    assert np.isnan(hz.times[60:64]).sum() >= 2  # the input is not modified
    gap = np.isnan(hz.times)
    assert np.nanmax(np.abs(filled.times[gap] - ref[gap])) < 2.0


def test_write_horizon_text_and_surface(tmp_path):
    times = np.array([[10.0, 10.5, np.nan], [11.0, 11.5, 12.0]], np.float32)
    hz = Horizon(times, np.ones_like(times), "peak", np.zeros((1, 3)))
    out = tmp_path / "h.txt"
    n = write_horizon_text(out, hz, inlines=[100, 101], xlines=[7, 8, 9], samples=4.0 * np.arange(20) + 4.0)
    rows = np.loadtxt(out, comments="#")
    assert n == 5 and rows.shape == (5, 3)
    np.testing.assert_allclose(rows[0], [100, 7, 44.0])
    np.testing.assert_allclose(rows[1], [100, 8, 46.0])
    from seismo3d.viz import horizon_surface

    mesh = horizon_surface(hz, inlines=[100, 101], xlines=[7, 8, 9])
    assert mesh.n_points == 5 and mesh.n_cells == 1  # one quad: the other has an empty corner
    np.testing.assert_allclose(mesh.points[:, 2], -times[np.isfinite(times)])


def test_bad_input_gives_clear_errors():
    syn = synthetic_cube((20, 20, 64), n_faults=0, seed=0)
    with pytest.raises(InputError, match="outside the data"):
        track_horizon(syn.cube, (25, 3, 30.0))
    with pytest.raises(InputError, match="outside the data"):
        track_horizon(syn.cube, (5, 3, 64.0))
    dead = syn.cube.copy()
    dead[5, 3] = 0.0
    with pytest.raises(InputError, match="dead trace"):
        track_horizon(dead, (5, 3, 30.0))
    with pytest.raises(InputError, match="polarity"):
        track_horizon(syn.cube, (5, 3, 30.0), polarity="max")
    with pytest.raises(InputError, match="seeds must be"):
        track_horizon(syn.cube, (5, 30.0))
    with pytest.raises(InputError, match="same shape"):
        horizon_errors(np.zeros(3), np.zeros(4))


def test_gap_closing_refills_a_hole_and_leaves_noise_empty():
    from seismo3d.seismic.horizons import _POLARITY_CODE, _close_gaps, _FaultIndex, _Options

    syn = synthetic_cube((24, 40, 64), n_faults=0, seed=4, noise=0.05)
    k = 2
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    hz = track_horizon(syn.cube, _seed_on(syn.horizons[k], 12), polarity=pol, features=None)
    assert np.isfinite(hz.times).all()
    opt = _Options(model="rigid", half_traces=10, half_samples=20.0, step=4, snap=3.0, min_confidence=0.3,
                   max_throw=10, min_fitness=0.3)
    times, conf = hz.times.astype(np.float64), hz.confidence.astype(np.float64)
    holed = times.copy()
    holed[8:14, 10:18] = np.nan
    _close_gaps(syn.cube, _POLARITY_CODE[pol], holed, conf.copy(), opt, _FaultIndex.from_interpretation(None, 3))
    np.testing.assert_allclose(holed[8:14, 10:18], times[8:14, 10:18], atol=0.5)
    # where the traces hold only noise, nothing correlates at min_confidence 0.6: the hole stays empty (at the
    # default 0.3, chance correlations fill a few noise traces)
    noisy = syn.cube.copy()
    noisy[8:14, 10:18] = np.random.default_rng(1).standard_normal((6, 8, noisy.shape[2])).astype(np.float32)
    holed = times.copy()
    holed[8:14, 10:18] = np.nan
    opt = dataclasses.replace(opt, min_confidence=0.6)
    _close_gaps(noisy, _POLARITY_CODE[pol], holed, conf.copy(), opt, _FaultIndex.from_interpretation(None, 3))
    assert np.isnan(holed[9:13, 12:16]).all()


def _vertical_fault_points(x0, n_y=9, n_t=40):
    """Points of a vertical fault plane at trace x0 (3D index space), normals along +x."""
    y, t = np.meshgrid(np.arange(n_y, dtype=float), np.arange(n_t, dtype=float), indexing="ij")
    pts = np.column_stack([np.full(y.size, float(x0)), y.ravel(), t.ravel()])
    return pts, np.tile([1.0, 0.0, 0.0], (len(pts), 1))


def test_fault_index_adds_up_faults_and_ignores_a_grazing_one():
    from seismo3d.seismic.horizons import _FaultIndex

    p1, n1 = _vertical_fault_points(10.5)
    p2, n2 = _vertical_fault_points(12.5)
    both = _FaultIndex(np.vstack([p1, p2]), np.vstack([n1, n2]), np.r_[np.full(len(p1), 4.0), np.full(len(p2), 6.0)],
                       np.r_[np.zeros(len(p1)), np.ones(len(p2))])
    a, b = np.array([4.0, 4.0, 20.0]), np.array([8.0, 4.0, 20.0])
    assert both.jump(a, b) == 0.0  # no fault between
    a, b = np.array([10.0, 4.0, 20.0]), np.array([13.0, 4.0, 20.0])
    # both faults lie between: +x points into both footwalls, so the horizon moves up by both throws
    assert both.crossings(a, b) == {0: -4.0, 1: -6.0}
    assert both.jump(a, b) == -10.0
    assert both.jump(b, a) == 10.0
    crossed = {0}  # fault 0 already crossed: left out, and fault 1 recorded
    assert both.jump(a, b, crossed) == -6.0 and crossed == {0, 1}
    # a fault that ends beside the step: the step crosses its plane 2 voxels past its last point, which is no crossing
    edge = np.column_stack([np.arange(0.0, 11.0), np.full(11, 4.0), np.full(11, 20.0)])
    ending = _FaultIndex(edge, np.tile([0.0, 0.0, 1.0], (11, 1)), np.full(11, 5.0))
    assert ending.jump(np.array([10.0, 4.0, 18.0]), np.array([14.0, 4.0, 22.0])) == 0.0
    assert ending.jump(np.array([6.0, 4.0, 18.0]), np.array([10.0, 4.0, 22.0])) == -5.0  # through it: into the footwall


def test_fault_index_finds_the_fault_block_of_a_pick():
    # Along a slice, the panels registered around a pick stay within its fault block: the traces a horizon through
    # the pick reaches without crossing a fault (reflector points past a fault belong to another block).
    from seismo3d.seismic.horizons import _FaultIndex

    p1, n1 = _vertical_fault_points(10.5, n_t=30)  # samples 0-29
    p2, n2 = _vertical_fault_points(20.5, n_t=30)
    idx = _FaultIndex(np.vstack([p1, p2]), np.vstack([n1, n2]), np.full(len(p1) + len(p2), 4.0),
                      np.r_[np.zeros(len(p1)), np.ones(len(p2))])
    on_line = lambda x, t: np.array([x, 4.0, t], float)  # noqa: E731 - inline 4 of the index's cube
    assert idx.block(on_line, 40, 14, 15.0, 0.0, 0, 39) == (11, 20)
    assert idx.block(on_line, 40, 4, 15.0, 0.0, 0, 8) == (0, 8)  # no fault within the span
    assert idx.block(on_line, 40, 25, 15.0, 0.0, 15, 35) == (21, 35)
    assert idx.block(on_line, 40, 14, 36.0, 0.0, 0, 39) == (0, 39)  # below the faults' lower ends: one block
    # a dipping horizon (1 sample per trace) meets fault 1 at sample 22.5 and passes below fault 2's end (at 32.5)
    assert idx.block(on_line, 40, 14, 26.0, 1.0, 0, 39) == (11, 39)
    assert _FaultIndex.from_interpretation(None, 3).block(on_line, 40, 14, 15.0, 0.0, 0, 39) == (0, 39)


def test_fault_index_leaves_out_faults_whose_throw_does_not_correlate():
    # A fault whose two sides do not look alike (median throw correlation under 0.5), or has no throw at all, gives
    # no jump: on the clipped Penobscot data such faults carry throws of 5-6 samples where people see none.
    from types import SimpleNamespace

    from seismo3d.seismic.horizons import _FaultIndex

    p1, n1 = _vertical_fault_points(10.5)
    p2, n2 = _vertical_fault_points(20.5)
    p3, n3 = _vertical_fault_points(30.5)
    n = len(p1)
    corr = np.linspace(0.3, 0.9, n)  # median 0.6
    interp = SimpleNamespace(
        faults=[SimpleNamespace(points=p, normals=q) for p, q in ((p1, n1), (p2, n2), (p3, n3))],
        throws=[SimpleNamespace(throw=np.full(n, 4.0), correlation=corr),
                SimpleNamespace(throw=np.full(n, 6.0), correlation=corr - 0.2),  # median 0.4
                SimpleNamespace(throw=np.full(n, np.nan), correlation=np.full(n, np.nan))])
    idx = _FaultIndex.from_interpretation(interp, 3)
    assert set(idx.ids) == {0}
    step = np.array([[10.0, 4.0, 20.0], [11.0, 4.0, 20.0]])
    assert idx.jump(*step) == 4.0  # a vertical fault's hanging wall is its +x side (see the next test)
    assert idx.jump(*(step + [10.0, 0.0, 0.0])) == 0.0
    assert idx.jump(*(step + [20.0, 0.0, 0.0])) == 0.0


def test_fault_index_orients_normals_as_the_throw_was_measured():
    # Normals from strike and dip point to either side of a vertical fault (strike and strike + 180): the Penobscot
    # fault at crossline ~51 had 147 of its 377 normals one way and the rest the other, so the jump changed sign from
    # point to point. The index aligns them as fault_throw does (principal direction; for a vertical fault its +x
    # side is the hanging wall), so every step across gives the same jump.
    from types import SimpleNamespace

    from seismo3d.seismic.horizons import _FaultIndex
    from seismo3d.seismic.throw import _hanging_wall_normals

    p, nrm = _vertical_fault_points(10.5)
    flip = np.where(np.arange(len(p)) % 3 == 0, -1.0, 1.0)[:, None]
    interp = SimpleNamespace(faults=[SimpleNamespace(points=p, normals=nrm * flip)],
                             throws=[SimpleNamespace(throw=np.full(len(p), 4.0), correlation=np.full(len(p), 0.9))])
    idx = _FaultIndex.from_interpretation(interp, 3)
    assert np.allclose(idx.normals, -_hanging_wall_normals(nrm)) and np.allclose(idx.normals, [-1.0, 0.0, 0.0])
    jumps = {idx.jump(np.array([10.0, y, t]), np.array([11.0, y, t])) for y in range(9) for t in range(5, 35, 3)}
    assert jumps == {4.0}  # into the hanging wall: down by the throw, everywhere
    # a fault dipping towards +x (normals into the footwall point down and to -x), some flipped: the footwall stays
    # below the plane
    d = np.radians(70.0)
    down = np.array([-np.sin(d), 0.0, np.cos(d)])
    interp.faults[0].normals = np.tile(down, (len(p), 1)) * flip
    idx = _FaultIndex.from_interpretation(interp, 3)
    assert np.allclose(idx.normals, down)


def test_fault_crossing_uses_the_faults_own_plane_and_knows_a_point_on_it():
    # A traced fault is a set of voxels (positions rounded to the grid). The crossing test takes the least-squares
    # plane of the fault's points near the step. It used to test each point's own plane within a +-3 voxel band, and
    # missed the along-slice step (4 traces) below, which starts 3.5 voxels from this dipping fault and ends 0.3
    # voxel past it.
    from seismo3d.seismic.horizons import _FaultIndex

    d = np.radians(60.0)
    into_footwall = np.array([-np.sin(d), 0.0, np.cos(d)])  # the fault dips towards +x; its footwall is below
    y, t = np.meshgrid(np.arange(0.0, 9.0), np.arange(10.0, 31.0), indexing="ij")
    x = np.round(10.0 + (t - 20.0) / np.tan(d))
    pts = np.column_stack([x.ravel(), y.ravel(), t.ravel()])
    idx = _FaultIndex(pts, np.tile(into_footwall, (len(pts), 1)), np.full(len(pts), 5.0))
    for tz in (19.6, 20.3, 21.0, 21.7):
        x0 = 10.0 + (tz - 20.0) / np.tan(d)  # where the true plane is at this time
        a, b = np.array([x0 + 4.0, 4.0, tz]), np.array([x0 - 0.3 / np.sin(d), 4.0, tz])
        assert idx.jump(a, b) == -5.0 and idx.jump(b, a) == 5.0  # into the footwall: up by the throw
    # a step beside the fault's end is no crossing
    assert idx.jump(np.array([20.0, 4.0, 33.0]), np.array([16.0, 4.0, 33.0])) == 0.0
    # a vertical fault's plane lies on a grid plane, so an inline-to-inline carry lands on it and then leaves it:
    # exactly one of the two steps crosses it
    p, nrm = _vertical_fault_points(30.0)
    vertical = _FaultIndex(p, nrm, np.full(len(p), 4.0))
    for t in (5.0, 20.0, 33.5):
        a, on, b = (np.array([x, 4.0, t]) for x in (29.0, 30.0, 31.0))
        assert sorted((vertical.jump(a, on), vertical.jump(on, b))) == [-4.0, 0.0]  # into the footwall (+x)
        assert sorted((vertical.jump(b, on), vertical.jump(on, a))) == [0.0, 4.0]
    # a point on the fault (a seed picked on it) is in neither wall
    assert idx.on_fault(np.array([10.0, 4.0, 20.0])) == {0}
    assert idx.on_fault(np.array([14.0, 4.0, 20.0])) == set()


def test_seed_on_a_fault_steps_off_it_by_registration():
    # A seed on a traced fault is in neither wall as far as the fault surface can tell; the first step to each side
    # stays in the seed's wall or jumps out of the other one, whichever the seed's waveform correlates with better.
    # Synthetic cube 1, horizon 4 is seeded on a fault traced 1-2 traces beside the true one; deciding the side
    # from the surface alone put one side of the seed inline 4.4 samples off (median).
    syn, faults = _faulted(1)
    k = 4
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    from seismo3d.seismic.horizons import _FaultIndex

    seed = _seed_on(ref, syn.shape[0] // 2)
    assert _FaultIndex.from_interpretation(faults, 3).on_fault(np.array(seed)), "the seed is no longer on a fault"
    hz = track_horizon(syn.cube, seed, polarity=pol, faults=faults, features=None)
    line = horizon_errors(hz.times[seed[0]], ref[seed[0]])
    assert line["median_abs"] <= 0.5 and line["within_2"] >= 0.8, line


def test_despike_puts_a_cycle_skipped_pick_back_and_leaves_a_step_alone():
    from seismo3d.seismic.horizons import _POLARITY_CODE, _despike, _FaultIndex, _Options, _Slice

    syn = synthetic_cube((60, 96), n_faults=0, seed=3, noise=0.05)
    k = 2
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    sl = _Slice(syn.cube, _POLARITY_CODE[pol], (2.0, 2.0))
    truth = np.array([sl.snap(j, syn.horizons[k][j], 1.0) for j in range(60)])
    assert np.isfinite(truth).all()
    picks, offsets = reflector_picks(syn.cube, polarity=pol)
    other = picks[offsets[30]:offsets[31]]
    wrong = other[np.argmin(np.where(np.abs(other - truth[30]) > 3, np.abs(other - truth[30]), np.inf))]
    out = truth.copy()
    out[30] = wrong  # one pick on the neighbouring cycle
    out[45:] += 6.0  # and a step (a fault's jump) further on
    carried, conf = out.copy(), np.ones(60)
    opt = _Options(model="rigid", half_traces=10, half_samples=20.0, step=4, snap=3.0, min_confidence=0.3,
                   max_throw=10, min_fitness=0.3)
    changed = _despike(sl, out, carried, conf, opt, _FaultIndex.from_interpretation(None, 2),
                       lambda x, t: np.array([x, t], float))
    assert changed == 1
    assert out[30] == pytest.approx(truth[30]) and carried[30] == pytest.approx(truth[30])
    np.testing.assert_array_equal(out[45:], truth[45:] + 6.0)


# measured by benchmarks/horizons.py (point-to-plane, no fault input): % within 5 samples of the people's picks on
# live traces, and the plain autotracker's; the target (99 %, median <= 1) is reached on horizons 0-4 without
# fault input, all asserted here (horizon 6 needs the faults: next test)
@pytest.mark.parametrize("k, within_5, median, plain_within_5",
                         [(0, 0.995, 1.0, 1.0), (1, 0.990, 1.0, 0.965), (2, 0.990, 0.5, 0.988),
                          (3, 0.995, 0.5, 0.9995), (4, 0.995, 0.5, 1.0)])
def test_penobscot_horizons_against_peoples_picks(penobscot, k, within_5, median, plain_within_5):
    ref = penobscot.horizons[:, k]
    seed = (0, 256, ref[0, 256])
    ours = horizon_errors(track_horizon(penobscot.cube, seed, features=None).times, ref)
    plain = horizon_errors(autotrack(penobscot.cube, seed).times, ref)
    assert ours["within_5"] >= within_5 and ours["median_abs"] <= median
    assert plain["within_5"] == pytest.approx(plain_within_5, abs=0.002)  # the peer, as the issue describes it
    assert ours["within_5"] >= plain["within_5"] - 0.005


# With the faults trace_faults finds in the cube (the "use the fault throw from the fault tracing"), as in the
# "traced faults" rows of benchmarks/horizons.py. Horizon 6 crosses the people's fault at crossline ~55 (throw about
# 8 samples): it was at 89 % while a run of five equal 8-bit values on that fault counted as dead samples and blanked
# its likelihood over inlines 0-5, and while steps ended in the fault's drag zone. Horizon 2 crosses a 28-sample fault
# whose throw was measured one reflector period off (-12 samples) before the throw search was held to a third of
# the fault's height: it was at 92.7 %. Horizon 5 reaches 99 % but its median stays at 1.5: the people's picks wander
# within 6-8-sample clipped plateaus (about +1 sample from the centre on traces 0-200, -2.5 on 210-511, on every
# inline), so no extremum tracker meets the median target there.
@pytest.mark.parametrize("k, median", [(0, 1.0), (1, 1.0), (2, 0.5), (3, 0.5), (4, 0.5), (5, 1.5), (6, 1.0)])
def test_penobscot_horizons_with_traced_faults(penobscot, penobscot_faults, k, median):
    ref = penobscot.horizons[:, k]
    seed = (0, 256, ref[0, 256])
    ours = horizon_errors(track_horizon(penobscot.cube, seed, faults=penobscot_faults, features=None).times, ref)
    assert ours["within_5"] >= 0.99 and ours["median_abs"] <= median, ours
