"""register_volumes: the five stages of the sub-volume registration in order, and its result.

Stages 1-5 of :mod:`seismo3d.seismic.volumes`, each a call to a named step; the candidates passed between them are
dataclasses.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..._options import resolve_options
from ..._progress import progress_steps
from ..._validation import check_choice
from ...errors import DegenerateGeometryWarning, InputError, RegistrationError
from ...geometry.transforms import decompose_axis_scaled
from ...registration import ICPOptions, fused_icp
from ...registration.result import RegistrationResult
from ..reflectors import normalise_amplitudes, reflector_points
from .frames import WorkingFrames, homogeneous_diag
from .inputs import as_volume
from .options import VOLUME_MODELS, VolumeOptions
from .polish import OverlapCorrelation, Polished, polish
from .refine import SliceTracker, envelope, refine_with_tracks, reflector_fit
from .starts import FeatureStart, correlation_starts, feature_starts, is_thin

__all__ = ["VolumeRegistration", "register_volumes"]


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
    converged : bool
        The final correlation polish stopped on its tolerances (not on its evaluation limit), and the result
        correlates at least ``min_correlation``.
    scaled_axes : {'moving', 'fixed'}
        Which volume's axes carry the per-axis scales of the final polish (see ``VolumeOptions.symmetric``).
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
    converged: bool = True
    scaled_axes: str = "moving"

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
            "scaled_axes": self.scaled_axes,
            "converged": bool(self.converged),
        }


@dataclass(frozen=True, eq=False)
class _Candidate:
    """A registration before the polish: its overlap correlation, the transform and where it came from."""

    correlation: float
    overlap: float
    transform: np.ndarray  # (4, 4) moving index -> fixed index
    fused: RegistrationResult | None = None  # the fused ICP's result (None after a correlation start)
    n_matches: int = 0  # feature matches of the fused ICP


@dataclass(frozen=True, eq=False)
class _Volumes:
    """The two checked, normalised volumes, their frames and the overlap correlations used to rank and polish."""

    fixed: np.ndarray  # normalised float32
    moving: np.ndarray
    frames: WorkingFrames
    score: OverlapCorrelation  # ranks candidates (about score_points samples)
    overlap: OverlapCorrelation  # the polish's (about polish_points samples)


def register_volumes(fixed, moving, *, model: str = "axis_scaled", fixed_spacing=None, moving_spacing=None,
                     options: VolumeOptions | None = None, progress: bool = False,
                     **overrides) -> VolumeRegistration:
    """Register a moving seismic sub-volume onto a fixed one: bin sizes, sample rates and map orientation may differ.

    The five stages (vertical scale and shift from trace spectra and envelope profiles; a global start from
    HOG-pyramid matches between corresponding slices with RANSAC, or for volumes too small for slice features from a
    correlation search over map rotations within +-45 degrees and the scale range; the fused ICP of reflector points
    and those matches; refinement by slice tracks; a local maximisation of the amplitude correlation) are described
    in :mod:`seismo3d.seismic.volumes`. Which volume is passed as fixed does not change the answer (up to the
    polish's tolerance): see ``VolumeOptions.symmetric``.

    Parameters
    ----------
    fixed : (n_inlines, n_xlines, n_samples) array_like or SeismicCube
        The reference volume: amplitudes of any real dtype (uint8 images of sections too), or an open
        :class:`~seismo3d.seismic.SeismicCube` whose spacing is then read from its CDP coordinates and sample interval
        (:func:`~seismo3d.seismic.volume_spacing`).
    moving : (n_inlines', n_xlines', n_samples') array_like or SeismicCube
        The volume to map onto ``fixed``; it must overlap it (at least ~40 % of the shorter one in time / depth).
    model : {'axis_scaled', 'rigid', 'affine'}
        Transform family in the working frame (module docstring): ``'rigid'`` trusts the spacings, ``'axis_scaled'``
        estimates a scale per axis within ``scale_range`` of them, ``'affine'`` estimates any affine map (started as
        ``'axis_scaled'``).
    fixed_spacing, moving_spacing : (3,) array_like of float, optional
        Inline bin (m), crossline bin (m) and sample interval (ms or m; the same unit for both volumes). Default: from
        the SEG-Y headers for a SeismicCube, else 1 (index units; scales are then in fixed traces and samples).
    options : VolumeOptions, optional
        Scale range, fused-ICP weight, features, point counts, thresholds, seed and the search ranges of every stage
        (:class:`~seismo3d.seismic.volumes.VolumeOptions`).
    progress : bool
        Report progress over the stages and inside the long ones (:mod:`seismo3d._progress`: a bar on a terminal,
        log lines otherwise; a pair takes 10-140 s, ``benchmarks/volumes.py``).
    **overrides
        Fields of :class:`~seismo3d.seismic.volumes.VolumeOptions` by name (e.g. ``scale_range=(0.5, 2.0)``,
        ``min_correlation=0.9``, ``seed=1``), replacing those of ``options``.

    Returns
    -------
    VolumeRegistration
        ``transform_index`` (moving index -> fixed index), ``transform_physical``, ``scales``, ``rotation_deg``,
        ``fitness``, ``inlier_rmse``, ``correlation``, ``converged``, ... and the fused ICP's ``result``.

    Raises
    ------
    InputError
        A volume that is not 3D, smaller than 8 along an axis, constant or (almost) all dead; NaN / inf values; a
        spacing that is not three positive numbers; an unknown model or option; too few reflector points.
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
    check_choice(model, "model", VOLUME_MODELS)
    opt = resolve_options(VolumeOptions, options, overrides, "register_volumes")
    fixed_in = as_volume(fixed, "fixed", fixed_spacing)
    moving_in = as_volume(moving, "moving", moving_spacing)
    fn, mn = normalise_amplitudes(fixed_in.data, "fixed"), normalise_amplitudes(moving_in.data, "moving")
    frames = WorkingFrames(fixed_in.spacing, moving_in.spacing)
    fit_model = "axis_scaled" if model == "affine" else model

    # reflector points first: they also reject volumes without reflectors before the expensive stages
    pf, nf, pm = _reflector_point_sets(fn, mn, opt)
    with progress_steps(4, "register_volumes", enabled=progress) as bar:
        # stages 1 and 2: vertical scale and shift, slice features, RANSAC
        bar.start("slice features")
        env_f, env_m = envelope(fn), envelope(mn)
        thin = is_thin(fn.shape, mn.shape, frames, opt.scale_range[1], opt)
        starts = feature_starts(fn, mn, frames, fit_model, (env_f.mean(axis=(0, 1)), env_m.mean(axis=(0, 1))), thin,
                                opt)
        bar.advance()
        bar.start("fused ICP and slice tracks")
        coef_f = ndi.spline_filter(fn, order=3, output=np.float32, mode="mirror")
        vols = _Volumes(fn, mn, frames, OverlapCorrelation(fn, mn, coef_f, opt.score_points, opt.taper),
                        OverlapCorrelation(fn, mn, coef_f, opt.polish_points, opt.taper))
        # stages 4 and 3: the fused ICP from each of the best starts, refined by slice tracks
        best = _refined_feature_candidate(vols, starts, (pf, nf, pm), (env_f, env_m), model, fit_model, thin, opt,
                                          progress)
        if best is None:
            # no slice features matched (volumes too small for them, or featureless), or the fused ICP failed from
            # every feature-based start: the correlation search, each start polished
            best = _correlation_candidate(vols, fit_model, thin, opt, progress)
        bar.advance()
        # stage 5: the polish, with the scales along either volume's axes
        bar.start("correlation polish")
        polished, scaled_axes = _polish_either_way(vols, best.transform, model, opt)
        bar.advance()
        bar.start("checks")
        result = _finish(vols, best, polished, scaled_axes, fixed_in, moving_in, pf, pm, opt)
        bar.advance()
    return result


def _reflector_point_sets(fn, mn, opt: VolumeOptions):
    """Fixed reflector points and normals, moving reflector points (normalised volumes); at least 100 each."""
    pf, nf = reflector_points(fn, max_points=int(opt.max_points), seed=opt.seed, normalise=False)
    pm, _ = reflector_points(mn, max_points=int(opt.max_points), seed=opt.seed + 1, normalise=False)
    for name, p in (("fixed", pf), ("moving", pm)):
        if len(p) < 100:
            raise InputError(f"{name} has only {len(p)} reflector points (strong, planar amplitude peaks); at least "
                             "100 are needed. Check that it holds reflection seismic amplitudes, not noise or a "
                             "smooth property such as velocity")
    return pf, nf, pm


def _refined_feature_candidate(vols: _Volumes, starts: list[FeatureStart], points, envelopes, model: str,
                               fit_model: str, thin: bool, opt: VolumeOptions, progress: bool) -> _Candidate | None:
    """The fused ICP (eq. 16: RANSAC inlier matches + reflector points) from each of the best feature starts, then
    the refinement with slice tracks; the candidate that correlates best over the overlap, or None."""
    if not starts:
        return None
    pf, nf, pm = points
    frames = vols.frames
    wf, wm = frames.w_fixed, frames.w_moving
    nf_w = nf / wf
    nf_w /= np.linalg.norm(nf_w, axis=1, keepdims=True)
    tracker = SliceTracker(vols.fixed, vols.moving, window=opt.klt_window)
    envelope_tracker = SliceTracker(*envelopes, order=1, window=opt.klt_window)  # smooth: linear suffices
    best = None
    with progress_steps(min(len(starts), opt.max_starts), "feature starts", unit="start", enabled=progress) as bar:
        for start in starts[:opt.max_starts]:
            bar.advance()
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", DegenerateGeometryWarning)  # reported via result.degenerate
                    fused = fused_icp(pm * wm, pf * wf, target_normals=nf_w, source_features=start.source_matches,
                                      target_features=start.target_matches, alpha=opt.alpha, model=fit_model,
                                      init=frames.to_work(start.transform), ransac_threshold=2.0, seed=opt.seed,
                                      options=ICPOptions(max_distance=(4.0, 2.0, 1.0)))
            except RegistrationError:
                continue
            t = refine_with_tracks(tracker, envelope_tracker, vols.score, frames, frames.to_index(fused.transform),
                                   fit_model, thin, int(opt.max_rounds), opt)
            corr, overlap = vols.score.correlation(t)
            if best is None or corr > best.correlation:
                best = _Candidate(corr, overlap, t, fused, len(start.source_matches))
            if corr >= opt.good_correlation:
                break
    if best is not None and model == "affine":  # the affine refinement: rows fitted freely from the tracks
        t = refine_with_tracks(tracker, envelope_tracker, vols.score, frames, best.transform, "affine", thin, 3, opt)
        best = _Candidate(best.correlation, best.overlap, t, best.fused, best.n_matches)
    return best


def _correlation_candidate(vols: _Volumes, fit_model: str, thin: bool, opt: VolumeOptions,
                           progress: bool) -> _Candidate:
    """The best polished start of the correlation search; raises :class:`RegistrationError` when none correlates
    at least ``min_correlation``."""
    best = None
    for start in correlation_starts(vols.fixed, vols.moving, vols.frames, fit_model, opt, progress=progress):
        t = polish(vols.overlap, start.transform, vols.frames, fit_model, opt).transform
        corr, overlap = vols.score.correlation(t)
        if best is None or corr > best.correlation:
            best = _Candidate(corr, overlap, t)
    if best is None or best.correlation < opt.min_correlation:
        fn, mn = vols.fixed, vols.moving
        small = ""
        if thin:
            small = (f" The volumes are small for slice features (fixed {fn.shape[0]} x {fn.shape[1]} traces,"
                     f" moving {mn.shape[0]} x {mn.shape[1]}; features need about {opt.min_map} traces across), "
                     "and the correlation search over map rotations within +-"
                     f"{opt.max_rotation:g} degrees found no start: register larger sub-volumes if you can.")
        raise RegistrationError("no usable feature matches between slices of the two volumes, and no "
                                "correlating start: they may not overlap, or their scales / rotation are "
                                "outside the search (scale_range); check the spacings and the overlap." + small)
    return best


def _polish_either_way(vols: _Volumes, t_index, model: str, opt: VolumeOptions) -> tuple[Polished, str]:
    """The polish with the scales along the moving axes and, for an anisotropic 'axis_scaled' result, along the
    fixed axes too: the reverse problem polished from the forward result projected onto its model (the polish only
    reaches transforms of its own family from there), then inverted. The one that halves the misfit
    ``1 - correlation`` wins, the correlation taken both ways (at the moving samples with the fixed volume
    interpolated, and the reverse): one way alone favours the side whose volume is finer."""
    forward = polish(vols.overlap, t_index, vols.frames, model, opt)
    if not (opt.symmetric and model == "axis_scaled"):
        return forward, "moving"
    scales = np.linalg.norm(vols.frames.to_work(forward.transform)[:3, :3], axis=0)
    if abs(np.log(scales[0] / scales[1])) <= np.log1p(opt.anisotropy):
        return forward, "moving"  # laterally isotropic: both models are the same family
    reverse_frames = vols.frames.swapped()
    coef_m = ndi.spline_filter(vols.moving, order=3, output=np.float32, mode="mirror")
    reverse_overlap = OverlapCorrelation(vols.moving, vols.fixed, coef_m, opt.polish_points, opt.taper)
    reverse_score = OverlapCorrelation(vols.moving, vols.fixed, coef_m, opt.score_points, opt.taper)
    start = reverse_frames.project_index(np.linalg.inv(forward.transform), model)
    reverse = polish(reverse_overlap, start, reverse_frames, model, opt)
    backward = Polished(np.linalg.inv(reverse.transform), forward.n_evaluations + reverse.n_evaluations,
                        reverse.converged)

    def both_ways(t):
        return 0.5 * (vols.score.correlation(t)[0] + reverse_score.correlation(np.linalg.inv(t))[0])

    if 1.0 - both_ways(backward.transform) < 0.5 * (1.0 - both_ways(forward.transform)):
        return backward, "fixed"
    return forward, "moving"


def _finish(vols: _Volumes, best: _Candidate, polished: Polished, scaled_axes: str, fixed_in, moving_in, pf, pm,
            opt: VolumeOptions) -> VolumeRegistration:
    """The final checks and measures: correlation (raises below ``min_correlation``), reflector fit, physical
    transform, scales and map rotation."""
    frames = vols.frames
    t_index = polished.transform
    corr, overlap = vols.score.correlation(t_index)
    if corr < opt.min_correlation:
        raise RegistrationError(
            f"the best registration correlates only {corr:.2f} with the fixed volume over {overlap:.0%} of it "
            f"(min_correlation={opt.min_correlation}); the volumes may not overlap or differ too much. Check the "
            "spacings and the overlap, or lower min_correlation"
        )
    fitness, rmse = reflector_fit(t_index, frames, pm, pf)
    fused = best.fused
    if fused is None:  # the correlation start: the polish is the registration
        fused = RegistrationResult(transform=frames.to_work(t_index), fitness=fitness, inlier_rmse=rmse,
                                   n_iterations=polished.n_evaluations, converged=polished.converged,
                                   info={"start": "correlation", "correlation": corr})
    sp_f, sp_m = fixed_in.spacing, moving_in.spacing
    t_phys = homogeneous_diag(sp_f) @ t_index @ homogeneous_diag(1.0 / sp_m)
    r, scales, _ = decompose_axis_scaled(t_phys)
    return VolumeRegistration(
        transform_index=t_index, transform_physical=t_phys, scales=scales,
        rotation_deg=float(np.degrees(np.arctan2(r[1, 0], r[0, 0]))), fitness=fitness, inlier_rmse=rmse,
        correlation=corr, overlap=overlap, n_reflector_points=int(len(pm)), n_feature_matches=int(best.n_matches),
        fixed_spacing=sp_f, moving_spacing=sp_m, spacing_note=f"fixed: {fixed_in.note}; moving: {moving_in.note}",
        result=fused, converged=bool(polished.converged), scaled_axes=scaled_axes,
    )
