"""Fault throw by registering the reflectors on the two sides of each fault.

For every fault (from :func:`seismo3d.seismic.fault_skins`, or any set of fault points), the reflectors of the
footwall and of the hanging wall are carried onto the fault plane along their slopes, giving two *fault-plane images*;
the vertical shift that aligns them is the throw (Hale 2013, section "Fault throws"). The shift is found in two steps:
a global search of the normalised cross-correlation over integer shifts (immune to cycle skipping on the periodic
reflectors), then a registration of the reflector peaks of the two images with the ICP engine
(:func:`seismo3d.registration.icp`, method.md section 1), which models throw varying linearly along strike.

Conventions (index space, as :mod:`seismo3d.data.synthetic`): axis 0 inline, 1 crossline, the last the sample
(down); a trace spacing and a sample count as 1. Throw is the vertical slip in samples (times the sample interval: ms
or m): **positive when the hanging wall moved down** (normal fault), negative when it moved up (reverse). The hanging
wall is the block above the fault plane, on the side it dips toward (undefined for a vertical fault: sign arbitrary).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._options import resolve_options
from ..._progress import progress_steps, reporting_within
from ..._threads import deferred, task_pool, task_workers
from ..._validation import as_normals, as_points, check_positive
from ...errors import InputError
from ...geometry.normals import estimate_normals
from ..attributes import ReflectorOrientation
from .windows import ArrayWindows, LazyWindows, StoredWindows, cube_windows, is_dask_array
from .result import FaultThrow
from .throw_patches import ncc_shift, patch_grid, patch_images, read_box, register_patch
from .throw_profile import fault_zone, section_profile, section_read_box
from .throw_windows import TensorWindows

__all__ = ["FaultThrow", "ThrowOptions", "fault_throw", "fault_throws", "hanging_wall_normals"]


@dataclass(frozen=True)
class ThrowOptions:
    """Options of :func:`fault_throw` and :func:`fault_throws`; the defaults are the ones every seismo3d command uses.

    Attributes
    ----------
    max_throw : int, optional
        Largest |throw| searched, samples. None: ``min(20, n_samples // 4)`` (3D; a patch searches at most
        ``max_throw_per_height`` of its height), ``n_samples // 4`` (2D: ``profile_max_*`` bound it).
    side_traces : (int, int)
        Nearest and farthest lateral offsets from the fault read on each side, in traces.
    patch_traces : float
        Length of the patches along strike, in traces.
    refine : bool
        Refine the correlation shift by ICP registration of reflector peaks (3D only).
    max_throw_per_height : float
        Largest |throw| searched, as a fraction of the samples a patch's fault-plane images span (the fault's height
        there): faults displace about 1-10 % of their length (displacement-length scaling, Kim & Sanderson 2005), so a
        shift of over a third of the traced height is a cycle skip between periodic reflectors rather than a throw.
        (8-bit Penobscot cube, before this limit: 14 of 282 faults read 9-20 samples on faults 26-45 samples tall.)
    min_overlap : (int, int)
        Fewest fault-plane image samples seen on both sides for a correlation shift to count (2D, 3D).
    min_rows : int
        ... and fewest distinct samples (t) among them: about 2.5 periods of a 0.15 cycles/sample wavelet.
    small_shift_prior : float
        Weight of the preference for small shifts in the correlation search: the correlation is multiplied by
        ``1 - small_shift_prior |k| / (max_throw + 1)``, so that of two shifts that correlate about equally (a
        reflector sequence repeating by chance) the smaller displacement is kept.
    min_peaks : int
        Fewest reflector-peak points per side for a registration.
    max_rotation : float
        Radians: a registration whose in-plane rotation, or a throw gradient along strike, exceeds this (one sample
        per 10 traces) is rejected.
    slope_margin : int
        Traces beyond the farthest offset where reflector slopes are read (outside the structure tensor's blur).
    icp_distances : tuple of float
        Coarse-to-fine correspondence distances of the peak registration, samples (under half a reflector spacing).
    profile_window : int
        2D: length of the windows down the fault whose throws make its throw profile, samples (a fault spanning
        fewer than two windows is one window: windows that all overlap do not measure apart). 64: 6-8 periods of a
        0.1-0.15 cycles/sample wavelet, so that a window's shift is not a cycle skip, and a quarter to a sixth of the
        large faults of the real sections (250-400 samples tall).
    profile_step : int
        2D: distance between the starts of consecutive windows, samples.
    profile_smoothness : float
        2D: cost of a change of throw between consecutive windows, correlation per squared sample (the windows'
        shifts maximise their correlations less this times their squared changes): a jump of a reflector period
        (8-10 samples) costs 0.3-0.5 of correlation, a gradient of a sample per window 0.005.
    profile_max_throw_per_length : float
        2D: largest |throw| searched, as a fraction of the fault's extent down the section, samples per sample (the
        whole fault, where ``max_throw_per_height`` bounds a 3D patch, a piece of one). Faults displace at most about
        a tenth of their length (displacement-length scaling, Kim & Sanderson 2005: 0.001-0.1), and a 2D fault's
        extent in samples is at most its length (a Volve fault 85 samples tall read -66 ms with a third of it:
        a cycle skip). ``tools/dev_fault_scores.py``, 2026-11-26, 1/3, 0.2, 0.15, 0.1: F3 F1 0.486, 0.486, 0.489,
        0.494, the Great South Basin 0.829 at each.
    profile_max_shift : float
        2D: largest |throw| searched, a fraction of ``profile_window`` (32 samples: a window and its shifted twin
        share half their samples). A third with 20 samples at most until 2026-11-27: xl1155's large fault read 51
        ms near 1500 ms (116 ms now; 104-108 ms by hand), generated faults throwing 21-28 samples a cycle skip.
    step_traces : int
        2D: traces beside each edge of a fault's zone whose neighbour lags give that side's dip for the step at the
        fault (:func:`~seismo3d.seismic.faults.throw_profile.section_step`; at most the traces read beyond it).
    ambiguous_ratio : float
        A fault's throw is ambiguous when the median of its points' ``rival_ratio`` (the best rival shift's weighted
        correlation over the chosen one's, :attr:`FaultThrow.rival_ratio`) reaches this; its
        ``alternative_throw`` is then the rivals' median. 0.4, chosen on Penobscot inlines 1075-1083 only
        (``benchmarks/fault_throw.py --half choose``, 2026-11-28; the largest share of wrong throws reached less
        the share of right ones, of 0.3-0.9 by 0.1): of the 22 faults cutting a people's horizon, 4 of the 5 whose
        throw is 5 samples or more off the horizon's offset, or of the wrong sign, reach it, and 3 of the 17 others
        (0.3, 0.5, 0.6, 0.7: 4, 2, 1, 1 of 5 against 9, 2, 0, 0 of 17); reported on inlines 1084-1092.

    Raises
    ------
    InputError
        A value out of range (checked when the options are made).
    """

    max_throw: int | None = None
    side_traces: tuple = (2, 6)
    patch_traces: float = 32.0
    refine: bool = True
    max_throw_per_height: float = 1.0 / 3.0
    min_overlap: tuple = (16, 48)
    min_rows: int = 16
    small_shift_prior: float = 0.25
    min_peaks: int = 12
    max_rotation: float = 0.1
    slope_margin: int = 3
    icp_distances: tuple = (2.0, 1.0)
    profile_window: int = 64
    profile_step: int = 16
    profile_smoothness: float = 0.005
    profile_max_throw_per_length: float = 0.1
    profile_max_shift: float = 0.5
    step_traces: int = 3
    ambiguous_ratio: float = 0.4

    def __post_init__(self):
        if self.max_throw is not None:
            object.__setattr__(self, "max_throw", int(round(check_positive(self.max_throw, "max_throw"))))
        try:
            lo, hi = (int(v) for v in self.side_traces)
        except (TypeError, ValueError) as exc:
            raise InputError(f"side_traces must be a pair of ints (nearest, farthest) in traces; got "
                             f"{self.side_traces!r}") from exc
        if not 1 <= lo <= hi:
            raise InputError(f"side_traces must satisfy 1 <= nearest <= farthest; got {self.side_traces!r}")
        object.__setattr__(self, "side_traces", (lo, hi))
        object.__setattr__(self, "patch_traces", float(check_positive(self.patch_traces, "patch_traces")))
        check_positive(self.max_throw_per_height, "max_throw_per_height")
        check_positive(self.profile_max_throw_per_length, "profile_max_throw_per_length")
        if not 0.0 < float(self.profile_max_shift) <= 1.0:
            raise InputError(f"profile_max_shift must be a fraction of profile_window in (0, 1]; got "
                             f"{self.profile_max_shift!r}")
        check_positive(self.max_rotation, "max_rotation")
        check_positive(self.small_shift_prior, "small_shift_prior", allow_zero=True)
        for name in ("profile_window", "profile_step", "step_traces"):
            value = getattr(self, name)
            if not isinstance(value, (int, np.integer)) or value < 1:
                raise InputError(f"{name} must be a positive int of samples; got {value!r}")
        check_positive(self.profile_smoothness, "profile_smoothness", allow_zero=True)
        check_positive(self.ambiguous_ratio, "ambiguous_ratio")
        if self.profile_window < 2 * self.min_rows:
            raise InputError(f"profile_window={self.profile_window} samples must be at least 2 * min_rows "
                             f"({2 * self.min_rows}) for a window's shift to overlap enough rows; use a longer window")


# --------------------------------------------------------------------------------------------------------------------
# validation


def _fault_arrays(fault, ndim: int) -> tuple[np.ndarray, np.ndarray, int]:
    """Points, normals and id of a Fault-like object or of a bare (n, ndim) point array."""
    if isinstance(fault, np.ndarray) or isinstance(fault, (list, tuple)):
        pts = as_points(fault, "fault", dims=(ndim,), min_points=ndim + 1)
        normals, fid = None, 0
    elif hasattr(fault, "points"):
        pts = as_points(fault.points, "fault.points", dims=(ndim,), min_points=1)
        normals = getattr(fault, "normals", None)
        fid = int(getattr(fault, "id", 0))
    else:
        raise InputError(f"fault must be a Fault (with .points and .normals) or an (n, {ndim}) array of fault points; "
                         f"got {type(fault).__name__}")
    if normals is None:
        if len(pts) < ndim + 1:
            raise InputError(f"fault has {len(pts)} points; at least {ndim + 1} are needed to estimate its normals")
        normals = estimate_normals(pts, k=min(16, len(pts)), orient="none")
    else:
        normals = as_normals(normals, "fault.normals", pts.shape)
    return pts, normals, fid


def _max_throw(opt: ThrowOptions, n_samples: int, *, two_d: bool = False) -> int:
    """The largest |throw| searched: ``opt.max_throw`` or ``min(20, n_samples // 4)`` (2D: n_samples // 4)."""
    if opt.max_throw is None:
        max_throw = n_samples // 4 if two_d else min(20, n_samples // 4)
    else:
        max_throw = opt.max_throw
    max_throw = int(round(check_positive(max_throw, "max_throw")))
    if max_throw < 1 or max_throw >= n_samples // 2:
        raise InputError(f"max_throw={max_throw} samples must be >= 1 and below half the trace length "
                         f"({n_samples // 2}); use a smaller max_throw")
    return max_throw


# --------------------------------------------------------------------------------------------------------------------
# fault-plane images


def hanging_wall_normals(normals3) -> np.ndarray:
    """Fault normals sign-aligned to their principal direction and oriented upward, into the hanging wall: the sides
    :func:`fault_throw` measures the throw with.

    Normals from strike and dip point to either side of a (near-)vertical fault (strike and strike + 180 degrees);
    aligning them to the principal direction of the set gives every point the same sides.

    Parameters
    ----------
    normals3 : (n, 3) array_like of float
        Unit fault normals (inline, xline, sample), of either sign.

    Returns
    -------
    (n, 3) float64 ndarray
        The normals, each multiplied by +-1; their principal direction has a non-positive sample component (for a
        vertical fault, a negative first non-zero lateral component is flipped).
    """
    normals3 = np.asarray(normals3, dtype=np.float64)
    m = normals3.T @ normals3
    ref = np.linalg.eigh(m)[1][:, -1]
    if ref[2] > 1e-6 or (abs(ref[2]) <= 1e-6 and (ref[0], ref[1]) < (0.0, 0.0)):
        ref = -ref
    sgn = np.where(normals3 @ ref < 0, -1.0, 1.0)
    return normals3 * sgn[:, None]


# --------------------------------------------------------------------------------------------------------------------
# correlation start and registration refinement


# --------------------------------------------------------------------------------------------------------------------
# public API


def fault_throw(data, fault, *, orientation: ReflectorOrientation | None = None, options: ThrowOptions | None = None,
                **overrides) -> FaultThrow:
    """Vertical throw along one fault, by registering the reflectors on its two sides.

    1. **Fault-plane images** (Hale 2013). The fault is cut into patches of ``patch_traces`` traces along strike
       (so a curved fault is locally planar); each patch has a local frame: ``u`` along strike, ``t`` the sample and
       ``s`` across the fault (the horizontal part of its normal, positive into the hanging wall). On a (u, t) grid
       over the patch (lateral fault position interpolated from the fault points), the cube is read at lateral
       offsets ``s = -far..-near`` (footwall) and ``near..far`` (hanging wall), each sample taken on the reflector
       that passes through the fault-plane node (``t + p s``, ``p`` the structure-tensor reflector slope along ``s``
       where the reflector lands). The averages over offsets are the footwall and hanging-wall images ``F(u, t)`` and
       ``H(u, t)``. For pure dip-slip, ``H(u, t) = F(u, t - throw(u))``: the shift between them is the vertical throw
       itself, not the separation seen at one lateral position (which differs by the factor
       ``1 - tan(reflector dip) / tan(fault dip)``).
    2. **Start**: the integer shift in ``[-m, m]`` maximising the normalised cross-correlation of ``F`` and ``H``,
       refined by a parabola through the three best values. Searching all shifts avoids the cycle skipping that ICP
       from zero suffers on periodic reflectors once the throw exceeds half a period. ``m`` is ``max_throw`` or a
       third of the samples the patch spans, whichever is smaller: faults displace about 1-10 % of their length
       (displacement-length scaling [4]_), and a larger shift on a short fault is a cycle skip onto the next
       reflector of a periodic sequence.
    3. **Refinement** (3D, ``refine=True``): the reflector peaks (maxima along ``t`` above half the image RMS, with
       parabolic sub-sample position) of ``F`` are registered onto those of ``H`` as 2D (u, t) points by rigid
       point-to-plane ICP (:func:`seismo3d.registration.icp`, method.md eqs. 10-15) started at the correlation
       shift, with correspondences within 2 then 1 sample; the in-plane rotation lets the throw vary linearly along
       strike. The throw of each registered peak is the t offset, at the peak's ``u``, of the hanging-wall reflector
       it lands on; a robust line ``a + b u`` through them gives the throw at every fault point of the patch. A
       registration that fails, has fitness < 0.5, rotates more than ``max_rotation`` (0.1 rad) or moves more than
       1.5 samples from the start is rejected and the correlation shift is kept (``registered`` is False there).

    In a 2D section the fault plane is a line (one ``u``), and its throw is a **profile down the fault**:

    a. **Fault zone**: at each sample, the traces from the fault's first to its last point within 1 sample, every
       strand of it (a fault traced as two strands a few traces apart, or a Y, has a block between them whose
       reflectors belong to neither side).
    b. **Side images** read ``side_traces`` beyond the zone's edges, each sample on the reflector through the node
       of the zone's centre, carried along that side's own reflector slope (read ``side_traces[1] + slope_margin``
       traces beyond the edge): the reflectors' dip on either side, not the fault's, says where they meet it.
    c. **Windows** of ``profile_window`` samples every ``profile_step`` down the fault (one window when the fault
       spans fewer than two), each with its correlation curve over the shifts; the shifts of all windows are chosen
       together (dynamic programming: their correlations less ``profile_smoothness`` times their squared changes,
       the whole fault's curve added to each window's against a cycle skip), refined by a parabola and interpolated
       to the points. ``correlation`` and ``correlation_unshifted`` are then per window too. No registration.
       Penobscot crossline 1155's large fault reads 116 ms near 1500 ms, 54-58 ms at 1900-2100 ms and 0-2 ms at
       2350-2550 ms, against 104-108, 57-62 and under 15 ms by hand (tests/seismic/faults/test_pipeline.py).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like, or 3D dask.array.Array
        Seismic amplitudes, the last axis the sample. Must be finite. A 3D dask array (e.g.
        ``seismo3d.open(path).data``, any numeric dtype and chunks) is never held whole: each
        patch reads only its window of traces (see :func:`fault_throws`), with the same result as in memory.
    fault : Fault or (n_points, ndim) array_like
        A fault from :func:`seismo3d.seismic.fault_skins` (any object with ``points`` (n, ndim) index
        coordinates and ``normals`` (n, ndim) unit fault normals, of either sign; ``id`` is used when present), or a
        bare array of fault points (index coordinates) whose normals are then estimated by PCA over 16 neighbours.
    orientation : ReflectorOrientation, optional
        Reflector orientation of ``data`` (:func:`structure_tensor_orientation`); computed when not given (pass it
        when measuring several faults of one cube, or use :func:`fault_throws`).
    options : ThrowOptions, optional
        Search range, sides, patch length, refinement and the registration's limits (:class:`ThrowOptions`).
    **overrides
        Fields of :class:`ThrowOptions` by name (e.g. ``max_throw=8``, ``side_traces=(2, 6)``, ``patch_traces``,
        ``refine``), replacing those of ``options``.

    Returns
    -------
    FaultThrow
        ``throw (n_points,) float32`` in samples (positive = hanging wall down), ``registered``, ``correlation``,
        ``median_throw``, ``fitness``, ``inlier_rmse``, ``n_points_used``.

    Raises
    ------
    InputError
        If ``data`` is not a finite 2D/3D array, the fault's points do not match its dimension, the orientation does
        not match ``data``, or an option is out of range.

    References
    ----------
    .. [1] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1.
    .. [2] Y. Chen and G. Medioni, "Object modelling by registration of multiple range images", Image and Vision
       Computing 10(3), 1992, doi:10.1016/0262-8856(92)90066-C (point-to-plane ICP).
    .. [3] A. Vokhmintcev and M. Timchenko, the registration method of seismo3d (method.md, eqs. 10-16).
    .. [4] Y.-S. Kim and D. J. Sanderson, "The relationship between displacement and length of faults: a review",
       Earth-Science Reviews 68(3-4), 317-334, 2005, doi:10.1016/j.earscirev.2004.06.003.

    Examples
    --------
    >>> from seismo3d.data.synthetic import synthetic_cube
    >>> syn = synthetic_cube((64, 64), n_faults=1, seed=3, noise=0.0)
    >>> pts = np.argwhere(syn.fault_labels == 1)
    >>> res = fault_throw(syn.cube, pts)
    >>> sign = 1 if syn.faults[0].kind == "normal" else -1
    >>> bool(abs(res.median_throw - sign * syn.faults[0].throw_samples) < 1)
    True
    """
    source = _windows(data, orientation)
    opt = resolve_options(ThrowOptions, options, overrides, "fault_throw")
    return _fault_throw(source, fault, opt)


def fault_throws(data, faults, *, orientation: ReflectorOrientation | None = None, options: ThrowOptions | None = None,
                 progress: bool = False, **overrides) -> list[FaultThrow]:
    """Throw along each of several faults of one cube or section (see :func:`fault_throw`).

    For an in-memory cube the reflector orientation is computed once (when not given) and shared by all faults: every
    fault is cut into its patches first, the structure tensor smoothed at the traces they read, its slopes
    eigen-decomposed only at the samples the throws read
    (:class:`~seismo3d.seismic.faults.throw_windows.TensorWindows`, the whole cube's slopes bit for bit there).
    A 3D dask array is never held whole: each patch reads only the traces it samples (its nodes' bounding box widened
    by ``side_traces[1] + slope_margin`` + 2 traces), from tiles of 64 x 64 traces whose slopes are computed with the
    structure tensor's halo (:func:`~seismo3d.seismic.attributes.structure_tensor_halo`: 9 traces) and kept (up to 256
    MiB, :class:`~seismo3d.seismic.faults.windows.LazyWindows`): the throws are the in-memory ones (bit for bit on the
    tests' generated cubes). Memory: the tile cache, one window (about 150 x 150 traces for a fault dipping 60-70
    degrees over 256 samples), one tile's orientation workspace and the faults.

    Threads: an in-memory cube's patches are gridded and measured, and the parts of its structure tensor smoothed,
    on numba's thread count of threads (``NUMBA_NUM_THREADS`` or ``numba.set_num_threads``; one, the calling thread,
    when called from another thread than the main one: :func:`seismo3d._threads.task_workers`); each patch's work is
    that of one thread and the faults are assembled in order, so the throws are the same bits whatever the count.
    Their heavy calls (OpenCV's filters, SciPy's interpolation and trees, NumPy) release the GIL; the reflector
    slopes are decomposed by one thread at a time. A section's faults, a dask array's and a given orientation's are
    measured in the calling thread.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like, or 3D dask.array.Array
        Seismic amplitudes, the last axis the sample. Must be finite (for a dask array: the traces read, checked as
        they are read). Or a window source of :mod:`seismo3d.seismic.faults.windows` (e.g.
        ``LazyWindows(dask_array, tile=32, cache_mb=64)`` for another memory / speed trade-off).
    faults : sequence of Fault or of (n_points, ndim) array_like
        Faults from :func:`seismo3d.seismic.fault_skins`.
    orientation : ReflectorOrientation, optional
        As in :func:`fault_throw`; with a dask array, its slopes are sliced per window instead of recomputed.
    options, **overrides
        As in :func:`fault_throw`.
    progress : bool
        Report progress over the faults (:mod:`seismo3d._progress`), after a line when an in-memory cube's reflector
        slopes are prepared (its structure tensor where the faults' patches read, before the first fault) and a line
        per part of that tensor (:meth:`~seismo3d.seismic.faults.throw_windows.TensorWindows.prepare`). A fault is
        counted when all its patches are measured.

    Returns
    -------
    list of FaultThrow
        One per fault, in the order given.

    Raises
    ------
    InputError
        As :func:`fault_throw`.

    References
    ----------
    .. [1] D. Hale, Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1.
    """
    source = _windows(data, orientation)
    opt = resolve_options(ThrowOptions, options, overrides, "fault_throws")
    cuts = [_fault_cut(source.shape, f, opt) for f in faults]  # checked, and cut into patches, before the work
    # an in-memory cube's patches on numba's thread count of threads (their heavy calls release the GIL): each
    # patch's work is the same whichever thread runs it, and the faults are assembled in order, patch by patch
    tensor = isinstance(source, TensorWindows)
    out = []
    with task_pool(task_workers(sum(len(c[-1]) for c in cuts)) if tensor else 1, "seismo3d-throw") as run:
        faults = _fault_setups(source.shape, cuts, opt, run)
        with progress_steps(len(faults), "throw", unit="fault", enabled=progress) as bar:
            if tensor and faults:  # the structure tensor where the patches read, first
                bar.advance(0, status="reflector slopes: the structure tensor where the faults are")
                with reporting_within("throw" if progress else None):  # a line per part of the tensor
                    source.prepare([p.box for f in faults for p in f.patches], run=run)
            measured = [[run(_measure_patch, source, p, opt, f.max_throw) for p in f.patches] if f.patches else ()
                        for f in faults]
            for f, patches in zip(faults, measured):
                out.append(_measure(source, f, opt, [p.result() for p in patches]))
                bar.advance()
    return out


def _windows(data, orientation):
    """The window source the throws read: an in-memory cube without its orientation, its slopes decomposed where
    they are read (:class:`~seismo3d.seismic.faults.throw_windows.TensorWindows`); else
    :func:`~seismo3d.seismic.faults.windows.cube_windows` (a section, a given orientation, a dask array or a source)."""
    if isinstance(data, TensorWindows) and orientation is None:
        return data
    if (orientation is None and not isinstance(data, (ArrayWindows, LazyWindows, StoredWindows))
            and not is_dask_array(data) and np.ndim(data) == 3):
        return TensorWindows(data)
    return cube_windows(data, orientation)


@dataclass(frozen=True, eq=False)
class _Patch:
    """A patch of a 3D fault: its points (``sel``: rows of the fault's), fault-plane grid and the traces it reads."""

    sel: np.ndarray
    grid: object  # throw_patches._PatchGrid
    box: tuple  # (i0, i1, j0, j1): read_box


@dataclass(frozen=True, eq=False)
class _FaultSetup:
    """One fault checked and ready to measure: its points and hanging-wall normals (3D: (n, 3); a section's points
    (n, 2) beside (n, 3) normals), id, largest shift searched, and patches (3D; none for a section)."""

    pts: np.ndarray
    nrm3: np.ndarray
    fid: int
    max_throw: int
    patches: tuple


def _fault_setup(shape, fault, opt: ThrowOptions) -> _FaultSetup:
    """Check one fault against the data of ``shape`` and cut it into patches along its mean strike (3D): the
    geometry its throw is measured on, made once."""
    return _fault_setups(shape, [_fault_cut(shape, fault, opt)], opt, deferred)[0]


def _fault_setups(shape, cuts: list, opt: ThrowOptions, run) -> list[_FaultSetup]:
    """The faults of :func:`_fault_cut` with their patches' grids (:func:`patch_grid`, each by ``run``, as
    :func:`seismo3d._threads.task_pool` yields it) and read boxes, in the order of the faults and of their patches;
    the horizontal patches left out."""
    grids = [[run(patch_grid, pts[sel], nrm3[sel]) for sel in sels] for pts, nrm3, _, _, sels in cuts]
    setups = []
    for (pts, nrm3, fid, max_throw, sels), fault_grids in zip(cuts, grids):
        # the patch's traces (plus the halo of their reflector slopes) only; the whole array when in memory
        patches = [_Patch(sel, grid, read_box(grid, opt.side_traces[1] + opt.slope_margin, shape))
                   for sel, grid in zip(sels, (g.result() for g in fault_grids)) if grid is not None]
        setups.append(_FaultSetup(pts, nrm3, fid, max_throw, tuple(patches)))
    return setups


def _fault_cut(shape, fault, opt: ThrowOptions) -> tuple:
    """Check one fault against the data of ``shape`` and cut it into patches along its mean strike (3D): ``(points,
    hanging-wall normals (n, 3), id, largest shift searched, the rows of each patch of 3 points or more)`` (no
    patches for a section)."""
    two_d = len(shape) == 2
    max_throw = _max_throw(opt, shape[-1], two_d=two_d)
    pts, normals, fid = _fault_arrays(fault, len(shape))
    if np.any(pts.min(axis=0) < -0.5) or np.any(pts.max(axis=0) > np.array(shape) - 0.5):
        raise InputError(f"fault {fid} has points outside the data of shape {shape}; pass the faults of this data")
    if two_d:
        nrm3 = np.column_stack([normals[:, 0], np.zeros(len(pts)), normals[:, 1]])
        return pts, hanging_wall_normals(nrm3), fid, max_throw, ()
    nrm3 = hanging_wall_normals(normals)
    n = len(pts)
    # patches along the mean strike
    mean_n = nrm3.mean(axis=0)
    lat = mean_n[:2]
    if np.linalg.norm(lat) > 1e-6:
        h = lat / np.linalg.norm(lat)
        ug = pts[:, :2] @ np.array([-h[1], h[0]])
        n_patch = max(1, int(round(np.ptp(ug) / opt.patch_traces)))
        edges = np.linspace(ug.min(), ug.max(), n_patch + 1)
        pid = np.clip(np.searchsorted(edges, ug, side="right") - 1, 0, n_patch - 1)
    else:
        n_patch, pid = 1, np.zeros(n, np.int64)
    sels = (np.nonzero(pid == k)[0] for k in range(n_patch))
    return pts, nrm3, fid, max_throw, tuple(sel for sel in sels if len(sel) >= 3)


def _fault_throw(source, fault, opt: ThrowOptions) -> FaultThrow:
    """Throw along one fault, reading ``source`` (:func:`~seismo3d.seismic.faults.windows.cube_windows`) one patch
    window at a time."""
    return _measure(source, _fault_setup(source.shape, fault, opt), opt)


def _measure_patch(source, p: _Patch, opt: ThrowOptions, max_throw: int) -> tuple:
    """One patch's measurements, reading ``source``: ``(side coherence, shift, correlation, correlation unshifted,
    rival shift, rival ratio, PatchFit or None)`` (NaN from the shift on when none is found; no fit then, nor
    without ``opt.refine``)."""
    win = source.window(*p.box)
    patch = patch_images(p.grid, win, opt.side_traces, opt.slope_margin)
    coherence = float(np.min(patch.coherence))  # NaN when either side is NaN
    reach = min(max_throw, int(opt.max_throw_per_height * patch.img[0].shape[1]))
    shift, cc, cc0, rival, ratio = ncc_shift(
        patch.img[0], patch.img[1], patch.valid[0], patch.valid[1], reach, opt.min_overlap[1],
        opt) if reach >= 1 else (np.nan,) * 5
    fit = register_patch(patch, shift, opt) if opt.refine and np.isfinite(shift) else None
    return coherence, shift, cc, cc0, rival, ratio, fit


def _measure(source, setup: _FaultSetup, opt: ThrowOptions, measured=None) -> FaultThrow:
    """Throw along one fault set up by :func:`_fault_setup`, reading ``source`` one patch window at a time, or
    assembled from its patches' ``measured`` (:func:`_measure_patch`, in the order of ``setup.patches``)."""
    if len(source.shape) == 2:
        return _section_throw(source, setup.pts, setup.nrm3, setup.fid, opt, setup.max_throw)
    if measured is None:
        measured = [_measure_patch(source, p, opt, setup.max_throw) for p in setup.patches]
    n = len(setup.pts)
    throw = np.full(n, np.nan)
    corr = np.full(n, np.nan)
    corr0 = np.full(n, np.nan)
    coherence = np.full(n, np.nan)
    rival = np.full(n, np.nan)
    rival_ratio = np.full(n, np.nan)
    registered = np.zeros(n, bool)
    fits, rmses, counts = [], [], []
    n_measured = 0
    for p, (coherence_p, shift, cc, cc0, rival_p, ratio_p, fit) in zip(setup.patches, measured):
        sel, ut = p.sel, p.grid.ut
        coherence[sel] = coherence_p
        rival[sel], rival_ratio[sel] = rival_p, ratio_p
        if not np.isfinite(shift):
            continue
        n_measured += 1
        throw[sel] = shift
        corr[sel] = cc
        corr0[sel] = cc0
        if fit is not None:
            throw[sel] = fit.a + fit.b * ut[:, 0]
            registered[sel] = True
            fits.append(fit.fitness)
            rmses.append(fit.inlier_rmse)
            counts.append(fit.n_points)
    finite = np.isfinite(throw)
    if counts:
        wts = np.asarray(counts, float)
        fitness = float(np.average(fits, weights=wts))
        rmse = float(np.sqrt(np.average(np.square(rmses), weights=wts)))
    else:
        fitness = rmse = float("nan")
    return FaultThrow(
        fault_id=setup.fid, throw=throw.astype(np.float32), registered=registered,
        correlation=corr.astype(np.float32), correlation_unshifted=corr0.astype(np.float32),
        median_throw=float(np.median(throw[finite])) if finite.any() else float("nan"), fitness=fitness,
        inlier_rmse=rmse, n_points_used=int(sum(counts)), side_coherence=coherence.astype(np.float32),
        n_patches_measured=n_measured, rival_ratio=rival_ratio.astype(np.float32),
        **_ambiguity(rival, rival_ratio, opt.ambiguous_ratio),
    )


def _ambiguity(rival: np.ndarray, ratio: np.ndarray, ambiguous_ratio: float) -> dict:
    """The fault's ``ambiguity`` (median rival ratio of its measured points) and ``alternative_throw`` (the median
    rival shift when that reaches ``ambiguous_ratio``, else NaN) for :class:`FaultThrow`."""
    measured = np.isfinite(ratio)
    if not measured.any():
        return dict(ambiguity=float("nan"), alternative_throw=float("nan"))
    ambiguity = float(np.median(ratio[measured]))
    shifts = rival[measured & np.isfinite(rival)]
    alternative = float(np.median(shifts)) if ambiguity >= ambiguous_ratio and shifts.size else float("nan")
    return dict(ambiguity=ambiguity, alternative_throw=alternative)


def _section_throw(source, pts, nrm3, fid: int, opt: ThrowOptions, max_throw: int) -> FaultThrow:
    """Throw profile of a fault of a 2D section: its zone (every strand), the side images carried to the zone's centre
    along each side's dip, the correlation shift per window down the fault, interpolated to every point."""
    # which way the hanging wall lies along the traces (the normals' principal direction, into the hanging wall)
    hw = 1.0 if float(np.mean(nrm3[:, 0])) >= 0 else -1.0
    zone = fault_zone(pts, hw)
    n_traces = source.shape[0]
    win = source.window(*section_read_box(zone, opt.side_traces[1] + opt.slope_margin, n_traces))
    reach = min(max_throw, int(opt.profile_max_throw_per_length * zone.t.size),
                int(opt.profile_max_shift * opt.profile_window))
    n = len(pts)
    nan = np.full(n, np.nan, np.float32)
    if reach < 1:
        return FaultThrow(fault_id=fid, throw=nan, registered=np.zeros(n, bool), correlation=nan.copy(),
                          correlation_unshifted=nan.copy(), median_throw=float("nan"), fitness=float("nan"),
                          inlier_rmse=float("nan"), n_points_used=0, side_coherence=nan.copy(), n_patches_measured=0)
    prof = section_profile(zone, win, sides=opt.side_traces, slope_margin=opt.slope_margin,
                           window=opt.profile_window, step=opt.profile_step, reach=reach,
                           min_overlap=opt.min_overlap[0], smoothness=opt.profile_smoothness, opt=opt)
    ok = np.isfinite(prof.throw)

    def at_points(values):  # window values to the points, linear in the sample between window centres
        if not ok.any():
            return nan.copy()
        return np.interp(pts[:, 1], prof.t[ok], values[ok]).astype(np.float32)

    throw = at_points(prof.throw)
    finite = np.isfinite(throw)
    rival = at_points(prof.rival)  # the rival profile, as the throw's
    profile_ratio = prof.rival_ratio[ok][0] if ok.any() else np.nan  # one value for the profile
    rival_ratio = np.where(finite, profile_ratio, np.nan)
    return FaultThrow(
        fault_id=fid, throw=throw, registered=np.zeros(n, bool), correlation=at_points(prof.correlation),
        correlation_unshifted=at_points(prof.correlation_unshifted),
        median_throw=float(np.median(throw[finite])) if finite.any() else float("nan"), fitness=float("nan"),
        inlier_rmse=float("nan"), n_points_used=0, side_coherence=np.full(n, prof.coherence, np.float32),
        n_patches_measured=int(ok.sum()), step=prof.median_step, rival_ratio=rival_ratio.astype(np.float32),
        **_ambiguity(rival, rival_ratio, opt.ambiguous_ratio),
    )
