"""The results of the fault steps and their index-space conventions.

- :class:`FaultLikelihood` (step 1), :class:`FaultVotes` (the voting), :class:`Fault` (a fault skin: points, normals,
  likelihood), :class:`FaultThrow` (the throw along a fault), :class:`FaultInterpretation` (the whole run of
  :func:`~seismo3d.seismic.faults.trace_faults`);
- :func:`check_fault_arrays`: a likelihood, strike and dip checked to be arrays of one shape (2D or 3D);
  :func:`fault_labels`: faults painted into a label array;
- :func:`fault_normals`, :func:`fault_strike_dip`, :func:`fault_frames`: a fault plane's unit normal from its strike
  and dip and back, and the plane's frame (conventions of :mod:`~seismo3d.seismic.faults.likelihood.scan`).
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass, field

import numpy as np

from ..._validation import as_seismic
from ...errors import InputError

__all__ = ["ChunkedFaults", "ChunkedLikelihood", "Fault", "FaultInterpretation", "FaultLikelihood", "FaultThrow", "FaultVotes",
           "check_fault_arrays", "fault_frames", "fault_labels", "fault_normals", "fault_strike_dip"]


def fault_strike_dip(normal) -> tuple[float, float]:
    """Strike and dip of a fault normal (the inverse of :func:`fault_normals`).

    Parameters
    ----------
    normal : (3,) or (2,) array_like of float
        A unit fault normal, (inline, xline, sample) or (trace, sample) components, of either sign.

    Returns
    -------
    strike_deg : float
        Degrees in [0, 360) (90 or 270 in 2D; module conventions).
    dip_deg : float
        Degrees in [0, 90].
    """
    n = np.asarray(normal, dtype=np.float64)
    if n[-1] < 0:
        n = -n
    dip = np.degrees(np.arccos(np.clip(n[-1], 0.0, 1.0)))
    if n.shape[0] == 2:
        strike = 90.0 if n[0] >= 0 else 270.0
    else:
        strike = np.degrees(np.arctan2(n[0], -n[1])) % 360.0
    return float(strike), float(dip)


def fault_normals(strike_deg, dip_deg, *, ndim: int = 3) -> np.ndarray:
    """Unit fault normals from strike and dip.

    Parameters
    ----------
    strike_deg, dip_deg : array_like of float
        Strike in degrees [0, 360) and dip in degrees (0, 90], same shape (module conventions, index space).
    ndim : {2, 3}, optional
        3 for cube normals (inline, xline, sample); 2 for section normals (trace, sample).

    Returns
    -------
    (*strike_deg.shape, ndim) float32 ndarray
        ``(sin(dip) sin(strike), -sin(dip) cos(strike), cos(dip))``, or its (trace, sample) components in 2D.

    Raises
    ------
    InputError
        If the shapes differ or ``ndim`` is not 2 or 3.
    """
    phi = np.radians(np.asarray(strike_deg, dtype=np.float64))
    theta = np.radians(np.asarray(dip_deg, dtype=np.float64))
    if phi.shape != theta.shape:
        raise InputError(f"strike_deg {phi.shape} and dip_deg {theta.shape} must have the same shape")
    if ndim not in (2, 3):
        raise InputError(f"ndim must be 2 or 3; got {ndim!r}")
    st = np.sin(theta)
    comps = [st * np.sin(phi), -st * np.cos(phi), np.cos(theta)]
    if ndim == 2:
        comps = [comps[0], comps[2]]
    return np.stack(comps, axis=-1).astype(np.float32)


# --------------------------------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Fault:
    """One linked fault: a surface of thinned samples in 3D, a curve in 2D.

    Attributes
    ----------
    id : int
        Fault id, 1, 2, ... in decreasing size.
    points : (n, ndim) int64 ndarray
        Index coordinates (inline, xline, sample) or (trace, sample) of the fault's samples.
    likelihood : (n,) float32 ndarray
        The value at each point of the thinned fault image the fault was linked from
        (:func:`~seismo3d.seismic.faults.surfaces.skins.fault_skins`): in
        :func:`~seismo3d.seismic.trace_faults`, the thinned votes of the optimal-surface voting, not the fault
        likelihood itself (Hale's skins, whose cells carry a thinned likelihood, give the name).
    strike_deg, dip_deg : (n,) float32 ndarray
        Strike and dip at each point, degrees (module conventions).
    normals : (n, ndim) float32 ndarray
        Unit fault normal at each point, pointing into the footwall. The two sides of the fault at point ``p`` are
        near ``p + d * normal`` (footwall) and ``p - d * normal`` (hanging wall): the hook for measuring throw by
        registering the reflectors of the two sides.
    """

    id: int
    points: np.ndarray
    likelihood: np.ndarray
    strike_deg: np.ndarray
    dip_deg: np.ndarray
    normals: np.ndarray

    @property
    def size(self) -> int:
        """Number of samples on the fault."""
        return int(self.points.shape[0])

    @property
    def mean_normal(self) -> np.ndarray:
        """(ndim,) float64 unit mean normal (likelihood-weighted, sign-aligned, sample component >= 0)."""
        n = self.normals.astype(np.float64)
        ref = n[np.argmax(self.likelihood)]
        sgn = np.where(n @ ref < 0, -1.0, 1.0)
        m = (n * (sgn * self.likelihood)[:, None]).sum(axis=0)
        m /= max(np.linalg.norm(m), 1e-12)
        return -m if m[-1] < 0 else m

    @property
    def mean_strike_deg(self) -> float:
        """Strike of :attr:`mean_normal`, degrees in [0, 360)."""
        return float(fault_strike_dip(self.mean_normal)[0])

    @property
    def mean_dip_deg(self) -> float:
        """Dip of :attr:`mean_normal`, degrees in [0, 90]."""
        return float(fault_strike_dip(self.mean_normal)[1])


def check_fault_arrays(likelihood, strike, dip):
    """A fault image and its strike and dip as float32 arrays of one shape, or :class:`InputError`.

    Parameters
    ----------
    likelihood : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Fault likelihood, votes or thinned faults; finite.
    strike, dip : array_like of float, same shape
        Strike and dip, degrees; NaN where there is none (the learned likelihood's below
        ``LearnedOptions.orientation_floor``): the ridges neither test nor smooth along the dip there.

    Returns
    -------
    likelihood, strike, dip : float32 ndarray

    Raises
    ------
    InputError
        Shapes differ, the likelihood is not finite, or strike or dip is infinite.
    """
    fl = as_seismic(likelihood, "likelihood", min_size=1)
    st = np.asarray(strike, dtype=np.float32)
    dp = np.asarray(dip, dtype=np.float32)
    if st.shape != fl.shape or dp.shape != fl.shape:
        raise InputError(
            f"likelihood {fl.shape}, strike {st.shape} and dip {dp.shape} must have the same shape; pass the fields "
            "of one FaultLikelihood"
        )
    if np.isinf(st).any() or np.isinf(dp).any():
        raise InputError("strike and dip have inf values; pass the strike_deg and dip_deg of a FaultLikelihood")
    return fl, st, dp


def fault_labels(faults, shape) -> np.ndarray:
    """Paint faults into a label array.

    Parameters
    ----------
    faults : sequence of Fault
        Faults (:func:`~seismo3d.seismic.faults.fault_skins`).
    shape : tuple of int
        Shape of the cube or section the faults came from.

    Returns
    -------
    shape int32 ndarray
        0 off faults, ``fault.id`` on each fault's points.

    Raises
    ------
    InputError
        If a fault's points do not fit ``shape``.
    """
    shape = tuple(int(s) for s in shape)
    labels = np.zeros(shape, dtype=np.int32)
    for f in faults:
        p = np.asarray(f.points)
        if p.ndim != 2 or p.shape[1] != len(shape) or (p.size and (p.min() < 0 or np.any(p.max(0) >= shape))):
            raise InputError(f"fault {f.id} has points outside an array of shape {shape}")
        labels[tuple(p.T)] = f.id
    return labels


@dataclass(frozen=True, eq=False)
class FaultLikelihood:
    """Result of :func:`fault_likelihood`.

    Attributes
    ----------
    likelihood : (*shape) float32 ndarray
        Fault likelihood in [0, 1]: ``1 - s^power`` of the fault-plane semblance ``s``, maximised over the scan.
    strike_deg : (*shape) float32 ndarray
        Strike of the most likely fault plane at each sample, degrees in [0, 360) (see the module conventions).
    dip_deg : (*shape) float32 ndarray
        Dip of the most likely fault plane at each sample, degrees in (0, 90], index space.
    """

    likelihood: np.ndarray
    strike_deg: np.ndarray
    dip_deg: np.ndarray

    @property
    def normals(self) -> np.ndarray:
        """(*shape, ndim) float32 unit fault normals from the strike and dip (see :func:`fault_normals`)."""
        return fault_normals(self.strike_deg, self.dip_deg, ndim=self.likelihood.ndim)


@dataclass(frozen=True, eq=False)
class FaultVotes:
    """Result of :func:`vote_faults`.

    Attributes
    ----------
    votes : (*shape) float32 ndarray
        Accumulated votes divided by :meth:`VotingOptions.full_vote`, clipped to [0, 1]: about the mean likelihood
        of the fault surfaces through a sample, scaled down where fewer surfaces than on a long fault pass.
    strike_deg, dip_deg : (*shape) float32 ndarray
        Orientation of the best voting surface through each sample (degrees, conventions of
        :mod:`~seismo3d.seismic.faults.likelihood.scan`); 0 where no surface passed.
    n_seeds : int
        Number of seeds that voted.
    """

    votes: np.ndarray
    strike_deg: np.ndarray
    dip_deg: np.ndarray
    n_seeds: int


def fault_frames(strike_deg, dip_deg) -> np.ndarray:
    """Orthonormal frames of fault planes: unit normal, dip vector and strike vector.

    Parameters
    ----------
    strike_deg, dip_deg : (n,) array_like of float
        Fault strikes and dips, degrees (conventions of :mod:`~seismo3d.seismic.faults.likelihood.scan`; a 2D section's
        strike is 90 or 270).

    Returns
    -------
    (n, 3, 3) float64 ndarray
        Rows: the normal ``(sin(dip) sin(strike), -sin(dip) cos(strike), cos(dip))`` (into the footwall), the dip
        vector ``(-cos(dip) sin(strike), cos(dip) cos(strike), sin(dip))`` (down the fault) and the strike vector
        ``(cos(strike), sin(strike), 0)``, in (inline, xline, sample) components.
    """
    phi = np.radians(np.asarray(strike_deg, np.float64))
    theta = np.radians(np.asarray(dip_deg, np.float64))
    sp, cp, st, ct = np.sin(phi), np.cos(phi), np.sin(theta), np.cos(theta)
    u = np.stack([st * sp, -st * cp, ct], -1)
    v = np.stack([-ct * sp, ct * cp, st], -1)
    w = np.stack([cp, sp, np.zeros_like(sp)], -1)
    return np.stack([u, v, w], axis=-2)


@dataclass(frozen=True)
class FaultInterpretation:
    """Result of :func:`trace_faults`: one type however the run went (in memory or block by block).

    The volumes (``likelihood``, ``strike_deg``, ``dip_deg``, ``votes``, ``thin``) follow the input: for a seismic
    ``xarray.DataArray`` (:func:`seismo3d.open`) they are DataArrays on its dimensions and coordinates (``cdp_x`` /
    ``cdp_y`` included; numpy-backed in memory, dask-backed over the Zarr stores by blocks); for a plain array,
    arrays (numpy in memory, Zarr arrays of the stores by blocks).

    Attributes
    ----------
    likelihood : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 DataArray or array
        Fault likelihood in [0, 1] (0 on and next to dead samples).
    strike_deg, dip_deg : same shape and type, float32
        Strike and dip of the most likely fault plane at each sample, degrees, index space.
    votes : same shape and type, float32
        Optimal-surface votes in [0, 1] (:func:`~seismo3d.seismic.vote_faults`): about the mean likelihood of the
        fault surfaces through each sample.
    thin : same shape and type, float32
        The votes on the 1-sample-wide thinned faults above the lower threshold, 0 elsewhere.
    thresholds : (float, float)
        The lower and upper thresholds on the thinned votes (see :class:`FaultTracingOptions`).
    faults : list of Fault
        Fault skins (surfaces in 3D, curves in 2D), ids 1, 2, ... by decreasing size; their ``likelihood`` holds the
        thinned votes.
    throws : list of FaultThrow
        One per fault, in the order of ``faults``; ``throws[i].throw`` is the vertical throw at each point of
        ``faults[i]``, in samples.
    evidence : list of FaultEvidence
        One per fault: median throw, its spread, the sides' correlation and its gain from the throw's shift.
    sample_interval : float
        Sample interval in ``sample_unit`` (1 for 'samples').
    sample_unit : {'samples', 'ms', 'm', 'ft'}
        Unit of the sample axis.
    stores : dict of str to pathlib.Path
        Empty for a run in memory. For a cube traced block by block, the Zarr groups its arrays are read from:
        ``likelihood`` (fault likelihood, strike and dip of the scan) and ``surfaces``
        (:class:`~seismo3d.seismic.faults.surfaces.blocks.ChunkedFaults`); the volumes above are then read from
        them.
    step_seconds : dict of str to float
        Wall time of each step, seconds, in the order they ran: in memory ``fault likelihood``, ``ridges``,
        ``voting``, ``thinning``, ``fault skins``, ``throw``, ``evidence``; by blocks the likelihood's block steps
        computed in this call (``fault likelihood: network_inline_0``, ... ``orientation``, or the scan's), then
        ``fault likelihood`` (the rest: its checks and stores; all of it when a finished one was reused), the
        fault surfaces' (:attr:`ChunkedFaults.seconds`: ``fill``, ``ridges``, ``surfaces``, ``votes``, ``thin``,
        ..., ``fault skins``, ``throw``, ``evidence``) and ``fault surfaces`` (the rest).
    """

    likelihood: np.ndarray
    strike_deg: np.ndarray
    dip_deg: np.ndarray
    votes: np.ndarray
    thin: np.ndarray
    thresholds: tuple
    faults: list
    throws: list
    evidence: list
    sample_interval: float
    sample_unit: str
    stores: dict = field(default_factory=dict)
    step_seconds: dict = field(default_factory=dict)


@dataclass(frozen=True, eq=False)
class FaultThrow:
    """Throw along one fault (see :func:`~seismo3d.seismic.faults.throw.fault_throw`).

    Attributes
    ----------
    fault_id : int
        The fault's ``id`` (0 for a bare point array).
    throw : (n_points,) float32 ndarray
        Vertical throw at each fault point, in samples; positive = hanging wall down (normal fault), negative =
        hanging wall up (reverse fault). NaN where the fault's two sides could not be compared: a patch whose two
        fault-plane images overlap on fewer than 16 samples along dip (a short fault, or one at the edge of the data).
    registered : (n_points,) bool ndarray
        True where the throw comes from the ICP registration of reflector peaks; False where the registration failed
        or was rejected and the correlation shift (with parabolic sub-sample refinement) is used instead.
    correlation : (n_points,) float32 ndarray
        Peak normalised cross-correlation of the two fault-plane images of the point's patch, in [-1, 1] (a quality
        measure: low values mean the two sides do not look alike); NaN where ``throw`` is NaN.
    correlation_unshifted : (n_points,) float32 ndarray
        The same correlation with no shift across the fault (NaN where it overlaps too little): the sides of a fault
        correlate better after the throw's shift (``correlation - correlation_unshifted`` is the correlation gain);
        sides that correlate as well unshifted are reflectors continuing across, not a fault.
    median_throw : float
        Median of the finite ``throw`` values, samples (NaN if none).
    side_coherence : (n_points,) float32 ndarray
        How continuous the reflectors are along each side of the point's patch: the normalised correlation of the
        mean of the nearer half of the side traces with the mean of the farther half, the smaller of the two sides',
        in [-1, 1]; NaN where a side has too few samples read at every offset (None for a ``FaultThrow`` made
        without it). Noise or a chaotic body matches nothing, itself included:
        sides that do not match each other say more of a fault when each is continuous in itself.
    fitness : float
        Fraction of footwall reflector peaks with a hanging-wall peak within 1 sample after registration, averaged over
        the registered patches (weighted by their number of peaks); NaN if no patch was registered.
    inlier_rmse : float
        Root-mean-square distance between those corresponding peaks, in samples (same averaging); NaN if none.
    n_points_used : int
        Number of footwall reflector-peak points registered (summed over the registered patches).
    n_patches_measured : int
        Patches whose throw was measured (-1: not counted, a ``FaultThrow`` made without it); for a 2D fault, the
        windows of its throw profile (1: a fault spanning fewer than two windows, one shift for the whole fault,
        which says nothing of how the throw varies along it).
    step : float
        2D: median over the windows of the throw profile of the offset that is a step at the fault
        (:func:`~seismo3d.seismic.faults.throw_profile.section_step`: the lag between the traces just outside the
        fault's zone less the dip of its sides over that width), samples, positive = hanging wall down; about the
        throw at a fault, about 0 at a flexure that bends the reflectors over several traces. NaN when unmeasured
        (3D faults; a fault at the section's edge).
    half_period : float
        The half period of the reflectors around the fault, samples
        (:func:`~seismo3d.seismic.faults.reflector_period.half_period`); NaN when not measured (set by
        :func:`~seismo3d.seismic.faults.steps.faults_from_cells` when the evidence asks for it).
    rival_ratio : (n_points,) float32 ndarray or None
        How ambiguous the throw is at each point: the weighted correlation of the best rival shift (another peak of
        the correlation curve that set the point's throw, its patch's; down a 2D fault, the whole throw profile
        moved alike in every window, one value for the fault; on periodic reflectors usually a reflector period
        away) over the chosen shift's
        (:func:`~seismo3d.seismic.traces.runner_up_peak`). Near or above 1, two shifts match the sides about equally
        and the throw, its sign included, may be either; 0 where the curve has no rival; NaN where the throw is
        unmeasured or its correlation is not positive.
    ambiguity : float
        The median ``rival_ratio`` of the fault's measured points (over the whole fault, as ``median_throw``); NaN if
        none.
    alternative_throw : float
        When the throw is ambiguous (``ambiguity`` at least
        :attr:`~seismo3d.seismic.faults.throw.ThrowOptions.ambiguous_ratio`): the median of the rival shifts, samples,
        the throw the sides support nearly as well as ``median_throw``; NaN otherwise.
    """

    fault_id: int
    throw: np.ndarray
    registered: np.ndarray
    correlation: np.ndarray
    correlation_unshifted: np.ndarray
    median_throw: float
    fitness: float
    inlier_rmse: float
    n_points_used: int
    side_coherence: np.ndarray | None = None
    n_patches_measured: int = -1
    step: float = float("nan")
    half_period: float = float("nan")
    rival_ratio: np.ndarray | None = None
    ambiguity: float = float("nan")
    alternative_throw: float = float("nan")


@dataclass(frozen=True, eq=False)
class ChunkedLikelihood:
    """Result of a fault likelihood computed block by block into a Zarr group
    (:func:`~seismo3d.seismic.faults.likelihood.scan_blocks.chunked_fault_likelihood`,
    :func:`~seismo3d.seismic.faults.likelihood.learned_blocks.chunked_learned_likelihood`).

    Attributes
    ----------
    path : pathlib.Path
        The output Zarr group: arrays ``likelihood``, ``strike_deg``, ``dip_deg`` (float32, dims inline, crossline,
        sample) and the coordinates ``inline``, ``crossline``, ``sample``; opened as is by ``xarray.open_zarr``.
    shape : tuple of int
        ``(n_inlines, n_xlines, n_samples)``.
    blocks_computed, blocks_resumed : dict
        Per step (the scan's ``'balance'``, ``'semblance'``, ``'scan_inline'``, ``'scan_crossline'``, ``'decode'``;
        the network's ``'network_inline_0'``, ..., ``'orientation'``), blocks computed by this run and blocks found
        finished by an earlier, interrupted run.
    saturated_fraction : float
        Fraction of the live samples with likelihood above the saturation level (see ``FaultScanOptions.saturated``).
    seconds : dict
        Wall-clock seconds of each step of this run (``'statistics'`` and the steps above).
    """

    path: pathlib.Path
    shape: tuple
    blocks_computed: dict
    blocks_resumed: dict
    saturated_fraction: float
    seconds: dict

    def open(self):
        """The output arrays as a dict of read-only ``zarr.Array`` (name -> array)."""
        import zarr
        group = zarr.open_group(str(self.path), mode="r")
        return {name: group[name] for name in ("likelihood", "strike_deg", "dip_deg")}


@dataclass(frozen=True, eq=False)
class ChunkedFaults:
    """Result of :func:`~seismo3d.seismic.faults.surfaces.blocks.chunked_fault_surfaces`.

    Attributes
    ----------
    path : pathlib.Path
        The output Zarr group: ``likelihood`` (the fault likelihood, 0 near dead samples, as
        :attr:`~seismo3d.seismic.faults.FaultInterpretation.likelihood`), ``votes`` (optimal-surface votes),
        ``thin`` (thinned votes at or above the lower threshold, 0 elsewhere), ``vote_strike_deg`` and
        ``vote_dip_deg``, each (n_inlines, n_xlines, n_samples) float32 with dimensions inline, crossline, sample;
        the cells linked into skins as ``cell_points`` (n, 3) int32 and ``cell_values``, ``cell_strike_deg``,
        ``cell_dip_deg`` (n,) float32; attrs ``thresholds``, ``n_seeds``, ``n_cells``, ``saturated_fraction``,
        ``run`` (what was computed) and ``complete``.
    faults : list of Fault
        Fault skins, as :attr:`~seismo3d.seismic.faults.FaultInterpretation.faults`.
    throws : list of FaultThrow
        One per fault.
    evidence : list of FaultEvidence
        One per fault (:func:`~seismo3d.seismic.faults.evidence.supported_faults`: faults without a displacement
        are left out, as in memory).
    thresholds : (float, float)
        Lower and upper thresholds on the thinned votes.
    n_seeds, n_cells : int
        Voting seeds, and thinned-vote samples linked into skins.
    saturated_fraction : float
        Fraction of the live samples (not near dead ones) with a likelihood above ``saturation_level``.
    blocks_computed, blocks_resumed : dict
        Blocks per step computed in this call and found finished by an earlier one.
    seconds : dict
        Wall-clock seconds per step.
    """

    path: pathlib.Path
    faults: list
    throws: list
    evidence: list
    thresholds: tuple
    n_seeds: int
    n_cells: int
    saturated_fraction: float
    blocks_computed: dict
    blocks_resumed: dict
    seconds: dict
