"""The fault tables of ``seismo3d faults``: ``fault_points.csv`` (a row per fault point) and ``fault_summary.csv``
(a row per fault, with the evidence a user sorts and filters by), labelled with the input's inlines, crosslines and
times or depths. Written atomically.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from .._atomic import atomic_path
from ..seismic.faults.result import FaultInterpretation
from ..seismic.io.text_rows import TextColumn, format_rows

__all__ = ["read_points", "sample_position", "trace_columns", "write_points", "write_summary"]


def sample_position(samples: np.ndarray, k) -> np.ndarray:
    """Time or depth of fractional sample indices ``k`` on the ``samples`` axis (linear between samples)."""
    return np.interp(np.asarray(k, dtype=np.float64), np.arange(samples.size), samples)


def trace_columns(inp) -> list:
    """The names of the trace columns of the fault tables for the job's input ``inp``.

    Parameters
    ----------
    inp : object
        The faults job's input: ``xline`` is None when its traces carry no inline / crossline numbers.

    Returns
    -------
    list of str
        ``['inline', 'crossline']`` for numbered traces, ``['trace']`` for raw sections, 2D ``.npy`` arrays (the
        trace index, from 0) and trace lists without numbers (the trace number, from 1 in file order).
    """
    return ["trace"] if inp.xline_labels is None else ["inline", "crossline"]


def _fmt(v: float) -> str:
    return "" if not np.isfinite(v) else f"{v:.5g}"


def _throw_of(throws, fault, field="throw") -> np.ndarray:
    """(n_points,) float64 throw in samples (or another per-point field, e.g. ``correlation``) of ``fault``; NaN
    where it was not measured."""
    for t in throws:
        if t.fault_id == fault.id and getattr(t, field) is not None:
            values = np.asarray(getattr(t, field), dtype=np.float64)
            if values.shape == (fault.size,):
                return values
    return np.full(fault.size, np.nan)


def _column(values, fmt: str) -> list:
    """Format a column for CSV: ``fmt`` for finite values, empty for NaN."""
    return [format(v, fmt) if v == v else "" for v in np.asarray(values, dtype=np.float64).tolist()]


def _number_column(values, fmt: str) -> TextColumn:
    """A float column of a CSV table: ``fmt`` for finite values, empty for NaN (:func:`_column`)."""
    return TextColumn(np.asarray(values, dtype=np.float64), fmt, lambda block: _column(block, fmt))


def write_points(inp, result: FaultInterpretation, path: Path, coordinates=None) -> Path:
    """fault_points.csv: one row per fault point (its trace's labels, with ``coordinates``
    (:class:`~seismo3d.seismic.io.coordinates.SurveyCoordinates` of the traced array) its trace's ``x``, ``y`` and
    their unit ``xy_unit`` ('m', 'ft', or 'inline/crossline' for an input without coordinates), time or depth, fault
    id, throw and its evidence); ``inp`` is the job's input (its trace labels, samples and unit).

    The trace columns say what they hold (:func:`trace_columns`): ``inline, crossline`` where the traces have
    inline and crossline numbers (cubes, lines of a survey, trace lists whose headers number them), one ``trace``
    column for raw sections, 2D ``.npy`` arrays (the trace index, from 0) and trace lists without numbers (the trace
    number, from 1 in file order, as :func:`seismo3d.open` numbers them).
    """
    unit = inp.sample_unit
    extra = [] if unit == "samples" else [f"throw_{unit}"]
    xy = [] if coordinates is None else ["x", "y", "xy_unit"]
    header = [*trace_columns(inp), *xy, "time_or_depth", "fault_id", "throw_samples", *extra, "throw_correlation",
              "correlation_gain", "side_coherence", "confidence"]
    confidence = {e.fault_id: e.confidence for e in result.evidence}
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        fh.write(",".join(header) + "\n")
        for f in result.faults:
            p = f.points
            throw = _throw_of(result.throws, f)
            xl = inp.xline_labels
            lateral = inp.inline_labels[p[:, 0]], (None if xl is None else xl[p[:, 1 if p.shape[1] == 3 else 0]])
            cols = [TextColumn(np.asarray(lateral[0]), "s")]  # str() of the labels, as Python numbers
            if lateral[1] is not None:
                cols.append(TextColumn(np.asarray(lateral[1]), "s"))
            if coordinates is not None:  # the trace's own header coordinates (scalar applied)
                x, y = coordinates.at(p[:, :-1])
                cols += [_number_column(x, ".3f"), _number_column(y, ".3f"), TextColumn(coordinates.unit)]
            cols += [_number_column(sample_position(inp.samples, p[:, -1]), ".6g"), TextColumn(str(f.id)),
                     _number_column(throw, ".5g")]
            if extra:
                cols.append(_number_column(throw * result.sample_interval, ".5g"))
            correlation = _throw_of(result.throws, f, "correlation")
            cols.append(_number_column(correlation, ".3f"))
            cols.append(_number_column(correlation - _throw_of(result.throws, f, "correlation_unshifted"), ".3f"))
            cols.append(_number_column(_throw_of(result.throws, f, "side_coherence"), ".3f"))
            cols.append(TextColumn(_column([confidence.get(f.id, np.nan)], ".4g")[0]))  # the fault's, on each point
            fh.writelines(format_rows(cols, f.size, sep=","))  # a block of rows at a time
    return path


def _dip_direction(inp, fault) -> str:
    """Where a fault of a 2D section deepens, in the section's own terms: 'increasing inline' etc."""
    toward_higher = fault.mean_strike_deg > 180.0  # strike 270: deepens toward increasing trace index
    labels = inp.axes[0]
    if labels.size > 1 and labels[-1] < labels[0]:  # trace labels decrease along the section
        toward_higher = not toward_higher
    return f"{'increasing' if toward_higher else 'decreasing'} {inp.trace_axis}"


def write_summary(inp, result: FaultInterpretation, path: Path, rows: list) -> Path:
    """fault_summary.csv; its rows are also appended to ``rows`` (column name to text) for the job's result."""
    unit = inp.sample_unit
    extra = [] if unit == "samples" else [f"median_throw_{unit}"]
    two_d = inp.amplitudes.ndim == 2
    orientation = ["dips_toward"] if two_d else ["mean_strike_deg"]
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        header = ["id", "n_points", *orientation, "mean_dip_deg", "median_throw_samples", *extra,
                  "throw_spread_samples", "throw_step_samples", "throw_alternative_samples", "throw_ambiguity",
                  "throw_correlation", "correlation_gain",
                  "side_coherence", "vote_ratio", "mean_likelihood", "confidence"]
        w.writerow(header)
        evidence = {e.fault_id: e for e in result.evidence}
        throws = {t.fault_id: t for t in result.throws}
        for f in result.faults:
            e, t = evidence[f.id], throws.get(f.id)
            row = [f.id, f.size, _dip_direction(inp, f) if two_d else f"{f.mean_strike_deg:.1f}",
                   f"{f.mean_dip_deg:.1f}", _fmt(e.median_throw)]
            if extra:
                row.append(_fmt(e.median_throw * result.sample_interval))
            row += [_fmt(e.throw_spread), _fmt(e.step),
                    _fmt(t.alternative_throw if t is not None else float("nan")),
                    _fmt(t.ambiguity if t is not None else float("nan")), _fmt(e.correlation), _fmt(e.correlation_gain),
                    _fmt(e.side_coherence),
                    _fmt(e.vote_ratio), _fmt(e.mean_likelihood), _fmt(e.confidence)]
            w.writerow(row)
            rows.append(dict(zip(header, (str(v) for v in row))))
    return path


def read_points(path: Path) -> dict:
    """The columns of a ``fault_points.csv`` (:func:`write_points`) as arrays, by name: float64, NaN where empty;
    ``xy_unit`` as strings.

    Parameters
    ----------
    path : path-like
        A ``fault_points.csv`` written by ``seismo3d faults``.

    Returns
    -------
    dict of str to (n,) ndarray

    Raises
    ------
    InputError
        The file is not such a table (a column it needs is missing or a value is not a number).
    """
    from ..errors import InputError

    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    names = rows[0].keys() if rows else []
    if not {"time_or_depth", "fault_id", "throw_samples"} <= set(names):
        raise InputError(f"{path} is not the fault_points.csv of a `seismo3d faults` run (columns "
                         f"{', '.join(names) or 'none'}); pass the run's output folder")
    try:
        return {name: (np.array([r[name] for r in rows]) if name == "xy_unit" else
                       np.array([float(r[name]) if r[name] != "" else np.nan for r in rows], dtype=np.float64))
                for name in names}
    except ValueError as exc:
        raise InputError(f"{path}: {exc}; pass the fault_points.csv a `seismo3d faults` run wrote") from None
