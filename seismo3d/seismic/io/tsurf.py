"""GOCAD TSurf (``.ts``): triangulated fault surfaces in map coordinates, one surface per file, as xtgeo reads them
and Petrel, SKUA-GOCAD and OpendTect import them.

Each file holds one ``GOCAD TSurf 1`` object: its name, the coordinate system block (axis names and units;
``ZPOSITIVE Depth``: time and depth increase downward), and a ``TFACE`` of ``VRTX`` and ``TRGL`` lines (vertex ids
from 1). The header holds the name only, as xtgeo's reader requires. GOCAD's format lets one file hold several
objects one after the other, but xtgeo's reader (``xtgeo.triangulated_surface_from_file``) reads one object and
refuses the file at the second (``invalid line ... GOCAD TSurf 1``), so :func:`write_tsurf_folder` writes a folder of
one file per surface, which Petrel and OpendTect import together (a multiple selection in their import dialogs).

xtgeo writes TSurf too (``xtgeo.TriangulatedSurface``, marked experimental, without the unit of a time axis); this
writer adds the units (two-way time in ms) and needs no xtgeo; the tests read every file back with xtgeo's reader and
with a parser of the format's description.

References
----------
GOCAD ASCII file formats, *TSurf* (Paradigm / Emerson, GOCAD Developer's Guide, appendix "ASCII file formats"):
``GOCAD TSurf 1``, ``HEADER { name: ... }``, ``GOCAD_ORIGINAL_COORDINATE_SYSTEM`` ...
``END_ORIGINAL_COORDINATE_SYSTEM``, ``TFACE``, ``VRTX id x y z CNXYZ`` (as Petrel writes it, and xtgeo requires),
``TRGL i j k``, ``END``. xtgeo's reader: ``xtgeo/io/tsurf/_tsurf_io.py`` (xtgeo 4.x, one object per file).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..._atomic import atomic_directory, atomic_path
from ...errors import InputError
from .coordinates import LINE_UNITS
from .text_rows import TextColumn, format_rows

__all__ = ["TriangulatedSurface", "write_tsurf", "write_tsurf_folder"]


@dataclass(frozen=True, eq=False)
class TriangulatedSurface:
    """A named triangulated surface in map coordinates.

    Attributes
    ----------
    name : str
    vertices : (n, 3) float64 ndarray
        X, Y in ``xy_unit``, Z (two-way time or depth, increasing downward) in ``z_unit``.
    triangles : (m, 3) int64 ndarray
        Vertex indices from 0.
    xy_unit : {'m', 'ft', 'inline/crossline'}
    z_unit : {'ms', 'm', 'ft', 'samples'}
    """

    name: str
    vertices: np.ndarray
    triangles: np.ndarray
    xy_unit: str = "m"
    z_unit: str = "ms"

    def __post_init__(self):
        v, t = np.asarray(self.vertices), np.asarray(self.triangles)
        if v.ndim != 2 or v.shape[1] != 3 or not np.all(np.isfinite(v)):
            raise InputError(f"surface {self.name!r}: vertices must be a finite (n, 3) array; got {v.shape}")
        if t.size and (t.ndim != 2 or t.shape[1] != 3 or t.min() < 0 or t.max() >= v.shape[0]):
            raise InputError(f"surface {self.name!r}: triangles must be (m, 3) indices into its {v.shape[0]} "
                             "vertices")


def _name(text: str) -> str:
    return re.sub(r"\s+", "_", str(text)) or "surface"


def write_tsurf(path, surface: TriangulatedSurface, *, source: str = "") -> Path:
    """Write one triangulated surface as a GOCAD TSurf file (one ``GOCAD TSurf 1`` object), atomically.

    Parameters
    ----------
    path : str or os.PathLike
        The file (its folder must exist).
    surface : TriangulatedSurface
        With at least one triangle.
    source : str, optional
        Written as a ``#`` comment line after the header (where the surface comes from).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        A surface without triangles.

    Notes
    -----
    A survey without coordinates (``xy_unit='inline/crossline'``) is written with axis names ``INLINE`` and
    ``CROSSLINE`` and unit ``"none"``, so that no reader takes line numbers for metres.
    """
    if not np.asarray(surface.triangles).size:
        raise InputError(f"surface {surface.name!r} has no triangles to write; a 2D line's faults are curves (write "
                         "them as fault sticks)")
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "w", newline="\n") as fh:
        fh.writelines(_tsurf_text(surface, source))  # a block of rows at a time: a large fault is never held whole
    return path


def write_tsurf_folder(folder, surfaces, *, source: str = "") -> Path:
    """Write triangulated surfaces as a folder of GOCAD TSurf files, ``<name>.ts`` per surface, written whole.

    Parameters
    ----------
    folder : str or os.PathLike
        The folder to make (its parent must exist); an existing one is replaced once every file is written.
    surfaces : sequence of TriangulatedSurface
        One file each (white space in names replaced by ``_``); surfaces without triangles are left out.
    source : str, optional
        Written as a ``#`` comment line after each header.

    Returns
    -------
    pathlib.Path
        The folder.

    Raises
    ------
    InputError
        No surface with triangles, or two surfaces of one name.
    """
    surfaces = [s for s in surfaces if np.asarray(s.triangles).size]
    if not surfaces:
        raise InputError("no surface with triangles to write; a 2D line's faults are curves (write them as fault "
                         "sticks)")
    names = [_name(s.name) for s in surfaces]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InputError(f"surfaces named {', '.join(twice)} more than once; give each surface its own name (one "
                         "file per name)")
    folder = Path(folder)
    with atomic_directory(folder) as tmp:
        for name, s in zip(names, surfaces):
            write_tsurf(tmp / f"{name}.ts", s, source=source)
    return folder


def _tsurf_text(s: TriangulatedSurface, source: str):
    """The text of one surface's ``GOCAD TSurf 1`` object: its header lines, then blocks of ``VRTX`` and ``TRGL``
    rows (:data:`~seismo3d.seismic.io.text_rows.ROWS` at a time), every line ended by a line feed."""
    lines_units = s.xy_unit == LINE_UNITS
    axis_names = '"INLINE" "CROSSLINE" "Z"' if lines_units else '"X" "Y" "Z"'
    xy = "none" if lines_units else s.xy_unit
    z = {"samples": "none"}.get(s.z_unit, s.z_unit)
    header = ["GOCAD TSurf 1", "HEADER {", f"name: {_name(s.name)}", "}"]
    if source:
        header.append(f"# written by seismo3d from {source}")
    header += ["GOCAD_ORIGINAL_COORDINATE_SYSTEM", "NAME Default", f"AXIS_NAME {axis_names}",
               f'AXIS_UNIT "{xy}" "{xy}" "{z}"', "ZPOSITIVE Depth", "END_ORIGINAL_COORDINATE_SYSTEM", "TFACE"]
    yield "".join(line + "\n" for line in header)
    # one % of the row template over a block of rows' numbers (text_rows): the same text as per-row f-strings
    vertices = np.asarray(s.vertices, dtype=np.float64)
    n = vertices.shape[0]
    yield from format_rows([TextColumn("VRTX"), TextColumn(np.arange(1, n + 1), "d"), TextColumn(vertices[:, 0], ".3f"),
                            TextColumn(vertices[:, 1], ".3f"), TextColumn(vertices[:, 2], ".4f"), TextColumn("CNXYZ")],
                           n, sep=" ")
    triangles = np.asarray(s.triangles, dtype=np.int64).reshape(-1, 3) + 1
    yield from format_rows([TextColumn("TRGL"), *(TextColumn(triangles[:, i], "d") for i in range(3))],
                           triangles.shape[0], sep=" ")
    yield "END\n"
