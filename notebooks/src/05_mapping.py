# %% [markdown]
# # 05 RGB-D mapping
#
# The paper's mapping loop on a real Kinect sequence (Microsoft 7-Scenes "redkitchen", every 5th frame): each frame
# is tracked against the map by fused ICP (projective association, SIFT landmarks), an extended Kalman filter
# predicts the pose, the depth is fused into a TSDF map, keyframes are kept and loops closed with a gtsam pose graph.
# The estimated trajectory is compared with the 7-Scenes reference poses (ATE after rigid alignment, RPE per step).
#
# The sequence is read as one folder: the seismo3d data folder's copy (`SEISMO3D_DATA_DIR`), or its frames fetched
# by origin (hash-checked) into the cache when the data folder is not there. The same on the
# command line: `seismo3d map SEQUENCE -o OUTDIR` then `seismo3d render
# OUTDIR -o map.png`; `python benchmarks/mapping.py` runs the whole subset beside Open3D's odometry.

# %%

import numpy as np

from seismo3d.data import fetch_folder
from seismo3d.mapping import RGBDMapper, absolute_trajectory_error, open_sequence, relative_pose_error
from seismo3d.viz import show_map

FRAMES = 40  # of the 100 in the subset (every 5th frame of the first 500): about 2.5 s of the original video

sequence = open_sequence(fetch_folder("rgbd/7scenes_redkitchen_0000_0495"))
print(f"sequence: {len(sequence)} frames ({sequence.layout}), mapping the first {FRAMES}")

mapper = RGBDMapper()
for i in range(FRAMES):
    mapper.process(sequence.read(i), index=i)
trajectory = mapper.trajectory()
print(f"{FRAMES} frames mapped; keyframes: {len(mapper.graph.keyframes)}, loop closures: {mapper.graph.n_loops}")

# %% [markdown]
# ## The trajectory against the reference

# %%
ref_t, ref_p = sequence.groundtruth
ate = absolute_trajectory_error(trajectory.timestamps, trajectory.poses, ref_t, ref_p)
rpe_translation, rpe_rotation = relative_pose_error(trajectory.timestamps, trajectory.poses, ref_t, ref_p)
path_length = np.linalg.norm(np.diff(trajectory.poses[:, :3, 3], axis=0), axis=1).sum()
print(f"camera path: {path_length:.2f} m over {FRAMES} frames")
print(f"ATE RMSE: {100 * ate.rmse:.1f} cm (max {100 * ate.max:.1f} cm) over {ate.n} poses")
print(f"RPE per step: {100 * rpe_translation.rmse:.1f} cm and {rpe_rotation.rmse:.2f} deg (RMSE)")

# %% [markdown]
# ## The map
# The TSDF mesh coloured by height, the camera trajectory (red), the keyframes (blue pyramids) and the reference
# trajectory (green), placed in the map's frame by its first pose.

# %%
mesh = mapper.volume.extract_mesh()
first = np.searchsorted(ref_t, trajectory.timestamps[0])
reference = trajectory.poses[0] @ np.linalg.inv(ref_p[first]) @ ref_p[first:first + FRAMES]
print(f"mesh: {len(mesh.vertices)} vertices, {len(mesh.faces)} triangles")
show_map(mesh, trajectory.poses, mapper.graph.poses(), reference=reference, window_size=(900, 650));
