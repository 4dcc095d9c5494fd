"""The options of adapting the fault network (:func:`seismo3d.training.adapt.fine_tune`, ``seismo3d adapt``),
apart from the training so that they import without PyTorch: the command's help, its job's checks and the held-back
tracings (:func:`seismo3d.jobs.adapt.held_back_tracings`) read them on a machine without the ``train`` extra.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import InputError

__all__ = ["AdaptOptions", "LAYERS", "SCALE_SHIFT"]

_BLOCKS = ("enc0", "enc1", "enc2", "bottleneck", "dec2", "dec1", "dec0")
LAYERS = {"all": (), "decoder": _BLOCKS[:4], "last": _BLOCKS[:6],
          "scale_shift": _BLOCKS + ("head",), "scale_shift_head": _BLOCKS}  # the convolutions kept frozen
SCALE_SHIFT = ("scale_shift", "scale_shift_head")  # the modes that train the per-channel scales and shifts


@dataclass(frozen=True)
class AdaptOptions:
    """Options of :func:`seismo3d.training.adapt.fine_tune`.

    Attributes
    ----------
    layers : {'all', 'decoder', 'last', 'scale_shift', 'scale_shift_head'}
        The parameters trained: every convolution, the decoder's and the head (the encoder and bottleneck frozen),
        the last decoder level's and the head; or, every convolution frozen, only the per-channel scale and shift
        after each of the 14 convolutions (1,056 parameters: the batch normalisations' affine, folded into the
        convolutions when MODEL is written; BitFit, Ben Zaken et al. 2022; FiLM, Perez et al. 2018), and with
        ``'scale_shift_head'`` the head's 13 as well. Not the default: adapted on F3 inline 100, the mean F1 of
        inlines 200-500 was 0.51 with ``'scale_shift_head'`` at learning rate 0.03 (the best of 0.003-0.03, chosen
        there), against 0.57 with every convolution and 0.50 with the shipped network; adapted on inline 500, its
        held-back band fell (F1 0.49 -> 0.25) and MODEL kept the shipped network (2026-11-28,
        ``benchmarks/adapt.py --variants``).
    steps : int
        Optimiser steps (each on ``batch_size`` new patches).
    batch_size : int
        Patches per step.
    patch : int
        Side of the square patches, samples (a multiple of 8; smaller on a line of fewer traces or samples).
    learning_rate : float
        Adam's learning rate (constant).
    positive_weight : float
        Weight of the fault samples in the cross-entropy (4, the original training's).
    anchor : float
        Weight of the L2-SP penalty (Li et al. 2018): the squared distance of the trained weights to the shipped
        ones, summed, added to the loss; 0: none.
    rehearsal : float
        Share of each batch's patches drawn from the generated sections the network was trained on
        (:func:`~seismo3d.data.synthetic_sections.synthetic_fault_section`, their true faults as labels), so that it
        keeps its idea of a fault while it learns the interpreter's; 0: the picked lines only.
    focus : float
        Share of the picked lines' patches placed around a picked fault sample (the rest anywhere on the line).
    labels : {'band', 'thin'}
        The labels: the picks as drawn, or their skeleton with the picked samples near it not counted
        (:func:`seismo3d.jobs.adapt.training_grids`).
    balance : bool
        Weight the picked fault samples so that the picks hold the weighted share of fault samples the network's
        training held: ``positive_weight`` times the odds of a fault sample in the generated sections
        (:func:`seismo3d.training.adapt.generated_fault_odds`) over its odds on the picked lines (their counted
        samples); the generated patches keep ``positive_weight``. An interpreter who draws fewer faults than the
        generated sections hold (F3 inline 500: 0.9 % of its samples, inline 100 1.8 %, the generated sections
        5.2 %) may teach the network to leave faults out. Not the default: adapted on F3 inline 100, the mean F1 of
        inlines 200-500 fell from 0.57 to 0.47 (precision 0.66 -> 0.42, recall 0.50 -> 0.59, sensitivity 0.35;
        2026-11-28). False: ``positive_weight`` on every patch.
    sensitivity : float
        The tracing's sensitivity (:attr:`~seismo3d.seismic.FaultTracingOptions.sensitivity`) the adapted network
        traces with, stored in MODEL's record (``seismo3d faults --model MODEL`` uses it unless given another).
    runs : int
        Independent fine-tunings from the shipped weights, with seeds ``seed``, ``seed + 1``, ...; with more than
        one, the network adapted is their uniform soup, the mean of their weights (Wortsman et al. 2022). Not the
        default: adapted on F3 inline 100, the mean F1 of inlines 200-500 fell from 0.57 to 0.48 with three runs
        (held-back band 0.62 -> 0.48; 2026-11-28, ``benchmarks/adapt.py --only f3 --f3-source 100 --variants all
        all:runs=3``). A run on a few picked faults depends on the patches drawn, and the soup lowered that spread
        on generated dimmed zones, but it also averaged away what each run learned of the interpreter's faults.
    seed : int
        Seed of the first run (the patches drawn, the generated sections and PyTorch).
    threads : int
        PyTorch threads.
    """

    layers: str = "all"
    steps: int = 100
    batch_size: int = 4
    patch: int = 128
    learning_rate: float = 1e-3
    positive_weight: float = 4.0
    anchor: float = 0.0
    rehearsal: float = 0.25
    focus: float = 0.75
    labels: str = "band"
    balance: bool = False
    sensitivity: float = 0.35
    runs: int = 1
    seed: int = 0
    threads: int = 2

    def __post_init__(self):
        if self.layers not in LAYERS:
            raise InputError(f"layers must be one of {', '.join(map(repr, LAYERS))}; got {self.layers!r}")
        for name in ("steps", "batch_size", "runs", "threads"):
            if int(getattr(self, name)) < 1:
                raise InputError(f"{name} must be >= 1; got {getattr(self, name)!r}")
        if int(self.patch) < 16 or int(self.patch) % 8:
            raise InputError(f"patch must be a multiple of 8 of at least 16 samples; got {self.patch!r}")
        if not float(self.learning_rate) > 0 or not float(self.positive_weight) > 0:
            raise InputError("learning_rate and positive_weight must be > 0")
        if not float(self.anchor) >= 0:
            raise InputError(f"anchor must be >= 0; got {self.anchor!r}")
        if not 0.0 <= float(self.sensitivity) <= 1.0:
            raise InputError(f"sensitivity must be in [0, 1]; got {self.sensitivity!r}")
        if not isinstance(self.balance, bool):
            raise InputError(f"balance must be True or False; got {self.balance!r}")
        if self.labels not in ("band", "thin"):
            raise InputError(f"labels must be 'band' or 'thin'; got {self.labels!r}")
        if not 0.0 <= float(self.focus) <= 1.0:
            raise InputError(f"focus must be a share in [0, 1]; got {self.focus!r}")
        if not 0.0 <= float(self.rehearsal) < 1.0:
            raise InputError(f"rehearsal must be a share of each batch in [0, 1); got {self.rehearsal!r}")

    def method(self) -> str:
        """One sentence saying how the network is adapted (the ``method`` of MODEL's record)."""
        trained = {"all": "every layer", "decoder": "the decoder and head", "last": "the last decoder level and head",
                   "scale_shift": "the per-channel scales and shifts after each convolution",
                   "scale_shift_head": "the per-channel scales and shifts after each convolution and the head"}
        parts = [f"{trained[self.layers]} fine-tuned from the shipped weights, {self.steps} Adam steps of "
                 f"{self.batch_size} patches at learning rate {self.learning_rate:g}" + (
                     f", the mean of {self.runs} such runs' weights (a model soup)" if self.runs > 1 else ""),
                 f"{self.focus:.0%} of the picked patches around a picked fault"]
        if self.rehearsal:
            parts.append(f"{self.rehearsal:.0%} of each batch generated sections (rehearsal)")
        if self.anchor:
            parts.append(f"L2-SP weight {self.anchor:g}")
        if self.balance:
            parts.append("the picked fault samples weighted to the training's share of faults")
        parts.append(f"labels: the picks {'as drawn' if self.labels == 'band' else 'thinned'}; traced at sensitivity "
                     f"{self.sensitivity:g}")
        return "; ".join(parts)
