"""Registration of two 3D seismic sub-volumes whose bin sizes, sample rates and map orientation differ.

Two overlapping sub-volumes (overlapping surveys, a time-lapse repeat, a cube resampled differently) are registered
with the fused ICP of method.md eq. 16: reflector points with structure-tensor normals are the dense point-to-plane
term, feature matches between corresponding slices the feature term. :func:`register_volumes` runs five stages:

1. **Vertical scale and shift.** The sample-rate ratio is where the mean amplitude spectra of the traces of both
   volumes agree (a change of sample rate stretches the spectrum, and the wavelet is common to both); the vertical
   shift candidates are the peaks of the correlation of their mean envelope profiles.
2. **Global start from slice features.** Time slices of the moving volume, resampled with a grid of candidate
   inline / crossline anisotropies (an affine simulation, as in ASIFT), are matched with the HOG-pyramid matcher
   (method.md section 2) to the fixed time slices at the corresponding times (and the two neighbouring samples on each
   side, which absorbs the error of stage 1); the matches are lifted to 3D with their sample coordinate and a RANSAC
   over all of them gives the first transform. Thin volumes (fewer than 32 traces across) use inline sections instead.
   When no slice features match (volumes of a few tens of traces, such as f3_crop's 23 x 18), the start comes from a
   correlation search instead: for map rotations within +-45 degrees and lateral scales over ``scale_range``, the
   moving volume is resampled through that linear map and its normalised cross-correlation with the fixed volume is
   computed for all translations at once in the Fourier domain (masked NCC, Padfield 2012); the best maps go
   straight to stage 5 (without feature matches, reflector points slide along flat layers, so stages 3-4 are
   skipped).
3. **Refinement with guided slice matches** (of each stage-4 result). The moving volume is resampled onto slices of
   the fixed grid through the current transform; corners of the fixed slices are tracked into them (pyramidal
   Lucas-Kanade with a forward-backward check). Tracks on inline and crossline sections update the vertical row of the
   transform, tracks on time slices its two lateral rows: each slice family measures only the displacement in its own
   plane, so this split avoids the bias that a residual vertical error puts on time-slice tracks in dipping layers.
   Repeated until the transform stops moving.
4. **Fused ICP.** :func:`seismo3d.registration.fused_icp` with the reflector points of both volumes (dense term) and
   the RANSAC-kept slice matches (feature term), from each of the best starts; each result is refined as in stage 3
   and the one that correlates best with the fixed volume is kept.
5. **Polish.** A local maximisation (Powell) of the normalised cross-correlation of the two volumes over the model's
   parameters, from that result. Reflector points constrain the vertical and the tilt well but slide along flat
   layers, and slice tracks carry the aperture problem; the correlation of the amplitudes themselves removes the
   last errors of scale and rotation they leave. It is evaluated at the moving volume's samples with the fixed
   volume interpolated (interpolating a coarser moving volume biases it), rotation and translation act in the fixed
   frame and scales along the moving axes, and scales stay within ``scale_range``.

Conventions
-----------
* Index space: axis 0 inline, axis 1 crossline, axis 2 sample (downward); voxel centres at integer coordinates, the
  first inline / crossline / sample of each volume at 0.
* ``transform_index`` maps MOVING index coordinates to FIXED index coordinates: ``f = A m + t`` (4x4 homogeneous, column
  vectors).
* Physical coordinates are ``spacing * index`` per axis: metres along the inline axis (inline number increasing),
  metres along the crossline axis, and the sample axis in the unit of the sample interval (ms for time, m for depth),
  each from the volume's first trace and first sample (add ``cube.samples[0]`` for the time of the first sample).
  ``transform_physical = diag(fixed_spacing, 1) @ transform_index @ diag(1 / moving_spacing, 1)``.
* The model is imposed in a working frame with square map cells: physical coordinates divided by
  ``(b, b, dt_fixed)``, ``b`` the smaller fixed bin; there a map rotation is a rotation. ``'rigid'`` is then a rigid
  motion of the physical coordinates (sample axis counted in fixed samples), ``'axis_scaled'`` adds a scale per moving
  axis (unknown bin sizes or sample rate, a time stretch), ``'affine'`` any affine map.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from .._validation import check_choice, check_positive
from ..errors import DegenerateGeometryWarning, InputError, RegistrationError
from ..geometry.transforms import decompose_axis_scaled
from ..registration.result import RegistrationResult
from .attributes import _as_seismic

__all__ = [
    "VolumeRegistration", "reflector_points", "register_volumes", "registration_errors", "resample_volume",
    "volume_spacing",
]

VOLUME_MODELS = ("rigid", "axis_scaled", "affine")

_MIN_SIZE = 8  # fewest samples / traces along any axis of a volume
_MIN_MAP = 32  # fewest traces across (working cells) for time slices to carry features
_MAX_FEATURE_SIDE = 192  # slices for the global feature search are downsampled to at most this many pixels a side
_SHIFT_WINDOW = (-2, -1, 0, 1, 2)  # fixed time slices matched around the predicted one (samples)
_KLT_WINDOW = 15  # Lucas-Kanade window, pixels
_MIN_TRACKS = 24
_N_SLICES = 10  # moving time slices matched in the global search
_TRIALS = 1000  # RANSAC samples per global hypothesis
# Correlation start (volumes without slice-feature matches, e.g. too small for them): map rotations within
# +-_MAX_ROTATION degrees every _ROTATION_STEP, lateral scales on _SCALE_STEPS log-spaced values per axis over
# scale_range, then again on half those steps around the _N_REFINED best.
_MAX_ROTATION = 45.0
_ROTATION_STEP = 7.5
_SCALE_STEPS = 7
_N_REFINED = 4
_MIN_FRACTION = 0.3  # overlap needed by a correlation (of the smaller volume's samples)
_TAPER = 2.0  # samples: the correlation's weights fall linearly to 0 over this distance from the fixed volume's edge
_MAX_SEARCH = 100_000  # samples of each volume (sample axis halved) beyond which the correlation search is not run


@dataclass(frozen=True, eq=False)
class VolumeRegistration:
    """Result of :func:`register_volumes`.

    Attributes
    ----------
    transform_index : (4, 4) float64 ndarray
        Maps moving index coordinates (inline, crossline, sample indices) to fixed index coordinates.
    transform_physical : (4, 4) float64 ndarray
        The same map between physical coordinates ``spacing * index`` (m, m, ms or m), i.e.
        ``diag(fixed_spacing, 1) @ transform_index @ diag(1 / moving_spacing, 1)``.
    scales : (3,) float64 ndarray
        Per-axis scales of the moving axes in ``transform_physical`` (column norms of its linear part): the length of
        one moving physical unit along each moving axis, in fixed physical units. 1 when the spacings are right; with
        the default spacing of 1 (arrays), the moving bin sizes and sample interval in fixed traces and samples.
    rotation_deg : float
        Map-view rotation of the moving axes in the physical (inline m, crossline m) plane, degrees, counter-clockwise
        from the +inline axis towards the +crossline axis.
    fitness : float
        Fraction of moving reflector points with a fixed reflector point within the final correspondence distance of
        the fused ICP (1 fixed sample), over all moving reflector points (so at most the overlap fraction).
    inlier_rmse : float
        RMS distance between those corresponding reflector points, in fixed samples (working frame units).
    correlation : float
        Normalised cross-correlation of the fixed volume and the registered moving volume over their overlap, in
        [-1, 1]: a quality measure independent of the reflector picking.
    overlap : float
        Fraction of the fixed volume's voxels covered by the registered moving volume.
    n_reflector_points : int
        Moving reflector points used by the fused ICP (dense term).
    n_feature_matches : int
        Feature matches (slice tracks) used by the fused ICP (feature term); 0 after a correlation start.
    fixed_spacing, moving_spacing : (3,) float64 ndarray
        Inline bin (m), crossline bin (m), sample interval (ms or m) used for each volume.
    spacing_note : str
        Where the spacings came from (given, SEG-Y headers, or the default 1 when unknown).
    result : RegistrationResult
        The fused ICP's result, in working-frame coordinates (see the module docstring). When no slice features
        matched (the correlation start), the polish's: the final transform, the reflector fit's fitness and RMSE,
        the correlation evaluations as ``n_iterations``, and ``info['start'] == 'correlation'``.
    """

    transform_index: np.ndarray
    transform_physical: np.ndarray
    scales: np.ndarray
    rotation_deg: float
    fitness: float
    inlier_rmse: float
    correlation: float
    overlap: float
    n_reflector_points: int
    n_feature_matches: int
    fixed_spacing: np.ndarray
    moving_spacing: np.ndarray
    spacing_note: str
    result: RegistrationResult

    def to_dict(self) -> dict:
        """JSON-ready dict of the transforms (nested lists), scales, rotation, quality measures and spacings."""
        return {
            "transform_index": np.asarray(self.transform_index).tolist(),
            "transform_physical": np.asarray(self.transform_physical).tolist(),
            "scales": np.asarray(self.scales).tolist(),
            "rotation_deg": float(self.rotation_deg),
            "fitness": float(self.fitness),
            "inlier_rmse": float(self.inlier_rmse),
            "correlation": float(self.correlation),
            "overlap": float(self.overlap),
            "n_reflector_points": int(self.n_reflector_points),
            "n_feature_matches": int(self.n_feature_matches),
            "fixed_spacing": np.asarray(self.fixed_spacing).tolist(),
            "moving_spacing": np.asarray(self.moving_spacing).tolist(),
            "spacing_note": self.spacing_note,
            "converged": bool(self.result.converged),
        }


# --------------------------------------------------------------------------------------------------------------------
# inputs


def volume_spacing(cube):
    """Inline bin, crossline bin and sample interval of a SEG-Y cube, from its CDP coordinates and sample interval.

    The inline bin is the median distance between the CDP positions of neighbouring inlines (same crossline), the
    crossline bin that between neighbouring crosslines, with the coordinate scalar applied (see
    :attr:`SeismicCube.cdp_x <seismo3d.seismic.io.SeismicCube.cdp_x>`).

    Parameters
    ----------
    cube : SeismicCube
        A cube opened with :func:`~seismo3d.seismic.open_segy` (open, or closed after :func:`read_segy`, which loads the
        coordinates).

    Returns
    -------
    spacing : (3,) float64 ndarray
        Inline bin and crossline bin in the survey's unit (m or ft), sample interval in ``cube.sample_unit``. A bin
        is 1.0 when the coordinates are missing or do not change along that axis (then see ``note``).
    note : str
        Where each value came from, e.g. ``'bins from CDP X/Y, sample interval 4 ms'``.

    Raises
    ------
    SegyGeometryError
        If the cube was opened as a trace list (``ignore_geometry=True``).
    InputError
        If ``cube`` is not a SeismicCube.
    """
    from .io import SeismicCube

    if not isinstance(cube, SeismicCube):
        raise InputError(f"cube must be a SeismicCube from open_segy(); got {type(cube).__name__}")
    cube._require_geometry("volume_spacing()")
    try:
        x, y = cube.cdp_x, cube.cdp_y
    except InputError:  # closed before its coordinates were read
        x = y = None
    bins, missing = [1.0, 1.0], []
    for axis in (0, 1):
        d = None
        if x is not None and x.shape[axis] > 1:
            d = np.hypot(np.diff(x, axis=axis), np.diff(y, axis=axis))
            d = float(np.median(d)) if d.size else None
        if d is None or not np.isfinite(d) or d <= 0:
            missing.append("inline" if axis == 0 else "crossline")
        else:
            bins[axis] = d
    dt = float(cube.sample_interval) if cube.sample_interval > 0 else 1.0
    note = f"sample interval {dt:g} {cube.sample_unit} from the binary header"
    if missing:
        note = (f"{' and '.join(missing)} bin unknown (no CDP coordinates), set to 1; " + note)
    else:
        note = f"bins {bins[0]:.4g} x {bins[1]:.4g} from CDP X/Y, " + note
    return np.array([bins[0], bins[1], dt]), note


def _as_spacing(value, name):
    try:
        sp = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be three numbers (inline bin, crossline bin, sample interval)") from exc
    if sp.shape != (3,):
        raise InputError(f"{name} must have 3 values (inline bin m, crossline bin m, sample interval ms or m); got "
                         f"shape {sp.shape}")
    if not np.all(np.isfinite(sp)) or np.any(sp <= 0):
        raise InputError(f"{name} must be finite and > 0; got {sp.tolist()}")
    return sp


def _as_volume(volume, name, spacing):
    """(float32 cube, (3,) spacing, note) from an array or a SeismicCube."""
    from .io import SeismicCube

    note = "given"
    if isinstance(volume, SeismicCube):
        if volume._f is None:
            raise InputError(f"{name} is a closed SeismicCube; pass it while open (with open_segy(path) as cube: "
                             "...) or pass the array from read_segy with fixed_spacing= / moving_spacing=")
        volume._require_geometry(f"register_volumes({name})")
        sp_file, note = volume_spacing(volume)
        data = volume.read()
        if spacing is None:
            spacing = sp_file
        else:
            note = "given"
    else:
        data = volume
        if spacing is None:
            note = "not given, 1 per axis (index units)"
    if np.ndim(data) != 3:
        raise InputError(f"{name} must be a 3D volume (n_inlines, n_xlines, n_samples); got shape "
                         f"{np.shape(data)}. A 2D section cannot be registered as a volume; stack sections along a "
                         "new first axis")
    arr = _as_seismic(data, name, min_size=_MIN_SIZE)
    sp = np.ones(3) if spacing is None else _as_spacing(spacing, f"{name}_spacing")
    return arr, sp, note


def _normalise(v, name):
    """Zero-median, unit robust-spread amplitudes; raise for constant or (almost) dead volumes."""
    live = np.ptp(v, axis=2) > 0
    if live.mean() < 0.05:
        raise InputError(f"{name} is constant or has fewer than 5 % live traces ({int(live.sum())} of {live.size}); "
                         "check that it holds seismic amplitudes (dead or padded region?)")
    vals = v[live]
    med = float(np.median(vals))
    spread = float(np.percentile(np.abs(vals - med), 75)) / 1.15  # sigma of a Gaussian
    if not spread > 0:
        spread = float(np.std(vals))
    if not spread > 0:
        raise InputError(f"{name} has no amplitude variation on its live traces; check the data")
    return ((v - med) / spread).astype(np.float32)


# --------------------------------------------------------------------------------------------------------------------
# reflector points


def reflector_points(data, *, quantile: float = 0.5, min_planarity: float = 0.5, max_points: int | None = None,
                     seed: int = 0):
    """Reflector points of a seismic cube: strong amplitude peaks along each trace, with structure-tensor normals.

    A point is a local maximum of the amplitude along the trace (one polarity: peaks), refined to sub-sample precision
    by the vertex of the parabola through the sample and its two neighbours, kept where its amplitude is above the
    ``quantile`` of all peak amplitudes and the reflector planarity (from the structure tensor,
    :func:`~seismo3d.seismic.structure_tensor_orientation`) is at least ``min_planarity``. The amplitudes are first
    smoothed along the trace by a Gaussian of 1 sample, which rounds the plateaus of clipped data.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) array_like
        Seismic amplitudes, any real dtype; finite.
    quantile : float in [0, 1)
        Fraction of the weakest peaks dropped.
    min_planarity : float in [0, 1]
        Smallest structure-tensor planarity kept (near 1 on clean reflectors, low at faults and in noise).
    max_points : int, optional
        Keep at most this many points (a uniform random subset, fixed by ``seed``).
    seed : int
        Seed of the subset.

    Returns
    -------
    points : (N, 3) float64 ndarray
        Index coordinates (inline, crossline, sample), the sample coordinate fractional.
    normals : (N, 3) float64 ndarray
        Unit reflector normals in index space, pointing down (positive sample component).

    Raises
    ------
    InputError
        If ``data`` is not a finite 3D array of at least 8 samples per axis, or an option is out of range.

    References
    ----------
    Fehmers, G. C., Hoecker, C. F. W. (2003). Fast structural interpretation with structure-oriented filtering.
    Geophysics 68(4), 1286-1293. doi:10.1190/1.1598121
    """
    arr, _, _ = _as_volume(data, "data", None)
    if not 0.0 <= float(quantile) < 1.0:
        raise InputError(f"quantile must be in [0, 1); got {quantile!r}")
    if not 0.0 <= float(min_planarity) <= 1.0:
        raise InputError(f"min_planarity must be in [0, 1]; got {min_planarity!r}")
    if max_points is not None and int(max_points) < 1:
        raise InputError(f"max_points must be >= 1 or None; got {max_points!r}")
    return _reflector_points(_normalise(arr, "data"), quantile, min_planarity, max_points, seed)


def _reflector_points(a, quantile=0.5, min_planarity=0.5, max_points=None, seed=0):
    from .attributes import structure_tensor_orientation

    s = ndi.gaussian_filter1d(a, 1.0, axis=2)
    mid = s[:, :, 1:-1]
    peak = (mid > s[:, :, :-2]) & (mid >= s[:, :, 2:]) & (mid > 0)
    if not peak.any():
        return np.zeros((0, 3)), np.zeros((0, 3))
    thr = np.quantile(mid[peak], quantile)
    i, j, k = np.nonzero(peak & (mid > thr))
    k = k + 1
    orient = structure_tensor_orientation(a)
    keep = orient.planarity[i, j, k] >= min_planarity
    i, j, k = i[keep], j[keep], k[keep]
    if max_points is not None and i.size > max_points:
        sel = np.sort(np.random.default_rng(seed).choice(i.size, int(max_points), replace=False))
        i, j, k = i[sel], j[sel], k[sel]
    ym, y0, yp = s[i, j, k - 1], s[i, j, k], s[i, j, k + 1]
    den = ym - 2.0 * y0 + yp
    frac = np.clip(np.where(den < 0, 0.5 * (ym - yp) / np.where(den < 0, den, -1.0), 0.0), -0.5, 0.5)
    points = np.column_stack([i, j, k + frac]).astype(np.float64)
    normals = orient.normals[i, j, k].astype(np.float64)
    normals *= np.where(normals[:, 2:] < 0, -1.0, 1.0)
    return points, normals


# --------------------------------------------------------------------------------------------------------------------
# transforms between index, working and physical frames


def _diag(v):
    return np.diag(np.r_[np.asarray(v, dtype=np.float64), 1.0])


def _project(transform, model):
    """The transform of ``model`` nearest to an affine one (column scales, then the nearest rotation)."""
    if model == "affine":
        return transform
    r, s, _ = decompose_axis_scaled(transform)
    out = transform.copy()
    out[:3, :3] = r * s if model == "axis_scaled" else r
    return out


class _Frames:
    """Index <-> working-frame scalings of the two volumes (working = physical / (b, b, dt_fixed))."""

    def __init__(self, sp_fixed, sp_moving):
        b = min(sp_fixed[0], sp_fixed[1])
        ref = np.array([b, b, sp_fixed[2]])
        self.w_fixed = sp_fixed / ref
        self.w_moving = sp_moving / ref

    def to_work(self, t_index):
        return _diag(self.w_fixed) @ t_index @ _diag(1.0 / self.w_moving)

    def to_index(self, t_work):
        return _diag(1.0 / self.w_fixed) @ t_work @ _diag(self.w_moving)

    def project_index(self, t_index, model):
        return self.to_index(_project(self.to_work(t_index), model))


# --------------------------------------------------------------------------------------------------------------------
# stage 1: vertical scale and shift


def _trace_spectrum(v, n_fft):
    tr = v.reshape(-1, v.shape[2])
    tr = tr[np.ptp(tr, axis=1) > 0]
    if len(tr) > 4000:
        tr = tr[np.linspace(0, len(tr) - 1, 4000).astype(int)]
    tr = tr - tr.mean(axis=1, keepdims=True)
    return np.abs(np.fft.rfft(tr * np.hanning(tr.shape[1]), n=n_fft, axis=1)).mean(axis=0)


def _vertical_scale(fixed, moving, lo, hi):
    """Sample-rate ratio (moving sample in fixed samples) where the mean trace spectra agree best."""
    n_fft = int(2 ** np.ceil(np.log2(4 * max(fixed.shape[2], moving.shape[2]))))
    freqs = np.fft.rfftfreq(n_fft)
    sf, sm = _trace_spectrum(fixed, n_fft), _trace_spectrum(moving, n_fft)
    best, best_c = 1.0, -np.inf
    for s2 in np.exp(np.linspace(np.log(lo), np.log(hi), 361)):
        f = freqs[1:] / s2  # moving frequency (cycles per moving sample) in cycles per fixed sample
        ok = f < 0.5
        if ok.sum() < 8:
            continue
        c = np.corrcoef(np.interp(f[ok], freqs, sf), sm[1:][ok])[0, 1]
        if c > best_c:
            best, best_c = float(s2), c
    return best


def _profile_correlation(pf, pm, s2, min_overlap):
    """Correlation of two vertical profiles for every shift t (fixed sample of moving sample 0), step 1/4 sample."""
    nf, zm = len(pf), np.arange(len(pm), dtype=np.float64)
    need = min_overlap * min(len(pm) * s2, nf)
    shifts = np.arange(-s2 * (len(pm) - 1), nf, 0.25)
    corr = np.full(len(shifts), -np.inf)
    for n, t in enumerate(shifts):
        zf = s2 * zm + t
        ok = (zf >= 0) & (zf <= nf - 1)
        if ok.sum() * s2 < need or ok.sum() < 8:
            continue
        a = np.interp(zf[ok], np.arange(nf), pf)
        b = pm[ok]
        if a.std() > 0 and b.std() > 0:
            corr[n] = np.corrcoef(a, b)[0, 1]
    return shifts, corr


def _peaks(shifts, corr, k, taken):
    out = []
    for n in np.argsort(-corr):
        if not np.isfinite(corr[n]) or len(out) == k:
            break
        if all(abs(shifts[n] - t) > 3.0 for t in taken + out):
            out.append(float(shifts[n]))
    return out


def _vertical_shifts(fn, mn, frames, s2, method, profiles):
    """Candidate vertical shifts t (fixed sample of moving sample 0), best first.

    Two from feature matches between vertical sections (inline and crossline sections of the moving volume, resampled
    to the fixed sample rate and three lateral scales, against five of each in the fixed volume): the modes of the
    vertical offsets of the matches. Layered reflectors look alike in every section, so the offsets agree whatever
    the lateral misfit. One more from the correlation of the mean envelope profiles (``profiles``: fixed, moving),
    in case the sections have no features.
    """
    from ..features import detect_and_describe

    wf, wm = frames.w_fixed, frames.w_moving
    g = min(1.0, 2 * _MAX_FEATURE_SIDE / max(fn.shape[0] * wf[0], fn.shape[1] * wf[1], fn.shape[2]))
    fixed_features = []
    for axis in (0, 1):
        lateral = wf[1 - axis]
        for i in np.unique(np.linspace(0, fn.shape[axis] - 1, 5).round().astype(int)):
            img, p0, p1 = _resample2(np.take(fn, i, axis=axis), g * lateral, g)
            fixed_features.append((detect_and_describe(img, method=method, max_keypoints=800), p1))
    offsets = []
    for axis in (0, 1):
        for i in np.unique(np.linspace(0, mn.shape[axis] - 1, 4)[1:-1].round().astype(int)):
            for aspect in (0.5, 1.0, 2.0):
                img, p0, p1 = _resample2(np.take(mn, i, axis=axis), g * wm[1 - axis] * aspect, g * s2)
                fm = detect_and_describe(img, method=method, max_keypoints=800)
                for ff, pf1 in fixed_features:
                    r = _pairs(fm, ff)
                    if r is not None:
                        offsets.append(r.xy2[:, 0] * pf1 - s2 * r.xy1[:, 0] * p1)
    out = []
    if offsets:
        offsets = np.concatenate(offsets)
        edges = np.arange(-s2 * mn.shape[2], fn.shape[2] + 1.0)
        hist = np.convolve(np.histogram(offsets, bins=edges)[0], [1, 2, 1], "same")
        for n in np.argsort(-hist):
            if hist[n] < 6 or len(out) == 2:
                break
            near = offsets[np.abs(offsets - edges[n] - 0.5) <= 1.5]
            t = float(np.median(near)) if len(near) else float(edges[n] + 0.5)
            if all(abs(t - u) > 3.0 for u in out):
                out.append(t)
    shifts, corr = _profile_correlation(*profiles, s2, 0.4)
    out += _peaks(shifts, corr, 1, out)
    if not out:
        raise RegistrationError("the two volumes cannot overlap vertically by 40 % at any shift; check that they "
                                "cover a common time / depth range and the sample intervals")
    return out


# --------------------------------------------------------------------------------------------------------------------
# stage 2: global start from slice features


def _resample2(img, f0, f1):
    """Resample an image by factors (f0 rows, f1 columns); area-averaged when shrinking."""
    import cv2

    n0, n1 = max(int(round(img.shape[0] * f0)), 2), max(int(round(img.shape[1] * f1)), 2)
    interp = cv2.INTER_AREA if f0 * f1 < 1 else cv2.INTER_LINEAR
    out = cv2.resize(np.ascontiguousarray(img, dtype=np.float32), (n1, n0), interpolation=interp)
    return out, img.shape[0] / n0, img.shape[1] / n1  # image pixel -> slice index factors


def _aspects(model, lo, hi):
    """Candidate ratios (moving axis-0 scale / axis-1 scale) of the affine simulation, steps of sqrt(2)."""
    if model == "rigid":
        return (1.0,)
    n = int(np.ceil(np.log(hi / lo) / np.log(np.sqrt(2.0)) - 1e-9))
    return tuple(float(a) for a in np.exp(np.linspace(-np.log(hi / lo), np.log(hi / lo), 2 * n + 1)))


class _FeatureCache:
    def __init__(self, method):
        self.method = method
        self.store = {}

    def get(self, key, make_image):
        from ..features import detect_and_describe

        if key not in self.store:
            img = make_image()
            self.store[key] = (detect_and_describe(img[0], method=self.method, max_keypoints=800), img[1], img[2])
        return self.store[key]


def _pairs(features_m, features_f, ratio=0.85):
    from ..features import match_features

    if len(features_m) < 2 or len(features_f) < 2:
        return None
    r = match_features(features_m, features_f, verify=None, ratio=ratio)
    return r if len(r) else None


def _time_slice_matches(fn, mn, frames, s2, t2, aspect, cache_f, cache_m, n_slices):
    """3D matches (moving index, fixed index) from time slices for one shift and one anisotropy."""
    wf, wm = frames.w_fixed, frames.w_moving
    g = min(2.0, _MAX_FEATURE_SIDE / max(fn.shape[0] * wf[0], fn.shape[1] * wf[1]))
    c0, c1 = np.sqrt(aspect), 1.0 / np.sqrt(aspect)
    # moving slices from one grid of 2 n_slices samples (so that their features serve every shift t2), n_slices of
    # those inside the fixed volume at this shift
    grid = np.unique(np.linspace(0, mn.shape[2] - 1, 2 * n_slices + 2)[1:-1].round())
    inside = grid[(s2 * grid + t2 >= 0) & (s2 * grid + t2 <= fn.shape[2] - 1)]
    if len(inside) < 2:
        return None
    src, dst = [], []
    for zm in inside[np.unique(np.linspace(0, len(inside) - 1, n_slices).round().astype(int))]:
        zm = float(zm)
        fm, pm0, pm1 = cache_m.get((zm, aspect), lambda: _resample2(mn[:, :, int(zm)], g * wm[0] * c0,
                                                                      g * wm[1] * c1))
        for dz in _SHIFT_WINDOW:
            zf = float(np.round(s2 * zm + t2 + dz))
            if not 0 <= zf <= fn.shape[2] - 1:
                continue
            ff, pf0, pf1 = cache_f.get(zf, lambda: _resample2(fn[:, :, int(zf)], g * wf[0], g * wf[1]))
            r = _pairs(fm, ff)
            if r is None:
                continue
            src.append(np.column_stack([r.xy1[:, 1] * pm0, r.xy1[:, 0] * pm1, np.full(len(r), zm)]))
            dst.append(np.column_stack([r.xy2[:, 1] * pf0, r.xy2[:, 0] * pf1, np.full(len(r), zf)]))
    if not src:
        return None
    return np.vstack(src), np.vstack(dst)


def _section_matches(fn, mn, frames, s2, aspect, cache_f, cache_m, n_sections):
    """3D matches from inline sections (thin volumes); ``aspect`` is the crossline scale in fixed samples."""
    wf, wm = frames.w_fixed, frames.w_moving
    g = min(1.0, 2 * _MAX_FEATURE_SIDE / max(fn.shape[1] * wf[1], fn.shape[2]))
    n_f = fn.shape[0]
    f_idx = np.unique(np.linspace(0, n_f - 1, min(n_f, 24)).round().astype(int))
    src, dst = [], []
    for im in np.unique(np.linspace(0, mn.shape[0] - 1, n_sections + 2)[1:-1].round().astype(int)):
        fm, pm0, pm1 = cache_m.get((int(im), aspect), lambda: _resample2(mn[im], g * wm[1] * aspect, g * s2))
        for i_f in f_idx:
            ff, pf0, pf1 = cache_f.get(int(i_f), lambda: _resample2(fn[i_f], g * wf[1], g))
            r = _pairs(fm, ff)
            if r is None:
                continue
            src.append(np.column_stack([np.full(len(r), float(im)), r.xy1[:, 1] * pm0, r.xy1[:, 0] * pm1]))
            dst.append(np.column_stack([np.full(len(r), float(i_f)), r.xy2[:, 1] * pf0, r.xy2[:, 0] * pf1]))
    if not src:
        return None
    return np.vstack(src), np.vstack(dst)


def _is_thin(shape_f, shape_m, frames, hi):
    """Too few traces across (in working cells, the moving at its largest scale) for time-slice features?"""
    wf, wm = frames.w_fixed, frames.w_moving
    return min(shape_f[0] * wf[0], shape_f[1] * wf[1], shape_m[0] * wm[0] * hi, shape_m[1] * wm[1] * hi) < _MIN_MAP


def _sample_ratio(fn, mn, frames, model, scale_range):
    """The moving sample interval in fixed samples: from the spacings (rigid) or the trace spectra (stage 1)."""
    wf, wm = frames.w_fixed, frames.w_moving
    if model == "rigid":
        return wm[2] / wf[2]
    return _vertical_scale(fn, mn, scale_range[0] * wm[2], scale_range[1] * wm[2])


def _global_starts(fn, mn, frames, model, scale_range, method, seed, profiles, thin):
    """Candidate starting transforms (index space), best first: (number of RANSAC inliers, transform).

    ``profiles``: the mean envelope profiles (fixed, moving) along the sample axis; ``thin``: :func:`_is_thin`."""
    from ..registration import ransac

    lo, hi = scale_range
    wf, wm = frames.w_fixed, frames.w_moving
    s2 = _sample_ratio(fn, mn, frames, model, scale_range)
    cache_f, cache_m = _FeatureCache(method), _FeatureCache(method)
    hyps = []
    if thin:
        # inline sections: 3D RANSAC (the inline correspondence is unknown)
        sizes = (1.0,) if model == "rigid" else tuple(np.exp(np.linspace(np.log(lo), np.log(hi), 5)))
        for aspect in sizes:
            m = _section_matches(fn, mn, frames, s2, aspect, cache_f, cache_m, n_sections=3)
            if m is None or len(m[0]) < 8:
                continue
            src, dst = m[0] * wm, m[1] * wf
            try:
                r = ransac(src, dst, model="rigid" if model == "rigid" else "affine", threshold=2.0, seed=seed,
                           max_trials=3000)
            except (RegistrationError, InputError):
                continue
            inl = r.info["inliers"]
            hyps.append((int(inl.sum()), r.transform, src[inl], dst[inl]))
    else:
        # time slices: the vertical map is (s2, t2) up to the +-2 samples of the slice window, so RANSAC fits the
        # map-view part only (2D, 3 matches per sample) and the vertical shift is the inliers' median
        aspects = _aspects(model, lo, hi)
        for t2 in _vertical_shifts(fn, mn, frames, s2, method, profiles):
            for aspect in aspects:
                m = _time_slice_matches(fn, mn, frames, s2, t2, aspect, cache_f, cache_m, n_slices=_N_SLICES)
                if m is None or len(m[0]) < 8:
                    continue
                src, dst = m[0] * wm, m[1] * wf
                try:
                    r = ransac(src[:, :2], dst[:, :2], model="rigid" if model == "rigid" else "affine",
                               threshold=2.0, seed=seed, max_trials=_TRIALS)
                except (RegistrationError, InputError):
                    continue
                inl = r.info["inliers"]
                t = np.eye(4)
                t[:2, :2], t[:2, 3] = r.transform[:2, :2], r.transform[:2, 2]
                t[2, 2] = s2 * wf[2] / wm[2]  # working units
                t[2, 3] = float(np.median(dst[inl, 2] - t[2, 2] * src[inl, 2]))
                hyps.append((int(inl.sum()), t, src[inl], dst[inl]))
    out = []
    for n_in, t_work, src, dst in sorted(hyps, key=lambda h: -h[0]):
        t_work = _project(t_work, model)
        s = np.linalg.norm(t_work[:3, :3], axis=0)
        if model != "rigid" and (np.any(s < lo / 1.25) or np.any(s > hi * 1.25)):
            continue  # implausible scales: a false consensus
        out.append((n_in, frames.to_index(t_work), src, dst))
    return out


class _ShiftCorrelation:
    """Normalised cross-correlation of the fixed volume with a masked image for every integer shift at once, in the
    Fourier domain (masked NCC, Padfield 2012); the fixed volume's transforms are kept per padded shape."""

    def __init__(self, fixed):
        self.f = np.asarray(fixed, np.float64)
        self.cache = {}

    def __call__(self, img, mask, min_overlap):
        """(ncc, origin): ``ncc[k]`` correlates ``fixed[x + k - origin]`` with ``img[x]`` over the mask; -inf where
        fewer than ``min_overlap`` samples overlap."""
        from scipy import fft

        origin = np.array(img.shape) - 1
        shape = tuple(fft.next_fast_len(int(a + b - 1), real=True) for a, b in zip(self.f.shape, img.shape))
        if shape not in self.cache:
            self.cache[shape] = [fft.rfftn(a, shape, workers=-1) for a in (self.f, self.f * self.f,
                                                                             np.ones_like(self.f))]
        f1, f2, f0 = self.cache[shape]
        flip = (slice(None, None, -1),) * 3
        g1, g2, g0 = (fft.rfftn(a[flip], shape, workers=-1) for a in (img * mask, img * img * mask, mask))

        def corr(a, b):
            return fft.irfftn(a * b, shape, workers=-1)

        n = np.round(corr(f0, g0))
        nn = np.maximum(n, 1.0)
        sum_f, sum_f2, sum_m, sum_m2 = corr(f1, g0), corr(f2, g0), corr(f0, g1), corr(f0, g2)
        num = corr(f1, g1) - sum_f * sum_m / nn
        den = np.sqrt(np.maximum(sum_f2 - sum_f ** 2 / nn, 0.0) * np.maximum(sum_m2 - sum_m ** 2 / nn, 0.0))
        ok = (n >= min_overlap) & (den > 1e-6 * nn)
        return np.where(ok, num / np.where(ok, den, 1.0), -np.inf), origin


def _correlation_starts(fn, mn, frames, model, scale_range, n_best=3):
    """Starting transforms (index space) without features, best first: [(NCC, transform)].

    For each map rotation within +-``_MAX_ROTATION`` degrees and (unless rigid) each pair of lateral scales over
    ``scale_range``, with the vertical scale of stage 1, the moving volume is resampled (linear) onto the fixed grid
    through that linear map, and its normalised cross-correlation with the fixed volume is computed for every integer
    translation at once (:class:`_ShiftCorrelation`), over overlaps of at least ``_MIN_FRACTION`` of the smaller
    volume; the best translation scores the map. The ``_N_REFINED`` best distinct maps are searched again on a grid
    of half the steps. The sample axis of both volumes is halved for the search (after smoothing), which keeps the
    cost to about 20 ms per map on a 23 x 18 x 75 cube; volumes of more than ``_MAX_SEARCH`` samples (so halved) are
    not searched (an empty list).
    """
    lo, hi = scale_range
    wf, wm = frames.w_fixed, frames.w_moving
    dec = 2 if min(fn.shape[2], mn.shape[2]) >= 32 else 1
    if max(fn.size, mn.size) / dec > _MAX_SEARCH:
        return []  # about 0.1 s per map at this size: larger volumes carry slice features
    s2 = _sample_ratio(fn, mn, frames, model, scale_range) * wf[2] / wm[2]  # working units
    fz, mz = ((ndi.gaussian_filter1d(v, 0.5 * dec, axis=2)[:, :, ::dec] if dec > 1 else v).astype(np.float64)
              for v in (fn, mn))
    shifts = _ShiftCorrelation(fz)
    corners = np.array(np.meshgrid(*[[0.0, n - 1.0] for n in mz.shape], indexing="ij")).reshape(3, -1)
    m_hi = np.array(mz.shape, dtype=np.float64)[:, None] - 1

    def score(theta, sx, sy):
        c, s = np.cos(np.radians(theta)), np.sin(np.radians(theta))
        work = np.diag([sx, sy, s2])
        work[:2, :2] = np.array([[c, -s], [s, c]]) @ np.diag([sx, sy])
        lin = np.diag(1.0 / wf) @ work @ np.diag(wm)  # moving index -> fixed index
        foot = lin @ corners
        g_lo, g_hi = np.floor(foot.min(axis=1)).astype(int), np.ceil(foot.max(axis=1)).astype(int)
        grid = np.indices(g_hi - g_lo + 1).reshape(3, -1) + g_lo[:, None]
        m = np.linalg.solve(lin, grid)
        mask = np.all((m >= 0) & (m <= m_hi), axis=0)
        img = np.zeros(grid.shape[1])
        img[mask] = ndi.map_coordinates(mz, m[:, mask], order=1)
        shape = tuple(g_hi - g_lo + 1)
        need = _MIN_FRACTION * min(fz.size, mz.size * abs(np.linalg.det(lin)))
        ncc, origin = shifts(img.reshape(shape), mask.reshape(shape).astype(np.float64), need)
        k = np.unravel_index(int(np.argmax(ncc)), ncc.shape)
        t = np.eye(4)
        t[:3, :3], t[:3, 3] = lin, np.array(k) - origin - g_lo
        t[2, 3] *= dec  # back to full-resolution samples (the vertical scale is the same at both)
        return float(ncc[k]), t

    angles = np.arange(-_MAX_ROTATION, _MAX_ROTATION + 1e-9, _ROTATION_STEP)
    n_s = 1 if model == "rigid" else _SCALE_STEPS
    scales = np.exp(np.linspace(np.log(lo), np.log(hi), n_s)) if n_s > 1 else np.ones(1)
    step = np.log(hi / lo) / (n_s - 1) if n_s > 1 else 0.0
    coarse = sorted(((*score(a, sx, sy), a, sx, sy) for a in angles for sx in scales for sy in scales),
                    key=lambda r: -r[0])
    top = []
    for r in coarse:
        if not np.isfinite(r[0]):
            break
        if all(abs(r[2] - q[2]) > _ROTATION_STEP / 2 or abs(np.log(r[3] / q[3])) > step / 2
               or abs(np.log(r[4] / q[4])) > step / 2 for q in top):
            top.append(r)
        if len(top) == _N_REFINED:
            break
    half = [-0.5, 0.0, 0.5]
    fine = [score(a + da * _ROTATION_STEP, sx * np.exp(dx * step), sy * np.exp(dy * step))
            for _, _, a, sx, sy in top for da in half for dx in (half if n_s > 1 else [0.0])
            for dy in (half if n_s > 1 else [0.0])]
    fine = [r for r in sorted(fine, key=lambda r: -r[0]) if np.isfinite(r[0])]
    return fine[:n_best]


# --------------------------------------------------------------------------------------------------------------------
# stage 3: guided slice tracks


class _Tracker:
    """Corners of fixed slices tracked into the moving volume resampled through the current transform."""

    def __init__(self, fn, mn, order=3):
        self.fn = fn
        self.order = order
        # cubic B-spline coefficients of moving (the samples themselves for linear interpolation)
        self.coef = ndi.spline_filter(mn, order=3, output=np.float32) if order == 3 else mn
        self.m_hi = np.array(mn.shape, dtype=np.float64) - 1.0

    @staticmethod
    def _u8(a):
        return np.clip((a + 3.0) * (255.0 / 6.0), 0, 255).astype(np.uint8)

    def family(self, axis, t_index, step=None):
        """Tracks on the fixed slices normal to ``axis``: (moving points, fixed points), index coordinates."""
        import cv2

        fn = self.fn
        t_inv = np.linalg.inv(t_index)
        other = [a for a in range(3) if a != axis]
        shape2 = (fn.shape[other[0]], fn.shape[other[1]])
        win = int(min(_KLT_WINDOW, max(5, (min(shape2) // 3) | 1)))
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


def _fit_rows(t_index, src, dst, rows):
    """Refit the given rows of an affine transform to matches by least squares with 3-sigma outlier rejection."""
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


def _consistent(src, dst, seed, threshold=1.0, min_tracks=_MIN_TRACKS):
    """Tracks consistent with one affine transform (engine RANSAC), or None when there are too few."""
    from ..registration import ransac

    if len(src) < min_tracks or not all(np.ptp(src[:, a]) > 2.0 for a in range(3)):
        return None
    try:
        r = ransac(src, dst, model="affine", threshold=threshold, seed=seed, max_trials=1000)
    except (RegistrationError, InputError):
        return None
    inl = r.info["inliers"]
    return (src[inl], dst[inl]) if inl.sum() >= min_tracks else None


def _envelope(v):
    """Instantaneous amplitude along the traces, normalised: it varies slowly with time, so slices of it barely
    change under a small vertical misfit."""
    from scipy.signal import hilbert

    e = np.abs(hilbert(v, axis=2)).astype(np.float32)
    return ((e - e.mean()) / max(float(e.std()), 1e-12)).astype(np.float32)


def _refine(tracker, envelope_tracker, score, frames, t_index, model, thin, max_rounds, seed):
    """Alternate vertical (section tracks) and lateral (time-slice tracks, or sections when thin) row updates.

    The lateral rows come from envelope time slices (when they give enough tracks) until the transform moves less
    than 0.3 voxel, then from two rounds of amplitude time slices (sharper, but biased by a residual vertical error that
    the first rounds remove). A round that lowers the correlation of the two volumes is undone and ends the loop.
    """
    corners = np.array(np.meshgrid(*[[0, n] for n in tracker.m_hi], indexing="ij")).reshape(3, -1).T
    corners = np.column_stack([corners, np.ones(len(corners))])
    corr = score.correlation(t_index)[0]
    sharp = 0
    for _ in range(max_rounds):
        before = t_index.copy()
        sections = [tracker.family(a, t_index) for a in (0, 1)]
        ok = _consistent(np.vstack([s for s, _ in sections]), np.vstack([d for _, d in sections]), seed)
        if ok is not None:
            t_index = frames.project_index(_fit_rows(t_index, *ok, [2]), model)
        if thin:
            for axis, row in ((0, 1), (1, 0)):  # inline sections see crosslines, crossline sections inlines
                ok = _consistent(*tracker.family(axis, t_index), seed)
                if ok is not None:
                    t_index = frames.project_index(_fit_rows(t_index, *ok, [row]), model)
        else:
            ok = None if sharp else _consistent(*envelope_tracker.family(2, t_index), seed, min_tracks=40)
            if ok is None:
                ok = _consistent(*tracker.family(2, t_index), seed)
            if ok is not None:
                t_index = frames.project_index(_fit_rows(t_index, *ok, [0, 1]), model)
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


def _reflector_fit(t_index, frames, pm, pf, max_distance=1.0):
    """Fitness and inlier RMSE of the reflector points at a transform, as the ICP reports them (working units)."""
    from scipy.spatial import cKDTree

    t_work = frames.to_work(t_index)
    moved = (pm * frames.w_moving) @ t_work[:3, :3].T + t_work[:3, 3]
    dist, _ = cKDTree(pf * frames.w_fixed).query(moved, distance_upper_bound=max_distance, workers=-1)
    ok = np.isfinite(dist)
    return float(ok.mean()), (float(np.sqrt(np.mean(dist[ok] ** 2))) if ok.any() else float("inf"))


def _polish(overlap, t_index, frames, model, scale_range, max_evals=800):
    """Local maximisation of the NCC of the two volumes (``overlap``, an :class:`_Overlap`) over the model's
    parameters (Powell), with the moving axes' scales (working frame) kept within ``scale_range`` widened by a
    quarter; returns (transform, evaluations, converged).

    The parameters act about the moving volume's centre: a rotation vector and a translation in the fixed working
    frame (so that a rotation is a rotation of the physical coordinates, whatever the moving axes' scales), and
    log-scales (and for 'affine' a symmetric stretch) along the moving axes, applied before the current transform.
    Rotation and scale parameters are radians and log units times the volume's radius (one unit moves its edge by
    about one cell). A correction applied on the moving side only rotates the moving *index* axes: with unequal
    moving scales that is a shear of the physical coordinates, and the polish stalled half a degree from the truth
    on a pair with moving scales 0.6 and 1.8. On volumes that are each other's resampling the NCC peaks at the true
    transform, while slice tracks (stage 3) keep a bias along the reflectors where the aperture problem leaves them
    free.
    """
    from scipy.optimize import minimize
    from scipy.spatial.transform import Rotation

    t0_work = frames.to_work(t_index)
    c_m = (np.array(overlap.moving_shape) - 1.0) / 2.0 * frames.w_moving
    c_f = t0_work[:3, :3] @ c_m + t0_work[:3, 3]
    radius = max(float(np.linalg.norm(t0_work[:3, :3] @ c_m)), 1.0)

    def about(centre, linear, shift=0.0):
        out = np.eye(4)
        out[:3, :3], out[:3, 3] = linear, centre + shift - linear @ centre
        return out

    def transform(p):
        rot = Rotation.from_rotvec(p[:3] / radius).as_matrix()
        stretch = np.eye(3)
        if model == "axis_scaled":
            stretch = np.diag(np.exp(p[6:9] / radius))
        elif model == "affine":
            stretch = np.eye(3) + np.array([[p[6], p[9], p[10]], [p[9], p[7], p[11]], [p[10], p[11], p[8]]]) / radius
        return frames.to_index(about(c_f, rot, p[3:6]) @ t0_work @ about(c_m, stretch))

    # the overlap may not shrink below half its start (nor the shared fraction below _MIN_FRACTION, or half the
    # start's when that is smaller): a small overlap can correlate by chance
    min_overlap = max(1000, 0.5 * overlap.inside(t_index)[1].sum())
    min_shared = min(_MIN_FRACTION, 0.5 * overlap.shared(t_index))
    lo, hi = scale_range[0] / 1.25, scale_range[1] * 1.25

    def cost(p):
        t = transform(p)
        scales = np.linalg.norm(frames.to_work(t)[:3, :3], axis=0)
        if np.any(scales < lo) or np.any(scales > hi) or overlap.shared(t) < min_shared:
            # out of the model's range, or overlapping too little: a volume squeezed into a corner of the other
            # can correlate by chance (two unrelated 24 x 18-trace synthetic volumes reach 0.88 over 1 % of the
            # fixed one)
            return 1.0
        c = overlap.ncc(t, min_overlap)[0]
        return -c if np.isfinite(c) else 1.0

    n = {"rigid": 6, "axis_scaled": 9, "affine": 12}[model]
    res = minimize(cost, np.zeros(n), method="Powell",
                   options=dict(xtol=1e-3, ftol=1e-7, maxfev=int(max_evals), direc=np.eye(n) * 0.5))
    return (transform(res.x) if res.fun < cost(np.zeros(n)) else t_index), int(res.nfev), bool(res.success)


class _Overlap:
    """The normalised cross-correlation of the two volumes through a transform, over their overlap.

    It is evaluated at the moving volume's samples (a subsampled grid of about ``n_points``), with the fixed volume
    interpolated there (cubic B-spline): the fixed cube is the reference whose sampling is trusted. Interpolating the
    moving volume instead, which may be coarser (aliased) than the fixed one, moves the NCC maximum off the truth: by
    1-3 % in scale on pairs cut from f3_crop (and to none within +-3 % for moving bins twice the fixed ones).
    """

    def __init__(self, fn, mn, coef_f, n_points):
        step = max(1, int(round((mn.size / n_points) ** (1 / 3))))
        sub = mn[::step, ::step, ::step]
        self.grid = np.indices(sub.shape).reshape(3, -1).astype(np.float64) * step
        self.m = sub.ravel().astype(np.float64)
        self.coef = coef_f  # cubic B-spline coefficients of fixed
        self.hi = np.array(fn.shape, dtype=np.float64)[:, None] - 1
        self.moving_shape = mn.shape
        # fixed samples (subsampled) for the fraction of the fixed volume the moving one covers
        step_f = max(1, int(round((fn.size / n_points) ** (1 / 3))))
        sub_f = fn[::step_f, ::step_f, ::step_f]
        self.fixed_grid = np.indices(sub_f.shape).reshape(3, -1).astype(np.float64) * step_f
        self.m_hi = np.array(mn.shape, dtype=np.float64)[:, None] - 1

    def inside(self, t_index):
        """Fixed index coordinates of the moving grid points, and which fall inside the fixed volume."""
        f = t_index[:3, :3] @ self.grid + t_index[:3, 3:]
        return f, np.all((f >= 0) & (f <= self.hi), axis=0)

    def ncc(self, t_index, min_points):
        """(NCC, overlap points); the NCC is NaN under ``min_points`` or without variance.

        Points within ``_TAPER`` samples of the fixed volume's edge are weighted down linearly to 0 at the edge, so
        the NCC changes continuously as points enter or leave the overlap (a hard edge makes it jump, which the
        polish's line searches can stop on)."""
        f, ok = self.inside(t_index)
        n = int(ok.sum())
        if n < min_points:
            return np.nan, n
        f = f[:, ok]
        w = np.clip(np.minimum(f, self.hi - f) / _TAPER, 0.0, 1.0).prod(axis=0)
        m = self.m[ok]
        v = ndi.map_coordinates(self.coef, f, order=3, prefilter=False, mode="mirror")
        sw = w.sum()
        m, v = m - np.dot(w, m) / sw, v - np.dot(w, v) / sw
        den = np.sqrt(np.dot(w, m * m) * np.dot(w, v * v))
        return (float(np.dot(w, m * v) / den) if den > 0 else np.nan), n

    def covered(self, t_index):
        """Fraction of the fixed volume's samples that the moving volume covers through ``t_index``."""
        t_inv = np.linalg.inv(t_index)
        m = t_inv[:3, :3] @ self.fixed_grid + t_inv[:3, 3:]
        return float(np.all((m >= 0) & (m <= self.m_hi), axis=0).mean())

    def shared(self, t_index):
        """The overlap as a fraction of the smaller volume (measured in fixed samples)."""
        n_f = float(np.prod(self.hi + 1))
        n_m = float(np.prod(self.m_hi + 1)) * abs(np.linalg.det(t_index[:3, :3]))
        return self.covered(t_index) * n_f / max(min(n_f, n_m), 1.0)

    def correlation(self, t_index):
        """NCC and the fraction of the fixed volume covered; NCC -1 when fewer than 100 grid points overlap, 0
        without variance."""
        c, n = self.ncc(t_index, 100)
        if n < 100:
            return -1.0, self.covered(t_index)
        return (c if np.isfinite(c) else 0.0), self.covered(t_index)


# --------------------------------------------------------------------------------------------------------------------
# the public functions


def registration_errors(estimate, truth, moving_shape) -> dict:
    """Errors of an estimated index-space transform against the true one: rotation, per-axis scale, centre position.

    Parameters
    ----------
    estimate, truth : (4, 4) array_like of float
        Moving-index to fixed-index transforms (e.g. ``VolumeRegistration.transform_index`` and the transform
        returned by :func:`seismo3d.data.resampled_pair`).
    moving_shape : tuple of 3 int
        Shape of the moving volume; the translation error is measured at its centre.

    Returns
    -------
    dict
        ``rotation_deg`` (angle of the rotation between the two rotational parts, degrees), ``scale_pct`` ((3,)
        relative error of each moving axis's scale, %), ``max_scale_pct``, ``centre_error`` (distance between the
        fixed positions the two transforms give the moving volume's centre, fixed index units: traces and samples).

    Raises
    ------
    InputError
        Malformed transforms or shape.
    """
    from ..geometry.transforms import apply_transform, as_transform, rotation_error_deg

    e = as_transform(estimate, "estimate", dims=(3,))
    g = as_transform(truth, "truth", dims=(3,))
    shape = np.asarray(moving_shape, dtype=np.float64)
    if shape.shape != (3,):
        raise InputError(f"moving_shape must be 3 ints; got {moving_shape!r}")
    pct = 100.0 * np.abs(np.linalg.norm(e[:3, :3], axis=0) / np.linalg.norm(g[:3, :3], axis=0) - 1.0)
    centre = ((shape - 1.0) / 2.0)[None]
    return {
        "rotation_deg": rotation_error_deg(e, g),
        "scale_pct": pct,
        "max_scale_pct": float(pct.max()),
        "centre_error": float(np.linalg.norm(apply_transform(e, centre) - apply_transform(g, centre))),
    }


def resample_volume(volume, transform_index, shape, *, order: int = 3, fill: float = np.nan) -> np.ndarray:
    """Resample a volume onto another grid through an index-space transform, e.g. MOVING onto FIXED after registration.

    ``out[p] = volume(T^-1 p)`` for every integer index ``p`` of the output grid, where ``T = transform_index`` maps
    the volume's index coordinates to the output's (the convention of
    :attr:`VolumeRegistration.transform_index`), with a cubic B-spline (``order=3``) between samples.

    Parameters
    ----------
    volume : (n_inlines, n_xlines, n_samples) array_like
        Amplitudes, any real dtype; finite.
    transform_index : (4, 4) array_like of float
        Invertible affine map from the volume's index coordinates (inline, crossline, sample) to the output's.
    shape : tuple of 3 int
        Output shape (n_inlines, n_xlines, n_samples).
    order : int in [0, 5]
        Spline order of :func:`scipy.ndimage.map_coordinates` (0 nearest, 1 linear, 3 cubic).
    fill : float
        Value of output samples that fall outside the volume (by more than half a sample).

    Returns
    -------
    (shape) float32 ndarray

    Raises
    ------
    InputError
        A volume that is not a finite 3D array, a transform that is not an invertible 4x4 affine map, a bad shape or
        order.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.random.default_rng(0).normal(size=(8, 8, 8))
    >>> shift = np.eye(4); shift[:3, 3] = (1, 0, 0)          # output inline i is volume inline i - 1
    >>> out = resample_volume(v, shift, (8, 8, 8))
    >>> bool(np.allclose(out[1:], v[:-1], atol=1e-5)), bool(np.isnan(out[0]).all())
    (True, True)
    """
    from ..geometry.transforms import as_transform

    arr, _, _ = _as_volume(volume, "volume", None)
    t = as_transform(transform_index, "transform_index", dims=(3,))
    try:
        t_inv = np.linalg.inv(t)
    except np.linalg.LinAlgError as exc:
        raise InputError("transform_index is singular; pass an invertible affine map (e.g. a registration's "
                         "transform_index)") from exc
    try:
        shape = tuple(int(n) for n in shape)
    except (TypeError, ValueError) as exc:
        raise InputError(f"shape must be three ints; got {shape!r}") from exc
    if len(shape) != 3 or min(shape) < 1:
        raise InputError(f"shape must be three ints >= 1 (n_inlines, n_xlines, n_samples); got {shape}")
    if int(order) not in range(6):
        raise InputError(f"order must be an int in [0, 5]; got {order!r}")
    out = np.empty(shape, np.float32)
    hi = np.array(arr.shape, dtype=np.float64)[:, None] - 0.5
    grid = np.indices(shape[1:]).reshape(2, -1).astype(np.float64)
    # the B-spline coefficients once for all output inlines, as map_coordinates' own prefilter makes them (the data
    # padded by its edge values, mode="nearest"), instead of once per inline
    pad = 12 if int(order) > 1 else 0
    coef = ndi.spline_filter(np.pad(arr, pad, mode="edge"), int(order), mode="nearest") if pad else arr
    for i in range(shape[0]):  # one output inline at a time keeps the coordinate arrays small
        p = np.vstack([np.full(grid.shape[1], float(i)), grid])
        m = t_inv[:3, :3] @ p + t_inv[:3, 3:]
        vals = ndi.map_coordinates(coef, m + pad, order=int(order), prefilter=False, mode="nearest")
        vals[~np.all((m >= -0.5) & (m <= hi), axis=0)] = fill
        out[i] = vals.reshape(shape[1:])
    return out



def register_volumes(fixed, moving, *, model: str = "axis_scaled", fixed_spacing=None, moving_spacing=None,
                     scale_range=(0.5, 2.0), alpha: float = 0.5, feature_method: str = "hog",
                     max_points: int = 60000, max_rounds: int = 8, min_correlation: float = 0.5,
                     seed: int = 0, progress: bool = False) -> VolumeRegistration:
    """Register a moving seismic sub-volume onto a fixed one: bin sizes, sample rates and map orientation may differ.

    The five stages (vertical scale and shift from trace spectra and envelope profiles; a global start from
    HOG-pyramid matches between corresponding slices with RANSAC, or for volumes too small for slice features from a
    correlation search over map rotations within +-45 degrees and the scale range; the fused ICP of reflector points
    and those matches; refinement by slice tracks; a local maximisation of the amplitude correlation) are described
    in :mod:`seismo3d.seismic.volumes`.

    Parameters
    ----------
    fixed : (n_inlines, n_xlines, n_samples) array_like or SeismicCube
        The reference volume: amplitudes of any real dtype (uint8 images of sections too), or an open
        :class:`~seismo3d.seismic.SeismicCube` whose spacing is then read from its CDP coordinates and sample interval
        (:func:`volume_spacing`).
    moving : (n_inlines', n_xlines', n_samples') array_like or SeismicCube
        The volume to map onto ``fixed``; it must overlap it (at least ~40 % of the shorter one in time / depth).
    model : {'axis_scaled', 'rigid', 'affine'}
        Transform family in the working frame (module docstring): ``'rigid'`` trusts the spacings, ``'axis_scaled'``
        estimates a scale per moving axis within ``scale_range`` of them, ``'affine'`` estimates any affine map
        (started as ``'axis_scaled'``).
    fixed_spacing, moving_spacing : (3,) array_like of float, optional
        Inline bin (m), crossline bin (m) and sample interval (ms or m; the same unit for both volumes). Default: from
        the SEG-Y headers for a SeismicCube, else 1 (index units; scales are then in fixed traces and samples).
    scale_range : (float, float)
        Smallest and largest per-axis scale searched, relative to the spacings (default 0.5 to 2).
    alpha : float in [0, 1]
        Weight of the feature term of the final fused ICP (eq. 16).
    feature_method : {'hog', 'sift'}
        Slice features of the global start: the HOG-pyramid (method.md section 2) or OpenCV's SIFT.
    max_points : int
        Largest number of reflector points per volume in the fused ICP (a fixed random subset beyond it).
    max_rounds : int
        Largest number of track-refinement rounds (stage 3).
    min_correlation : float
        Raise :class:`RegistrationError` when the best registration correlates less than this over the overlap.
        Resampled pairs of one cube reach 0.90-1.0 (the correlation column of ``benchmarks/volumes.py``).
        Lower it for a time-lapse repeat or two surveys processed differently. Volumes too small for slice
        features (the correlation start) fit 7-9 parameters to few samples: two unrelated 24 x 18-trace synthetic
        volumes reached 0.88 there, so raise it (to 0.9 for resampled copies) when you need a failure to be
        reported.
    seed : int
        Seed of RANSAC and of the point subsets; the result is deterministic given it.
    progress : bool
        Show a tqdm bar over the stages (a pair takes 10-140 s; ``benchmarks/volumes.py``).

    Returns
    -------
    VolumeRegistration
        ``transform_index`` (moving index -> fixed index), ``transform_physical``, ``scales``, ``rotation_deg``,
        ``fitness``, ``inlier_rmse``, ``correlation``, ... and the fused ICP's ``result``.

    Raises
    ------
    InputError
        A volume that is not 3D, smaller than 8 along an axis, constant or (almost) all dead; NaN / inf values; a
        spacing that is not three positive numbers; an unknown model; too few reflector points.
    RegistrationError
        No consistent slice matches and no correlating start (the volumes do not overlap, look too different, or
        are rotated by more than 45 degrees while too small for slice features), or a result whose correlation is
        below ``min_correlation``.

    References
    ----------
    Vokhmintcev, A., Timchenko, M., method.md eqs. 1-9 (per-axis scale), eq. 16 (fused objective), section 2
    (HOG-pyramid matcher).
    Padfield, D. (2012). Masked object registration in the Fourier domain. IEEE Trans. Image Process. 21(5),
    2706-2718. doi:10.1109/TIP.2011.2181402
    Morel, J.-M., Yu, G. (2009). ASIFT: A new framework for fully affine invariant image comparison. SIAM J. Imaging
    Sci. 2(2), 438-469. doi:10.1137/080732730
    Bouguet, J.-Y. (2000). Pyramidal implementation of the Lucas Kanade feature tracker. Intel Corporation.
    Shi, J., Tomasi, C. (1994). Good features to track. CVPR, 593-600. doi:10.1109/CVPR.1994.323794

    Examples
    --------
    >>> import numpy as np
    >>> from seismo3d.data import synthetic_cube
    >>> cube = synthetic_cube((96, 96, 96), n_faults=3, seed=1).cube
    >>> reg = register_volumes(cube[:72, :72], cube[16:, 20:, 10:])        # doctest: +SKIP
    >>> np.round(reg.transform_index[:3, 3], 1)                              # doctest: +SKIP
    array([16., 20., 10.])
    """
    from ..registration import fused_icp

    check_choice(model, "model", VOLUME_MODELS)
    check_choice(feature_method, "feature_method", ("hog", "sift"))
    try:
        lo, hi = (float(v) for v in scale_range)
    except (TypeError, ValueError) as exc:
        raise InputError(f"scale_range must be two numbers (smallest, largest); got {scale_range!r}") from exc
    if not 0 < lo <= 1 <= hi or not np.isfinite(hi):
        raise InputError(f"scale_range must satisfy 0 < smallest <= 1 <= largest; got {scale_range!r}")
    alpha = float(alpha)
    if not 0.0 <= alpha <= 1.0:
        raise InputError(f"alpha must be in [0, 1]; got {alpha}")
    check_positive(max_points, "max_points")
    f_arr, sp_f, note_f = _as_volume(fixed, "fixed", fixed_spacing)
    m_arr, sp_m, note_m = _as_volume(moving, "moving", moving_spacing)
    fn, mn = _normalise(f_arr, "fixed"), _normalise(m_arr, "moving")
    frames = _Frames(sp_f, sp_m)
    fit_model = "axis_scaled" if model == "affine" else model

    # reflector points first: they also reject volumes without reflectors before the expensive stages
    pf, nf = _reflector_points(fn, max_points=int(max_points), seed=seed)
    pm, _ = _reflector_points(mn, max_points=int(max_points), seed=seed + 1)
    for name, p in (("fixed", pf), ("moving", pm)):
        if len(p) < 100:
            raise InputError(f"{name} has only {len(p)} reflector points (strong, planar amplitude peaks); at least "
                             "100 are needed. Check that it holds reflection seismic amplitudes, not noise or a "
                             "smooth property such as velocity")

    # stages 1 and 2: vertical scale and shift, slice features, RANSAC
    from tqdm.auto import tqdm

    with tqdm(total=4, desc="register_volumes", unit="stage", disable=not progress) as bar:
        bar.set_postfix_str("slice features")
        env_f, env_m = _envelope(fn), _envelope(mn)
        thin = _is_thin(fn.shape, mn.shape, frames, hi)
        hyps = _global_starts(fn, mn, frames, fit_model, (lo, hi), feature_method, seed,
                              (env_f.mean(axis=(0, 1)), env_m.mean(axis=(0, 1))), thin)
        bar.update(1)
        bar.set_postfix_str("fused ICP and slice tracks")
        coef_f = ndi.spline_filter(fn, order=3, output=np.float32, mode="mirror")
        score = _Overlap(fn, mn, coef_f, 2e5)
        polish = _Overlap(fn, mn, coef_f, 40000)
        best = None
        if hyps:
            # fused ICP from each of the best starts (eq. 16: RANSAC inlier matches + reflector points), then the
            # refinement with slice tracks; the candidate that correlates best over the overlap wins
            wf, wm = frames.w_fixed, frames.w_moving
            nf_w = nf / wf
            nf_w /= np.linalg.norm(nf_w, axis=1, keepdims=True)
            tracker = _Tracker(fn, mn)
            envelope_tracker = _Tracker(env_f, env_m, order=1)  # smooth: linear interpolation suffices
            for _, t_start, src, dst in hyps[:3]:
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", DegenerateGeometryWarning)  # reported via result.degenerate
                        fused = fused_icp(pm * wm, pf * wf, target_normals=nf_w, source_features=src,
                                          target_features=dst, alpha=alpha, model=fit_model,
                                          init=frames.to_work(t_start), ransac_threshold=2.0,
                                          max_distance=(4.0, 2.0, 1.0), seed=seed)
                except RegistrationError:
                    continue
                t = _refine(tracker, envelope_tracker, score, frames, frames.to_index(fused.transform), fit_model,
                            thin, int(max_rounds), seed)
                corr, overlap = score.correlation(t)
                if best is None or corr > best[0]:
                    best = (corr, overlap, t, fused, len(src))
                if corr >= 0.9:
                    break
            if best is not None and model == "affine":  # the affine refinement: rows fitted freely from the tracks
                best = (*best[:2], _refine(tracker, envelope_tracker, score, frames, best[2], "affine", thin, 3,
                                           seed), *best[3:])
        if best is None:
            # no slice features matched (volumes too small for them, or featureless), or the fused ICP failed from
            # every feature-based start: the correlation search, each start polished
            for _, t_start in _correlation_starts(fn, mn, frames, fit_model, (lo, hi)):
                t = _polish(polish, t_start, frames, fit_model, (lo, hi))[0]
                corr, overlap = score.correlation(t)
                if best is None or corr > best[0]:
                    best = (corr, overlap, t)
            if best is None or best[0] < min_correlation:
                small = ""
                if thin:
                    small = (f" The volumes are small for slice features (fixed {fn.shape[0]} x {fn.shape[1]} traces,"
                             f" moving {mn.shape[0]} x {mn.shape[1]}; features need about {_MIN_MAP} traces across), "
                             "and the correlation search over map rotations within +-"
                             f"{_MAX_ROTATION:g} degrees found no start: register larger sub-volumes if you can.")
                raise RegistrationError("no usable feature matches between slices of the two volumes, and no "
                                        "correlating start: they may not overlap, or their scales / rotation are "
                                        "outside the search (scale_range); check the spacings and the overlap."
                                        + small)
            best = (*best, None, 0)  # no fused ICP: without feature matches the reflector points slide freely
        corr, overlap, t_index, fused, n_matches = best
        bar.update(1)
        bar.set_postfix_str("correlation polish")
        t_index, n_evals, converged = _polish(polish, t_index, frames, model, (lo, hi))
        bar.update(1)
        corr, overlap = score.correlation(t_index)
        if corr < min_correlation:
            raise RegistrationError(
                f"the best registration correlates only {corr:.2f} with the fixed volume over {overlap:.0%} of it "
                f"(min_correlation={min_correlation}); the volumes may not overlap or differ too much. Check the "
                "spacings and the overlap, or lower min_correlation"
            )
        fitness, rmse = _reflector_fit(t_index, frames, pm, pf)
        if fused is None:  # the correlation start: the polish is the registration
            fused = RegistrationResult(transform=frames.to_work(t_index), fitness=fitness, inlier_rmse=rmse,
                                       n_iterations=n_evals, converged=converged,
                                       info={"start": "correlation", "correlation": corr})
        bar.update(1)
    t_phys = _diag(sp_f) @ t_index @ _diag(1.0 / sp_m)
    r, scales, _ = decompose_axis_scaled(t_phys)
    note = f"fixed: {note_f}; moving: {note_m}"
    return VolumeRegistration(
        transform_index=t_index, transform_physical=t_phys, scales=scales,
        rotation_deg=float(np.degrees(np.arctan2(r[1, 0], r[0, 0]))), fitness=fitness, inlier_rmse=rmse,
        correlation=corr, overlap=overlap, n_reflector_points=int(len(pm)), n_feature_matches=int(n_matches),
        fixed_spacing=sp_f, moving_spacing=sp_m, spacing_note=note, result=fused,
    )
