"""Where the faults of the F3 inlines drawn by a person are missed or invented: tolerant precision and recall by
window of samples, for the defaults' faults and for every candidate before the evidence rules (issue 35).

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/fault_depth_windows.py [--bounds 260,400]
[--likelihood learned|scan]``

The five F3 inlines of ``seismic/f3_fault_masks`` (951 traces x 462 samples, 4 ms) are traced as in
``benchmarks/faults.py --only f3``. A predicted fault sample is right when a drawn one lies within 3 samples of it
(Euclidean, on the whole section: the definition of ``shared/tools/fault_scores.py``), a drawn one is found when a
predicted one lies within 3 samples; both are then counted by the window of samples they lie in, pooled over the five
inlines. The default bounds (samples 260 and 400) bracket the interval of short, steep discontinuities that the
pictures of inlines 300 and 400 showed; they are a reporting choice, nothing is fitted to them. Printed per window:
predicted and drawn fault samples, precision, recall and the false-positive samples; then F1 per inline with the
middle window left out of both images.
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.ndimage import distance_transform_edt

from faults import _candidates, _kept_mask, _scores  # benchmarks/faults.py: the same runs as its F3 table
from seismo3d.data import load_f3_fault_sections
from seismo3d.seismic.faults import EvidenceOptions

TOLERANCE = 3.0


def window_counts(pred, drawn, bounds) -> np.ndarray:
    """(n_windows, 4) int: predicted, predicted right, drawn, drawn found, per window of samples (axis 1)."""
    right = distance_transform_edt(~drawn) <= TOLERANCE
    found = distance_transform_edt(~pred) <= TOLERANCE
    edges = [0, *bounds, pred.shape[1]]
    return np.array([[pred[:, a:b].sum(), (pred & right)[:, a:b].sum(), drawn[:, a:b].sum(),
                      (drawn & found)[:, a:b].sum()] for a, b in zip(edges[:-1], edges[1:])])


def f1_without(pred, drawn, a, b) -> float:
    """Tolerant F1 with samples ``a:b`` left out of both images."""
    keep = np.ones(pred.shape[1], bool)
    keep[a:b] = False
    return _scores(pred[:, keep], drawn[:, keep], TOLERANCE)[2]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bounds", default="260,400", help="sample indices between the windows (default 260,400)")
    ap.add_argument("--likelihood", choices=("learned", "scan"), default="learned")
    args = ap.parse_args(argv)
    bounds = [int(v) for v in args.bounds.split(",")]
    data = load_f3_fault_sections()
    edges = [0, *bounds, data.sections[0].shape[1]]
    totals = {"defaults": 0, "every candidate": 0}
    f1 = {name: [] for name in totals}
    for k, inline in enumerate(data.inlines):
        section, drawn = data.sections[k], data.faults[k].astype(bool)
        faults, evidence, _ = _candidates(section, args.likelihood, sample_interval=4.0, sample_unit="ms")
        for name, options in (("defaults", EvidenceOptions()), ("every candidate", None)):
            pred = _kept_mask(faults, evidence, section.shape, options)
            totals[name] = totals[name] + window_counts(pred, drawn, bounds)
            if len(bounds) == 2:
                f1[name].append(f1_without(pred, drawn, *bounds))
        print(f"inline {inline} traced", flush=True)
    for name, t in totals.items():
        print(f"\n{args.likelihood} likelihood, {name}: tolerance {TOLERANCE:g} samples, pooled over inlines "
              f"{', '.join(map(str, data.inlines))}\n")
        print("| samples | predicted | precision | drawn | recall | false positives |\n|---|---|---|---|---|---|")
        for (a, b), (n_pred, n_right, n_drawn, n_found) in zip(zip(edges[:-1], edges[1:]), t):
            print(f"| {a}-{b} | {n_pred} | {n_right / max(n_pred, 1):.3f} | {n_drawn} | "
                  f"{n_found / max(n_drawn, 1):.3f} | {n_pred - n_right} |")
        if f1[name]:
            print(f"F1 per inline with samples {bounds[0]}-{bounds[1]} left out: "
                  + " / ".join(f"{v:.3f}" for v in f1[name]) + f" (mean {np.mean(f1[name]):.3f})")


if __name__ == "__main__":
    main()
