"""Optimal surface voting: fault likelihood made continuous by the votes of optimal fault surfaces (paths in 2D).

After Wu & Fomel (2018). Seeds are picked on the thinned fault likelihood. Around each seed the likelihood is sampled
in a box aligned with the seed's fault plane (u across the fault, v down its dip, w along its strike); dynamic
programming finds the surface u(v, w) of least total cost ``1 - likelihood`` whose slope relative to the seed's plane
stays below a strain bound; every sample the surface passes through receives a vote equal to the mean likelihood along
the surface. Samples on long, continuous faults collect many strong votes; noise collects few, weak ones; gaps in a
fault's likelihood are bridged by the surfaces that pass through them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba as nb
import numpy as np

from ...._options import resolve_options
from ...._progress import progress_steps, progress_within
from ...._validation import check_positive
from ....errors import InputError
from ... import _kernels
from ...blocks.apply import BlockOutput
from ..result import FaultVotes, check_fault_arrays, fault_frames
from .ridges import without_dead_edges
from .voting_kernels import cast_votes, greedy_seeds, place_order, strongest, surface_kernel

__all__ = ["VotingOptions", "SeedSurfaces", "VoteSum", "vote_faults",
           "image_seeds", "seed_surfaces", "seed_votes", "surface_block", "surface_votes", "vote_block"]


@dataclass(frozen=True)
class VotingOptions:
    """Options of :func:`vote_faults`; the defaults are Wu & Fomel's (2018) and every seismo3d command uses them.

    Attributes
    ----------
    half_width : int, optional
        Half-width of the voting box across the fault, samples: the surface may leave the seed's plane by at most
        this much. None: 15 in 2D, 10 in 3D.
    half_length_dip : int, optional
        Half-length of the box down the fault's dip, samples. None: 30 in 2D, 20 in 3D, at most a fifth of the
        samples per trace: a vote is a surface's mean likelihood, so a fault shorter than the surfaces gets its
        votes times its length over theirs, and surfaces of 61 samples on the 76-sample Great South Basin lines
        left their small faults below the thresholds (issue 54; traces of 150 samples or more keep 30, of 100 or more
        in 3D keep 20).
    half_length_strike : int
        Half-length of the box along the fault's strike, traces (3D only).
    seed_spacing : int, optional
        Seeds are more than this many samples apart (Chebyshev distance), strongest first. None: 4 in 2D (Wu &
        Fomel's value), 6 in 3D (a 3D surface's box holds 30 times more samples; on the synthetic 128^3 cubes 6
        votes as well as 4 at 0.7 of the time).
    seed_threshold : float
        Only thinned fault-likelihood samples above this are seeds, in [0, 1).
    max_strain : float
        Largest slope of a voting surface relative to its seed's plane, in (0, 1]: the surface moves across the fault
        by one sample per ``ceil(1 / max_strain)`` samples along it.
    surface_smoothing : float
        Half-width of the exponential smoothing of each picked surface, in units of ``ceil(1 / max_strain)`` samples
        (0 for none).

    Raises
    ------
    InputError
        A value out of range (checked when the options are made).
    """

    half_width: int | None = None
    half_length_dip: int | None = None
    half_length_strike: int = 30
    seed_spacing: int | None = None
    seed_threshold: float = 0.3
    max_strain: float = 0.25
    surface_smoothing: float = 2.0

    def __post_init__(self):
        for name in ("half_width", "half_length_dip"):
            value = getattr(self, name)
            if value is not None:
                _check_int(value, name, 1)
        _check_int(self.half_length_strike, "half_length_strike", 1)
        if self.seed_spacing is not None:
            _check_int(self.seed_spacing, "seed_spacing", 1)
        if not 0.0 <= float(self.seed_threshold) < 1.0:
            raise InputError(f"seed_threshold must be in [0, 1); got {self.seed_threshold!r}")
        if not 0.0 < float(self.max_strain) <= 1.0:
            raise InputError(f"max_strain must be in (0, 1]; got {self.max_strain!r}")
        check_positive(self.surface_smoothing, "surface_smoothing", allow_zero=True)

    def box(self, shape: tuple) -> tuple[int, int, int]:
        """(half_width, half_length_dip, half_length_strike) of the voting box for an image of ``shape``: along the
        strike at most half the narrower lateral axis (a slab of a few inlines holds no longer fault), along the dip
        at most half the samples."""
        two_d = len(shape) == 2
        ru = self.half_width if self.half_width is not None else (15 if two_d else 10)
        rv = (self.half_length_dip if self.half_length_dip is not None
              else min(30 if two_d else 20, round(shape[-1] / 5)))
        rv = max(2, min(int(rv), (shape[-1] - 1) // 2))
        rw = 0 if two_d else max(1, min(int(self.half_length_strike), (min(shape[0], shape[1]) - 1) // 2))
        return int(ru), rv, rw

    def reach(self, shape: tuple) -> int:
        """The farthest a seed's box reaches from the seed along any axis, samples (rounded to the nearest sample):
        the box's half-diagonal, whatever its orientation, since the rows of a fault frame are orthonormal."""
        ru, rv, rw = self.box(shape)
        return int(np.ceil(np.sqrt(ru * ru + rv * rv + rw * rw) + 0.5))

    def spacing(self, ndim: int) -> int:
        """The seed spacing for a 2D or 3D image."""
        return int(self.seed_spacing) if self.seed_spacing is not None else (4 if ndim == 2 else 6)

    def full_vote(self, shape: tuple) -> float:
        """The votes a sample in the middle of a long fault of likelihood 1 receives in an image of ``shape``: one
        per seed whose box covers it, seeds every ``spacing + 1`` samples along dip (and strike)."""
        _, rv, rw = self.box(shape)
        step = self.spacing(len(shape)) + 1.0
        return (2 * rv + 1) / step * ((2 * rw + 1) / step if rw else 1.0)


def _check_int(value, name, minimum):
    if isinstance(value, bool) or int(value) != value or value < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}; got {value!r}")


def _strike_dip(normal: np.ndarray, two_d: bool) -> tuple[np.ndarray, np.ndarray]:
    """Strike and dip (degrees) of (..., 3) normals (inline, xline, sample); 0, 0 where the normal is 0. Computed
    slab by slab along the first axis (about 4 M samples each), so the temporaries stay small."""
    shape = normal.shape[:-1]
    strike = np.zeros(shape, np.float32)
    dip = np.zeros(shape, np.float32)
    step = max(1, (1 << 22) // max(1, int(np.prod(shape[1:], dtype=np.int64))))
    for a in range(0, shape[0], step):
        part = normal[a:a + step]
        n = np.where(part[..., 2:3] < 0, -part, part)
        d = np.degrees(np.arccos(np.clip(n[..., 2], 0.0, 1.0)))
        if two_d:
            s = np.where(n[..., 0] >= 0, 90.0, 270.0)
        else:
            s = np.degrees(np.arctan2(n[..., 0], -n[..., 1])) % 360.0
        none = ~np.any(part != 0, axis=-1)
        strike[a:a + step] = np.where(none, 0.0, s)
        dip[a:a + step] = np.where(none, 0.0, d)
    return strike, dip


def vote_faults(likelihood, strike_deg, dip_deg, thin, *, options: VotingOptions | None = None,
                progress: bool = False, **overrides) -> FaultVotes:
    """Optimal surface voting (optimal path voting in 2D) over a fault likelihood image.

    1. Seeds: thinned likelihood samples above ``seed_threshold``, strongest first, more than
       :meth:`VotingOptions.spacing` samples apart.
    2. Around each seed, a box aligned with its fault plane (``half_width`` across, ``half_length_dip`` down the dip,
       ``half_length_strike`` along the strike) is filled with the cost ``1 - likelihood`` (nearest sample); costs
       outside a cone around the seed are 1, so the surface passes close to it.
    3. The costs are smoothed nonlinearly (accumulated both ways and summed) down the dip and along the strike, and
       the least-cost surface is picked by dynamic programming down the dip in every strike slice, its slope across
       the fault bounded by ``max_strain`` (Hale's dynamic warping), then smoothed.
    4. The surface votes: each of its samples receives the mean likelihood along it.

    Votes are divided by :meth:`VotingOptions.full_vote` (the votes a long fault of likelihood 1 receives), so the
    result is on an absolute scale, comparable between images.

    Parameters
    ----------
    likelihood : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Fault likelihood in [0, 1] (:func:`~seismo3d.seismic.faults.fault_likelihood`).
    strike_deg, dip_deg : array_like of float, same shape
        Fault strike and dip of each sample, degrees.
    thin : array_like of float, same shape
        Thinned likelihood (:func:`~seismo3d.seismic.thin_faults` with ``threshold=0``): the seed candidates.
    options : VotingOptions, optional
        The box, seeds and strain (defaults of Wu & Fomel 2018); keyword arguments replace its fields.
    progress : bool, optional
        Report progress over the seeds (see :func:`seismo3d._progress.progress_steps`).

    Returns
    -------
    FaultVotes
        ``votes`` in [0, 1], the orientation of the best voting surface through each sample, and the seed count.

    Raises
    ------
    InputError
        Shapes differ, values are not finite, or an option is out of range.

    References
    ----------
    .. [1] X. Wu and S. Fomel, "Automatic fault interpretation with optimal surface voting", Geophysics 83(5),
       O67-O82, 2018, doi:10.1190/geo2018-0115.1.
    .. [2] D. Hale, "Dynamic warping of seismic images", Geophysics 78(2), S105-S115, 2013,
       doi:10.1190/geo2012-0327.1.
    """
    opt = resolve_options(VotingOptions, options, overrides, "vote_faults")
    fl, st, dp = check_fault_arrays(likelihood, strike_deg, dip_deg)
    th = np.asarray(thin, dtype=np.float32)
    if th.shape != fl.shape:
        raise InputError(f"thin {th.shape} must have the shape of likelihood {fl.shape}")
    seeds, frames = image_seeds(th, st, dp, opt)
    return seed_votes(fl, seeds, frames, options=opt, progress=progress)


def image_seeds(thin: np.ndarray, strike_deg: np.ndarray, dip_deg: np.ndarray,
                options: VotingOptions) -> tuple[np.ndarray, np.ndarray]:
    """Step 1 of :func:`vote_faults` on a whole image: the seeds and their fault frames.

    Parameters
    ----------
    thin, strike_deg, dip_deg : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Thinned likelihood (the seed candidates), fault strike and dip (degrees).
    options : VotingOptions

    Returns
    -------
    seeds : (k, 3) int64 ndarray
        Seeds (a section's as (trace, 0, sample)), strongest first (:func:`greedy_seeds`).
    frames : (k, 3, 3) float64 ndarray
        Their fault frames (:func:`fault_frames`).
    """
    th3 = _kernels.as_3d(thin)
    cand = np.argwhere(th3 > float(options.seed_threshold))
    seeds = greedy_seeds(cand, th3[tuple(cand.T)], th3.shape, options.spacing(thin.ndim))
    del cand
    s3, d3 = _kernels.as_3d(strike_deg), _kernels.as_3d(dip_deg)
    return seeds, fault_frames(s3[tuple(seeds.T)], d3[tuple(seeds.T)]).reshape(-1, 3, 3)


def seed_votes(likelihood: np.ndarray, seeds: np.ndarray, frames: np.ndarray, *, options: VotingOptions,
               progress: bool = False) -> FaultVotes:
    """Steps 2-4 of :func:`vote_faults` on a whole image: the votes of the seeds of :func:`image_seeds`.

    Parameters
    ----------
    likelihood : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Fault likelihood in [0, 1].
    seeds : (k, 3) int64 ndarray
    frames : (k, 3, 3) float64 ndarray
    options : VotingOptions
    progress : bool

    Returns
    -------
    FaultVotes
        Arrays of the image's shape.
    """
    result = surface_votes(_kernels.as_3d(likelihood), seeds, np.arange(len(seeds)), frames,
                           image_shape=likelihood.shape, options=options, progress=progress)
    if likelihood.ndim == 2:
        return FaultVotes(*(np.ascontiguousarray(a[:, 0]) for a in (result.votes, result.strike_deg,
                                                                     result.dip_deg)), result.n_seeds)
    return result


def surface_votes(likelihood, seeds, seed_ids, frames, *, image_shape, options: VotingOptions | None = None,
                  origin=(0, 0), core=None, progress: bool = False) -> FaultVotes:
    """The votes of the optimal surfaces of given seeds over (a block of) a fault likelihood image: steps 2-4 of
    :func:`vote_faults`, which also run block by block on a cube larger than memory.

    A block's votes equal those of the whole image over its ``core`` when ``likelihood`` holds every sample the
    seeds' boxes reach and ``seeds`` every seed whose box reaches the core (see :meth:`VotingOptions.reach`), listed
    in the order of ``seed_ids``: positions are computed in image coordinates, and each seed's votes go to the thread
    ``seed_id % n_threads``, so the float sums are the same, in the same order (on a machine with as many numba
    threads).

    Parameters
    ----------
    likelihood : (n_a, n_b, n_samples) array_like of float
        Fault likelihood in [0, 1] (a 2D section as (n_traces, 1, n_samples)): the whole image, or the block of it
        from inline ``origin[0]`` and crossline ``origin[1]`` on.
    seeds : (k, 3) array_like of int
        Seeds (:func:`greedy_seeds`), image indices.
    seed_ids : (k,) array_like of int
        The seeds' positions in the list of all the image's seeds, increasing.
    frames : (k, 3, 3) array_like of float
        The seeds' fault frames (:func:`fault_frames`).
    image_shape : tuple of int
        Shape of the whole image, 2D or 3D: the voting box and the scale of the votes depend on it.
    options : VotingOptions, optional
        The box and the strain.
    origin : (int, int)
        Image indices of ``likelihood[0, 0]``.
    core : (int, int, int, int), optional
        ``(i0, j0, m0, m1)``: the votes are kept for the image's inlines ``i0 .. i0 + m0 - 1`` and crosslines
        ``j0 .. j0 + m1 - 1``, which ``likelihood`` must hold (default: all of ``likelihood``).
    progress : bool, optional
        Report progress over the seeds.

    Returns
    -------
    FaultVotes
        Arrays of the core's shape (3D form).

    Raises
    ------
    InputError
        Seeds, ids and frames differ in length, or the core lies outside ``likelihood``.

    References
    ----------
    .. [1] X. Wu and S. Fomel, Geophysics 83(5), O67-O82, 2018, doi:10.1190/geo2018-0115.1.
    """
    opt = options or VotingOptions()
    seeds = np.ascontiguousarray(seeds, dtype=np.int64).reshape(-1, 3)
    ids = np.ascontiguousarray(seed_ids, dtype=np.int64).ravel()
    frames = np.ascontiguousarray(frames, dtype=np.float64).reshape(-1, 3, 3)
    if not len(seeds) == len(ids) == len(frames):
        raise InputError(f"surface_votes got {len(seeds)} seeds, {len(ids)} ids and {len(frames)} frames; pass one "
                         "id and one frame per seed")
    att = np.ascontiguousarray(likelihood, dtype=np.float32)  # once, not per batch of seeds
    g0, g1 = (int(v) for v in origin)
    i0, j0, m0, m1 = (int(v) for v in core) if core is not None else (g0, g1, att.shape[0], att.shape[1])
    if i0 < g0 or j0 < g1 or m0 < 1 or m1 < 1 or i0 + m0 > g0 + att.shape[0] or j0 + m1 > g1 + att.shape[1]:
        raise InputError(f"core {core} lies outside the likelihood block of shape {att.shape} at {origin}")
    total = VoteSum(image_shape, (i0, j0, m0, m1), options=opt)
    n_chunks = max(1, min(20, len(seeds) // 200))  # the surfaces of one chunk at a time: bounded memory, progress
    bounds = np.linspace(0, len(seeds), n_chunks + 1).astype(int)
    with progress_steps(len(seeds), "fault voting", unit="seed", enabled=progress) as steps:
        for lo, hi in zip(bounds[:-1], bounds[1:]):
            part = seed_surfaces(att, seeds[lo:hi], frames[lo:hi], image_shape=image_shape, options=opt,
                                 origin=origin)
            total.add(seeds[lo:hi], ids[lo:hi], part)
            steps.advance(int(hi - lo))
    return total.votes()


@dataclass(frozen=True, eq=False)
class SeedSurfaces:
    """Optimal surfaces of seeds (steps 2-3 of :func:`vote_faults`), where they pass and how strong they are: what a
    seed's votes need, wherever it is voted.

    Attributes
    ----------
    offsets : (k, nw, nv, 3) int8 (int16 for boxes reaching beyond 127 samples) ndarray
        The sample (inline, crossline, sample) each surface passes at strike step ``iw`` and dip step ``iv``,
        relative to its seed, rounded in image coordinates.
    mean_likelihood : (k,) float64 ndarray
        Each surface's mean likelihood inside the image: its vote; -1 where no sample of it is inside (no vote).
    normals : (k, 3) float32 ndarray
        Each surface's unit normal at its seed.
    """

    offsets: np.ndarray
    mean_likelihood: np.ndarray
    normals: np.ndarray

    def take(self, rows) -> SeedSurfaces:
        """The surfaces of ``rows`` (indices or a boolean mask)."""
        return SeedSurfaces(self.offsets[rows], self.mean_likelihood[rows], self.normals[rows])


def seed_surfaces(likelihood, seeds, frames, *, image_shape, options: VotingOptions | None = None,
                  origin=(0, 0)) -> SeedSurfaces:
    """The optimal surface of each seed in its voting box (steps 2-3 of :func:`vote_faults`), on (a block of) the
    fault likelihood holding every sample the seeds' boxes reach (:meth:`VotingOptions.reach` around the seeds).

    Positions are computed in image coordinates, so a seed's surface is the same whichever block holds its box: a
    cube larger than memory computes each seed's surface once and casts its votes into every block it reaches
    (:class:`VoteSum`).

    Parameters
    ----------
    likelihood : (n_a, n_b, n_samples) array_like of float
        Fault likelihood in [0, 1] (a 2D section as (n_traces, 1, n_samples)): the whole image, or the block of it
        from inline ``origin[0]`` and crossline ``origin[1]`` on.
    seeds : (k, 3) array_like of int
        Seeds (:func:`greedy_seeds`), image indices.
    frames : (k, 3, 3) array_like of float
        The seeds' fault frames (:func:`fault_frames`).
    image_shape : tuple of int
        Shape of the whole image, 2D or 3D: the voting box depends on it.
    options : VotingOptions, optional
    origin : (int, int)
        Image indices of ``likelihood[0, 0]``.

    Returns
    -------
    SeedSurfaces

    Raises
    ------
    InputError
        Seeds and frames differ in length.

    References
    ----------
    .. [1] X. Wu and S. Fomel, Geophysics 83(5), O67-O82, 2018, doi:10.1190/geo2018-0115.1.
    .. [2] D. Hale, "Dynamic warping of seismic images", Geophysics 78(2), S105-S115, 2013,
       doi:10.1190/geo2012-0327.1.
    """
    opt = options or VotingOptions()
    att = np.ascontiguousarray(likelihood, dtype=np.float32)
    seeds = np.ascontiguousarray(seeds, dtype=np.int64).reshape(-1, 3)
    frames = np.ascontiguousarray(frames, dtype=np.float64).reshape(-1, 3, 3)
    if len(seeds) != len(frames):
        raise InputError(f"seed_surfaces got {len(seeds)} seeds and {len(frames)} frames; pass one frame per seed")
    shape3 = np.asarray(image_shape if len(image_shape) == 3 else (image_shape[0], 1, image_shape[1]), np.int64)
    ru, rv, rw = opt.box(tuple(image_shape))
    b = int(np.ceil(1.0 / float(opt.max_strain)))
    sigma = float(opt.surface_smoothing) * b
    a_smooth = 0.0 if sigma <= 0 else (1.0 + sigma * sigma - np.sqrt(1.0 + 2.0 * sigma * sigma)) / (sigma * sigma)
    dtype = np.int8 if opt.reach(tuple(image_shape)) < 127 else np.int16
    offsets = np.zeros((len(seeds), 2 * rw + 1, 2 * rv + 1, 3), dtype)
    fa = np.full(len(seeds), -1.0)
    normals = np.zeros((len(seeds), 3), np.float32)
    g0, g1 = (int(v) for v in origin)
    surface_kernel(att, g0, g1, shape3, seeds, frames, ru, rv, rw, b, a_smooth, nb.get_num_threads(), offsets, fa,
                   normals)
    return SeedSurfaces(offsets, fa, normals)


class VoteSum:
    """The votes of seed surfaces over (a block of) an image, summed as seeds are added (step 4 of
    :func:`vote_faults`).

    Seeds must be added in increasing id order (their positions in the image's list of seeds), in one or several
    calls: each seed's votes go to the thread ``id % n_threads`` (numba's threads), so the float sums are those of
    the whole image voted at once, in the same order, whichever block or batch of seeds a surface comes in.

    Parameters
    ----------
    image_shape : tuple of int
        Shape of the whole image, 2D or 3D (the scale of the votes depends on it).
    core : (int, int, int, int)
        ``(i0, j0, m0, m1)``: the votes kept, for the image's inlines ``i0 .. i0 + m0 - 1`` and crosslines
        ``j0 .. j0 + m1 - 1``.
    options : VotingOptions, optional

    Notes
    -----
    Memory: 12 bytes per core sample and numba thread, until :meth:`votes`.
    """

    def __init__(self, image_shape, core, *, options: VotingOptions | None = None):
        self.image_shape = tuple(int(n) for n in image_shape)
        self.opt = options or VotingOptions()
        self.i0, self.j0, m0, m1 = (int(v) for v in core)
        n2 = self.image_shape[-1]
        n_threads = nb.get_num_threads()
        self._votes = np.zeros((n_threads, m0, m1, n2), np.float32)
        self._best = np.zeros((n_threads, m0, m1, n2), np.float32)
        self._best_seed = np.full((n_threads, m0, m1, n2), -1, np.int32)
        self._normals = []
        self._count = 0
        self._last = -1

    def add(self, seeds, seed_ids, surfaces: SeedSurfaces) -> None:
        """Cast the votes of ``surfaces`` (of ``seeds``, ids ``seed_ids`` increasing, after those added before).

        Raises
        ------
        InputError
            Lengths differ, or the ids do not follow those added before in increasing order.
        """
        seeds = np.ascontiguousarray(seeds, dtype=np.int64).reshape(-1, 3)
        ids = np.ascontiguousarray(seed_ids, dtype=np.int64).ravel()
        if not len(seeds) == len(ids) == len(surfaces.mean_likelihood):
            raise InputError(f"VoteSum.add got {len(seeds)} seeds, {len(ids)} ids and "
                             f"{len(surfaces.mean_likelihood)} surfaces; pass one id and one surface per seed")
        if len(ids) == 0:
            return
        if ids[0] <= self._last or np.any(np.diff(ids) <= 0):
            raise InputError("VoteSum.add needs the seeds in increasing id order, after those added before")
        # the strongest surface is recorded by its position in the seeds added so far (increasing with the ids:
        # the same tie-breaks)
        positions = np.arange(self._count, self._count + len(ids), dtype=np.int64)
        cast_votes(seeds, ids, positions, np.ascontiguousarray(surfaces.offsets),
                    np.ascontiguousarray(surfaces.mean_likelihood, dtype=np.float64), self.i0, self.j0,
                    self._votes, self._best, self._best_seed)
        self._normals.append(np.asarray(surfaces.normals, np.float32))
        self._count += len(ids)
        self._last = int(ids[-1])

    def votes(self) -> FaultVotes:
        """The summed votes, divided by :meth:`VotingOptions.full_vote` and clipped to [0, 1], and the orientation
        of the strongest surface through each sample; the arrays are freed from this object.

        Returns
        -------
        FaultVotes
            Arrays of the core's shape (3D form).
        """
        total = self._votes.sum(axis=0)
        self._votes = None
        normals = np.concatenate(self._normals) if self._normals else np.zeros((0, 3), np.float32)
        seed_strike, seed_dip = _strike_dip(normals, len(self.image_shape) == 2)
        positions = np.arange(self._count, dtype=np.int64)
        strike = np.zeros(total.shape, np.float32)
        dip = np.zeros(total.shape, np.float32)
        strongest(self._best, self._best_seed, positions, seed_strike, seed_dip, strike, dip)
        self._best = self._best_seed = None
        np.multiply(total, np.float32(1.0 / self.opt.full_vote(self.image_shape)), out=total)
        np.clip(total, 0.0, 1.0, out=total)
        return FaultVotes(total, strike, dip, self._count)


def surface_block(place, likelihood, seeds, frames, shape, opt) -> BlockOutput:
    """The optimal surfaces (:func:`seed_surfaces`) of the seeds in one block, on the live likelihood read with the
    voting's reach around it.

    Parameters
    ----------
    place : BlockPlace
    likelihood : (m0, m1, n_samples) float32 ndarray
        The live likelihood of ``place.region``.
    seeds, frames : (k, 3) int64 and (k, 3, 3) float64 ndarrays
        Every seed of the cube and its fault frame.
    shape : (int, int, int)
    opt : VotingOptions

    Returns
    -------
    BlockOutput
        Lists ``ids`` (the block's seeds' indices in ``seeds``, in :func:`place_order`), ``mean_likelihood``,
        ``normals`` and ``offsets`` (:class:`SeedSurfaces`), read back row by row by :func:`vote_block`.
    """
    i0, i1, j0, j1 = place.block
    ids = np.nonzero((seeds[:, 0] >= i0) & (seeds[:, 0] < i1) & (seeds[:, 1] >= j0) & (seeds[:, 1] < j1))[0]
    ids = ids[place_order(seeds[ids])]  # neighbouring seeds in one part (vote_block adds them back in id order)
    likelihood = np.ascontiguousarray(likelihood, dtype=np.float32)
    parts = []  # the seeds in up to 20 parts, reported in memory (each seed's surface its own: the same bits)
    with progress_within(ids.size, unit="seed") as bar:
        for part in np.array_split(ids, max(1, min(20, ids.size // 200))):
            parts.append(seed_surfaces(likelihood, seeds[part], frames[part], image_shape=shape, options=opt,
                                       origin=place.origin))
            bar.advance(part.size)
    return BlockOutput(lists={"ids": np.asarray(ids, np.int64),
                              **{name: np.concatenate([getattr(p, name) for p in parts])
                                 for name in ("mean_likelihood", "normals", "offsets")}})


def vote_block(place, near, seeds, blocks, surfaces, shape, opt, batch_bytes) -> BlockOutput:
    """Votes over one block's core of the surfaces of the seeds reaching it, added in id order (as in memory,
    :class:`VoteSum`), a batch of at most ``batch_bytes`` of surfaces at a time, 0 near dead samples.

    Parameters
    ----------
    place : BlockPlace
    near : (n_inlines, n_xlines, n_samples) uint8 array read by slicing, or None
        Samples near dead ones (None: none).
    seeds : (k, 3) int64 ndarray
        Every seed of the cube.
    blocks : list of tuple
        The blocks of the seed surfaces.
    surfaces : callable
        ``surfaces(block, names) -> dict``: the lists of :func:`surface_block` of a block, memory-mapped.
    shape : (int, int, int)
    opt : VotingOptions
    batch_bytes : int
        Bytes of surfaces read back at once (the sums do not depend on it).

    Returns
    -------
    BlockOutput
        ``votes``, ``vote_strike_deg``, ``vote_dip_deg`` of the core.
    """
    i0, i1, j0, j1 = place.block
    r = opt.reach(shape)
    total = VoteSum(shape, (i0, j0, i1 - i0, j1 - j0), options=opt)
    parts = []  # (ids, rows, stored lists) of the seeds reaching the block, per seed block
    for b in blocks:  # seed blocks within reach
        if b[1] <= i0 - r or b[0] >= i1 + r or b[3] <= j0 - r or b[2] >= j1 + r:
            continue
        stored = surfaces(b, ("ids", "mean_likelihood", "normals", "offsets"))
        at = seeds[stored["ids"]]
        rows = np.nonzero((at[:, 0] >= i0 - r) & (at[:, 0] < i1 + r) & (at[:, 1] >= j0 - r) &
                          (at[:, 1] < j1 + r))[0]
        if rows.size:
            parts.append((stored["ids"][rows], rows, stored))
    if parts:
        ids = np.concatenate([q[0] for q in parts])
        which = np.concatenate([np.full(q[0].size, n) for n, q in enumerate(parts)])
        rows = np.concatenate([q[1] for q in parts])
        order = np.argsort(ids)
        ids, which, rows = ids[order], which[order], rows[order]
        # at most batch_bytes of surfaces, and a 20th of the seeds (reported in memory), at a time: the same sums
        # whatever the batches (VoteSum)
        batch = max(1, min(batch_bytes // (parts[0][2]["offsets"][:1].nbytes + 32), -(-ids.size // 20)))
        with progress_within(ids.size, unit="seed") as bar:
            for lo in range(0, ids.size, batch):
                hi = min(lo + batch, ids.size)
                total.add(seeds[ids[lo:hi]], ids[lo:hi], _surfaces_of(parts, which[lo:hi], rows[lo:hi]))
                bar.advance(hi - lo)
    votes = total.votes()
    del total
    if near is not None:  # None: no dead sample (a run in memory)
        without_dead_edges(votes.votes, near[place.target].view(bool))
    return BlockOutput({"votes": votes.votes, "vote_strike_deg": votes.strike_deg, "vote_dip_deg": votes.dip_deg})


def _surfaces_of(parts, which, rows) -> SeedSurfaces:
    """The stored surfaces of a batch of seeds, in the batch's order: seed k is row ``rows[k]`` of seed block
    ``which[k]`` (an item of ``parts``)."""
    out = None
    for n, (_, _, stored) in enumerate(parts):
        mine = np.nonzero(which == n)[0]
        if not mine.size:
            continue
        offsets = stored["offsets"]
        if out is None:
            out = SeedSurfaces(np.empty((which.size,) + offsets.shape[1:], offsets.dtype), np.empty(which.size),
                               np.empty((which.size, 3), np.float32))
        out.offsets[mine] = offsets[rows[mine]]
        out.mean_likelihood[mine] = stored["mean_likelihood"][rows[mine]]
        out.normals[mine] = stored["normals"][rows[mine]]
    return out
