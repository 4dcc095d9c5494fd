"""Registration benchmark: seismo3d's point-to-plane ICP beside Open3D and small_gicp, its fused ICP and Fast ICP.

Run:  SEISMO3D_DATA_DIR=../shared/data python benchmarks/registration.py [--trials 5] [--success-trials 10]

Table 1, speed and accuracy (issue 34): the real Stanford bunny pair (bun045 -> bun000, 40k points) from the ground
truth perturbed by 10 and 34 degrees about random axes through the moved source's centroid, and the real 7-Scenes
pair frame 5 -> frame 0 at 1 cm voxels (about 60k points) from the identity and from 10 degrees (same inits for every
method). The methods run interleaved (one init, every method, next init) so that load changes hit all alike; the
table gives the median wall time, median iterations, median rotation / translation error and the success count
(rotation < 1 deg and translation < 2 cm), then the ratios of seismo3d's time to each peer's. Peers: Open3D's
point-to-plane ``registration_icp`` (``pip install open3d``; needs the system library libusb-1.0-0) with seismo3d's
distance schedule (one call per stage, 50 iterations each, its default relative criteria) and with the finest distance
alone; small_gicp's GICP (``pip install small_gicp``, 2 threads) with the coarsest distance and with the finest one.
Every method gets its inputs prepared outside the timing (seismo3d and Open3D the target normals, small_gicp the
covariances of both clouds); search structures (voxel hashes, KD-trees) are built inside it.

Table 2, robustness (the paper's Table 1 protocol): success rate (rotation error < 1 deg, translation error < 2 cm) of
fused ICP and of point-to-plane alone from inits perturbed by 5..30 degrees, on real RGB-D pairs.
"""

from __future__ import annotations

import argparse
import os
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
try:
    import small_gicp
except ImportError:
    small_gicp = None

THREADS = 2  # small_gicp's threads (the benchmark machine has 2 cores; Open3D and numba use all cores)


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


def _small_gicp_clouds(source, target):
    clouds = []
    for pts in (source, target):
        cloud = small_gicp.PointCloud(np.asarray(pts, dtype=np.float64))
        small_gicp.estimate_covariances(cloud, num_neighbors=20, num_threads=THREADS)
        clouds.append(cloud)
    return clouds


def _small_gicp(clouds, init, dmax):
    src, dst = clouds
    tree = small_gicp.KdTree(dst, num_threads=THREADS)
    res = small_gicp.align(dst, src, tree, init, registration_type="GICP", max_correspondence_distance=dmax,
                           num_threads=THREADS)
    return np.asarray(res.T_target_source), res.iterations


def _cases():
    bunny = load_bunny()
    bunny_normals = estimate_normals(bunny.target, orient="none")
    for angle in (10.0, 34.0):
        yield dict(name=f"bunny, {angle:g} deg", source=bunny.source, target=bunny.target, normals=bunny_normals,
                   truth=bunny.transform, angle=angle)
    a, b = load_7scenes_frame(5), load_7scenes_frame(0)
    sp, _ = frame_points(a.depth, a.intrinsics, voxel_size=0.01)
    tp, tn = frame_points(b.depth, b.intrinsics, voxel_size=0.01)
    truth = np.linalg.inv(b.pose) @ a.pose
    for angle in (None, 10.0):
        yield dict(name="7-Scenes 5->0, " + ("identity" if angle is None else f"{angle:g} deg"), source=sp,
                   target=tp, normals=tn, truth=truth, angle=angle)


def _methods(case, sched):
    src, dst, nrm = case["source"], case["target"], case["normals"]
    methods = {"seismo3d point-to-plane": lambda m0: _ours(icp(src, dst, target_normals=nrm, init=m0))}
    if o3d is not None:
        methods["Open3D p2plane, schedule"] = lambda m0: _open3d_icp(src, dst, nrm, m0, sched)
        methods["Open3D p2plane, finest"] = lambda m0: _open3d_icp(src, dst, nrm, m0, sched[-1:])
    if small_gicp is not None:
        clouds = _small_gicp_clouds(src, dst)
        methods["small_gicp GICP, coarsest"] = lambda m0: _small_gicp(clouds, m0, sched[0])
        methods["small_gicp GICP, finest"] = lambda m0: _small_gicp(clouds, m0, sched[-1])
    return methods


def speed_table(trials):
    """Table 1: speed and accuracy of seismo3d's ICP beside Open3D and small_gicp, interleaved runs."""
    header = f"{'case':24s} {'N src/tgt':>13s} {'method':27s} {'time s':>7s} {'iters':>6s} {'rot deg':>8s} " \
             f"{'trans mm':>9s} {'ok':>5s}"
    print(f"load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(header)
    print("-" * len(header))
    ratios = []
    for case in _cases():
        src, dst, truth = case["source"], case["target"], case["truth"]
        sched = default_distance_schedule(dst)
        rng = np.random.default_rng(0)
        centre = apply_transform(truth, src).mean(axis=0)
        inits = [np.eye(4) if case["angle"] is None else perturb(truth, case["angle"], centre=centre, rng=rng)
                 for _ in range(trials)]
        methods = _methods(case, sched)
        rows = {name: ([], [], [], []) for name in methods}
        _ours(icp(src[:2000], dst, target_normals=case["normals"]))  # compile / warm the caches outside the timing
        for m0 in inits:
            for name, run in methods.items():
                times, iters, rot, trans = rows[name]
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    t0 = time.perf_counter()
                    m, n = run(m0)
                    times.append(time.perf_counter() - t0)
                iters.append(n)
                rot.append(rotation_error_deg(m, truth))
                trans.append(1000 * translation_error(m, truth))
        medians = {}
        for name, (times, iters, rot, trans) in rows.items():
            ok = sum(r < 1.0 and t < 20.0 for r, t in zip(rot, trans))
            medians[name] = (float(np.median(times)), ok)
            cap = "<=" if name.startswith("Open3D") else ""
            print(f"{case['name']:24s} {len(src):>6d}/{len(dst):<6d} {name:27s} {np.median(times):7.3f} "
                  f"{cap + str(int(np.median(iters))):>6s} {np.median(rot):8.3f} {np.median(trans):9.2f} "
                  f"{ok:>2d}/{len(inits):<2d}")
        ours = medians.pop("seismo3d point-to-plane")[0]
        ratios.append((case["name"], ours, medians))
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print("\nseismo3d's median time / each peer's (targets: <= 1.0 x Open3D with the schedule, <= 1.5 x small_gicp "
          "GICP; ok = that peer's successes)")
    for name, ours, medians in ratios:
        print(f"{name:24s} " + "  ".join(f"{peer}: {ours / t:.2f}x (ok {k})" for peer, (t, k) in medians.items()))
    if o3d is None:
        print("(Open3D not installed: pip install 'seismo3d[bench]' and apt-get install libusb-1.0-0)")
    if small_gicp is None:
        print("(small_gicp not installed: pip install small_gicp)")


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
    parser.add_argument("--trials", type=int, default=5, help="inits per case in the speed table")
    parser.add_argument("--success-trials", type=int, default=10, help="inits per angle in the success table")
    parser.add_argument("--success-voxel", type=float, default=0.02, help="voxel (m) for the success table")
    parser.add_argument("--only", choices=("speed", "success"), help="print one table")
    args = parser.parse_args()
    if args.only in (None, "speed"):
        speed_table(args.trials)
    if args.only in (None, "success"):
        success_table(args.success_trials, args.success_voxel)


if __name__ == "__main__":
    main()
