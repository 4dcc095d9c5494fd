"""Registration benchmark: seismo3d's point-to-plane, fused ICP and Fast ICP beside Open3D's point-to-plane.

Run:  SEISMO3D_DATA_DIR=../shared/data python benchmarks/registration.py [--trials 5] [--success-trials 10]

Table 1, speed and accuracy: on the real Stanford bunny pair (40k points) and a real 7-Scenes pair at 0.5 cm voxels
(about 100k points), from the ground truth perturbed by a fixed angle about a random axis through the moved source's
centroid (same inits for every method): median wall time, median iterations, median rotation / translation error
and the success count. Open3D (``pip install open3d``; needs the system library libusb-1.0-0) runs with the same
correspondence-distance schedule (one ``registration_icp`` call per stage, 50 iterations each, its default relative
criteria) and, separately, with a single distance (the finest stage).

Table 2, robustness (the paper's Table 1 protocol): success rate (rotation error < 1 deg, translation error < 2 cm) of
fused ICP and of point-to-plane alone from inits perturbed by 5..30 degrees, on real RGB-D pairs.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from seismo3d.data import load_7scenes_frame, load_bunny, load_tum_pair
from seismo3d.geometry import apply_transform, estimate_normals, perturb, rotation_error_deg, translation_error
from seismo3d.mapping.frames import frame_feature_matches, frame_points
from seismo3d.registration import default_distance_schedule, fast_icp, fused_icp, icp

try:
    import open3d as o3d
except (ImportError, OSError):  # OSError: libusb missing
    o3d = None


def _open3d_icp(source, target, normals, init, schedule):
    reg = o3d.pipelines.registration
    src = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.array(source)))
    dst = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.array(target)))
    dst.normals = o3d.utility.Vector3dVector(np.array(normals))
    m, iters = init, 0
    for dmax in schedule:
        res = reg.registration_icp(src, dst, dmax, m, reg.TransformationEstimationPointToPlane(),
                                   reg.ICPConvergenceCriteria(max_iteration=50))
        m = np.asarray(res.transformation)
        iters += 50  # Open3D does not report its iteration count; this is the cap
    return m, iters


def _cases(voxel_7scenes):
    bunny = load_bunny()
    yield dict(name="bunny bun045->bun000", source=bunny.source, target=bunny.target,
               normals=estimate_normals(bunny.target, orient="none"), truth=bunny.transform, features=None)
    a, b = load_7scenes_frame(0), load_7scenes_frame(10)
    sp, _ = frame_points(a.depth, a.intrinsics, voxel_size=voxel_7scenes)
    tp, tn = frame_points(b.depth, b.intrinsics, voxel_size=voxel_7scenes)
    yield dict(name="7-Scenes 0->10", source=sp, target=tp, normals=tn, truth=np.linalg.inv(b.pose) @ a.pose,
               features=frame_feature_matches(a, b))


def speed_table(trials, angle, voxel_7scenes):
    header = f"{'case':22s} {'N src/tgt':>13s} {'method':28s} {'time s':>7s} {'iters':>6s} {'rot deg':>8s} " \
             f"{'trans mm':>9s} {'ok':>5s}"
    print(header)
    print("-" * len(header))
    for case in _cases(voxel_7scenes):
        src, dst, nrm, truth = case["source"], case["target"], case["normals"], case["truth"]
        sched = default_distance_schedule(dst)
        rng = np.random.default_rng(0)
        centre = apply_transform(truth, src).mean(axis=0)
        inits = [perturb(truth, angle, centre=centre, rng=rng) for _ in range(trials)]
        methods = {
            "seismo3d point-to-plane": lambda m0: _ours(icp(src, dst, target_normals=nrm, init=m0)),
            "seismo3d Fast ICP": lambda m0: _ours(fast_icp(src, dst, init=m0)),
        }
        if case["features"] is not None:
            fs, fd = case["features"]
            methods["seismo3d fused (SIFT)"] = lambda m0: _ours(
                fused_icp(src, dst, target_normals=nrm, source_features=fs, target_features=fd, init=m0))
        if o3d is not None:
            methods["Open3D p2plane, schedule"] = lambda m0: _open3d_icp(src, dst, nrm, m0, sched)
            methods["Open3D p2plane, single"] = lambda m0: _open3d_icp(src, dst, nrm, m0, sched[-1:])
        for name, run in methods.items():
            times, iters, rot, trans = [], [], [], []
            for m0 in inits:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    t0 = time.perf_counter()
                    m, n = run(m0)
                    times.append(time.perf_counter() - t0)
                iters.append(n)
                rot.append(rotation_error_deg(m, truth))
                trans.append(1000 * translation_error(m, truth))
            ok = sum(r < 1.0 and t < 20.0 for r, t in zip(rot, trans))
            cap = "<=" if name.startswith("Open3D") else ""
            print(f"{case['name']:22s} {len(src):>6d}/{len(dst):<6d} {name:28s} {np.median(times):7.3f} "
                  f"{cap + str(int(np.median(iters))):>6s} {np.median(rot):8.3f} {np.median(trans):9.2f} "
                  f"{ok:>2d}/{len(inits):<2d}")
    if o3d is None:
        print("(Open3D not installed: pip install 'seismo3d[bench]' and apt-get install libusb-1.0-0)")


def _ours(result):
    return result.transform, result.n_iterations


def success_table(trials, voxel):
    angles = (5, 10, 15, 20, 25, 30)
    pairs = [("7-Scenes 0->10", load_7scenes_frame(0), load_7scenes_frame(10)),
             ("7-Scenes 250->260", load_7scenes_frame(250), load_7scenes_frame(260)),
             ("TUM fr1/xyz pair", *load_tum_pair())]
    print(f"\nSuccess rate (rot < 1 deg and trans < 2 cm), {trials} inits per angle, clouds at {voxel * 100:g} cm voxels")
    print(f"{'pair':20s} {'method':16s} " + " ".join(f"{a:>5d}" for a in angles) + "   s/run")
    for name, a, b in pairs:
        sp, _ = frame_points(a.depth, a.intrinsics, voxel_size=voxel)
        tp, tn = frame_points(b.depth, b.intrinsics, voxel_size=voxel)
        fs, fd = frame_feature_matches(a, b)
        truth = np.linalg.inv(b.pose) @ a.pose
        centre = apply_transform(truth, sp).mean(axis=0)
        runs = {"fused ICP": lambda m0: fused_icp(sp, tp, target_normals=tn, source_features=fs,
                                                  target_features=fd, init=m0),
                "point-to-plane": lambda m0: icp(sp, tp, target_normals=tn, init=m0),
                "Fast ICP": lambda m0: fast_icp(sp, tp, init=m0)}
        for method, run in runs.items():
            row, seconds = [], []
            for angle in angles:
                rng = np.random.default_rng(angle)
                ok = 0
                for _ in range(trials):
                    m0 = perturb(truth, angle, centre=centre, rng=rng)
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        t0 = time.perf_counter()
                        try:
                            res = run(m0).transform
                        except Exception:  # noqa: BLE001 - a failed run counts as a failure in this table
                            res = m0
                        seconds.append(time.perf_counter() - t0)
                    ok += rotation_error_deg(res, truth) < 1.0 and translation_error(res, truth) < 0.02
                row.append(100.0 * ok / trials)
            print(f"{name:20s} {method:16s} " + " ".join(f"{v:5.0f}" for v in row) + f"   {np.median(seconds):.2f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=5, help="perturbed inits per case in the speed table")
    parser.add_argument("--angle", type=float, default=10.0, help="perturbation of the speed table, degrees")
    parser.add_argument("--voxel", type=float, default=0.005, help="7-Scenes voxel (m) for the speed table")
    parser.add_argument("--success-trials", type=int, default=10, help="inits per angle in the success table")
    parser.add_argument("--success-voxel", type=float, default=0.02, help="voxel (m) for the success table")
    args = parser.parse_args()
    speed_table(args.trials, args.angle, args.voxel)
    success_table(args.success_trials, args.success_voxel)


if __name__ == "__main__":
    main()
