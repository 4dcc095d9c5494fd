"""Memory of the stages of ``seismo3d faults`` after its blocks, per fault cell and per sample (issue 75).

Run: ``python benchmarks/post_block_memory.py [--cube 160,160,256,4 --cube 224,224,192,8 ...] [--keep DIR]``

For each generated cube (``n_inlines,n_xlines,n_samples,n_faults``: :func:`~seismo3d.data.synthetic_cube`, seed 3,
written as an inline-sorted SEG-Y file) :func:`~seismo3d.jobs.faults.run_faults_job` runs in this process by blocks
(under the smallest ``--memory-limit`` its refusal names, or ``--limit``), and each stage after the blocks is
measured: the process's resident memory when the stage starts and its high-water mark during the stage (``VmHWM`` of
``/proc/self/status``, the kernel's exact peak, reset at the stage's start by writing 5 to ``/proc/self/clear_refs``),
both less the process the run's memory plan counted (:func:`~seismo3d.seismic.blocks.memory.resident_memory` when
:func:`~seismo3d.seismic.faults.pipeline.check_block_run` measured it). The stages: the cells read from the store
(``cells``), the fault skins, the throw, the reflectors' half periods, the evidence and the tips, then each writer.
Printed per cube and stage: the cells, the samples, the resident memory at the stage's start and its peak beyond the
process; then the plan's models of the stages with the cells counted
(:func:`~seismo3d.seismic.faults.surfaces.blocks.held_stages` and the job's writers), beyond the process the plan
counts (rounded up to 64 MiB) and ``STAGE_GROWTH`` (64 MiB), and the need against the limit. The runs measured for
the models ran a worktree of the code before them (``PYTHONPATH``) with the limit its refusal named, each cube in a
fresh process.
"""

from __future__ import annotations

import argparse
import functools
import pathlib
import sys
import tempfile
import time

import numpy as np


def _status() -> dict:
    found = {}
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(("VmHWM", "VmRSS")):
                key, value = line.split(":")
                found[key] = int(value.split()[0]) * 1024
    return found


def _reset_peak() -> int:
    """The high-water mark reset to the resident memory now; that memory, bytes."""
    with open("/proc/self/clear_refs", "w") as fh:
        fh.write("5")
    return _status()["VmRSS"]


class _Stages:
    """Peaks of named stages of this process (module attributes wrapped)."""

    def __init__(self):
        self.rows, self.process = [], None

    def wrap(self, module, name: str, label: str | None = None):
        original = getattr(module, name)

        @functools.wraps(original)
        def measured(*args, **kwargs):
            start = _reset_peak()
            try:
                return original(*args, **kwargs)
            finally:
                self.rows.append((label or name, start, _status()["VmHWM"]))

        setattr(module, name, measured)
        return original


def _measure(sgy: pathlib.Path, out: pathlib.Path, limit: str) -> tuple[_Stages, dict]:
    import seismo3d.jobs.faults as job
    import seismo3d.seismic.faults.pipeline as pipeline
    import seismo3d.seismic.faults.steps as steps
    import seismo3d.seismic.faults.surfaces.blocks as surfaces
    from seismo3d.seismic.blocks.memory import resident_memory

    stages = _Stages()
    check = pipeline.check_block_run

    def checked(*args, **kwargs):
        found = check(*args, **kwargs)
        stages.process = resident_memory()
        return found

    pipeline.check_block_run = checked
    cells_at = {}
    surface_cells = surfaces.surface_cells

    def after_blocks(*args, **kwargs):
        found = surface_cells(*args, **kwargs)
        cells_at["start"] = _reset_peak()
        return found

    surfaces.surface_cells = after_blocks
    faults_from_cells = surfaces.faults_from_cells

    def linked(cells, *args, **kwargs):
        stages.rows.append(("cells", cells_at.get("start", _status()["VmRSS"]), _status()["VmHWM"]))
        cells_at["n"] = len(cells[0])
        return faults_from_cells(cells, *args, **kwargs)

    surfaces.faults_from_cells = linked
    for name in ("skins_from_cells", "fault_throws", "half_period", "supported_faults", "trimmed_tips"):
        stages.wrap(steps, name)

    def write_steps(steps_, written, progress, **_):  # each writer alone (the job's thread beside: memory only)
        for key, write in steps_:
            start = _reset_peak()
            written[key] = write()
            stages.rows.append((f"write {key}", start, _status()["VmHWM"]))
            job.release_memory()

    job._write_steps = write_steps
    started = time.perf_counter()
    result = job.run_faults_job(sgy, out, memory_limit=limit, progress=False, overwrite=True)
    return stages, {"seconds": time.perf_counter() - started, "cells": cells_at.get("n", 0),
                    "faults": result.n_faults, "by_blocks": "surfaces_zarr" in result.written}


def _cube(root: pathlib.Path, spec: str) -> tuple[pathlib.Path, tuple, int]:
    sys.path.insert(0, str(pathlib.Path(__file__).parent))
    from fault_throw_lazy import write_segy
    from seismo3d.data.synthetic import synthetic_cube

    *size, faults = spec.split(",")
    n0, n1, nt = (int(v) for v in size)
    sgy = root / f"cube_{n0}x{n1}x{nt}_{faults}.sgy"
    if not sgy.exists() and faults == "mosaic":  # the 256-trace tile of benchmarks/out_of_core.py mirrored
        from out_of_core import write_mosaic_segy

        write_mosaic_segy(sgy, (n0, n1, nt))
    elif not sgy.exists():
        write_segy(sgy, synthetic_cube((n0, n1, nt), n_faults=int(faults), seed=3).cube.astype(np.float32))
    return sgy, (n0, n1, nt), faults


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cube", action="append", help="n_inlines,n_xlines,n_samples,n_faults (repeatable); n_faults "
                    "'mosaic': benchmarks/out_of_core.py's mirrored tile (fault_paths.py's target: 400,400,500,mosaic)")
    ap.add_argument("--limit", default=None, help="--memory-limit (default: the smallest the refusal names)")
    ap.add_argument("--keep", type=pathlib.Path, default=None)
    args = ap.parse_args(argv)
    root = args.keep or pathlib.Path(tempfile.mkdtemp(prefix="post_block_memory_"))
    root.mkdir(parents=True, exist_ok=True)
    from seismo3d.errors import InputError

    for spec in args.cube or ["160,160,256,4"]:
        sgy, shape, n_faults = _cube(root, spec)
        limit = args.limit or "300MB"
        try:
            stages, run = _measure(sgy, root / f"out_{sgy.stem}", limit)
        except InputError as exc:  # the smallest limit that works, as the refusal names it
            import re

            limit = re.search(r"memory_limit='([^']+)'", str(exc)).group(1)
            stages, run = _measure(sgy, root / f"out_{sgy.stem}", limit)
        samples = int(np.prod(shape))
        print(f"\n{' x '.join(map(str, shape))}, {n_faults} faults, --memory-limit {limit}: by blocks "
              f"{run['by_blocks']}, {run['cells']} cells, {run['faults']} faults, {run['seconds']:.0f} s; process "
              f"at the plan {stages.process / 2**20:.0f} MiB", flush=True)
        print("stage | start MiB beyond | peak MiB beyond | peak B/cell | peak B/sample")
        for label, start, peak in stages.rows:
            beyond = peak - stages.process
            print(f"{label} | {(start - stages.process) / 2**20:.1f} | {beyond / 2**20:.1f} | "
                  f"{beyond / max(run['cells'], 1):.0f} | {beyond / samples:.2f}", flush=True)
        _models(shape, run["cells"], stages, limit)


def _models(shape, cells: int, stages: _Stages, limit: str) -> None:
    """The plan's model of each stage after the blocks with ``cells`` (code that has them), beside the peak."""
    try:
        from seismo3d.jobs.faults import _writer_stages
        from seismo3d.seismic.faults.pipeline import STAGE_GROWTH
        from seismo3d.seismic.faults.surfaces.blocks import held_stages
    except ImportError:
        return
    from seismo3d.seismic.blocks.memory import PROCESS_STEP, parse_memory_limit

    planned = -(-stages.process // PROCESS_STEP) * PROCESS_STEP + STAGE_GROWTH
    peak = max(p for _, _, p in stages.rows)
    print(f"plan: process {stages.process / 2**20:.0f} MiB counted as {planned / 2**20:.0f} with the growth; "
          f"measured peak {peak / 2**30:.3f} GiB, limit {parse_memory_limit(limit) / 2**30:.3f} GiB")
    for stage in held_stages(shape) + _writer_stages(shape):
        held = stage.held_bytes(cells)
        print(f"  {stage.name}: model {held / 2**20:.0f} MiB, planned peak {(planned + held) / 2**30:.3f} GiB")


if __name__ == "__main__":
    main()
