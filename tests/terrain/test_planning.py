"""seismo3d.terrain.planning: A* against scikit-image's MCP_Geometric and a Dijkstra reference, D* Lite against A*
after changes, errors."""

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


def _dijkstra_no_corner_cutting(free, start, goal, spacing):
    """Reference: scipy's Dijkstra on the 8-connected graph without diagonal steps between two blocked cells."""
    h, w = free.shape
    dy, dx = spacing
    rows, cols, vals = [], [], []
    for dr, dc in [(0, 1), (1, 0), (1, 1), (1, -1)]:
        for r in range(h):
            for c in range(w):
                r2, c2 = r + dr, c + dc
                if not (0 <= r2 < h and 0 <= c2 < w) or not (free[r, c] and free[r2, c2]):
                    continue
                if dr and dc and not (free[r + dr, c] and free[r, c + dc]):
                    continue
                rows.append(r * w + c)
                cols.append(r2 * w + c2)
                vals.append(np.hypot(dr * dy, dc * dx))
    graph = coo_matrix((vals, (rows, cols)), shape=(h * w, h * w)).tocsr()
    return dijkstra(graph, directed=False, indices=start[0] * w + start[1])[goal[0] * w + goal[1]]


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
        ref = _mcp_length(free, s, g, spacing) if corner_cutting else _dijkstra_no_corner_cutting(free, s, g, spacing)
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


def test_dstar_lite_replans_like_astar_from_scratch():
    """Moves along the path, blocks and frees cells, replans; every plan equals A* on the current grid."""
    rng = np.random.default_rng(11)
    compared = 0
    for _ in range(60):
        free, s, g, spacing = _random_case(rng, density=rng.uniform(0.05, 0.3))
        cc = bool(rng.integers(2))
        planner = DStarLite(free, s, g, spacing=spacing, corner_cutting=cc)
        grid, here = free.copy(), s
        for _ in range(4):
            try:
                expected = astar(grid, here, g, spacing=spacing, corner_cutting=cc).length_m
            except PlanningError:
                with pytest.raises(PlanningError):
                    planner.plan()
                break
            plan = planner.plan()
            assert plan.length_m == pytest.approx(expected, rel=1e-9)
            assert path_length(plan.cells, spacing) == pytest.approx(expected, rel=1e-9)
            assert grid[plan.cells[:, 0], plan.cells[:, 1]].all()
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
    assert compared >= 150


def test_dstar_lite_with_a_small_heap_compacts_and_stays_exact():
    """With the smallest allowed queue array, outdated entries are dropped and the heap rebuilt many times."""
    rng = np.random.default_rng(5)
    for _ in range(10):
        free, s, g, spacing = _random_case(rng, shape=(15, 15), density=0.15)
        planner = DStarLite(free, s, g, spacing=spacing, heap_capacity=free.size + 32)
        grid = free.copy()
        for _ in range(8):
            try:
                expected = astar(grid, s, g, spacing=spacing).length_m
            except PlanningError:
                break
            assert planner.plan().length_m == pytest.approx(expected, rel=1e-9)
            cells = np.argwhere(rng.random(grid.shape) < 0.05)
            cells = cells[[tuple(c) not in (s, g) for c in cells]]
            flip = rng.random() < 0.6
            planner.set_cells(cells, free=not flip)
            grid[cells[:, 0], cells[:, 1]] = not flip
    with pytest.raises(InputError, match="heap_capacity"):
        DStarLite(free, s, g, heap_capacity=10)


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
