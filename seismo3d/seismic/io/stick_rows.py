"""The rows of the fault-stick layouts of :func:`~seismo3d.seismic.io.fault_sticks.write_fault_sticks`
(OpendTect, Charisma, IESX, RMS polygons; the module docstring of :mod:`~seismo3d.seismic.io.fault_sticks` describes them), as blocks
of text: the nodes' columns in stick order, formatted a block of rows at a time (:mod:`.text_rows`)."""

from __future__ import annotations

import math
import re

import numpy as np

from .text_rows import TextColumn, format_rows

__all__ = ["charisma_rows", "iesx_rows", "opendtect_rows", "rms_rows"]


def _safe_name(name: str) -> str:
    """A fault name without white space or quotes (the formats split on white space)."""
    return re.sub(r"[\s\"']+", "_", str(name)) or "fault"


def _fmt(v: float) -> str:
    return "1e30" if not math.isfinite(v) else f"{v:.3f}"


def _stick_nodes(sticks) -> dict:
    """The nodes in stick order (as :meth:`~seismo3d.seismic.io.fault_sticks.FaultSticks.sticks` yields them) as
    columns: ``fault_id``, ``stick_no`` (the stick's number within its fault from 0), ``node_no`` (the node's within
    its stick from 0), ``x``, ``y``, ``z``, ``inline``, ``crossline``; (n,) arrays."""
    order = np.argsort(sticks.stick, kind="stable")
    n = order.size
    first = np.ones(n, dtype=bool)
    first[1:] = np.diff(sticks.stick[order]) != 0
    starts = np.flatnonzero(first)
    group = np.cumsum(first) - 1  # each node's stick, 0.. in stick order
    fault_of = sticks.fault_id[order[starts]]  # each stick's fault (its first node's)
    by_fault = np.argsort(fault_of, kind="stable")  # sticks grouped by fault, in stick order within each
    new_fault = np.ones(by_fault.size, dtype=bool)
    new_fault[1:] = np.diff(fault_of[by_fault]) != 0
    rank = np.arange(by_fault.size) - np.flatnonzero(new_fault)[np.cumsum(new_fault) - 1]
    stick_no = np.empty(by_fault.size, dtype=np.int64)
    stick_no[by_fault] = rank
    columns = {"fault_id": fault_of[group], "stick_no": stick_no[group],
               "node_no": np.arange(n, dtype=np.int64) - starts[group]}
    for key in ("x", "y", "z", "inline", "crossline"):
        columns[key] = getattr(sticks, key)[order]
    return columns


def _names(sticks, fault_id: np.ndarray, quote: str = "") -> np.ndarray:
    """(n,) object ndarray: the safe name of each node's fault, between ``quote`` marks."""
    names = np.array([f"{quote}{_safe_name(n)}{quote}" for n in sticks.names] or [""], dtype=object)
    return names[fault_id - 1]


def _xy_text(block: np.ndarray) -> list:
    return [_fmt(v) for v in block.tolist()]


def opendtect_rows(sticks):
    """OpendTect's rows: tab-separated ``"name" X Y Z stick node inline crossline`` (X / Y ``1e30`` where
    undefined), blocks of text.

    Parameters
    ----------
    sticks : FaultSticks

    Returns
    -------
    iterator of str
        Blocks of rows, each row ended by a line feed (:func:`~seismo3d.seismic.io.text_rows.format_rows`).
    """
    c = _stick_nodes(sticks)
    return format_rows([TextColumn(_names(sticks, c["fault_id"], '"')), TextColumn(c["x"], ".3f", _xy_text),
                        TextColumn(c["y"], ".3f", _xy_text), TextColumn(c["z"], ".4f"), TextColumn(c["stick_no"], "d"),
                        TextColumn(c["node_no"], "d"), TextColumn(c["inline"], "g"),
                        TextColumn(c["crossline"], "g")], c["x"].size, sep="\t")


def charisma_rows(sticks):
    """Charisma's rows: space-separated ``INLINE- inline crossline X Y Z name stick`` (inline / crossline rounded half
    to even, as Python's ``round``), blocks of text.

    Parameters
    ----------
    sticks : FaultSticks

    Returns
    -------
    iterator of str
        Blocks of rows, each row ended by a line feed (:func:`~seismo3d.seismic.io.text_rows.format_rows`).
    """
    c = _stick_nodes(sticks)
    return format_rows([TextColumn("INLINE-"), TextColumn(np.rint(c["inline"]).astype(np.int64), "d"),
                        TextColumn(np.rint(c["crossline"]).astype(np.int64), "d"), TextColumn(c["x"], ".3f", _xy_text),
                        TextColumn(c["y"], ".3f", _xy_text), TextColumn(c["z"], ".4f"),
                        TextColumn(_names(sticks, c["fault_id"])), TextColumn(c["stick_no"] + 1, "d")],
                       c["x"].size, sep=" ")


def iesx_rows(sticks):
    """The IESX file's text: per fault its ``PROFILE`` and ``SNAPPING PARAMETERS`` lines and its fixed-column node
    rows, then ``EOD``, in blocks.

    Parameters
    ----------
    sticks : FaultSticks

    Returns
    -------
    iterator of str
        Blocks of rows, each row ended by a line feed (:func:`~seismo3d.seismic.io.text_rows.format_rows`).
    """
    unit = "ft" if sticks.xy_unit == "ft" else "m "
    c = _stick_nodes(sticks)
    bounds = np.flatnonzero(np.diff(c["fault_id"])) + 1
    for lo, hi in zip(np.r_[0, bounds], np.r_[bounds, c["x"].size]):
        if lo == hi:
            continue
        name = _safe_name(sticks.names[c["fault_id"][lo] - 1])[:17]
        yield f"PROFILE {name:<17s}TYPE 1  4 {'fault sticks, seismo3d':<45s}3d_ci7m.ifdf     {unit} ms\n"
        yield "SNAPPING PARAMETERS 5     0 1\n"
        yield from format_rows([TextColumn(c["x"][lo:hi], "16.8E"), TextColumn(c["y"][lo:hi], "16.8E"),
                                TextColumn((c["stick_no"][lo:hi] + 1) % 1000, "3d"), TextColumn(" 14"),
                                TextColumn(c["z"][lo:hi], "9.2f")], hi - lo)
    yield "EOD\n"


def rms_rows(sticks):
    """The rows of RMS's XYZ polygons: one ``X Y Z`` row per node, space-separated, each stick (one polygon) ended by
    the row ``999.0 999.0 999.0``, in blocks.

    Parameters
    ----------
    sticks : FaultSticks

    Returns
    -------
    iterator of str
        Blocks of rows, each row ended by a line feed (:func:`~seismo3d.seismic.io.text_rows.format_rows`).

    References
    ----------
    xtgeo's ``Polygons`` XYZ format (``xtgeo.polygons_from_file(path, fformat="xyz")``), which RMS imports and exports
    as *IRAP RMS internal* / *XYZ* polygons.
    """
    c = _stick_nodes(sticks)
    bounds = np.flatnonzero((np.diff(c["fault_id"]) != 0) | (np.diff(c["stick_no"]) != 0)) + 1
    for lo, hi in zip(np.r_[0, bounds], np.r_[bounds, c["x"].size]):
        if lo == hi:
            continue
        yield from format_rows([TextColumn(c["x"][lo:hi], ".3f"), TextColumn(c["y"][lo:hi], ".3f"),
                                TextColumn(c["z"][lo:hi], ".4f")], hi - lo, sep=" ")
        yield "999.0 999.0 999.0\n"
