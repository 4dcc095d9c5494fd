"""The patches of a fault whose throw is measured (:mod:`~seismo3d.seismic.faults.throw`): the fault's points gridded on
its plane, the box of the cube each patch reads, and the images of the reflectors on both sides of it."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ...errors import DegenerateGeometryWarning, RegistrationError
from ...geometry.normals import estimate_normals
from ...geometry.transforms import make_transform
from ...registration import ICPOptions, icp
from .windows import CubeWindow
from ..traces import ncc_curve, parabolic_offset, runner_up_peak, side_coherence, small_shift_weight, subsample_peak

# used by the throw module; not part of the package's public face
__all__ = ["PatchFit", "ncc_shift", "patch_grid", "patch_images", "read_box", "reflector_peaks", "register_patch"]


def _side_slope(win: CubeWindow, il, xl, t, h, d_slope):
    """Reflector slope along ``h`` (samples per trace) of the reflector through each fault-plane node.

    The slope is read on that reflector ``d_slope`` traces from the fault (signed: the side), where the reflector
    lands at ``t + p d_slope`` (two fixed-point iterations): next to the fault the structure tensor averages the
    offset reflectors of both sides and its slope is biased.
    """
    a = il + d_slope * h[0]
    b = xl + d_slope * h[1]
    p = np.zeros(len(t))
    for _ in range(2):
        p = win.slope_along(a, b, t + p * d_slope, h)
    return p


def _sample(win: CubeWindow, il, xl, t, h, offsets, p):
    """Amplitudes over the lateral ``offsets`` (traces along ``h``), read on the reflector ``t + p d``: (values
    (n_offsets, n_nodes), 0 at positions outside the cube (``win.cube_shape``), and the mask of those inside)."""
    d = np.asarray(offsets, np.float64)[:, None]
    a = il + d * h[0]
    b = xl + d * h[1]
    tt = t + p * d
    n0, n1, nt = win.cube_shape
    inside = (a >= -0.01) & (a <= n0 - 0.99) & (b >= -0.01) & (b <= n1 - 0.99) & (tt >= 0) & (tt <= nt - 1)
    vals = win.amplitude_at(a.ravel(), b.ravel(), tt.ravel()).reshape(a.shape)
    return np.where(inside, vals, 0.0), inside


@dataclass(frozen=True)
class _Patch:
    """Fault-plane images of one patch: F (footwall) and H (hanging wall) on a (u, t) grid."""

    u0: int  # u of row 0 (traces along strike, local frame)
    t0: int  # t of column 0 (samples)
    img: tuple  # (F, H) float64 (nu, nt)
    valid: tuple  # (valid_F, valid_H) bool (nu, nt)
    coherence: tuple = (float("nan"), float("nan"))  # (F, H): nearer against farther traces of each side


@dataclass(frozen=True)
class _PatchGrid:
    """Fault-plane grid of one patch: the (u, t) nodes and their cube positions; no amplitudes yet."""

    h: np.ndarray  # (2,) horizontal unit vector into the hanging wall (inline, xline)
    il: np.ndarray  # (n_nodes,) inline of each node on the fault
    xl: np.ndarray  # (n_nodes,) crossline
    t: np.ndarray  # (n_nodes,) sample
    rows: np.ndarray  # (n_nodes,) int row (u - u0) of each node in the images
    cols: np.ndarray  # (n_nodes,) int column (t - t0)
    u0: int
    t0: int
    shape: tuple  # (nu, nt) of the images
    ut: np.ndarray  # (n_points, 2) the fault points' (u, t)


def patch_grid(pts3, nrm3) -> _PatchGrid | None:
    """The fault-plane grid of one patch of fault points (None for a horizontal fault).

    Frame: origin at the points' mean lateral position, ``h`` the horizontal part of the mean normal (into the
    hanging wall), ``w`` along strike. The grid nodes are the integer (u, t) within 1.5 of a fault point; each node's
    position across the fault is the mean ``s`` of the fault points within 2 of it (this follows a curved or rough
    fault).
    """
    n = nrm3.mean(axis=0)
    lat = n[:2]
    if np.linalg.norm(lat) < 1e-6:  # horizontal "fault": no sides to compare
        return None
    h = lat / np.linalg.norm(lat)  # horizontal unit vector into the hanging wall
    w = np.array([-h[1], h[0]])  # along strike
    origin = pts3[:, :2].mean(axis=0)
    rel = pts3[:, :2] - origin
    u, s, t = rel @ w, rel @ h, pts3[:, 2]
    ut = np.column_stack([u, t])
    u_lo, u_hi = int(np.floor(u.min())), int(np.ceil(u.max()))
    t_lo, t_hi = int(np.floor(t.min())), int(np.ceil(t.max()))
    gu, gt = np.meshgrid(np.arange(u_lo, u_hi + 1), np.arange(t_lo, t_hi + 1), indexing="ij")
    nodes = np.column_stack([gu.ravel(), gt.ravel()]).astype(np.float64)
    k = min(6, len(pts3))
    dist, idx = cKDTree(ut).query(nodes, k=k, distance_upper_bound=2.0)
    dist, idx = dist.reshape(len(nodes), k), idx.reshape(len(nodes), k)
    ok = np.isfinite(dist)
    on = dist[:, 0] <= 1.5
    s_pad = np.append(s, 0.0)
    s_node = np.where(ok, s_pad[np.minimum(idx, len(s))], 0.0).sum(1) / np.maximum(ok.sum(1), 1)
    nodes, s_node = nodes[on], s_node[on]
    il = origin[0] + nodes[:, 0] * w[0] + s_node * h[0]
    xl = origin[1] + nodes[:, 0] * w[1] + s_node * h[1]
    rows = (nodes[:, 0] - u_lo).astype(np.int64)
    cols = (nodes[:, 1] - t_lo).astype(np.int64)
    return _PatchGrid(h, il, xl, nodes[:, 1], rows, cols, u_lo, t_lo, gu.shape, ut)


def read_box(grid: _PatchGrid, reach: float, cube_shape) -> tuple[int, int, int, int]:
    """Inline and crossline ranges ``(i0, i1, j0, j1)`` (half-open) of the traces :func:`patch_images` reads for
    ``grid``: every read is at ``node + d h`` with ``|d| <= reach`` traces (the slopes at ``side_traces[1] +
    slope_margin``, the amplitudes nearer), interpolated linearly from the traces ``floor`` and ``floor + 1``; one
    trace more on each side against rounding; clipped to the cube (beyond it reads clamp to the edge trace)."""
    n0, n1 = cube_shape[0], cube_shape[1]
    if grid.il.size == 0:
        return 0, 0, 0, 0
    da, db = reach * abs(grid.h[0]), reach * abs(grid.h[1])
    i0 = int(np.floor(grid.il.min() - da)) - 1
    i1 = int(np.floor(grid.il.max() + da)) + 3
    j0 = int(np.floor(grid.xl.min() - db)) - 1
    j1 = int(np.floor(grid.xl.max() + db)) + 3
    i0, j0 = min(max(i0, 0), n0 - 1), min(max(j0, 0), n1 - 1)
    return i0, max(min(i1, n0), i0 + 1), j0, max(min(j1, n1), j0 + 1)


def patch_images(grid: _PatchGrid, win: CubeWindow, sides, slope_margin) -> _Patch:
    """The footwall and hanging-wall fault-plane images of one patch, read from ``win`` (which holds the traces of
    :func:`read_box`)."""
    images, valids, coherence = [], [], []
    for sign in (-1.0, 1.0):
        p = _side_slope(win, grid.il, grid.xl, grid.t, grid.h, sign * (sides[1] + slope_margin))
        vals, inside = _sample(win, grid.il, grid.xl, grid.t, grid.h, sign * np.arange(sides[0], sides[1] + 1), p)
        acc, cnt = vals.sum(axis=0), inside.sum(axis=0)
        coherence.append(side_coherence(vals, inside))
        n_off = sides[1] - sides[0] + 1
        img = np.zeros(grid.shape)
        val = np.zeros(grid.shape, bool)
        good = cnt >= 0.5 * n_off
        img[grid.rows[good], grid.cols[good]] = acc[good] / cnt[good]
        val[grid.rows[good], grid.cols[good]] = True
        images.append(img)
        valids.append(val)
    return _Patch(grid.u0, grid.t0, tuple(images), tuple(valids), tuple(coherence))


def ncc_shift(f, h, vf, vh, max_throw, min_overlap, opt):
    """Shift k maximising the normalised cross-correlation of f(u, t - k) with h(u, t) (:func:`ncc_curve`), refined
    by a parabola.

    Returns (shift in samples, normalised correlation over the overlap at that shift, the same with no shift, the
    rival shift and its weighted correlation over the chosen one's: :func:`runner_up_peak`), or NaNs when no shift
    overlaps enough.
    """
    curve = ncc_curve(f, h, vf, vh, max_throw, min_overlap, opt.min_rows)
    if curve is None or not np.any(np.isfinite(curve[1])):
        return (np.nan,) * 5
    ks, cc, local = curve
    # pick the peak with a mild preference for small shifts (weight 1 at zero, 0.75 at max_throw): when two shifts
    # correlate about equally (a reflector sequence repeating by chance), the smaller displacement is kept
    weighted = cc * small_shift_weight(ks, max_throw, opt.small_shift_prior)
    i = int(np.nanargmax(weighted))
    rival, ratio = runner_up_peak(weighted, i)
    return (float(ks[i]) + subsample_peak(cc, i), float(local[i]), float(local[max_throw]), rival - max_throw,
            ratio)


def reflector_peaks(img, valid, u0, t0):
    """Reflector-peak points (u, t) of a fault-plane image: local maxima along t above half the image's RMS."""
    inner = valid[:, 1:-1] & valid[:, :-2] & valid[:, 2:]
    if not inner.any():
        return np.zeros((0, 2))
    c, up, dn = img[:, 1:-1], img[:, :-2], img[:, 2:]
    rms = np.sqrt(np.mean(img[valid] ** 2))
    is_peak = inner & (c > up) & (c >= dn) & (c > 0.5 * rms)
    r, k = np.nonzero(is_peak)
    off = parabolic_offset(up[r, k], c[r, k], dn[r, k])
    return np.column_stack([r + u0, k + 1 + t0 + off]).astype(np.float64)


@dataclass(frozen=True)
class PatchFit:
    """A patch's registered throw ``a + b u`` and the registration's quality."""

    a: float  # throw at u = 0, samples
    b: float  # throw gradient along strike, samples per trace
    fitness: float
    inlier_rmse: float
    n_points: int  # footwall peaks registered


def register_patch(patch, shift, opt):
    """ICP of footwall peaks onto hanging-wall peaks in the (u, t) plane; a :class:`PatchFit`, or None.

    The throw model is ``a + b u`` (pure dip-slip: the slip is along t in the fault plane, linear along strike).
    """
    src = reflector_peaks(patch.img[0], patch.valid[0], patch.u0, patch.t0)
    dst = reflector_peaks(patch.img[1], patch.valid[1], patch.u0, patch.t0)
    if len(src) < opt.min_peaks or len(dst) < opt.min_peaks or np.ptp(src[:, 0]) < 4:
        return None
    nrm = estimate_normals(dst, k=min(5, len(dst)), orient="none")
    try:
        with warnings.catch_warnings():
            # sliding along the reflectors (along strike) is unconstrained when they are parallel; the throw is
            # measured at constant u below, so that direction does not matter
            warnings.simplefilter("ignore", DegenerateGeometryWarning)
            res = icp(src, dst, method="point_to_plane", model="rigid", target_normals=nrm,
                      init=make_transform(np.eye(2), [0.0, shift]),
                      options=ICPOptions(max_distance=opt.icp_distances, max_iterations=20, tolerance=1e-4))
    except RegistrationError:
        return None
    m = res.transform
    angle = float(np.arctan2(m[1, 0], m[0, 0]))
    if abs(angle) > opt.max_rotation or res.fitness < 0.5:
        return None
    # Throw at each registered footwall peak: the t offset, at the peak's own u, of the hanging-wall reflector it lands
    # on (the target line through the moved point, with the nearest target normal): removes any slide along strike.
    moved = src @ m[:2, :2].T + m[:2, 2]
    dist, j = cKDTree(dst).query(moved, k=1, distance_upper_bound=opt.icp_distances[-1])
    ok = np.isfinite(dist)
    if ok.sum() < opt.min_peaks:
        return None
    n_u, n_t = nrm[j[ok], 0], nrm[j[ok], 1]
    flat = np.abs(n_t) > 0.5  # reflector lines within 60 degrees of the strike direction
    mv, sp = moved[ok][flat], src[ok][flat]
    if len(sp) < opt.min_peaks:
        return None
    thr = mv[:, 1] - n_u[flat] / n_t[flat] * (sp[:, 0] - mv[:, 0]) - sp[:, 1]
    # robust straight line thr = a + b u: least squares, drop residuals beyond 3 MAD, least squares again
    design = np.column_stack([np.ones(len(sp)), sp[:, 0]])
    coef = np.linalg.lstsq(design, thr, rcond=None)[0]
    r = thr - design @ coef
    keep = np.abs(r - np.median(r)) <= 3.0 * 1.4826 * np.median(np.abs(r - np.median(r))) + 1e-3
    if keep.sum() < opt.min_peaks:
        return None
    coef = np.linalg.lstsq(design[keep], thr[keep], rcond=None)[0]
    a, b = float(coef[0]), float(coef[1])
    u_mid = 0.5 * (sp[:, 0].min() + sp[:, 0].max())
    if abs(b) > opt.max_rotation or abs(a + b * u_mid - shift) > 1.5:
        return None  # the refinement moved to another reflector: keep the correlation start
    return PatchFit(a, b, float(res.fitness), float(res.inlier_rmse), int(len(src)))
