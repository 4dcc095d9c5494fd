"""Shortest paths on 8-connected occupancy grids: A* for one query, D* Lite for replanning as obstacles appear.

A grid is a (H, W) boolean array of traversable cells with metric cell sizes ``(dy, dx)``; a step to one of the 8
neighbours costs its length in metres (``dy``, ``dx`` or ``sqrt(dx^2 + dy^2)``), so a path's cost is its horizontal
length. A diagonal step joins two traversable cells even when both cells beside it are blocked, as in
scikit-image's ``MCP_Geometric``; ``corner_cutting=False`` forbids such steps (a robot of non-zero width cannot
squeeze between two obstacles touching at a corner; the grid is then 4-connected for reachability).

Path costs are summed in integers (a unit of at most 2^-40 of a diagonal step, see ``_step_costs``): sums are exact
whatever their order, so equally long paths tie exactly, and the lengths returned are the chosen path's length in
metres, equal to the float optimum to about 1e-12.

Complexity, with N cells (memory O(N) for every planner):

- :func:`astar`: O(N log N) time in the worst case; the heuristic, the octile distance (exact on an empty grid,
  hence admissible and consistent), limits it to the cells whose cost from the start plus heuristic is below the
  optimum, often far fewer than N. Ties on f go to the cell farther from the start.
- :class:`DStarLite`, first plan: D* Lite's search from the goal, O(N log N), expanding the cells whose cost to the
  goal plus octile distance to the robot is below the robot's cost (the cells A* run from the goal would expand:
  2.5 times those of A* from the start on the real DEM's corner-to-corner query, 0.5-2.9 times on generated grids),
  plus a thin band beyond it (``lookahead``, default 1 % of the robot's cost), so that the cells round the robot
  are settled for the guided search below.
- :class:`DStarLite`, replanning by repairing the backward search: after cells change, only the cells whose cost to
  the goal changed and whose key is below the robot's (plus the band) are expanded, each at most twice: O(M log N)
  for M such cells. M is small when the change is near the robot and off its way, and grows with its distance from
  it, since every cell between the robot and the change whose way to the goal crossed it must be raised and
  lowered; a raised cell costs about twice an A* expansion (the costs of the cells that relied on it are recomputed
  from their neighbours).
- :class:`DStarLite`, replanning by the guided search: A* from the robot with the backward search's
  costs to the goal as heuristic, computed before the new obstacles: exact where they changed nothing, lower bounds
  everywhere (costs only grow when cells are blocked) and consistent. O(F log F) for the F cells whose cost from the
  robot plus old cost to the goal is below the new optimum: the cells within the detour's extra length of an old
  shortest path through them, plus the new path. F is small for a local detour; a wall that closes a passage
  makes every cell that led to it look as good as before, and F approaches A*'s count.
- The choice between the two: a breadth-first walk down the backward search's tree from the blocked cells, counting
  the cells the repair would raise, O(B) with B the number of steps from the robot to the goal: the repair is run
  when it would raise fewer cells than B, which the guided search expands at the least, and the robot is not among
  them. A wall across the robot's way is thus always searched round by the guided search first (near the robot
  both are cheap; far from it only the guided search is), and given to the backward search once the robot's old
  way to the goal no longer crosses it.

References
----------
Hart, P. E., Nilsson, N. J., Raphael, B. (1968). A formal basis for the heuristic determination of minimum cost
paths. IEEE Trans. SSC 4(2), 100-107. doi:10.1109/TSSC.1968.300136
Koenig, S., Likhachev, M. (2002). D* Lite. AAAI-02, 476-483 (the optimised version, Figure 4).
Koenig, S., Likhachev, M., Furcy, D. (2004). Lifelong Planning A*. Artificial Intelligence 155, 93-146.
doi:10.1016/j.artint.2003.12.001 (the invariants behind the guided search's bound)
Koenig, S., Likhachev, M. (2005). Adaptive A*. AAMAS-05, 1311-1312 (the costs of an earlier search as heuristic).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from .._validation import check_positive
from ..errors import InputError, PlanningError
from . import _planning_kernels as kernels

__all__ = ["GridPath", "CostBounds", "astar", "DStarLite", "path_length", "check_cell"]


@dataclass(frozen=True)
class GridPath:
    """A path through a grid.

    Attributes
    ----------
    cells : (K, 2) int64 ndarray
        (row, col) of every cell from start to goal, consecutive cells 8-neighbours.
    length_m : float
        Sum of the step lengths, metres.
    n_expanded : int
        Cells the search expanded (for :class:`DStarLite`: in this call only).
    planner : str
        ``'astar'``; for :class:`DStarLite` ``'dstar_lite'`` (the backward search, repaired) or ``'guided_astar'``
        (A* from the robot guided by the backward search's costs).
    """

    cells: np.ndarray
    length_m: float
    n_expanded: int
    planner: str


@dataclass(frozen=True)
class CostBounds:
    """What a :class:`DStarLite` planner's backward search knows of every cell's cost to the goal.

    Attributes
    ----------
    lower_m : (H, W) float64 ndarray
        Lower bounds of the costs to the goal, metres (inf: the goal is unreachable from the cell); the guided
        search's heuristic. Valid on the grid the backward search knows, and on the current grid as long as no
        pending cell was freed.
    exact : (H, W) bool ndarray
        Cells whose bound is their exact cost on the grid the backward search knows (settled cells).
    """

    lower_m: np.ndarray
    exact: np.ndarray


def _as_free(free) -> np.ndarray:
    arr = np.asarray(free)
    if arr.ndim != 2 or min(arr.shape) < 1:
        raise InputError(f"the occupancy grid must be a 2D array of traversable flags; got shape {arr.shape}")
    if arr.dtype != np.bool_:
        if arr.dtype.kind not in "biu":
            raise InputError(f"the occupancy grid must be boolean (True = traversable); got dtype {arr.dtype}")
        arr = arr != 0
    return np.ascontiguousarray(arr)


def _spacing(spacing) -> tuple[float, float]:
    try:
        dy, dx = (float(v) for v in spacing)
    except (TypeError, ValueError):
        raise InputError(f"spacing must be (dy, dx) in metres; got {spacing!r}") from None
    return check_positive(dy, "spacing dy"), check_positive(dx, "spacing dx")


def check_cell(free, cell, name: str) -> tuple[int, int]:
    """Validate a (row, col) cell: integers inside the grid and traversable.

    Parameters
    ----------
    free : (H, W) bool ndarray
    cell : (int, int)
    name : str
        What the cell is, for messages (``'start'``, ``'goal'``).

    Returns
    -------
    (int, int)

    Raises
    ------
    InputError
        Outside the grid, or on a blocked cell.
    """
    try:
        r, c = (int(v) for v in cell)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be (row, col) integers; got {cell!r}") from None
    h, w = free.shape
    if not (0 <= r < h and 0 <= c < w):
        raise InputError(f"{name} ({r}, {c}) is outside the {h} x {w} grid (rows 0-{h - 1}, cols 0-{w - 1})")
    if not free[r, c]:
        raise InputError(f"{name} ({r}, {c}) is on an obstacle (a cell that is not traversable); choose a free cell")
    return r, c


def path_length(cells, spacing) -> float:
    """Length in metres of a path of 8-connected cells.

    Parameters
    ----------
    cells : (K, 2) array_like of int
    spacing : (dy, dx)
        Cell height and width, metres.

    Returns
    -------
    float
    """
    dy, dx = _spacing(spacing)
    d = np.abs(np.diff(np.asarray(cells, dtype=np.float64), axis=0))
    return float(np.sum(np.hypot(d[:, 0] * dy, d[:, 1] * dx)))


def _no_path(free, start, goal, corner_cutting) -> PlanningError:
    """The error when start and goal are not connected, naming the goal's region cell nearest to the start."""
    structure = np.ones((3, 3), bool) if corner_cutting else np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], bool)
    labels, _ = ndimage.label(free, structure=structure)
    region = labels == labels[goal]
    size_start = int(np.count_nonzero(labels == labels[start]))
    _, (rr, cc) = ndimage.distance_transform_edt(~region, return_indices=True)
    near = (int(rr[start]), int(cc[start]))
    return PlanningError(f"no path from start {start} to goal {goal} through traversable cells: the start's region "
                         f"has {size_start} cells and does not reach the goal; the goal's region comes nearest to "
                         f"the start at {near} (or relax the traversability limit)")


_KM_LIMIT = 1 << 60  # D* Lite resets km above this (keys stay below kernels.INF = 2^62)


def _step_costs(spacing, n_cells: int) -> np.ndarray:
    """Integer step costs ``(dy, dx, diag)``: the diagonal is 2^b units, b = min(40, 59 - bits of N), so sums over
    any path (at most N steps), plus heuristics, stay below 2^60; one unit is 2^-40 of a diagonal step on grids up
    to 2^19 cells, far below the smallest difference between two path lengths that count (float metres would
    break exact ties between equally long paths by rounding, in a different order depending on how each sum was
    formed)."""
    dy, dx = spacing
    diag = float(np.hypot(dy, dx))
    bits = min(40, 59 - int(n_cells).bit_length())
    unit = diag / 2.0 ** bits
    cost = np.array([round(dy / unit), round(dx / unit), round(diag / unit)], dtype=np.int64)
    if cost[:2].min() < 64:
        raise InputError(f"cells of {dy} x {dx} m are too elongated for exact path costs; resample the grid")
    return cost


def _metres_per_unit(spacing, cost) -> float:
    """The length of one integer cost unit, metres."""
    return float(np.hypot(*spacing)) / float(cost[2])


def astar(free, start, goal, *, spacing=(1.0, 1.0), corner_cutting: bool = True) -> GridPath:
    """Shortest 8-connected path by A* with the octile-distance heuristic.

    Parameters
    ----------
    free : (H, W) array_like of bool
        True where the robot may be.
    start, goal : (int, int)
        (row, col) cells.
    spacing : (dy, dx)
        Cell height and width, metres.
    corner_cutting : bool
        Allow diagonal steps between two blocked cells.

    Returns
    -------
    GridPath
        The shortest path (ties go to the cell farther from the start).

    Raises
    ------
    InputError
        Bad grid, start or goal outside the grid or on an obstacle.
    PlanningError
        No path exists.

    References
    ----------
    Hart, Nilsson & Raphael (1968).
    """
    grid = _as_free(free)
    metres = _spacing(spacing)
    s = check_cell(grid, start, "start")
    g = check_cell(grid, goal, "goal")
    n, w = grid.size, grid.shape[1]
    start_flat, goal_flat = s[0] * w + s[1], g[0] * w + g[1]
    parent = np.empty(n, dtype=np.int64)
    total, expanded, _ = kernels.run_forward_search(
        grid, start_flat, goal_flat, _step_costs(metres, n), bool(corner_cutting), np.empty(n, dtype=np.int64), parent,
        np.zeros(n, dtype=np.int64), 0, np.zeros(1, dtype=np.int64), np.zeros(5, dtype=np.int64), [])
    if total >= kernels.INF:
        raise _no_path(grid, s, g, corner_cutting)
    flat = kernels.trace_back(parent, start_flat, goal_flat)
    cells = np.column_stack([flat // w, flat % w])
    return GridPath(cells, path_length(cells, metres), int(expanded), "astar")


class DStarLite:
    """Incremental shortest paths: plan once, then replan cheaply as cells become blocked or free and as the robot
    moves.

    Two searches share the work. D* Lite searches back from the goal and keeps every cell's cost to the goal; when
    cells change it repairs only the costs they affect, in order of relevance to the robot's cell: cheap when the
    change is near the robot, but a wall far ahead raises the cost of every cell between the robot and the wall
    whose way to the goal crossed it, and all of them must be repaired; so does a wall that closes a passage just in
    front of the robot, for the whole region behind it. So when cells were only blocked (none freed) and the repair
    would raise the robot's own cost or more cells than there are steps from the robot to the goal, :meth:`plan`
    leaves the backward search as it was (the changed cells stay pending) and runs A* forward from the robot on the
    current grid, with the backward search's costs as heuristic: computed with fewer obstacles, they are lower
    bounds, exact where the new obstacles changed nothing, so A* runs straight along the old path to the obstacle,
    round it and back onto the old path, expanding only the cells whose old way to the goal is about as short as the
    detour. Where the backward search has not settled a cell, the bound comes from its queue: a cell whose key is
    not below the queue's smallest has a cost to the goal of at least that key less km and the heuristic from the
    robot (the invariant of LPA* / D* Lite's loop, which holds whenever the loop stops). Pending cells are given to
    the backward search at the first :meth:`plan` where the repair has become cheap (the robot's old way to the goal
    no longer crosses them, e.g. once it is on its way round them), or where a cell was freed.

    Parameters
    ----------
    free : (H, W) array_like of bool
        True where the robot may be (copied; change it with :meth:`set_cells`).
    start, goal : (int, int)
        (row, col) cells.
    spacing : (dy, dx)
        Cell height and width, metres.
    corner_cutting : bool
        Allow diagonal steps between two blocked cells.
    forward_search : bool
        Use the guided forward search for obstacles far from the robot (default). ``False`` gives plain D* Lite:
        every change is repaired in the backward search at once.
    lookahead : float
        The backward search carries on until its queue's smallest key exceeds the robot's by this fraction of the
        robot's cost, in [0, 1] (0: the paper's loop). The cells round the robot are then settled, with exact
        costs, and the guided search needs no weaker bound near the robot for detours up to that fraction; 1 %
        costs 2-15 % more expansions in the first plan (real DEM, generated grids).

    Raises
    ------
    InputError
        Bad grid, start or goal outside the grid or on an obstacle, a lookahead outside [0, 1].

    Notes
    -----
    Memory: 6 integer arrays of N entries for D* Lite (g, rhs, an indexed heap with one entry per cell and its
    positions), 3 for the guided search, and two copies of the grid (the current one and the one the backward
    search knows). See the module's notes for the complexity of each step.

    Examples
    --------
    >>> import numpy as np
    >>> from seismo3d.terrain import DStarLite
    >>> free = np.ones((50, 50), bool)
    >>> planner = DStarLite(free, (0, 0), (49, 49))
    >>> first = planner.plan()
    >>> planner.set_cells([(25, c) for c in range(10, 50)], free=False)
    40
    >>> second = planner.plan()
    >>> second.length_m > first.length_m
    True

    References
    ----------
    Koenig, S., Likhachev, M. (2002). D* Lite. AAAI-02, 476-483.
    Koenig, S., Likhachev, M., Furcy, D. (2004). Lifelong Planning A*. Artificial Intelligence 155, 93-146.
    Koenig, S., Likhachev, M. (2005). Adaptive A*. AAMAS-05, 1311-1312 (the costs of an earlier search as an
    admissible, consistent heuristic when step costs only grow).
    """

    def __init__(self, free, start, goal, *, spacing=(1.0, 1.0), corner_cutting: bool = True,
                 forward_search: bool = True, lookahead: float = 0.01):
        self._free = _as_free(free).copy()
        self._spacing = _spacing(spacing)
        self._corner = bool(corner_cutting)
        self._forward = bool(forward_search)
        self._lookahead = float(lookahead)
        if not 0.0 <= self._lookahead <= 1.0:
            raise InputError(f"lookahead must be a fraction of the robot's cost in [0, 1]; got {lookahead!r}")
        s = check_cell(self._free, start, "start")
        g = check_cell(self._free, goal, "goal")
        h, w = self._free.shape
        n = h * w
        self._w = w
        self._cost = _step_costs(self._spacing, n)
        self._start = s[0] * w + s[1]
        self._goal = g[0] * w + g[1]
        # the backward search (D* Lite) and the grid it knows
        self._known = self._free.copy()
        self._pending = np.zeros(0, dtype=np.int64)
        self._last = self._start
        self._km = 0
        self._g = np.full(n, kernels.INF, dtype=np.int64)
        self._rhs = np.full(n, kernels.INF, dtype=np.int64)
        self._k1 = np.empty(n, dtype=np.int64)
        self._k2 = np.empty(n, dtype=np.int64)
        self._nodes = np.empty(n, dtype=np.int64)
        self._pos = np.full(n, -1, dtype=np.int64)
        self._rhs[self._goal] = 0
        key = kernels.octile(s[0], s[1], g[0], g[1], self._cost)
        self._size = kernels.heap_set(self._k1, self._k2, self._nodes, self._pos, 0, self._goal, key, 0)
        self._certificate = np.zeros(5, dtype=np.int64)  # none until the first backward search
        # work arrays of the forward search, written once here so that their pages are mapped before a replan
        self._fwd_g = np.full(n, kernels.INF, dtype=np.int64)
        self._fwd_parent = np.full(n, -1, dtype=np.int64)
        self._fwd_stamp = np.full(n, 0, dtype=np.int64)
        self._generation = 0
        self._fwd_queue = []  # the forward search's queue (allocated at its first search)
        self.n_expanded_total = 0

    @property
    def free(self) -> np.ndarray:
        """(H, W) bool: the planner's current grid (read-only view)."""
        view = self._free.view()
        view.flags.writeable = False
        return view

    @property
    def start(self) -> tuple[int, int]:
        """The robot's current cell."""
        return divmod(self._start, self._w)

    @property
    def n_pending(self) -> int:
        """Changed cells the backward search has not been given yet."""
        return int(len(self._outstanding()))

    def cost_bounds(self) -> CostBounds:
        """The backward search's costs to the goal, as the guided search reads them (see :class:`CostBounds`).

        Returns
        -------
        CostBounds
            All zeros and nothing exact before the first :meth:`plan`.
        """
        h, w = self._free.shape
        lower = np.empty(h * w, dtype=np.int64)
        exact = np.empty(h * w, dtype=np.bool_)
        kernels.bound_field(h, w, self._goal, self._cost, self._g, self._certificate, lower, exact)
        if self._certificate[0] == 0:
            lower[:] = 0
        metres = np.where(lower >= kernels.INF, np.inf, lower * _metres_per_unit(self._spacing, self._cost))
        return CostBounds(metres.reshape(h, w), exact.reshape(h, w))

    def plan(self) -> GridPath:
        """The shortest path from the current start to the goal on the current grid.

        Repairs the backward search with the pending changes when the repair would not raise the robot's cost and
        would raise fewer cells than there are steps from the robot to the goal, when a cell was freed, or with
        ``forward_search=False``; otherwise
        searches forward from the robot, guided by the backward search (``GridPath.planner`` says which:
        ``'dstar_lite'`` or ``'guided_astar'``).

        Raises
        ------
        PlanningError
            No path exists (the planner stays usable: free cells again and call :meth:`plan`).
        """
        pending = self._outstanding()
        if len(pending) and self._repair_first(pending):
            self._repair(pending)
            pending = pending[:0]
        if len(pending) == 0:
            expanded = self._compute()
            flat = kernels.descend(self._known, self._g, self._rhs, self._start, self._goal, self._cost,
                                   self._corner)
            planner = "dstar_lite"
        else:
            flat, expanded = self._guided_search()
            planner = "guided_astar"
        self.n_expanded_total += int(expanded)
        if flat.size == 0:
            raise _no_path(self._free, self.start, divmod(self._goal, self._w), self._corner)
        if flat[-1] != self._goal:
            raise RuntimeError("internal error: the path does not reach the goal")
        cells = np.column_stack([flat // self._w, flat % self._w])
        return GridPath(cells, path_length(cells, self._spacing), int(expanded), planner)

    def set_cells(self, cells, *, free: bool) -> int:
        """Mark cells as blocked (``free=False``) or traversable (``free=True``) before the next :meth:`plan`.

        Parameters
        ----------
        cells : (K, 2) array_like of int
            (row, col) cells; those outside the grid are ignored.
        free : bool

        Returns
        -------
        int
            The number of cells that changed.

        Raises
        ------
        InputError
            When blocking the current start or the goal.
        """
        arr = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
        h, w = self._free.shape
        inside = (arr[:, 0] >= 0) & (arr[:, 0] < h) & (arr[:, 1] >= 0) & (arr[:, 1] < w)
        arr = arr[inside]
        changed = arr[self._free[arr[:, 0], arr[:, 1]] != bool(free)]
        if len(changed) == 0:
            return 0
        flat = np.unique(changed[:, 0] * w + changed[:, 1])
        if not free and (np.any(flat == self._start) or np.any(flat == self._goal)):
            raise InputError("cannot block the robot's current cell or the goal")
        self._free.ravel()[flat] = bool(free)
        self._pending = np.union1d(self._pending, flat)
        return int(len(flat))

    def move_to(self, cell) -> None:
        """Move the robot (the start) to ``cell``, e.g. the next cells of the last path.

        Raises
        ------
        InputError
            Outside the grid or on an obstacle.
        """
        r, c = check_cell(self._free, cell, "the new start")
        self._start = r * self._w + c

    # ---- steps of plan() ----------------------------------------------------------------------------------------

    def _outstanding(self) -> np.ndarray:
        """Pending cells that still differ from the grid the backward search knows (a cell blocked then freed
        again is no change)."""
        p = self._pending
        self._pending = p[self._free.ravel()[p] != self._known.ravel()[p]]
        return self._pending

    def _repair_first(self, pending) -> bool:
        """Whether the backward search should take the pending changes now: always when a cell was freed (its
        costs are then no lower bounds) or when it has not searched yet; otherwise when it would not raise the
        robot's cost and would raise fewer cells than the forward search expands at the least (the steps from the
        robot to the goal)."""
        if not self._forward or self._certificate[0] == 0 or self._free.ravel()[pending].any():
            return True
        (sr, sc), (gr, gc) = self.start, divmod(self._goal, self._w)
        budget = max(abs(sr - gr), abs(sc - gc)) + 1
        self._generation += 1
        raised = kernels.count_raised(self._known, self._g, self._rhs, pending, self._start, self._cost,
                                      self._corner, self._lookahead, budget, self._fwd_stamp, self._generation)
        return bool(raised < budget)

    def _sync_start(self) -> None:
        """Keys queued before the robot moved stay lower bounds when km grows by the heuristic distance moved
        (Koenig & Likhachev 2002, Fig. 4); km is reset, and the queue's keys recomputed, before it could
        overflow."""
        if self._start != self._last:
            lr, lc = divmod(self._last, self._w)
            sr, sc = self.start
            self._km += int(kernels.octile(lr, lc, sr, sc, self._cost))
            self._last = self._start
        if self._km > _KM_LIMIT:
            kernels.dstar_rekey(self._g, self._rhs, self._k1, self._k2, self._nodes, self._pos, self._size,
                                self._start, self._w, self._cost)
            self._km = 0

    def _repair(self, pending) -> None:
        """Give the pending changes to the backward search (it recomputes the affected cells' rhs and queues
        them)."""
        self._sync_start()
        self._known.ravel()[pending] = self._free.ravel()[pending]
        self._size = kernels.dstar_cells_changed(
            self._known, self._g, self._rhs, self._k1, self._k2, self._nodes, self._pos, self._size, pending,
            self._start, self._goal, self._km, self._cost, self._corner)
        self._pending = pending[:0]

    def _compute(self) -> int:
        """D* Lite's ComputeShortestPath; records the certificate the guided search needs. Returns expansions."""
        self._sync_start()
        self._size, expanded, top = kernels.dstar_compute(
            self._known, self._g, self._rhs, self._k1, self._k2, self._nodes, self._pos, self._size, self._start,
            self._goal, self._km, self._cost, self._corner, self._lookahead)
        sr, sc = self.start
        self._certificate[:] = (1, top, self._km, sr, sc)
        return int(expanded)

    def _guided_search(self):
        """A* from the robot on the current grid, its heuristic the backward search's costs to the goal."""
        total, expanded, self._generation = kernels.run_forward_search(
            self._free, self._start, self._goal, self._cost, self._corner, self._fwd_g, self._fwd_parent,
            self._fwd_stamp, self._generation, self._g, self._certificate, self._fwd_queue)
        if total >= kernels.INF:
            return np.zeros(0, dtype=np.int64), expanded
        return kernels.trace_back(self._fwd_parent, self._start, self._goal), expanded
