"""VolumeOptions: search ranges, levels, sizes and check tolerances of :func:`~seismo3d.seismic.register_volumes`."""

from __future__ import annotations

from dataclasses import dataclass

from ..._validation import check_int, check_positive
from ...errors import InputError

__all__ = ["VolumeOptions"]


@dataclass(frozen=True)
class VolumeOptions:
    """Options of :func:`~seismo3d.seismic.register_volumes`; the defaults are the ones every seismo3d command and
    benchmark uses (stages as in :mod:`seismo3d.seismic.volumes`).

    Attributes
    ----------
    scale_range : (float, float)
        Smallest and largest scale of a moving bin (inline, crossline) and sample interval, relative to the spacings,
        that the search covers; the result may leave it by a quarter (then it is ``converged: false``).
    max_rotation : float
        Degrees: the search covers map rotations within +-max_rotation ...
    rotation_step : float
        ... every rotation_step degrees ...
    scale_step : float
        ... and the lateral scale of each axis of either volume on log-spaced values ``scale_step`` apart over
        ``scale_range`` (the refinement converges from half a step off: 7.5 degrees, 19 % per axis, on f3_crop).
    max_anisotropy : float
        Largest ratio of the two lateral scales of a volume searched (f3_crop pairs with scales 0.6 and 1.6, a ratio
        of 2.7, need 2.83, the next step).
    n_starts : int
        Distinct best starts of the search refined on the coarsest level.
    n_spectral : int
        Map-view candidates of the two volumes' spectra (Fourier-Mellin, :mod:`~seismo3d.seismic.volumes.spectral`)
        scored beside the search's grid (0: none) ...
    spectral_min_traces : int
        ... when both volumes hold at least this many traces along each map axis. On maps of 18-24 traces (f3_crop,
        the Penobscot and Volve blocks of ``benchmarks/volumes.py --only spectral``) a map within half a grid step
        of the right one is among the 6 best candidates in 24 of 36 pairs, and the coarsest level correlates wrong
        candidates as well as right ones (Volve: 0.99 at 9-14 samples off), so they are left to the grid there.
    min_lateral, min_vertical : int
        The coarsest level keeps at least this many traces along each map axis and samples along the traces ...
    max_factor : int
        ... decimating each by at most this factor (a power of 2).
    smooth_property : float
        Two volumes whose traces keep this fraction of their variance under a Gaussian of ``max_factor / 2`` samples
        hold a smooth property (the Volve velocity model: 0.97) and are registered by their derivatives along the
        traces (seismic amplitudes keep 0.01-0.2).
    keep_amplitude : float
        A level holds the amplitudes while its smoothing keeps this fraction of their variance (f3_crop: 0.56 at a
        decimation of 2, 0.30 at 4; a velocity model: 0.97 at 8) ...
    min_contrast : float
        ... then the envelope of the traces while its spread is this fraction of its mean (f3_crop: 0.5 at 8; the
        clipped Penobscot amplitudes: 0.09 at 4) ...
    min_amplitude : float
        ... then the smoothed amplitudes while they keep this fraction of their variance (Penobscot: 0.12 at 4, 0.03
        at 8); the samples are decimated no further. Both volumes hold the same kind on each level.
    n_points : int
        About this many samples of each volume are correlated at full resolution ...
    n_points_coarse : int
        ... and on the decimated levels, whose refinements only bring the next level into its peak (chosen on pairs
        of :func:`~seismo3d.data.random_grid_pair` drawn with seed 1001, not the benchmark's 78, three per cube of
        ``benchmarks/volumes.py --only any_grid``, both orders: 5000 instead of 20,000 there kept every right answer
        right, within 0.03 samples at the corners, and cut the coarse stage's CPU time by 3-4 on Penobscot).
    screen_keep : int
        The search scores every map first on its level decimated further (by 4 or 2 along the traces where the
        shorter level keeps ``2 * min_vertical`` samples, by 2 along a map axis where the smaller level keeps
        ``min_lateral / 2`` traces; a level decimated no further is scored at once) and only the ``screen_keep``
        best ones, of either direction, again on the level itself (0: every map on the level itself; chosen on the
        same pairs of seed 1001: the same registrations right and converged, the search 2-4 times faster).
    max_iterations : int
        Largest number of Levenberg-Marquardt steps per level.
    tolerance : float
        Samples: the full-resolution refinement stops when a step moves no corner of the moving volume further (the
        coarser levels at five times this, in their samples).
    taper : float
        Samples: correlation weights fall to 0 over this distance at the volumes' edges and dead traces.
    min_fraction : float
        Overlap needed, as a fraction of the smaller volume (in the search, and to be ``converged``).
    min_correlation : float
        A result whose correlation (the mean of both ways) is below this is not ``converged``.
    max_disagreement : float
        Fixed samples: the two-way optimum refined again on the correlation of the way that leads it alone (MOVING
        onto FIXED or FIXED onto MOVING, :mod:`~seismo3d.seismic.volumes.check`; its optimum is the answer) must map
        every corner of the moving volume within this distance of the two-way optimum (and their map rotations
        agree within ``max_rotation_disagreement``) for the answer to be ``converged``: the issue's 0.5 samples.
    max_rotation_disagreement : float
        Degrees: the issue's 0.5. Their scales are not asked to agree: the two-way optimum is pulled off by the way
        that interpolates an aliased (coarse) volume (on the Volve velocity pairs of ``benchmarks/volumes.py``, up to
        3.4 % while the leading way's optimum is within 0.3 % of the truth; ``--only grid`` prints both).
    control_level : float
        The shifted controls displace the result along each axis of the fixed volume, both ways, by its correlation
        length: the lag at which its autocorrelation (the mean trace left out) falls to this level
        (:func:`~seismo3d.seismic.volumes.check.control_shifts`; 0.5, the half width of its central lobe, kept after
        pairs of :func:`~seismo3d.data.random_grid_pair` drawn with seed 1001, not the benchmark's 78, four per cube
        of ``benchmarks/volumes.py --only any_grid`` in both orders: the right answers' misfit 0.01-0.54 of the
        controls' at 0.5 (up to 0.76 at 0.8, over the 0.7 allowed), 18 unrelated pairs cut from those draws
        0.92-1.1 at every level from 0.2 to 0.8) ...
    max_control_shift : float
        ... at most this fraction of the axis's length (at least 1 sample) ...
    control_ratio : float
        ... and the result is ``converged`` only when its misfit ``1 - correlation`` is at most ``control_ratio``
        times the smallest misfit of the controls, and of the best distinct other optimum of the search (resampled
        pairs of f3_crop reach 0.1-0.4, unrelated volumes 0.9-1.0: ``benchmarks/volumes.py``).

    Raises
    ------
    InputError
        A value out of range (checked when the options are made).
    """

    scale_range: tuple = (0.5, 2.0)
    max_rotation: float = 45.0
    rotation_step: float = 15.0
    scale_step: float = 2.0 ** 0.5
    max_anisotropy: float = 2.0 ** 1.5
    n_starts: int = 6
    n_spectral: int = 6
    spectral_min_traces: int = 32
    min_lateral: int = 16
    min_vertical: int = 8
    max_factor: int = 8
    smooth_property: float = 0.9
    keep_amplitude: float = 0.35
    min_contrast: float = 0.25
    min_amplitude: float = 0.1
    n_points: int = 20_000
    n_points_coarse: int = 5_000
    screen_keep: int = 12
    max_iterations: int = 20
    tolerance: float = 0.02
    taper: float = 2.0
    min_fraction: float = 0.3
    min_correlation: float = 0.3
    max_disagreement: float = 0.5
    max_rotation_disagreement: float = 0.5
    control_level: float = 0.5
    max_control_shift: float = 0.25
    control_ratio: float = 0.7

    def __post_init__(self):
        try:
            lo, hi = (float(v) for v in self.scale_range)
        except (TypeError, ValueError) as exc:
            raise InputError(f"scale_range must be two numbers (smallest, largest); got {self.scale_range!r}") from exc
        if not 0 < lo <= 1 <= hi or not hi < float("inf"):
            raise InputError(f"scale_range must satisfy 0 < smallest <= 1 <= largest; got {self.scale_range!r}")
        object.__setattr__(self, "scale_range", (lo, hi))
        check_int(self.n_spectral, "n_spectral", minimum=0)
        check_int(self.screen_keep, "screen_keep", minimum=0)
        check_int(self.spectral_min_traces, "spectral_min_traces", minimum=8)
        for name in ("n_starts", "min_lateral", "min_vertical", "n_points", "n_points_coarse", "max_iterations"):
            check_int(getattr(self, name), name, minimum=1)
        factor = check_int(self.max_factor, "max_factor", minimum=1)
        if factor & (factor - 1):
            raise InputError(f"max_factor must be a power of 2 (1, 2, 4, 8, ...); got {factor}")
        for name in ("max_rotation", "rotation_step", "tolerance", "taper", "min_fraction", "max_disagreement",
                     "keep_amplitude", "min_contrast", "min_amplitude", "smooth_property",
                     "max_rotation_disagreement", "control_ratio"):
            check_positive(getattr(self, name), name)
        if not self.max_anisotropy >= 1.0:
            raise InputError(f"max_anisotropy must be >= 1 (a ratio of two scales); got {self.max_anisotropy}")
        if not self.scale_step > 1.0:
            raise InputError(f"scale_step must be > 1 (a factor between neighbouring scales); got {self.scale_step}")
        for name in ("control_level", "max_control_shift"):
            if not 0.0 < getattr(self, name) < 1.0:
                raise InputError(f"{name} must be in (0, 1); got {getattr(self, name)}")
        if not -1.0 <= self.min_correlation < 1.0:
            raise InputError(f"min_correlation must be in [-1, 1); got {self.min_correlation}")
