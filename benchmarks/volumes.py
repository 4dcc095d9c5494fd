"""Sub-volume registration: accuracy against known resampling transforms, a peer, and seconds per pair.

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/volumes.py [--quick] [--only synthetic,peer,speed,real]``

Every pair comes from :func:`seismo3d.data.resampled_pair`: a fixed sub-volume cut from a cube and a moving one
resampled (Lanczos-3 windowed sinc, not the registration's own cubic B-spline) from an overlapping region with known
per-axis scales (moving spacing in fixed traces / samples) and a map-view rotation. Errors
(:func:`seismo3d.seismic.registration_errors`): rotation (degrees), the largest per-axis scale error (%), the
displacement of the moving centre (fixed traces / samples). The issue's tolerances are 0.5 degrees, 1 % and 0.5. A
case counts as passed ("ok") when all three hold.

1. synthetic: 64 x 64 x 80 fixed from a 112 x 112 x 128 faulted synthetic cube; scales 0.5-2, rotations 0-30 degrees.
2. peer: the same reflector points (the dense term's) registered by Open3D's point-to-plane ICP (rigid, started
   with the reflector points' centroids aligned: there is no feature start) on unit-scale pairs; seismo3d with
   model='rigid' beside it.
3. speed: seconds per pair for growing fixed sizes (scales (1.25, 0.8, 1.1), 10 degrees).
4. real: the 18 consecutive Penobscot inlines as an (18, 512, 768) cube (every second sample), and f3_crop.sgy
   (23 x 18 x 75 traces x samples: too small for slice features, so the correlation start; the whole cube is the
   fixed volume and the moving one spans its whole extent, moving_fraction=1, plus one case at the default 0.75).
5. masked_ncc: the masked FFT normalised cross-correlation of the correlation start (``MaskedNCC``, Padfield 2012)
   beside scikit-image's ``phase_cross_correlation(..., reference_mask=, moving_mask=)`` on the registration's own
   calls (recorded while the correlation start of three f3_crop pairs runs): how often the best shift is the same,
   the largest difference of the correlation maps (skimage's ``cross_correlate_masked``, the function behind it),
   and milliseconds per call. scikit-image returns the shift only, thresholds the overlap as a fraction of the
   largest overlap (set here to the start's threshold in samples over the mask size) and recomputes the fixed
   volume's transforms on every call.
"""

from __future__ import annotations

import argparse
import functools
import time
import warnings

import numpy as np

from seismo3d.data import fetch, load_penobscot_sections, resampled_pair, synthetic_cube
from seismo3d.errors import Seismo3dError
from seismo3d.seismic import read_segy, reflector_points, register_volumes, registration_errors

HEADER = ("| pair | moving shape | model | s | rotation err deg | max scale err % | centre err | correlation | "
          "fitness | ok |\n|---|---|---|---|---|---|---|---|---|---|")


def _row(label, fixed, moving, truth) -> None:
    model = "axis_scaled"
    t0 = time.perf_counter()
    try:
        reg = register_volumes(fixed, moving, model=model)
    except Seismo3dError as exc:
        print(f"| {label} | {moving.shape} | {model} | {time.perf_counter() - t0:.1f} | failed: "
              f"{type(exc).__name__}: {str(exc)[:80]} | | | | | no |", flush=True)
        return
    sec = time.perf_counter() - t0
    e = registration_errors(reg.transform_index, truth, moving.shape)
    ok = e.rotation_deg <= 0.5 and e.max_scale_pct <= 1.0 and e.centre_error <= 0.5
    print(f"| {label} | {moving.shape} | {model} | {sec:.1f} | {e.rotation_deg:.3f} | {e.max_scale_pct:.2f} | "
          f"{e.centre_error:.3f} | {reg.correlation:.3f} | {reg.fitness:.2f} | {'yes' if ok else 'no'} |",
          flush=True)


@functools.lru_cache(maxsize=1)
def _big():
    """The 112 x 112 x 128 faulted synthetic cube the synthetic and peer pairs are cut from."""
    return synthetic_cube((112, 112, 128), n_faults=3, seed=1).cube


def synthetic(quick: bool) -> None:
    big = _big()
    print("\n## Synthetic faulted cube, fixed 64 x 64 x 80\n")
    print(HEADER)
    cases = [((1, 1, 1), 0), ((0.5, 1, 2), 15), ((2, 0.7, 1.3), 30), ((1.3, 1.3, 0.6), -30), ((0.5, 0.5, 0.5), 30),
             ((2, 2, 2), -15), ((0.7, 2, 0.8), 25), ((1.6, 0.6, 1.8), -20)]
    for scales, angle in cases[:4] if quick else cases:
        f, m, t = resampled_pair(big, (64, 64, 80), scales=scales, angle_deg=angle, offset=(3, -2, 1.5))
        _row(f"scales {scales}, {angle} deg", f, m, t)


def peer(quick: bool) -> None:
    try:
        import open3d as o3d
    except Exception as exc:  # noqa: BLE001 - any import failure means no peer on this machine
        print(f"\n## Peer: Open3D unavailable ({exc}); skipped\n")
        return
    big = _big()
    print("\n## Peer on unit-scale pairs: Open3D point-to-plane ICP (rigid, centroids aligned) on the same reflector "
          "points; seismo3d rigid\n")
    print("| rotation deg | Open3D s | Open3D rotation err | Open3D centre err | seismo3d s | seismo3d rotation err | "
          "seismo3d centre err |")
    print("|---|---|---|---|---|---|---|")
    for angle in (0, 5, 15) if quick else (0, 5, 15, 30):
        f, m, t = resampled_pair(big, (64, 64, 80), angle_deg=angle, offset=(3, -2, 1.5))
        pf, nf = reflector_points(f)
        pm, _ = reflector_points(m)
        t0 = time.perf_counter()
        src, dst = o3d.geometry.PointCloud(), o3d.geometry.PointCloud()
        src.points = o3d.utility.Vector3dVector(pm)
        dst.points = o3d.utility.Vector3dVector(pf)
        dst.normals = o3d.utility.Vector3dVector(nf)
        est = o3d.pipelines.registration.TransformationEstimationPointToPlane()
        crit = o3d.pipelines.registration.ICPConvergenceCriteria(max_iteration=100)
        init = np.eye(4)
        init[:3, 3] = pf.mean(axis=0) - pm.mean(axis=0)  # centroids aligned: the usual start without features
        res = o3d.pipelines.registration.registration_icp(src, dst, 3.0, init, est, crit)
        s_o3d = time.perf_counter() - t0
        e_o3d = registration_errors(np.asarray(res.transformation), t, m.shape)
        t0 = time.perf_counter()
        reg = register_volumes(f, m, model="rigid")
        s_us = time.perf_counter() - t0
        e = registration_errors(reg.transform_index, t, m.shape)
        print(f"| {angle} | {s_o3d:.2f} | {e_o3d.rotation_deg:.3f} | {e_o3d.centre_error:.3f} | {s_us:.1f} | "
              f"{e.rotation_deg:.3f} | {e.centre_error:.3f} |", flush=True)


def speed(quick: bool) -> None:
    print("\n## Seconds per registered pair, growing sizes (scales (1.25, 0.8, 1.1), 10 degrees)\n")
    print(HEADER)
    sizes = (32, 48, 64, 96) if quick else (32, 48, 64, 96, 128, 160)
    for n in sizes:
        big = synthetic_cube((int(n * 1.5),) * 3, n_faults=3, seed=2).cube
        f, m, t = resampled_pair(big, (n, n, n), scales=(1.25, 0.8, 1.1), angle_deg=10.0, offset=(1, -1, 0.5))
        _row(f"fixed {n}^3", f, m, t)


def real(quick: bool) -> None:
    peno = load_penobscot_sections().cube[:, :, ::2]
    print("\n## Real: Penobscot, 18 consecutive inlines (fixed 18 x 256 x 384)\n")
    print(HEADER)
    cases = [((1, 1, 1), 0), ((1, 1, 1.5), 0), ((0.7, 1.3, 0.8), 5), ((0.5, 2, 1), 0), ((2, 0.5, 0.5), 3),
             ((1.3, 0.8, 1.6), 10), ((1, 1, 1), 30)]
    for scales, angle in cases[:3] if quick else cases:
        f, m, t = resampled_pair(peno, (18, 256, 384), scales=scales, angle_deg=angle, offset=(0.3, 1.2, 1.5))
        _row(f"scales {scales}, {angle} deg", f, m, t)
    f3, _ = read_segy(fetch("seismic/f3_crop.sgy"))
    print("\n## Real: f3_crop.sgy (23 inlines x 18 crosslines x 75 samples, the whole cube as the fixed volume)\n")
    print(HEADER)
    cases = [((1, 1, 1), 0), ((1, 1, 1.5), 0), ((1, 1, 1), 30), ((0.5, 0.5, 1), 15), ((2, 2, 1), 20),
             ((1.3, 0.8, 1.6), 10), ((0.6, 1.8, 0.7), 25), ((2, 0.5, 0.5), -30), ((0.7, 1.4, 1.2), -20),
             ((0.5, 2, 2), 30)]
    for scales, angle in cases[:3] if quick else cases:
        f, m, t = resampled_pair(f3, f3.shape, scales=scales, angle_deg=angle, offset=(0.3, 1.2, 1.5),
                                 moving_fraction=1.0)
        _row(f"scales {scales}, {angle} deg", f, m, t)
    f, m, t = resampled_pair(f3, f3.shape, scales=(2, 2, 1), angle_deg=20, offset=(0.3, 1.2, 1.5))
    _row("scales (2, 2, 1), 20 deg, moving_fraction 0.75", f, m, t)


def masked_ncc(quick: bool) -> None:
    from skimage.registration import phase_cross_correlation
    from skimage.registration._masked_phase_cross_correlation import cross_correlate_masked

    from seismo3d.seismic.reflectors import normalise_amplitudes
    from seismo3d.seismic.volumes import VolumeOptions, starts
    from seismo3d.seismic.volumes.frames import WorkingFrames

    f3, _ = read_segy(fetch("seismic/f3_crop.sgy"))
    cases = [((0.6, 1.8, 0.7), 25.0), ((1.25, 0.8, 1.1), 12.0), ((2, 0.5, 0.5), -30.0)]
    calls = []

    class Recording(starts.MaskedNCC):
        def __call__(self, img, mask, min_overlap):
            calls.append((self.f, img.copy(), mask.copy(), float(min_overlap)))
            return super().__call__(img, mask, min_overlap)

    original = starts.MaskedNCC
    starts.MaskedNCC = Recording
    try:
        for scales, angle in cases[:1] if quick else cases:
            f, m, _ = resampled_pair(f3, f3.shape, scales=scales, angle_deg=angle, offset=(0.3, 1.2, 1.5),
                                     moving_fraction=1.0)
            fn, mn = normalise_amplitudes(f, "fixed"), normalise_amplitudes(m, "moving")
            starts.correlation_starts(fn, mn, WorkingFrames(np.ones(3), np.ones(3)), "axis_scaled", VolumeOptions())
    finally:
        starts.MaskedNCC = original
    print(f"\n## Masked NCC of the correlation start: seismo3d MaskedNCC vs scikit-image, {len(calls)} calls recorded "
          "on f3_crop pairs\n")
    same, valid, diffs, t_ours, t_sk = 0, 0, [], 0.0, 0.0
    ours = {}
    for fixed, img, mask, need in calls:
        ncc_fn = ours.setdefault(id(fixed), original(fixed))  # the fixed volume's FFTs reused, as in the search
        t0 = time.perf_counter()
        ncc, origin = ncc_fn(img, mask, need)
        t_ours += time.perf_counter() - t0
        k = np.unravel_index(int(np.argmax(ncc)), ncc.shape)
        ratio = need / max(mask.sum(), 1.0)
        t0 = time.perf_counter()
        shift = phase_cross_correlation(fixed, img, reference_mask=np.ones(fixed.shape, bool),
                                        moving_mask=mask > 0, overlap_ratio=ratio)[0]
        t_sk += time.perf_counter() - t0
        shift = shift - (np.array(img.shape) - np.array(fixed.shape)) / 2.0  # skimage's centring -> our shift
        if np.isfinite(ncc[k]):  # a shift with enough overlap exists (else the start drops the map)
            valid += 1
            same += bool(np.all(np.abs(shift - (np.array(k) - origin)) < 0.5))
        # skimage's NCC map in our layout: its 'full' output is indexed like ours up to the flip of the roles
        sk = cross_correlate_masked(img, fixed, mask > 0, np.ones(fixed.shape, bool), axes=(0, 1, 2), mode="full",
                                    overlap_ratio=0.0)[::-1, ::-1, ::-1]
        ncc = ncc[tuple(slice(0, n) for n in sk.shape)]  # ours is computed on FFT-friendly padded shapes
        ok = np.isfinite(ncc)
        diffs.append(float(np.max(np.abs(sk[ok] - ncc[ok]))) if ok.any() else 0.0)
    n = max(len(calls), 1)
    print("| implementation | same best shift (calls with enough overlap) | max abs NCC difference | ms per call |")
    print("|---|---|---|---|")
    print(f"| seismo3d MaskedNCC (rfftn, fixed FFTs cached) | reference | reference | {1e3 * t_ours / n:.2f} |")
    print(f"| skimage phase_cross_correlation (masked) | {same} of {valid} | {max(diffs):.2e} | "
          f"{1e3 * t_sk / n:.2f} |", flush=True)


SECTIONS = {"synthetic": synthetic, "peer": peer, "speed": speed, "real": real, "masked_ncc": masked_ncc}

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer cases and sizes")
    ap.add_argument("--only", default=",".join(SECTIONS), help="comma-separated sections: " + ", ".join(SECTIONS))
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    for name in args.only.split(","):
        SECTIONS[name.strip()](args.quick)
