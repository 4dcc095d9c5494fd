"""Stage 3 of the volume registration: refinement of the transform by slice tracks.

The moving volume is resampled onto slices of the fixed grid through the current transform; corners of the fixed slices
are tracked into them (pyramidal Lucas-Kanade with a forward-backward check, Bouguet 2000; Shi & Tomasi 1994), and rows
of the transform are refitted to the tracks consistent with one affine map.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from scipy.spatial import cKDTree

from ...errors import InputError, RegistrationError
from ...registration import ransac
from .frames import WorkingFrames
from .options import VolumeOptions

__all__ = ["SliceTracker", "fit_rows", "consistent_tracks", "envelope", "refine_with_tracks", "reflector_fit"]


class SliceTracker:
    """Corners of fixed slices tracked into the moving volume resampled through the current transform.

    Parameters
    ----------
    fn, mn : (n0, n1, n2) float32 ndarray
        Fixed and moving volumes (normalised amplitudes, or their envelopes).
    order : {1, 3}
        Interpolation of the moving volume (cubic B-spline, or linear for smooth volumes).
    window : int
        Lucas-Kanade window, pixels (smaller on small slices).
    """

    def __init__(self, fn, mn, order=3, window: int = 15):
        self.window = int(window)
        self.fn = fn
        self.order = order
        # cubic B-spline coefficients of moving (the samples themselves for linear interpolation)
        self.coef = ndi.spline_filter(mn, order=3, output=np.float32) if order == 3 else mn
        self.m_hi = np.array(mn.shape, dtype=np.float64) - 1.0

    @staticmethod
    def _u8(a):
        """Normalised amplitudes (about -3..3) as an 8-bit image."""
        return np.clip((a + 3.0) * (255.0 / 6.0), 0, 255).astype(np.uint8)

    def family(self, axis, t_index, step=None):
        """Tracks on the fixed slices normal to ``axis`` (every ``step``-th, default about 24 slices) through the
        (4, 4) moving-index to fixed-index ``t_index``: ((K, 3) moving points, (K, 3) fixed points), index
        coordinates."""
        import cv2

        fn = self.fn
        t_inv = np.linalg.inv(t_index)
        other = [a for a in range(3) if a != axis]
        shape2 = (fn.shape[other[0]], fn.shape[other[1]])
        win = int(min(self.window, max(5, (min(shape2) // 3) | 1)))
        if min(shape2) < win + 4:
            return np.zeros((0, 3)), np.zeros((0, 3))
        n = fn.shape[axis]
        step = step or max(2, n // 24)
        grid = np.indices(shape2, dtype=np.float64)
        kernel = np.ones((win, win), np.uint8)
        lk = dict(winSize=(win, win), maxLevel=3, criteria=(cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 30, 0.01))
        src, dst = [], []
        for idx in range(step // 2, n, step):
            coords = np.empty((3,) + shape2)
            coords[axis] = idx
            coords[other[0]], coords[other[1]] = grid
            m = np.tensordot(t_inv[:3, :3], coords, axes=1) + t_inv[:3, 3, None, None]
            valid = np.all((m >= 0) & (m <= self.m_hi[:, None, None]), axis=0)
            if valid.mean() < 0.05:
                continue
            mask = cv2.erode(valid.astype(np.uint8), kernel)
            if mask.sum() < 4 * win:
                continue
            warped = ndi.map_coordinates(self.coef, m.reshape(3, -1), order=self.order, prefilter=False,
                                         mode="nearest")
            im_w = self._u8(warped.reshape(shape2))
            im_f = self._u8(np.take(fn, idx, axis=axis))
            pts = cv2.goodFeaturesToTrack(im_f, maxCorners=300, qualityLevel=0.01, minDistance=4, mask=mask * 255,
                                          blockSize=5)
            if pts is None:
                continue
            nxt, st, _ = cv2.calcOpticalFlowPyrLK(im_f, im_w, pts, None, **lk)
            back, st2, _ = cv2.calcOpticalFlowPyrLK(im_w, im_f, nxt, None, **lk)
            ok = (st.ravel() == 1) & (st2.ravel() == 1) & (np.linalg.norm((back - pts).reshape(-1, 2), axis=1) < 0.5)
            a, b = pts.reshape(-1, 2)[ok].astype(np.float64), nxt.reshape(-1, 2)[ok].astype(np.float64)
            inside = (b[:, 0] >= 0) & (b[:, 0] <= shape2[1] - 1) & (b[:, 1] >= 0) & (b[:, 1] <= shape2[0] - 1)
            inside &= mask[np.clip(np.round(b[:, 1]).astype(int), 0, shape2[0] - 1),
                           np.clip(np.round(b[:, 0]).astype(int), 0, shape2[1] - 1)] > 0
            a, b = a[inside], b[inside]
            if not len(a):
                continue
            pf = np.empty((len(a), 3))
            pw = np.empty((len(a), 3))
            pf[:, axis] = pw[:, axis] = idx
            pf[:, other[0]], pf[:, other[1]] = a[:, 1], a[:, 0]  # image (x = column, y = row)
            pw[:, other[0]], pw[:, other[1]] = b[:, 1], b[:, 0]
            src.append(pw @ t_inv[:3, :3].T + t_inv[:3, 3])
            dst.append(pf)
        if not src:
            return np.zeros((0, 3)), np.zeros((0, 3))
        return np.vstack(src), np.vstack(dst)


def fit_rows(t_index, src, dst, rows) -> np.ndarray:
    """Refit the given rows of a (4, 4) affine transform to matches ((K, 3) each) by least squares with 3-sigma
    outlier rejection (three rounds); the other rows are kept."""
    out = t_index.copy()
    a = np.column_stack([src, np.ones(len(src))])
    for r in rows:
        keep = np.ones(len(src), bool)
        coef = out[r]
        for _ in range(3):
            if keep.sum() < 8:
                break
            coef = np.linalg.lstsq(a[keep], dst[keep, r], rcond=None)[0]
            res = np.abs(a @ coef - dst[:, r])
            keep = res < 3.0 * max(1.4826 * np.median(res[keep]), 0.1)
        out[r] = coef
    return out


def consistent_tracks(src, dst, seed: int, min_tracks: int, threshold: float = 1.0):
    """The tracks ((K, 3) moving, (K, 3) fixed) consistent with one affine transform (the engine's RANSAC within
    ``threshold``), or None when fewer than ``min_tracks`` (or tracks that do not spread over all three axes)."""
    if len(src) < min_tracks or not all(np.ptp(src[:, a]) > 2.0 for a in range(3)):
        return None
    try:
        r = ransac(src, dst, model="affine", threshold=threshold, seed=seed, max_trials=1000)
    except (RegistrationError, InputError):
        return None
    inl = r.info["inliers"]
    return (src[inl], dst[inl]) if inl.sum() >= min_tracks else None


def envelope(v) -> np.ndarray:
    """Instantaneous amplitude (Hilbert transform) along the traces of a cube, normalised (float32): it varies slowly
    with time, so slices of it barely change under a small vertical misfit."""
    from scipy.signal import hilbert  # scipy.signal takes 0.5 s to import: only when a volume is registered

    e = np.abs(hilbert(v, axis=2)).astype(np.float32)
    return ((e - e.mean()) / max(float(e.std()), 1e-12)).astype(np.float32)


def refine_with_tracks(tracker: SliceTracker, envelope_tracker: SliceTracker, score, frames: WorkingFrames,
                       t_index, model: str, thin: bool, max_rounds: int, opt: VolumeOptions) -> np.ndarray:
    """Alternate vertical (section tracks) and lateral (time-slice tracks, or sections when thin) row updates of the
    (4, 4) ``t_index``; ``score`` is an :class:`~seismo3d.seismic.volumes.polish.OverlapCorrelation`.

    The lateral rows come from envelope time slices (when they give enough tracks) until the transform moves less
    than 0.3 voxel, then from two rounds of amplitude time slices (sharper, but biased by a residual vertical error that
    the first rounds remove). A round that lowers the correlation of the two volumes is undone and ends the loop.
    """
    corners = np.array(np.meshgrid(*[[0, n] for n in tracker.m_hi], indexing="ij")).reshape(3, -1).T
    corners = np.column_stack([corners, np.ones(len(corners))])
    seed, min_tracks = opt.seed, opt.min_tracks
    corr = score.correlation(t_index)[0]
    sharp = 0
    for _ in range(max_rounds):
        before = t_index.copy()
        sections = [tracker.family(a, t_index) for a in (0, 1)]
        ok = consistent_tracks(np.vstack([s for s, _ in sections]), np.vstack([d for _, d in sections]), seed,
                               min_tracks)
        if ok is not None:
            t_index = frames.project_index(fit_rows(t_index, *ok, [2]), model)
        if thin:
            for axis, row in ((0, 1), (1, 0)):  # inline sections see crosslines, crossline sections inlines
                ok = consistent_tracks(*tracker.family(axis, t_index), seed, min_tracks)
                if ok is not None:
                    t_index = frames.project_index(fit_rows(t_index, *ok, [row]), model)
        else:
            ok = None if sharp else consistent_tracks(*envelope_tracker.family(2, t_index), seed, 40)
            if ok is None:
                ok = consistent_tracks(*tracker.family(2, t_index), seed, min_tracks)
            if ok is not None:
                t_index = frames.project_index(fit_rows(t_index, *ok, [0, 1]), model)
        new_corr = score.correlation(t_index)[0]
        if new_corr < corr - 0.005:
            return before
        corr = max(corr, new_corr)
        move = np.abs(corners @ (t_index - before)[:3].T).max()
        if sharp:
            sharp += 1
            if sharp > 2:
                break
        elif move < 0.3:
            sharp = 1
    return t_index


def reflector_fit(t_index, frames: WorkingFrames, pm, pf, max_distance: float = 1.0) -> tuple[float, float]:
    """Fitness and inlier RMSE of the moving reflector points ``pm`` against the fixed ones ``pf`` ((N, 3) index
    coordinates) at a transform, as the ICP reports them (working units, within ``max_distance``)."""
    t_work = frames.to_work(t_index)
    moved = (pm * frames.w_moving) @ t_work[:3, :3].T + t_work[:3, 3]
    dist, _ = cKDTree(pf * frames.w_fixed).query(moved, distance_upper_bound=max_distance, workers=-1)
    ok = np.isfinite(dist)
    return float(ok.mean()), (float(np.sqrt(np.mean(dist[ok] ** 2))) if ok.any() else float("inf"))
