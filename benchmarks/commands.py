"""Speed a user feels: ``seismo3d convert`` as a process beside a ``segyio.tools.cube`` read, and every ``--help``.

Run:  python benchmarks/commands.py [--shape 400 400 250] [--repeats 5] [--work DIR] [--check] [--baseline CODE_DIR]

Everything is timed as a user meets it, a whole process from start to exit (interpreter, imports, work), by wall
clock (and the CPU seconds of the process, which change less with the machine's load), the medians of ``--repeats``
runs:

- ``seismo3d convert`` of a generated inline-sorted IEEE SEG-Y cube (default 400 x 400 x 250 float32, 198 MB; written
  once by :func:`convert.write_segy` into ``--work``, outside the repository, and reused) beside its peer, a fresh
  Python process reading the same file with ``segyio.tools.cube`` (segyio's memory map: the I/O floor of reading it
  from Python; the same reader as ``benchmarks/convert.py``). The runs alternate (read, convert, read, ...) after one
  untimed run of each (the file in the page cache), so that load changes hit both alike; each convert writes a new
  store (the previous one is removed outside the clock). The convert also hashes an input of up to 200 MiB for its
  run.json (sha256 on a thread, 0.11-0.16 CPU s for 198 MB; ``runinfo.HASH_LIMIT``): ``--shape 800 400 250``
  (397 MB, "198 MB and larger") is identified by size and modification time instead, as every larger input.
- In the same rounds, the floor of any such conversion: a process that reads the file as the peer does, imports
  zarr (the library that writes the store's metadata), computes the file's sha256 (run.json's identity of an input
  up to ``runinfo.HASH_LIMIT``) and writes nothing. ``floor / read`` is the least ``convert / read`` can be while
  the convert writes with zarr-python and hashes its input; on a loaded machine, where a process's wall time follows
  its CPU time, the convert cannot come nearer the read than that. A second floor adds what a convert cannot skip
  and does as a convert does it: the sha256 on a thread from the start (overlapping the imports and the read, which
  lowers the wall time where a core is idle) and the cube's bytes written (as one file): ``convert / that floor`` is
  what the store's layout, the headers, the CLI and the metadata add. Beside them, a process that only
  imports what a convert imports (the ``seismo3d`` CLI, numpy, segyio, zarr): ``convert - imports`` is the CPU its
  work takes (the read, the sha256, the copy and the writes).
- ``seismo3d --help`` and ``seismo3d COMMAND --help`` for every command of the ``seismo3d`` app, beside the floor of
  any typer command: ``--help`` of a command of a two-command typer app (typer imports rich and pydantic to show it;
  ``seismo3d`` converts its values without pydantic, :mod:`seismo3d._cli_coercion`, and prints its help in click's
  plain text, without rich).

``--baseline CODE_DIR`` (e.g. ``/work/main``) times that code's ``seismo3d convert`` too (``PYTHONPATH=CODE_DIR``),
in the same rounds (read, baseline convert, convert, ...), so that the two are paired at the same load.

Every process caches its bytecode in ``--work``'s ``bytecode`` folder, filled by the untimed first round (a checkout
run where ``PYTHONDONTWRITEBYTECODE`` is set would otherwise compile its seismo3d modules in every timed run, as an
installed package never does).

The command is the installed ``seismo3d`` script beside this interpreter (``python -m seismo3d.cli`` when there is
none), run with this checkout first on ``PYTHONPATH``. Targets (issues 58, 76): convert <= 1.5 x the segyio read (wall
clock, both as processes), every ``--help`` <= 0.5 s; ``--check`` exits with 1 when one is missed (the floor is
printed, not checked).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from convert import _SEGYIO_READ, write_segy  # benchmarks/convert.py: the same generated cube and the same peer

# the floor of a conversion with zarr-python and run.json's sha256: the peer's read, zarr imported, the file hashed
# (through one memory map: the cheapest way to hash it), nothing written
_FLOOR = _SEGYIO_READ + """
import hashlib, mmap
import zarr
with open(sys.argv[1], "rb") as fh, mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as whole:
    hashlib.sha256(whole).hexdigest()
"""

# the same with what a convert adds that no code can skip: the sha256 on a second thread from the start (as run.json's
# identity is computed, overlapping the imports and the read) and the amplitudes written (the cube's bytes as one file,
# argv[2]); the least wall time a convert can take on the machine as it is loaded
_FLOOR_WRITTEN = """
import hashlib, mmap, sys, threading

def digest():
    with open(sys.argv[1], "rb") as fh, mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as whole:
        hashlib.sha256(whole).hexdigest()

hashing = threading.Thread(target=digest)
hashing.start()
""" + _SEGYIO_READ + """
import zarr
cube.tofile(sys.argv[2])
hashing.join()
"""

# what a convert imports, and nothing else
_IMPORTS = "import seismo3d.cli, numpy, segyio, zarr"

# the floor of any typer command's --help: a two-command typer app (typer imports rich and pydantic to show it)
_TYPER_HELP = """
import pathlib, typer
app = typer.Typer(add_completion=False)

@app.command()
def one(path: pathlib.Path, number: int = typer.Option(1, help="A number.")):
    \"\"\"The first command.\"\"\"

@app.command()
def two():
    \"\"\"The second command.\"\"\"

app()
"""

REPO = Path(__file__).resolve().parents[1]
CONVERT_LIMIT = 1.5  # x the segyio read
HELP_LIMIT = 0.5  # seconds


def _environment(code: Path, cwd: Path) -> dict:
    """``code`` first on the path, so that the command runs its code and not an installed copy's; Python's bytecode
    cached in ``cwd/bytecode`` (``PYTHONPYCACHEPREFIX``), also where the caller's environment says not to write it
    (``PYTHONDONTWRITEBYTECODE``): an installed package has its modules compiled, and without a cache every timed run
    of a checkout would compile each seismo3d module it imports (0.05-0.07 CPU s of a convert), which the peer's
    segyio and numpy never do. The untimed first round fills the cache, outside the checkouts."""
    env = dict(os.environ, PYTHONPATH=str(code) + os.pathsep + os.environ.get("PYTHONPATH", ""),
               PYTHONPYCACHEPREFIX=str(cwd / "bytecode"))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def seismo3d_command() -> list[str]:
    """The ``seismo3d`` script installed beside this interpreter, or ``python -m seismo3d.cli``."""
    script = Path(sys.executable).parent / "seismo3d"
    return [str(script)] if script.exists() else [sys.executable, "-m", "seismo3d.cli"]


def command_names() -> list[str]:
    """The commands of the ``seismo3d`` app, in the order ``seismo3d --help`` lists them."""
    sys.path.insert(0, str(REPO))
    import typer.main

    from seismo3d.cli import app

    return list(typer.main.get_command(app).commands)


@dataclass(frozen=True)
class ProcessTime:
    """The wall time of one process, start to exit, and the CPU time it used (user + system, all its threads)."""

    wall: float
    cpu: float


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def process_time(argv: list[str], cwd: Path, code: Path = REPO) -> ProcessTime:
    """Run one process with ``code`` first on the path (its output discarded; a failure raises with its standard
    error) and time it."""
    cpu, start = _children_cpu(), time.perf_counter()
    done = subprocess.run(argv, env=_environment(code, cwd), cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                          text=True)
    wall = time.perf_counter() - start
    if done.returncode:
        raise RuntimeError(f"{' '.join(argv)} exited with {done.returncode}:\n{done.stderr}")
    return ProcessTime(wall, _children_cpu() - cpu)


@dataclass(frozen=True)
class ConvertRuns:
    """``seismo3d convert`` beside the segyio read: the processes' times and, per convert, its run.json (the job's
    ``seconds`` and ``stage_seconds``)."""

    converts: list[ProcessTime]
    reads: list[ProcessTime]
    records: list[dict]
    baseline: list[ProcessTime]
    floors: list[ProcessTime]
    imports: list[ProcessTime]
    written: list[ProcessTime]


def convert_against_segyio(segy: Path, work: Path, repeats: int, baseline: Path | None = None) -> ConvertRuns:
    """``seismo3d convert SEGY STORE``, a segyio read of SEGY and the floor (``_FLOOR``), ``repeats`` each,
    alternating (with the ``baseline`` code's convert before ours when given)."""
    store = work / "seismo3d_bench_commands.zarr"
    record = Path(f"{store}.run.json")  # the run record beside the store
    peer = [sys.executable, "-c", _SEGYIO_READ, str(segy)]
    floor = [sys.executable, "-c", _FLOOR, str(segy)]
    written = [sys.executable, "-c", _FLOOR_WRITTEN, str(segy), str(work / "seismo3d_bench_floor.bin")]
    imports = [sys.executable, "-c", _IMPORTS]
    ours = [*seismo3d_command(), "convert", str(segy), str(store)]
    runs = ConvertRuns([], [], [], [], [], [], [])
    for timed in [False] + [True] * repeats:  # the first pair warms the page cache
        shutil.rmtree(store, ignore_errors=True)
        record.unlink(missing_ok=True)
        read = process_time(peer, work)
        least = process_time(floor, work)
        least_written = process_time(written, work)
        Path(written[-1]).unlink(missing_ok=True)
        imported = process_time(imports, work)
        if baseline is not None:
            before = process_time(ours, work, baseline)
            shutil.rmtree(store, ignore_errors=True)
            record.unlink(missing_ok=True)
            if timed:
                runs.baseline.append(before)
        convert = process_time(ours, work)
        if timed:
            runs.reads.append(read)
            runs.floors.append(least)
            runs.written.append(least_written)
            runs.imports.append(imported)
            runs.converts.append(convert)
            runs.records.append(json.loads(record.read_text()))
    shutil.rmtree(store, ignore_errors=True)
    record.unlink(missing_ok=True)
    return runs


def help_times(commands: list[str], work: Path, repeats: int) -> dict[str, list[ProcessTime]]:
    """Times of ``seismo3d --help`` and of each ``seismo3d COMMAND --help``, ``repeats`` each, round by round."""
    lines = {"seismo3d --help": []} | {f"seismo3d {c} --help": [] for c in commands}
    for _ in range(repeats):
        for line in lines:
            lines[line].append(process_time([*seismo3d_command(), *line.split()[1:]], work))
    return lines


def _median(runs: list[ProcessTime], field: str) -> float:
    return float(np.median([getattr(r, field) for r in runs]))


def _row(name: str, runs: list[ProcessTime], target: str = "") -> float:
    """Print a row of the table; the median wall time."""
    wall = _median(runs, "wall")
    print(f"{name:36s} {wall:7.3f} {_median(runs, 'cpu'):6.3f} {' '.join(f'{r.wall:.2f}' for r in runs):>30s}  "
          f"{target}")
    return wall


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shape", type=int, nargs=3, default=(400, 400, 250),
                        help="inlines, crosslines, samples of the generated SEG-Y (default: 198 MB)")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs of each process (the median is printed)")
    parser.add_argument("--work", default=Path(tempfile.gettempdir()) / "seismo3d_bench", type=Path,
                        help="folder of the generated SEG-Y (kept for reruns) and of the stores")
    parser.add_argument("--check", action="store_true", help="exit with 1 if a target is missed")
    parser.add_argument("--baseline", type=Path, default=None, metavar="CODE_DIR",
                        help="also time this code's convert (PYTHONPATH=CODE_DIR, e.g. a worktree of main) in the same "
                        "rounds")
    args = parser.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    segy = args.work / ("seismo3d_bench_%dx%dx%d.sgy" % tuple(args.shape))
    if not segy.exists():
        print(f"writing {segy} ...", flush=True)
        write_segy(segy, args.shape)
    print(f"{segy.name}: {segy.stat().st_size / 1e6:.0f} MB; command: {' '.join(seismo3d_command())}; load average "
          f"before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    # 1. convert beside the segyio read, alternating; 2. every --help
    runs = convert_against_segyio(segy, args.work, args.repeats, args.baseline)
    helps = help_times(command_names(), args.work, args.repeats)
    help_floor = [process_time([sys.executable, "-c", _TYPER_HELP, "one", "--help"], args.work)
                  for _ in range(args.repeats)]
    # 3. the table (wall-clock medians: the targets; CPU medians: the work, nearly the same at any load)
    print(f"{'process':36s} {'wall s':>7s} {'CPU s':>6s} {'wall s of each run':>30s}  target")
    read = _row("python -c segyio.tools.cube(...)", runs.reads)
    least = _row("the read + import zarr + sha256", runs.floors)
    print(f"{'':2s}floor / read: {least / read:.2f} (wall), "
          f"{_median(runs.floors, 'cpu') / _median(runs.reads, 'cpu'):.2f} (CPU): the least convert / read can be "
          "while it imports zarr and hashes its input")
    written = _row("the same, hashing on a thread, writing", runs.written)
    print(f"{'':2s}that floor / read: {written / read:.2f} (wall), "
          f"{_median(runs.written, 'cpu') / _median(runs.reads, 'cpu'):.2f} (CPU): the read, zarr imported, the "
          "sha256 on a second thread, the cube written as one file")
    _row("a convert's imports, no work", runs.imports)
    if runs.baseline:
        before = _row(f"seismo3d convert of {args.baseline}", runs.baseline)
        print(f"{'':2s}{args.baseline}'s convert / read: {before / read:.2f} (wall), "
              f"{_median(runs.baseline, 'cpu') / _median(runs.reads, 'cpu'):.2f} (CPU)")
    convert = _row("seismo3d convert", runs.converts, f"<= {CONVERT_LIMIT} x the read")
    job = float(np.median([r["seconds"] for r in runs.records]))
    write = float(np.median([r["stage_seconds"]["write"] for r in runs.records]))
    rest = float(np.median([c.wall - r["seconds"] for c, r in zip(runs.converts, runs.records)]))
    print(f"{'':2s}convert / read: {convert / read:.2f} (wall), "
          f"{_median(runs.converts, 'cpu') / _median(runs.reads, 'cpu'):.2f} (CPU); convert / the floor with the "
          f"write: {convert / written:.2f} (wall), {_median(runs.converts, 'cpu') / _median(runs.written, 'cpu'):.2f} "
          "(CPU)\n"
          f"{'':2s}convert - imports: {_median(runs.converts, 'cpu') - _median(runs.imports, 'cpu'):.3f} CPU s (the "
          f"read, the sha256, the copy and the writes)\n"
          f"{'':2s}convert: the job (run.json) {job:.2f} s, of which writing {write:.2f} s (the job imports numpy "
          f"and segyio, and hashes the input on a thread); the rest of the process (interpreter, the CLI, exit) "
          f"{rest:.2f} s")
    help_walls = {line: _row(line, runs, f"<= {HELP_LIMIT} s") for line, runs in helps.items()}
    _row("typer app of two commands: one --help", help_floor)
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    missed = ([f"convert {convert / read:.2f} x the segyio read"] if convert > CONVERT_LIMIT * read else []) + \
             [f"{line} {s:.2f} s" for line, s in help_walls.items() if s > HELP_LIMIT]
    if missed:
        print("missed: " + "; ".join(missed))
    return 1 if args.check and missed else 0


if __name__ == "__main__":
    sys.exit(main())
