"""Horizon tracking: accuracy against people's picks and the generator's truth, beside a plain autotracker; speed.

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/horizons.py [--quick] [--only SECTION] [--check]``

1. Penobscot cross-validation (18 consecutive real inlines, 7 horizons picked by people, split into two folds of 9
   inlines: 1075-1083 and 1084-1092): one seed per horizon on the fold's first inline (crossline 256, at the
   interpreter's pick), the same defaults on both folds. Per horizon: median absolute error, % of live traces within
   5 samples (untracked traces count as misses; dead traces are not scored), coverage, seconds per slice; for
   track_horizon's default, the registration tracker and the plain amplitude autotracker (same extremum picks,
   +-3 samples, breadth-first), in the same run.
2. Synthetic faulted cubes (seismo3d.data.synthetic_cube, 3 faults, seeds 0-2): faults traced with trace_faults,
   every horizon tracked from one seed on the middle inline; median absolute error against the true horizons.
   ``--check`` exits 1 unless, on every cube, every horizon's median is within 0.16 samples and the mean share of
   traces within 2 samples is at least 0.89 (``SYNTHETIC_*_LIMIT``): the claim of
   tests/seismic/test_horizon_tracking.py, which keeps cube 0 (2.4 min for the three cubes on 2 cores).
3. Speed: seconds per tracked slice (along one inline, and inline-to-inline carry) for growing slice sizes.
4. f3_crop (23 x 18 traces of 75 samples at 4 ms, real): no picks by people; the jitter of neighbouring picks (share
   of steps of 10 ms or more between neighbouring traces along inlines and crosslines, median step) and coverage of
   one seed at 132 ms and at 236 ms (inline 11, crossline 9), for the default, the registration tracker and the plain
   autotracker.
5. traced_faults: the 18 Penobscot inlines with the faults :func:`trace_faults` finds in them (many spurious: the
   clipped 8-bit slab), every horizon tracked from inline 0, trace 256 (at the people's pick) with and without that
   fault input. ``--check`` exits 1 unless, on every horizon, the faults cost no more than half a point of the
   traces within 5 samples against tracking without them, the median stays at the one measured (``MEDIAN_MEASURED``,
   the same as tests/seismic/test_horizon_tracking.py's) and, but on horizon 6 (whose fault throw the traced faults
   do not carry), 99 % of the traces are within 5 samples: the claim moved here from the test suite (about 4 min on 2
   cores; the suite keeps a window of these inlines); and unless no traced fault lies in the crosshatch of dipping
   events at crosslines 300-390, samples 830-1040 (issue 54's claim, moved from
   tests/seismic/faults/test_pipeline.py, which keeps Penobscot crossline 1155's).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

import numpy as np

from seismo3d.data import load_penobscot_sections
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic import autotrack, horizon_errors, reflector_picks, trace_faults, track_horizon
from seismo3d.seismic.reflectors import nearest_pick


FOLDS = (("1075-1083", slice(0, 9)), ("1084-1092", slice(9, 18)))


def penobscot(quick: bool) -> None:
    # Dead traces (the image's first column on most sections) hold no data; their "picks" are mask artefacts
    # (e.g. 255 where the next trace has 35), so the loader leaves them out and they are not scored.
    peno = load_penobscot_sections()
    print("\n## Penobscot cross-validation: the same defaults on each half of the 18 inlines (9 inlines x 512 traces), "
          "one seed per horizon (the fold's first inline, trace 256, at the people's pick)\n")
    print("The defaults were developed on inlines 1075-1083 and are reported unchanged on 1084-1092 (and the reverse). "
          "Per horizon: median absolute error (samples, over tracked traces), % of live traces within 5 samples "
          "(untracked count as misses), coverage; for track_horizon's default (global least squares + DP), the "
          "registration tracker (method='registration', point-to-plane) and the plain amplitude autotracker "
          "(+-3 samples, breadth-first), in the same run; seconds per inline (slice).\n")
    runs = [("seismo3d (default: global)", dict())]
    if not quick:
        runs.append(("registration tracker", dict(method="registration", features=None)))
    # compiled kernels are loaded (or compiled) once before any timing: a small run of each method
    small = np.ascontiguousarray(peno.cube[:3, 200:300])
    picks, offsets = reflector_picks(small[0, 50][None])
    warm = (0, 50, nearest_pick(picks, offsets, 0, float(peno.horizons[0, 0, 250]), 5.0))
    for _, kw in runs:
        track_horizon(small, warm, **kw)
    autotrack(small, warm)
    print("| fold (inlines) | horizon | method | median abs | within 5 % | coverage % | s per slice |")
    print("|---|---|---|---|---|---|---|")
    summary = {}  # (fold, method) -> [seconds, medians, within-5 fractions]
    for fold, rows_sel in FOLDS:
        cube = np.ascontiguousarray(peno.cube[rows_sel])
        human = peno.horizons[rows_sel]
        for k in range(human.shape[1]):
            ref = human[:, k]
            # both trackers get the same seed: the peak nearest the people's pick (within 5 samples; on 1084-1092
            # horizon 5's pick sits 4 samples from it, beyond the autotracker's own 3-sample snap)
            picks, offsets = reflector_picks(cube[0, 256][None])
            seed = (0, 256, nearest_pick(picks, offsets, 0, float(ref[0, 256]), 5.0))
            rows = []
            for name, kw in runs:
                t0 = time.perf_counter()
                hz = track_horizon(cube, seed, **kw)
                rows.append((name, hz.times, time.perf_counter() - t0))
            t0 = time.perf_counter()
            plain = autotrack(cube, seed)
            rows.append(("plain autotracker", plain.times, time.perf_counter() - t0))
            for name, times, sec in rows:
                e = horizon_errors(times, ref)
                print(f"| {fold} | {k} | {name} | {e.median_abs:.2f} | {100 * e.within_5:.2f} | "
                      f"{100 * e.coverage:.1f} | {sec / cube.shape[0]:.3f} |", flush=True)
                acc = summary.setdefault((fold, name), [0.0, [], []])
                acc[0] += sec / cube.shape[0]
                acc[1].append(e.median_abs)
                acc[2].append(e.within_5)
    n_hz = peno.horizons.shape[1]
    print(f"\nPer fold, all {n_hz} horizons (same run; every horizon has the same live traces, so the mean of the "
          "horizons' within-5 is the pooled share): seconds per slice (mean over horizons) and the ratio to the "
          "plain autotracker; load average " + " ".join(f"{v:.2f}" for v in os.getloadavg()) + "\n")
    print("| fold (inlines) | method | s per slice | x autotracker | median of medians | within 5 % |")
    print("|---|---|---|---|---|---|")
    for (fold, name), (sec, med, w5) in summary.items():
        peer = summary[(fold, "plain autotracker")][0]
        print(f"| {fold} | {name} | {sec / n_hz:.3f} | {sec / peer:.1f} | {np.median(med):.2f} | "
              f"{100 * np.mean(w5):.2f} |", flush=True)


def _seed(syn, k: int, i0: int) -> tuple[tuple[float, float, float], str]:
    """Seed on the generator's horizon ``k`` at inline ``i0``, at the picked trace nearest the middle, and the
    horizon's polarity."""
    ref = syn.horizons[k]
    ok = np.nonzero(np.isfinite(ref[i0]))[0]
    j0 = int(ok[np.argmin(np.abs(ok - syn.shape[1] // 2))])
    return (i0, j0, float(ref[i0, j0])), "peak" if syn.horizon_polarity[k] > 0 else "trough"


# The generated cubes' limits (tests/seismic/test_horizon_tracking.py keeps cube 0; cubes 1 and 2 are checked here):
# every horizon's median |error| within 0.16 samples (measured 0.083 / 0.068 / 0.106 on cubes 0-2 on 2026-11-27,
# 1.5x the worst; the target is one sample) and, per cube, the mean share of traces within 2 samples at least
# 0.89 (measured 0.951 / 0.928 / 0.958, the worst less 3 points).
SYNTHETIC_MEDIAN_LIMIT = 0.16
SYNTHETIC_WITHIN_2_LIMIT = 0.89


def synthetic(quick: bool) -> bool:
    """Section 2: the generated faulted cubes (seeds 0-2; 0 with ``quick``), every horizon tracked with the traced
    faults by ``track_horizon``'s defaults, beside no fault input and the plain autotracker; True when every cube
    meets the limits above."""
    print("\n## Synthetic faulted cubes 64 x 64 x 96 (3 faults, noise 0.1), all horizons, seed on the middle inline\n")
    print("| cube seed | horizon | faults traced | median abs, with faults | within 2 % | coverage % | median abs, "
          "no fault input | plain autotracker median abs | plain within 2 % |")
    print("|---|---|---|---|---|---|---|---|---|")
    ok = True
    for cs in range(1 if quick else 3):
        syn = synthetic_cube((64, 64, 96), n_faults=3, seed=cs)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            faults = trace_faults(syn.cube, progress=False)
        i0 = syn.shape[0] // 2
        medians, within_2 = [], []
        for k in range(syn.horizons.shape[0]):
            ref = syn.horizons[k]
            seed, pol = _seed(syn, k, i0)
            e = horizon_errors(track_horizon(syn.cube, seed, polarity=pol, faults=faults).times, ref)
            e0 = horizon_errors(track_horizon(syn.cube, seed, polarity=pol).times, ref)
            ea = horizon_errors(autotrack(syn.cube, seed, polarity=pol).times, ref)
            medians.append(e.median_abs)
            within_2.append(e.within_2)
            print(f"| {cs} | {k} | {len(faults.faults)} | {e.median_abs:.2f} | {100 * e.within_2:.1f} | "
                  f"{100 * e.coverage:.1f} | {e0.median_abs:.2f} | {ea.median_abs:.2f} | "
                  f"{100 * ea.within_2:.1f} |", flush=True)
        right = bool(np.all(np.isfinite(medians)) and max(medians) <= SYNTHETIC_MEDIAN_LIMIT
                     and np.mean(within_2) >= SYNTHETIC_WITHIN_2_LIMIT)
        ok &= right
        print(f"cube {cs}: largest median {max(medians):.3f} samples (limit {SYNTHETIC_MEDIAN_LIMIT}), mean within 2 "
              f"samples {np.mean(within_2):.3f} (limit {SYNTHETIC_WITHIN_2_LIMIT}): {'ok' if right else 'MISSED'}",
              flush=True)
    return ok


def speed(quick: bool) -> None:
    print("\n## Speed: seconds per tracked slice (synthetic, no faults; 16 inlines)\n")
    print("| slice (traces x samples) | along the seed inline s | per inline-to-inline carry s (point-to-plane) | "
          "per carry s (fused, HOG) |")
    print("|---|---|---|---|")
    sizes = [(128, 128), (256, 256)] if quick else [(128, 128), (256, 256), (512, 512)]
    for n_xl, n_s in sizes:
        syn = synthetic_cube((16, n_xl, n_s), n_faults=0, seed=0)
        seed, pol = _seed(syn, len(syn.horizons) // 2, 0)
        t0 = time.perf_counter()
        track_horizon(syn.cube[0], seed[1:], polarity=pol)
        along = time.perf_counter() - t0
        out = []
        for feats in (None, "hog"):
            t0 = time.perf_counter()
            track_horizon(syn.cube, seed, polarity=pol, features=feats)
            out.append((time.perf_counter() - t0 - along) / 15)
        print(f"| {n_xl} x {n_s} | {along:.2f} | {out[0]:.2f} | {out[1]:.2f} |", flush=True)


def f3_crop(quick: bool) -> None:
    from seismo3d.data import fetch
    from seismo3d.seismic import read_segy

    cube, geom = read_segy(fetch("seismic/f3_crop.sgy"))
    print("\n## f3_crop (23 x 18 traces x 75 samples, 4 ms): jitter of neighbouring picks, one seed at inline 11, "
          "crossline 9\n")
    print("| seed (ms) | method | coverage % | steps >= 10 ms % | median step ms | largest step ms |")
    print("|---|---|---|---|---|---|")
    dt = float(geom.sample_interval)
    runs = (("seismo3d (default: global)", lambda c, s: track_horizon(c, s)),
            ("registration tracker", lambda c, s: track_horizon(c, s, method="registration")),
            ("plain autotracker", lambda c, s: autotrack(c, s)))
    for ms in (132.0, 236.0):
        picks, offsets = reflector_picks(cube[11, 9][None])
        seed = (11, 9, nearest_pick(picks, offsets, 0, (ms - float(geom.samples[0])) / dt, 5.0))
        for name, fn in runs:
            times = np.asarray(fn(cube, seed).times, np.float64)
            steps = np.concatenate([np.abs(np.diff(times, axis=0)).ravel(), np.abs(np.diff(times, axis=1)).ravel()])
            steps = steps[np.isfinite(steps)] * dt
            print(f"| {ms:.0f} | {name} | {100 * np.isfinite(times).mean():.1f} | {100 * np.mean(steps >= 10.0):.1f} | "
                  f"{np.median(steps):.1f} | {steps.max():.1f} |", flush=True)


# The median |error| per horizon measured on both folds and with traced faults (tests/seismic/test_horizon_tracking.py
# MEDIAN_MEASURED: the people's picks sit on a grid of half a sample, so a median moves in steps of 0.5)
MEDIAN_MEASURED = {0: 1.0, 1: 1.0, 2: 0.5, 3: 0.5, 4: 0.5, 5: 1.5, 6: 1.0}


def traced_faults(quick: bool) -> bool:
    """Section 5: the Penobscot horizons tracked with the faults traced in the same inlines; True when every
    horizon meets the check (module notes)."""
    from seismo3d.errors import Seismo3dWarning

    peno = load_penobscot_sections()
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)  # clipped amplitudes and the muted top are reported
        faults = trace_faults(peno.cube, progress=False)
    print(f"\n## Penobscot: the 18 inlines' horizons with the {len(faults.faults)} faults trace_faults finds in them "
          f"({time.perf_counter() - t0:.0f} s), seed inline 0, trace 256\n")
    # no fault where dipping events cross (issue 54; moved from tests/seismic/faults/test_pipeline.py, issue 58): the
    # one these inlines had until 2026-11-26, a crosshatch at crosslines 312-383, samples 838-1033 (throw 5.07 under
    # the reflectors' half period 5.31, side correlation 0.20), is not a clear displacement
    crosshatch = [f.id for f in faults.faults if 300 <= np.median(f.points[:, 1]) <= 390
                  and 830 <= np.median(f.points[:, 2]) <= 1040]
    ok = not crosshatch
    print(f"faults in the crosshatch (crosslines 300-390, samples 830-1040): {crosshatch} "
          f"({'ok' if ok else 'MISSED'}: none expected)\n")
    print("| horizon | median abs, with faults | within 5 %, with faults | median abs, no fault input | within 5 %, "
          "no fault input | median limit | check |")
    print("|---|---|---|---|---|---|---|")
    for k in range(peno.horizons.shape[1]):
        ref = peno.horizons[:, k]
        seed = (0, 256, ref[0, 256])
        ours = horizon_errors(track_horizon(peno.cube, seed, faults=faults).times, ref)
        without = horizon_errors(track_horizon(peno.cube, seed).times, ref)
        right = (ours.within_5 >= without.within_5 - 0.005 and ours.median_abs <= MEDIAN_MEASURED[k]
                 and (k == 6 or ours.within_5 >= 0.99))
        ok &= bool(right)
        print(f"| {k} | {ours.median_abs:.2f} | {100 * ours.within_5:.2f} | {without.median_abs:.2f} | "
              f"{100 * without.within_5:.2f} | {MEDIAN_MEASURED[k]} | {'ok' if right else 'MISSED'} |", flush=True)
    return ok


SECTIONS = {"penobscot": penobscot, "synthetic": synthetic, "speed": speed, "f3_crop": f3_crop,
            "traced_faults": traced_faults}
CHECKED = {"synthetic", "traced_faults"}  # the sections whose targets --check asserts


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer cases (point-to-plane only on Penobscot)")
    parser.add_argument("--only", choices=list(SECTIONS))
    parser.add_argument("--check", action="store_true",
                        help="run the checked sections (synthetic, traced_faults; with --only, that one) and exit 1 "
                             "when a target is missed")
    args = parser.parse_args()
    if args.check and args.quick:  # --quick tracks one generated cube of the three the check asserts
        parser.error("--quick runs fewer cases than --check asserts: run --check without --quick")
    names = [args.only] if args.only else (sorted(CHECKED) if args.check else list(SECTIONS))
    failed = [name for name in names if SECTIONS[name](args.quick) is False]
    if args.check and failed:
        print(f"check failed: {', '.join(failed)}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
