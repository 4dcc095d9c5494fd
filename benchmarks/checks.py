"""Every claim too long for the test suite, asserted by its benchmark's ``--check``: one command runs them all.

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/checks.py [--list] [NAME ...]``

Each check is a benchmark run with ``--check`` (or the notebooks run again by ``notebooks/build.py --check``), which
exits non-zero when its target is missed. They run one after the other, each in its own process (so that one check's
memory and threads do not disturb the next one's timing), with this checkout first on ``PYTHONPATH``; the table gives
each one's exit code and minutes, and this script exits 1 when any check failed. ``CHECKS`` is the one list of them
(``--list`` prints it, ``CONTRIBUTING.md`` points to it): a claim moved out of the suite is added here, beside the
command that asserts it.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Check:
    """A command that asserts claims too long for the suite: its name, arguments (after ``python``) and what it
    asserts."""

    name: str
    argv: tuple
    asserts: str


CHECKS = [
    Check("volumes-coordinates", ("benchmarks/volumes.py", "--only", "coordinates", "--check"),
          "a Penobscot block and its copy at 12 degrees (bins 1.25 / 0.8, vertical 1.1), both SEG-Y without "
          "coordinates, right and converged in both orders, the orders within 0.1 samples"),
    Check("volumes-grid", ("benchmarks/volumes.py", "--only", "suite_grid", "--check"),
          "the sub-volume pairs of f3_crop, Penobscot and Volve that left the suite, right and converged in the "
          "issue's tolerances in both orders"),
    Check("volumes-any-grid", ("benchmarks/volumes.py", "--only", "any_grid", "--pairs", "50", "--check"),
          "50 pairs from each of three real cubes (Parihaka, Penobscot, f3_crop) on grids rotated up to 30 degrees, "
          "bins 0.7-1.4 per map axis, samples 0.9-1.1, without coordinates, in both orders (300 registrations): "
          "95 % right in the issue's tolerances and converged, each within 5 CPU s, none converged wrongly; "
          "unrelated pairs refused (35.8 min at load 5-12 on 2 cores)"),
    Check("horizons-traced-faults", ("benchmarks/horizons.py", "--only", "traced_faults", "--check"),
          "the 18 Penobscot inlines' horizons with the faults traced in them: no loss against no fault input, the "
          "measured medians, 99 % within 5 samples; no fault traced in those inlines' crosshatch of dipping events"),
    Check("horizons-generated", ("benchmarks/horizons.py", "--only", "synthetic", "--check"),
          "the generated faulted cubes 0-2 (the suite keeps cube 0): every horizon tracked across the traced faults "
          "within 0.16 samples at the median, at least 89 % of the traces within 2 samples"),
    Check("fault-throw", ("benchmarks/fault_throw.py", "--check"),
          "the faults job's throw on the 18 Penobscot inlines against the offsets of people's horizons across the "
          "traced faults, on the report half (inlines 1084-1092): the sign, the error at the crossings, the cycle "
          "skips and which of them are called ambiguous, as the benchmark's bounds say (about 1 min)"),
    Check("notebooks", ("notebooks/build.py", "--check"),
          "the six notebooks' cells equal their sources, their outputs hold no warning, error or absolute path, and "
          "a fresh run of each prints what the saved notebook shows"),
    Check("commands", ("benchmarks/commands.py", "--check"),
          "seismo3d convert <= 1.5 x a segyio read of the same file, every --help <= 0.5 s"),
    Check("fault-speed", ("benchmarks/fault_speed.py", "--repeats", "3", "--check"),
          "issue 76, in CPU seconds of the processes on 2 threads (a wall-time ratio moves with the load of a shared "
          "machine): the whole seismo3d faults command on a generated 256^3 cube in no more than FaultNet's fault "
          "probability of the same cube, its fault likelihood in no more than half of it"),
    Check("fault-blocks", ("benchmarks/fault_blocks.py", "--check"),
          "the learned likelihood by blocks on a grid of 0.7 and on three grids, a block on the 0.7 network grid, "
          "the faults job beyond its memory limit on a 192 x 192 x 64 cube and a SEG-Y cube, and the 128^3 demo "
          "by blocks and its interchange files: equal to them in memory (the suite keeps smaller cubes)"),
    Check("faults-3d", ("benchmarks/faults_3d.py", "--only", "parihaka", "--check"),
          "the real Parihaka 3D cube (the 128 most-labelled time slices), defaults: at least 0.80 of the fault bands "
          "people outlined hit with at least 0.60 of the traced points inside bands, ahead of the 1-semblance "
          "skeleton on both"),
    Check("adapt", ("benchmarks/adapt.py", "--check"),
          "seismo3d adapt (needs PyTorch and onnx): F3 adapted on inline 100 (500), the four other inlines traced with "
          "MODEL: mean F1 >= 0.62 and mean precision >= 0.60 in both folds; Great South Basin adapted on crossline "
          "2600 (2800), the other traced: F1 above the shipped network's; adapt on both crosslines within 2 cores x "
          "300 s of CPU time"),
]


def run(check: Check) -> tuple[int, float]:
    """Run one check in the repository's folder; its exit code and wall seconds (its output goes to ours)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH")) if p))
    start = time.perf_counter()
    done = subprocess.run([sys.executable, *check.argv], cwd=REPO, env=env)
    return done.returncode, time.perf_counter() - start


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help="checks to run (default: all); --list names them")
    parser.add_argument("--list", action="store_true", help="list the checks and what each asserts, run nothing")
    args = parser.parse_args()
    known = {c.name: c for c in CHECKS}
    unknown = [n for n in args.names if n not in known]
    if unknown:
        parser.error(f"unknown check(s) {', '.join(unknown)}; --list names them: {', '.join(known)}")
    chosen = [known[n] for n in args.names] if args.names else CHECKS
    if args.list:
        for c in chosen:
            print(f"{c.name}: python {' '.join(c.argv)}\n    {c.asserts}")
        return 0
    if not os.environ.get("SEISMO3D_DATA_DIR"):  # the notebooks would be skipped, and skipped is not passed
        parser.error("SEISMO3D_DATA_DIR is not set: the checks run on the real data; export "
                     "SEISMO3D_DATA_DIR=/path/to/data (docs/data.md)")
    results = []
    for c in chosen:
        print(f"\n# {c.name}: python {' '.join(c.argv)}", flush=True)
        results.append((c, *run(c)))
    print(f"\n{'check':26s} {'exit':>4s} {'min':>6s}")
    for c, code, seconds in results:
        print(f"{c.name:26s} {code:4d} {seconds / 60:6.1f}")
    failed = [c.name for c, code, _ in results if code]
    print(f"failed: {', '.join(failed)}" if failed else "all checks passed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
