"""Registration of two 3D seismic sub-volumes whose bin sizes, sample rates and map orientation differ.

Two overlapping sub-volumes (overlapping surveys, a time-lapse repeat, a cube resampled differently) are registered
with the fused ICP of method.md eq. 16: reflector points with structure-tensor normals are the dense point-to-plane
term, feature matches between corresponding slices the feature term. :func:`register_volumes` runs five stages, one
module each (:mod:`.vertical`, :mod:`.starts`, :mod:`.refine`, :mod:`.polish`; :mod:`.registration` runs them in
order, :mod:`.frames` holds the index and working frames, :mod:`.options` the tuning values):

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
   frame and scales along the moving axes, and scales stay within ``scale_range``. Scales along one volume's axes
   cannot represent scales along the other's under a map rotation, so an anisotropic result is polished a second
   time with the scales along the fixed axes (the reverse problem, inverted) and the better one kept
   (``VolumeOptions.symmetric``): which volume is passed as fixed then does not change the answer.

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

from .inputs import volume_spacing
from .options import VOLUME_MODELS, VolumeOptions
from .registration import VolumeRegistration, register_volumes
from .resample import resample_volume

__all__ = ["VOLUME_MODELS", "VolumeOptions", "VolumeRegistration", "register_volumes", "resample_volume",
           "volume_spacing"]
