"""The ``seismo3d adapt`` job: the fault network adapted to a survey from an interpreter's faults on a few lines.

:func:`run_adapt_job` reads each picked line (a SEG-Y inline or crossline, a 2D ``.npy`` / ``.f32be`` section, or the
inlines and crosslines of a 3D SEG-Y cube that one fault-stick file was picked on) and the interpreter's faults on it
(fault sticks or a mask), through evaluate's reader :func:`~seismo3d.jobs.evaluate.read_picked_lines`, then:

1. **holds back** picks the training never sees (:func:`held_back_traces`): with several lines, the whole of the line
   with the fewest picks; with one line, a band of a quarter of its traces (:func:`held_back_band`: the band holding
   the share of the line's picked fault samples closest to a quarter);
2. traces the faults of the held-back traces with the shipped network and scores them (the project's tolerant
   precision / recall / F1 at 3 samples, :func:`~seismo3d.seismic.fault_scoring.tolerant_scores`): **before**;
3. fine-tunes the network on the rest (:func:`seismo3d.training.adapt.fine_tune`, PyTorch, the ``train`` extra): every
   sample outside the held-back traces counts, a sample away from the picks as no fault, so **each picked line is
   taken as fully interpreted** (a fault left undrawn is taught as none);
4. traces the held-back traces again with the fine-tuned network, with the tracing's evidence dropping the faults
   across which the reflectors continue unbroken and without (:func:`held_back_tracings`), and scores them:
   **after** (the better of the two), on the whole of each line's held-back traces and on each of its
   :data:`HELD_BACK_PARTS` parts (:func:`held_back_parts`);
5. writes MODEL (:mod:`~seismo3d.seismic.adapted_network`): the fine-tuned network when it wins clearly
   (:func:`wins_clearly`: a higher mean held-back F1 and a higher F1 on most of the held-back parts holding picks),
   else the shipped float network itself (the default kept, said in one line),
   and the record ``adapt.json`` (the method and its options, the held-back traces, every tracing's scores, the
   decision, and how MODEL traces: the sensitivity and the unbroken veto of the best tracing).

The network is fine-tuned once, without the held-back traces: the model written is the one validated.
"""

from __future__ import annotations

import hashlib
import tempfile
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np
from scipy.ndimage import zoom

from .._atomic import atomic_directory
from .._progress import LOGGER
from ..errors import InputError, MissingDependencyError
from ..seismic.fault_scoring import tolerant_scores
from ..seismic.adapted_network import MODEL_NETWORK, MODEL_RECORD
from ..training.adapt_options import AdaptOptions
from .runinfo import RunRecord

__all__ = ["AdaptJobResult", "HELD_BACK", "HELD_BACK_PARTS", "HeldBackScores", "HeldBackTracing", "MIN_GRID_TRACES",
           "TORCH_HINT", "adapt_report", "chosen_tracing", "held_back_band", "held_back_parts", "held_back_tracings",
           "held_back_traces", "min_traces", "paired_picks", "run_adapt_job", "training_grids", "training_module",
           "wins_clearly", "write_model"]

HELD_BACK = 0.25  # share of each line's traces held back for validation
HELD_BACK_PARTS = 4  # the held-back traces of a line are scored whole and in this many parts (held_back_parts)
MIN_GRID_TRACES = 16  # the fewest traces of a section on a network grid that the fine-tuning draws patches from
TORCH_HINT = ("seismo3d adapt trains the fault network with PyTorch, which is not installed: "
              "pip install 'seismo3d[train]' (CPU only: pip install torch==2.13.0 onnx)")


@dataclass(frozen=True)
class AdaptJobResult:
    """What :func:`run_adapt_job` measured and wrote.

    Attributes
    ----------
    kept : {'adapted', 'default'}
        The network MODEL holds: the fine-tuned one, or the shipped one (adapting did not win clearly on the held-back
        traces).
    before, after : list of dict
        Per line with held-back traces (:func:`held_back_traces`): their ``precision``, ``recall``, ``f1`` with the
        shipped and the fine-tuned network.
    lines : list of dict
        Per line: ``input``, ``line`` (its name), ``n_traces``, ``n_samples``, ``picked_samples``,
        ``held_back_traces`` ([first, end); [0, 0]: none).
    model : pathlib.Path
        The MODEL folder written.
    seconds : dict
        Wall time of each stage.
    tracings : list of HeldBackScores
        Every tracing scored on the held-back traces (:func:`held_back_tracings`), the shipped network's default
        first; MODEL traces as the best (:func:`chosen_tracing`).
    """

    kept: str
    before: list
    after: list
    lines: list
    model: Path
    seconds: dict = field(default_factory=dict)
    tracings: list = field(default_factory=list)

    @property
    def chosen(self) -> "HeldBackScores | None":
        """The tracing MODEL traces with (:func:`chosen_tracing`); None when none was scored."""
        return chosen_tracing(self.tracings) if self.tracings else None

    def mean(self, which: str, score: str = "f1") -> float:
        """The mean over the lines of a held-back score of ``which`` ('before' or 'after')."""
        return float(np.mean([s[score] for s in getattr(self, which)]))


def paired_picks(sticks, mask) -> list:
    """The picks of ``seismo3d adapt``'s ``--sticks`` and ``--mask`` as :func:`run_adapt_job` takes them:
    ``[('sticks', path), ...]`` or ``[('mask', path), ...]``.

    Parameters
    ----------
    sticks, mask : list of str or os.PathLike, or None

    Returns
    -------
    list of (str, pathlib.Path)

    Raises
    ------
    InputError
        Both given (the command line does not tell which of them belongs to which input) or neither.
    """
    if sticks and mask:
        raise InputError("pass the picks of every INPUT one way: all --sticks or all --mask")
    if not sticks and not mask:
        raise InputError("pass the interpreter's faults of each INPUT: --sticks FILE or --mask FILE")
    return [("sticks", Path(p)) for p in sticks or []] + [("mask", Path(p)) for p in mask or []]


def adapt_report(job: "AdaptJobResult") -> list:
    """The lines ``seismo3d adapt`` prints: each line's held-back band and scores before -> after, their means,
    the network kept (one line when the shipped one), and where MODEL is.

    Parameters
    ----------
    job : AdaptJobResult

    Returns
    -------
    list of str
    """
    held = [line for line in job.lines if line["held_back_traces"][1] > line["held_back_traces"][0]]
    out = [f"  {line['line']}: held back traces {line['held_back_traces'][0]}-{line['held_back_traces'][1] - 1}, F1 "
           f"{b['f1']:.3f} -> {a['f1']:.3f} (P {b['precision']:.2f} -> {a['precision']:.2f}, R {b['recall']:.2f} -> "
           f"{a['recall']:.2f})" for line, b, a in zip(held, job.before, job.after)]
    out.append(f"held-back F1: shipped network {job.mean('before'):.3f}, adapted {job.mean('after'):.3f}")
    adapted = [t for t in job.tracings if t.tracing.network == "adapted"]
    if len(adapted) > 1:
        out.append("adapted network traced: " + "; ".join(f"{t.tracing.describe().removeprefix('adapted network ')} "
                                                          f"F1 {t.f1:.3f}" for t in adapted))
    best = max(adapted, key=lambda t: t.f1, default=None)
    if best is not None:
        pairs = _paired_parts(best, job.tracings[0])
        out.append(f"held-back parts with picks won by the adapted network: {sum(c > r for c, r in pairs)} of "
                   f"{len(pairs)} (F1 {', '.join(f'{r:.3f} -> {c:.3f}' for c, r in pairs)})")
    if job.kept == "default":
        out.append("adapting did not win clearly on the held-back traces: MODEL keeps the shipped network")
    else:
        out.append(f"MODEL traces with the {job.chosen.tracing.describe()}")
    out.append(f"wrote {job.model} ({MODEL_NETWORK}, {MODEL_RECORD}); trace with: seismo3d faults INPUT -o OUT "
               f"--model {job.model}")
    return out


def held_back_traces(picks: list, share: float = HELD_BACK) -> list:
    """The traces of each picked line held back from the training to decide whether adapting helps: with one line, a
    band of it (:func:`held_back_band`); with several, the whole of the line with the fewest picked fault samples
    (the first of equals), and nothing of the others.

    A band of the line the network learns from says little of the lines it did not: on the F3 inlines a person drew,
    the network fine-tuned on three quarters of inline 100 went from F1 0.37 to 0.60 in the band held back while the
    four other inlines went from 0.50 to 0.34 (``docs/guide/faults.md``). A whole line is the user's question
    itself: does MODEL trace a line it was not adapted on better?

    Parameters
    ----------
    picks : list of (n_traces, n_samples) bool ndarray
        The interpreter's fault samples of each line.
    share : float, optional
        The band's share of a single line's traces, in (0, 1).

    Returns
    -------
    list of (int, int)
        Per line: first trace held back and one past the last ((0, 0): none).
    """
    if len(picks) == 1:
        return [held_back_band(picks[0], share)]
    kept = int(np.argmin([int(np.count_nonzero(p)) for p in picks]))
    return [(0, p.shape[0]) if i == kept else (0, 0) for i, p in enumerate(picks)]


def held_back_band(picks: np.ndarray, share: float = HELD_BACK) -> tuple[int, int]:
    """The band of traces held back from the training: ``share`` of the line's traces, placed where its share of the
    picked fault samples is closest to ``share`` among the bands that leave picks both in and out of it (any band
    when none does; the leftmost of equals; starts on a grid of a sixteenth of the line).

    Parameters
    ----------
    picks : (n_traces, n_samples) bool ndarray
        The interpreter's fault samples on the line.
    share : float, optional
        In (0, 1).

    Returns
    -------
    (int, int)
        First trace of the band and one past its last.
    """
    n = picks.shape[0]
    width = max(1, int(round(n * share)))
    per_trace = np.asarray(picks, bool).sum(axis=1)
    total = max(int(per_trace.sum()), 1)
    cum = np.concatenate([[0], np.cumsum(per_trace)])
    starts = np.unique(np.linspace(0, n - width, 17).round().astype(int))
    shares = (cum[starts + width] - cum[starts]) / total
    gap = np.abs(shares - share) + 2.0 * ((shares <= 0) | (shares >= 1))  # picks on both sides of the band first
    first = int(starts[np.argmin(gap)])
    return first, first + width


@dataclass(frozen=True)
class _Line:
    """A picked line: where it comes from, its amplitudes and the interpreter's fault samples."""

    input: Path
    name: str
    section: np.ndarray
    picks: np.ndarray
    sample_interval: float
    sample_unit: str
    band: tuple


def _check_before_work(inputs, picks, model: Path) -> None:
    """The refusals that need no reading: MODEL present, counts that do not pair."""
    if model.exists():
        raise InputError(f"{model} exists; adapt writes a new MODEL folder: pass another -o or remove it")
    if not model.parent.is_dir():
        raise InputError(f"the folder {model.parent} that is to hold MODEL does not exist; create it or pass another "
                         "-o")
    if not inputs:
        raise InputError("pass at least one picked line (INPUT)")
    if len(picks) not in (1, len(inputs)) or (len(picks) == 1 and len(inputs) > 1 and picks[0][0] != "sticks"):
        raise InputError(f"{len(inputs)} inputs and {len(picks)} --sticks / --mask: pass one per input, in the same "
                         "order (or one --sticks file for every input)")


def training_module():
    """The fine-tuning (:mod:`seismo3d.training.adapt`, which imports PyTorch; onnx exports its network), imported
    when the inputs have been read; one line saying how to install them when either is missing.

    Returns
    -------
    module
        :mod:`seismo3d.training.adapt`.

    Raises
    ------
    MissingDependencyError
        PyTorch or onnx cannot be imported (not installed), with :data:`TORCH_HINT`.
    """
    import importlib

    try:
        importlib.import_module("onnx")  # the adapted network leaves as ONNX
        adapt = importlib.import_module("seismo3d.training.adapt")
    except ImportError as exc:
        if (exc.name or "").split(".")[0] not in ("torch", "onnx"):
            raise  # not the framework: a bug of ours, with its traceback
        raise MissingDependencyError(TORCH_HINT) from None
    return adapt


def _read_lines(inputs, picks, segy: dict) -> list:
    """Every picked line and its picks, read and placed before any work: an input's one line, or the lines of a cube
    its sticks were picked on (:func:`~seismo3d.jobs.evaluate.read_picked_lines`; a stick off the cube's lines, a
    mask of another shape, a line without faults or with too few traces are refused here)."""
    from .evaluate import read_picked_lines

    lines = []
    for i, path in enumerate(inputs):
        kind, pick_path = picks[i if len(picks) > 1 else 0]
        for line, people in read_picked_lines(path, segy_options=segy, **{kind: pick_path}):
            people = people.mask()
            if not people.any():
                raise InputError(f"the {kind} {Path(pick_path).name} draw no fault sample on {line.name}; adapt "
                                 "learns from lines with faults drawn")
            _check_line_size(line, f"--{kind} {Path(pick_path).name}")
            step = np.diff(line.samples)
            unit = line.sample_unit if line.sample_unit in ("ms", "m", "ft") else "samples"
            interval = float(np.median(step)) if unit != "samples" and step.size else 1.0
            lines.append(_Line(Path(path), line.name, line.section, people, interval, unit, held_back_band(people)))
    return lines


def min_traces(n_samples: int) -> int:
    """The fewest traces of a picked line of ``n_samples`` samples that ``seismo3d adapt`` learns from: what fault
    tracing needs of a section (:attr:`~seismo3d.seismic.FaultTracingOptions.min_traces`, 32: the line is traced
    before and after adapting), and on every network grid the tracing runs the line on (``LearnedOptions().grids``)
    at least ``MIN_GRID_TRACES`` traces, the smallest section the fine-tuning draws patches from (two of the network's
    pooling multiples, so that its coarsest level keeps two samples a side).

    Parameters
    ----------
    n_samples : int
        Samples per trace of the line.

    Returns
    -------
    int
    """
    from ..seismic.faults.likelihood.learned import LearnedOptions
    from ..seismic.faults.likelihood.network_grid import grid_size
    from ..seismic.faults.options import FaultTracingOptions

    n = max(MIN_GRID_TRACES, int(FaultTracingOptions().min_traces[0]))
    while any(grid_size(n, f) < MIN_GRID_TRACES for f in LearnedOptions().grids(int(n_samples), 2)):
        n += 1
    return n


def _check_line_size(line, picks: str) -> None:
    """A picked line with enough traces (:func:`min_traces`) and samples to trace and learn from, or an InputError in
    the CLI's terms."""
    from ..seismic.faults.options import FaultTracingOptions

    n_traces, n_samples = line.section.shape
    need, need_samples = min_traces(n_samples), int(FaultTracingOptions().min_samples)
    if n_traces < need or n_samples < need_samples:
        raise InputError(f"{line.name} ({picks}) has {n_traces} traces of {n_samples} samples; adapt traces and learns "
                         f"from lines of at least {need} traces of {need_samples} samples or more: pick longer lines "
                         "(of a larger cube), or leave this one out")


@dataclass(frozen=True)
class HeldBackTracing:
    """One way of tracing the held-back traces that ``seismo3d adapt`` scores (:func:`held_back_tracings`).

    Attributes
    ----------
    network : {'shipped', 'adapted'}
        The shipped network or the one fine-tuned on the picks.
    sensitivity : float
        The tracing's sensitivity, in [0, 1] (:attr:`~seismo3d.seismic.FaultTracingOptions.sensitivity`).
    unbroken_veto : bool
        Whether the tracing's evidence drops the faults across which the reflectors continue unbroken
        (:attr:`~seismo3d.seismic.faults.EvidenceOptions.unbroken_veto`).
    """

    network: str
    sensitivity: float
    unbroken_veto: bool

    def options(self, trial=None):
        """The tracing's options (:class:`~seismo3d.seismic.FaultTracingOptions`): with the adapted network, the
        MODEL folder ``trial`` run as :meth:`~seismo3d.seismic.FaultTracingOptions.with_model` runs a MODEL."""
        from ..seismic.faults.options import FaultTracingOptions

        opt = FaultTracingOptions()
        if self.network == "adapted":
            opt = opt.with_model(trial)
        return replace(opt, sensitivity=self.sensitivity,
                       evidence=replace(opt.evidence, unbroken_veto=self.unbroken_veto))

    def describe(self) -> str:
        """A few words: the network, its sensitivity and the veto."""
        return (f"{self.network} network at sensitivity {self.sensitivity:g}, unbroken veto "
                f"{'on' if self.unbroken_veto else 'off'}")


@dataclass(frozen=True)
class HeldBackScores:
    """A :class:`HeldBackTracing` scored on the held-back traces of each line.

    Attributes
    ----------
    tracing : HeldBackTracing
    lines : list of dict
        Per line with held-back traces: ``precision``, ``recall``, ``f1`` (tolerant, 3 samples), rounded to 4 digits.
    """

    tracing: HeldBackTracing
    lines: list

    @property
    def f1(self) -> float:
        """The mean F1 over the lines."""
        return float(np.mean([s["f1"] for s in self.lines]))

    def summary(self) -> dict:
        """The tracing and its scores, for MODEL's record."""
        return {**asdict(self.tracing), "f1": round(self.f1, 4), "lines": self.lines}


def held_back_tracings(options) -> list:
    """The ways of tracing the held-back traces that ``seismo3d adapt`` scores, the first of equal scores chosen
    (:func:`chosen_tracing`): the shipped network as ``seismo3d faults`` runs it by default; the adapted network at
    ``options.sensitivity`` with the evidence's unbroken veto on, then off.

    The veto drops a fault across which the reflectors continue unbroken whatever the network says: right for the
    shipped network, trained on faults that all offset the reflectors, it throws away what an interpreter taught the
    adapted network when they draw faults where the reflectors dim or fracture without a throw (the test's generated
    sections of dimmed zones: traced by the adapted network with the veto off, dropped with it on).

    The sensitivity is not chosen there: adapted on F3 inline 100, its held-back band scored best at 0.65 of 0.2,
    0.35, 0.5 and 0.65 (F1 0.577), where the four inlines not picked scored 0.49 (0.57 at ``options.sensitivity``,
    0.35; 2026-11-28): a band of a quarter of a line holds too few faults to choose a threshold from.

    Parameters
    ----------
    options : seismo3d.training.adapt_options.AdaptOptions

    Returns
    -------
    list of HeldBackTracing
    """
    from ..seismic.faults.options import FaultTracingOptions

    default = FaultTracingOptions()
    return [HeldBackTracing("shipped", float(default.sensitivity), bool(default.evidence.unbroken_veto))] + [
        HeldBackTracing("adapted", float(options.sensitivity), veto) for veto in (True, False)]


def chosen_tracing(scored: list) -> HeldBackScores:
    """The scored tracing MODEL traces with: the adapted network's tracing of the highest mean held-back F1 (the
    first of equals) when it wins clearly over the shipped network's default (:func:`wins_clearly`), else the
    shipped network's default.

    Parameters
    ----------
    scored : list of HeldBackScores
        The shipped network's default first (:func:`held_back_tracings`' order).

    Returns
    -------
    HeldBackScores
    """
    shipped, adapted = scored[0], [s for s in scored[1:] if s.tracing.network == "adapted"]
    if not adapted:
        return shipped
    best = adapted[int(np.argmax([s.f1 for s in adapted]))]
    return best if wins_clearly(best, shipped) else shipped


def wins_clearly(candidate: HeldBackScores, reference: HeldBackScores) -> bool:
    """Whether ``candidate`` traces the held-back picks clearly better than ``reference``: a higher mean F1 over the
    held-back traces, and a higher F1 on more than half of the held-back parts holding picks
    (:func:`held_back_parts`; a tie is no win).

    One band of a quarter of a line holds few faults, so its mean F1 can rest on one of them: adapted on F3 inline
    500 (0.9 % fault samples), the fine-tuned network tied the shipped one on its band (F1 0.486 against 0.485) by
    tracing one fault the shipped network missed and missing one it traced (parts F1 0 / 0 / 0.655 against
    0 / 0.958 / 0.330), and lost on the four inlines not picked (0.398 against 0.489). Adapted on inline 100 it won
    both parts holding picks (0.604 / 0.180 against 0.553 / 0) and won on the four other inlines (0.566 against
    0.497; measured 2026-11-28, ``benchmarks/adapt.py``'s folds).

    Parameters
    ----------
    candidate, reference : HeldBackScores
        Scored on the same lines (their ``lines`` in the same order, each with ``parts_f1``).

    Returns
    -------
    bool
    """
    pairs = _paired_parts(candidate, reference)
    won = sum(c > r for c, r in pairs)
    return candidate.f1 > reference.f1 and won > len(pairs) / 2


def _paired_parts(candidate: HeldBackScores, reference: HeldBackScores) -> list:
    """(candidate's F1, reference's F1) of every held-back part holding picks, line by line."""
    return [(c, r) for cl, rl in zip(candidate.lines, reference.lines)
            for c, r in zip(cl["parts_f1"], rl["parts_f1"]) if c is not None and r is not None]


def held_back_parts(band: tuple, n: int = HELD_BACK_PARTS) -> list:
    """The held-back traces of a line cut into ``n`` parts of equal width (within a trace when they do not divide),
    each scored on its own (:func:`wins_clearly`).

    Parameters
    ----------
    band : (int, int)
        The held-back traces [first, end).
    n : int, optional
        Parts, >= 1.

    Returns
    -------
    list of (int, int)
        [first, end) of each non-empty part, in trace order.
    """
    edges = np.linspace(band[0], band[1], int(n) + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:]) if b > a]


def _held_back_scores(held: list, tracings: list, trial) -> list:
    """Each tracing scored on the held-back traces of each line (:class:`HeldBackScores`); the network runs once
    per line, the other tracings of that network take its likelihood."""
    from ..seismic.faults.pipeline import trace_faults
    from ..seismic.faults.result import FaultLikelihood, fault_labels

    scores = [[] for _ in tracings]
    for line in held:
        likelihood = None
        for k, tracing in enumerate(tracings):
            result = trace_faults(line.section, sample_interval=line.sample_interval, sample_unit=line.sample_unit,
                                  options=tracing.options(trial), likelihood=likelihood, progress=False)
            likelihood = FaultLikelihood(result.likelihood, result.strike_deg, result.dip_deg)
            scores[k].append(_band_scores(line, fault_labels(result.faults, line.section.shape) > 0))
    return [HeldBackScores(t, s) for t, s in zip(tracings, scores)]


def _band_scores(line: _Line, traced: np.ndarray) -> dict:
    """Tolerant precision / recall / F1 (3 samples) of the traced faults in the line's held-back band, and the F1
    of each of its parts (:func:`held_back_parts`; None in a part without picks)."""
    a, b = line.band
    p, r, f1 = tolerant_scores(traced[a:b], line.picks[a:b], 3.0)
    parts = [round(tolerant_scores(traced[u:v], line.picks[u:v], 3.0)[2], 4) if line.picks[u:v].any() else None
             for u, v in held_back_parts(line.band)]
    return {"precision": round(p, 4), "recall": round(r, 4), "f1": round(f1, 4), "parts_f1": parts}


def training_grids(section: np.ndarray, picks: np.ndarray, band: tuple, labels: str = "band") -> list:
    """A picked line on each network grid the tracing runs it on, with its picks and the loss weights (0 in the
    held-back band), as :func:`seismo3d.training.adapt.fine_tune` takes them.

    Parameters
    ----------
    section : (n_traces, n_samples) float32 ndarray
        Amplitudes.
    picks : (n_traces, n_samples) bool ndarray
        The interpreter's fault samples.
    band : (int, int)
        The held-back traces [first, end) (:func:`held_back_band`).
    labels : {'band', 'thin'}, optional
        The labels: the picks as drawn, or their skeleton on each grid, the other picked samples within 2 samples
        of it not counted (weight 0), so that a band drawn several samples wide does not teach a wide fault.

    Returns
    -------
    list of (x, y, w) float32 ndarrays
        Per grid (``LearnedOptions().grids``): the normalised amplitudes resampled as
        :func:`~seismo3d.seismic.faults.likelihood.network_grid.to_network_grid` does (stretched along the samples when
        the tracing stretches them), the picks and the weights resampled with them.
    """
    from ..seismic.faults.likelihood.learned import LearnedOptions, amplitude_scale
    from ..seismic.faults.likelihood.network import POOLING_MULTIPLE, normalise_section
    from ..seismic.faults.likelihood.network_grid import to_network_grid

    thin = {"band": False, "thin": True}[labels]
    opt = LearnedOptions()
    weight = np.ones(section.shape, np.float32)
    weight[band[0]:band[1]] = 0.0
    scale = amplitude_scale(section)
    grids = []
    for factor in opt.grids(section.shape[1], 2):
        small, _ = to_network_grid(section, factor, align=POOLING_MULTIPLE)
        x = normalise_section(small, scale=scale)
        stretch = opt.stretch(section.shape[1], factor, 2)
        size = (x.shape[0], stretch or x.shape[1])
        if size != x.shape:  # the short traces stretched along the samples, as the tracing does
            x = zoom(x, (1.0, size[1] / x.shape[1]), order=3).astype(np.float32)
        resampled = [zoom(a.astype(np.float32), (size[0] / a.shape[0], size[1] / a.shape[1]), order=1)
                     for a in (picks, weight)]
        y, w = resampled[0] > 0.25, (resampled[1] > 0.5).astype(np.float32)
        if thin:
            from scipy.ndimage import binary_dilation
            from skimage.morphology import skeletonize

            skeleton = skeletonize(y)
            w[binary_dilation(skeleton, iterations=2) & ~skeleton] = 0.0
            y = skeleton
        grids.append((x, y.astype(np.float32), w))
    return grids


def write_model(model, network: bytes, record: RunRecord, inputs: dict, results: dict) -> Path:
    """Write a MODEL folder atomically: the network and its record (the network's sha256 added to ``results``).

    Parameters
    ----------
    model : str or os.PathLike
        The folder (replaced if present: the caller refuses an existing one first).
    network : bytes
        A serialised ONNX model of the fault network's architecture
        (:func:`~seismo3d.training.export_onnx.onnx_model`).
    record : RunRecord
        The run's record (written as ``adapt.json``).
    inputs : dict
        Input paths by role, identified with their sha256 in the record.
    results : dict
        What the run measured (:func:`run_adapt_job`'s record).

    Returns
    -------
    pathlib.Path
        The MODEL folder.
    """
    model = Path(model)
    results = dict(results, network_sha256=hashlib.sha256(network).hexdigest())
    with atomic_directory(model) as tmp:
        (tmp / MODEL_NETWORK).write_bytes(network)
        record.write(tmp / MODEL_RECORD, inputs=inputs,
                     outputs={"network": model / MODEL_NETWORK, "record": model / MODEL_RECORD}, results=results)
    return model


def run_adapt_job(inputs, picks, model, *, iline=189, xline=193, endian=None, ignore_geometry=False,
                  sample_unit=None, options=None, steps=None, progress=True) -> AdaptJobResult:
    """Adapt the fault network to a survey from an interpreter's faults on a few lines: the ``seismo3d adapt``
    command (module notes).

    Parameters
    ----------
    inputs : sequence of str or os.PathLike
        The picked lines: SEG-Y inlines or crosslines, ``.npy`` (n_traces, n_samples) or ``.f32be`` sections, or a 3D
        SEG-Y cube whose fault sticks were picked on some of its inlines and crosslines (each such line taken out of
        the cube and learned from as a picked line; :func:`~seismo3d.jobs.evaluate.read_picked_lines`).
    picks : sequence of ('sticks' or 'mask', path)
        The interpreter's faults, the i-th on the i-th input (or one fault-stick file for every input): fault sticks
        (OpendTect, Charisma, IESX; on a line, sticks of other lines left out; on a cube, every stick on one of its
        inlines or crosslines) or a mask of the line (.npy (n_traces, n_samples) or an image of a row per sample).
    model : str or os.PathLike
        The MODEL folder to write (must not exist).
    iline, xline, endian, ignore_geometry, sample_unit : optional
        How the SEG-Y inputs are read (as ``seismo3d faults`` reads them).
    options : seismo3d.training.adapt_options.AdaptOptions, optional
        The fine-tuning (default: every layer, 100 steps of 4 patches, seed 0).
    steps : int, optional
        Training steps, in place of ``options``' (``--steps``: the command passes plain values, so that it imports
        PyTorch only once the inputs have been read).
    progress : bool, optional
        Log the stages and a progress bar over the training steps.

    Returns
    -------
    AdaptJobResult

    Raises
    ------
    InputError
        MODEL exists; inputs and picks do not pair; an input neither a line nor a SEG-Y cube (a trace list, a 3D
        array), or a cube with a mask; sticks not on their line; on a cube, a stick on no single inline or crossline,
        between two of its lines or outside it; a mask of another shape; a line without picked faults or with fewer
        traces than :func:`min_traces`. All before the work.
    MissingDependencyError
        PyTorch or onnx missing (the message says how to install them), after the inputs' checks, before the work.
    DataNotFoundError
        An input or pick file is missing.
    """
    record = RunRecord("adapt", locals())
    model = Path(model)
    picks = [(str(k), Path(p)) for k, p in picks]
    if any(k not in ("sticks", "mask") for k, _ in picks):
        raise InputError("each pick must be ('sticks', path) or ('mask', path)")
    _check_before_work(list(inputs), picks, model)
    segy = dict(iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian, sample_unit=sample_unit)
    segy = {k: v for k, v in segy.items() if v is not None}
    with record.stage("read lines and picks"):
        lines = _read_lines(list(inputs), picks, segy)
    lines = [replace(line, band=band) for line, band in zip(lines, held_back_traces([ln.picks for ln in lines]))]
    held = [line for line in lines if line.band[1] > line.band[0]]
    training = training_module()
    from ..seismic.faults.likelihood.network import WEIGHTS_FILE
    from ..training.export_onnx import onnx_model

    opt = options or AdaptOptions()
    if steps is not None:
        opt = replace(opt, steps=int(steps))
    say = LOGGER.info if progress else (lambda *a: None)
    tracings = held_back_tracings(opt)
    with record.stage("held-back score before"):
        scored = _held_back_scores(held, [t for t in tracings if t.network == "shipped"], None)
    say("held-back F1 with the shipped network: %.3f", scored[0].f1)
    from importlib import resources

    shipped = resources.files("seismo3d.seismic.faults.likelihood")
    with shipped.joinpath("fault_unet.npz").open("rb") as fh, np.load(fh) as npz:
        start = {k: npz[k] for k in npz.files}
    with record.stage("fine-tune"):
        grids = [g for line in lines if line.band != (0, line.section.shape[0])
                 for g in training_grids(line.section, line.picks, line.band, opt.labels)]
        tuned = training.fine_tune(start, grids, options=opt, progress=progress)
    network = onnx_model(tuned["weights"])
    with record.stage("held-back score after"), _staged_model(model, network) as trial:
        scored += _held_back_scores(held, [t for t in tracings if t.network == "adapted"], trial)
    best = chosen_tracing(scored)
    adapted = max((s for s in scored if s.tracing.network == "adapted"), key=lambda s: s.f1)  # the first of equals
    before, after = scored[0].lines, adapted.lines
    kept = "adapted" if best.tracing.network == "adapted" else "default"
    if kept == "default":
        network = shipped.joinpath(WEIGHTS_FILE).read_bytes()
    described = [{"input": str(line.input), "line": line.name, "n_traces": int(line.section.shape[0]),
                  "n_samples": int(line.section.shape[1]), "picked_samples": int(line.picks.sum()),
                  "held_back_traces": list(line.band)} for line in lines]
    results = {"kept": kept, "method": opt.method() if kept == "adapted" else "the shipped network",
               "sensitivity": best.tracing.sensitivity if kept == "adapted" else None,
               "unbroken_veto": best.tracing.unbroken_veto if kept == "adapted" else None,
               "held_back_before": before, "held_back_after": after,
               "held_back_f1_before": round(scored[0].f1, 4), "held_back_f1_after": round(adapted.f1, 4),
               "held_back_tracings": [s.summary() for s in scored], "lines": described,
               "training": {**asdict(opt), "loss": tuned["loss"]}}
    roles = {f"input_{i}": line.input for i, line in enumerate(lines)}
    roles.update({f"{kind}_{i}": path for i, (kind, path) in enumerate(picks)})
    write_model(model, network, record, roles, results)
    return AdaptJobResult(kept, before, after, described, model, dict(record.stage_seconds), scored)


@contextmanager
def _staged_model(model: Path, network: bytes):
    """A MODEL folder of the trial network in a temporary folder beside MODEL (removed after), for the tracing that
    scores it (each :class:`HeldBackTracing` sets its own sensitivity and veto)."""
    with tempfile.TemporaryDirectory(prefix=f".{model.name}.trial.", dir=model.parent) as tmp:
        yield write_model(Path(tmp) / "trial", network, RunRecord("adapt", {}), {}, {"kept": "trial"})
