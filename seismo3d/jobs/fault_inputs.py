"""The inputs of the ``seismo3d faults`` job: the file opened once, read whole or lazily as the memory decision says
(:class:`FaultsInput`, labelled for the outputs), and the demo's generated cube.

Every input goes through the jobs' one reader (:func:`seismo3d.jobs.inputs.read_seismic`), which asks the memory
decision (``lazy_if``) with a 3D cube's shape before reading its samples; this module only labels what it read for
the job's outputs.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import segyio

from .._atomic import atomic_path
from .._progress import LOGGER
from .inputs import read_seismic

__all__ = ["DEMO_DT_MS", "DEMO_SHAPE", "FaultsInput", "LAZY_TILE", "read_input", "write_demo_input"]


DEMO_SHAPE = (128, 128, 128)  # the --demo cube: inlines x crosslines x samples
DEMO_DT_MS = 4.0  # its sample interval
LAZY_TILE = 32  # traces a side of a lazy input's chunks: a block of the run by blocks reads only the tiles around it


@dataclass(frozen=True)
class FaultsInput:
    """What the job read: the array it traces (in memory or lazy) and how to label and write results."""

    data: np.ndarray  # (n_il, n_xl, ns) 3D or (n_traces, ns) 2D; a float32 dask array (3D) when `lazy`
    name: str
    segy_path: Path | None  # template for SEG-Y outputs
    segy_shape: tuple | None  # the template's grid shape (cube.shape) to write 2D results back into
    inline: np.ndarray  # inline number per inline (3D) or per trace (2D; the trace index for raw sections)
    xline: np.ndarray | None  # crossline number per crossline (3D) or per trace (2D); None for raw sections
    samples: np.ndarray  # (ns,) sample positions in `unit` (sample index for 'samples')
    unit: str
    trace_axis: str = "trace"  # 2D: what labels the traces in pictures: 'inline', 'crossline' or 'trace' (index)
    sorting: str | None = None  # SEG-Y trace order of a grid: 'inline' or 'crossline'
    lazy: bool = False  # `data` is read block by block: the cube is traced by blocks
    cube: object = None  # `data` labelled: the xarray.DataArray of seismo3d.open (the input of trace_faults)

    @property
    def sample_interval(self) -> float | None:
        """The sample step in :attr:`unit`, None for an input in samples (``trace_faults``' ``sample_interval``)."""
        if self.unit == "samples":
            return None
        return float(self.samples[1] - self.samples[0]) if self.samples.size > 1 else 1.0

    @property
    def coords(self) -> dict:
        """Coordinates of a run by blocks' Zarr stores (``BlockRunOptions.coords``)."""
        return {"inline": self.inline, "crossline": self.xline, "sample": self.samples, "sample_unit": self.unit}

    def file_order(self, values: np.ndarray) -> np.ndarray:
        """(n_traces, n_samples) of an array shaped like ``data``, in the SEG-Y file's trace order."""
        ns = values.shape[-1]
        if self.segy_shape is None:  # trace list: already in file order (contiguous float32 for segyio)
            return np.ascontiguousarray(values.reshape(-1, ns), dtype=np.float32)
        grid = values.reshape(self.segy_shape)
        if self.sorting == "crossline":
            grid = np.swapaxes(grid, 0, 1)
        return np.ascontiguousarray(grid, dtype=np.float32).reshape(-1, ns)

    @property
    def axes(self) -> tuple:
        """Annotation of each array axis: (inlines, crosslines, samples) in 3D, (trace labels, samples) in 2D."""
        if self.data.ndim == 3:
            return (self.inline, self.xline, self.samples)
        lateral = {"inline": self.inline, "crossline": self.xline}.get(self.trace_axis)
        return (np.arange(self.data.shape[0]) if lateral is None else lateral, self.samples)

    @property
    def labels(self) -> tuple:
        """Axis names for pictures."""
        vertical = {"samples": "sample", "ms": "time (ms)", "m": "depth (m)", "ft": "depth (ft)"}[self.unit]
        if self.data.ndim == 3:
            return ("inline", "crossline", vertical)
        return (self.trace_axis, vertical)


def read_input(path, *, iline, xline, ignore_geometry, sample_unit, n_samples, endian=None,
               lazy_if=None) -> FaultsInput:
    """The input through :func:`seismo3d.open` (:func:`~seismo3d.jobs.inputs.read_seismic`: its headers read once; a
    3D cube kept lazy when ``lazy_if(shape)`` says so, with chunks of :data:`LAZY_TILE` traces a side), labelled for
    the outputs."""
    seismic = read_seismic(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, sample_unit=sample_unit,
                           n_samples=n_samples, endian=endian, lazy_if=None if ignore_geometry else lazy_if,
                           tile=LAZY_TILE)
    path, data, samples, unit, lazy = seismic.path, seismic.data, seismic.samples, seismic.sample_unit, seismic.lazy
    cube = seismic.cube
    if seismic.kind == "store":  # a Zarr store of seismo3d convert: labelled by its inline / crossline numbers
        return FaultsInput(data, path.name.split(".")[0], None, None, seismic.inlines.astype(np.int64),
                           seismic.xlines.astype(np.int64), samples, unit, lazy=lazy, cube=cube)
    if not seismic.is_segy:  # .npy, .f32be: traces labelled by their index
        idx = [np.arange(n, dtype=np.int64) for n in data.shape]
        return FaultsInput(data, path.stem, None, None, idx[0], idx[1] if data.ndim == 3 else None, samples, unit,
                           lazy=lazy, cube=cube)
    if seismic.kind == "trace list":  # label traces with their header inline / crossline numbers, if any
        il, xl = seismic.trace_inlines.astype(np.int64), seismic.trace_xlines.astype(np.int64)
        if np.all(il == il[0]) and np.all(xl == xl[0]):  # no numbers there: the trace index
            il, xl = np.arange(il.size, dtype=np.int64), None
        return FaultsInput(data, path.stem, path, None, il, xl, samples, unit, "trace", cube=cube)
    LOGGER.info("%s: %s, %d samples of %g %s, %s, %s-endian", path.name, seismic.description, samples.size,
                seismic.sample_interval, unit, seismic.format_name, seismic.endian)
    il, xl = seismic.inlines.astype(np.int64), seismic.xlines.astype(np.int64)
    shape, sorting = seismic.grid_shape, seismic.sorting
    if seismic.kind == "cube":
        return FaultsInput(data, path.stem, path, shape, il, xl, samples, unit, "trace", sorting, lazy, cube)
    if shape[1] == 1:  # a line along inlines (one crossline), e.g. penobscot_xl1155
        return FaultsInput(data[:, 0, :], path.stem, path, shape, il, np.full(il.size, xl[0]), samples, unit, "inline",
                           sorting, cube=cube)
    return FaultsInput(data[0], path.stem, path, shape, np.full(xl.size, il[0]), xl, samples, unit, "crossline", sorting,
                       cube=cube)


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
