"""Shortest paths on 8-connected occupancy grids: A* for one query, D* Lite for replanning as obstacles appear.

A grid is a (H, W) boolean array of traversable cells with metric cell sizes ``(dy, dx)``; a step to one of the 8
neighbours costs its length in metres (``dy``, ``dx`` or ``sqrt(dx^2 + dy^2)``), so a path's cost is its horizontal
length. A diagonal step joins two traversable cells even when both cells beside it are blocked, as in
scikit-image's ``MCP_Geometric``; ``corner_cutting=False`` forbids such steps (a robot of non-zero width cannot
squeeze between two obstacles touching at a corner; the grid is then 4-connected for reachability).

Complexity, with N cells:

- :func:`astar`: O(N log N) time and O(N) memory in the worst case; the heuristic (the octile distance, exact on an
  empty grid, hence admissible and consistent) makes it expand only the cells whose cost plus heuristic is below
  the optimum, often far fewer than N.
- :class:`DStarLite`: the first plan costs what A* does (searching from the goal); after k cells change, replanning
  expands only cells whose cost to the goal changed and that can matter for the current start, each at most twice:
  O(M log M) for M such cells, typically a small fraction of N when obstacles appear near the robot.

References
----------
Hart, P. E., Nilsson, N. J., Raphael, B. (1968). A formal basis for the heuristic determination of minimum cost
paths. IEEE Trans. SSC 4(2), 100-107. doi:10.1109/TSSC.1968.300136
Koenig, S., Likhachev, M. (2002). D* Lite. AAAI-02, 476-483 (the optimised version, Figure 4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from .._validation import check_positive
from ..errors import InputError, PlanningError
from . import _planning_kernels as kernels

__all__ = ["GridPath", "astar", "DStarLite", "path_length", "check_cell"]


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
        Cells the search expanded (for D* Lite: in this call only).
    planner : str
        ``'astar'`` or ``'dstar_lite'``.
    """

    cells: np.ndarray
    length_m: float
    n_expanded: int
    planner: str


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
        The shortest path (ties broken arbitrarily).

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
    dy, dx = _spacing(spacing)
    s = check_cell(grid, start, "start")
    g = check_cell(grid, goal, "goal")
    w = grid.shape[1]
    parent, cost, expanded = kernels.astar(grid, s[0] * w + s[1], g[0] * w + g[1], dy, dx, bool(corner_cutting))
    goal_flat = g[0] * w + g[1]
    if not np.isfinite(cost[goal_flat]):
        raise _no_path(grid, s, g, corner_cutting)
    chain = [goal_flat]
    while chain[-1] != s[0] * w + s[1]:
        chain.append(int(parent[chain[-1]]))
    flat = np.array(chain[::-1], dtype=np.int64)
    cells = np.column_stack([flat // w, flat % w])
    return GridPath(cells, float(cost[goal_flat]), int(expanded), "astar")


class DStarLite:
    """Incremental shortest paths (D* Lite): plan once, then replan cheaply as cells become blocked or free and as
    the robot moves.

    The search runs from the goal, so the cost-to-goal of every cell it settled stays valid; when cells change,
    only the costs they affect are repaired, in order of relevance to the robot's current cell.

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
    heap_capacity : int, optional
        Entries of the priority queue's array (default 4 N). Outdated entries stay in it until popped; when it is
        nearly full they are dropped and the heap rebuilt, so any capacity of at least N + 32 works.

    Raises
    ------
    InputError
        Bad grid, start or goal outside the grid or on an obstacle, a capacity below N + 32.

    Examples
    --------
    >>> import numpy as np
    >>> from seismo3d.terrain import DStarLite
    >>> free = np.ones((50, 50), bool)
    >>> planner = DStarLite(free, (0, 0), (49, 49))
    >>> first = planner.plan()
    >>> planner.set_cells([(25, c) for c in range(10, 50)], free=False)
    >>> second = planner.plan()
    >>> second.length_m > first.length_m
    True

    References
    ----------
    Koenig, S., Likhachev, M. (2002). D* Lite. AAAI-02, 476-483.
    """

    def __init__(self, free, start, goal, *, spacing=(1.0, 1.0), corner_cutting: bool = True,
                 heap_capacity: int | None = None):
        self._free = _as_free(free).copy()
        self._dy, self._dx = _spacing(spacing)
        self._corner = bool(corner_cutting)
        s = check_cell(self._free, start, "start")
        g = check_cell(self._free, goal, "goal")
        h, w = self._free.shape
        n = h * w
        self._w = w
        self._start = s[0] * w + s[1]
        self._goal = g[0] * w + g[1]
        self._last = self._start
        self._km = 0.0
        self._g = np.full(n, np.inf)
        self._rhs = np.full(n, np.inf)
        self._open_k1 = np.zeros(n)
        self._open_k2 = np.zeros(n)
        self._in_open = np.zeros(n, dtype=np.bool_)
        cap = 4 * n + 64 if heap_capacity is None else int(heap_capacity)
        if cap < n + 32:  # live entries are at most n; a step pushes at most 9 between two fullness checks
            raise InputError(f"heap_capacity must be at least the number of cells + 32 ({n + 32}); got {cap}")
        self._k1 = np.empty(cap)
        self._k2 = np.empty(cap)
        self._nodes = np.empty(cap, dtype=np.int64)
        self._rhs[self._goal] = 0.0
        diag = np.hypot(self._dx, self._dy)
        key = kernels.octile(s[0], s[1], g[0], g[1], self._dy, self._dx, diag)
        self._in_open[self._goal] = True
        self._open_k1[self._goal] = key
        self._open_k2[self._goal] = 0.0
        self._size = kernels.heap_push(self._k1, self._k2, self._nodes, 0, key, 0.0, self._goal)
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

    def plan(self) -> GridPath:
        """Repair the costs the changes since the last call affect, and return the shortest path from the current
        start to the goal.

        Raises
        ------
        PlanningError
            No path exists (the planner stays usable: free cells again and call :meth:`plan`).
        """
        self._size, expanded = kernels.dstar_compute(
            self._free, self._g, self._rhs, self._open_k1, self._open_k2, self._in_open, self._k1, self._k2,
            self._nodes, self._size, self._start, self._goal, self._km, self._dy, self._dx, self._corner)
        self.n_expanded_total += int(expanded)
        flat = kernels.descend(self._free, self._g, self._rhs, self._start, self._goal, self._dy, self._dx,
                               self._corner)
        if flat.size == 0:
            raise _no_path(self._free, self.start, divmod(self._goal, self._w), self._corner)
        cells = np.column_stack([flat // self._w, flat % self._w])
        length = min(self._g[self._start], self._rhs[self._start])
        return GridPath(cells, float(length), int(expanded), "dstar_lite")

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
        flat = changed[:, 0] * w + changed[:, 1]
        if not free and (np.any(flat == self._start) or np.any(flat == self._goal)):
            raise InputError("cannot block the robot's current cell or the goal")
        self._free[changed[:, 0], changed[:, 1]] = bool(free)
        # keys queued before the robot moved stay lower bounds when km grows by the heuristic distance moved
        lr, lc = divmod(self._last, self._w)
        sr, sc = divmod(self._start, self._w)
        self._km += kernels.octile(lr, lc, sr, sc, self._dy, self._dx, np.hypot(self._dx, self._dy))
        self._last = self._start
        self._size = kernels.dstar_cells_changed(
            self._free, self._g, self._rhs, self._open_k1, self._open_k2, self._in_open, self._k1, self._k2,
            self._nodes, self._size, np.unique(flat), self._start, self._goal, self._km, self._dy, self._dx,
            self._corner)
        return int(len(changed))

    def move_to(self, cell) -> None:
        """Move the robot (the start) to ``cell``, e.g. the next cells of the last path.

        Raises
        ------
        InputError
            Outside the grid or on an obstacle.
        """
        r, c = check_cell(self._free, cell, "the new start")
        self._start = r * self._w + c
