"""Which fault candidates of the F3 inlines drawn by a person are right, and what tells them apart (issue 35).

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/fault_candidates.py`` (about 3 minutes on 2 cores)

The five F3 inlines of ``seismic/f3_fault_masks`` are traced as in ``benchmarks/faults.py --only f3`` with the
defaults, except that no evidence is asked (every candidate the skins give, with its evidence measured). A candidate
is *right* when at least half of its samples lie within 3 samples of a drawn fault (the tolerance of
``shared/tools/fault_scores.py``). Printed:

1. Per inline, tolerant precision / recall / F1 of the defaults' faults, of every candidate, and of the right
   candidates alone (an oracle that keeps exactly those: the ceiling of any rule that keeps or drops whole
   candidates of this likelihood).
2. Per measure of a candidate, the area under the ROC curve of right against wrong (candidates weighted by their
   samples; 0.5 = no better than chance, below 0.5 = the wrong ones score higher): its length, the displacement
   evidence of ``FaultEvidence`` (|median throw|, spread, correlation, correlation gain, measured fraction, side
   coherence), the mean fault likelihood (network probability) and the mean votes along it, and the mean likelihood
   6-12 traces to either side (the background).
3. Logistic regressions over those measures, cross-validated: fitted (and their keep threshold chosen by mean F1) on
   three inlines, scored on the other two, for all ten splits; held-out precision / recall / F1 beside the defaults'
   on the same held-out inlines. One model over the displacement measures and the length, one with the mean
   likelihood and votes added.
4. Rules over whole candidates without fitted weights, and the one of them chosen by cross-validation (chosen by
   mean F1 on three inlines, scored on the other two, every split): the defaults' displacement evidence ("ev"),
   alone or with the mean fault likelihood c as an alternative ("ev | lk >= c") and with the mean votes asked to
   reach the upper vote threshold ("votes >= upper & (ev | lk >= c)"), for c in 0.5 ... 0.9 (c = 1.01: never).

Nothing here changes a default: it measures where a rule over whole candidates could go.
"""

from __future__ import annotations

import itertools
import warnings

import numpy as np
from scipy.ndimage import distance_transform_edt
from scipy.optimize import minimize

from faults import _scores  # benchmarks/faults.py: the tolerant scores of the F3 table
from seismo3d.data import load_f3_fault_sections
from seismo3d.seismic import trace_faults
from seismo3d.seismic.faults import EvidenceOptions, FaultTracingOptions

TOLERANCE = 3.0
DISPLACEMENT = ("log_length", "throw", "throw_spread", "correlation", "correlation_gain", "measured_fraction",
                "side_coherence")
STRENGTH = ("likelihood", "votes")


def candidates(section: np.ndarray, drawn: np.ndarray, k: int) -> list[dict]:
    """Every candidate of one inline (no evidence asked) with its measures, whether it is right, its points."""
    every = FaultTracingOptions(evidence=EvidenceOptions(min_throw=0.0, min_correlation_gain=-1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the 8-bit rendering's clipped amplitudes are reported
        res = trace_faults(section, progress=False, options=every, sample_interval=4.0, sample_unit="ms")
    near = distance_transform_edt(~drawn) <= TOLERANCE
    n_traces = section.shape[0]
    rows = []
    for fault, e in zip(res.faults, res.evidence):
        t, s = fault.points[:, 0], fault.points[:, 1]
        side = [res.likelihood[np.clip(t + sign * d, 0, n_traces - 1), s] for d in range(6, 13) for sign in (-1, 1)]
        finite = lambda v: float(v) if np.isfinite(v) else 0.0  # noqa: E731  (unmeasured: no evidence)
        rows.append(dict(
            inline=k, points=fault.points, n=len(t), right=bool(near[t, s].mean() >= 0.5),
            kept=bool(e.supports(EvidenceOptions())), log_length=float(np.log(len(t))),
            throw=min(abs(finite(e.median_throw)), 5.0), throw_spread=finite(e.throw_spread),
            correlation=finite(e.correlation), correlation_gain=finite(e.correlation_gain),
            measured_fraction=float(e.measured_fraction), side_coherence=finite(e.side_coherence),
            likelihood=float(res.likelihood[t, s].mean()), votes=float(res.votes[t, s].mean()),
            background=float(np.mean(side)), upper=float(res.thresholds[1])))
    return rows


def masks_scores(rows, keep, data, inlines) -> list[tuple]:
    """Tolerant (precision, recall, F1) of the kept candidates on each of ``inlines``."""
    out = []
    for k in inlines:
        mask = np.zeros(data.sections[k].shape, bool)
        for r, kp in zip(rows, keep):
            if kp and r["inline"] == k:
                mask[tuple(r["points"].T)] = True
        out.append(_scores(mask, data.faults[k].astype(bool), TOLERANCE))
    return out


def weighted_auc(x: np.ndarray, right: np.ndarray, w: np.ndarray) -> float:
    """Area under the ROC curve of ``x`` for right against wrong candidates, each weighted by ``w``."""
    pos, neg, wp, wn = x[right], x[~right], w[right], w[~right]
    wins = sum(wp[i] * (wn * ((neg < pos[i]) + 0.5 * (neg == pos[i]))).sum() for i in range(len(pos)))
    return float(wins / (wp.sum() * wn.sum()))


def fit_logistic(x: np.ndarray, y: np.ndarray, w: np.ndarray, l2: float = 1.0):
    """Sample-weighted, L2-regularised logistic regression on standardised measures; the probability function."""
    mu, sd = x.mean(0), x.std(0) + 1e-9
    z = np.c_[np.ones(len(x)), (x - mu) / sd]

    def loss(b):
        p = 1.0 / (1.0 + np.exp(-(z @ b)))
        ll = -(w * (y * np.log(p + 1e-12) + (1 - y) * np.log(1 - p + 1e-12))).sum() / w.sum()
        return ll + l2 * (b[1:] ** 2).sum() / len(x)

    b = minimize(loss, np.zeros(z.shape[1]), method="L-BFGS-B").x
    return lambda xs: 1.0 / (1.0 + np.exp(-(np.c_[np.ones(len(xs)), (xs - mu) / sd] @ b)))


def mean3(scores) -> str:
    return " / ".join(f"{np.mean([s[i] for s in scores]):.3f}" for i in range(3))


def main() -> None:
    data = load_f3_fault_sections()
    n = len(data.inlines)
    rows = [r for k in range(n) for r in candidates(data.sections[k], data.faults[k].astype(bool), k)]
    right = np.array([r["right"] for r in rows])
    weight = np.array([r["n"] for r in rows], float)
    print(f"\nF3 inlines, every candidate before the evidence rules: {len(rows)} candidates, {right.sum()} right "
          f"(half their samples within {TOLERANCE:g} of a drawn fault)\n")
    choices = {"defaults": [r["kept"] for r in rows], "every candidate": [True] * len(rows),
               "right ones only (oracle)": list(right)}
    print(f"{'inline':>6s} | " + " | ".join(f"{c:>24s}" for c in choices))
    per = {c: masks_scores(rows, keep, data, range(n)) for c, keep in choices.items()}
    for k in range(n):
        print(f"{data.inlines[k]:6d} | " + " | ".join(f"{mean3([per[c][k]]):>24s}" for c in choices))
    print(f"{'mean':>6s} | " + " | ".join(f"{mean3(per[c]):>24s}" for c in choices) + "   (precision / recall / F1)")

    print("\nEach measure alone: area under the ROC curve of right against wrong (weighted by samples), medians")
    for name in ("log_length",) + DISPLACEMENT[1:] + STRENGTH + ("background",):
        x = np.array([r[name] for r in rows], float)
        print(f"  {name:18s} AUC {weighted_auc(x, right, weight):.2f}   right {np.median(x[right]):7.3f}   "
              f"wrong {np.median(x[~right]):7.3f}")

    print("\nLogistic regressions, fitted and thresholded on three inlines, scored on the other two (10 splits): "
          "held-out precision / recall / F1")
    inline_of = np.array([r["inline"] for r in rows])
    for label, names in (("displacement + length", DISPLACEMENT), ("+ likelihood and votes", DISPLACEMENT + STRENGTH)):
        x = np.array([[r[m] for m in names] for r in rows], float)
        held, default = [], []
        for train in itertools.combinations(range(n), 3):
            test = [k for k in range(n) if k not in train]
            fit = np.isin(inline_of, train)
            prob = fit_logistic(x[fit], right[fit].astype(float), weight[fit])(x)
            cut = max(np.linspace(0.05, 0.95, 19),
                      key=lambda c: np.mean([s[2] for s in masks_scores(rows, prob >= c, data, train)]))
            held += masks_scores(rows, prob >= cut, data, test)
            default += masks_scores(rows, choices["defaults"], data, test)
        print(f"  {label:24s} {mean3(held)}   (defaults on the same held-out inlines: {mean3(default)})")

    print("\nRules over whole candidates (mean precision / recall / F1 over the five inlines), then the rule chosen "
          "on three inlines and scored on the other two")
    rules = {}
    for c in (0.5, 0.6, 0.7, 0.8, 0.9, 1.01):
        rules[f"ev | lk >= {c:g}"] = [r["kept"] or r["likelihood"] >= c for r in rows]
        rules[f"votes >= upper & (ev | lk >= {c:g})"] = [r["votes"] >= r["upper"] and (r["kept"] or
                                                                                     r["likelihood"] >= c)
                                                        for r in rows]
    rules["votes >= upper"] = [r["votes"] >= r["upper"] for r in rows]
    scores = {name: masks_scores(rows, keep, data, range(n)) for name, keep in rules.items()}
    for name, sc in scores.items():
        print(f"  {name:36s} {sum(rules[name]):4d} kept   {mean3(sc)}")
    held, default = [], []
    for train in itertools.combinations(range(n), 3):
        test = [k for k in range(n) if k not in train]
        choice = max(scores, key=lambda name: np.mean([scores[name][k][2] for k in train]))
        held += [scores[choice][k] for k in test]
        default += [per["defaults"][k] for k in test]
        print(f"  chosen on {','.join(str(data.inlines[k]) for k in train):>12s}: {choice}")
    print(f"  held-out {mean3(held)}   (defaults on the same held-out inlines: {mean3(default)})")


if __name__ == "__main__":
    main()
