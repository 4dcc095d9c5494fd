"""Register the two real Stanford bunny scans with point-to-plane ICP from a 15-degree error.

Run:  SEISMO3D_DATA_DIR=../shared/data python examples/register_bunny.py
"""

# %% Load the scans and their ground-truth relative pose
import numpy as np

from seismo3d.data import load_bunny
from seismo3d.geometry import apply_transform, estimate_normals, perturb, rotation_error_deg, translation_error
from seismo3d.registration import fast_icp, icp

pair = load_bunny()
normals = estimate_normals(pair.target)
init = perturb(pair.transform, 15.0, centre=apply_transform(pair.transform, pair.source).mean(axis=0),
               rng=np.random.default_rng(0))

# %% Point-to-plane ICP (default coarse-to-fine schedule) beside the Fast ICP baseline
for name, result in [("point-to-plane", icp(pair.source, pair.target, target_normals=normals, init=init)),
                     ("Fast ICP", fast_icp(pair.source, pair.target, init=init))]:
    print(f"{name:15s} rotation error {rotation_error_deg(result.transform, pair.transform):.3f} deg, translation "
          f"error {1000 * translation_error(result.transform, pair.transform):.2f} mm, {result.n_iterations} iterations")
