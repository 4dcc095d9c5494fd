"""The fault job: from a seismic cube or section to fault likelihood, fault surfaces, throws and report files.

Two functions:

* :func:`trace_faults` runs the pipeline on an array (fault likelihood -> thinning -> linking -> throw) and returns a
  :class:`FaultInterpretation`;
* :func:`run_faults_job` reads an input file (SEG-Y cube, 2D SEG-Y line, raw ``.f32be`` section, ``.npy`` array) or
  makes a synthetic cube, runs :func:`trace_faults` and writes the outputs of ``seismo3d faults`` (see its docstring
  for the list of files and their columns). Every file is written atomically; the input is only read.

Index-space conventions (axes, strike, dip) are those of :mod:`seismo3d.seismic.faults`.
"""

from __future__ import annotations

import csv
import shutil
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._atomic import atomic_path
from .._validation import check_choice, check_positive
from ..errors import InputError, Seismo3dWarning
from .faults import fault_likelihood, link_faults, thin_faults

__all__ = ["FaultInterpretation", "trace_faults", "run_faults_job"]

_UNITS = {"samples", "ms", "m", "ft"}
_DEMO_SHAPE = (128, 128, 128)
_DEMO_DT_MS = 4.0
# Reach (traces, samples) of a dead zone's edge in fault_likelihood: the 3 x 3-trace semblance and the reflector slopes
# of the structure tensor (smoothed over about 2 traces and 6 samples) see the edge this far; likelihood this close to
# a dead sample is an artefact of the edge, not a fault.
_DEAD_REACH = (3, 8)
# Fraction of samples at the data's extremes above which the data are reported as clipped (unclipped data such as F3
# and the synthetic cubes have a handful of such samples; 8-bit exports like the Penobscot sections, most of them).
_CLIPPED_WARN = 0.05
# Equal values in a row along a trace that make a run of dead samples (mute, dead trace, gap), at a fill value.
_DEAD_RUN = 5
# A value that fills a run this long somewhere in the data (or a whole trace) is a fill value (a mute's or a padding's
# value) besides 0. Shorter runs at other values are the quantisation of slowly varying amplitudes in integer exports:
# in the 8-bit Penobscot sections a run of five 107s sits on a fault at inlines 1-2, and reading it as dead blanked
# the fault's likelihood over inlines 0-5.
_FILL_RUN = 16


@dataclass(frozen=True)
class FaultInterpretation:
    """Result of :func:`trace_faults`.

    Attributes
    ----------
    likelihood : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Fault likelihood in [0, 1] (0 on and next to dead samples).
    strike_deg, dip_deg : same shape, float32 ndarray
        Strike and dip of the most likely fault plane at each sample, degrees, index space.
    thin : same shape, float32 ndarray
        The likelihood on the 1-sample-wide thinned fault traces, 0 elsewhere (``thin > 0`` is the fault mask).
    faults : list of Fault
        Linked faults (surfaces in 3D, curves in 2D), ids 1, 2, ... by decreasing size.
    throws : list of FaultThrow
        One per fault, in the order of ``faults``; ``throws[i].throw`` is the vertical throw at each point of
        ``faults[i]``, in samples.
    sample_interval : float
        Sample interval in ``sample_unit`` (1 for 'samples').
    sample_unit : {'samples', 'ms', 'm', 'ft'}
        Unit of the sample axis.
    """

    likelihood: np.ndarray
    strike_deg: np.ndarray
    dip_deg: np.ndarray
    thin: np.ndarray
    faults: list
    throws: list
    sample_interval: float
    sample_unit: str


def _clean_traces(data) -> tuple[np.ndarray, np.ndarray]:
    """Replace NaN / inf by 0 (with a warning); return float32 data and the mask of dead samples (with a warning).

    Dead samples are those in runs of at least ``_DEAD_RUN`` equal values along a trace at a *fill value*: dead
    traces, mutes (the zeroed top of a survey), zero padding and NaN gaps. The fill values are 0 and every value that
    fills a whole trace or a run of at least ``_FILL_RUN`` samples somewhere in the data (a mute or padding value
    such as the grey of an image export). Short runs at other values are quantisation (integer exports), and runs at
    the data's largest or smallest value are clipped amplitudes (8-bit exports of sections): neither is dead, unless
    it fills the whole trace.
    """
    from scipy.ndimage import binary_opening

    arr = np.asarray(data)
    if arr.ndim not in (2, 3):
        raise InputError(f"data must be a 2D section (n_traces, n_samples) or a 3D cube (n_inlines, n_xlines, "
                         f"n_samples); got shape {arr.shape}")
    if not (np.issubdtype(arr.dtype, np.number) or arr.dtype == bool):
        raise InputError(f"data must be numeric; got dtype {arr.dtype}")
    if min(arr.shape) < 3:
        raise InputError(f"data has shape {arr.shape}; every axis needs at least 3 samples")
    arr = np.asarray(arr, dtype=np.float32)
    finite = np.isfinite(arr)
    if not finite.all():
        n_bad = int(arr.size - np.count_nonzero(finite))
        warnings.warn(f"data has {n_bad} NaN or inf samples ({n_bad / arr.size:.1%}); they are read as 0, and "
                      "runs of them are skipped like dead traces", Seismo3dWarning, stacklevel=3)
        arr = np.where(finite, arr, np.float32(0.0))
    del finite
    n_s = arr.shape[-1]
    if arr.max() == arr.min():
        raise InputError("every sample has the same value (or is NaN): there are no reflectors to trace faults in; "
                         "check that the file is the right one and that its data format is read correctly")
    # equal neighbours along the trace, in runs of >= _DEAD_RUN - 1 differences
    flat = np.diff(arr, axis=-1) == 0
    lo, hi = arr.min(), arr.max()
    clipped = (arr[..., 1:] == lo) | (arr[..., 1:] == hi)
    clipped &= ~flat.all(axis=-1, keepdims=True)
    frac_clipped = float(np.count_nonzero(clipped)) / clipped.size
    if frac_clipped > _CLIPPED_WARN:
        warnings.warn(f"{frac_clipped:.0%} of the samples sit at the data's smallest or largest value: clipped "
                      "amplitudes (an 8-bit export?). Fault likelihood and throws are measured on the clipped "
                      "waveforms and are less reliable; trace the unclipped data if you have it",
                      Seismo3dWarning, stacklevel=3)
    flat &= ~clipped
    del clipped

    def runs(equal, length):  # the differences inside runs of at least `length` equal values
        structure = np.ones((1,) * (arr.ndim - 1) + (min(length - 1, n_s - 1),), dtype=bool)
        return binary_opening(equal, structure=structure)

    whole = np.broadcast_to(flat.all(axis=-1, keepdims=True), flat.shape)
    fill = np.union1d([0.0], arr[..., 1:][runs(flat, _FILL_RUN) | whole])
    flat = runs(flat, _DEAD_RUN) & np.isin(arr[..., 1:], fill)
    dead = np.zeros(arr.shape, dtype=bool)
    dead[..., 1:] |= flat
    dead[..., :-1] |= flat
    del flat
    if dead.any():
        n_dead = int(np.count_nonzero(dead))
        n_tr = int(np.count_nonzero(dead.all(axis=-1)))
        warnings.warn(f"{n_dead / dead.size:.1%} of the samples are constant over {_DEAD_RUN} or more samples "
                      f"(mutes, gaps, {n_tr} dead traces); fault likelihood within {_DEAD_REACH[0]} traces and "
                      f"{_DEAD_REACH[1]} samples of them is set to 0", Seismo3dWarning, stacklevel=3)
    return arr, dead


def _near(dead: np.ndarray) -> np.ndarray:
    """Dead samples grown by ``_DEAD_REACH`` (a box: separable maximum filters)."""
    from scipy.ndimage import maximum_filter1d

    near = dead.view(np.uint8)
    for axis in range(dead.ndim):
        reach = _DEAD_REACH[1] if axis == dead.ndim - 1 else _DEAD_REACH[0]
        if dead.shape[axis] > 1:
            near = maximum_filter1d(near, 2 * reach + 1, axis=axis, mode="constant")
    return near.view(bool)


def _fault_throws(data, faults) -> list:
    """The throw step, one call: register the two sides of each fault (:mod:`seismo3d.seismic.throw`)."""
    from .throw import fault_throws

    return fault_throws(data, faults)


def trace_faults(data, *, sample_interval=None, sample_unit="samples", progress=True) -> FaultInterpretation:
    """Trace the faults of a seismic cube or section: likelihood, thinning, linking, throw.

    The steps, with their defaults chosen from the data (no per-file tuning):

    1. :func:`~seismo3d.seismic.faults.fault_likelihood` (scan of fault strikes and dips, Hale 2013);
    2. :func:`~seismo3d.seismic.faults.thin_faults` (non-maximum suppression across the fault, Otsu + hysteresis);
    3. :func:`~seismo3d.seismic.faults.link_faults` (fault surfaces in 3D, curves in 2D; tiny ones dropped);
    4. :func:`~seismo3d.seismic.throw.fault_throws` (vertical throw by registering the reflectors on both sides).

    NaN / inf samples are read as 0 (with a :class:`~seismo3d.errors.Seismo3dWarning`). Dead samples (runs of 5 or
    more equal values along a trace: dead traces, mutes, gaps, NaN runs) are skipped, with a warning: the likelihood
    within 3 traces and 8 samples of them is set to 0, since the edge of a dead zone is not a fault.

    Memory and time: the whole array is processed in memory. The whole ``seismo3d faults`` command on a 256^3
    float32 cube (64 MiB) peaked at 1.3 GB resident and took about 55 s on 2 cores (128^3: 0.4 GB, about 20 s);
    both grow about linearly with the number of samples. Crop larger cubes, or trace them in overlapping pieces.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes; the last axis is the sample (time or depth, downward).
    sample_interval : float, optional
        Sample interval in ``sample_unit``; required unless ``sample_unit`` is 'samples'.
    sample_unit : {'samples', 'ms', 'm', 'ft'}, optional
        Unit of the sample axis (for converting throws, see :attr:`FaultInterpretation.sample_interval`).
    progress : bool, optional
        Show a progress bar over the steps on standard error (only when it is a terminal).

    Returns
    -------
    FaultInterpretation
        Likelihood, strike, dip, thinned faults, linked faults and their throws.

    Raises
    ------
    InputError
        ``data`` is not a numeric 2D / 3D array with at least 3 samples per axis, all samples are equal, or the
        sample interval / unit is invalid.

    Warns
    -----
    Seismo3dWarning
        NaN / inf samples, dead samples (constant runs), or clipped amplitudes (more than 5 % of the samples at the
        data's smallest or largest value).

    References
    ----------
    .. [1] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1.
    .. [2] D. Hale, "Fault surfaces and fault throws from 3D seismic images", Geophysics 79(5), O53-O66, 2014,
       doi:10.1190/geo2013-0270.1.

    Examples
    --------
    >>> from seismo3d.data.synthetic import synthetic_cube
    >>> syn = synthetic_cube((64, 64, 64), seed=0)
    >>> result = trace_faults(syn.cube, sample_interval=4.0, sample_unit="ms", progress=False)
    >>> len(result.faults) >= 1
    True
    """
    from tqdm.auto import tqdm

    check_choice(sample_unit, "sample_unit", _UNITS)
    if sample_unit == "samples":
        if sample_interval not in (None, 1, 1.0):
            raise InputError(f"sample_interval={sample_interval!r} needs a unit; pass sample_unit='ms', 'm' or 'ft'")
        sample_interval = 1.0
    elif sample_interval is None:
        raise InputError(f"sample_unit={sample_unit!r} needs sample_interval= (the sample interval in {sample_unit})")
    sample_interval = check_positive(sample_interval, "sample_interval")

    arr, dead = _clean_traces(data)
    with tqdm(total=4, desc="faults", unit="step", disable=None if progress else True, leave=False) as bar:
        bar.set_postfix_str("fault likelihood")
        fl = fault_likelihood(arr)
        likelihood, strike, dip = fl.likelihood, fl.strike_deg, fl.dip_deg
        del fl
        if dead.any():
            likelihood[_near(dead)] = 0.0
            del dead
        bar.update(1)
        bar.set_postfix_str("thinning")
        thin = thin_faults(likelihood, strike, dip)
        bar.update(1)
        bar.set_postfix_str("linking")
        faults = link_faults(thin, strike, dip)
        bar.update(1)
        bar.set_postfix_str("throw")
        throws = _fault_throws(arr, faults) if faults else []
        bar.update(1)
    return FaultInterpretation(likelihood=likelihood, strike_deg=strike, dip_deg=dip, thin=thin, faults=faults,
                               throws=list(throws), sample_interval=float(sample_interval), sample_unit=sample_unit)


# --------------------------------------------------------------------------------------------------------------------
# the job: inputs


@dataclass(frozen=True)
class _Input:
    """What the job read: the array it traces and how to label and write results."""

    data: np.ndarray  # (n_il, n_xl, ns) 3D or (n_traces, ns) 2D
    name: str
    segy_path: Path | None  # template for SEG-Y outputs
    segy_shape: tuple | None  # the template's grid shape (cube.shape) to write 2D results back into
    inline: np.ndarray  # inline number per inline (3D) or per trace (2D; the trace index for raw sections)
    xline: np.ndarray | None  # crossline number per crossline (3D) or per trace (2D); None for raw sections
    samples: np.ndarray  # (ns,) sample positions in `unit` (sample index for 'samples')
    unit: str
    trace_axis: str = "trace"  # 2D: what labels the traces in pictures: 'inline', 'crossline' or 'trace' (index)
    sorting: str | None = None  # SEG-Y trace order of a grid: 'inline' or 'crossline'

    def file_order(self, values: np.ndarray) -> np.ndarray:
        """(n_traces, n_samples) of an array shaped like ``data``, in the SEG-Y file's trace order."""
        ns = values.shape[-1]
        if self.segy_shape is None:  # trace list: already in file order
            return values.reshape(-1, ns)
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


def _read_input(path, *, iline, xline, ignore_geometry, sample_unit, n_samples) -> _Input:
    from .io import open_segy, read_section

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in (".f32be", ".npy"):
        if not path.is_file():
            from ..errors import DataNotFoundError

            raise DataNotFoundError(f"no input file at {path}; check the path")
        if suffix == ".f32be":
            data = read_section(path, n_samples=n_samples)
        else:
            try:
                data = np.load(path, allow_pickle=False, mmap_mode="r")
            except (ValueError, OSError) as exc:
                raise InputError(f"{path.name} is not a readable .npy array ({exc}); save it with numpy.save") from exc
            if data.ndim not in (2, 3):
                raise InputError(f"{path.name} holds an array of shape {data.shape}; expected a 2D section "
                                 "(n_traces, n_samples) or a 3D cube (n_inlines, n_xlines, n_samples)")
        unit = "samples"
        if sample_unit is not None:
            raise InputError(f"{path.name} has no sample interval, so --sample-unit cannot be used; its results are "
                             "in samples")
        idx = [np.arange(n, dtype=np.int64) for n in data.shape]
        if data.ndim == 2:
            return _Input(np.asarray(data), path.stem, None, None, idx[0], None, idx[1].astype(np.float64), unit)
        return _Input(np.asarray(data), path.stem, None, None, idx[0], idx[1], idx[2].astype(np.float64), unit)

    with open_segy(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, sample_unit=sample_unit) as cube:
        data = cube.read()
        samples = np.asarray(cube.samples, dtype=np.float64)
        unit = cube.sample_unit
        if cube.inlines is None:  # trace list: label traces with their header inline / crossline numbers, if any
            f = cube.segyfile
            il = np.asarray(f.attributes(cube.iline_byte)[:], dtype=np.int64)
            xl = np.asarray(f.attributes(cube.xline_byte)[:], dtype=np.int64)
            if np.all(il == il[0]) and np.all(xl == xl[0]):  # no numbers there: the trace index
                il, xl = np.arange(cube.n_traces, dtype=np.int64), None
            return _Input(data, path.stem, path, None, il, xl, samples, unit, "trace")
        il = np.asarray(cube.inlines, dtype=np.int64)
        xl = np.asarray(cube.xlines, dtype=np.int64)
        if cube.is_3d:
            return _Input(data, path.stem, path, cube.shape, il, xl, samples, unit, "trace", cube.sorting)
        shape, sorting = cube.shape, cube.sorting
    if shape[1] == 1:  # a line along inlines (one crossline), e.g. penobscot_xl1155
        return _Input(data[:, 0, :], path.stem, path, shape, il, np.full(il.size, xl[0]), samples, unit, "inline",
                      sorting)
    return _Input(data[0], path.stem, path, shape, np.full(xl.size, il[0]), xl, samples, unit, "crossline", sorting)


def _demo_input(out_dir: Path, seed) -> tuple[_Input, Path]:
    """Write a synthetic cube as SEG-Y (4 ms, inlines / crosslines 1..128) and its true faults (CSV) into ``out_dir``;
    read the cube back."""
    import segyio

    from ..data.synthetic import synthetic_cube

    syn = synthetic_cube(_DEMO_SHAPE, seed=seed)
    path = out_dir / "demo_seismic.sgy"
    with atomic_path(path) as tmp:
        segyio.tools.from_array3D(str(tmp), syn.cube, format=5, dt=int(_DEMO_DT_MS * 1000))
    truth = out_dir / "demo_truth.csv"
    with atomic_path(truth) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["id", "kind", "strike_deg", "dip_deg", "throw_samples", "throw_ms", "throw_gradient"])
        for f in syn.faults:
            signed = f.throw_samples if f.kind == "normal" else -f.throw_samples  # + = hanging wall down
            w.writerow([f.id, f.kind, f"{f.strike_deg:.1f}", f"{f.dip_deg:.1f}", f"{signed:.5g}",
                        f"{signed * _DEMO_DT_MS:.5g}", f"{f.throw_gradient:.4g}"])
    del syn
    inp = _read_input(path, iline=189, xline=193, ignore_geometry=False, sample_unit="ms", n_samples=None)
    return inp, truth


# --------------------------------------------------------------------------------------------------------------------
# the job: outputs


def _write_volume(inp: _Input, out_dir: Path, stem: str, values: np.ndarray, *, like=None, iline, xline,
                  ignore_geometry) -> Path:
    """SEG-Y with the input's headers for a SEG-Y input, .npy otherwise.

    With ``like`` (a SEG-Y file this job already wrote with :func:`~seismo3d.seismic.io.write_like`), the file is a
    copy of it with the trace data replaced: the same headers, without copying them field by field again.
    """
    if inp.segy_path is not None:
        out = out_dir / f"{stem}.sgy"
        if like is None:
            from .io import write_like

            grid = values.reshape(inp.segy_shape) if inp.segy_shape is not None else values
            return write_like(inp.segy_path, out, grid, iline=iline, xline=xline, ignore_geometry=ignore_geometry)
        import segyio

        traces = inp.file_order(values)
        with atomic_path(out) as tmp:
            shutil.copyfile(like, tmp)
            with segyio.open(str(tmp), "r+", ignore_geometry=True) as f:
                if f.tracecount != traces.shape[0] or len(f.samples) != traces.shape[1]:  # pragma: no cover
                    raise RuntimeError(f"{like} does not match the input's {traces.shape} traces")
                f.trace.raw[:] = traces
        return out
    out = out_dir / f"{stem}.npy"
    with atomic_path(out) as tmp:
        with open(tmp, "wb") as fh:
            np.save(fh, np.asarray(values, dtype=np.float32), allow_pickle=False)
    return out


def _sample_position(samples: np.ndarray, k) -> np.ndarray:
    return np.interp(np.asarray(k, dtype=np.float64), np.arange(samples.size), samples)


def _fmt(v: float) -> str:
    return "" if not np.isfinite(v) else f"{v:.5g}"


def _throw_of(throws, fault, field="throw") -> np.ndarray:
    """(n_points,) float64 throw in samples (or its ``correlation``) of ``fault``; NaN where it was not measured."""
    for t in throws:
        if t.fault_id == fault.id:
            values = np.asarray(getattr(t, field), dtype=np.float64)
            if values.shape == (fault.size,):
                return values
    return np.full(fault.size, np.nan)


def _column(values, fmt: str) -> list:
    """Format a column for CSV: ``fmt`` for finite values, empty for NaN."""
    return [format(v, fmt) if v == v else "" for v in np.asarray(values, dtype=np.float64).tolist()]


def _write_points(inp: _Input, result: FaultInterpretation, path: Path) -> Path:
    unit = inp.unit
    extra = [] if unit == "samples" else [f"throw_{unit}"]
    header = ["inline", "crossline", "time_or_depth", "fault_id", "throw_samples", *extra, "throw_correlation"]
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        fh.write(",".join(header) + "\n")
        for f in result.faults:
            p = f.points
            throw = _throw_of(result.throws, f)
            lateral = inp.inline[p[:, 0]], (None if inp.xline is None else inp.xline[p[:, 1 if p.shape[1] == 3 else 0]])
            cols = [
                [str(v) for v in lateral[0].tolist()],
                [""] * f.size if lateral[1] is None else [str(v) for v in lateral[1].tolist()],
                _column(_sample_position(inp.samples, p[:, -1]), ".6g"),
                [str(f.id)] * f.size,
                _column(throw, ".5g"),
            ]
            if extra:
                cols.append(_column(throw * result.sample_interval, ".5g"))
            cols.append(_column(_throw_of(result.throws, f, "correlation"), ".3f"))
            fh.writelines(",".join(row) + "\n" for row in zip(*cols))
    return path


def _write_summary(inp: _Input, result: FaultInterpretation, path: Path) -> Path:
    unit = inp.unit
    extra = [] if unit == "samples" else [f"median_throw_{unit}"]
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["id", "n_points", "mean_strike_deg", "mean_dip_deg", "median_throw_samples", *extra])
        for f in result.faults:
            throw = _throw_of(result.throws, f)
            med = float(np.median(throw[np.isfinite(throw)])) if np.isfinite(throw).any() else np.nan
            row = [f.id, f.size, f"{f.mean_strike_deg:.1f}", f"{f.mean_dip_deg:.1f}", _fmt(med)]
            if extra:
                row.append(_fmt(med * result.sample_interval))
            w.writerow(row)
    return path


def _check_out_dir(path, out_dir) -> Path:
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"output folder {out_dir} is a file; pass a folder (it is created if missing)")
    if path is not None:
        src = Path(path)
        if src.exists() and out_dir.resolve() == src.resolve().parent:
            raise InputError(f"output folder {out_dir} is the folder of the input {src.name}; write the results to "
                             f"another folder (e.g. -o {src.resolve().parent / (src.stem + '_faults')}) so that "
                             "inputs and results stay apart")
    return out_dir


def run_faults_job(input_path, out_dir, *, demo=False, seed=0, iline=189, xline=193, ignore_geometry=False,
                   sample_unit=None, n_samples=None, progress=True) -> dict:
    """Trace the faults of a seismic file and write the results: the ``seismo3d faults`` command.

    Inputs
    ------
    * a SEG-Y 3D cube (any sorting, inline / crossline numbers at trace bytes ``iline`` / ``xline``);
    * a 2D SEG-Y line: one inline or one crossline of a survey (e.g. ``penobscot_xl1155.sgy``, shape (601, 1, 1501)),
      or any file opened with ``ignore_geometry=True`` (a trace list); traced as a 2D section;
    * a raw section ``.f32be`` (big-endian float32, trace after trace; see :func:`~seismo3d.seismic.io.read_section`);
    * a ``.npy`` array, 2D (n_traces, n_samples) or 3D (n_inlines, n_xlines, n_samples);
    * nothing, with ``demo=True``: a synthetic 128^3 cube with 3 faults (:func:`~seismo3d.data.synthetic_cube`)
      is written as ``demo_seismic.sgy`` (inlines and crosslines 1..128, 4 ms) into ``out_dir`` and traced; its
      true faults go to ``demo_truth.csv`` (columns ``id, kind, strike_deg, dip_deg, throw_samples, throw_ms,
      throw_gradient``: the throw at the fault's reference point, + for hanging wall down, and its change per trace
      along strike), to compare with ``fault_summary.csv``.

    The input is read whole into memory (see :func:`trace_faults` for the memory needed); it is never written to.

    Outputs (in ``out_dir``, created if needed; each written atomically, so an interrupted run leaves either the
    previous file or none, never a half-written one)
    ------------------------------------------------------------------------------------------------------------
    * ``fault_likelihood.sgy``, ``fault_strike.sgy``, ``fault_dip.sgy``: fault likelihood in [0, 1], strike and dip
      in degrees, as SEG-Y with the textual, binary and trace headers of the input (for a SEG-Y input; IEEE float).
      For other inputs the same volumes as float32 ``.npy`` arrays of the input's shape.
    * ``faults.vtp``: all fault surfaces (triangulated; polylines for 2D inputs) in one VTK PolyData, points at
      (inline, crossline, time_or_depth) (2D: (trace label, 0, time_or_depth)), point arrays ``fault_id``,
      ``throw`` (samples) and ``likelihood``.
    * ``fault_points.csv``: one row per fault sample, columns ``inline, crossline, time_or_depth, fault_id,
      throw_samples, throw_<unit>, throw_correlation``; ``time_or_depth`` is in the sample unit (ms, m or ft from the
      SEG-Y headers or ``sample_unit``; the sample index for raw sections and ``.npy``, which have no
      ``throw_<unit>`` column).
      For raw sections, 2D ``.npy`` arrays and trace lists whose inline / crossline header bytes hold no numbers,
      ``inline`` is the trace index (from 0) and ``crossline`` is empty. Throw is
      positive where the hanging wall moved down (normal fault); ``throw_correlation`` (in [-1, 1]) is the
      normalised cross-correlation of the reflectors on the two sides once aligned, a quality measure (see
      :class:`~seismo3d.seismic.throw.FaultThrow`). An unmeasured throw is empty.
    * ``fault_summary.csv``: one row per fault, columns ``id, n_points, mean_strike_deg, mean_dip_deg,
      median_throw_samples, median_throw_<unit>``. Strike and dip are in index space (one trace step = one
      sample; strike from the inline axis toward the crossline axis, see :mod:`seismo3d.seismic.faults`).
    * ``faults.png``: an inline, a crossline and a time slice (the most faulted of each) with the faults drawn over
      the seismic, above the same slices of the fault likelihood; for 2D inputs the section.

    Parameters
    ----------
    input_path : str or os.PathLike or None
        The input file; None with ``demo=True``.
    out_dir : str or os.PathLike
        Output folder; must not be the input's own folder.
    demo : bool, optional
        Run on a synthetic cube instead of ``input_path``.
    seed : int, optional
        Seed of the synthetic cube (``demo=True``).
    iline, xline : int, optional
        Trace header bytes of the inline and crossline numbers of a SEG-Y input.
    ignore_geometry : bool, optional
        Read a SEG-Y input as a trace list (unsorted file, arbitrary line) and trace it as a 2D section.
    sample_unit : {'ms', 'm', 'ft'}, optional
        Unit of a SEG-Y input's sample axis; by default guessed from its headers (see
        :func:`~seismo3d.seismic.io.open_segy`).
    n_samples : int, optional
        Samples per trace of a raw ``.f32be`` section whose shape is not known by name.
    progress : bool, optional
        Progress bar on standard error (only when it is a terminal).

    Returns
    -------
    dict of str to pathlib.Path
        The files written, keyed ``likelihood``, ``strike``, ``dip``, ``surfaces``, ``points``, ``summary``,
        ``figure`` (and ``input``, ``truth`` for the demo).

    Raises
    ------
    InputError
        No input (and not ``demo``), ``out_dir`` is the input's folder or a file, an invalid option, a constant input.
    DataNotFoundError
        The input does not exist.
    SegyFormatError
        The input is not SEG-Y or is truncated.
    SegyGeometryError
        The inline / crossline geometry cannot be read with ``iline`` / ``xline`` (the message suggests header bytes
        that work, or ``ignore_geometry``).

    Warns
    -----
    Seismo3dWarning
        NaN / inf samples or constant traces in the input.
    """
    from tqdm.auto import tqdm

    from ..viz.faults import fault_surfaces, plot_fault_slices, save_polydata

    if sample_unit is not None:
        check_choice(sample_unit, "sample_unit", {"ms", "m", "ft"})
    if demo:
        if input_path is not None:
            raise InputError("pass either an input file or demo=True (--demo), not both")
        out_dir = _check_out_dir(None, out_dir)
    else:
        if input_path is None:
            raise InputError("no input file; pass a SEG-Y cube or line, a .f32be section or a .npy array, or use "
                             "demo=True (--demo) to run on a synthetic cube")
        out_dir = _check_out_dir(input_path, out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)

    written = {}
    if demo:
        inp, written["truth"] = _demo_input(out_dir, seed)
        iline, xline, ignore_geometry = 189, 193, False
    else:
        inp = _read_input(input_path, iline=iline, xline=xline, ignore_geometry=ignore_geometry,
                          sample_unit=sample_unit, n_samples=n_samples)
    dt = float(inp.samples[1] - inp.samples[0]) if inp.samples.size > 1 else 1.0
    if inp.unit != "samples" and not dt > 0:
        raise InputError(f"the sample interval of {inp.name} is {dt:g} {inp.unit}; it must be > 0 (check the "
                         "binary header's sample interval, bytes 3217-3218)")
    result = trace_faults(inp.data, sample_interval=None if inp.unit == "samples" else dt, sample_unit=inp.unit,
                          progress=progress)

    if demo:
        written["input"] = inp.segy_path
    geo = dict(iline=iline, xline=xline, ignore_geometry=ignore_geometry)
    axes = inp.axes
    steps = [
        ("likelihood", lambda: _write_volume(inp, out_dir, "fault_likelihood", result.likelihood, **geo)),
        ("strike", lambda: _write_volume(inp, out_dir, "fault_strike", result.strike_deg,
                                         like=written["likelihood"], **geo)),
        ("dip", lambda: _write_volume(inp, out_dir, "fault_dip", result.dip_deg, like=written["likelihood"], **geo)),
        ("surfaces", lambda: save_polydata(fault_surfaces(result.faults, result.throws, axes=axes),
                                           out_dir / "faults.vtp")),
        ("points", lambda: _write_points(inp, result, out_dir / "fault_points.csv")),
        ("summary", lambda: _write_summary(inp, result, out_dir / "fault_summary.csv")),
        ("figure", lambda: plot_fault_slices(inp.data, result.faults, path=out_dir / "faults.png",
                                             likelihood=result.likelihood, axes=axes, axis_labels=inp.labels,
                                             title=inp.name)),
    ]
    with tqdm(total=len(steps), desc="writing", unit="file", disable=None if progress else True,
              leave=False) as bar:
        for key, write in steps:
            bar.set_postfix_str(key)
            written[key] = write()
            bar.update(1)
    return written
