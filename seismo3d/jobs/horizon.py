"""The ``seismo3d horizon`` job: track a horizon in a SEG-Y cube from seed picks and write it as text (and a surface).

Seeds are given in the survey's terms (inline and crossline numbers, time or depth in the cube's sample unit) and
converted to index positions; the faults are traced first when asked (:func:`seismo3d.seismic.trace_faults`), and the
horizon is tracked by registering neighbouring inlines (:func:`seismo3d.seismic.track_horizon`).
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, SegyGeometryError
from ..seismic.horizons import Horizon

__all__ = ["HorizonJob", "run_horizon_job"]


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


def run_horizon_job(input_path, seeds, output, *, polarity: str = "peak", faults: bool = False, fill: bool = False,
                    surface=None, iline: int = 189, xline: int = 193, endian=None, progress: bool = True) -> HorizonJob:
    """Track a horizon in a SEG-Y cube from seed picks and write "inline xline time" rows.

    Parameters
    ----------
    input_path : str or path-like
        SEG-Y cube (inline- or crossline-sorted, either byte order), read by :func:`~seismo3d.seismic.open_segy`;
        only read.
    seeds : sequence of (float, float, float)
        Seed picks: inline number, crossline number, time (or depth) in the cube's sample unit.
    output : str or path-like
        The text file (written atomically; not the input).
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        The event the horizon follows.
    faults : bool
        Trace the faults first and jump across them by their throw (the whole fault interpretation runs in memory).
    fill : bool
        Fill empty traces by interpolation after tracking (:func:`seismo3d.seismic.fill_horizon`).
    surface : str or path-like, optional
        Also write the horizon as a surface (.vtp or .vtk; :func:`seismo3d.viz.horizon_surface`).
    iline, xline : int
        Trace header bytes of the inline and crossline numbers.
    endian : {'big', 'little'}, optional
        Byte order of the file; by default detected from its binary header.
    progress : bool
        Report progress (:mod:`seismo3d._progress`).

    Returns
    -------
    HorizonJob

    Raises
    ------
    InputError
        An output path that is the input, a seed outside the cube (the message names ``--seed``).
    SegyGeometryError
        The file is not a 3D cube (the message says what it is: a 2D line, a trace list), or holds prestack gathers.
    SegyFormatError
        The file is not SEG-Y or cannot be read (see :func:`~seismo3d.seismic.open_segy`).
    """
    from ..seismic import fill_horizon, open_segy, trace_faults, track_horizon, write_horizon_text

    input_path, output = pathlib.Path(input_path), pathlib.Path(output)
    surface = None if surface is None else pathlib.Path(surface)
    if output.resolve() == input_path.resolve() or (surface is not None and surface.resolve() == input_path.resolve()):
        raise InputError(f"{output} would overwrite the input; choose another output path")
    with open_segy(input_path, iline=iline, xline=xline, endian=endian) as cube:
        if not cube.is_3d:
            raise SegyGeometryError(f"{input_path.name} is {cube.description}, not a 3D cube; horizon tracking needs "
                                    "inlines and crosslines: give it a 3D cube")
        data = cube.read()
        inlines, xlines, samples = cube.inlines, cube.xlines, cube.samples
        unit = cube.sample_unit
    index_seeds = [seed_index(s, inlines, xlines, samples, unit) for s in seeds]
    interp = None
    if faults:
        interp = trace_faults(data, sample_interval=float(samples[1] - samples[0]), sample_unit=unit,
                              progress=progress)
    result = track_horizon(data, index_seeds, polarity=polarity, faults=interp, progress=progress)
    if fill:
        result = fill_horizon(result)
    n = write_horizon_text(output, result, inlines=inlines, xlines=xlines, samples=samples)
    if surface is not None:
        from ..viz import horizon_surface, save_polydata

        save_polydata(horizon_surface(result, inlines=inlines, xlines=xlines, samples=samples), surface)
    return HorizonJob(result, n, output, surface)


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
