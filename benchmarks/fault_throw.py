"""Benchmark: the throw of ``seismo3d faults`` against the offsets of people's horizons on real Penobscot sections.

Run: ``python benchmarks/fault_throw.py [--half choose|report|both] [--keep DIR] [--reuse] [--check]``

The 18 consecutive Penobscot inlines 1075-1092 (:func:`~seismo3d.data.load_penobscot_sections`: 8-bit, clipped,
512 traces x 1536 samples, 7 horizons picked by people) are traced one by one as 2D sections by the ``faults`` job
(:func:`~seismo3d.jobs.faults.run_faults_job` on each section saved as ``.npy``, default options, the same on every
section). Where a traced fault cuts a people's horizon, the horizon's vertical offset across the fault, read on its
picks 3-12 traces beyond the fault zone on each side and extrapolated to the fault along each side's own dip
(:func:`~seismo3d.seismic.horizon_offsets`), is the true throw at that crossing, positive where the hanging wall
(the side the traced fault dips toward: a line fitted to its points) moved down, the sign convention of
``fault_summary.csv``.

Printed per fault that cuts a horizon: the people's offsets at its crossings, our throw at those crossings
(``fault_points.csv``'s ``throw_samples`` of the fault point nearest each crossing), our median throw
(``fault_summary.csv``), whether the signs agree and the absolute error in samples. Per half: how many faults people
show a throw on (a median offset of at least 2 samples: the picks' resolution is about a sample, the sections being
upscaled from 1501 x 481), the fraction of them with our throw's sign right (at the crossings; and of the median
throw), the median absolute error over the crossings (people's offset >= 2 samples). Faults whose people's offsets
are under 2 samples are counted apart (a fault people did not see offset, or one they smoothed over).

The sections are split: anything chosen on the throw method is chosen on inlines 1075-1083 (``choose``) and
reported on 1084-1092 (``report``), never fitted on the latter (``ThrowOptions.ambiguous_ratio`` was chosen on the
first half only; the report half had been looked at before that choice, so it is not an unseen hold-out).
Each fault's ``throw_ambiguity`` and ``throw_alternative_samples`` are printed too, and per half how many of the
faults off by a cycle skip or of the wrong sign ``fault_summary.csv`` calls ambiguous, and how many of the others.
``--check`` asserts the report half's figures (margins in ``CHECK``); it traces the 9 sections of the report half,
about 40 s on 2 quiet cores, and runs in CI (``benchmarks/checks.py fault-throw``).

``--keep DIR`` keeps each section's job outputs in ``DIR/inline_N``; ``--reuse`` scores those of an earlier run
instead of tracing again (only for the same checkout).
"""

from __future__ import annotations

import argparse
import csv
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

CHOOSE = tuple(range(1075, 1084))
REPORT = tuple(range(1084, 1093))
MIN_OFFSET = 2.0  # samples: people's median offset on a fault for its sign to count
SKIP = 5.0  # samples: an error of about half the reflectors' period (9-12 samples here) or more is a cycle skip
# the report half as measured 2026-11-28 (2 of 3 faults with the right sign at the crossings, median |error| 5.0
# samples at their crossings and 0.7 over every crossing, 4 of 11 faults off by a cycle skip, 2 of the 4 wrong ones
# called ambiguous and none of the 7 others): a guard against a regression, not a target (3 faults with a people's
# offset of 2 samples or more are too few for one)
CHECK = dict(sign_at_crossings=(">=", 0.6), median_abs_error=("<=", 6.0), median_abs_error_all=("<=", 1.0),
             skips=("<=", 4), flagged_wrong=(">=", 2), flagged_right=("<=", 1))


@dataclass(frozen=True)
class FaultRow:
    """One traced fault that cuts at least one people's horizon."""

    inline: int
    fault_id: int
    dip_deg: float
    people: np.ndarray  # (m,) offsets at its crossings, samples
    ours: np.ndarray  # (m,) our throw at those crossings, samples (NaN unmeasured)
    median_throw: float  # fault_summary.csv's median throw, samples
    step: float  # fault_summary.csv's throw_step_samples
    alternative: float  # fault_summary.csv's throw_alternative_samples (NaN: the throw is not ambiguous)
    ambiguity: float  # fault_summary.csv's throw_ambiguity

    @property
    def people_median(self) -> float:
        return float(np.median(self.people))

    @property
    def ambiguous(self) -> bool:
        """fault_summary.csv gives an alternative throw."""
        return bool(np.isfinite(self.alternative))

    @property
    def ours_median(self) -> float:
        ok = np.isfinite(self.ours)
        return float(np.median(self.ours[ok])) if ok.any() else float("nan")


def trace_section(section: np.ndarray, inline: int, keep: Path, reuse: bool) -> Path:
    """Run the faults job on one section (saved as .npy), defaults; its output folder."""
    from seismo3d.errors import Seismo3dWarning
    from seismo3d.jobs.faults import run_faults_job

    out = keep / f"inline_{inline}"
    if reuse and (out / "fault_summary.csv").is_file():
        return out
    npy = keep / f"inline_{inline}.npy"
    np.save(npy, np.ascontiguousarray(section))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)  # the clipped 8-bit amplitudes and the muted top
        run_faults_job(npy, out, progress=False, overwrite=True)
    return out


def _read_csv(path: Path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _number(text: str) -> float:
    return float(text) if text not in ("", None) else float("nan")


def hanging_wall_sides(points: np.ndarray, ids: np.ndarray) -> tuple[dict, dict]:
    """Per fault id, +1 when its points deepen toward increasing trace (the hanging wall on that side), else -1, and
    its dip from the horizontal in degrees (the principal axis of its points, a trace and a sample counted as 1)."""
    sides, dips = {}, {}
    for fid in np.unique(ids):
        p = points[ids == fid]
        if len(p) < 3:
            continue
        c = p - p.mean(axis=0)
        axis = np.linalg.eigh(c.T @ c)[1][:, -1]  # (trace, sample)
        if axis[1] < 0:
            axis = -axis
        sides[int(fid)] = 1 if axis[0] > 0 else -1
        dips[int(fid)] = float(np.degrees(np.arctan2(axis[1], abs(axis[0]))))
    return sides, dips


def score_section(out: Path, horizons: np.ndarray, inline: int) -> list[FaultRow]:
    """The faults of one section's job outputs that cut a people's horizon, with the offsets and our throws."""
    from seismo3d.seismic import horizon_offsets

    rows = _read_csv(out / "fault_points.csv")
    if not rows:
        return []
    points = np.array([(float(r["trace"]), float(r["time_or_depth"])) for r in rows])
    ids = np.array([int(r["fault_id"]) for r in rows])
    throw = np.array([_number(r["throw_samples"]) for r in rows])
    summary = {int(r["id"]): r for r in _read_csv(out / "fault_summary.csv")}
    sides, dips = hanging_wall_sides(points, ids)
    res = horizon_offsets(points, ids, sides, horizons)
    faults = []
    for fid in np.unique(res.fault_id):
        sel = res.fault_id == fid
        s = summary[int(fid)]
        faults.append(FaultRow(inline, int(fid), dips[int(fid)], res.offset[sel], throw[res.point[sel]],
                               _number(s["median_throw_samples"]), _number(s["throw_step_samples"]),
                               _number(s["throw_alternative_samples"]), _number(s["throw_ambiguity"])))
    return faults


@dataclass(frozen=True)
class HalfScores:
    """The scores of one half of the sections."""

    n_faults: int  # faults cutting a horizon
    n_offset: int  # ... whose people's median offset is at least MIN_OFFSET
    sign_at_crossings: float  # fraction of those whose throw at the crossings has the people's sign
    sign_of_median: float  # ... whose median throw (fault_summary.csv) has it
    sign_of_step: float  # ... whose throw_step_samples has it
    median_abs_error: float  # over their crossings, samples
    n_crossings: int
    unmeasured: int  # crossings without a throw
    median_abs_error_all: float  # over every fault's crossings, samples
    skips: int  # faults whose throw at the crossings is SKIP samples or more from the people's offset
    n_wrong: int  # faults off by SKIP or more, or of the wrong sign (people's offset >= MIN_OFFSET)
    flagged_wrong: int  # ... whose throw fault_summary.csv calls ambiguous (an alternative given)
    flagged_right: int  # the other faults called ambiguous


def half_scores(faults: list[FaultRow]) -> HalfScores:
    big = [f for f in faults if abs(f.people_median) >= MIN_OFFSET]

    def frac(values):
        return float(np.mean(values)) if values else float("nan")

    wrong = [abs(f.ours_median - f.people_median) >= SKIP
             or (abs(f.people_median) >= MIN_OFFSET and np.sign(f.ours_median) != np.sign(f.people_median))
             for f in faults]
    every = np.concatenate([np.abs(f.ours - f.people) for f in faults]) if faults else np.zeros(0)
    every = every[np.isfinite(every)]
    errors, unmeasured = [], 0
    for f in big:
        ok = np.isfinite(f.ours)
        unmeasured += int((~ok).sum())
        errors.extend(np.abs(f.ours[ok] - f.people[ok]).tolist())
    return HalfScores(
        n_faults=len(faults), n_offset=len(big),
        sign_at_crossings=frac([np.sign(f.ours_median) == np.sign(f.people_median) for f in big]),
        sign_of_median=frac([np.sign(f.median_throw) == np.sign(f.people_median) for f in big]),
        sign_of_step=frac([np.sign(f.step) == np.sign(f.people_median) for f in big if np.isfinite(f.step)]),
        median_abs_error=float(np.median(errors)) if errors else float("nan"),
        n_crossings=len(errors) + unmeasured, unmeasured=unmeasured,
        median_abs_error_all=float(np.median(every)) if every.size else float("nan"),
        skips=sum(abs(f.ours_median - f.people_median) >= SKIP for f in faults),
        n_wrong=sum(wrong), flagged_wrong=sum(w and f.ambiguous for w, f in zip(wrong, faults)),
        flagged_right=sum(not w and f.ambiguous for w, f in zip(wrong, faults)))


def print_half(name: str, inlines, faults: list[FaultRow], seconds: float) -> HalfScores:
    print(f"\n{name}: inlines {inlines[0]}-{inlines[-1]} ({seconds:.0f} s)")
    head = (f"{'inline':>6s} {'fault':>5s} {'dip':>5s}  {'people offsets':28s} {'ours at crossings':28s} "
            f"{'median':>7s} {'step':>6s} {'sign':>5s} {'|err|':>6s} {'ambig':>5s} {'alt':>6s}")
    print(head + "\n" + "-" * len(head))

    def nums(values):
        return " ".join("  nan" if not np.isfinite(v) else f"{v:+5.1f}" for v in values)

    for f in faults:
        seen = abs(f.people_median) >= MIN_OFFSET
        ok = np.isfinite(f.ours)
        err = float(np.median(np.abs(f.ours[ok] - f.people[ok]))) if ok.any() else float("nan")
        sign = ("yes" if np.sign(f.ours_median) == np.sign(f.people_median) else "NO") if seen else "-"
        print(f"{f.inline:6d} {f.fault_id:5d} {f.dip_deg:5.1f}  {nums(f.people):28s} {nums(f.ours):28s} "
              f"{f.median_throw:+7.1f} {f.step:+6.1f} {sign:>5s} {err:6.1f} {f.ambiguity:5.2f} {f.alternative:+6.1f}")
    s = half_scores(faults)
    print(f"{name}: {s.n_faults} faults cut a people's horizon, {s.n_offset} with a people's median offset >= "
          f"{MIN_OFFSET:g} samples; right sign: {s.sign_at_crossings:.0%} at the crossings, {s.sign_of_median:.0%} "
          f"of the median throw, {s.sign_of_step:.0%} of throw_step_samples; median |error| at their "
          f"{s.n_crossings} crossings {s.median_abs_error:.1f} samples ({s.unmeasured} unmeasured); over every "
          f"fault's crossings {s.median_abs_error_all:.1f} samples; {s.skips} of {s.n_faults} faults off by >= "
          f"{SKIP:g} samples (a cycle skip); called ambiguous: {s.flagged_wrong} of the {s.n_wrong} off by a skip or "
          f"of the wrong sign, {s.flagged_right} of the {s.n_faults - s.n_wrong} others")
    return s


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--half", choices=("choose", "report", "both"), default="both")
    ap.add_argument("--keep", type=Path, help="folder for each section's job outputs (inline_N)")
    ap.add_argument("--reuse", action="store_true", help="score the outputs already in --keep")
    ap.add_argument("--check", action="store_true", help="assert the report half's figures (CHECK)")
    args = ap.parse_args(argv)
    if args.reuse and args.keep is None:
        ap.error("--reuse needs --keep DIR, the folder of an earlier run's outputs")
    if args.check:
        args.half = "report"

    from seismo3d.data import load_penobscot_sections

    slab = load_penobscot_sections()
    ids = [int(i) for i in slab.section_ids]
    halves = {"choose": CHOOSE, "report": REPORT}
    wanted = list(halves) if args.half == "both" else [args.half]
    scores = {}
    with tempfile.TemporaryDirectory() as tmp:
        keep = args.keep or Path(tmp)
        keep.mkdir(parents=True, exist_ok=True)
        for name in wanted:
            t0 = time.perf_counter()
            faults = []
            for inline in halves[name]:
                i = ids.index(inline)
                out = trace_section(slab.cube[i], inline, keep, args.reuse)
                faults.extend(score_section(out, slab.horizons[i], inline))
            scores[name] = print_half(name, halves[name], faults, time.perf_counter() - t0)
    if args.check:
        s, failed = scores["report"], []
        for key, (op, bound) in CHECK.items():
            value = getattr(s, key)
            if not (value >= bound if op == ">=" else value <= bound):  # NaN fails
                failed.append(f"{key} {value:.3g} (wanted {op} {bound})")
        print("check: " + ("passed" if not failed else "FAILED: " + "; ".join(failed)))
        return 1 if failed else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
