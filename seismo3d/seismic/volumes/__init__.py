"""Registration of two 3D seismic sub-volumes whose bin sizes, sample rates and map orientation differ.

Two overlapping sub-volumes (overlapping surveys, a time-lapse repeat, a cube resampled differently) are registered
by maximising the correlation of their amplitudes over a map with the bins of both volumes
(:mod:`.model`): in map view any linear map (a map rotation, and inline / crossline bin scales on either volume), along
the traces a scale and a shift. Its inverse is of the same family, so the answer does not depend on which volume is
passed as fixed. :func:`register_volumes` (:mod:`.registration`) runs, coarse to fine from the start:

1. **Levels** (:mod:`.pyramid`). Each volume decimated by powers of 2 until about ``min_lateral`` traces across and
   ``min_vertical`` samples remain. A level holds the same kind of data in both volumes: the amplitudes while the
   smoothing keeps them, the trace envelope where it does not (smooth: a vertical misfit of a few samples does not
   flip the correlation's sign), or, where the envelope is flat (clipped amplitudes), the smoothed amplitudes while a
   little of them is left; the samples are decimated no further. Two smooth properties (velocity models) are
   registered by their derivatives along the traces.
2. **Search** (:mod:`.search`, coarsest level). Map rotations within +-``max_rotation`` degrees and the lateral
   scales of each axis of either volume over ``scale_range`` (``scale_step`` apart), with the vertical scale where
   the mean trace spectra agree (:mod:`.vertical`), and, on volumes of ``spectral_min_traces`` traces or more per
   map axis, the maps their map-view power spectra tell off that grid (Fourier-Mellin over the anisotropies of both
   volumes, :mod:`.spectral`: the amplitudes alone, no coordinates); for each map the smaller volume (or, for the
   larger volume's scales, the larger one) is resampled and correlated with the other at every translation at once
   (masked FFT normalised cross-correlation, Padfield 2012): the same maps in either argument order. The search
   correlates the levels without their mean traces, which tell nothing of the map view (in time slices rendered
   each by its own range they are most of the variance), and scores every map first on the level decimated
   further, then the ``screen_keep`` best ones on the level itself.
3. **Refinement** (:mod:`.refine`). The ``n_starts`` best distinct starts, Levenberg-Marquardt on the correlation of
   the two volumes taken both ways (at the moving samples with the fixed volume interpolated, and the reverse, each
   weighted by the inverse of its misfit: symmetric in the two volumes) over the 8 parameters of the map, on the
   coarsest level (the Jacobian from the spline's own derivative there: the starts are furthest off), the best one on
   each finer level, full resolution last (``n_points_coarse`` samples on the decimated levels, ``n_points`` at
   full resolution).
4. **Answer and check** (:mod:`.check`). The two-way optimum refined again on the way that leads it alone (the one
   interpolating the less aliased volume: the other is biased) is the answer; ``converged`` only with enough overlap
   and correlation, scales within the range, the two estimates on one peak (the leading way's optimum within the
   tolerances of the two-way optimum), no other optimum nearly as good, and a correlation clearly better than the
   answer's shifted controls; otherwise the reason in one line.

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
* Map rotations are rotations of the physical (inline m, crossline m) plane; ``'rigid'`` is a map rotation and a
  translation of the physical coordinates (the spacings trusted), ``'affine'`` the general map above.
"""

from .inputs import volume_spacing
from .model import VOLUME_MODELS, MapDecomposition, decompose_map
from .options import VolumeOptions
from .registration import VolumeRegistration, register_volumes
from .resample import resample_volume

__all__ = ["VOLUME_MODELS", "MapDecomposition", "VolumeOptions", "VolumeRegistration", "decompose_map",
           "register_volumes", "resample_volume", "volume_spacing"]
