"""Options of horizon tracking (:func:`~seismo3d.seismic.track_horizon`): one frozen dataclass for both methods, the
global least-squares tracker (:mod:`~seismo3d.seismic.horizons.lsq`, the default) and the slice-by-slice registration
tracker (:mod:`~seismo3d.seismic.horizons.tracking`)."""

from __future__ import annotations

from dataclasses import dataclass

from ..._validation import as_sigma_pair, check_choice, check_int, check_positive
from ...errors import InputError
from .fault_crossings import FaultCrossings

__all__ = ["TrackingOptions"]


@dataclass(frozen=True)
class TrackingOptions:
    """Options of :func:`track_horizon`; the defaults are the ones every seismo3d command and benchmark uses.

    Attributes
    ----------
    method : {'global', 'registration'}
        'global' (default): least-squares horizons from correlation shifts between near and distant traces, solved
        at once, then dynamic programming over the candidate picks of each line, swept over both lateral axes in
        a cube (:mod:`~seismo3d.seismic.horizons.lsq`); 'registration': the slice-by-slice tracker of
        :mod:`~seismo3d.seismic.horizons.tracking`.
    pair_distances : tuple of int
        ('global') Distances, traces, of the correlated pairs along each lateral axis.
    correlation_half : int
        ('global') Half-length, samples, of the correlation windows (several reflector cycles).
    max_lag : int
        ('global') Lags searched, samples, each side of the current estimate (more than a reflector period).
    min_pair_correlation : float
        ('global') Pairs correlating less are left out of the solve.
    iterations : int
        ('global') Largest number of solves with the shifts re-measured around the estimate.
    distance_power : float
        ('global') A pair's weight is its correlation squared over its distance (traces) to this power: 1 gives every
        distance the same say over a stretch of traces (a pair spans ``d`` traces), so short pairs shape a narrow
        feature while long pairs still hold the cycle over a region.
    robust : float
        ('global') Scale, samples, of the Cauchy weights that down-weight pairs the solution disagrees with.
    robust_iterations : int
        ('global') Re-weighted solves per iteration.
    dp_reach : float
        ('global') Candidate picks of a trace lie within this many samples of the least-squares solution.
    dp_guide : float
        ('global') Cost per sample of a candidate's distance from the least-squares solution.
    dp_step : float
        ('global') Cost per squared sample of a step between neighbouring picks away from the reflector slope.
    dp_wave : float
        ('global') Cost of neighbouring picks' waveforms that do not correlate (times 1 - correlation).
    dp_sweeps : int
        ('global', cubes) Sweeps over inlines and crosslines after the line-by-line choice of picks, each line
        re-chosen with the picks of its neighbouring lines held (:func:`~seismo3d.seismic.horizons.dp.dp_picks`);
        0 keeps the line-by-line picks.
    repair : bool
        ('global') Run the cycle-skip self-check and repair flagged traces
        (:func:`~seismo3d.seismic.horizons.lsq.cycle_skips`), then move flagged regions by a cycle where the pairs
        correlate better (:func:`~seismo3d.seismic.horizons.cycle_cut.cycle_cut`).
    cut_gain : float
        ('global') A region the cycle cut moves must remove at least this fraction of its traces' mean
        decorrelation with their neighbours (1 - confidence): regions continuous either way, or in chaotic data,
        stay.
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
        Transform family of the panel registrations (2D). 'axis_scaled' allows per-axis scale (layers that thicken)
        but its vertical scale can slide a band that reaches the top or bottom of the data by one cycle (seen on a
        synthetic section), so the default is 'rigid'.
    half_traces : int
        Half-width of a panel along the slice, traces (source and target panels hold 2 * half_traces + 1 traces).
    half_samples : float
        Half-height of the band of reflector points around the horizon, samples.
    step : int
        Traces between two registrations along a slice.
    snap : float
        Largest distance, samples, from the carried position to the extremum it snaps to.
    min_confidence : float
        Picks whose waveform correlation with the pick they came from is below this are left empty.
    max_throw : int
        Largest shift, samples, searched when a discontinuity is found without fault input.
    features : {'hog', 'sift'} or None
        Feature matches between neighbouring inlines for the fused ICP (3D only); None: point-to-plane only.
    panel_traces : int
        Width, traces, of the panels registered between neighbouring inlines (3D).
    sigma_tensor : (float, float)
        Smoothing (traces, samples) of the structure tensor that gives the reflector normals and slopes.
    min_fitness : float
        A panel registration with a lower fitness does not fit (noise, a chaotic zone, a discontinuity).
    ncc_half : int
        Samples each side of a pick in the confidence correlation (the waveform window).
    panel_iterations : int
        ICP iterations per distance stage of a panel registration: panels of ~100 points converge in a few, and
        sliding along the reflectors never stops by itself.
    reference_weight : float
        Weight of the newest accepted pick in the running reference waveform along a slice.
    seed_snap : float
        Samples: a seed snaps to an extremum this far at most (about half a period).
    fault_zone : float
        Traces: along a slice, no step ends this close to a fault, where drag bends the reflectors towards it; it is
        carried on over the zone.
    pierce : float
        Voxels: a step crosses a fault when it pierces the fault's local plane this close to one of its points
        (:class:`~seismo3d.seismic.horizons.fault_crossings.FaultCrossings`).
    on_fault : float
        Voxels: a point this close to a fault's local plane (and its points) lies on the fault.
    min_throw_correlation : float
        Faults whose two sides correlate less than this at their throw (median of ``FaultThrow.correlation``), or not
        better than without it, are not used (:func:`~seismo3d.seismic.horizons.fault_crossings.reliable_throw`);
        where a horizon crosses a used fault, its pairs of traces decide whether it takes the jump.
    despike_reach : int
        Traces searched on each side for the neighbours of the lateral continuity check (:func:`despike`).
    despike_agree : float
        Samples within which those neighbours must agree, and beyond which a pick is a spike.
    gap_passes : int
        Largest number of gap-closing passes (:func:`close_gaps`).

    Raises
    ------
    InputError
        A value out of range (checked when the options are made).
    """

    method: str = "global"
    pair_distances: tuple = (1, 2, 4, 8, 16, 32)
    correlation_half: int = 16
    max_lag: int = 12
    min_pair_correlation: float = 0.5
    iterations: int = 6
    distance_power: float = 0.5
    robust: float = 2.0
    robust_iterations: int = 5
    dp_reach: float = 16.0
    dp_guide: float = 0.2
    dp_step: float = 1.0
    dp_wave: float = 4.0
    dp_sweeps: int = 2
    repair: bool = True
    cut_gain: float = 0.4
    model: str = "rigid"
    half_traces: int = 10
    half_samples: float = 20.0
    step: int = 4
    snap: float = 3.0
    min_confidence: float = 0.3
    max_throw: int = 10
    features: str | None = "hog"
    panel_traces: int = 64
    sigma_tensor: tuple = (2.0, 2.0)
    min_fitness: float = 0.3
    ncc_half: int = 8
    panel_iterations: int = 15
    reference_weight: float = 0.3
    seed_snap: float = 5.0
    fault_zone: float = 2.0
    pierce: float = 1.5
    on_fault: float = 0.5
    min_throw_correlation: float = 0.0
    despike_reach: int = 2
    despike_agree: float = 2.0
    gap_passes: int = 50

    def __post_init__(self):
        check_choice(self.method, "method", ("global", "registration"))
        dists = tuple(int(d) for d in self.pair_distances)
        if not dists or min(dists) < 1 or any(d != v for d, v in zip(dists, self.pair_distances)):
            raise InputError(f"pair_distances must be positive ints; got {self.pair_distances!r}")
        object.__setattr__(self, "pair_distances", dists)
        for name in ("correlation_half", "max_lag", "iterations", "robust_iterations"):
            check_int(getattr(self, name), name, minimum=1)
        check_int(self.dp_sweeps, "dp_sweeps", minimum=0)
        for name in ("robust", "dp_reach", "dp_step"):
            object.__setattr__(self, name, float(check_positive(getattr(self, name), name)))
        for name in ("dp_guide", "dp_wave", "distance_power"):
            object.__setattr__(self, name, float(check_positive(getattr(self, name), name, allow_zero=True)))
        if not -1.0 <= self.min_pair_correlation <= 1.0:
            raise InputError(f"min_pair_correlation is a correlation in [-1, 1]; got {self.min_pair_correlation}")
        check_choice(self.model, "model", ("rigid", "similarity", "axis_scaled", "affine"))
        if self.features is not None:
            check_choice(self.features, "features", ("hog", "sift"))
        for name in ("half_traces", "step", "max_throw", "panel_traces", "ncc_half", "panel_iterations",
                     "despike_reach", "gap_passes"):
            check_int(getattr(self, name), name, minimum=1)
        for name in ("half_samples", "snap", "seed_snap", "pierce", "on_fault", "despike_agree"):
            object.__setattr__(self, name, float(check_positive(getattr(self, name), name)))
        check_positive(self.fault_zone, "fault_zone", allow_zero=True)
        if not 0.0 <= self.cut_gain <= 1.0:
            raise InputError(f"cut_gain is a fraction in [0, 1]; got {self.cut_gain}")
        if not -1.0 <= self.min_confidence <= 1.0:
            raise InputError(f"min_confidence is a correlation in [-1, 1]; got {self.min_confidence}")
        if not 0.0 <= self.reference_weight <= 1.0:
            raise InputError(f"reference_weight must be in [0, 1]; got {self.reference_weight}")
        object.__setattr__(self, "sigma_tensor", as_sigma_pair(self.sigma_tensor, "sigma_tensor"))

    def fault_crossings(self, faults, ndim: int) -> FaultCrossings:
        """The :class:`~seismo3d.seismic.horizons.fault_crossings.FaultCrossings` of ``faults`` (None: none) with these
        options."""
        return FaultCrossings.from_interpretation(faults, ndim, min_throw_correlation=self.min_throw_correlation,
                                                  pierce=self.pierce, on_fault=self.on_fault)
