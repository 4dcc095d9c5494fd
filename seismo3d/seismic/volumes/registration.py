"""register_volumes: the stages of the sub-volume registration in order, and its result.

Stages of :mod:`seismo3d.seismic.volumes`, each a call to a named step, each timed: ``prepare`` (inputs, levels),
``search`` (the coarsest level), ``coarse`` (the best starts refined there), ``fine`` (the best one through the finer
levels to full resolution), ``check`` (:mod:`.check`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage as ndi

from ..._options import resolve_options
from ..._progress import progress_steps
from ..._validation import check_choice
from ..reflectors import normalise_amplitudes
from .check import Consistency, consistency_check
from .inputs import VolumeInput, as_volume
from .model import VOLUME_MODELS, Reparam, corner_distance, decompose_map, homogeneous_diag, map_matrix
from .options import VolumeOptions
from .pyramid import (Sampled, build_level, envelope, from_level, level_factors, level_kind, live_traces,
                      smoothing_measures, to_level, without_mean_trace)
from .refine import PairCorrelation, Refined, refine
from .search import Start, correlation_search, distinct_starts, screen_scores
from .spectral import map_spectrum, spectral_maps
from .vertical import vertical_scale

__all__ = ["VolumeRegistration", "register_volumes"]

STAGES = ("prepare", "search", "coarse", "fine", "check")


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
    rotation_deg : float
        Map rotation of the moving grid, degrees, counter-clockwise from the fixed +inline axis towards the fixed
        +crossline axis (:func:`~seismo3d.seismic.volumes.model.decompose_map`).
    moving_scales : (3,) float64 ndarray
        Moving inline bin, crossline bin and sample interval in units of the fixed spacings (1 when the spacings are
        right; with the default spacing of 1 for arrays, in fixed traces and samples).
    fixed_scales : (3,) float64 ndarray
        Corrections of the fixed inline and crossline bins (their product is 1), and 1.
    scales_separable : bool
        Whether the bin anisotropy of the two grids could be told apart (a map rotation away from 0 and 90 degrees);
        otherwise all of it is on ``moving_scales``.
    correlation : float
        Normalised cross-correlation of the two volumes through the result, the mean of both ways (at the moving
        samples with the fixed volume interpolated, and the reverse), in [-1, 1].
    overlap : float
        Fraction of the smaller volume (live samples) inside the other one.
    converged : bool
        The consistency check passed (:mod:`seismo3d.seismic.volumes.check`).
    reason : str
        Why not converged, in one line ('' when converged).
    check : Consistency
        The last stage's measures: the two-way optimum and the one-way registrations refined from it (the leading
        one is the answer), how far apart they are, the best other optimum, the shifted controls.
    stage_seconds : dict
        Seconds per stage: ``prepare``, ``search``, ``coarse``, ``fine``, ``check``.
    n_maps : int
        Linear maps scored by the search (the grid's and the spectra's).
    fixed_spacing, moving_spacing : (3,) float64 ndarray
        Inline bin (m), crossline bin (m), sample interval (ms or m) used for each volume.
    spacing_note : str
        Where the spacings came from (given, SEG-Y headers, or the default 1 when unknown).
    model : {'affine', 'rigid'}
    """

    transform_index: np.ndarray
    transform_physical: np.ndarray
    rotation_deg: float
    moving_scales: np.ndarray
    fixed_scales: np.ndarray
    scales_separable: bool
    correlation: float
    overlap: float
    converged: bool
    reason: str
    check: Consistency
    stage_seconds: dict = field(default_factory=dict)
    n_maps: int = 0
    fixed_spacing: np.ndarray = field(default_factory=lambda: np.ones(3))
    moving_spacing: np.ndarray = field(default_factory=lambda: np.ones(3))
    spacing_note: str = ""
    model: str = "affine"

    def to_dict(self) -> dict:
        """JSON-ready dict of the transforms (nested lists), decomposition, quality measures, check and timings."""
        return {
            "transform_index": np.asarray(self.transform_index).tolist(),
            "transform_physical": np.asarray(self.transform_physical).tolist(),
            "rotation_deg": float(self.rotation_deg),
            "moving_scales": np.asarray(self.moving_scales).tolist(),
            "fixed_scales": np.asarray(self.fixed_scales).tolist(),
            "scales_separable": bool(self.scales_separable),
            "correlation": float(self.correlation),
            "overlap": float(self.overlap),
            "converged": bool(self.converged),
            "reason": self.reason,
            "check": self.check.to_dict(),
            "stage_seconds": {k: round(float(v), 3) for k, v in self.stage_seconds.items()},
            "n_maps": int(self.n_maps),
            "fixed_spacing": np.asarray(self.fixed_spacing).tolist(),
            "moving_spacing": np.asarray(self.moving_spacing).tolist(),
            "spacing_note": self.spacing_note,
        }


@dataclass(frozen=True, eq=False)
class _Pyramid:
    """One volume's levels, finest (full resolution) first."""

    levels: list  # of Sampled

    def at(self, k: int) -> Sampled:
        """Level ``k``, or the coarsest when it has fewer."""
        return self.levels[min(k, len(self.levels) - 1)]


@dataclass(frozen=True, eq=False)
class _Coarse:
    """The starts refined on the coarsest level: the best, and the best distinct other one."""

    best: Refined
    runner_up: Refined | None  # None when every start led to the best


def register_volumes(fixed, moving, *, model: str = "affine", fixed_spacing=None, moving_spacing=None,
                     options: VolumeOptions | None = None, progress: bool = False,
                     **overrides) -> VolumeRegistration:
    """Register a moving seismic sub-volume onto a fixed one: bin sizes, sample rates and map orientation may differ.

    The map has the bins of both volumes (:mod:`~seismo3d.seismic.volumes.model`): a general linear map in map view
    (a map rotation and the inline / crossline bin scales of either volume), a vertical scale and a shift, so the
    answer does not depend on which volume is passed as fixed. Coarse to fine from the start: a search over map
    rotations and the scales of either volume on the coarsest decimated level (every translation at once by masked
    FFT correlation; on volumes of ``spectral_min_traces`` traces or more per map axis with the maps the map-view
    spectra tell, :mod:`~seismo3d.seismic.volumes.spectral`), the best starts refined there (Levenberg-Marquardt on
    the correlation of both volumes, taken both ways), the best one through the finer levels to full resolution;
    the answer is that two-way optimum refined on the way that leads it alone (the one interpolating the less
    aliased volume), checked (:mod:`~seismo3d.seismic.volumes.check`) before it is called converged.

    Parameters
    ----------
    fixed : (n_inlines, n_xlines, n_samples) array_like or SeismicCube
        The reference volume: amplitudes of any real dtype, or an open :class:`~seismo3d.seismic.SeismicCube` whose
        spacing is then read from its CDP coordinates and sample interval (:func:`~seismo3d.seismic.volume_spacing`).
        Dead (constant) traces are left out.
    moving : (n_inlines', n_xlines', n_samples') array_like or SeismicCube
        The volume to map onto ``fixed``; the two must share at least ``min_fraction`` of the smaller one.
    model : {'affine', 'rigid'}
        ``'affine'``: the map rotation, the bin scales of both volumes and the vertical scale are estimated (within
        ``scale_range`` of the spacings); ``'rigid'``: the spacings are right, only a map rotation and a translation
        (and a vertical shift) are estimated.
    fixed_spacing, moving_spacing : (3,) array_like of float, optional
        Inline bin (m), crossline bin (m) and sample interval (ms or m; the same unit for both volumes). Default: from
        the SEG-Y headers for a SeismicCube, else 1 (index units; scales are then in fixed traces and samples).
    options : VolumeOptions, optional
        Search ranges, levels, sizes and check tolerances (:class:`~seismo3d.seismic.volumes.VolumeOptions`).
    progress : bool
        Report progress over the stages (:mod:`seismo3d._progress`).
    **overrides
        Fields of :class:`~seismo3d.seismic.volumes.VolumeOptions` by name (e.g. ``scale_range=(0.5, 2.0)``,
        ``max_rotation=90``), replacing those of ``options``.

    Returns
    -------
    VolumeRegistration
        ``transform_index`` (moving index -> fixed index), ``transform_physical``, ``rotation_deg``,
        ``moving_scales``, ``fixed_scales``, ``correlation``, ``overlap``, ``converged`` and ``reason``, the check's
        measures and ``stage_seconds``. A result that is not converged still holds the best map found.

    Raises
    ------
    InputError
        A volume that is not 3D, smaller than 8 along an axis, constant or (almost) all dead; NaN / inf values; a
        spacing that is not three positive numbers; an unknown model or option.

    References
    ----------
    Padfield, D. (2012). Masked object registration in the Fourier domain. IEEE Trans. Image Process. 21(5),
    2706-2718. doi:10.1109/TIP.2011.2181402
    Marquardt, D. W. (1963). An algorithm for least-squares estimation of nonlinear parameters. J. Soc. Ind. Appl.
    Math. 11(2), 431-441. doi:10.1137/0111030
    Reddy, B. S., Chatterji, B. N. (1996). An FFT-based technique for translation, rotation, and scale-invariant
    image registration. IEEE Trans. Image Process. 5(8), 1266-1271. doi:10.1109/83.506761

    Examples
    --------
    >>> import numpy as np
    >>> from seismo3d.data import synthetic_cube
    >>> cube = synthetic_cube((96, 96, 96), n_faults=3, seed=1).cube
    >>> reg = register_volumes(cube[:72, :72], cube[16:, 20:, 10:])        # doctest: +SKIP
    >>> np.round(reg.transform_index[:3, 3], 1), reg.converged              # doctest: +SKIP
    (array([16., 20., 10.]), True)
    """
    check_choice(model, "model", VOLUME_MODELS)
    opt = resolve_options(VolumeOptions, options, overrides, "register_volumes")
    seconds = {}
    with progress_steps(len(STAGES), "register_volumes", enabled=progress) as bar:
        clock = time.perf_counter()

        def done(stage):  # the time of each stage, in the result
            nonlocal clock
            now = time.perf_counter()
            seconds[stage] = now - clock
            clock = now
            bar.advance()

        bar.start("prepare")
        fixed_in, moving_in = as_volume(fixed, "fixed", fixed_spacing), as_volume(moving, "moving", moving_spacing)
        # two smooth properties (velocity models) are registered by their derivatives along the traces, the layer
        # contrasts: a trend that grows with depth fixes no position, and a vertical scale only multiplies them
        derivative = _is_smooth(fixed_in, opt) and _is_smooth(moving_in, opt)
        pf, pm = _pyramids([(fixed_in, "fixed"), (moving_in, "moving")], derivative, opt)
        sp_f, sp_m = fixed_in.spacing, moving_in.spacing
        done("prepare")
        # stage 1: every candidate map on the coarsest level, both volumes' bin scales
        bar.start("search")
        top = max(len(pf.levels), len(pm.levels)) - 1
        starts, n_maps = _search(pf, pm, top, sp_f, sp_m, model, opt)
        done("search")
        # stage 2: the best starts refined on the coarsest level
        bar.start("coarse")
        coarse = _refine_starts(pf.at(top), pm.at(top), starts, sp_f, sp_m, model, opt,
                                tolerance=opt.tolerance * (5 if top else 1))
        done("coarse")
        # stage 3: the best one through the finer levels, and the best distinct other one (for the check)
        bar.start("fine")
        t_index, final, path = _refine_down(pf, pm, coarse.best.transform, top, sp_f, sp_m, model, opt)
        runner_up = None
        if coarse.runner_up is not None and _close(coarse.best, coarse.runner_up, opt):
            # as good on the coarsest level: which one is better only full resolution tells (unless it joins the
            # best one's peak on the way down)
            runner_up = _refine_down(pf, pm, coarse.runner_up.transform, top, sp_f, sp_m, model, opt, path)[0]
        done("fine")
        # stage 4: the answer from the way that leads (refined alone from the two-way optimum), and the check
        bar.start("check")
        check = consistency_check(final, t_index, runner_up, (sp_f, sp_m), opt)
        t_index, correlation, overlap = check.transform, check.correlation, check.overlap
        done("check")
    t_phys = homogeneous_diag(sp_f) @ t_index @ homogeneous_diag(1.0 / sp_m)
    dec = decompose_map(t_phys)
    return VolumeRegistration(
        transform_index=t_index, transform_physical=t_phys, rotation_deg=dec.rotation_deg,
        moving_scales=dec.moving_scales, fixed_scales=dec.fixed_scales, scales_separable=dec.separable,
        correlation=correlation, overlap=overlap, converged=check.converged, reason=check.reason, check=check,
        stage_seconds=seconds, n_maps=n_maps, fixed_spacing=sp_f, moving_spacing=sp_m,
        spacing_note=f"fixed: {fixed_in.note}; moving: {moving_in.note}", model=model,
    )


def _is_smooth(vol: VolumeInput, opt: VolumeOptions) -> bool:
    """Whether a volume holds a smooth property (a velocity model) rather than seismic amplitudes: a Gaussian of
    width ``max_factor / 2`` samples along the traces keeps at least ``smooth_property`` of its variance."""
    live = live_traces(vol.data)
    if not live.any():
        return False  # a constant volume: refused with its reason when it is normalised
    traces = vol.data[live].astype(np.float64)
    traces = traces - traces.mean()
    kept = ndi.gaussian_filter1d(traces, opt.max_factor / 2.0, axis=-1, mode="nearest").var()
    return bool(kept >= opt.smooth_property * max(traces.var(), 1e-30))


def _pyramids(volumes, derivative: bool, opt: VolumeOptions) -> list[_Pyramid]:
    """The levels of the checked fixed and moving volumes: normalised amplitudes (0 on dead traces), or with
    ``derivative`` their derivatives along the traces, or the envelope of either, decimated coarse to fine; each
    level holds the same kind of data in both (:func:`~seismo3d.seismic.volumes.pyramid.level_kind`)."""
    prepared = []
    for vol, name in volumes:
        data = np.gradient(vol.data, axis=2).astype(np.float32) if derivative else vol.data
        data = normalise_amplitudes(data, name)
        live = live_traces(vol.data)
        data[~live] = 0.0
        env = None if derivative else envelope(data, live)  # the derivative of a property is no oscillating wavelet
        coarsest = np.array(level_factors(data.shape, min_lateral=opt.min_lateral, min_vertical=opt.min_vertical,
                                          max_factor=opt.max_factor))
        prepared.append((data, env, live, coarsest))
    memo = {}

    def cached(i, factor):  # each volume's smoothing measures once per vertical factor
        if (i, factor) not in memo:
            data, env, live, _ = prepared[i]
            memo[i, factor] = smoothing_measures(data, env, live, factor)
        return memo[i, factor]

    # level by level: the samples are decimated while both volumes keep a kind of data, the traces further
    plan = []  # (factors per volume, kind) per level, finest first
    last_vertical = np.inf  # the last level whose samples are decimated further
    for k in range(int(np.log2(max(c.max() for *_, c in prepared))) + 1):
        for attempt in range(2):
            factors = [np.minimum([2 ** k, 2 ** k, 2 ** min(k, last_vertical)], c) for *_, c in prepared]
            if plan and all(np.array_equal(a, b) for a, b in zip(factors, plan[-1][0])):
                break  # nothing decimated further
            measures = [cached(i, int(f[2])) for i, f in enumerate(factors)]
            kind = level_kind(measures, plan[-1][1] if plan else None, keep_amplitude=opt.keep_amplitude,
                              min_contrast=opt.min_contrast, min_amplitude=opt.min_amplitude)
            if kind is not None:
                plan.append((factors, kind))
                break
            last_vertical = k - 1  # neither kind survives: the samples stay as on the level before
    out = []
    for i, (data, env, live, _) in enumerate(prepared):
        levels = [build_level(env if kind == "envelope" else data, live, factors[i], opt.taper)
                  for factors, kind in plan]
        out.append(_Pyramid(levels))
    return out


def _search(pf: _Pyramid, pm: _Pyramid, top: int, sp_f, sp_m, model: str, opt: VolumeOptions) -> tuple[list, int]:
    """The distinct best starts of the search on level ``top`` over map rotations and the lateral scales of either
    volume, with the vertical scale of the trace spectra (full resolution), and the number of maps scored.

    The maps the two volumes' map-view spectra tell (:mod:`.spectral`, volumes of ``spectral_min_traces`` traces or
    more along each map axis) are scored beside them: they are not bound to the grid's steps. Maps with the scales
    on the smaller volume's axes (physical volume of the live samples) resample it onto the larger one's grid;
    maps with the scales on the larger volume's axes are the same search with the volumes' roles swapped, inverted
    (only the rotated ones anisotropic by two scale steps or more: the others are, or start the refinement as close
    as, maps of the first kind). Which volume is passed as fixed does not change the maps scored, only their
    direction. Lateral anisotropies above ``max_anisotropy`` are left out.
    """
    # scored without the mean traces: they tell nothing of the map view (the refinement keeps them)
    fixed, moving = without_mean_trace(pf.at(top)), without_mean_trace(pm.at(top))
    ratio = sp_m[2] / sp_f[2]  # moving sample interval in fixed samples, by the spacings
    lo, hi = opt.scale_range
    spectral = []
    if model == "rigid":
        vertical, axis_scales = ratio, np.ones(1)
    else:
        vertical = vertical_scale(pf.at(0).data, pm.at(0).data, lo * ratio, hi * ratio)
        # the maps the map-view spectra tell (Fourier-Mellin, off the grid below), with their best translations
        spectral = _spectral_starts(pf, pm, top, vertical, opt)
        n = int(np.floor(np.log(hi / lo) / np.log(opt.scale_step) + 1e-9))
        axis_scales = lo * opt.scale_step ** np.arange(n + 1)
        axis_scales = np.unique(np.r_[axis_scales, hi] if hi / axis_scales[-1] > opt.scale_step ** 0.5 else
                                axis_scales)
    angles = np.arange(-opt.max_rotation, opt.max_rotation + 1e-9, opt.rotation_step)
    pairs = [(sx, sy) for sx in axis_scales for sy in axis_scales
             if max(sx, sy) / min(sx, sy) <= opt.max_anisotropy * (1 + 1e-9)]
    # the full grid resamples the smaller volume onto the larger one's grid (the template inside the search
    # image, as the masked NCC is posed best), the other direction only the maps it adds: the search, and so the
    # answer, is the same in either argument order
    swap = _footprint(moving, sp_m) > _footprint(fixed, sp_f)
    full, extra = [], []  # (3, 3) maps from the smaller volume's level index to the larger one's
    small, large = ((moving, sp_m, vertical), (fixed, sp_f, 1.0)) if not swap else ((fixed, sp_f, 1.0),
                                                                                      (moving, sp_m, vertical))
    for theta in angles:
        for lateral in pairs:
            full.append(_level_map(theta, lateral, small[2] / large[2], large[1], small[1], large[0], small[0]))
            # rotated and anisotropic by two steps or more: also on the larger volume's axes (a milder anisotropy
            # on either side starts the refinement close enough)
            if theta != 0 and max(lateral) / min(lateral) > opt.scale_step ** 1.5:
                extra.append(_level_map(theta, lateral, large[2] / small[2], small[1], large[1], small[0],
                                        large[0]))
    forward, backward = (full, extra) if not swap else (extra, full)
    # every map scored first along coarser traces (long traces: Penobscot's 100 samples), the best ones again
    n_maps = len(forward) + len(backward) + len(spectral)
    forward, backward = _screened(fixed, moving, forward, backward, opt)
    starts = correlation_search(fixed, moving, forward, opt.min_fraction) + spectral
    starts += [Start(s.correlation, np.linalg.inv(s.transform), s.ncc)
               for s in correlation_search(moving, fixed, backward, opt.min_fraction)]
    starts.sort(key=lambda s: -s.correlation)
    return distinct_starts(starts, moving.shape, opt.n_starts, 2.0), n_maps


def _screened(fixed: Sampled, moving: Sampled, forward: list, backward: list, opt: VolumeOptions):
    """The ``screen_keep`` best of the search's maps (MOVING onto FIXED, and FIXED onto MOVING), scored together on
    the two levels decimated (:func:`~.search.screen_scores`): along the traces by the largest of 4 and 2 that
    leaves ``2 * min_vertical`` samples of the shorter level, along a map axis by 2 where the smaller level keeps
    ``min_lateral / 2`` traces; all of them when nothing is decimated or when ``screen_keep`` is 0."""
    n_samples = min(fixed.shape[2], moving.shape[2])
    factors = [2 if min(fixed.shape[a], moving.shape[a]) // 2 >= opt.min_lateral / 2 else 1 for a in (0, 1)]
    factors.append(next((f for f in (4, 2) if n_samples // f >= 2 * opt.min_vertical), 1))
    if max(factors) == 1 or not 0 < opt.screen_keep < len(forward) + len(backward):
        return forward, backward
    scores = np.r_[screen_scores(fixed, moving, forward, opt.min_fraction, factors),
                   screen_scores(moving, fixed, backward, opt.min_fraction, factors)]
    kept = set(np.argsort(-scores, kind="stable")[:opt.screen_keep].tolist())
    return ([m for i, m in enumerate(forward) if i in kept],
            [m for i, m in enumerate(backward) if i + len(forward) in kept])


def _footprint(level: Sampled, spacing) -> float:
    """The volume of a level's live samples in physical units (full-resolution spacings)."""
    return float(level.live.sum()) * level.shape[2] * float(np.prod(np.asarray(spacing) * level.factors))


def _spectral_starts(pf: _Pyramid, pm: _Pyramid, top: int, vertical: float, opt: VolumeOptions) -> list:
    """The map-view candidates of the two volumes' spectra (:mod:`.spectral`, full resolution) with the vertical
    scale, each with its best translation on level ``top`` (:func:`~.search.correlation_search`), best first; none
    when ``n_spectral`` is 0 or a volume has fewer than ``spectral_min_traces`` traces along a map axis."""
    f0, m0 = pf.at(0), pm.at(0)
    if opt.n_spectral == 0 or min(*f0.shape[:2], *m0.shape[:2]) < opt.spectral_min_traces:
        return []
    candidates = spectral_maps(map_spectrum(f0.data, f0.live), map_spectrum(m0.data, m0.live),
                               scale_range=opt.scale_range, max_rotation=opt.max_rotation,
                               max_anisotropy=opt.max_anisotropy, n_best=opt.n_spectral)
    fixed, moving = without_mean_trace(pf.at(top)), without_mean_trace(pm.at(top))
    maps = []
    for c in candidates:
        lin = np.eye(3)
        lin[:2, :2], lin[2, 2] = c.linear, vertical
        maps.append(np.diag(1.0 / fixed.factors) @ lin @ np.diag(moving.factors))
    return correlation_search(fixed, moving, maps, opt.min_fraction)


def _level_map(theta, lateral, vertical, sp_to, sp_from, to: Sampled, frm: Sampled) -> np.ndarray:
    """(3, 3) linear map from ``frm``'s level index to ``to``'s: a map rotation and lateral scales of the physical
    coordinates (``sp_*`` the spacings), and ``vertical`` full-resolution samples of ``to`` per sample of ``frm``."""
    lin = np.diag(1.0 / sp_to) @ map_matrix(theta, lateral, 1.0) @ np.diag(sp_from)
    lin[2, 2] = vertical
    return np.diag(1.0 / to.factors) @ lin @ np.diag(frm.factors)


def _refine_starts(fixed: Sampled, moving: Sampled, starts: list, sp_f, sp_m, model: str, opt: VolumeOptions, *,
                   tolerance: float) -> _Coarse:
    """Each start refined on the coarsest level; the best, and the best distinct other optimum.

    The starts lie up to half a search step from an optimum (7.5 degrees, 19 % per axis), where the direction of the
    first steps decides which peak they climb: the Jacobian here holds the derivative of the spline values the
    correlation is made of (``gradient='spline'``). With the smoother central differences, whose sign differs from
    it in places on aliased volumes, a start on the right peak of a Volve velocity pair (0 degrees, fixed bins 0.6 /
    1.6, FIXED onto MOVING) climbed out of it to a map rotation of 118 degrees. The finer levels start on the peak
    and keep the central differences (:attr:`~seismo3d.seismic.volumes.pyramid.Sampled.gradient_volumes`)."""
    pair = PairCorrelation(fixed, moving, Reparam(model, sp_f * fixed.factors, sp_m * moving.factors),
                           opt.n_points_coarse, gradient="spline")
    results = sorted((refine(pair, s.transform, max_iterations=opt.max_iterations, tolerance=tolerance)
                      for s in starts), key=lambda r: -r.correlation)
    if not results:  # no map overlaps enough anywhere: the identity, which the check reports
        results = [refine(pair, np.eye(4), max_iterations=1, tolerance=tolerance)]
    best = results[0]
    others = [r for r in results[1:] if corner_distance(r.transform, best.transform, moving.shape) > 2.0]
    return _Coarse(best, others[0] if others else None)


def _close(best: Refined, other: Refined, opt: VolumeOptions) -> bool:
    """Whether ``other`` correlates nearly as well as ``best`` (misfit ratio above ``control_ratio``)."""
    return 1.0 - best.correlation > opt.control_ratio * (1.0 - other.correlation)


def _refine_down(pf: _Pyramid, pm: _Pyramid, t_top, top: int, sp_f, sp_m, model: str, opt: VolumeOptions,
                 path: list | None = None) -> tuple[np.ndarray | None, PairCorrelation | None, list]:
    """A transform of level ``top`` refined on every finer level down to full resolution: the full-resolution
    transform, the full-resolution correlation and the transform after each level (full-resolution indices, finest
    last).

    With the ``path`` of another refinement, one that reaches within ``max_disagreement`` full-resolution samples of
    it on a level has climbed the same peak: (None, None, its path so far)."""
    t_index = from_level(t_top, pf.at(top), pm.at(top))
    pair, steps = None, []
    full_shape = pm.at(0).shape
    for k in range(top - 1, -1, -1):
        fixed, moving = pf.at(k), pm.at(k)
        pair = PairCorrelation(fixed, moving, Reparam(model, sp_f * fixed.factors, sp_m * moving.factors),
                               opt.n_points if k == 0 else opt.n_points_coarse)
        # the finer levels only need to bring the next one into its peak: a tenth of a sample of theirs
        r = refine(pair, to_level(t_index, fixed, moving), max_iterations=opt.max_iterations,
                   tolerance=opt.tolerance if k == 0 else 5 * opt.tolerance)
        t_index = from_level(r.transform, fixed, moving)
        steps.append(t_index)
        if path is not None and len(path) >= len(steps) and \
                corner_distance(t_index, path[len(steps) - 1], full_shape) <= opt.max_disagreement:
            return None, None, steps
    if pair is None:  # a single level
        fixed, moving = pf.at(0), pm.at(0)
        pair = PairCorrelation(fixed, moving, Reparam(model, sp_f, sp_m), opt.n_points)
    return t_index, pair, steps
