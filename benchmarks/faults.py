"""Benchmark: fault tracing on real sections beside the published OSV faults and a plain semblance skeleton, on
generated cubes against their truth, and its speed and memory beside a plain semblance and bruges.

Three tables (each can be skipped):

1. **Real sections** (needs ``SEISMO3D_DATA_DIR``):

   - Costa Rica ``sections/costarica_crf.f32be`` against X. Wu's published optimal-surface-voting faults
     (``references/costarica_crf_osv_fvt.f32be`` > 0.3; a reference from another algorithm, not truth), tolerance 3
     samples (the definition of ``shared/tools/fault_scores.py``: ``seismo3d.seismic.evaluate_faults``):
     seismo3d's faults with the defaults; a plain 1-semblance skeleton (flat 3-trace x 9-sample semblance,
     thresholded, ``skimage.morphology.skeletonize``) at the threshold that gives it its best F1; Wu's own thinned
     fault likelihood (``references/costarica_crf_ft.f32be``, Hale's method without voting); evenly spaced vertical
     lines every 10 traces (a data-blind control: recall alone proves nothing).
   - Penobscot crossline 1155 (``penobscot_xl1155.sgy``): the large normal fault from inline 1385 at 900 ms to
     inline 1222 at 2550 ms; the largest fraction of its samples from 1000 to 2400 ms that one fault id holds within
     10 traces of that line (the issue's target: >= 70 %), for seismo3d and for the plain skeleton's connected
     components at the same threshold rule.
   - The 18 Penobscot inlines (``load_penobscot_sections``, 8-bit and clipped): how many faults span at least 10 of
     the 18 inlines, and the seconds.

2. **Generated cubes** (``--synthetic``): five 128^3 cubes (``synthetic_cube``, seeds 0-4, noise 0.1, three faults
   each): precision and recall of the fault skins against the true fault samples (tolerance 2), and the median
   error of the throw at skin points within 2 samples of a true fault (|measured - true| in samples, where the true
   throw is at least 3 samples; unmeasured points count as misses).

3. **Speed and memory** on generated 64^3, 128^3 and 256^3 cubes, each (method, size) in its own subprocess so that
   its peak memory is its own (numba kernels compiled on a small cube first; "peak MB" = increase of the peak
   resident set over the memory in use before the call, i.e. what the method needs on top of its input; "CPU s" =
   process CPU time of all threads, which barely moves when other jobs load the machine):

   - ``fault_likelihood`` (the scan over 24 strikes x 13 dips at half vertical resolution);
   - ``learned_likelihood``: the fault network on every inline and crossline section (numpy and numba), with strike
     and dip;
   - ``voting+skins``: ridges, optimal surface voting, thinning, thresholds and fault skins, from the likelihood;
   - ``trace_faults learned`` / ``trace_faults scan``: the whole interpretation of the array, throws included,
     with the learned likelihood (the default) or the scan;
   - ``faults command learned`` / ``faults command scan``: the whole ``seismo3d faults`` job (``run_faults_job``):
     read the .npy, trace, and write every output (volumes, VTK surfaces, CSVs, PNG), with ``--likelihood learned``
     (the default) or ``scan``;
   - peers: ``seismo3d.seismic.semblance`` (structure-oriented, 3 x 3 traces x 9 samples), a plain vectorised
     semblance written here with ``scipy.ndimage.uniform_filter`` (3 x 3 traces x 9 samples, flat windows; the
     cheapest discontinuity attribute one can write with numpy), and ``bruges.attribute.discontinuity`` (64^3 only:
     one call computes Marfurt semblance, Gersztenkorn eigen-coherence and the gradient structure tensor in Python
     loops over windows; ``pip install -e ".[bench]"``).

Tables of the learned likelihood: ``--only f3`` (the F3 inlines drawn by a person, both likelihoods, the skeleton,
FaultNet run in this process on each inline, ``benchmarks/faultnet.py``, without torch a line saying so, and the
cross-validated choice of likelihood and evidence), ``--only gsb`` (the two Great South
Basin crosslines with an interpreter's fault sticks, scored by the job of ``seismo3d evaluate``, beside the skeleton
and a second person's drawing), ``--only counts`` (fault counts of
both on every real section), ``--only checks`` (what an interpreter sees: teapot_tpd's three visible faults, no fault
through the Volve line's continuous reflectors at 2300-2500 ms, Penobscot xl1155's large fault as one fault),
``--only generated`` (generated sections and cubes never trained on, both).

Run: ``python benchmarks/faults.py`` (about 10 minutes on 2 cores); ``--sizes 64 128`` for a quicker speed table,
``--no-speed``, ``--no-real``, ``--synthetic`` to choose the tables, ``--no-bruges`` to skip bruges.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from seismo3d.data.interpretations import (TEAPOT_TPD_FAULTS, VOLVE_CONTINUOUS_MS, XL1155_FIRST_INLINE,
                                           XL1155_LINE, XL1155_MS, load_real_sections, opposite_dip_faults,
                                           xl1155_coverage)
from seismo3d.seismic.evaluation import evaluate_faults, plain_semblance, semblance_skeleton

from faultnet import NOT_RUN, faultnet_probability, load_faultnet  # benchmarks/faultnet.py: the peer

METHODS = ("fault_likelihood", "learned_likelihood", "voting+skins", "trace_faults scan", "trace_faults learned",
           "faults command scan", "faults command learned", "semblance", "plain_semblance", "bruges")
PEERS = {"plain_semblance", "bruges"}


# --------------------------------------------------------------------------------------------------------------------
# 1. real sections


def _f32be(data_dir: Path, name: str, shape) -> np.ndarray:
    return np.fromfile(data_dir / "seismic" / name, ">f4").reshape(shape).astype(np.float32)


def _scores(pred, ref, tol=3.0):
    """(precision, recall, F1) of a fault mask against a reference (:func:`seismo3d.seismic.evaluate_faults`)."""
    s = evaluate_faults(pred, ref, tolerance=tol)
    return s.precision, s.recall, s.f1


def _best_skeleton(section, reference):
    """The plain skeleton's threshold (a quantile of 1 - semblance, 1 to 99 %) of best F1, and its scores."""
    disc = 1.0 - plain_semblance(section)
    best = None
    for q in np.linspace(0.01, 0.99, 50):
        thr = float(np.quantile(disc, q))
        p, r, f = _scores(semblance_skeleton(section, thr), reference)
        if best is None or f > best[4]:
            best = (q, thr, p, r, f)
    return best


def real_sections(data_dir: Path, out_dir: Path) -> None:
    from scipy import ndimage as ndi

    from seismo3d.seismic import fault_labels, open_segy, trace_faults
    from seismo3d.seismic.faults import FaultTracingOptions

    section = _f32be(data_dir, "sections/costarica_crf.f32be", (500, 180))
    osv = _f32be(data_dir, "references/costarica_crf_osv_fvt.f32be", (500, 180)) > 0.3
    ft = _f32be(data_dir, "references/costarica_crf_ft.f32be", (500, 180)) > 0.3
    t = time.perf_counter()
    res = trace_faults(section, progress=False)
    seconds = time.perf_counter() - t
    ours = fault_labels(res.faults, section.shape) > 0
    rows = [("seismo3d faults (defaults)", *_scores(ours, osv), f"{len(res.faults)} faults, {seconds:.1f} s")]
    q, thr, p, r, f = _best_skeleton(section, osv)
    rows.append(("plain 1-semblance skeleton, best F1", p, r, f, f"threshold {thr:.3f} ({q:.0%} quantile)"))
    rows.append(("Wu's thinned likelihood (Hale, no voting)", *_scores(ft, osv), "the reference's own input"))
    lines = np.zeros(section.shape, bool)
    lines[::10] = True
    rows.append(("vertical lines every 10 traces (control)", *_scores(lines, osv), "data-blind"))
    print("\nCosta Rica crf (500 x 180) against the published OSV faults (fvt > 0.3), tolerance 3 samples\n")
    head = f"{'method':44s} {'precision':>9s} {'recall':>7s} {'F1':>6s}   note"
    print(head + "\n" + "-" * len(head))
    for name, p, r, f, note in rows:
        print(f"{name:44s} {p:9.3f} {r:7.3f} {f:6.3f}   {note}")
    # where the defaults fall short: the left half's dense small faults (reflectors dipping about 30 degrees), beside
    # the scan, whose voting is OSV's own kind of image
    scan = trace_faults(section, options=FaultTracingOptions(likelihood="scan"), progress=False)
    by_half = []
    for label, mask in (("defaults", ours), ("scan", fault_labels(scan.faults, section.shape) > 0)):
        for lo, hi in ((0, 250), (250, 500)):
            p, r, _ = _scores(mask[lo:hi], osv[lo:hi])
            by_half.append(f"{label} traces {lo}-{hi - 1} {p:.3f} / {r:.3f}")
    print("by half, precision / recall: " + "; ".join(by_half))

    with open_segy(data_dir / "seismic" / "penobscot_xl1155.sgy") as cube:
        line = cube.read()[:, 0, :]
        if cube.inlines[0] != XL1155_FIRST_INLINE or cube.samples[0] != 0 or cube.samples[1] != XL1155_MS:
            raise SystemExit("penobscot_xl1155.sgy's axes differ from XL1155_LINE's: update XL1155_FIRST_INLINE and "
                             "XL1155_MS")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # its muted corner is reported
        t = time.perf_counter()
        res = trace_faults(line, sample_interval=4.0, sample_unit="ms", progress=False)
        seconds = time.perf_counter() - t
    labels = fault_labels(res.faults, line.shape)
    main, whole = xl1155_coverage(labels), xl1155_coverage(labels, span=(900.0, 2550.0))
    cov, fid, cov_issue, fid_issue = main.one_fault, main.fault_id, whole.one_fault, whole.fault_id
    # the peer at the same relative threshold as its best crf F1: connected skeleton pieces as its "faults"
    skel = semblance_skeleton(line, float(np.quantile(1.0 - plain_semblance(line), q)))
    pieces, n_pieces = ndi.label(skel, structure=np.ones((3, 3)))
    peer = xl1155_coverage(pieces)
    cov_peer, piece = peer.one_fault, peer.fault_id
    cov_peer_issue = xl1155_coverage(pieces, span=(900.0, 2550.0)).one_fault
    share = float(np.count_nonzero(pieces == piece)) / max(int(np.count_nonzero(pieces)), 1)
    print("\nPenobscot crossline 1155: the large normal fault (inline 1385 at 900 ms to 1222 at 2550 ms), fraction of "
          "1000-2400 ms and of 900-2550 ms held by one fault within 10 traces of that line (targets >= 70 % and, "
          "issue 35, >= 80 %)\n")
    head = f"{'method':44s} {'1000-2400':>9s} {'900-2550':>9s} {'faults':>7s}   note"
    print(head + "\n" + "-" * len(head))
    print(f"{'seismo3d faults (defaults)':44s} {cov:9.0%} {cov_issue:9.0%} {len(res.faults):7d}   fault {fid} "
          f"({fid_issue} over 900-2550), {seconds:.1f} s")
    print(f"{'plain 1-semblance skeleton, crf threshold':44s} {cov_peer:9.0%} {cov_peer_issue:9.0%} {n_pieces:7d}   "
          f"connected pieces; the one on the fault holds {share:.0%} of the skeleton (a web, not a fault)")

    from seismo3d.data import load_penobscot_sections

    sections = load_penobscot_sections()
    cube = np.array(sections.cube)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # clipped amplitudes and the muted top are reported
        t = time.perf_counter()
        res = trace_faults(cube, progress=False)
        seconds = time.perf_counter() - t
    spans = [np.unique(f.points[:, 0]).size for f in res.faults]
    wide = sum(s >= 10 for s in spans)
    print(f"\nPenobscot inlines 1075-1092 ({cube.shape[0]} x {cube.shape[1]} x {cube.shape[2]}, 8-bit, clipped): "
          f"{len(res.faults)} faults, {wide} of them spanning >= 10 of the {cube.shape[0]} inlines, largest "
          f"{max((f.size for f in res.faults), default=0)} samples; {seconds:.0f} s")
    from seismo3d.viz import plot_fault_slices

    out_dir.mkdir(parents=True, exist_ok=True)
    png = plot_fault_slices(cube, res.faults, path=out_dir / "penobscot_inlines_faults.png",
                            axes=(np.asarray(sections.section_ids), np.arange(cube.shape[1]), np.arange(cube.shape[2])),
                            axis_labels=("inline", "trace", "sample"),
                            title="Penobscot inlines 1075-1092: faults by id (seismo3d faults defaults)")
    print(f"picture: {png}")


LIKELIHOODS = ("learned", "scan")
# the learned likelihood's network grids (LearnedOptions.resample) tried by the cross-validation on the F3 inlines:
# one grid each, and the means of several (the default among them)
RESAMPLE_GRID = ((1.0,), (0.85,), (0.7,), (0.6,), (0.5,), (0.5, 0.7, 1.0), (0.6, 0.7, 0.85, 1.0),
                 (0.5, 0.6, 0.7, 0.85, 1.0))
# the evidence options tried by the cross-validation (EvidenceOptions: min_throw samples, min_correlation_gain,
# min_vote_ratio, min_probability (None: the unshifted mismatch of the sides as evidence, the scan's rule),
# clear_throw (None: no throw clear enough to stand without the vote ratio on a likely fault))
EVIDENCE_FIELDS = ("min_throw", "min_correlation_gain", "min_vote_ratio", "min_probability", "clear_throw")
EVIDENCE_GRID = [(t, g, v, p, c) for t in (1.0, 1.5) for g in (0.0, 0.1) for v in (0.0, 0.75, 0.9, 1.0, 1.1)
                 for p in (0.5, 0.6, 0.7, None) for c in (None, 2.0, 3.0, 4.0)]
# (min_correlation and sure_probability at their defaults)
# every candidate: each measured fault, nothing asked
EVERY = dict(min_throw=0.0, min_correlation_gain=-1.0, min_vote_ratio=0.0, min_probability=None, clear_throw=None,
             min_correlation=None)
# the defaults before issue 35's rules (stop 49): one network grid of 0.7, a displacement or sides not matching
# unshifted, no vote ratio
BEFORE = dict(resample=0.7, evidence=dict(min_vote_ratio=0.0, min_probability=None, clear_throw=None,
                                          min_correlation=None))


def _kept_mask(faults, evidence, shape, options=None):
    """The samples of the faults whose evidence ``options`` accept (all of them for None)."""
    mask = np.zeros(shape, bool)
    for fault, e in zip(faults, evidence):
        if options is None or e.supports(options):
            mask[tuple(fault.points.T)] = True
    return mask


def _candidates(section, likelihood="scan", resample=None, **unit):
    """Every measured candidate of the whole pipeline before the evidence is asked, their evidence (throw, vote
    ratio, mean likelihood), and the seconds of the run. ``resample``: the learned likelihood's network grids
    (default: LearnedOptions's)."""
    from seismo3d.seismic import trace_faults
    from seismo3d.seismic.faults import EvidenceOptions, FaultTracingOptions, LearnedOptions

    learned = LearnedOptions() if resample is None else LearnedOptions(resample=resample)
    every = FaultTracingOptions(likelihood=likelihood, learned=learned, evidence=EvidenceOptions(**EVERY))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # muted tops and clipped amplitudes are reported
        t = time.perf_counter()
        res = trace_faults(section, progress=False, options=every, **unit)
        seconds = time.perf_counter() - t
    return res.faults, res.evidence, seconds


def _defaults_run(section, **unit) -> tuple:
    """The fault mask and the number of faults of :func:`trace_faults` with the default options."""
    from seismo3d.seismic import fault_labels, trace_faults

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # muted tops and clipped amplitudes are reported
        res = trace_faults(section, progress=False, **unit)
    return fault_labels(res.faults, section.shape) > 0, len(res.faults)


def _grid_name(resample) -> str:
    return "learned@" + "+".join(f"{f:g}" for f in resample)


def f3_people() -> None:
    """The five F3 inlines with faults drawn by a person: scores per inline of the defaults (learned), the scan's
    defaults, the defaults before issue 35, the plain skeleton at its single best threshold; each network grid with
    the default evidence; and the cross-validation of the grids and the evidence options (chosen on three inlines,
    scored on the other two, every split)."""
    import itertools

    from seismo3d.data import load_f3_fault_sections
    from seismo3d.seismic.faults import EvidenceOptions, LearnedOptions

    data = load_f3_fault_sections()
    n = len(data.inlines)
    unit = dict(sample_interval=4.0, sample_unit="ms")
    candidates, seconds = {}, {}
    for name, lk, resample in [("scan", "scan", None)] + [(_grid_name(r), "learned", r) for r in RESAMPLE_GRID]:
        runs = [_candidates(data.sections[k], lk, resample, **unit) for k in range(n)]
        candidates[name] = [(f, e) for f, e, _ in runs]
        seconds[name] = float(np.mean([sec for _, _, sec in runs]))
    default_grid = _grid_name(LearnedOptions().resample)
    before_grid = _grid_name(LearnedOptions(resample=BEFORE["resample"]).resample)
    shown = {"defaults (learned)": (default_grid, EvidenceOptions()),
             "scan defaults": ("scan", EvidenceOptions.for_likelihood("scan")),
             "before (stop 49)": (before_grid, EvidenceOptions(**BEFORE["evidence"]))}

    cache: dict = {}  # (candidates, inline, the ids kept) -> scores: most choices keep the same faults

    def score(name, opt):
        out = []
        for k in range(n):
            faults, evidence = candidates[name][k]
            kept = tuple(e.supports(opt) for e in evidence)
            key = (name, k, kept)
            if key not in cache:
                cache[key] = _scores(_kept_mask(faults, evidence, data.sections[k].shape, opt), data.faults[k])
            out.append(cache[key])
        return out

    ours = {label: score(*v) for label, v in shown.items()}
    counts = {label: [sum(e.supports(v[1]) for e in candidates[v[0]][k][1]) for k in range(n)]
              for label, v in shown.items()}
    # the defaults as the command runs them: the filter of the candidates above approximates a run (each fault's throw
    # reads its sides beyond every strand traced beside it, and the kept faults' tips are trimmed), so the defaults'
    # row is the pipeline itself (the scores of the slow test and of tools/dev_fault_scores.py)
    runs = [_defaults_run(data.sections[k], **unit) for k in range(n)]
    ours["defaults (learned)"] = [_scores(mask, data.faults[k]) for k, (mask, _) in enumerate(runs)]
    counts["defaults (learned)"] = [count for _, count in runs]
    best = None  # the peer: one quantile of 1 - plain semblance for all five inlines, the best mean F1
    for q in np.concatenate([np.linspace(0.50, 0.98, 25), [0.985, 0.99, 0.993, 0.996, 0.998]]):
        sk = [_scores(semblance_skeleton(data.sections[k], float(np.quantile(
            1.0 - plain_semblance(data.sections[k]), q))), data.faults[k]) for k in range(n)]
        if best is None or np.mean([s[2] for s in sk]) > np.mean([s[2] for s in best[1]]):
            best = (q, sk)
    faultnet = _faultnet_f3(data)  # FaultNet's released weights in this process; None without torch
    fmt = lambda s: f"{s[0]:5.3f} / {s[1]:5.3f} / {s[2]:5.3f}"  # noqa: E731
    mean = lambda scores: tuple(float(np.mean([s[i] for s in scores])) for i in range(3))  # noqa: E731
    print("\nF3 inlines with faults drawn by a person (951 x 462 each), tolerance 3 samples: precision / recall / F1 "
          "and fault count; FaultNet (Dou et al. 2022, its released weights run here: probability > 0.5, "
          "skeletonised)\n")
    fn_cell = lambda k: f" | {fmt(faultnet[k]) if faultnet else 'not run':>21s}"  # noqa: E731
    head = (f"{'inline':>6s} | " + " | ".join(f"{label:>28s}" for label in shown)
            + f" | {'1-semblance skeleton':>21s} | {'FaultNet':>21s}")
    print(head + "\n" + "-" * len(head))
    for k in range(n):
        print(f"{data.inlines[k]:6d} | " + " | ".join(f"{fmt(ours[label][k])} {counts[label][k]:4d}" for label in shown)
              + f" | {fmt(best[1][k]):>21s}" + fn_cell(k))
    print(f"{'mean':>6s} | " + " | ".join(f"{fmt(mean(ours[label]))}     " for label in shown)
          + f" | {fmt(mean(best[1])):>21s} | {fmt(mean(faultnet)) if faultnet else 'not run':>21s}")
    if not faultnet:
        print(NOT_RUN)
    beaten = all(ours["defaults (learned)"][k][2] > max(best[1][k][2], faultnet[k][2] if faultnet else 0.0)
                 for k in range(n))
    print(f"defaults: network grids {LearnedOptions().resample}, {EvidenceOptions()}; F1 above both peers on every "
          f"inline: {'yes' if beaten else 'NO'}; skeleton threshold: the {best[0]:.1%} quantile of 1 - semblance on "
          "every inline")
    print("\nEach likelihood with its default evidence: mean precision / recall / F1 over the five inlines, F1 per "
          "inline, seconds per inline (the pipeline without the evidence; the scores from filtering its candidates, "
          "which approximates a run with those options)")
    for name in candidates:
        sc = score(name, EvidenceOptions.for_likelihood("scan" if name == "scan" else "learned"))
        print(f"  {name:28s} {fmt(mean(sc))}   F1 " + " ".join(f"{x[2]:.3f}" for x in sc) + f"   {seconds[name]:.1f} s")
    # the cross-validation: every (likelihood, evidence) choice's scores on every inline
    grid = {(name, e): EvidenceOptions(**dict(zip(EVIDENCE_FIELDS, e))) for name in candidates for e in EVIDENCE_GRID}
    grid_scores = {key: score(key[0], opt) for key, opt in grid.items()}
    print(f"\nCross-validation of the likelihood (the scan, or the network on each set of grids) and the evidence "
          f"({', '.join(EVIDENCE_FIELDS)}), {len(grid)} choices: chosen by mean "
          "F1 on three inlines, scored on the other two; beside them the defaults on the same two\n")
    head = (f"{'chosen on':>12s} {'held out':>9s} {'choice':>52s} {'held-out P / R / F1':>21s} "
            f"{'defaults P / R / F1':>21s}")
    print(head + "\n" + "-" * len(head))
    held, held_default = [], []
    names = lambda ks: ",".join(str(data.inlines[k]) for k in ks)  # noqa: E731
    for train in itertools.combinations(range(n), 3):
        test = [k for k in range(n) if k not in train]
        choice = max(grid, key=lambda g: np.mean([grid_scores[g][k][2] for k in train]))
        held.append(mean([grid_scores[choice][k] for k in test]))
        held_default.append(mean([ours["defaults (learned)"][k] for k in test]))
        print(f"{names(train):>12s} {names(test):>9s} {str(choice[0]) + ' ' + str(choice[1]):>52s} "
              f"{fmt(held[-1]):>21s} {fmt(held_default[-1]):>21s}")
    print(f"{'mean':>12s} {'':>9s} {'':>52s} {fmt(mean(held)):>21s} {fmt(mean(held_default)):>21s}")
    on_all = max(grid, key=lambda g: np.mean([grid_scores[g][k][2] for k in range(n)]))
    print(f"chosen on all five inlines: {on_all[0]} {on_all[1]}, {fmt(mean(grid_scores[on_all]))}")


def _faultnet_f3(data) -> list | None:
    """(precision, recall, F1) on each F3 inline of FaultNet's probability above 0.5 skeletonised (as
    ``faults_3d.py`` judges it), its released weights run on each section (``benchmarks/faultnet.py``); None without
    torch."""
    from skimage.morphology import skeletonize

    net = load_faultnet()
    if net is None:
        return None
    return [_scores(skeletonize(faultnet_probability(net, section) > 0.5), truth)
            for section, truth in zip(data.sections, data.faults)]


def gsb_people(data_dir: Path) -> None:
    """The two Great South Basin crosslines with an interpreter's fault sticks: ``seismo3d faults`` with the defaults
    (the job of the command), scored by the job of ``seismo3d evaluate`` (``run_evaluate_job``: the computation a
    user runs, and that of ``dev_fault_scores.py``), beside the plain 1-semblance skeleton at its single best quantile
    for both lines and, on crossline 2800, a second person's drawing of the same faults."""
    import warnings as _warnings

    from seismo3d.jobs.evaluate import run_evaluate_job
    from seismo3d.jobs.faults import run_faults_job
    from seismo3d.seismic.fault_scoring import tolerant_scores

    folder = data_dir / "seismic" / "gsb_fault_sticks"
    lines, jobs = (2600, 2800), {}
    with tempfile.TemporaryDirectory() as tmp:
        for line in lines:
            out = Path(tmp) / f"faults_{line}"
            with _warnings.catch_warnings():
                _warnings.simplefilter("ignore")
                run_faults_job(folder / f"gsb_crl_{line}.sgy", out, progress=False)
            jobs[line] = run_evaluate_job(out, sticks=folder / f"gsb_crl_{line}_faults_opendtect.dat",
                                          out=Path(tmp) / f"evaluation_{line}", picture=False)
        second = run_evaluate_job(Path(tmp) / "faults_2800", mask=folder / "gsb_crl_2800_second_mask.png",
                                  out=Path(tmp) / "evaluation_2800_second", picture=False)
    best = None  # the peer: one quantile of 1 - plain semblance for both lines, the best mean F1
    for q in np.concatenate([np.linspace(0.50, 0.98, 25), [0.985, 0.99, 0.993, 0.996, 0.998]]):
        sk = [tolerant_scores(semblance_skeleton(jobs[n].line.section, float(np.quantile(
            1.0 - plain_semblance(jobs[n].line.section), q))), jobs[n].people.mask()) for n in lines]
        if best is None or np.mean([x[2] for x in sk]) > np.mean([x[2] for x in best[1]]):
            best = (q, sk)
    fmt = lambda s: f"{s[0]:5.3f} / {s[1]:5.3f} / {s[2]:5.3f}"  # noqa: E731
    print("\nGreat South Basin crosslines with an interpreter's fault sticks (484 traces x 76 samples each), tolerance "
          "3 samples: precision / recall / F1 (seismo3d evaluate), the faults' average precision over their "
          "confidence (mean_likelihood), and the peer\n")
    head = (f"{'crossline':>9s} | {'seismo3d defaults':>21s} {'faults':>6s} {'AP':>5s} | "
            f"{'1-semblance skeleton':>21s} | {'a second person':>21s}")
    print(head + "\n" + "-" * len(head))
    for n, sk in zip(lines, best[1]):
        s = jobs[n].scores
        other = second.people.mask() if n == 2800 else None
        person = fmt(tolerant_scores(other, jobs[n].people.mask())) if other is not None else ""
        print(f"{n:9d} | {fmt((s.precision, s.recall, s.f1))} {len(s.traced):6d} {s.curve.average_precision:5.3f} | "
              f"{fmt(sk)} | {person:>21s}")
    mean = [float(np.mean([getattr(jobs[n].scores, k) for n in lines])) for k in ("precision", "recall", "f1")]
    print(f"{'mean':>9s} | {fmt(mean)} {'':6s} {'':5s} | {fmt(np.mean(best[1], axis=0))} |")
    print(f"skeleton threshold: the {best[0]:.1%} quantile of 1 - semblance on both lines; a second person: the "
          "data folder's gsb_crl_2800_second_mask.png scored as if traced, against the sticks")


def real_section_counts(data_dir: Path) -> None:
    """Fault counts on every real 2D section of the data folder: the defaults now and before issue 35's rules (stop
    49: one network grid of 0.7, no vote ratio, the unshifted mismatch as evidence), the scan's defaults, and the
    candidates (nothing asked)."""
    from seismo3d.seismic.faults import EvidenceOptions

    print("\nFaults on every real section of the data folder: the defaults (a run of the pipeline), the defaults "
          "before issue 35's rules, the scan's defaults (both the candidates' filter); candidates: every measured "
          "fault of each run, nothing asked\n")
    runs = {"defaults": ("learned", None, EvidenceOptions()),
            "before": ("learned", BEFORE["resample"], EvidenceOptions(**BEFORE["evidence"])),
            "scan": ("scan", None, EvidenceOptions.for_likelihood("scan"))}
    head = f"{'section':30s} {'shape':>10s}" + "".join(f" | {name:>8s} {'of':>4s} {'s':>5s}" for name in runs)
    print(head + "\n" + "-" * len(head))
    for name, (arr, dt) in load_real_sections().items():
        row = f"{name:30s} {'x'.join(map(str, arr.shape)):>10s}"
        unit = {"sample_interval": dt, "sample_unit": "ms"} if dt else {}
        for label, (lk, resample, opt) in runs.items():
            faults, evidence, seconds = _candidates(arr, lk, resample, **unit)
            # the defaults as the command runs them (the candidates' filter approximates a run: f3_people)
            kept = _defaults_run(arr, **unit)[1] if label == "defaults" else sum(e.supports(opt) for e in evidence)
            row += f" | {kept:8d} {len(faults):4d} {seconds:5.1f}"
        print(row)


# --------------------------------------------------------------------------------------------------------------------
# 2. generated cubes


def interpreter_checks(data_dir: Path) -> None:
    """The defaults on the real sections against what an interpreter sees (issue 35): the three visible faults of
    teapot_tpd (the fraction of each line's samples with a fault within 8 traces, and the one fault holding most),
    faults crossing the Volve line's continuous reflectors at 2300-2500 ms, and Penobscot xl1155's large fault (one
    fault id along 900-2550 ms within 10 traces, faults of the opposite dip within 20 traces along 900-1700 ms)."""
    from seismo3d.seismic import fault_labels, fault_line_coverage, trace_faults

    sections = load_real_sections()
    runs = {}
    for name in ("teapot_tpd", "volve_fullstack_twt_arbline", "penobscot_xl1155"):
        arr, dt = sections[name]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            runs[name] = trace_faults(arr, progress=False,
                                      **({"sample_interval": dt, "sample_unit": "ms"} if dt else {}))
    print("\nWhat an interpreter sees, with the defaults\n")
    res = runs["teapot_tpd"]
    labels = fault_labels(res.faults, sections["teapot_tpd"][0].shape)
    print(f"teapot_tpd: {len(res.faults)} faults (target <= 8); its three visible faults, within 8 traces:")
    for name, line in TEAPOT_TPD_FAULTS.items():
        c = fault_line_coverage(labels, line, tolerance=8)
        print(f"  {name:38s} covered {c.covered:4.0%}, fault {c.fault_id} holds {c.one_fault:4.0%} "
              f"({c.n_faults} faults near it){'' if c.covered >= 0.5 else '  NOT TRACED (< 50 %)'}")
    res = runs["volve_fullstack_twt_arbline"]
    k0, k1 = (int(round(t / 4.0)) - 1 for t in VOLVE_CONTINUOUS_MS)  # samples at 4, 8, ... 3400 ms
    crossing = [f.id for f in res.faults if np.any((f.points[:, -1] >= k0) & (f.points[:, -1] <= k1))]
    print(f"volve_fullstack_twt_arbline: {len(res.faults)} faults; crossing {VOLVE_CONTINUOUS_MS[0]:g}-"
          f"{VOLVE_CONTINUOUS_MS[1]:g} ms: {crossing or 'none'}")
    res = runs["penobscot_xl1155"]
    c = xl1155_coverage(fault_labels(res.faults, sections["penobscot_xl1155"][0].shape), span=(900.0, 2550.0))
    print(f"penobscot_xl1155: {len(res.faults)} faults; the large fault: fault {c.fault_id} holds {c.one_fault:.0%} "
          f"of 900-2550 ms (target >= 80 %), {c.covered:.0%} covered by {c.n_faults} faults")
    print(f"  faults of the opposite dip along its upper part (900-1700 ms): {opposite_dip_faults(res.faults, XL1155_LINE)}")


def generated_sections(n: int = 20) -> None:
    """Generated sections the training never saw (seeds from 31,000,000): the learned and the scanned
    likelihood's faults against the labels on faulted ones, and the faults on unfaulted cubes with real-data
    degradations (a chaotic blob, coherent noise, 8-bit clipping)."""
    from seismo3d.data.degradations import add_noise, chaotic_interval, clip_and_quantise
    from seismo3d.data.synthetic import synthetic_cube
    from seismo3d.data.synthetic_sections import synthetic_fault_section
    from seismo3d.seismic import evaluate_faults, fault_labels, trace_faults
    from seismo3d.seismic.faults import FaultTracingOptions

    print(f"\nGenerated 256 x 256 sections never trained on ({n} seeds from 31,000,000, the training recipe's "
          "degradations): faults against the labels (tolerance 2 samples), summed over the faulted sections; "
          "faults found on the unfaulted ones\n")
    head = f"{'likelihood':>10s} {'precision':>9s} {'recall':>7s} {'faulted':>8s} {'unfaulted':>9s} {'their faults':>12s}"
    print(head + "\n" + "-" * len(head))
    sections = [synthetic_fault_section((256, 256), seed=31_000_000 + i) for i in range(n)]
    rng = np.random.default_rng(5)
    unfaulted = []
    for seed in range(5):  # unfaulted cubes (as sections) with the degradations of real data
        x = synthetic_cube((256, 256), n_faults=0, seed=100 + seed, noise=0.0, max_dip=25.0).cube
        x = add_noise(chaotic_interval(x, rng, strength=1.0, blob=True), rng, white=0.2, coherent=0.4)
        unfaulted.append(clip_and_quantise(x, rng, clip_percentile=98.0))
    for lk in LIKELIHOODS:
        opt = FaultTracingOptions(likelihood=lk)
        hits_p = hits_r = n_p = n_r = 0.0
        faulted, empty_faults = 0, []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for sec in sections:
                res = trace_faults(sec.section, options=opt, progress=False)
                if not sec.faults.any():
                    empty_faults.append(len(res.faults))
                    continue
                faulted += 1
                pred = fault_labels(res.faults, sec.section.shape) > 0
                sc = evaluate_faults(pred, sec.faults, tolerance=2)
                hits_p += sc.precision * pred.sum()
                n_p += pred.sum()
                hits_r += sc.recall * sec.faults.sum()
                n_r += sec.faults.sum()
            empty_faults += [len(trace_faults(x, options=opt, progress=False).faults) for x in unfaulted]
        print(f"{lk:>10s} {hits_p / max(n_p, 1):9.3f} {hits_r / max(n_r, 1):7.3f} {faulted:8d} "
              f"{len(empty_faults):9d} {str(empty_faults):>12s}")


def synthetic_accuracy(seeds=(0, 1, 2, 3, 4), likelihood: str = "scan") -> None:
    from scipy import ndimage as ndi

    from seismo3d.data.synthetic import synthetic_cube
    from seismo3d.seismic import evaluate_faults, fault_labels, trace_faults
    from seismo3d.seismic.faults import FaultTracingOptions

    print(f"\nGenerated 128^3 cubes (noise 0.1, 3 faults), {likelihood} likelihood: fault skins against the true fault "
          "samples (tolerance 2), throw at the true faults\n")
    head = f"{'seed':>4s} {'precision':>9s} {'recall':>7s} {'faults':>7s} {'median |throw error|':>21s} {'seconds':>8s}"
    print(head + "\n" + "-" * len(head))
    for seed in seeds:
        syn = synthetic_cube((128, 128, 128), seed=seed, noise=0.1)
        t = time.perf_counter()
        res = trace_faults(syn.cube, options=FaultTracingOptions(likelihood=likelihood), progress=False)
        seconds = time.perf_counter() - t
        s = evaluate_faults(fault_labels(res.faults, syn.cube.shape) > 0, syn.fault_labels, tolerance=2)
        # throw error at skin points within 2 samples of a true fault, against the true throw at the nearest fault
        # voxel (+ = hanging wall down); points with a true throw of at least 3 samples, as tests/seismic/test_throw
        dist, nearest = ndi.distance_transform_edt(syn.fault_labels == 0, return_indices=True)
        sign = {plane.id: 1.0 if plane.kind == "normal" else -1.0 for plane in syn.faults}
        errors = []
        for f, th in zip(res.faults, res.throws):
            idx = tuple(f.points.T)
            near = tuple(nearest[(slice(None),) + idx])
            true_id = syn.fault_labels[near]
            ok = (dist[idx] <= 2) & (true_id > 0)
            truth = syn.fault_throw[near] * np.array([sign.get(int(i), 0.0) for i in true_id])
            ok &= np.abs(truth) >= 3.0
            err = np.abs(th.throw.astype(np.float64) - truth)[ok]
            errors.append(np.where(np.isfinite(err), err, np.inf))  # unmeasured points count as misses
        err = float(np.median(np.concatenate(errors))) if errors else float("nan")
        print(f"{seed:4d} {s.precision:9.3f} {s.recall:7.3f} {len(res.faults):7d} {err:21.2f} {seconds:8.1f}")


# --------------------------------------------------------------------------------------------------------------------
# 3. speed and memory


def _rss_mb() -> float:
    """Current resident set size in MB (Linux /proc)."""
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def _worker(method: str, path: str) -> dict:
    from seismo3d import seismic
    from seismo3d.seismic import attributes

    cube = np.load(path)

    def prepare(c):
        """Inputs of the measured call (for voting+skins, the likelihood is computed beforehand)."""
        return seismic.fault_likelihood(c) if method == "voting+skins" else c

    def call(x):
        if method == "fault_likelihood":
            return seismic.fault_likelihood(x)
        if method == "learned_likelihood":
            return seismic.learned_fault_likelihood(x)
        if method.startswith("trace_faults"):
            likelihood = method.split()[-1]
            return seismic.trace_faults(x, progress=False, options=seismic.FaultTracingOptions(likelihood=likelihood))
        if method == "voting+skins":
            opt = seismic.FaultTracingOptions()
            ridges = seismic.thin_faults(x.likelihood, x.strike_deg, x.dip_deg, threshold=0.0)
            votes = seismic.vote_faults(x.likelihood, x.strike_deg, x.dip_deg, ridges)
            thin = seismic.thin_faults(votes.votes, votes.strike_deg, votes.dip_deg, threshold=0.0, sigma=0.0,
                                       dip_smoothing=0)
            lower, upper = opt.thresholds(thin)
            thin[thin < lower] = 0.0
            return seismic.fault_skins(thin, votes.strike_deg, votes.dip_deg, lower=lower, upper=upper)
        if method.startswith("faults command"):
            from seismo3d.jobs.faults import run_faults_job

            with tempfile.TemporaryDirectory() as out:
                return run_faults_job(x, out, progress=False,
                                      likelihood="learned" if method.endswith("learned") else "scan")
        if method == "semblance":
            return attributes.semblance(x)
        if method == "plain_semblance":
            return plain_semblance(x)
        if method == "bruges":
            from bruges.attribute import discontinuity

            return discontinuity(x, 9, 1)  # 9-sample windows, dt = 1 sample; computes all 3 methods
        raise ValueError(method)

    warnings.simplefilter("ignore")
    if method.startswith("faults command"):
        small = Path(tempfile.mkdtemp()) / "warmup.npy"
        np.save(small, np.ascontiguousarray(cube[:40, :40, :64]))
        call(small)  # compile numba kernels outside the measurement
        x = path  # the job reads its input file itself
    else:
        if method != "bruges":
            call(prepare(np.ascontiguousarray(cube[:40, :40, :64])))  # compile numba kernels outside the measurement
        x = prepare(cube)
    rss_before = _rss_mb()
    peak_before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    t_wall, t_cpu = time.perf_counter(), time.process_time()
    call(x)
    wall, cpu = time.perf_counter() - t_wall, time.process_time() - t_cpu
    peak_after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    # the increase of the peak resident set over the memory in use before the call (NaN: no new peak was reached,
    # the call needed less than the earlier peak of loading and warm-up)
    extra = peak_after - rss_before if peak_after > peak_before else float("nan")
    return {"wall": wall, "cpu": cpu, "peak_mb": extra}


def speed(sizes, no_bruges: bool) -> None:
    from seismo3d.data.synthetic import synthetic_cube

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            cube = synthetic_cube((n, n, n), seed=0).cube
            path = Path(tmp) / f"cube{n}.npy"
            np.save(path, cube)
            del cube
            for method in METHODS:
                if method == "bruges" and (n != 64 or no_bruges):
                    continue
                proc = subprocess.run([sys.executable, __file__, "--worker", method, str(path)],
                                      capture_output=True, text=True, check=False)
                if proc.returncode != 0:
                    print(f"{method} {n}^3 failed:\n{proc.stderr[-2000:]}", file=sys.stderr)
                    continue
                res = json.loads(proc.stdout.strip().splitlines()[-1])
                rows.append((method, n, res))
                print(f"  {method:17s} {n:4d}^3  {res['wall']:8.2f} s", file=sys.stderr, flush=True)

    load = os.getloadavg()[0]
    print(f"\nFault tracing speed and memory ({os.cpu_count()} CPUs, load average {load:.1f}, "
          f"numba threads {os.environ.get('NUMBA_NUM_THREADS', 'default')})\n")
    head = f"{'method':22s} {'cube':>6s} {'wall s':>9s} {'CPU s':>9s} {'ns/sample':>10s} {'peak MB':>9s}"
    print(head + "\n" + "-" * len(head))
    for method, n, res in rows:
        name = method + (" (peer)" if method in PEERS else "")
        print(f"{name:22s} {n:>4d}^3 {res['wall']:9.2f} {res['cpu']:9.2f} {1e9 * res['wall'] / n**3:10.0f} "
              f"{res['peak_mb']:9.0f}")
    print("\nvoting+skins: from the likelihood (computed beforehand) to the fault skins. peak MB: increase of the peak "
          "resident memory over the memory in use before the call (the input cube, float32: 1, 8 and 64 MB, is not "
          "counted). The issue's speed target: the whole command at 256^3 in <= 60 s on 2 cores.")
    print("bruges.attribute.discontinuity computes its three methods (marfurt, gersztenkorn, gst) in every call.")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256])
    ap.add_argument("--no-bruges", action="store_true", help="skip bruges.attribute.discontinuity")
    ap.add_argument("--no-speed", action="store_true", help="skip the speed and memory table")
    ap.add_argument("--no-real", action="store_true", help="skip the real sections")
    ap.add_argument("--only", choices=("f3", "gsb", "counts", "checks", "generated"),
                    help="only the F3 inlines drawn by a person, the GSB lines with an interpreter's sticks, the fault "
                    "counts on every real section, what an interpreter sees on teapot_tpd, Volve and xl1155, or the "
                    "generated sections and cubes")
    ap.add_argument("--synthetic", action="store_true", help="also the accuracy on five generated cubes")
    ap.add_argument("--out", default="out/benchmarks", help="folder of the pictures (default: out/benchmarks)")
    ap.add_argument("--worker", nargs=2, metavar=("METHOD", "NPY"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        print(json.dumps(_worker(*args.worker)))
        return
    root = os.environ.get("SEISMO3D_DATA_DIR")
    if args.only == "generated":
        generated_sections()
        for likelihood in LIKELIHOODS:
            synthetic_accuracy(likelihood=likelihood)
        return
    if args.only:
        if not root:
            sys.exit("set SEISMO3D_DATA_DIR to the data folder")
        {"f3": f3_people, "gsb": lambda: gsb_people(Path(root)), "counts": lambda: real_section_counts(Path(root)),
         "checks": lambda: interpreter_checks(Path(root))}[args.only]()
        return
    if not args.no_real:
        if root:
            f3_people()
            gsb_people(Path(root))
            real_section_counts(Path(root))
            interpreter_checks(Path(root))
            real_sections(Path(root), Path(args.out))
        else:
            print("real sections skipped: set SEISMO3D_DATA_DIR to the data folder", file=sys.stderr)
    if args.synthetic:
        generated_sections()
        for likelihood in LIKELIHOODS:
            synthetic_accuracy(likelihood=likelihood)
    if not args.no_speed:
        speed(args.sizes, args.no_bruges)


if __name__ == "__main__":
    main()
