"""The ``seismo3d horizon`` job: track a horizon in a SEG-Y cube or 2D line from seed picks and write it as text (and a
surface).

Seeds are given in the survey's terms (inline and crossline numbers, time or depth in the cube's sample unit) and
converted to index positions; on cubes the faults are traced first (:func:`seismo3d.seismic.trace_faults`; their jumps
are taken only where the correlation across them supports it), and the horizon is tracked by
:func:`seismo3d.seismic.track_horizon` (global least squares, then dynamic programming over candidate picks).
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, SegyGeometryError, UnsupportedDataError
from ..seismic.horizons import Horizon

__all__ = ["HorizonInput", "HorizonJob", "read_horizon_input", "run_horizon_job", "seed_index"]


@dataclass(frozen=True, eq=False)
class HorizonJob:
    """What :func:`run_horizon_job` did.

    Attributes
    ----------
    horizon : Horizon
        The tracked (and, with ``fill``, filled) horizon, index space.
    n_rows : int
        Rows written to the text file (tracked traces).
    output : pathlib.Path
        The text file.
    surface : pathlib.Path or None
        The surface file, when asked for.
    """

    horizon: Horizon
    n_rows: int
    output: pathlib.Path
    surface: pathlib.Path | None


def run_horizon_job(input_path, seeds, output, *, polarity: str = "peak", faults: bool | None = None,
                    fill: bool = False, surface=None, iline: int = 189, xline: int = 193,
                    ignore_geometry: bool = False, sample_unit=None, progress: bool = True) -> HorizonJob:
    """Track a horizon in a SEG-Y cube or 2D line from seed picks and write "inline xline time" rows.

    Parameters
    ----------
    input_path : str or path-like
        SEG-Y cube (inline- or crossline-sorted) or 2D line (a single inline or crossline, or any file read as a
        trace list with ``ignore_geometry``); only read.
    seeds : sequence of (float, float, float)
        Seed picks: inline number, crossline number, time (or depth) in the data's sample unit. On a 2D line the
        trace is the one whose header inline and crossline numbers match (a number that is the same on every trace
        of the line must match it).
    output : str or path-like
        The text file (written atomically; not the input).
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        The event the horizon follows.
    faults : bool or None
        Trace the faults first (:func:`seismo3d.seismic.trace_faults`) and let the tracker take their jumps where the
        correlation across them supports it. None (default): on 3D cubes, where faults can be traced in 3D, yes; on
        2D lines no. (The whole fault interpretation runs in memory.)
    fill : bool
        Fill empty traces by interpolation after tracking (:func:`seismo3d.seismic.fill_horizon`).
    surface : str or path-like, optional
        Also write the horizon as a surface (.vtp or .vtk; :func:`seismo3d.viz.horizon_surface`; 3D only).
    iline, xline : int
        Trace header bytes of the inline and crossline numbers.
    ignore_geometry : bool
        Read the file as a trace list (a 2D line, or a cube whose headers do not describe a grid).
    sample_unit : {'ms', 'm', 'ft'}, optional
        Unit of the sample axis; default from the SEG-Y headers.
    progress : bool
        Report progress (:mod:`seismo3d._progress`).

    Returns
    -------
    HorizonJob

    Raises
    ------
    InputError
        An output path that is the input, a seed outside the data or not on the line (the message names ``--seed``),
        a surface asked for a 2D line.
    UnsupportedDataError
        ``faults=True`` on data the fault tracer refuses.
    SegyGeometryError
        The file's geometry cannot be read at the given header bytes (try ``--ignore-geometry``).
    """
    from ..seismic import fill_horizon, trace_faults, track_horizon, write_horizon_text

    input_path, output = pathlib.Path(input_path), pathlib.Path(output)
    surface = None if surface is None else pathlib.Path(surface)
    if output.resolve() == input_path.resolve() or (surface is not None and surface.resolve() == input_path.resolve()):
        raise InputError(f"{output} would overwrite the input; choose another output path")
    grid = read_horizon_input(input_path, iline=iline, xline=xline, ignore_geometry=ignore_geometry,
                              sample_unit=sample_unit)
    if grid.data.ndim == 2 and surface is not None:
        raise InputError(f"{input_path.name} is a 2D line: --surface needs a 3D cube; leave it out")
    index_seeds = [grid.seed_index(s) for s in seeds]
    interp = None
    if faults or (faults is None and grid.data.ndim == 3):
        try:
            interp = trace_faults(grid.data, sample_interval=float(grid.samples[1] - grid.samples[0]),
                                  sample_unit=grid.unit, progress=progress)
        except (InputError, UnsupportedDataError):
            if faults:  # asked for: the refusal (e.g. a cube too small to trace) is the user's to see
                raise
    result = track_horizon(grid.data, index_seeds, polarity=polarity, faults=interp, progress=progress)
    if fill:
        result = fill_horizon(result)
    n = write_horizon_text(output, result, inlines=grid.inlines, xlines=grid.xlines, samples=grid.samples)
    if surface is not None:
        from ..viz import horizon_surface, save_polydata

        save_polydata(horizon_surface(result, inlines=grid.inlines, xlines=grid.xlines, samples=grid.samples), surface)
    return HorizonJob(result, n, output, surface)


@dataclass(frozen=True, eq=False)
class HorizonInput:
    """The data a horizon is tracked in, with its labels.

    Attributes
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
    inlines : (n_inlines,) or (n_traces,) int ndarray
        Inline numbers of the cube's grid, or of each trace of a 2D line.
    xlines : (n_xlines,) or (n_traces,) int ndarray
        Crossline numbers likewise.
    samples : (n_samples,) float64 ndarray
        The sample axis, ``unit``.
    unit : str
    """

    data: np.ndarray
    inlines: np.ndarray
    xlines: np.ndarray
    samples: np.ndarray
    unit: str

    def seed_index(self, seed) -> tuple:
        """A seed (inline, crossline, time) as an index position (3 values for a cube, 2 for a line); raises
        :class:`InputError` naming ``--seed``."""
        if self.data.ndim == 3:
            return seed_index(seed, self.inlines, self.xlines, self.samples, self.unit)
        il, xl, t = (float(v) for v in seed)
        text = f"{il:g},{xl:g},{t:g}"
        hit = np.nonzero((self.inlines == il) & (self.xlines == xl))[0]
        if hit.size == 0:
            raise InputError(f"--seed {text}: no trace of the line has inline {il:g} and crossline {xl:g} (inlines "
                             f"{self.inlines.min()}..{self.inlines.max()}, crosslines "
                             f"{self.xlines.min()}..{self.xlines.max()})")
        s = np.asarray(self.samples, dtype=np.float64)
        if not s[0] <= t <= s[-1]:
            raise InputError(f"--seed {text}: time {t:g} {self.unit} is outside the line's samples "
                             f"({s[0]:g}..{s[-1]:g} {self.unit})")
        return float(hit[0]), float(np.interp(t, s, np.arange(s.size)))


def read_horizon_input(path, *, iline: int = 189, xline: int = 193, ignore_geometry: bool = False,
                       sample_unit=None) -> HorizonInput:
    """Read a SEG-Y cube or 2D line for horizon tracking (see :func:`run_horizon_job`).

    Raises
    ------
    SegyGeometryError
        The geometry cannot be read at the given header bytes.
    """
    from ..seismic import open_segy

    with open_segy(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, sample_unit=sample_unit) as cube:
        data = np.asarray(cube.read(), dtype=np.float32)
        samples = np.asarray(cube.samples, dtype=np.float64)
        unit = cube.sample_unit
        if cube.is_3d:
            return HorizonInput(data, np.asarray(cube.inlines), np.asarray(cube.xlines), samples, unit)
        f = cube.segyfile
        il = np.asarray(f.attributes(cube.iline_byte)[:], dtype=np.int64)
        xl = np.asarray(f.attributes(cube.xline_byte)[:], dtype=np.int64)
    data = data.reshape(-1, data.shape[-1])  # a single inline or crossline, or a trace list: one line of traces
    if il.size != data.shape[0]:
        raise SegyGeometryError(f"{pathlib.Path(path).name}: {il.size} trace headers for {data.shape[0]} traces; "
                                "check --iline/--xline header bytes or pass --ignore-geometry")
    return HorizonInput(data, il, xl, samples, unit)


def seed_index(seed, inlines, xlines, samples, unit: str) -> tuple[float, float, float]:
    """A seed in the survey's terms to index space.

    Parameters
    ----------
    seed : (float, float, float)
        Inline number, crossline number, time or depth in ``unit``.
    inlines, xlines : (n,) array_like of int
        The cube's inline and crossline numbers.
    samples : (n_samples,) array_like of float
        The cube's sample axis, ``unit``.
    unit : str
        The sample unit, for messages.

    Returns
    -------
    (float, float, float)
        Inline index, crossline index, fractional sample index.

    Raises
    ------
    InputError
        A line number not in the cube, or a time outside its samples (the message names ``--seed``).
    """
    il, xl, t = (float(v) for v in seed)
    text = f"{il:g},{xl:g},{t:g}"
    where = []
    for name, value, labels in (("inline", il, inlines), ("crossline", xl, xlines)):
        hit = np.nonzero(np.asarray(labels) == value)[0]
        if hit.size == 0:
            raise InputError(f"--seed {text}: {name} {value:g} is not in the cube ({name}s {labels[0]}..{labels[-1]})")
        where.append(float(hit[0]))
    s = np.asarray(samples, dtype=np.float64)
    if not s[0] <= t <= s[-1]:
        raise InputError(f"--seed {text}: time {t:g} {unit} is outside the cube's samples ({s[0]:g}..{s[-1]:g} {unit})")
    return where[0], where[1], float(np.interp(t, s, np.arange(s.size)))
