"""Register two real RGB-D frames (7-Scenes) with the fused ICP and compare with the ground-truth motion.

Run:  SEISMO3D_DATA_DIR=../shared/data python examples/register_rgbd_pair.py
"""

# %% Load two frames ten apart and their ground-truth camera-to-world poses
import numpy as np

from seismo3d.data import load_7scenes_frame
from seismo3d.geometry import rotation_error_deg, translation_error
from seismo3d.mapping.frames import register_frames

source, target = load_7scenes_frame(0), load_7scenes_frame(10)
truth = np.linalg.inv(target.pose) @ source.pose  # source camera -> target camera

# %% Fused ICP: SIFT matches lifted through depth start RANSAC, then features + point-to-plane in one objective
fused = register_frames(source, target, method="fused")
print(f"fused ICP:      rotation error {rotation_error_deg(fused.transform, truth):.3f} deg, "
      f"translation error {100 * translation_error(fused.transform, truth):.2f} cm, "
      f"{fused.info['n_feature_inliers']} feature inliers, fitness {fused.fitness:.3f}")

# %% Point-to-plane alone, from the identity
plane = register_frames(source, target, method="point_to_plane")
print(f"point-to-plane: rotation error {rotation_error_deg(plane.transform, truth):.3f} deg, "
      f"translation error {100 * translation_error(plane.transform, truth):.2f} cm")
