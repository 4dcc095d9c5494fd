"""The inputs of the ``seismo3d faults`` job: the file opened once, read whole or lazily as the memory decision says,
and the demo's generated cube.

Every input goes through the jobs' one reader (:func:`seismo3d.jobs.inputs.read_seismic`), which asks the memory
decision (``lazy_if``) with a 3D cube's shape before reading its samples, and gives the one input type,
:class:`~seismo3d.jobs.inputs.SeismicInput` (its traces labelled for the job's outputs).
"""

from __future__ import annotations

import csv
from pathlib import Path

import segyio

from .._atomic import atomic_path
from .._progress import LOGGER
from .inputs import SeismicInput, read_seismic

__all__ = ["DEMO_DT_MS", "DEMO_SHAPE", "LAZY_TILE", "read_input", "write_demo_input"]


DEMO_SHAPE = (128, 128, 128)  # the --demo cube: inlines x crosslines x samples
DEMO_DT_MS = 4.0  # its sample interval
LAZY_TILE = 32  # traces a side of a lazy input's chunks: a block of the run by blocks reads only the tiles around it


def read_input(path, *, iline, xline, ignore_geometry, sample_unit, n_samples, endian=None,
               lazy_if=None) -> SeismicInput:
    """The input through :func:`seismo3d.open` (:func:`~seismo3d.jobs.inputs.read_seismic`: its headers read once; a
    3D cube kept lazy when ``lazy_if(shape)`` says so, with chunks of :data:`LAZY_TILE` traces a side); a SEG-Y
    cube's or line's layout logged."""
    seismic = read_seismic(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, sample_unit=sample_unit,
                           n_samples=n_samples, endian=endian, lazy_if=None if ignore_geometry else lazy_if,
                           tile=LAZY_TILE)
    if seismic.kind in ("cube", "line"):
        LOGGER.info("%s: %s, %d samples of %g %s, %s, %s-endian", seismic.path.name, seismic.description,
                    seismic.samples.size, seismic.sample_interval, seismic.sample_unit, seismic.format_name,
                    seismic.endian)
    return seismic


def write_demo_input(out_dir: Path, seed) -> tuple[Path, Path]:
    """Write a synthetic cube as SEG-Y (4 ms, inlines / crosslines 1..128) and its true faults (CSV) into ``out_dir``;
    the two files' paths (the cube is then read like any SEG-Y input)."""
    from ..data.synthetic import synthetic_cube  # 0.5 s of imports (the data package): only for --demo

    syn = synthetic_cube(DEMO_SHAPE, seed=seed)
    path = out_dir / "demo_seismic.sgy"
    with atomic_path(path) as tmp:
        segyio.tools.from_array3D(str(tmp), syn.cube, format=5, dt=int(DEMO_DT_MS * 1000))
    truth = out_dir / "demo_truth.csv"
    with atomic_path(truth) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["id", "kind", "strike_deg", "dip_deg", "throw_samples", "throw_ms", "throw_gradient"])
        for f in syn.faults:
            signed = f.throw_samples if f.kind == "normal" else -f.throw_samples  # + = hanging wall down
            w.writerow([f.id, f.kind, f"{f.strike_deg:.1f}", f"{f.dip_deg:.1f}", f"{signed:.5g}",
                        f"{signed * DEMO_DT_MS:.5g}", f"{f.throw_gradient:.4g}"])
    del syn
    return path, truth
