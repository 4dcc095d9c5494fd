"""Interpretations that travel: what the ``faults``, ``horizon`` and ``render`` jobs write and read in the formats of
interpretation packages, in map coordinates.

* ``seismo3d faults`` writes, beside its other outputs (:func:`fault_interchange_steps`): ``fault_sticks_opendtect.txt``
  (OpendTect fault-stick ASCII), ``fault_sticks_charisma.txt`` and ``fault_sticks_iesx.txt`` (Charisma and IESX
  fault sticks, which Petrel imports), ``fault_sticks_rms.pol`` (RMS's XYZ polygons, which xtgeo reads),
  ``fault_surfaces_gocad/`` (a GOCAD TSurf file per fault, 3D inputs), and X / Y in ``fault_points.csv``.
* ``seismo3d horizon --maps`` writes the horizon as IRAP ASCII (``.fgr``), IRAP binary (``.gri``), ZMAP+ (``.zmap``)
  grids and ``X Y Z`` points (``.xyz``) beside its text file (:func:`write_horizon_maps`); ``--seed-file`` reads seeds
  from a file of picks (:func:`seeds_from_file`).
* ``seismo3d render --sticks`` draws fault sticks over the seismic (:func:`sticks_mesh`).

X / Y come from the SEG-Y trace headers (:mod:`seismo3d.seismic.io.coordinates`); an input without coordinates is
written in inline / crossline units, and every file says so.
"""

from __future__ import annotations

import functools
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..seismic.io.coordinates import SurveyCoordinates, cube_coordinates, read_survey_coordinates, survey_coordinates
from ..seismic.io.fault_sticks import FaultSticks, read_fault_sticks, write_fault_sticks
from ..seismic.io.tsurf import TriangulatedSurface, write_tsurf_folder

__all__ = ["FAULT_INTERCHANGE_FILES", "HORIZON_MAP_SUFFIXES", "fault_coordinates", "fault_interchange_steps",
           "horizon_map_paths", "write_horizon_maps", "seeds_from_file", "sticks_mesh"]

FAULT_INTERCHANGE_FILES = ("fault_sticks_opendtect.txt", "fault_sticks_charisma.txt", "fault_sticks_iesx.txt",
                           "fault_sticks_rms.pol", "fault_surfaces_gocad")
_STICK_FORMATS = {"sticks_opendtect": "opendtect", "sticks_charisma": "charisma", "sticks_iesx": "iesx",
                  "sticks_rms": "rms"}  # the stick files' keys in the job's outputs, in FAULT_INTERCHANGE_FILES' order
HORIZON_MAP_SUFFIXES = {"irap_ascii": ".fgr", "irap_binary": ".gri", "zmap": ".zmap", "xyz": ".xyz"}


# --------------------------------------------------------------------------------------------------------------------
# faults out


def fault_coordinates(inp, *, segy_path=None, iline: int = 189, xline: int = 193, ignore_geometry: bool = False,
                      endian=None) -> SurveyCoordinates:
    """The map coordinates of the faults job's input, shaped like its traced array's traces.

    Parameters
    ----------
    inp : SeismicInput
        The faults job's input (:class:`seismo3d.jobs.inputs.SeismicInput`): its ``amplitudes`` (3D cube or 2D
        section), ``segy_path`` (None for ``.npy`` / ``.f32be`` / Zarr inputs), ``inline_labels``,
        ``xline_labels``.
    segy_path : path-like, optional
        The SEG-Y file the input was read from, when ``inp`` does not name it (a cube read block by block).
    iline, xline, ignore_geometry, endian
        How the job read a SEG-Y input.

    Returns
    -------
    SurveyCoordinates
        (n_inlines, n_crosslines) for a cube, (n_traces,) for a 2D section; in inline / crossline units for inputs
        without coordinates.
    """
    cube = getattr(inp, "cube", None)
    segy_path = segy_path or getattr(inp, "segy_path", None)
    if segy_path is not None:  # from the cube seismo3d.open read (its headers read once), or from the file
        coords = cube_coordinates(cube) if cube is not None else read_survey_coordinates(
            segy_path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian)
        if coords.x.ndim == 1:  # a trace list: its traces labelled as the job labels them (fault_points.csv)
            xl = np.zeros(coords.x.size) if inp.xline_labels is None else np.asarray(inp.xline_labels, dtype=np.float64)
            return replace(coords, inline=np.asarray(inp.inline_labels, dtype=np.float64), crossline=xl)
        return coords.section() if inp.amplitudes.ndim == 2 else coords
    il = np.asarray(inp.inline_labels, dtype=np.float64)
    if inp.amplitudes.ndim == 3:
        grid = np.meshgrid(il, np.asarray(inp.xline_labels, dtype=np.float64), indexing="ij")
        return survey_coordinates(*grid)
    xl = np.zeros_like(il) if inp.xline_labels is None else np.asarray(inp.xline_labels, dtype=np.float64)
    return survey_coordinates(il, xl)


def _sticks(inp, result, coords: SurveyCoordinates) -> FaultSticks:
    unit = inp.sample_unit if inp.sample_unit in ("ms", "m", "ft") else "samples"
    return FaultSticks.from_faults(result.faults, coords, inp.samples, z_unit=unit)


def _fault_tsurf(inp, result, coords: SurveyCoordinates, path: Path, mesh=None) -> Path:
    """The triangulated faults of faults.vtp (:func:`seismo3d.viz.fault_surfaces`) as a folder of GOCAD TSurf files,
    ``fault_<id>.ts`` per fault: vertices at their traces' map X / Y (the CDP X / Y of the headers, scalar applied;
    inline / crossline numbers for an input without coordinates) and Z in the input's two-way time or depth;
    ``mesh``: that mesh when the job already made it (its points, ``fault_id`` and triangles are all this reads)."""
    from ..viz.fault_meshes import fault_surfaces

    mesh = fault_surfaces(result.faults, result.throws) if mesh is None else mesh
    points = np.asarray(mesh.points, dtype=np.float64)
    ids = np.asarray(mesh.point_data["fault_id"])
    faces = mesh.faces.reshape(-1, 4)[:, 1:] if mesh.n_cells else np.zeros((0, 3), np.int64)
    lateral = np.round(points[:, :2]).astype(np.int64)
    x, y = coords.at(lateral)
    z = np.interp(-points[:, 2], np.arange(inp.samples.size), inp.samples)
    surfaces = []
    for fid in np.unique(ids):
        keep = np.flatnonzero(ids == fid)
        tri = faces[np.isin(faces[:, 0], keep)]
        remap = np.full(points.shape[0], -1)
        remap[keep] = np.arange(keep.size)
        surfaces.append(TriangulatedSurface(f"fault_{int(fid)}", np.column_stack([x[keep], y[keep], z[keep]]),
                                            remap[tri], coords.unit, inp.sample_unit))
    return write_tsurf_folder(path, surfaces, source=inp.name)


def fault_interchange_steps(inp, result, out_dir, coords: SurveyCoordinates, *, mesh=None) -> list:
    """The writers of the faults job's interchange files, as ``(key, write)`` steps.

    Parameters
    ----------
    inp : the faults job's input
    result : FaultInterpretation
    out_dir : pathlib.Path
        Where to write (the job's staging folder).
    coords : SurveyCoordinates
        :func:`fault_coordinates` of ``inp``.
    mesh : callable, optional
        Returns the faults' mesh (:func:`seismo3d.viz.fault_surfaces` of ``result.faults`` and ``result.throws``,
        with or without ``axes``) or None; ``surfaces_tsurf`` triangulates the faults itself when it is not given
        or returns None (the job passes the mesh it wrote to ``faults.vtp``: one triangulation, not two).

    Returns
    -------
    list of (str, callable)
        ``sticks_opendtect``, ``sticks_charisma``, ``sticks_iesx``, ``sticks_rms`` and, for a 3D input with faults,
        ``surfaces_tsurf`` (a folder of a TSurf file per fault); each callable writes its file and returns its path.
    """
    out_dir = Path(out_dir)
    names = dict(zip(_STICK_FORMATS, FAULT_INTERCHANGE_FILES))

    sticks = functools.cache(lambda: _sticks(inp, result, coords))  # made once for the four layouts

    def sticks_writer(key: str, fmt: str):
        return lambda: write_fault_sticks(out_dir / names[key], sticks(), format=fmt, source=inp.name)

    steps = [(key, sticks_writer(key, fmt)) for key, fmt in _STICK_FORMATS.items()]
    if inp.amplitudes.ndim == 3 and len(result.faults):
        tsurf = out_dir / FAULT_INTERCHANGE_FILES[-1]
        steps.append(("surfaces_tsurf", lambda: _fault_tsurf(inp, result, coords, tsurf,
                                                             None if mesh is None else mesh())))
    return steps


# --------------------------------------------------------------------------------------------------------------------
# horizons out and seeds in


def horizon_map_paths(output) -> list:
    """The files ``seismo3d horizon --maps`` writes beside ``output``: ``<stem>.fgr``, ``.gri``, ``.zmap``,
    ``.xyz``."""
    output = Path(output)
    return [output.with_suffix(s) for s in HORIZON_MAP_SUFFIXES.values()]


def write_horizon_maps(output, survey, horizon, coordinates: SurveyCoordinates) -> dict:
    """Write a tracked horizon beside ``output`` as IRAP ASCII / binary and ZMAP+ grids and ``X Y Z`` points
    (a 2D line: points only), through xtgeo.

    Parameters
    ----------
    output : path-like
        The horizon job's text file; the maps take its stem.
    survey : the horizon job's survey
        ``data``, ``inlines``, ``xlines``, ``samples``, ``kind``.
    horizon : Horizon
        In index space (``times``: fractional samples; NaN where empty).
    coordinates : SurveyCoordinates
        The survey's coordinates (:func:`~seismo3d.seismic.io.coordinates.cube_coordinates` of the cube
        ``seismo3d.open`` read).

    Returns
    -------
    dict of str to pathlib.Path
    """
    from ..seismic.io.horizon_grids import write_horizon_grids

    k = np.asarray(horizon.times, dtype=np.float64)
    t = np.where(np.isfinite(k), np.interp(np.nan_to_num(k), np.arange(survey.samples.size), survey.samples), np.nan)
    stem = Path(output).with_suffix("")
    if survey.kind == "cube":
        return write_horizon_grids(stem, t, survey.inlines, survey.xlines, coordinates, name=stem.name)
    coords = coordinates.section()
    return write_horizon_grids(stem, t.ravel(), coords.inline, coords.crossline, coords, formats=("xyz",),
                               name=stem.name)


def seeds_from_file(path, coordinates: SurveyCoordinates, survey_name: str, *, trace_list: bool,
                    max_seeds: int = 64) -> list:
    """Horizon seeds from a file of picks, in the survey's terms, for ``seismo3d horizon --seed-file``.

    Parameters
    ----------
    path : path-like
        Picks: ``inline xline time`` rows, an IRAP / ZMAP+ grid or ``X Y Z`` points
        (:func:`~seismo3d.seismic.io.horizon_grids.read_horizon_picks`). Map picks are placed on the survey by its
        grid map, at the nearest trace.
    coordinates : SurveyCoordinates
        The survey's coordinates (:func:`~seismo3d.seismic.io.coordinates.cube_coordinates` of the cube
        ``seismo3d.open`` read).
    survey_name : str
        The survey's file name, for messages.
    trace_list : bool
        The survey is a trace list (a file without an inline / crossline grid): picks go to the nearest trace by
        X / Y.
    max_seeds : int
        At most this many picks are used, evenly spread through the file's picks on the survey (a grid of picks
        would otherwise give one seed per trace).

    Returns
    -------
    list of tuple
        ``(inline, crossline, time)`` per seed (``(trace, time)`` for a trace list, the nearest trace by X / Y).

    Raises
    ------
    InputError
        No pick of the file falls on the survey's traces.
    """
    from ..seismic.io.horizon_grids import read_horizon_picks

    picks = read_horizon_picks(path)
    coords = coordinates
    if trace_list:  # the nearest trace by X / Y
        d = np.hypot(coords.x[None, :] - picks.x[:, None], coords.y[None, :] - picks.y[:, None])
        trace = np.argmin(d, axis=1)
        ok = d[np.arange(trace.size), trace] <= _trace_spacing(coords)
        seeds = [(float(t + 1), float(z)) for t, z, good in zip(trace, picks.z, ok) if good]
    else:
        picks = picks.with_lines(coords)
        il, xl = np.round(picks.inline), np.round(picks.crossline)
        on = np.isin(il, np.unique(coords.inline)) & np.isin(xl, np.unique(coords.crossline))
        on &= np.hypot(picks.inline - il, picks.crossline - xl) <= 0.5
        seeds = [(float(a), float(b), float(z)) for a, b, z, good in zip(il, xl, picks.z, on) if good]
    if not seeds:
        raise InputError(f"no pick of {Path(path).name} falls on a trace of {survey_name}; pass picks of "
                         "this survey (same coordinates or line numbers)")
    step = max(1, int(np.ceil(len(seeds) / max_seeds)))
    return seeds[::step][:max_seeds]


def _trace_spacing(coords: SurveyCoordinates) -> float:
    d = np.hypot(np.diff(coords.x), np.diff(coords.y))
    return float(np.median(d)) if d.size else np.inf


# --------------------------------------------------------------------------------------------------------------------
# render: people's sticks over the seismic


def sticks_mesh(path, geometry, segy_path=None, *, segy_options=None):
    """Fault sticks of a file as a pyvista mesh of lines in the render scene's index space.

    Parameters
    ----------
    path : path-like
        A fault-stick file (:func:`~seismo3d.seismic.io.fault_sticks.read_fault_sticks`).
    geometry : CubeGeometry
        The scene's geometry (``inlines``, ``xlines``, ``samples``).
    segy_path : path-like, optional
        The seismic drawn: its grid map places nodes given only by X / Y, and fills X / Y given only by line numbers.
    segy_options : dict, optional
        How to read ``segy_path``.

    Returns
    -------
    pyvista.PolyData
        One polyline per stick at ``(inline index, crossline index, -sample index)``, point array ``fault_id``.

    Raises
    ------
    InputError
        Sticks that fall outside the drawn seismic.
    """
    import pyvista as pv

    coords = None
    if segy_path is not None:
        keep = ("iline", "xline", "ignore_geometry", "endian")
        options = {k: v for k, v in (segy_options or {}).items() if k in keep}
        coords = read_survey_coordinates(segy_path, **options)
    sticks = read_fault_sticks(path, coordinates=coords)
    il, xl = sticks.inline.copy(), sticks.crossline.copy()
    lost = ~(np.isfinite(il) & np.isfinite(xl))
    if lost.any() and coords is not None and coords.grid_map is not None:
        fixed = {}
        if coords.grid_map.is_line:
            key = "crossline" if np.any(coords.grid_map.inline_vector) else "inline"
            fixed[key] = float(np.ravel(getattr(coords, key))[0])
        il[lost], xl[lost] = coords.grid_map.to_lines(sticks.x[lost], sticks.y[lost], **fixed)

    def index(values, labels):
        labels = np.asarray(labels, dtype=np.float64)
        if labels.size == 1:
            return np.where(values == labels[0], 0.0, np.nan)
        order = np.argsort(labels)
        out = np.interp(values, labels[order], np.arange(labels.size, dtype=np.float64)[order], left=np.nan,
                        right=np.nan)
        return out

    i, j = index(il, geometry.inlines), index(xl, geometry.xlines)
    k = np.interp(sticks.z, geometry.samples, np.arange(geometry.samples.size), left=np.nan, right=np.nan)
    pts = np.column_stack([i, j, -k])
    if not np.all(np.isfinite(pts)):
        bad = int((~np.isfinite(pts).all(axis=1)).sum())
        raise InputError(f"{bad} of the {sticks.n_nodes} stick nodes of {Path(path).name} fall outside the seismic "
                         "drawn; pass the line or cube they were picked on (--seismic)")
    lines = []
    for _, nodes in sticks.sticks():
        lines += [nodes.size, *nodes.tolist()]
    mesh = pv.PolyData(pts, lines=np.asarray(lines, dtype=np.int64))
    mesh.point_data["fault_id"] = sticks.fault_id.astype(np.int32)
    mesh.point_data["throw"] = np.full(sticks.n_nodes, np.nan, np.float32)
    return mesh

