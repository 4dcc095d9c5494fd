"""seismo3d.terrain.planning: A* against scikit-image's MCP_Geometric and a Dijkstra reference, D* Lite (repaired
backward search and guided forward search) against A* after changes, its cost bounds against Dijkstra, errors."""

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra
from skimage.graph import MCP_Geometric

from seismo3d.errors import InputError, PlanningError
from seismo3d.terrain import DStarLite, astar, occupancy_from_dem, path_length


def _mcp_length(free, start, goal, spacing):
    costs, _ = MCP_Geometric(np.where(free, 1.0, np.inf), sampling=spacing).find_costs([start], [goal])
    return costs[goal]


def _grid_graph(free, spacing, corner_cutting):
    """Reference graph: the 8-connected grid as a scipy sparse matrix (optionally without diagonal steps between two
    blocked cells)."""
    h, w = free.shape
    dy, dx = spacing
    index = np.arange(h * w).reshape(h, w)
    rows, cols, vals = [], [], []
    for dr, dc in [(0, 1), (1, 0), (1, 1), (1, -1)]:
        r0, r1 = 0, h - dr
        c0, c1 = max(0, -dc), w - max(0, dc)
        a = (slice(r0, r1), slice(c0, c1))
        b = (slice(r0 + dr, r1 + dr), slice(c0 + dc, c1 + dc))
        ok = free[a] & free[b]
        if dr and dc and not corner_cutting:
            ok &= free[r0:r1, c0 + dc:c1 + dc] & free[r0 + dr:r1 + dr, c0:c1]
        rows.append(index[a][ok])
        cols.append(index[b][ok])
        vals.append(np.full(int(ok.sum()), np.hypot(dr * dy, dc * dx)))
    n = h * w
    return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)).tocsr()


def _distances_to(free, cell, spacing, corner_cutting=True):
    """Dijkstra (scipy) distances of every cell to ``cell``, (H, W) metres."""
    graph = _grid_graph(free, spacing, corner_cutting)
    return dijkstra(graph, directed=False, indices=cell[0] * free.shape[1] + cell[1]).reshape(free.shape)


def _random_case(rng, shape=None, density=None):
    h, w = shape or rng.integers(8, 40, 2)
    free = rng.random((h, w)) > (density if density is not None else rng.uniform(0.1, 0.35))
    cells = np.argwhere(free)
    s, g = (tuple(int(v) for v in cells[i]) for i in rng.choice(len(cells), 2, replace=False))
    return free, s, g, tuple(rng.uniform(0.5, 2.0, 2))


@pytest.mark.parametrize("corner_cutting", [True, False])
def test_astar_is_optimal(corner_cutting):
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(40):
        free, s, g, spacing = _random_case(rng)
        ref = _mcp_length(free, s, g, spacing) if corner_cutting else _distances_to(free, g, spacing, False)[s]
        if not np.isfinite(ref):
            with pytest.raises(PlanningError, match="no path"):
                astar(free, s, g, spacing=spacing, corner_cutting=corner_cutting)
            continue
        path = astar(free, s, g, spacing=spacing, corner_cutting=corner_cutting)
        assert path.length_m == pytest.approx(ref, rel=1e-12)
        assert path_length(path.cells, spacing) == pytest.approx(path.length_m, rel=1e-12)
        assert free[path.cells[:, 0], path.cells[:, 1]].all()
        assert tuple(path.cells[0]) == s and tuple(path.cells[-1]) == g
        assert np.abs(np.diff(path.cells, axis=0)).max() == 1
        checked += 1
    assert checked >= 20


@pytest.mark.slow
@pytest.mark.parametrize("forward_search, lookahead", [(True, 0.01), (True, 0.0), (True, 0.5), (False, 0.01)])
def test_dstar_lite_replans_like_astar_from_scratch(forward_search, lookahead):
    """Moves along the path, blocks and frees cells, replans; every plan equals A* on the current grid, whichever
    search (the repaired backward one or the guided forward one) made it."""
    rng = np.random.default_rng(11)
    compared, used = 0, set()
    for _ in range(60):
        free, s, g, spacing = _random_case(rng, density=rng.uniform(0.05, 0.3))
        cc = bool(rng.integers(2))
        planner = DStarLite(free, s, g, spacing=spacing, corner_cutting=cc, forward_search=forward_search,
                            lookahead=lookahead)
        grid, here = free.copy(), s
        for _ in range(5):
            try:
                expected = astar(grid, here, g, spacing=spacing, corner_cutting=cc).length_m
            except PlanningError:
                with pytest.raises(PlanningError):
                    planner.plan()
                break
            plan = planner.plan()
            used.add(plan.planner)
            assert plan.length_m == pytest.approx(expected, rel=1e-9)
            assert path_length(plan.cells, spacing) == pytest.approx(expected, rel=1e-9)
            assert grid[plan.cells[:, 0], plan.cells[:, 1]].all()
            assert tuple(plan.cells[0]) == here and tuple(plan.cells[-1]) == g
            compared += 1
            here = tuple(int(v) for v in plan.cells[min(len(plan.cells) - 1, rng.integers(0, 4))])
            planner.move_to(here)
            block = rng.random() < 0.7
            cand = np.argwhere(grid == block)
            cand = cand[[tuple(c) not in (here, g) for c in cand]]
            if len(cand):
                pick = cand[rng.choice(len(cand), min(len(cand), 6), replace=False)]
                planner.set_cells(pick, free=not block)
                grid[pick[:, 0], pick[:, 1]] = not block
    assert compared >= 200
    assert used == ({"dstar_lite", "guided_astar"} if forward_search else {"dstar_lite"})


@pytest.mark.slow
@pytest.mark.parametrize("reset_km", [False, True])
def test_cost_bounds_are_lower_bounds_and_exact_where_settled(monkeypatch, reset_km):
    """The guided search's heuristic, checked against Dijkstra on every cell: below the true cost to the goal on
    the current grid while cells are only blocked, equal to it where the backward search says it is exact. With
    ``reset_km`` km is reset (and the queue's keys recomputed) at every move, which must not change anything."""
    if reset_km:
        monkeypatch.setattr("seismo3d.terrain.planning._KM_LIMIT", 0)
    rng = np.random.default_rng(2)
    checked_exact = checked_pending = 0
    for case in range(40):
        free, s, g, spacing = _random_case(rng, shape=(24, 30), density=rng.uniform(0.05, 0.25))
        cc = bool(rng.integers(2))
        planner = DStarLite(free, s, g, spacing=spacing, corner_cutting=cc, forward_search=case % 2 == 0,
                            lookahead=rng.choice([0.0, 0.05]))
        assert not planner.cost_bounds().exact.any()
        grid, here = free.copy(), s
        for _ in range(5):
            try:
                plan = planner.plan()
            except PlanningError:
                break
            truth = _distances_to(grid, g, spacing, cc)
            bounds = planner.cost_bounds()
            assert np.all(bounds.lower_m <= truth * (1 + 1e-9) + 1e-9)
            if planner.n_pending == 0:
                np.testing.assert_allclose(bounds.lower_m[bounds.exact], truth[bounds.exact], rtol=1e-9)
                checked_exact += int(bounds.exact.sum())
            else:
                checked_pending += 1
            here = tuple(int(v) for v in plan.cells[min(len(plan.cells) - 1, rng.integers(1, 6))])
            planner.move_to(here)
            if rng.random() < 0.3 and planner.n_pending == 0:  # free cells (never with blocked cells pending)
                cells, value = np.argwhere(~grid), True
            else:  # block cells on the path ahead and elsewhere
                cells, value = np.concatenate([plan.cells[len(plan.cells) // 2:-1], np.argwhere(grid)]), False
            cells = cells[[tuple(c) not in (here, g) for c in cells]]
            pick = cells[rng.choice(len(cells), min(len(cells), 4), replace=False)] if len(cells) else cells
            planner.set_cells(pick, free=value)
            grid[pick[:, 0], pick[:, 1]] = value
    assert checked_exact > 2000 and checked_pending > 3


def test_wall_far_ahead_is_searched_forward_and_repaired_once_passed(dfw):
    """The real DEM's query: a wall across the path at 90 % of it leaves the backward search pending and is planned
    by the guided search; once the robot is on its way round the wall (its old way to the goal no longer crosses
    it), the repair is cheap and the pending cells are given to the backward search. Every plan equals A* on the
    changed grid."""
    grid = occupancy_from_dem(dfw, max_slope_deg=1.5)
    start, goal = (8, 0), (358, 366)
    planner = DStarLite(grid.free, start, goal, spacing=grid.spacing)
    first = planner.plan()
    at = first.cells[int(0.9 * (len(first.cells) - 1))]
    wall = np.array([(at[0] + dr, at[1] + dc) for dr in range(-4, 5) for dc in range(-1, 2)])
    changed = grid.free.copy()
    changed[wall[:, 0], wall[:, 1]] = False
    planner.set_cells(wall, free=False)
    far = planner.plan()
    assert far.planner == "guided_astar" and planner.n_pending > 0
    assert far.length_m == pytest.approx(astar(changed, start, goal, spacing=grid.spacing).length_m, rel=1e-9)
    here = tuple(int(v) for v in far.cells[int(0.9 * (len(far.cells) - 1)) - 6])
    planner.move_to(here)
    near = planner.plan()
    assert near.planner == "dstar_lite" and planner.n_pending == 0
    assert near.length_m == pytest.approx(astar(changed, here, goal, spacing=grid.spacing).length_m, rel=1e-9)


def test_errors():
    free = np.ones((10, 10), bool)
    free[:, 5] = False
    with pytest.raises(InputError, match="outside the 10 x 10 grid"):
        astar(free, (0, 0), (10, 3))
    with pytest.raises(InputError, match="on an obstacle"):
        astar(free, (0, 5), (9, 9))
    with pytest.raises(PlanningError, match=r"region has 50 cells .* comes nearest to the start at \(0, 6\)"):
        astar(free, (0, 0), (9, 9))
    planner = DStarLite(free, (0, 0), (9, 4))
    with pytest.raises(InputError, match="cannot block"):
        planner.set_cells([(9, 4)], free=False)
    with pytest.raises(InputError, match="spacing"):
        astar(free, (0, 0), (1, 1), spacing=(0, 1))
    with pytest.raises(InputError, match="lookahead"):
        DStarLite(free, (0, 0), (9, 4), lookahead=2.0)


def test_dfw_corners_equal_mcp(dfw):
    """The issue's query: --max-slope 1.5 between opposite corners of the real DEM (the corners of the traversable
    region, (8, 0) and (358, 366): cell (0, 0) is a single free cell cut off by steeper ones)."""
    grid = occupancy_from_dem(dfw, max_slope_deg=1.5)
    start, goal = (8, 0), (358, 366)
    path = astar(grid.free, start, goal, spacing=grid.spacing)
    assert path.length_m <= 1.03 * _mcp_length(grid.free, start, goal, grid.spacing)
    assert path.length_m == pytest.approx(_mcp_length(grid.free, start, goal, grid.spacing), rel=1e-9)
    with pytest.raises(PlanningError, match="comes nearest to the start at"):
        astar(grid.free, (0, 0), goal, spacing=grid.spacing)



def test_a_forward_search_whose_queue_fills_stops_and_runs_again_with_a_longer_one(monkeypatch):
    # the queue's arrays come from the caller (no allocation in the kernel): a search that fills them returns -1
    # expansions, and run_forward_search runs it again with longer ones (a new generation) to astar's path
    from seismo3d.terrain import _planning_kernels as kernels
    from seismo3d.terrain.planning import _step_costs

    rng = np.random.default_rng(3)
    free = rng.random((40, 50)) > 0.2
    free[0, 0] = free[-1, -1] = True
    want = astar(free, (0, 0), (39, 49))
    n = free.size
    args = (free, 0, n - 1, _step_costs((1.0, 1.0), n), True)
    work = [np.empty(n, np.int64), np.empty(n, np.int64), np.zeros(n, np.int64)]
    short = [np.empty(4, np.int64) for _ in range(3)]
    total, expanded = kernels.forward_search(*args, *work, 1, np.zeros(1, np.int64), np.zeros(5, np.int64), *short)
    assert (total, expanded) == (kernels.INF, -1)
    search, lengths = kernels.forward_search, []

    def first_fills(*a):  # the first search's queue of N + 1 entries taken as full
        lengths.append(a[-1].size)
        return (kernels.INF, -1) if len(lengths) == 1 else search(*a)

    monkeypatch.setattr(kernels, "forward_search", first_fills)
    queue = []
    total, expanded, generation = kernels.run_forward_search(*args, *work, 1, np.zeros(1, np.int64),
                                                             np.zeros(5, np.int64), queue)
    assert generation == 3 and lengths == [n + 1, 2 * (n + 1)] and [q.size for q in queue] == [2 * (n + 1)] * 3
    assert expanded == want.n_expanded
    assert np.array_equal(kernels.trace_back(work[1], 0, n - 1), want.cells[:, 0] * 50 + want.cells[:, 1])
