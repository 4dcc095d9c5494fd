"""Fault skins: thinned fault samples linked into fault surfaces (curves in 2D), one fault one object.

After Hale (2013): every thinned fault sample (a *cell*, with the normal of its fault plane) looks for its best
neighbour above and below it down the fault's dip, and left and right along its strike, among the cells near its own
plane whose normals agree with its own; skins grow over these links from the strongest cells, keeping to one mean
orientation. The search reaches a few samples along the fault, so a skin bridges small gaps, and two faults that
cross or meet stay apart because their cells' normals differ. Skins are kept when they hold a cell above the upper
threshold and are large enough.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from ...._threads import run_threads
from ...._validation import check_positive
from ....errors import InputError
from ... import _kernels
from ..result import Fault, check_fault_arrays, fault_frames, fault_normals
from .skin_merging import local_normal, merge_coplanar
from .skin_splits import split_forks, split_opposite_dips

__all__ = ["SkinOptions", "fault_skins", "image_cells", "skins_from_cells"]


@dataclass(frozen=True)
class SkinOptions:
    """Options of :func:`fault_skins`.

    Attributes
    ----------
    lateral_reach : int
        How far a cell looks for neighbours across traces (inline and crossline), traces.
    vertical_reach : int
        How far a cell looks for neighbours along the sample axis, samples: the longest gap down the dip a skin
        bridges is about this minus one.
    max_plane_distance : float
        A neighbour lies within this distance of the cell's fault plane and the cell within this distance of the
        neighbour's, samples.
    max_angle : float
        Largest angle between the normals of linked cells, degrees.
    min_size : int, optional
        Smallest skin kept, in cells. None: a fault must span a tenth of the data's height: in 2D 10 % of the
        samples per trace (at least 15); in 3D 1 % of the smaller vertical face, n_samples x min(n_inlines,
        n_xlines) (at least 100; a slab of a few inlines holds only short faults across it). On the 1501-sample
        Penobscot line this drops 495 of 561 skins, short ones in its chaotic deep section, and none of the faults
        of the 180-sample Costa Rica section.
    min_height : int, optional
        Smallest extent of a skin along the sample axis, samples. None: as tall as the smallest 2D fault (10 % of
        the samples per trace, at least 15), so that a 3D surface is kept only when each of its sections would
        be. Without it, a slab of nearly identical inlines turns every short 2D fragment into a surface of enough
        cells (on the 18 clipped Penobscot inlines: 1240 skins, 123 at least 153 samples tall).
    merge_gap : float
        Two skins whose cells come within this distance (samples) are merged when they are coplanar (see
        ``merge_angle`` and ``merge_offset``): one fault cut by a younger fault, or broken by a gap longer than the
        neighbour search, stays one fault (0: no merging).
    merge_offset : float
        Largest distance across the fault between the two skins' closest cells, measured along the normals of planes
        (lines in 2D) fitted to each skin near them, samples.
    merge_angle : float
        Largest angle between the normals of the two skins' fitted planes, degrees. With ``merge_gap`` 12 and 20
        degrees (formerly 8 and 10) a fault that bends where its pieces meet stays one fault: on Teapot tpd the
        near-vertical fault at traces 210-220 was two pieces (9 faults, 8 now). On 20 generated 256 x 160 sections
        of 4 faults and two 96^3 cubes (every candidate) no setting from 10 to 25 degrees merged two true faults,
        and 12 samples left one true fault fewer in two pieces; the F3 inlines' scores are unchanged (0.587 /
        0.445 / 0.500).
    max_shape_angle : float
        Largest angle between the plane (line in 2D) fitted to all of a skin's cells and the mean of the cells' own
        fault planes, degrees. A fault's cells lie on the plane they are oriented along; a skin that grew into a
        web of crossing or en-echelon pieces does not (on the 18 clipped Penobscot inlines, webs of short steep
        pieces copied across the nearly identical inlines made sheets parallel to the inline sections, 43-61 deg
        from their cells' planes; 44 of 121 skins are within 30 deg). None: no check.
    split_angle : float or None
        2D: a skin whose cells dip two opposite ways, in branches whose lines differ by at least this angle (degrees),
        is split into them, each judged by its own throw (:func:`~.skin_splits.split_opposite_dips`); None: no split
        (3D: never). Leave-one-survey-out: F3 F1 0.494 at 10-30 degrees, 0.490 at 5; Great South Basin 0.829 at each.
    split_forks : bool
        2D: a skin that forks into branches along lines at least ``split_angle`` apart (None: never) is split into
        them, the parts above and below going with the branch they continue (:func:`~.skin_splits.split_forks`).

    Raises
    ------
    InputError
        A value out of range.
    """

    lateral_reach: int = 2
    vertical_reach: int = 6
    max_plane_distance: float = 1.0
    max_angle: float = 30.0
    min_size: int | None = None
    min_height: int | None = None
    merge_gap: float = 12.0
    merge_offset: float = 4.0
    merge_angle: float = 20.0
    max_shape_angle: float | None = 30.0
    split_angle: float | None = 10.0
    split_forks: bool = True

    def __post_init__(self):
        for name in ("lateral_reach", "vertical_reach"):
            value = getattr(self, name)
            if isinstance(value, bool) or int(value) != value or value < 1:
                raise InputError(f"{name} must be an integer >= 1; got {value!r}")
        check_positive(self.max_plane_distance, "max_plane_distance")
        if not 0.0 < float(self.max_angle) < 90.0:
            raise InputError(f"max_angle must be in (0, 90) degrees; got {self.max_angle!r}")
        if self.min_size is not None and (isinstance(self.min_size, bool) or int(self.min_size) != self.min_size
                                          or self.min_size < 1):
            raise InputError(f"min_size must be an integer >= 1 or None; got {self.min_size!r}")
        if self.min_height is not None and (isinstance(self.min_height, bool)
                                            or int(self.min_height) != self.min_height or self.min_height < 1):
            raise InputError(f"min_height must be an integer >= 1 or None; got {self.min_height!r}")
        check_positive(self.merge_gap, "merge_gap", allow_zero=True)
        check_positive(self.merge_offset, "merge_offset")
        if not 0.0 < float(self.merge_angle) < 90.0:
            raise InputError(f"merge_angle must be in (0, 90) degrees; got {self.merge_angle!r}")
        if self.max_shape_angle is not None and not 0.0 < float(self.max_shape_angle) <= 90.0:
            raise InputError(f"max_shape_angle must be in (0, 90] degrees or None; got {self.max_shape_angle!r}")
        if self.split_angle is not None and not 0.0 < float(self.split_angle) < 90.0:
            raise InputError(f"split_angle must be in (0, 90) degrees or None; got {self.split_angle!r}")
        if not isinstance(self.split_forks, bool):
            raise InputError(f"split_forks must be True or False (a bool); got {self.split_forks!r}")

    def smallest(self, shape: tuple) -> int:
        """The smallest skin kept in an image of ``shape``, cells."""
        if self.min_size is not None:
            return int(self.min_size)
        if len(shape) == 2:
            return max(15, int(round(0.1 * shape[-1])))
        return max(100, int(round(0.01 * shape[-1] * min(shape[0], shape[1]))))

    def shortest(self, shape: tuple) -> int:
        """The smallest extent along the sample axis of a skin kept in an image of ``shape``, samples."""
        if self.min_height is not None:
            return int(self.min_height)
        return max(15, int(round(0.1 * shape[-1])))


def _offset_ranks(two_d: bool, lateral: int, vertical: int) -> np.ndarray:
    """(2 lateral + 1, 2 lateral + 1 (1 in 2D), 2 vertical + 1) int64: the rank of each neighbour offset (+-lateral
    traces, +-vertical samples) when ordered nearest first (ties in C order), -1 for the cell itself. The neighbour
    search takes the first of equally near candidates in this order."""
    lat = np.arange(-lateral, lateral + 1)
    grids = np.meshgrid(lat, np.array([0]) if two_d else lat, np.arange(-vertical, vertical + 1), indexing="ij")
    length = sum(g.astype(np.float64) ** 2 for g in grids)
    rank = np.empty(length.size, np.int64)
    rank[np.argsort(length.ravel(), kind="stable")] = np.arange(length.size) - 1  # the cell itself (0) first
    rank = rank.reshape(length.shape)
    rank[lateral, 0 if two_d else lateral, vertical] = -1
    return rank


@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _best_neighbours(t, n_threads, points, frames, keys, shape, ranks, max_plane, cos_angle, best, scores, ranked,
                     starts, stops):
    # best[c, k]: cell c's nearest neighbour above (k = 0) and below (1) it down the dip, left (2) and right (3) of it
    # along the strike, or -1. A neighbour lies within max_plane of c's plane and c within max_plane of its plane,
    # their normals make an angle below acos(cos_angle), and the neighbour is in the direction's 90-degree cone;
    # distance is measured in c's plane, with the distance off the plane counted double, ties to the lower offset
    # rank (``ranks``, :func:`_offset_ranks`). Cells are found by their linear index in the cube of ``shape`` among
    # the sorted ``keys`` (no array of the cube's size): the cells of one trace within the vertical reach are one
    # range of keys. Cells t, t + n_threads, ... (best filled with -1 before); work arrays scores[t], ranked[t], and
    # starts[t], stops[t] (all 0): the range of each lateral offset, found by moving its two ends forward. The cells
    # come in key order, so for one offset the keys that bound the range never decrease: the ends move over the keys
    # once per offset and thread (the ranges of a binary search per cell and offset, in a tenth of its steps on the
    # 232 k cells of the generated 256^3 cube)
    n = points.shape[0]
    n0, n1, n2 = shape[0], shape[1], shape[2]
    lat0, lat1, vert = ranks.shape[0] // 2, ranks.shape[1] // 2, ranks.shape[2] // 2
    score, rank = scores[t], ranked[t]
    start, stop = starts[t], stops[t]
    for c in range(t, n, n_threads):
        px, py, pz = points[c, 0], points[c, 1], points[c, 2]
        ux, uy, uz = frames[c, 0, 0], frames[c, 0, 1], frames[c, 0, 2]
        vx, vy, vz = frames[c, 1, 0], frames[c, 1, 1], frames[c, 1, 2]
        wx, wy, wz = frames[c, 2, 0], frames[c, 2, 1], frames[c, 2, 2]
        for k in range(4):
            score[k] = np.inf
            rank[k] = 0
        for ox in range(-lat0, lat0 + 1):
            qx = px + ox
            if qx < 0 or qx >= n0:
                continue
            for oy in range(-lat1, lat1 + 1):
                qy = py + oy
                if qy < 0 or qy >= n1:
                    continue
                base = (qx * n1 + qy) * n2
                slot = (ox + lat0) * (2 * lat1 + 1) + oy + lat1
                low = base + max(pz - vert, 0)  # the range: keys low .. high
                high = base + min(pz + vert, n2 - 1)
                first = start[slot]
                while first < n and keys[first] < low:
                    first += 1
                start[slot] = first
                last = max(stop[slot], first)
                while last < n and keys[last] <= high:
                    last += 1
                stop[slot] = last
                for q in range(first, last):
                    oz = keys[q] - base - pz
                    r = ranks[ox + lat0, oy + lat1, oz + vert]
                    if r < 0:  # c itself
                        continue
                    rx = float(ox)
                    ry = float(oy)
                    rz = float(oz)
                    off_c = rx * ux + ry * uy + rz * uz
                    if abs(off_c) > max_plane:
                        continue
                    if abs(rx * frames[q, 0, 0] + ry * frames[q, 0, 1] + rz * frames[q, 0, 2]) > max_plane:
                        continue
                    if abs(ux * frames[q, 0, 0] + uy * frames[q, 0, 1] + uz * frames[q, 0, 2]) < cos_angle:
                        continue
                    a = rx * vx + ry * vy + rz * vz
                    bs = rx * wx + ry * wy + rz * wz
                    d2 = a * a + bs * bs + 4.0 * off_c * off_c
                    if abs(a) >= abs(bs):
                        k = 0 if a < 0 else 1
                    else:
                        k = 2 if bs < 0 else 3
                    if d2 < score[k] or (d2 == score[k] and r < rank[k]):
                        score[k] = d2
                        rank[k] = r
                        best[c, k] = q


def grow_by_mean_normal(indptr, indices, normals, order, cos_mean):
    """Region growing over the neighbour graph (CSR ``indptr``, ``indices``; its edges already join only compatible
    normals): from the unassigned sample of highest likelihood (``order``), add neighbours whose normal (``normals``
    (n, dim) float64) is within acos(cos_mean) of the growing fault's mean normal, breadth first; (n,) int64 labels.
    The mean keeps a fault from drifting into another one through samples of intermediate orientation where two
    faults meet."""
    n_pts, dim = normals.shape
    label = np.full(n_pts, -1, np.int64)
    _grow_by_mean_normal(indptr, indices, normals, order, cos_mean, label, np.empty(n_pts, np.int64), np.zeros(dim))
    return label


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _grow_by_mean_normal(indptr, indices, normals, order, cos_mean, label, queue, mean):
    # grow_by_mean_normal's loop: label (all -1) takes the labels; queue and mean are work arrays (np.empty, np.full,
    # np.zeros in here each compiled a function of numba's of its own)
    dim = normals.shape[1]
    n_lab = 0
    for seed in order:
        if label[seed] >= 0:
            continue
        label[seed] = n_lab
        for d in range(dim):
            mean[d] = normals[seed, d]
        head = 0
        tail = 1
        queue[0] = seed
        while head < tail:
            i = queue[head]
            head += 1
            for e in range(indptr[i], indptr[i + 1]):
                j = indices[e]
                if label[j] >= 0:
                    continue
                dot = 0.0
                nm = 0.0
                for d in range(dim):
                    dot += normals[j, d] * mean[d]
                    nm += mean[d] * mean[d]
                if abs(dot) < cos_mean * math.sqrt(nm):
                    continue
                label[j] = n_lab
                sgn = 1.0 if dot >= 0 else -1.0
                for d in range(dim):
                    mean[d] += sgn * normals[j, d]
                queue[tail] = j
                tail += 1
        n_lab += 1


def _grow(best: np.ndarray, normals: np.ndarray, order: np.ndarray, cos_mean: float) -> np.ndarray:
    """Skins grown breadth first over the (undirected) neighbour links from the strongest cell not yet in a skin; a
    cell joins when its normal is within acos(cos_mean) of the skin's running mean normal (no drift through cells
    of intermediate orientation into another fault). ``best`` (n, 4) int32 the directed links of
    :func:`_best_neighbours`; returns the (n,) int64 skin labels."""
    n = best.shape[0]
    # undirected adjacency (CSR, up to 8 links a cell) built in place: 8 bytes a cell and 8 a link. Sorting the
    # links' index arrays with numpy instead peaked 142 MiB higher on the 683,362 cells (2.7 M links) of a
    # 400 x 400 x 500 cube, the largest part of the skins' memory there
    indptr = np.zeros(n + 1, np.int64)
    indices = np.empty(2 * int(np.count_nonzero(best >= 0)), np.int32)
    _undirected_links(best, indptr, indices)
    return grow_by_mean_normal(indptr, indices, normals, order, cos_mean)


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _undirected_links(best, indptr, indices):
    # _grow's adjacency: link (c, q) of best[c, k] = q puts q in row c and c in row q; the links in the order of
    # (c, k), so each row lists its entries in that order (the growth's ties follow it). indptr (n + 1) zeros in,
    # rows' starts out: indptr[c + 1] counts row c; after the running sum indptr[c] is row c's cursor, which ends at
    # row c + 1's start, so a shift by one puts the starts in place (no array beside indices)
    n, m = best.shape
    for c in range(n):
        for k in range(m):
            q = best[c, k]
            if q >= 0:
                indptr[c + 1] += 1
                indptr[q + 1] += 1
    for c in range(n):
        indptr[c + 1] += indptr[c]
    for c in range(n):
        for k in range(m):
            q = best[c, k]
            if q >= 0:
                indices[indptr[c]] = q
                indptr[c] += 1
                indices[indptr[q]] = c
                indptr[q] += 1
    for c in range(n, 0, -1):  # each cursor ended at the next row's start
        indptr[c] = indptr[c - 1]
    indptr[0] = 0


def _edge_cells(best: np.ndarray, label: np.ndarray, two_d: bool) -> np.ndarray:
    """Cells on the edge of their skin: a direction (above / below, and left / right in 3D) without a neighbour of
    the same skin."""
    links = best[:, :2] if two_d else best
    same = (links >= 0) & (label[np.maximum(links, 0)] == label[:, None])
    return ~same.all(axis=1)


def _fits_its_cells(points: np.ndarray, normals: np.ndarray, two_d: bool, cos_max: float) -> bool:
    """Whether the plane (line in 2D) fitted to a skin's ``points`` (n, 3) lies within ``arccos(cos_max)`` of the
    mean of its cells' ``normals`` (n, 3; signs aligned to the first cell's)."""
    if points.shape[0] < 3:
        return True
    fitted = local_normal(points, two_d)
    normals = np.asarray(normals, dtype=np.float64)
    mean = (normals * np.sign(normals @ normals[0])[:, None]).sum(axis=0)
    norm = float(np.linalg.norm(mean))
    return norm == 0.0 or abs(float(fitted @ mean)) >= cos_max * norm


def heights(samples: np.ndarray, label: np.ndarray, roots: np.ndarray) -> np.ndarray:
    """Extent along the sample axis (max - min + 1) of the skins ``roots``, samples."""
    top = np.full(label.size, np.iinfo(np.int64).max, dtype=np.int64)
    bottom = np.full(label.size, -1, dtype=np.int64)
    np.minimum.at(top, label, samples)
    np.maximum.at(bottom, label, samples)
    return bottom[roots] - top[roots] + 1


def fault_skins(thin, strike_deg, dip_deg, *, lower: float, upper: float,
                options: SkinOptions | None = None) -> list[Fault]:
    """Link thinned fault samples into faults (skins): surfaces in 3D, curves in 2D.

    Cells are the samples of ``thin`` at or above ``lower``. Each cell links to its best neighbour in each of four
    directions in its own fault plane (above and below down the dip, left and right along the strike; see
    :class:`SkinOptions` for the search). Skins grow over these links breadth first from the strongest cell not yet
    in a skin, taking a linked cell only when its normal is within ``max_angle`` of the skin's mean normal, so that a
    skin does not drift through cells of intermediate orientation into another fault. A skin is kept when
    one of its cells reaches ``upper`` (hysteresis, as in Canny 1986), it has at least
    :meth:`SkinOptions.smallest` cells, spans at least :meth:`SkinOptions.shortest` samples, and lies on the plane
    its cells are oriented along (``max_shape_angle``).

    Parameters
    ----------
    thin : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Thinned fault image (> 0 on fault samples), e.g. thinned votes of :func:`~seismo3d.seismic.vote_faults`.
    strike_deg, dip_deg : array_like of float, same shape
        Fault strike and dip of each sample, degrees (conventions of :mod:`~seismo3d.seismic.faults.likelihood.scan`).
    lower, upper : float
        Hysteresis thresholds on ``thin``, ``0 < lower <= upper``.
    options : SkinOptions, optional
        Neighbour search and the smallest skin.

    Returns
    -------
    list of Fault
        Sorted by decreasing size, ids 1, 2, ...; ``likelihood`` holds the values of ``thin``.

    Raises
    ------
    InputError
        Shapes differ, values are not finite, or the thresholds are out of order.

    References
    ----------
    .. [1] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1 (fault skins).
    .. [2] J. Canny, "A computational approach to edge detection", IEEE TPAMI 8(6), 1986,
       doi:10.1109/TPAMI.1986.4767851.
    """
    opt = options or SkinOptions()
    if not isinstance(opt, SkinOptions):
        raise InputError(f"fault_skins(options=...) must be a SkinOptions; got {type(opt).__name__}")
    values, st, dp = check_fault_arrays(thin, strike_deg, dip_deg)
    lower, upper = float(lower), float(upper)
    if not 0.0 < lower <= upper:
        raise InputError(f"fault_skins needs 0 < lower <= upper; got lower={lower!r}, upper={upper!r}")
    return skins_from_cells(*image_cells(values, st, dp, lower), shape=values.shape, lower=lower, upper=upper,
                            options=opt)


def image_cells(thin: np.ndarray, strike_deg: np.ndarray, dip_deg: np.ndarray, lower: float) -> tuple:
    """The cells of a thinned fault image that :func:`skins_from_cells` links: its samples at or above ``lower``.

    Parameters
    ----------
    thin, strike_deg, dip_deg : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Thinned fault image, fault strike and dip (degrees).
    lower : float
        Lower hysteresis threshold.

    Returns
    -------
    (points (n, 3) int64, values (n,), strike_deg (n,), dip_deg (n,) float32)
        In C order (a section's points as (trace, 0, sample)).
    """
    v3 = _kernels.as_3d(thin)
    cells = v3 >= lower
    return np.argwhere(cells), v3[cells], _kernels.as_3d(strike_deg)[cells], _kernels.as_3d(dip_deg)[cells]


def skins_from_cells(points, values, strike_deg, dip_deg, *, shape, lower: float, upper: float,
                     options: SkinOptions | None = None) -> list[Fault]:
    """Fault skins from the cells of a thinned fault image given as lists: :func:`fault_skins` without the image,
    for a cube larger than memory whose cells are gathered block by block.

    Parameters
    ----------
    points : (n, 3) array_like of int
        The cells' (inline, crossline, sample) indices (a 2D section's as (trace, 0, sample)), in any order (in C
        order, inline then crossline then sample, they are not copied to be sorted).
    values : (n,) array_like of float
        Their thinned votes, all at or above ``lower``.
    strike_deg, dip_deg : (n,) array_like of float
        Their fault strike and dip, degrees.
    shape : tuple of int
        Shape of the image, 2D (n_traces, n_samples) or 3D.
    lower, upper : float
        Hysteresis thresholds (see :func:`fault_skins`).
    options : SkinOptions, optional
        Neighbour search and the smallest skin.

    Returns
    -------
    list of Fault
        As :func:`fault_skins`: the same faults as from the image holding these cells.

    Raises
    ------
    InputError
        Lengths differ, a cell lies outside ``shape``, or the thresholds are out of order.

    References
    ----------
    .. [1] D. Hale, Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1 (fault skins).
    """
    opt = options or SkinOptions()
    if not isinstance(opt, SkinOptions):
        raise InputError(f"skins_from_cells(options=...) must be a SkinOptions; got {type(opt).__name__}")
    lower, upper = float(lower), float(upper)
    shape = tuple(int(n) for n in shape)
    two_d = len(shape) == 2
    shape3 = (shape[0], 1, shape[1]) if two_d else shape
    points = np.asarray(points).reshape(-1, 3)
    if points.size and not np.issubdtype(points.dtype, np.integer):
        raise InputError(f"skins_from_cells needs integer cell indices; got dtype {points.dtype}")
    vals = np.asarray(values, dtype=np.float32).ravel()
    s_cell = np.asarray(strike_deg, dtype=np.float32).ravel()
    d_cell = np.asarray(dip_deg, dtype=np.float32).ravel()
    if not points.shape[0] == vals.size == s_cell.size == d_cell.size:
        raise InputError(f"skins_from_cells got {points.shape[0]} points, {vals.size} values, {s_cell.size} strikes "
                         f"and {d_cell.size} dips; pass one of each per cell")
    if points.shape[0] == 0:
        return []
    if points.min() < 0 or np.any(points.max(axis=0) >= np.asarray(shape3)):
        raise InputError(f"skins_from_cells got cells outside an image of shape {shape}; pass indices of that image")
    if not 0.0 < lower <= upper:
        raise InputError(f"fault skins need 0 < lower <= upper; got lower={lower!r}, upper={upper!r}")
    # int32 for memory (a cube larger than memory has tens of millions of cells), C order: one compiled signature
    points = np.ascontiguousarray(points, dtype=np.int32)
    keys = np.ravel_multi_index(tuple(points.T), shape3)
    if np.any(keys[1:] <= keys[:-1]):  # the order of the image's cells, which the growth's ties follow
        order = np.argsort(keys, kind="stable")
        points, vals, s_cell, d_cell, keys = points[order], vals[order], s_cell[order], d_cell[order], keys[order]
        del order
    frames = np.empty((points.shape[0], 3, 3))
    for a in range(0, points.shape[0], 1 << 18):  # by slices: fault_frames' float64 temporaries stay small
        frames[a:a + (1 << 18)] = fault_frames(s_cell[a:a + (1 << 18)], d_cell[a:a + (1 << 18)])
    best = np.full((points.shape[0], 4), -1, np.int32)
    n_threads = nb.get_num_threads()  # work arrays from here: np.empty in the kernel compiled one of numba's
    ranks = _offset_ranks(two_d, int(opt.lateral_reach), int(opt.vertical_reach))
    n_lateral = ranks.shape[0] * ranks.shape[1]  # the lateral offsets, each with its range of keys per thread
    run_threads(_best_neighbours, n_threads, points, frames, keys, np.asarray(shape3, np.int64), ranks,
                float(opt.max_plane_distance), float(np.cos(np.radians(opt.max_angle))), best,
                np.empty((n_threads, 4)), np.empty((n_threads, 4), int), np.zeros((n_threads, n_lateral), np.int64),
                np.zeros((n_threads, n_lateral), np.int64))
    del keys
    normals = np.ascontiguousarray(frames[:, 0, :])
    del frames
    order = np.argsort(-vals, kind="stable")
    label = _grow(best, normals, order, float(np.cos(np.radians(opt.max_angle))))
    del order
    if opt.merge_gap > 0:
        label = merge_coplanar(points, label, _edge_cells(best, label, two_d), opt.smallest(shape), two_d,
                               gap=opt.merge_gap, offset=opt.merge_offset, angle=opt.merge_angle)
    del best
    if two_d and opt.split_angle is not None:
        label = split_opposite_dips(points[:, [0, 2]], normals[:, [0, 2]], label, opt.smallest(shape),
                                    int(opt.lateral_reach), int(opt.vertical_reach), float(opt.split_angle))
    if two_d and opt.split_forks and opt.split_angle is not None:
        label = split_forks(points[:, [0, 2]], label, opt.smallest(shape), int(opt.lateral_reach),
                            int(opt.vertical_reach), float(opt.split_angle))
    sizes = np.bincount(label, minlength=points.shape[0])
    strong = np.zeros(sizes.size, dtype=bool)
    strong[np.unique(label[vals >= upper])] = True
    keep = np.nonzero(strong & (sizes >= opt.smallest(shape)))[0]
    keep = keep[heights(points[:, 2], label, keep) >= opt.shortest(shape)]
    keep = keep[np.argsort(-sizes[keep], kind="stable")]
    by_label = np.argsort(label, kind="stable")
    starts = np.searchsorted(label[by_label], keep)
    if opt.max_shape_angle is not None and keep.size:
        cos_shape = np.cos(np.radians(float(opt.max_shape_angle)))
        planar = np.array([_fits_its_cells(points[m].astype(np.float64), normals[m], two_d, cos_shape)
                           for m in (by_label[a:a + sizes[r]] for r, a in zip(keep, starts))], dtype=bool)
        keep, starts = keep[planar], starts[planar]
    pts = points if not two_d else points[:, [0, 2]]
    faults = []
    for fid, (root, start) in enumerate(zip(keep, starts), start=1):
        members = by_label[start:start + sizes[root]]
        faults.append(Fault(id=fid, points=pts[members].astype(np.int64), likelihood=vals[members].astype(np.float32),
                            strike_deg=s_cell[members].astype(np.float32), dip_deg=d_cell[members].astype(np.float32),
                            normals=fault_normals(s_cell[members], d_cell[members], ndim=len(shape))))
    return faults

