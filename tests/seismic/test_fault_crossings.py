"""Fault crossings (seismo3d.seismic.horizons.fault_crossings): hand-made fault planes with known crossings, jumps,
blocks and walls, and the reliable-throw gate."""

from types import SimpleNamespace

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic import FaultCrossings, reliable_throw
from seismo3d.seismic.horizons.fault_pairs import fault_steps
from seismo3d.seismic.horizons.lsq import trace_pairs
from seismo3d.seismic.faults.throw import hanging_wall_normals


def _vertical_fault_points(x0, n_y=9, n_t=40):
    """Points of a vertical fault plane at trace x0 (3D index space), normals along +x."""
    y, t = np.meshgrid(np.arange(n_y, dtype=float), np.arange(n_t, dtype=float), indexing="ij")
    pts = np.column_stack([np.full(y.size, float(x0)), y.ravel(), t.ravel()])
    return pts, np.tile([1.0, 0.0, 0.0], (len(pts), 1))


def test_crossings_adds_up_faults_and_ignores_a_grazing_one():
    p1, n1 = _vertical_fault_points(10.5)
    p2, n2 = _vertical_fault_points(12.5)
    both = FaultCrossings(np.vstack([p1, p2]), np.vstack([n1, n2]), np.r_[np.full(len(p1), 4.0), np.full(len(p2), 6.0)],
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
    ending = FaultCrossings(edge, np.tile([0.0, 0.0, 1.0], (11, 1)), np.full(11, 5.0))
    assert ending.jump(np.array([10.0, 4.0, 18.0]), np.array([14.0, 4.0, 22.0])) == 0.0
    assert ending.jump(np.array([6.0, 4.0, 18.0]), np.array([10.0, 4.0, 22.0])) == -5.0  # through it: into the footwall


def test_crossings_finds_the_fault_block_of_a_pick():
    # Along a slice, the panels registered around a pick stay within its fault block: the traces a horizon through
    # the pick reaches without crossing a fault (reflector points past a fault belong to another block).
    p1, n1 = _vertical_fault_points(10.5, n_t=30)  # samples 0-29
    p2, n2 = _vertical_fault_points(20.5, n_t=30)
    idx = FaultCrossings(np.vstack([p1, p2]), np.vstack([n1, n2]), np.full(len(p1) + len(p2), 4.0),
                      np.r_[np.zeros(len(p1)), np.ones(len(p2))])
    on_line = lambda x, t: np.array([x, 4.0, t], float)  # noqa: E731 - inline 4 of the index's cube
    assert idx.block(on_line, 40, 14, 15.0, 0.0, 0, 39) == (11, 20)
    assert idx.block(on_line, 40, 4, 15.0, 0.0, 0, 8) == (0, 8)  # no fault within the span
    assert idx.block(on_line, 40, 25, 15.0, 0.0, 15, 35) == (21, 35)
    assert idx.block(on_line, 40, 14, 36.0, 0.0, 0, 39) == (0, 39)  # below the faults' lower ends: one block
    # a dipping horizon (1 sample per trace) meets fault 1 at sample 22.5 and passes below fault 2's end (at 32.5)
    assert idx.block(on_line, 40, 14, 26.0, 1.0, 0, 39) == (11, 39)
    assert FaultCrossings.empty(3).block(on_line, 40, 14, 15.0, 0.0, 0, 39) == (0, 39)


def test_crossings_leaves_out_faults_whose_throw_explains_nothing():
    # A fault whose two sides correlate no better at its throw than without it, or that has no throw at all, gives no
    # jump; one whose throw explains its sides is used however low their correlation (the large fault of
    # penobscot_xl1155: 0.317 at its throw, 0.113 without, before its 2D throw search reached 32 samples; 0.412 and
    # 0.094 since), unless a least correlation is asked for.
    pts = [_vertical_fault_points(x) for x in (10.5, 20.5, 30.5, 40.5)]
    n = len(pts[0][0])
    corr = np.linspace(0.3, 0.9, n)  # median 0.6
    interp = SimpleNamespace(
        faults=[SimpleNamespace(points=p, normals=q) for p, q in pts],
        throws=[SimpleNamespace(throw=np.full(n, 4.0), correlation=corr, correlation_unshifted=corr - 0.4),
                SimpleNamespace(throw=np.full(n, 6.0), correlation=corr, correlation_unshifted=corr + 0.1),
                SimpleNamespace(throw=np.full(n, np.nan), correlation=np.full(n, np.nan),
                                correlation_unshifted=np.full(n, np.nan)),
                SimpleNamespace(throw=np.full(n, 5.0), correlation=np.full(n, 0.317),
                                correlation_unshifted=np.full(n, 0.113))])
    idx = FaultCrossings.from_interpretation(interp, 3)
    assert set(idx.ids) == {0, 3}
    step = np.array([[10.0, 4.0, 20.0], [11.0, 4.0, 20.0]])
    assert idx.jump(*step) == 4.0  # a vertical fault's hanging wall is its +x side (see the next test)
    assert idx.jump(*(step + [10.0, 0.0, 0.0])) == 0.0
    assert idx.jump(*(step + [20.0, 0.0, 0.0])) == 0.0
    assert idx.jump(*(step + [30.0, 0.0, 0.0])) == 5.0
    assert set(FaultCrossings.from_interpretation(interp, 3, min_throw_correlation=0.5).ids) == {0}
    assert not reliable_throw(SimpleNamespace(correlation=np.full(n, np.nan)))


def test_crossings_orients_normals_as_the_throw_was_measured():
    # Normals from strike and dip point to either side of a vertical fault (strike and strike + 180): the Penobscot
    # fault at crossline ~51 had 147 of its 377 normals one way and the rest the other, so the jump changed sign from
    # point to point. The index aligns them as fault_throw does (principal direction; for a vertical fault its +x
    # side is the hanging wall), so every step across gives the same jump.
    p, nrm = _vertical_fault_points(10.5)
    flip = np.where(np.arange(len(p)) % 3 == 0, -1.0, 1.0)[:, None]
    interp = SimpleNamespace(faults=[SimpleNamespace(points=p, normals=nrm * flip)],
                             throws=[SimpleNamespace(throw=np.full(len(p), 4.0), correlation=np.full(len(p), 0.9))])
    idx = FaultCrossings.from_interpretation(interp, 3)
    assert np.allclose(idx.normals, -hanging_wall_normals(nrm)) and np.allclose(idx.normals, [-1.0, 0.0, 0.0])
    jumps = {idx.jump(np.array([10.0, y, t]), np.array([11.0, y, t])) for y in range(9) for t in range(5, 35, 3)}
    assert jumps == {4.0}  # into the hanging wall: down by the throw, everywhere
    # a fault dipping towards +x (normals into the footwall point down and to -x), some flipped: the footwall stays
    # below the plane
    d = np.radians(70.0)
    down = np.array([-np.sin(d), 0.0, np.cos(d)])
    interp.faults[0].normals = np.tile(down, (len(p), 1)) * flip
    idx = FaultCrossings.from_interpretation(interp, 3)
    assert np.allclose(idx.normals, down)


def test_fault_crossing_uses_the_faults_own_plane_and_knows_a_point_on_it():
    # A traced fault is a set of voxels (positions rounded to the grid). The crossing test takes the least-squares
    # plane of the fault's points near the step. It used to test each point's own plane within a +-3 voxel band, and
    # missed the along-slice step (4 traces) below, which starts 3.5 voxels from this dipping fault and ends 0.3
    # voxel past it.
    d = np.radians(60.0)
    into_footwall = np.array([-np.sin(d), 0.0, np.cos(d)])  # the fault dips towards +x; its footwall is below
    y, t = np.meshgrid(np.arange(0.0, 9.0), np.arange(10.0, 31.0), indexing="ij")
    x = np.round(10.0 + (t - 20.0) / np.tan(d))
    pts = np.column_stack([x.ravel(), y.ravel(), t.ravel()])
    idx = FaultCrossings(pts, np.tile(into_footwall, (len(pts), 1)), np.full(len(pts), 5.0))
    for tz in (19.6, 20.3, 21.0, 21.7):
        x0 = 10.0 + (tz - 20.0) / np.tan(d)  # where the true plane is at this time
        a, b = np.array([x0 + 4.0, 4.0, tz]), np.array([x0 - 0.3 / np.sin(d), 4.0, tz])
        assert idx.jump(a, b) == -5.0 and idx.jump(b, a) == 5.0  # into the footwall: up by the throw
    # a step beside the fault's end is no crossing
    assert idx.jump(np.array([20.0, 4.0, 33.0]), np.array([16.0, 4.0, 33.0])) == 0.0
    # a vertical fault's plane lies on a grid plane, so an inline-to-inline carry lands on it and then leaves it:
    # exactly one of the two steps crosses it
    p, nrm = _vertical_fault_points(30.0)
    vertical = FaultCrossings(p, nrm, np.full(len(p), 4.0))
    for t in (5.0, 20.0, 33.5):
        a, on, b = (np.array([x, 4.0, t]) for x in (29.0, 30.0, 31.0))
        assert sorted((vertical.jump(a, on), vertical.jump(on, b))) == [-4.0, 0.0]  # into the footwall (+x)
        assert sorted((vertical.jump(b, on), vertical.jump(on, a))) == [0.0, 4.0]
    # a point on the fault (a seed picked on it) is in neither wall
    assert idx.on_fault(np.array([10.0, 4.0, 20.0])) == {0}
    assert idx.on_fault(np.array([14.0, 4.0, 20.0])) == set()


def test_near_segments_keeps_every_segment_that_crosses_a_fault():
    # the pre-filter of the horizon tracker's fault steps: a segment it leaves out never crosses a fault
    p1, n1 = _vertical_fault_points(10.5)
    p2, n2 = _vertical_fault_points(20.5, n_t=20)
    faults = FaultCrossings(np.vstack([p1, p2]), np.vstack([n1, n2]), np.r_[np.full(len(p1), 4.0), np.full(len(p2), 6.0)],
                            np.r_[np.zeros(len(p1)), np.ones(len(p2))])
    rng = np.random.default_rng(0)
    a = rng.uniform([0, 0, 0], [30, 9, 40], (400, 3))
    b = a + rng.normal(0.0, 1.5, (400, 3))
    near = faults.near_segments(a, b)
    crossing = np.array([bool(faults.crossings(x, y)) for x, y in zip(a, b)])
    assert crossing.any() and not near.all()
    assert np.all(near[crossing])
    assert not FaultCrossings.empty(3).near_segments(a, b).any()


def _dipping_fault_points(x0, dip_per_sample, n_y=9, n_t=40, jitter=0.0, rng=None):
    """A fault plane through trace x0 at sample 0 that moves ``dip_per_sample`` traces per sample (3D), normals
    into +x; ``jitter`` voxels of noise on the points (as a traced fault's)."""
    y, t = np.meshgrid(np.arange(n_y, dtype=float), np.arange(n_t, dtype=float), indexing="ij")
    pts = np.column_stack([x0 + dip_per_sample * t.ravel(), y.ravel(), t.ravel()])
    if jitter:
        pts[:, 0] += rng.normal(0.0, jitter, len(pts))
    n = np.array([1.0, 0.0, -dip_per_sample])
    return pts, np.tile(n / np.linalg.norm(n), (len(pts), 1))


@pytest.mark.slow
def test_step_jumps_equal_jump_step_by_step():
    # the horizon tracker's many neighbour steps in one compiled call: the same jump as jump() on every step, with
    # two faults (one dipping, with jittered points and an unknown throw on part of it), in 3D and in 2D
    rng = np.random.default_rng(3)
    p1, n1 = _vertical_fault_points(10.5)
    p2, n2 = _dipping_fault_points(16.0, 0.2, jitter=0.3, rng=rng)
    throws = np.r_[np.full(len(p1), 4.0), np.where(p2[:, 2] > 30, np.nan, 6.0)]
    pts, nrm, ids = np.vstack([p1, p2]), np.vstack([n1, n2]), np.r_[np.zeros(len(p1)), np.ones(len(p2))]
    for ndim in (3, 2):
        cols = [0, 1, 2] if ndim == 3 else [0, 2]
        keep = np.ones(len(pts), bool) if ndim == 3 else pts[:, 1] == 4.0  # 2D: the section at crossline 4
        faults = FaultCrossings(pts[keep][:, cols], nrm[keep][:, cols], throws[keep], ids[keep])
        a = rng.uniform(0.0, [30, 9, 40] if ndim == 3 else [30, 40], (3000, ndim))
        b = a + rng.normal(0.0, 1.5, (3000, ndim))
        expected = np.array([faults.jump(x, y) for x, y in zip(a, b)])
        got = faults.step_jumps(a, b)
        assert np.count_nonzero(expected) > 50 and np.isnan(expected).any(), ndim
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9, equal_nan=True)
    assert np.array_equal(FaultCrossings.empty(2).step_jumps(a, b), np.zeros(len(a)))
    with pytest.raises(InputError, match=r"\(n, 2\)"):
        FaultCrossings.empty(2).step_jumps(a, b[:, :1])


def test_a_fault_zone_is_crossed_once_and_left_untracked():
    # A 2D fault traced as two strands (traces 10.5 and 15.5) whose throw, 4 samples, was measured across both (the
    # sides read beyond every strand) and a one-strand fault at 30.5 (3 samples): a line of 40 traces at sample 20
    # crosses the zone once, by 4 and not 8; the traces between the strands are not tracked; pairs that end inside
    # the zone are left out and pairs from its nearest traces on each side span it.
    t = np.arange(40.0)
    strand = lambda x: np.column_stack([np.full(t.size, x), t])  # noqa: E731 - a vertical strand, (trace, sample)
    pts = np.vstack([strand(10.5), strand(15.5), strand(30.5)])
    ids = np.repeat([0, 0, 1], t.size)
    faults = FaultCrossings(pts, np.tile([1.0, 0.0], (len(pts), 1)), np.where(ids == 0, 4.0, 3.0), ids)
    steps = fault_steps(faults, (40,), np.full(40, 20.0), keep=np.array([2]), reach=2)
    assert np.flatnonzero(steps.zone).tolist() == [11, 12, 13, 14, 15]
    jump = steps.jumps[0]
    assert jump[10] == pytest.approx(-4.0) and jump[30] == pytest.approx(-3.0)
    assert np.count_nonzero(np.abs(jump) > 1e-9) == 2
    assert sorted(zip(*steps.spans[:2].tolist())) == [(9, 16), (9, 17), (10, 16), (10, 17)]
    a, b, dist, axis = trace_pairs((40,), (1, 2, 4, 8, 32))
    pa, pb, pd, _, pj = steps.pairs(a, b, dist, axis, (40,))
    assert not (steps.zone[pa] | steps.zone[pb]).any()
    assert np.array_equal(pd, pb - pa)
    across = (pa <= 10) & (pb >= 16) & (pb <= 30)
    assert across.any() and np.allclose(pj[across], -4.0)  # the zone's throw once
    beyond = (pa <= 10) & (pb > 30)
    assert beyond.any() and np.allclose(pj[beyond], -7.0)  # and the other fault's
    # a seed inside the zone keeps it as two strands: nothing is left untracked
    assert not fault_steps(faults, (40,), np.full(40, 20.0), keep=np.array([12])).zone.any()
