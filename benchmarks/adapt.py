"""``seismo3d adapt`` on the lines people drew: the fault network adapted on one line, the others traced with the
adapted MODEL, each beside the shipped network on the same lines; and the time ``adapt`` takes.

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/adapt.py [--only f3|gsb] [--check] [--variants ...]``

``--variants all scale_shift_head:learning_rate=0.03`` adapts with each of several :class:`AdaptOptions
<seismo3d.training.adapt_options.AdaptOptions>` (``LAYERS[:NAME=VALUE,...]``; ``all`` is adapt's default, the one
``--check`` judges) on the same folds, each row beside the shipped network traced once in the same run.

- **F3** (``seismic/f3_fault_masks/``, the lines built as ``tools/dev_fault_scores.py`` builds them: each inline's
  picture resampled bilinearly onto 951 crosslines x 462 samples, centred (value - 128), written as a SEG-Y line at
  4 ms; the person's faults the mask's alpha > 0, given to ``adapt`` as a ``.npy`` mask): adapted on inline 100, the
  inlines 200-500 traced; adapted on inline 500, the inlines 100-400 traced. ``--check``: in both folds the mean F1
  >= 0.62 and the mean precision >= 0.60 (issue 74).
- **Great South Basin** (``seismic/gsb_fault_sticks/``, the SEG-Y lines and the interpreter's OpendTect sticks):
  adapted on crossline 2600's sticks, crossline 2800 traced, and the other way; then adapted on both (the crossline
  with fewer picks held back whole). ``--check``: above the shipped network on both folds, and the two-line adapt
  within 2 cores x 300 s of CPU time (issue 74's 5 minutes on 2 cores; its wall time on this shared machine is
  printed beside the load average).

Only the per-channel scales and shifts (``scale_shift``, ``scale_shift_head``: every convolution frozen; 2026-11-28,
the shared 2-core machine; mean precision / recall / F1 of the lines traced with MODEL, tolerance 3 samples; the
learning rate chosen on F3 fold 100, the other folds reported as they came):

=======================================  =====================  =====================  ======================
variant                                  F3 100 -> 200-500      F3 500 -> 100-400      GSB 2600 / 2800 bands
=======================================  =====================  =====================  ======================
shipped network                          0.631 / 0.419 / 0.497  0.599 / 0.418 / 0.489  F1 0.888 / 0.910
``all`` (adapt's default)                0.660 / 0.498 / 0.566  shipped kept           0.720 / 0.536, shipped
``scale_shift_head`` lr 0.03             0.521 / 0.514 / 0.509  shipped kept (band     0.864 / 0.803, shipped
                                                                0.485 -> 0.249)        kept both ways
``scale_shift_head`` lr 0.03, sens. 0.5  0.449 / 0.593 / 0.499
``scale_shift_head`` lr 0.01             0.634 / 0.396 / 0.481
``scale_shift_head`` lr 0.003            shipped kept
``scale_shift`` lr 0.01                  shipped kept
=======================================  =====================  =====================  ======================

(``all`` on fold 100 from the run of 2026-11-28 before these; the others each beside the shipped network in their
own run. GSB: the held-back band's F1 after adapting, against the shipped network's first row; with MODEL keeping
the shipped network, crosslines 2800 and 2600 trace at 0.826 and 0.847 in every row.) Commands: ``--only f3
--f3-source 100 --variants scale_shift_head:learning_rate=0.01 scale_shift:learning_rate=0.01
scale_shift_head:learning_rate=0.003 scale_shift_head:learning_rate=0.03``; ``... --variants
scale_shift_head:learning_rate=0.03,sensitivity=0.5``; ``--only f3 --f3-source 500 --variants all
scale_shift_head:learning_rate=0.03``; ``--only gsb --no-both --variants all scale_shift_head:learning_rate=0.03``.

Scores: the tolerant precision / recall / F1 at 3 samples of the project (``seismo3d evaluate``'s job,
:func:`seismo3d.seismic.fault_scoring.tolerant_scores`), of the faults ``seismo3d faults`` traces (its job), with and
without ``--model`` (MODEL traces at the sensitivity it records). The time of each ``adapt`` (wall, on this machine
as loaded as it is, and CPU) is printed, with its held-back F1 before and after, the network MODEL keeps, and, when
it keeps the adapted one, whether the lines not picked confirm it.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

F3_INLINES = (100, 200, 300, 400, 500)
F3_FOLDS = ((100, (200, 300, 400, 500)), (500, (100, 200, 300, 400)))
GSB_FOLDS = ((2600, (2800,)), (2800, (2600,)))
F3_TARGET = {"f1": 0.62, "precision": 0.60}
MAX_SECONDS = 300  # adapt on two lines, 2 cores (issue 74)


def f3_lines(data: Path, work: Path) -> dict:
    """inline -> (SEG-Y line path, mask .npy path, (traces, samples) bool truth): as dev_fault_scores.py builds them."""
    import segyio
    from PIL import Image

    d = data / "seismic" / "f3_fault_masks"
    out = {}
    for i in F3_INLINES:
        img = Image.open(d / f"seismic_inline_{i}.png").convert("L").resize((951, 462), Image.BILINEAR)
        sec = (np.asarray(img, np.float32) - 128.0).T  # (951 crosslines, 462 samples)
        truth = (np.asarray(Image.open(d / f"mask_inline_{i}.png"))[..., 3] > 0).T
        path = work / f"f3_inline_{i}.sgy"
        segyio.tools.from_array(str(path), np.ascontiguousarray(sec[None]), dt=4000)
        np.save(work / f"f3_inline_{i}_mask.npy", truth)
        out[i] = (path, work / f"f3_inline_{i}_mask.npy", truth)
    return out


def traced_scores(segy: Path, work: Path, *, mask=None, sticks=None, model=None) -> tuple:
    """(precision, recall, F1) of ``seismo3d faults`` (with ``model`` or the shipped network) on a line, scored by
    ``seismo3d evaluate``'s job against the mask or sticks."""
    from seismo3d.jobs.evaluate import run_evaluate_job
    from seismo3d.jobs.faults import run_faults_job

    tag = f"{segy.stem}_{'model' if model else 'default'}_{Path(str(model)).name if model else ''}"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run_faults_job(segy, work / tag, progress=False, **({"model": model} if model else {}))
        job = run_evaluate_job(work / tag, mask=mask, sticks=sticks, out=work / f"{tag}_evaluation", picture=False)
    s = job.scores
    return s.precision, s.recall, s.f1


def variant(text: str):
    """``--variants`` item ``LAYERS[:NAME=VALUE,...]`` -> (label, AdaptOptions): ``all`` is adapt's default,
    ``scale_shift:learning_rate=0.01,steps=200`` the scales and shifts at another learning rate and length."""
    from dataclasses import fields

    from seismo3d.training.adapt_options import AdaptOptions

    layers, _, rest = text.partition(":")
    kinds = {f.name: f.type for f in fields(AdaptOptions)}
    given = {}
    for item in filter(None, rest.split(",")):
        name, _, value = item.partition("=")
        given[name] = {"int": int, "float": float, "bool": lambda v: v == "True"}.get(kinds[name], str)(value)
    return text, AdaptOptions(layers=layers, **given)


def adapt_lines(segys, model: Path, kind: str, paths, options=None):
    """``seismo3d adapt`` (its job) on lines; (result, wall seconds, CPU seconds of the process)."""
    from seismo3d.jobs.adapt import run_adapt_job

    t0, c0 = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        job = run_adapt_job(list(segys), [(kind, p) for p in paths], model, options=options, progress=False)
    return job, time.perf_counter() - t0, time.process_time() - c0


def _decision(job, default_f1: float, adapted_f1: float) -> str:
    """What adapt decided on its held-back picks and, when it kept the adapted network, whether the lines not picked
    confirm it."""
    from seismo3d.jobs.adapt import adapt_report

    parts = "".join(f", {line.removeprefix('held-back ')}" for line in adapt_report(job)
                    if line.startswith("held-back parts"))  # the parts won, which decide with the mean F1
    if job.kept == "default":
        return (f"held-back F1 {job.mean('before'):.3f} -> {job.mean('after'):.3f}{parts}: MODEL keeps the shipped "
                "network")
    return (f"held-back F1 {job.mean('before'):.3f} -> {job.mean('after'):.3f}{parts}: MODEL keeps the adapted network "
            f"(traced at sensitivity {job.chosen.tracing.sensitivity:g}, unbroken veto "
            f"{'on' if job.chosen.tracing.unbroken_veto else 'off'}), which the lines not picked "
            f"{'confirm' if adapted_f1 > default_f1 else 'CONTRADICT'}")


def _row(label, default, adapted) -> str:
    return (f"  {label:22s} shipped P {default[0]:.3f} R {default[1]:.3f} F1 {default[2]:.3f}   adapted "
            f"P {adapted[0]:.3f} R {adapted[1]:.3f} F1 {adapted[2]:.3f}")


def run_f3(data: Path, work: Path, only=None, variants=(("all", None),)) -> list:
    lines = f3_lines(data, work)
    failures, shipped = [], {}  # the shipped network's scores of a line: traced once for both folds and variants
    for source, targets in (f for f in F3_FOLDS if only in (None, f[0])):
        for k, (label, options) in enumerate(variants):
            model = work / f"model_f3_{source}_{k}"
            job, seconds, cpu = adapt_lines([lines[source][0]], model, "mask", [lines[source][1]], options)
            print(f"F3: adapted on inline {source} ({label}) in {seconds:.0f} s ({cpu:.0f} CPU s)", flush=True)
            rows = []
            for t in targets:
                if t not in shipped:
                    shipped[t] = traced_scores(lines[t][0], work, mask=lines[t][1])
                default = shipped[t]
                adapted = traced_scores(lines[t][0], work, mask=lines[t][1], model=model)
                rows.append((default, adapted))
                print(_row(f"inline {t}", default, adapted), flush=True)
            d, a = np.mean([r[0] for r in rows], axis=0), np.mean([r[1] for r in rows], axis=0)
            print(_row("mean", d, a), flush=True)
            print(f"  {_decision(job, d[2], a[2])}", flush=True)
            if k == 0 and (a[2] < F3_TARGET["f1"] or a[0] < F3_TARGET["precision"]):
                failures.append(f"F3 adapted on inline {source}: mean P {a[0]:.3f} F1 {a[2]:.3f}, targets P >= "
                                f"{F3_TARGET['precision']} and F1 >= {F3_TARGET['f1']}")
    return failures


def run_gsb(data: Path, work: Path, variants=(("all", None),), both: bool = True) -> list:
    d = data / "seismic" / "gsb_fault_sticks"
    failures, shipped = [], {}
    for source, targets in GSB_FOLDS:
        for k, (label, options) in enumerate(variants):
            model = work / f"model_gsb_{source}_{k}"
            job, seconds, cpu = adapt_lines([d / f"gsb_crl_{source}.sgy"], model, "sticks",
                                            [d / f"gsb_crl_{source}_faults_opendtect.dat"], options)
            print(f"Great South Basin: adapted on crossline {source} ({label}) in {seconds:.0f} s ({cpu:.0f} CPU s)",
                  flush=True)
            for t in targets:
                sticks = d / f"gsb_crl_{t}_faults_opendtect.dat"
                if t not in shipped:
                    shipped[t] = traced_scores(d / f"gsb_crl_{t}.sgy", work, sticks=sticks)
                default = shipped[t]
                adapted = traced_scores(d / f"gsb_crl_{t}.sgy", work, sticks=sticks, model=model)
                print(_row(f"crossline {t}", default, adapted), flush=True)
                print(f"  {_decision(job, default[2], adapted[2])}", flush=True)
                if k == 0 and not adapted[2] > default[2]:
                    failures.append(f"Great South Basin adapted on crossline {source}: crossline {t} F1 "
                                    f"{adapted[2]:.3f}, not above the shipped network's {default[2]:.3f}")
    if not both:
        return failures
    job, seconds, cpu = adapt_lines([d / "gsb_crl_2600.sgy", d / "gsb_crl_2800.sgy"], work / "model_gsb_both", "sticks",
                                    [d / "gsb_crl_2600_faults_opendtect.dat", d / "gsb_crl_2800_faults_opendtect.dat"])
    print(f"Great South Basin: adapt on both crosslines in {seconds:.0f} s, {cpu:.0f} CPU s (load average "
          f"{os.getloadavg()[0]:.1f}; target <= 300 s on 2 cores: <= {2 * MAX_SECONDS} CPU s); held back "
          f"{', '.join(ln['line'] for ln in job.lines if ln['held_back_traces'][1])}: F1 {job.mean('before'):.3f} -> "
          f"{job.mean('after'):.3f}, MODEL keeps the {job.kept} network", flush=True)
    if cpu > 2 * MAX_SECONDS:
        failures.append(f"adapt on the two Great South Basin crosslines took {cpu:.0f} CPU s, over 2 cores x "
                        f"{MAX_SECONDS} s")
    return failures


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", choices=("f3", "gsb"), default=None)
    ap.add_argument("--check", action="store_true", help="exit 1 when a target of issue 74 is missed")
    ap.add_argument("--f3-source", type=int, choices=(100, 500), default=None, help="one F3 fold only")
    ap.add_argument("--variants", nargs="+", default=["all"], metavar="LAYERS[:NAME=VALUE,...]",
                    help="adapt's options compared, each beside the shipped network (AdaptOptions fields; the first "
                         "is the one --check judges), e.g. all scale_shift:learning_rate=0.01")
    ap.add_argument("--no-both", action="store_true", help="leave out the Great South Basin adapt on both lines")
    a = ap.parse_args(argv)
    variants = [variant(v) for v in a.variants]
    data = os.environ.get("SEISMO3D_DATA_DIR")
    if not data:
        sys.exit("set SEISMO3D_DATA_DIR to the data folder")
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        if a.only in (None, "gsb"):
            failures += run_gsb(Path(data), work, variants, not a.no_both)
        if a.only in (None, "f3"):
            failures += run_f3(Path(data), work, a.f3_source, variants)
    for f in failures:
        print("MISSED:", f)
    if a.check and failures:
        sys.exit(1)


if __name__ == "__main__":
    main()
