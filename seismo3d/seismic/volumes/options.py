"""VolumeOptions: the search ranges, sizes and thresholds of :func:`~seismo3d.seismic.register_volumes`."""

from __future__ import annotations

from dataclasses import dataclass

from ..._validation import check_choice, check_int, check_positive
from ...errors import InputError

__all__ = ["VOLUME_MODELS", "VolumeOptions"]

VOLUME_MODELS = ("rigid", "axis_scaled", "affine")


@dataclass(frozen=True)
class VolumeOptions:
    """Options of :func:`~seismo3d.seismic.register_volumes`; the defaults are the ones every seismo3d command and
    benchmark uses (stages as in :mod:`seismo3d.seismic.volumes`).

    Attributes
    ----------
    scale_range : (float, float)
        Smallest and largest per-axis scale searched, relative to the spacings.
    alpha : float in [0, 1]
        Weight of the feature term of the fused ICP (method.md eq. 16).
    feature_method : {'hog', 'sift'}
        Slice features of the global start: the HOG-pyramid (method.md section 2) or OpenCV's SIFT.
    max_points : int
        Largest number of reflector points per volume in the fused ICP (a fixed random subset beyond it).
    max_rounds : int
        Largest number of track-refinement rounds (stage 3).
    min_correlation : float
        The registration fails (:class:`~seismo3d.errors.RegistrationError`) when the best result correlates less
        than this over the overlap. Resampled pairs of one cube reach 0.90-1.0 (the correlation column of
        ``benchmarks/volumes.py``). Lower it for a time-lapse repeat or two surveys processed differently. Volumes too
        small for slice features (the correlation start) fit 7-9 parameters to few samples: two unrelated 24 x
        18-trace synthetic volumes reached 0.88 there, so raise it (to 0.9 for resampled copies) when you need a
        failure to be reported.
    seed : int
        Seed of RANSAC and of the point subsets; the result is deterministic given it.
    min_map : int
        Fewest traces across (working cells, the moving volume at its largest scale) for time slices to carry
        features; thinner volumes use inline sections.
    max_feature_side : int
        Slices for the global feature search are downsampled to at most this many pixels a side.
    shift_window : tuple of int
        Fixed time slices matched around the predicted one, samples.
    n_slices : int
        Moving time slices matched in the global search.
    ransac_trials : int
        RANSAC samples per global hypothesis.
    max_starts : int
        Feature-based starts refined by the fused ICP (best first).
    good_correlation : float
        A refined start correlating this well ends the search over starts.
    klt_window : int
        Lucas-Kanade window of the slice tracks, pixels.
    min_tracks : int
        Fewest consistent slice tracks for a refinement round.
    max_rotation : float
        Degrees: the correlation start searches map rotations within +-max_rotation ...
    rotation_step : float
        ... every rotation_step degrees ...
    scale_steps : int
        ... and lateral scales on this many log-spaced values per axis over ``scale_range``, then again on half
        those steps around the ``n_refined`` best maps.
    n_refined : int
        See ``scale_steps``.
    min_fraction : float
        Overlap a correlation needs, as a fraction of the smaller volume's samples.
    taper : float
        Samples: the correlation's weights fall linearly to 0 over this distance from the fixed volume's edge.
    max_search : int
        Samples of each volume (sample axis halved) beyond which the correlation start is not searched (about 0.1 s
        per map at that size: larger volumes carry slice features).
    polish_evaluations : int
        Largest number of correlation evaluations of the polish (stage 5).
    score_points, polish_points : int
        Moving samples (a regular subset) at which the overlap correlation is evaluated to rank candidates and to
        polish.
    symmetric : bool
        For ``'axis_scaled'``: when the polished lateral scales differ by more than ``anisotropy``, polish again with
        the scales along the *fixed* volume's axes (the model of the reverse problem) and keep that result when it
        halves the misfit ``1 - correlation``. Scales along one volume's axes cannot represent scales along the
        other's under a map rotation, so without it the answer depends on which volume is passed as fixed (a
        f3_crop copy rotated 12 degrees with scales 1.25 / 0.8 / 1.1 landed 2.1 degrees off when passed as fixed).
    anisotropy : float
        See ``symmetric`` (a relative difference of the two lateral scales).

    Raises
    ------
    InputError
        A value out of range (checked when the options are made).
    """

    scale_range: tuple = (0.5, 2.0)
    alpha: float = 0.5
    feature_method: str = "hog"
    max_points: int = 60000
    max_rounds: int = 8
    min_correlation: float = 0.5
    seed: int = 0
    min_map: int = 32
    max_feature_side: int = 192
    shift_window: tuple = (-2, -1, 0, 1, 2)
    n_slices: int = 10
    ransac_trials: int = 1000
    max_starts: int = 3
    good_correlation: float = 0.9
    klt_window: int = 15
    min_tracks: int = 24
    max_rotation: float = 45.0
    rotation_step: float = 7.5
    scale_steps: int = 7
    n_refined: int = 4
    min_fraction: float = 0.3
    taper: float = 2.0
    max_search: int = 100_000
    polish_evaluations: int = 800
    score_points: int = 200_000
    polish_points: int = 40_000
    symmetric: bool = True
    anisotropy: float = 0.01

    def __post_init__(self):
        try:
            lo, hi = (float(v) for v in self.scale_range)
        except (TypeError, ValueError) as exc:
            raise InputError(f"scale_range must be two numbers (smallest, largest); got {self.scale_range!r}") from exc
        if not 0 < lo <= 1 <= hi or not hi < float("inf"):
            raise InputError(f"scale_range must satisfy 0 < smallest <= 1 <= largest; got {self.scale_range!r}")
        object.__setattr__(self, "scale_range", (lo, hi))
        alpha = float(self.alpha)
        if not 0.0 <= alpha <= 1.0:
            raise InputError(f"alpha must be in [0, 1]; got {alpha}")
        object.__setattr__(self, "alpha", alpha)
        check_choice(self.feature_method, "feature_method", ("hog", "sift"))
        check_positive(self.max_points, "max_points")
        for name in ("max_rounds", "min_map", "max_feature_side", "n_slices", "ransac_trials", "max_starts",
                     "klt_window", "min_tracks", "scale_steps", "n_refined", "max_search", "polish_evaluations",
                     "score_points", "polish_points"):
            check_int(getattr(self, name), name, minimum=1)
        check_int(self.seed, "seed", minimum=0)
        for name in ("max_rotation", "rotation_step", "min_fraction", "taper", "anisotropy"):
            check_positive(getattr(self, name), name)
