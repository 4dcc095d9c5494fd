"""Fault sticks: the points of each fault along each line, in map coordinates, as interpreters exchange them.

A :class:`FaultSticks` holds the nodes of every stick of every fault (X, Y, two-way time or depth, and the inline /
crossline of each node). It is made from traced faults (:meth:`FaultSticks.from_faults`) or read from a file
(:func:`read_fault_sticks`), and written in four layouts (:func:`write_fault_sticks`):

* ``'opendtect'``: OpendTect's fault-stick ASCII, tab-separated, one row per node: fault name (quoted), X, Y, Z,
  stick index, node index, inline, crossline; ``#`` lines first say what the columns are. OpendTect's *Import
  Fault / FaultStickSet (ASCII)* reads it with the column numbers set in its format definition.
* ``'charisma'``: the Charisma fault-stick layout that Petrel imports (*Charisma fault sticks*), space-separated,
  one row per node: ``INLINE-``, inline, crossline, X, Y, Z, fault name, stick number.
* ``'iesx'``: GeoQuest IESX fault sticks, fixed columns: per fault a ``PROFILE <name> TYPE ...`` line and a
  ``SNAPPING PARAMETERS`` line, then one row per node with X in characters 0-16, Y in 16-32 (``%16.8E``: 0.01 m at
  6 million), the stick index in 32-35, Z in 38-47 (``%9.2f``); ``EOD`` ends the file. The rows carry no line
  numbers: a reader places them by X / Y.
* ``'rms'``: RMS's XYZ polygons, as xtgeo reads them (``xtgeo.polygons_from_file(path, fformat="xyz")``): one
  ``X Y Z`` row per node, each stick one polygon ended by ``999.0 999.0 999.0``. The rows carry no fault names and no
  line numbers; seismo3d writes this layout but does not read it.

Readers accept the first three, and the export of the data folder's interpreter (``seismic/gsb_fault_sticks/*.dat``:
tab-separated X, Y (1e30 = undefined), two-way time, three stick-orientation columns, inline, crossline; each two
consecutive rows are the two ends of one stick, one fault per stick).

References
----------
OpendTect User Documentation, *Import / Export Faults and FaultStickSets (ASCII)*, dGB Earth Sciences.
Charisma fault-stick rows as read by seismiqb (``FaultSticksMixin.FAULT_STICKS_SPEC``: ``INLINE-``, inline,
crossline, CDP X, CDP Y, depth, name, number), https://github.com/gazprom-neft/seismiqb.
IESX fault rows: DUG Insight, *Importing a fault* (GeoQuest IESX format: X [0-16), Y [16-32), stick index [32-35),
Z [38-47)), https://help.dugeo.com/m/Insight/l/438710-importing-a-fault; the ``PROFILE`` and ``SNAPPING
PARAMETERS`` header lines as OpendTect's IESX (3d_ci7m) writer lays them out; ``EOD`` as the IESX loader expects
(Schlumberger IESX FAQ 399).
RMS XYZ polygons: xtgeo's ``Polygons`` text format (``xtgeo.xyz._xyz_io``, the ``999.0`` polygon terminator),
https://github.com/equinor/xtgeo.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..._atomic import atomic_path
from ...errors import DataNotFoundError, InputError
from .coordinates import LINE_UNITS, SurveyCoordinates
from .stick_sections import section_nodes, section_pixels
from .stick_rows import charisma_rows, iesx_rows, opendtect_rows, rms_rows
from .traced_sticks import STICK_LINE_STEP, stick_lines, stick_nodes

__all__ = ["FaultSticks", "READ_STICK_FORMATS", "STICK_FORMATS", "read_fault_sticks", "write_fault_sticks"]

STICK_FORMATS = ("opendtect", "charisma", "iesx", "rms")  # the layouts write_fault_sticks writes
READ_STICK_FORMATS = ("opendtect", "charisma", "iesx")  # those read_fault_sticks reads (RMS polygons name no faults)
_UNDEFINED = 1e29  # OpendTect writes 1e30 for an undefined X / Y


@dataclass(frozen=True, eq=False)
class FaultSticks:
    """The nodes of the sticks of one or more faults.

    Attributes
    ----------
    fault_id : (n,) int64 ndarray
        The fault of each node, 1..len(names).
    stick : (n,) int64 ndarray
        The stick of each node, 0..n_sticks - 1 over the whole set (a stick belongs to one fault); nodes of a stick
        are consecutive, in order along it.
    x, y : (n,) float64 ndarray
        Map coordinates in :attr:`xy_unit`; NaN where unknown (a file's undefined X / Y without coordinates to
        fill them).
    z : (n,) float64 ndarray
        Two-way time or depth, :attr:`z_unit`.
    inline, crossline : (n,) float64 ndarray
        Inline and crossline numbers of each node (fractional allowed); NaN where unknown.
    names : tuple of str
        The name of fault ``i`` at ``names[i - 1]``.
    z_unit : {'ms', 'm', 'ft', 'samples'}
    xy_unit : {'m', 'ft', 'inline/crossline'}
        ``'inline/crossline'`` when the survey has no coordinates (X, Y are then the inline and crossline numbers).
    """

    fault_id: np.ndarray
    stick: np.ndarray
    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    inline: np.ndarray
    crossline: np.ndarray
    names: tuple
    z_unit: str = "ms"
    xy_unit: str = "m"

    def __post_init__(self):
        n = self.fault_id.shape[0]
        for name in ("stick", "x", "y", "z", "inline", "crossline"):
            if getattr(self, name).shape != (n,):
                raise InputError(f"FaultSticks.{name} must have shape ({n},); got {getattr(self, name).shape}")

    @property
    def n_nodes(self) -> int:
        return int(self.fault_id.size)

    @property
    def n_sticks(self) -> int:
        return int(np.unique(self.stick).size)

    @property
    def n_faults(self) -> int:
        return int(np.unique(self.fault_id).size)

    def sticks(self):
        """Yield ``(fault_id, node_indices)`` per stick, in stick order; ``node_indices`` index the node arrays."""
        order = np.argsort(self.stick, kind="stable")
        bounds = np.flatnonzero(np.diff(self.stick[order])) + 1
        for nodes in np.split(order, bounds):
            if nodes.size:
                yield int(self.fault_id[nodes[0]]), nodes

    def take(self, nodes) -> "FaultSticks":
        """The sticks of some nodes (whole sticks, as :meth:`sticks` yields them), with the same faults' names.

        Parameters
        ----------
        nodes : (k,) int ndarray
            Indices into the node arrays.

        Returns
        -------
        FaultSticks
        """
        n = np.asarray(nodes, dtype=np.int64)
        return FaultSticks(self.fault_id[n], self.stick[n], self.x[n], self.y[n], self.z[n], self.inline[n],
                           self.crossline[n], self.names, self.z_unit, self.xy_unit)

    def with_coordinates(self, coordinates: SurveyCoordinates) -> "FaultSticks":
        """The sticks with undefined X / Y filled from their inline / crossline numbers through the survey's grid
        map (the file's own X / Y kept where defined).

        Parameters
        ----------
        coordinates : SurveyCoordinates
            Of the survey the sticks were picked in (:func:`~seismo3d.seismic.io.coordinates.read_survey_coordinates`).

        Returns
        -------
        FaultSticks

        Raises
        ------
        InputError
            Nodes without X / Y and without inline / crossline numbers, or a survey without a grid map.
        """
        missing = ~(np.isfinite(self.x) & np.isfinite(self.y))
        if not missing.any():
            return self
        if coordinates.grid_map is None:
            raise InputError("the survey's traces follow no grid map, so undefined stick X / Y cannot be computed "
                             f"from inline / crossline ({coordinates.grid_problem})")
        if not np.all(np.isfinite(self.inline[missing]) & np.isfinite(self.crossline[missing])):
            raise InputError("some stick nodes have neither X / Y nor inline / crossline numbers; fix the file")
        x, y = self.x.copy(), self.y.copy()
        x[missing], y[missing] = coordinates.grid_map.to_xy(self.inline[missing], self.crossline[missing])
        return FaultSticks(self.fault_id, self.stick, x, y, self.z, self.inline, self.crossline, self.names,
                           self.z_unit, coordinates.unit)

    def with_lines(self, coordinates: SurveyCoordinates) -> "FaultSticks":
        """The sticks with missing inline / crossline numbers computed from their X / Y through the survey's grid
        map (a map of a single line: projected onto the line).

        Parameters
        ----------
        coordinates : SurveyCoordinates

        Returns
        -------
        FaultSticks

        Raises
        ------
        InputError
            A survey without a grid map.
        """
        missing = ~(np.isfinite(self.inline) & np.isfinite(self.crossline))
        if not missing.any():
            return self
        gm = coordinates.grid_map
        if gm is None:
            raise InputError("the survey's traces follow no grid map, so the sticks' X / Y cannot be placed on its "
                             f"lines ({coordinates.grid_problem})")
        fixed = {}
        if gm.is_line:
            key = "crossline" if np.any(gm.inline_vector) else "inline"
            fixed[key] = float(np.ravel(getattr(coordinates, key))[0])
        il, xl = self.inline.copy(), self.crossline.copy()
        il[missing], xl[missing] = gm.to_lines(self.x[missing], self.y[missing], **fixed)
        return FaultSticks(self.fault_id, self.stick, self.x, self.y, self.z, il, xl, self.names, self.z_unit,
                           self.xy_unit)

    def section_lines(self, trace_labels, samples, *, axis: str = "inline") -> list:
        """The sticks as lines on a 2D section, in index space, for the fault evaluation
        (:func:`~seismo3d.seismic.fault_line_coverage`).

        Parameters
        ----------
        trace_labels : (n_traces,) array_like of float
            The section's inline (or crossline) number of each trace, monotonic.
        samples : (n_samples,) array_like of float
            Its sample axis, in :attr:`z_unit`.
        axis : {'inline', 'crossline'}
            Which number labels the traces.

        Returns
        -------
        list of (k, 2) float64 ndarray
            Per stick, its nodes as (trace index, fractional sample index), samples increasing.
        """
        return [line[np.argsort(line[:, 1], kind="stable")]
                for _, line in section_nodes(self, trace_labels, samples, axis=axis)]

    def section_mask(self, trace_labels, samples, *, axis: str = "inline") -> np.ndarray:
        """The sticks drawn on a 2D section as fault labels (each stick's fault id on the samples it crosses, placed
        by :func:`~seismo3d.seismic.io.stick_sections.section_pixels`), for :func:`~seismo3d.seismic.evaluate_faults`.

        Parameters
        ----------
        trace_labels, samples, axis
            As :meth:`section_lines`.

        Returns
        -------
        (n_traces, n_samples) int32 ndarray
            The fault id on stick samples (the later stick's where two cross), 0 elsewhere.
        """
        mask = np.zeros((np.asarray(trace_labels).size, np.asarray(samples).size), dtype=np.int32)
        for fid, pixels in section_pixels(self, trace_labels, samples, axis=axis):
            mask[pixels[:, 0], pixels[:, 1]] = fid
        return mask

    @classmethod
    def from_faults(cls, faults, coordinates: SurveyCoordinates, samples, *, z_unit: str = "ms", names=None,
                    line_step: int = STICK_LINE_STEP, tolerance: float = 1.0) -> "FaultSticks":
        """The sticks of traced faults, as an interpreter draws them: one stick per fault per section, from the
        fault's top to its bottom, with a node where it bends.

        On a 2D section a fault is one stick. In 3D the sticks lie on every ``line_step``-th inline or crossline,
        whichever cuts the fault across its strike (:func:`~seismo3d.seismic.io.traced_sticks.stick_lines`). On
        each section the fault's samples become one stick (:func:`~seismo3d.seismic.io.traced_sticks.stick_nodes`):
        a single-valued function of time (a strand folding back is left out, not drawn as a zigzag), its nodes
        where the fault bends, every other sample of the fault within ``tolerance`` of it, times strictly
        increasing along it. Every node is a fault sample, at its trace's own coordinates.

        Parameters
        ----------
        faults : sequence of Fault
            From :func:`~seismo3d.seismic.trace_faults` (``FaultInterpretation.faults``): ``points`` (n, 3) (inline,
            crossline, sample indices) or (n, 2) (trace, sample indices).
        coordinates : SurveyCoordinates
            Of the traced array: lateral shape (n_inlines, n_crosslines) in 3D, (n_traces,) for a section
            (:meth:`SurveyCoordinates.section` of a line of a survey).
        samples : (n_samples,) array_like of float
            The sample axis in ``z_unit``.
        z_unit : {'ms', 'm', 'ft', 'samples'}
        names : sequence of str, optional
            Fault names; default ``fault_<id>``.
        line_step : int
            In 3D, a stick on every ``line_step``-th line of the traced array, counted from its first (>= 1).
        tolerance : float
            Largest distance of a fault sample from its stick, in samples (the section's index space; > 0).

        Returns
        -------
        FaultSticks
            Fault ids renumbered 1.. in the order of ``faults``; sticks in order of their line, nodes in order of
            time. A fault that spans one sample of time on every line has no stick.

        Raises
        ------
        InputError
            Points that do not fit ``coordinates``' shape; ``line_step`` < 1 or ``tolerance`` <= 0.
        """
        s = np.asarray(samples, dtype=np.float64)
        parts = {k: [] for k in ("fault_id", "stick", "x", "y", "z", "inline", "crossline")}
        faults = list(faults)
        names = tuple(names) if names is not None else tuple(f"fault_{int(f.id)}" for f in faults)
        n_sticks = 0
        for number, fault in enumerate(faults, start=1):
            p = np.asarray(fault.points, dtype=np.int64)
            lateral = p[:, :-1]
            if lateral.shape[1] != coordinates.x.ndim or np.any(lateral.max(axis=0) >= coordinates.x.shape):
                raise InputError(f"fault {fault.id}'s points {p.shape} do not fit coordinates of shape "
                                 f"{coordinates.x.shape}; pass the coordinates of the traced array")
            if p.shape[1] == 3:  # a cube: a stick on each of the lines across the fault's strike
                axis, lines = stick_lines(p, line_step=line_step)
                sections = [(p[p[:, axis] == line], 1 - axis) for line in lines]
            else:
                sections = [(p, 0)]
            for q, along in sections:
                q = q[stick_nodes(q[:, along], q[:, -1], tolerance=tolerance)[0]]
                x, y = coordinates.at(q[:, :-1])
                il, xl = coordinates.lines_at(q[:, :-1])
                parts["fault_id"].append(np.full(q.shape[0], number))
                parts["stick"].append(np.full(q.shape[0], n_sticks))
                parts["x"].append(x)
                parts["y"].append(y)
                parts["z"].append(np.interp(q[:, -1].astype(np.float64), np.arange(s.size), s))
                parts["inline"].append(il)
                parts["crossline"].append(xl)
                n_sticks += 1
        arrays = {k: (np.concatenate(v) if v else np.zeros(0)) for k, v in parts.items()}
        return cls(arrays["fault_id"].astype(np.int64), arrays["stick"].astype(np.int64),
                   *(arrays[k].astype(np.float64) for k in ("x", "y", "z", "inline", "crossline")),
                   names=names, z_unit=z_unit, xy_unit=coordinates.unit)


# --------------------------------------------------------------------------------------------------------------------
# writing


def write_fault_sticks(path, sticks: FaultSticks, *, format: str = "opendtect", source: str = "") -> Path:
    """Write fault sticks in OpendTect's fault-stick ASCII, Charisma's, IESX's or RMS's polygon layout, atomically.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write (its folder must exist); replaced atomically.
    sticks : FaultSticks
    format : {'opendtect', 'charisma', 'iesx', 'rms'}
        ``'opendtect'``: ``#`` comment lines naming the columns and units, then tab-separated rows ``"name" X Y Z
        stick node inline crossline`` (stick and node indices from 0 per fault; undefined X / Y as 1e30).
        ``'charisma'``: no header; space-separated rows ``INLINE- inline crossline X Y Z name stick`` (stick numbers
        from 1 per fault; inline / crossline rounded to whole numbers, as the format holds them). ``'iesx'``: fixed
        columns (module docstring); stick indices from 1 per fault; nodes without X / Y are refused. ``'rms'``: ``X Y
        Z`` rows, each stick ended by ``999.0 999.0 999.0`` (xtgeo's XYZ polygons); nodes without X / Y are refused.
    source : str, optional
        A line for the OpendTect header saying where the sticks come from.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        An unknown ``format``, ``'charisma'`` for sticks without inline / crossline numbers, or ``'iesx'`` / ``'rms'``
        for sticks without X / Y.

    References
    ----------
    See the module docstring.
    """
    if format not in STICK_FORMATS:
        raise InputError(f"format={format!r} is not a fault-stick format; use one of {', '.join(STICK_FORMATS)}")
    path = Path(path)
    if format in ("iesx", "rms"):
        return _write_xyz_rows(path, sticks, format)
    header = []
    if format == "opendtect":
        xy = ("X, Y: inline and crossline numbers (the SEG-Y headers hold no coordinates)"
              if sticks.xy_unit == LINE_UNITS else f"X, Y: map coordinates in {sticks.xy_unit}")
        zname = {"ms": "two-way time (ms)", "m": "depth (m)", "ft": "depth (ft)"}.get(sticks.z_unit, "sample index")
        header = ["# OpendTect fault sticks (ASCII), written by seismo3d" + (f" from {source}" if source else ""),
                  f"# columns: fault name, X, Y, Z, stick index, node index, inline, crossline; {xy}; Z: {zname}",
                  f"# {sticks.n_faults} faults, {sticks.n_sticks} sticks, {sticks.n_nodes} nodes"]
    elif not (np.all(np.isfinite(sticks.inline)) and np.all(np.isfinite(sticks.crossline))):
        raise InputError("Charisma fault sticks need inline / crossline numbers; these sticks have none")
    rows = opendtect_rows(sticks) if format == "opendtect" else charisma_rows(sticks)
    with atomic_path(path) as tmp, open(tmp, "w", newline="\n") as fh:  # a block of rows at a time: never all the text
        fh.writelines(line + "\n" for line in header)
        fh.writelines(rows)
    return path


def _write_xyz_rows(path: Path, sticks: FaultSticks, format: str) -> Path:
    """The layouts placed by X / Y alone: IESX fault sticks (PROFILE / SNAPPING PARAMETERS per fault, fixed-column
    node rows, EOD) and RMS's XYZ polygons."""
    if not (np.all(np.isfinite(sticks.x)) and np.all(np.isfinite(sticks.y))):
        raise InputError(f"{format.upper()} fault sticks need X / Y on every node; fill them first "
                         "(FaultSticks.with_coordinates)")
    rows = iesx_rows(sticks) if format == "iesx" else rms_rows(sticks)
    with atomic_path(path) as tmp, open(tmp, "w", newline="\n") as fh:  # a block of rows at a time: never all the text
        fh.writelines(rows)
    return path


# --------------------------------------------------------------------------------------------------------------------
# reading


def _data_lines(path: Path) -> list:
    return [line.rstrip("\n") for line in path.read_text(errors="replace").splitlines()]


def _sniff(lines: list) -> str:
    for line in lines:
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        if text.upper().startswith("INLINE-"):
            return "charisma"
        if text.upper().startswith("PROFILE"):
            return "iesx"
        if text.startswith('"'):
            return "opendtect"
        fields = text.split()
        try:
            [float(v) for v in fields]
        except ValueError:
            break
        if len(fields) == 8:
            return "opendtect_pairs"
        break
    return "unknown"


def read_fault_sticks(path, *, coordinates: SurveyCoordinates | None = None, z_unit: str = "ms") -> FaultSticks:
    """Read fault sticks: OpendTect's fault-stick ASCII (as :func:`write_fault_sticks` writes it, or the
    interpreter's export of the data folder), Charisma or IESX fault sticks.

    Parameters
    ----------
    path : str or os.PathLike
    coordinates : SurveyCoordinates, optional
        The survey's coordinates: undefined X / Y (1e30) are filled from the nodes' inline / crossline numbers
        through its grid map (:meth:`FaultSticks.with_coordinates`), and nodes without line numbers (IESX) get
        them from their X / Y; without it they stay NaN.
    z_unit : {'ms', 'm', 'ft'}
        Unit of Z in the file (the formats do not say).

    Returns
    -------
    FaultSticks

    Raises
    ------
    DataNotFoundError
        No such file.
    InputError
        A file in none of these layouts, or rows that cannot be read (the message names the line).
    """
    path = Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"no fault-stick file at {path}; check the path")
    lines = _data_lines(path)
    layout = _sniff(lines)
    if layout == "unknown":
        raise InputError(f"{path.name} is not a fault-stick file seismo3d reads: expected OpendTect fault-stick "
                         "rows ('\"name\" X Y Z stick node [inline crossline]' or the 8 columns 'X Y Z o1 o2 o3 "
                         "inline crossline' in pairs), Charisma rows ('INLINE- inline crossline X Y Z name stick') or "
                         "IESX rows (PROFILE lines, fixed columns); RMS polygons ('X Y Z' rows, as "
                         "fault_sticks_rms.pol) name no faults: give the run's fault_sticks_opendtect.txt instead")
    reader = {"charisma": _read_charisma, "opendtect": _read_opendtect, "opendtect_pairs": _read_pairs,
              "iesx": _read_iesx}[layout]
    sticks = reader(path, lines, z_unit)
    if coordinates is not None:
        sticks = sticks.with_coordinates(coordinates).with_lines(coordinates)
    return sticks


def _build(records: list, names: list, z_unit: str, xy_unit: str) -> FaultSticks:
    """records: (fault_name, stick key, x, y, z, inline, crossline) per node, in file order."""
    fault_ids = {n: i + 1 for i, n in enumerate(names)}
    keys, stick = {}, []
    for r in records:
        stick.append(keys.setdefault((r[0], r[1]), len(keys)))
    arr = np.array([r[2:] for r in records], dtype=np.float64).reshape(-1, 5)
    x, y = arr[:, 0].copy(), arr[:, 1].copy()
    undefined = ~(np.abs(x) < _UNDEFINED) | ~(np.abs(y) < _UNDEFINED)
    x[undefined] = np.nan
    y[undefined] = np.nan
    return FaultSticks(np.array([fault_ids[r[0]] for r in records], dtype=np.int64), np.array(stick, dtype=np.int64),
                       x, y, arr[:, 2], arr[:, 3], arr[:, 4], tuple(names), z_unit, xy_unit)


def _numbers(fields, path: Path, n: int, line_no: int) -> list:
    try:
        return [float(v) for v in fields]
    except ValueError:
        raise InputError(f"{path.name}, line {line_no}: expected numbers, got {' '.join(fields)!r}") from None


def _xy_unit(lines: list) -> str:
    header = " ".join(line for line in lines if line.startswith("#"))
    if "no coordinates" in header:
        return LINE_UNITS
    return "ft" if "coordinates in ft" in header else "m"


def _read_opendtect(path: Path, lines: list, z_unit: str) -> FaultSticks:
    records, names = [], []
    for no, line in enumerate(lines, start=1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        match = re.match(r'^"([^"]*)"\s+(.*)$', text)
        if match is None:
            raise InputError(f"{path.name}, line {no}: expected '\"name\" X Y Z stick node ...', got {text!r}")
        name, rest = match.group(1), match.group(2).split()
        if len(rest) < 5:
            raise InputError(f"{path.name}, line {no}: expected X Y Z stick node after the name; got {rest}")
        v = _numbers(rest, path, 5, no)
        il, xl = (v[5], v[6]) if len(v) >= 7 else (np.nan, np.nan)
        if name not in names:
            names.append(name)
        records.append((name, int(v[3]), v[0], v[1], v[2], il, xl))
    return _build(records, names, z_unit, _xy_unit(lines))


def _read_pairs(path: Path, lines: list, z_unit: str) -> FaultSticks:
    rows = []
    for no, line in enumerate(lines, start=1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        fields = text.split()
        if len(fields) != 8:
            raise InputError(f"{path.name}, line {no}: expected 8 columns (X Y Z o1 o2 o3 inline crossline), got "
                             f"{len(fields)}")
        rows.append(_numbers(fields, path, 8, no))
    if len(rows) % 2:
        raise InputError(f"{path.name} has {len(rows)} node rows; each stick is two consecutive rows (its two ends), "
                         "so the count must be even")
    names = [f"stick_{i + 1}" for i in range(len(rows) // 2)]
    records = [(names[i // 2], i // 2, r[0], r[1], r[2], r[6], r[7]) for i, r in enumerate(rows)]
    return _build(records, names, z_unit, "m")


def _read_charisma(path: Path, lines: list, z_unit: str) -> FaultSticks:
    records, names = [], []
    for no, line in enumerate(lines, start=1):
        fields = line.split()
        if not fields or fields[0].startswith("#"):
            continue
        if fields[0].upper() != "INLINE-" or len(fields) < 8:
            raise InputError(f"{path.name}, line {no}: expected 'INLINE- inline crossline X Y Z name stick', got "
                             f"{line.strip()!r}")
        if fields[1].upper() == "I":  # a variant writes 'INLINE- I inline ...'
            fields = [fields[0]] + fields[2:]
        il, xl, x, y, z = _numbers(fields[1:6], path, 5, no)
        name = fields[6]
        if name not in names:
            names.append(name)
        records.append((name, fields[7], x, y, z, il, xl))
    return _build(records, names, z_unit, "m")


def _read_iesx(path: Path, lines: list, z_unit: str) -> FaultSticks:
    records, names, name = [], [], None
    for no, line in enumerate(lines, start=1):
        text = line.strip()
        if not text or text.startswith("#") or text.upper().startswith("SNAPPING"):
            continue
        if text.upper().startswith("PROFILE"):
            name = text.split()[1] if len(text.split()) > 1 else f"fault_{len(names) + 1}"
            while name in names:
                name += "_"
            names.append(name)
            continue
        if text.upper().startswith("EOD"):
            break
        if name is None or len(line.rstrip()) < 47:
            raise InputError(f"{path.name}, line {no}: expected an IESX node row of at least 47 characters after a "
                             f"PROFILE line, got {text!r}")
        stick = line[32:35] if " " in line[32:39] else line[32:39]  # DUG's rule for the stick index
        x, y, z = _numbers([line[0:16], line[16:32], line[38:47]], path, 3, no)
        records.append((name, stick.strip(), x, y, z, np.nan, np.nan))
    if not records:
        raise InputError(f"{path.name} holds no IESX fault-stick rows")
    unit = "ft" if any(" ft " in f" {line} " for line in lines if line.upper().startswith("PROFILE")) else "m"
    return _build(records, names, z_unit, unit)
