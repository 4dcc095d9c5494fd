"""Where the person's fault pixels that the network sees are lost, step by step after the network (issue 54).

Run: ``SEISMO3D_DATA_DIR=... python benchmarks/fault_stages.py [--sensitivity S]``

The dev lines as ``tools/dev_fault_scores.py`` (beside the data folder) builds them (F3 inlines 100-500, 951 x 462;
the Great South Basin crosslines 2600 and 2800, 484 x 76), traced in this process with the steps of
:func:`seismo3d.seismic.trace_faults` run one at a time (:func:`~seismo3d.seismic.faults.surfaces.blocks.memory_surface_run`, then
:func:`~seismo3d.seismic.faults.steps.faults_from_cells`' skins, throws, evidence and tips written out here), so that
what each step keeps can be seen; the final faults are checked to be those of ``trace_faults`` on the same line.

A person's pixel counts as *lost after the network* when the network's likelihood within 3 traces and samples of it is
over 0.5 (as ``benchmarks/fault_features.py``) and no final fault point is within 3 samples of it (the scorer's
tolerance, Euclidean). It is charged to the first step whose output has no point within 3 samples of it:

1. ``ridge``: the likelihood's ridges above the voting's seed threshold (the seed candidates);
2. ``thin votes``: the votes thinned (non-zero);
3. ``cells``: the thinned votes at or above the lower hysteresis threshold;
4. ``skins``: the cells linked into fault skins (both hysteresis passes, with the smallest size and height and the
   planarity of :class:`~seismo3d.seismic.faults.surfaces.skins.SkinOptions`);
5. ``evidence``: the skins :func:`~seismo3d.seismic.faults.evidence.supported_faults` keeps (the rule that dropped
   each skin is named: vote ratio, probability, flexure, unbroken, drag, low correlation, unseeded);
6. ``tips``: the kept faults after :func:`~seismo3d.seismic.faults.tips.trimmed_tips`.

Printed per line and per survey: the scores, the person's pixels, those missed, those lost after the network and the
step that lost them, the evidence rules behind the ``evidence`` column, the person's faults (8-connected pixels)
that are missed whole (under 0.1 of their pixels found) and how much of them the network saw, and for the ``ridge``
column the median distance from its pixels to the nearest likelihood over 0.5 (3 samples: at the edge of the window,
the network's ridge 4 samples away, out of the tolerance whatever the later steps do).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy import ndimage as ndi
from scipy.ndimage import distance_transform_edt

from seismo3d.errors import Seismo3dWarning
from seismo3d.seismic.amplitudes import clean_traces
from seismo3d.seismic.faults.evidence import fault_evidence
from seismo3d.seismic.faults.likelihood.learned import learned_fault_likelihood
from seismo3d.seismic.faults.options import FaultTracingOptions
from seismo3d.seismic.faults.pipeline import trace_faults
from seismo3d.seismic.faults.reflector_period import half_period
from seismo3d.seismic.faults.steps import surface_cells
from seismo3d.seismic.faults.surfaces.blocks import memory_surface_run
from seismo3d.seismic.faults.surfaces.skins import skins_from_cells
from seismo3d.seismic.faults.throw import fault_throws
from seismo3d.seismic.faults.tips import trimmed_tips

from fault_features import _dev_script  # benchmarks/fault_features.py: the dev lines of tools/dev_fault_scores.py

STAGES = ("ridge", "thin votes", "cells", "skins", "evidence", "tips")


def _rule(ev, opt, sensitivity, seeded):
    """The evidence rule that drops a skin (the order of ``FaultEvidence.supports``), or 'kept'."""
    if not (np.isfinite(ev.median_throw) and np.isfinite(ev.correlation_gain)):
        return "unmeasured"
    if not seeded:
        return "kept" if ev.is_clearly_displaced(opt, sensitivity) else "unseeded, not clear"
    if ev.is_unbroken(opt):
        if ev.is_flexure(opt):
            return "flexure"
        unbroken = opt.unbroken_correlation
        return "unbroken" if unbroken is not None and ev.correlation - ev.correlation_gain >= unbroken else "drag"
    if ev.is_clear_and_likely(opt, sensitivity):
        return "kept"
    if opt.min_vote_ratio > 0 and ev.vote_ratio < opt.min_vote_ratio:
        return "vote ratio"
    if opt.min_correlation is not None and not ev._sure(opt, sensitivity) and not ev.correlation >= opt.min_correlation:
        return "low correlation"
    if ev.shows_displacement(opt, sensitivity) or ev._reaches(opt.min_probability, sensitivity):
        return "kept"
    return "probability"


def traced_steps(section, opt):
    """Each step's faults or image on a section, in memory: the steps of ``trace_faults`` one at a time."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        cleaned = clean_traces(np.asarray(section, np.float32), options=opt.dead)
        arr = cleaned.data
        fl = learned_fault_likelihood(arr, options=opt.learned, progress=False)
    run = memory_surface_run(arr, fl.likelihood, fl.strike_deg, fl.dip_deg, opt)  # trace_faults' run in memory
    out = {}
    original = run.seeds

    def seeds():  # the ridges above the seed threshold: the seed candidates the ridges step listed
        points = run.run.gathered_lists("ridges", run.blocks("ridges"), ("points",))["points"]
        out["ridge"] = _mask(arr.shape, [points[:, [0, 2]]])
        return original()

    run.seeds = seeds
    original_cells = run.cells

    def cells(lower):  # the thinned votes, kept before the cells step zeroes those below the lower threshold
        out["thin votes"] = run.volume("thin_raw") > 0
        return original_cells(lower)

    run.cells = cells
    found = surface_cells(run, opt)
    lower, upper = found.thresholds
    likelihood = run.volume("likelihood")
    shape, cell_arrays = arr.shape, run.cells_found()
    points = np.asarray(cell_arrays[0])
    out["cells"] = _mask(shape, [points[:, [0, 2]]])
    faults = skins_from_cells(*cell_arrays, shape=shape, lower=lower, upper=upper, options=opt.skins)
    seeded = [True] * len(faults)
    if opt.evidence.unseeded_correlation_gain is not None and faults:  # faults_from_cells' second hysteresis
        shape3 = (shape[0], 1, shape[1])
        used = np.concatenate([np.insert(f.points, 1, 0, axis=1) for f in faults])
        free = ~np.isin(np.ravel_multi_index(tuple(points.T), shape3), np.ravel_multi_index(tuple(used.T), shape3))
        more = skins_from_cells(*(np.asarray(c)[free] for c in cell_arrays), shape=shape, lower=lower, upper=lower,
                                options=opt.skins) if free.any() else []
        faults += [dataclasses.replace(f, id=len(faults) + i + 1) for i, f in enumerate(more)]
        seeded += [False] * len(more)
    out["skins"] = _mask(shape, [f.points for f in faults])
    throws = fault_throws(arr, faults, progress=False) if faults else []
    throws = [dataclasses.replace(t, half_period=half_period(arr, f.points)) for f, t in zip(faults, throws)]
    kept, kept_throws, rules = [], [], []
    for f, t, by_seed in zip(faults, throws, seeded):
        ev = fault_evidence(t, vote_ratio=float(np.mean(f.likelihood)) / float(upper),
                            mean_likelihood=float(likelihood[tuple(f.points.T)].astype(np.float64).mean()))
        rule = _rule(ev, opt.evidence, opt.sensitivity, by_seed)
        rules.append((rule, f))
        if rule == "kept":
            kept.append(dataclasses.replace(f, id=len(kept) + 1))
            kept_throws.append(dataclasses.replace(t, fault_id=len(kept)))
    out["evidence"] = _mask(shape, [f.points for f in kept])
    final, _ = trimmed_tips(kept, kept_throws, likelihood, opt.tip_level_for(2))
    out["tips"] = _mask(shape, [f.points for f in final])
    return out, likelihood, rules, final


def _mask(shape, point_lists):
    m = np.zeros(shape, bool)
    for p in point_lists:
        if len(p):
            m[p[:, 0], p[:, 1]] = True
    return m


def _near(mask, tol=3.0):
    return distance_transform_edt(~mask) <= tol if mask.any() else np.zeros(mask.shape, bool)


def account(section, truth, opt, dev):
    """The line's scores and the step that lost each of the person's pixels the network saw."""
    out, likelihood, rules, final = traced_steps(section, opt)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        check = trace_faults(section, options=opt, progress=False)
    if not np.array_equal(_mask(truth.shape, [f.points for f in final]),
                          _mask(truth.shape, [f.points for f in check.faults])):
        raise SystemExit("the steps run here do not give trace_faults' faults: update this script")
    p, r, f1 = dev.tolerant_scores(out["tips"], truth, 3)
    seen = ndi.maximum_filter(likelihood.astype(np.float64), size=7) > 0.5
    missed = truth & ~_near(out["tips"])
    lost = missed & seen
    first = np.full(truth.shape, len(STAGES))
    for i in reversed(range(len(STAGES))):
        first[~_near(out[STAGES[i]])] = i
    row = {"P": p, "R": r, "F1": f1, "drawn": int(truth.sum()), "missed": int(missed.sum()), "lost": int(lost.sum())}
    row.update({name: int((lost & (first == i)).sum()) for i, name in enumerate(STAGES)})
    by_rule = {}
    for rule, fault in rules:
        if rule != "kept":
            n = int((lost & (first == STAGES.index("evidence")) & _near(_mask(truth.shape, [fault.points]))).sum())
            by_rule[rule] = by_rule.get(rule, 0) + n
    row["rules"] = {k: v for k, v in by_rule.items() if v}
    label, n = ndi.label(truth, structure=np.ones((3, 3)))
    found = ndi.mean(_near(out["tips"]), label, np.arange(1, n + 1)) if n else np.zeros(0)
    whole = np.isin(label, 1 + np.nonzero(found < 0.1)[0])  # the person's faults with under 0.1 of them found
    row.update(faults=n, whole=int((found < 0.1).sum()), whole_px=int(whole.sum()),
               whole_seen=int((whole & seen).sum()))
    ridge = lost & (first == 0)
    row["ridge_gap"] = float(np.median(distance_transform_edt(likelihood <= 0.5)[ridge])) if ridge.any() else 0.0
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=os.environ.get("SEISMO3D_DATA_DIR"))
    ap.add_argument("--sensitivity", type=float, default=0.5)
    a = ap.parse_args()
    if not a.data:
        sys.exit("set SEISMO3D_DATA_DIR or pass --data")
    dev = _dev_script(a.data)
    opt = FaultTracingOptions(sensitivity=a.sensitivity)
    head = f"{'line':19s} {'P':>5s} {'R':>5s} {'F1':>5s} {'drawn':>6s} {'missed':>6s} {'lost':>5s} " + " ".join(
        f"{s:>10s}" for s in STAGES)
    for survey, lines in (("F3", dev.f3_lines), ("GSB", dev.gsb_lines)):
        print(head)
        rows = []
        for label, section, truth, _ in lines(Path(a.data)):
            row = account(section, truth, opt, dev)
            rows.append(row)
            print(f"{label:19s} {row['P']:5.3f} {row['R']:5.3f} {row['F1']:5.3f} {row['drawn']:6d} {row['missed']:6d} "
                  f"{row['lost']:5d} " + " ".join(f"{row[s]:10d}" for s in STAGES))
        total = {k: sum(r[k] for r in rows) for k in ("drawn", "missed", "lost", *STAGES)}
        means = [np.mean([r[k] for r in rows]) for k in ("P", "R", "F1")]
        print(f"{survey + ' (sum; mean)':19s} {means[0]:5.3f} {means[1]:5.3f} {means[2]:5.3f} {total['drawn']:6d} "
              f"{total['missed']:6d} {total['lost']:5d} " + " ".join(f"{total[s]:10d}" for s in STAGES))
        rules = {}
        for r in rows:
            for k, v in r["rules"].items():
                rules[k] = rules.get(k, 0) + v
        whole = [sum(r[k] for r in rows) for k in ("faults", "whole", "whole_px", "whole_seen")]
        print(f"  the person's faults (8-connected) with under 0.1 of their pixels found: {whole[1]} of {whole[0]}, "
              f"{whole[2]} pixels ({whole[2] / total['drawn']:.2f} of the drawn), {whole[3]} of them seen (over 0.5)")
        gaps = ", ".join(f"{r['ridge_gap']:.1f}" for r in rows)
        print(f"  evidence rules: {rules}; ridge pixels' median distance to a likelihood over 0.5: {gaps}\n")


if __name__ == "__main__":
    main()
