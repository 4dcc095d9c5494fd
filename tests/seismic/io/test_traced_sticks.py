"""Sticks drawn from traced faults as interpreters draw them, on generated faults (a listric 2D fault, a planar
low-dip and a curved steep 3D fault, rasterised one sample thick as the thinned fault images are): one stick per fault
per line, every fault sample of the line within one sample of its stick (distances by an independent point-to-segment
computation), times strictly increasing, a few nodes, and the same sticks read back from every format."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic.faults import Fault
from seismo3d.seismic.io.coordinates import survey_coordinates
from seismo3d.seismic.io.fault_sticks import READ_STICK_FORMATS, FaultSticks, read_fault_sticks, write_fault_sticks
from seismo3d.seismic.io.traced_sticks import distance_to_stick, stick_lines, stick_nodes

SAMPLES = 1000.0 + 4.0 * np.arange(300)  # ms
IL0, XL0 = 100, 20  # line numbers of index 0


def _fault(points, fault_id=1) -> Fault:
    n = len(points)
    return Fault(fault_id, np.asarray(points, np.int64), np.ones(n, np.float32), np.zeros(n, np.float32),
                 np.zeros(n, np.float32), np.zeros((n, points.shape[1]), np.float32))


def _raster_curve(x_of_k, k0, k1):
    """(trace, sample) of an 8-connected one-sample-thick raster of the curve trace = x_of_k(sample)."""
    k = np.linspace(k0, k1, 40 * (k1 - k0) + 1)
    x = x_of_k(k)
    steps = np.ceil(np.abs(np.diff(x)).max() * 4 + 1).astype(int)  # dense enough for low-dip runs
    k = np.linspace(k0, k1, 40 * steps * (k1 - k0) + 1)
    return np.unique(np.rint(np.column_stack([x_of_k(k), k])).astype(np.int64), axis=0)


def _listric(k):
    """A listric fault on a section: steep at the top (0.1 trace per sample), 2.5 traces per sample at the bottom."""
    u = k / 200.0
    return 20.0 + 10.0 * u + 120.0 * u**4


def _cube_faults():
    """A planar fault of low dip (0.4 sample per trace: 2.5 traces per sample) striking 30 degrees off the inline
    axis, one sample thick in time; and a steep curved fault, listric on every inline (crossline index = 20 + 15
    sin(inline / 20) + 40 (sample / 280)^2), one trace thick along the crosslines."""
    il, xl = np.meshgrid(np.arange(60), np.arange(100), indexing="ij")
    strike = np.deg2rad(30.0)
    across = -np.sin(strike) * il + np.cos(strike) * xl  # distance across strike, traces
    k = 40.0 + 0.4 * (across - across.min())
    keep = k < 290
    low = np.column_stack([il[keep], xl[keep], np.rint(k[keep])]).astype(np.int64)
    i, s = np.meshgrid(np.arange(60), np.arange(20, 280), indexing="ij")
    steep = np.column_stack([i.ravel(), np.rint(20 + 15 * np.sin(i / 20.0) + 40 * (s / 280) ** 2).ravel(), s.ravel()])
    return _fault(low, 1), _fault(steep.astype(np.int64), 2)


def _distance(points, nodes):
    """Distance of each point from the polyline through nodes (nearest segment), written out independently of the
    library: project onto each segment, clamp, take the nearest."""
    best = np.full(len(points), np.inf)
    for a, b in zip(nodes[:-1], nodes[1:]):
        for j, p in enumerate(points):
            ab, ap = b - a, p - a
            u = min(max(float(ap @ ab) / float(ab @ ab), 0.0), 1.0)
            best[j] = min(best[j], float(np.linalg.norm(ap - u * ab)))
    return best


def _line_coordinates(n_traces):
    il = IL0 + np.arange(n_traces, dtype=np.float64)
    return survey_coordinates(il, np.full(n_traces, float(XL0)), 5000.0 + 12.5 * il, 7000.0 + 0.0 * il, unit="m",
                              resolution=0.1)


def _cube_coordinates(shape):
    il, xl = np.meshgrid(IL0 + np.arange(shape[0], dtype=np.float64), XL0 + np.arange(shape[1], dtype=np.float64),
                         indexing="ij")
    return survey_coordinates(il, xl, 1000.0 + 25.0 * il + 3.0 * xl, 5000.0 - 3.0 * il + 25.0 * xl, unit="m",
                              resolution=0.1)


def _check_sticks(sticks, fault, cube: bool):
    """The issue's properties of each fault's sticks against the fault's own samples; returns (nodes, samples) of the
    sticks' lines."""
    p = fault.points
    lines_seen, n_nodes, n_samples = set(), 0, 0
    for _, nodes in sticks.sticks():
        k = np.interp(sticks.z[nodes], SAMPLES, np.arange(SAMPLES.size))
        assert np.all(np.diff(k) > 0)  # times strictly increasing: a single-valued function of time, top to bottom
        if cube:
            on_inline = np.unique(sticks.inline[nodes]).size == 1
            assert on_inline or np.unique(sticks.crossline[nodes]).size == 1  # the stick lies on one line
            axis = 0 if on_inline else 1
            line = int(sticks.inline[nodes[0]] - IL0) if on_inline else int(sticks.crossline[nodes[0]] - XL0)
            assert (axis, line) not in lines_seen  # one stick per fault per line
            lines_seen.add((axis, line))
            q = p[p[:, axis] == line]
            trace = (sticks.crossline[nodes] - XL0) if on_inline else (sticks.inline[nodes] - IL0)
            along = q[:, 1 - axis]
        else:
            q, trace, along = p, sticks.inline[nodes] - IL0, p[:, 0]
        d = _distance(np.column_stack([along, q[:, -1]]).astype(float), np.column_stack([trace, k]))
        assert d.max() <= 1.0 + 1e-9, d.max()  # every fault sample of the line within one sample of its stick
        n_nodes += nodes.size
        n_samples += int(np.ptp(q[:, -1])) + 1
    return n_nodes, n_samples


def test_listric_section_fault_is_one_stick_with_nodes_where_it_bends():
    points = _raster_curve(_listric, 10, 200)
    fault = _fault(points)
    sticks = FaultSticks.from_faults([fault], _line_coordinates(200), SAMPLES)
    assert sticks.n_sticks == 1
    n_nodes, n_samples = _check_sticks(sticks, fault, cube=False)
    assert n_samples == 191 and len(points) > 300  # the low-dip bottom: several traces a sample
    assert n_nodes <= 12, n_nodes  # measured 9; one a sample before
    # the nodes crowd where the fault bends: more in the curved lower half than in the nearly straight upper half
    k = np.interp(sticks.z, SAMPLES, np.arange(SAMPLES.size))
    assert (k > 105).sum() > (k < 105).sum()


def test_low_dip_and_steep_cube_faults_one_stick_per_line_no_zigzag():
    low, steep = _cube_faults()
    sticks = FaultSticks.from_faults([low, steep], _cube_coordinates((60, 100)), SAMPLES)
    for fid, fault in ((1, low), (2, steep)):
        mine = sticks.fault_id == fid
        one = FaultSticks(*(getattr(sticks, a)[mine] for a in ("fault_id", "stick", "x", "y", "z", "inline",
                                                               "crossline")), names=sticks.names)
        n_nodes, n_samples = _check_sticks(one, fault, cube=True)
        assert n_nodes <= 0.1 * n_samples, (fid, n_nodes, n_samples)  # measured 0.057 and 0.019
        for _, nodes in one.sticks():  # a planar fault: the stick moves one way along its line, no zigzag
            if fid == 1:
                trace = one.crossline[nodes] if np.unique(one.inline[nodes]).size == 1 else one.inline[nodes]
                assert np.all(np.diff(trace) > 0) or np.all(np.diff(trace) < 0)
    # the low-dip fault strikes 30 degrees off the inlines: the inlines cut it across its strike, every 10th
    lines = np.unique(sticks.inline[sticks.fault_id == 1])
    assert np.array_equal(lines - IL0, np.arange(0, 60, 10))
    assert np.unique(sticks.crossline[sticks.fault_id == 2]).size > 1  # the steep one runs along crosslines: inlines


def test_lines_across_strike_and_small_faults():
    low, steep = _cube_faults()
    assert stick_lines(low.points)[0] == 0 and stick_lines(steep.points)[0] == 0
    swapped = low.points[:, [1, 0, 2]]  # the same fault with inlines and crosslines exchanged: cut by crosslines
    axis, lines = stick_lines(swapped, line_step=25)
    assert axis == 1 and np.array_equal(lines, [0, 25, 50])
    small = low.points[(low.points[:, 0] >= 11) & (low.points[:, 0] <= 18)]  # between two 10th lines: its two ends
    assert np.array_equal(stick_lines(small)[1], [11, 18])
    with pytest.raises(InputError, match="line_step"):
        stick_lines(low.points, line_step=0)


def test_a_strand_folding_back_is_left_out_not_zigzagged():
    """Two strands at the same times, 12 traces apart, over 30 samples: the stick follows one, never both."""
    main = _raster_curve(lambda k: 30.0 + 0.2 * k, 0, 100)
    strand = np.array([[42 + 0.2 * k, k] for k in range(40, 70)]).round().astype(np.int64)
    points = np.r_[main, strand]
    nodes, resolved = stick_nodes(points[:, 0], points[:, 1])
    assert np.all(np.diff(points[nodes, 1]) > 0)
    assert resolved.sum() == len(strand) and np.all(resolved[len(main):])  # the strand left out, the fault kept
    assert nodes.size <= 3  # a straight fault: its two ends (and at most one node more)
    with pytest.raises(InputError, match="tolerance"):
        stick_nodes(points[:, 0], points[:, 1], tolerance=0.0)


@pytest.mark.parametrize("fmt", READ_STICK_FORMATS)
def test_round_trip_of_traced_sticks(tmp_path, fmt):
    """Written, read back (IESX placed on the lines by X / Y): the same sticks, each fault sample of the line within
    one sample of the stick read back."""
    low, steep = _cube_faults()
    coords = _cube_coordinates((60, 100))
    sticks = FaultSticks.from_faults([low, steep], coords, SAMPLES)
    back = read_fault_sticks(write_fault_sticks(tmp_path / "s.txt", sticks, format=fmt), coordinates=coords)
    assert (back.n_faults, back.n_sticks, back.n_nodes) == (sticks.n_faults, sticks.n_sticks, sticks.n_nodes)
    back = FaultSticks(back.fault_id, back.stick, back.x, back.y, back.z, np.round(back.inline, 2),
                       np.round(back.crossline, 2), back.names)  # IESX: lines from X / Y (within 0.005)
    for fid, fault in ((1, low), (2, steep)):
        mine = back.fault_id == fid
        _check_sticks(FaultSticks(*(getattr(back, a)[mine] for a in ("fault_id", "stick", "x", "y", "z", "inline",
                                                                     "crossline")), names=back.names),
                      fault, cube=True)


@pytest.mark.parametrize("tolerance", [0.5, 1.0, 2.5])
def test_samples_near_the_path_are_those_distance_to_stick_finds(tolerance):
    """stick_nodes measures each sample against the few segments of its path that reach within the tolerance of its
    time: the same answer as measuring it against every segment (distance_to_stick), on paths with steps of one and
    of several samples in time and samples far off them."""
    from seismo3d.seismic.io.traced_sticks import _near_path

    rng = np.random.default_rng(7)
    for _ in range(20):
        times = np.cumsum(rng.integers(1, 4, size=rng.integers(1, 60)))
        path = np.column_stack([np.cumsum(rng.integers(-2, 3, size=times.size)), times]).astype(np.float64)
        samples = np.column_stack([rng.integers(-12, 12, 300), rng.integers(-5, times[-1] + 5, 300)]).astype(float)
        samples = np.concatenate([samples, path + rng.uniform(-1.5, 1.5, path.shape)])
        np.testing.assert_array_equal(_near_path(samples, path, tolerance),
                                      distance_to_stick(samples, path) <= tolerance)


def test_the_bends_of_a_path_are_the_vertices_skimage_keeps():
    """The nodes where a stick's path bends are the vertices scikit-image's Ramer-Douglas-Peucker
    (approximate_polygon) keeps, the same ones, on integer samples whose distances often equal the tolerance exactly
    (ties), on straight slanted runs, on chains that double back laterally (vertices projecting outside their chord)
    and on paths of 1 and 2 samples; a fault of one sample per time keeps them all as nodes."""
    from skimage.measure import approximate_polygon

    from seismo3d.seismic.io.traced_sticks import _bends

    rng = np.random.default_rng(11)
    for trial in range(120):
        tolerance = (0.5, 1.0, 1.5, 2.0)[trial % 4]
        n = int(rng.integers(1, 50))
        k = np.sort(rng.choice(200, size=n, replace=False))
        step = int(rng.choice([0, 1, 2, 8]))
        t = np.cumsum(rng.integers(-step, step + 1, size=n)) + 40
        if trial % 5 == 0:  # nearly straight, slanted: distances near the tolerance
            t = np.round(np.linspace(0, rng.integers(0, 60), n) + rng.normal(0, 0.6, n)).astype(np.int64)
        xy = np.column_stack([t, k]).astype(np.float64)
        kept = approximate_polygon(xy, tolerance)
        np.testing.assert_array_equal(xy[_bends(xy, tolerance)], kept)
        if trial < 20:  # its own path: those, and a sample a tie left beyond
            nodes, _ = stick_nodes(t, k, tolerance=tolerance)
            assert {tuple(v) for v in kept} <= {tuple(v) for v in xy[nodes]}
