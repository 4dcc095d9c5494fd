"""Which evidence tells the traced faults a person rejects from the ones a person drew, on the dev surveys (issue 54).

Run: ``SEISMO3D_DATA_DIR=... python benchmarks/fault_features.py [--keep DIR] [-- EXTRA FAULTS OPTIONS]``

The dev lines as ``tools/dev_fault_scores.py`` (beside the data folder) builds them (F3 inlines 100-500 as SEG-Y
lines, the Great South Basin crosslines 2600 and 2800 as they are), ``seismo3d faults`` on each, and per traced fault:
its points, the share of them within 3 samples of a person's fault (``near``: a fault with ``near`` >= 0.5 is
counted true, else false), the columns of ``fault_summary.csv`` (dip, throw, correlations, likelihood, votes), and
the angle between the fault and the reflectors beside it: at each point the fault's direction (the main axis of its
points within 6 traces and samples) against the reflectors' normal from the seismic's structure tensor (gradients
at sigma 1, tensor smoothed at sigma 4) 6 traces to either side, as the sine of the angle between fault and
reflectors (1: across them, 0: along them); ``sin_med`` its median over the fault, ``along`` the share of readings
under 0.5 (within 30 degrees of the layering). All in trace / sample index units: a sine of 0 (parallel) is kept
under any scaling of the axes, any other value is not. Printed: the table, each feature's AUC (true against false
faults) per survey, and the dev scores (the script's scorer) after dropping the faults with ``sin_med`` under each
threshold, and after dropping every fault with ``near`` under 0.3 / 0.5 (an oracle: the most dropping faults can
reach). Dropping is re-scored from the kept points, so the tips and throws of the faults left are the run's.
Last, per line, where the person's fault pixels that no traced fault comes within 3 samples of stand in the network's
``fault_likelihood.sgy`` (its largest value within 3 traces and samples): the share of all the person's pixels that
are missed with a likelihood over 0.5 / over 0.3 / under 0.1 (lost after the network / by the network).
"""

from __future__ import annotations

import argparse
import csv
import importlib.util
import itertools
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import segyio
from scipy import ndimage as ndi

COLUMNS = ("mean_dip_deg", "throw_correlation", "side_coherence", "mean_likelihood", "vote_ratio",
           "median_throw_samples", "throw_step_samples")


def _dev_script(data):
    path = Path(data).parent / "tools" / "dev_fault_scores.py"
    sys.path.insert(0, str(path.parent))
    spec = importlib.util.spec_from_file_location("dev_fault_scores", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _reflector_normal(sec):
    """The angle of the reflectors' normal (radians, in (trace, sample) index units) from the structure tensor."""
    gx = ndi.gaussian_filter(sec, 1.0, order=(1, 0))
    gz = ndi.gaussian_filter(sec, 1.0, order=(0, 1))
    jxx, jzz, jxz = (ndi.gaussian_filter(a, 4.0) for a in (gx * gx, gz * gz, gx * gz))
    return 0.5 * np.arctan2(2 * jxz, jxx - jzz)


def _sines(p, normal):
    """|sin| of the angle between the fault (its points p, (trace, sample)) and the reflectors 6 traces either side."""
    out = []
    for j, k in p:
        q = p[(np.abs(p[:, 1] - k) <= 6) & (np.abs(p[:, 0] - j) <= 6)]
        if len(q) < 3:
            continue
        q = q - q.mean(0)
        direction = np.linalg.eigh(q.T @ q)[1][:, -1]
        for off in (-6, 6):
            a = normal[int(np.clip(j + off, 0, normal.shape[0] - 1)), k]
            out.append(abs(direction @ np.array([np.cos(a), np.sin(a)])))
    return np.array(out)


def _line(label, sec, truth, segy, work, extra):
    name = label.replace(" ", "_")
    if segy is None:
        path = work / f"{name}.sgy"
        segyio.tools.from_array(str(path), np.ascontiguousarray(sec[None]), dt=4000)
        il, t, key = np.arange(1, sec.shape[0] + 1, dtype=float), 4.0 * np.arange(sec.shape[1]), "crossline"
    else:
        (path, il, t), key = segy, "inline"
    out = work / name
    subprocess.run(["seismo3d", "faults", str(path), "-o", str(out), *extra], check=True, capture_output=True)
    summary = {r["id"]: r for r in csv.DictReader(open(out / "fault_summary.csv"))}
    points = {}
    for r in csv.DictReader(open(out / "fault_points.csv")):
        j = int(np.searchsorted(il, float(r[key])))
        k = int(round((float(r["time_or_depth"]) - t[0]) / (t[1] - t[0])))
        if 0 <= j < len(il) and 0 <= k < len(t):
            points.setdefault(r["fault_id"], set()).add((j, k))
    return summary, {f: np.array(sorted(p)) for f, p in points.items()}


def _auc(x, y):
    return np.mean([(a > b) + 0.5 * (a == b) for a, b in itertools.product(x[y], x[~y])])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=os.environ.get("SEISMO3D_DATA_DIR"))
    ap.add_argument("--keep", help="keep the lines and outputs in this folder")
    ap.add_argument("extra", nargs="*", help="options passed to `seismo3d faults` (after --)")
    a = ap.parse_args()
    dev = _dev_script(a.data)
    work = Path(a.keep or tempfile.mkdtemp())
    work.mkdir(parents=True, exist_ok=True)
    lines, faults = [], []                                # lines: (survey, label, truth); faults: (line, id, feats)
    for survey, gen in (("F3", dev.f3_lines), ("GSB", dev.gsb_lines)):
        for label, sec, truth, segy in gen(Path(a.data)):
            summary, points = _line(label, sec, truth, segy, work, a.extra)
            near = ndi.binary_dilation(truth, iterations=3)
            normal = _reflector_normal(sec.astype(np.float64))
            lines.append((survey, label, truth, points, work / label.replace(" ", "_")))
            for fid, p in points.items():
                s = _sines(p, normal)
                feats = {"n": len(p), "near": near[p[:, 0], p[:, 1]].mean(),
                         "sin_med": np.median(s) if len(s) else np.nan, "along": np.mean(s < 0.5) if len(s) else 0}
                feats.update({c: abs(float(summary[fid][c])) for c in COLUMNS})
                faults.append((survey, label, fid, feats))
    keys = list(faults[0][3])
    print(f"{'line':20s} {'id':>3s} " + " ".join(f"{k[:8]:>8s}" for k in keys))
    for _, label, fid, f in faults:
        print(f"{label:20s} {fid:>3s} " + " ".join(f"{f[k]:8.2f}" for k in keys))
    for survey in ("F3", "GSB"):
        fs = [f for s, _, _, f in faults if s == survey]
        y = np.array([f["near"] >= 0.5 for f in fs])
        print(f"{survey}: {y.sum()} true, {(~y).sum()} false; AUC " + ", ".join(
            f"{k} {_auc(np.array([f[k] for f in fs]), y):.2f}" for k in keys if k != "near"))

    def rescore(drop):
        res = {"F3": [], "GSB": []}
        for survey, label, truth, points, _ in lines:
            ours = np.zeros(truth.shape, bool)
            for fid, p in points.items():
                if (label, fid) not in drop:
                    ours[p[:, 0], p[:, 1]] = True
            res[survey].append(dev.tolerant_scores(ours, truth, 3))
        return " | ".join(f"{s} P {m[0]:.3f} R {m[1]:.3f} F1 {m[2]:.3f}" for s, m in
                          ((s, np.mean(v, 0)) for s, v in res.items()))

    print(f"{'as drawn':28s}", rescore(set()))
    for th in (0.90, 0.92, 0.94, 0.96, 0.98):
        drop = {(lb, fid) for _, lb, fid, f in faults if f["sin_med"] < th}
        print(f"sin_med < {th:.2f} ({len(drop):2d} dropped)".ljust(28), rescore(drop))
    for th in (0.3, 0.5):
        drop = {(lb, fid) for _, lb, fid, f in faults if f["near"] < th}
        print(f"oracle near < {th} ({len(drop):2d} dropped)".ljust(28), rescore(drop))
    for _, label, truth, points, out in lines:
        with segyio.open(out / "fault_likelihood.sgy", ignore_geometry=True) as f:
            lik = ndi.maximum_filter(segyio.tools.collect(f.trace[:]).astype(np.float64).reshape(truth.shape), size=7)
        ours = np.zeros(truth.shape, bool)
        for p in points.values():
            ours[p[:, 0], p[:, 1]] = True
        missed = truth & ~ndi.binary_dilation(ours, iterations=3)
        share = [(missed & m).sum() / truth.sum() for m in (True, lik > 0.5, lik > 0.3, lik < 0.1)]
        print(f"{label:20s} the person's pixels missed: {share[0]:.3f}; with likelihood > 0.5 {share[1]:.3f}, "
              f"> 0.3 {share[2]:.3f}, < 0.1 {share[3]:.3f}")


if __name__ == "__main__":
    main()
