"""The options and the result of :func:`~seismo3d.seismic.faults.trace_faults`, whichever way it runs (in memory or
block by block)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..._validation import check_choice, check_positive
from ...errors import InputError
from ..adapted_network import model_tracing
from .evidence import EvidenceOptions, sensitivity_factor
from .likelihood.learned import LearnedOptions
from .likelihood.scan import FaultScanOptions
from ..amplitudes import DeadSampleOptions
from .surfaces.skins import SkinOptions
from ..blocks.statistics import otsu, quantile
from .surfaces.voting import VotingOptions

__all__ = ["FaultTracingOptions", "LIKELIHOODS"]

LIKELIHOODS = ("scan", "learned")


@dataclass(frozen=True)
class FaultTracingOptions:
    """Options of :func:`trace_faults`; the defaults are the ones every seismo3d command uses, on every input.

    Attributes
    ----------
    sensitivity : float
        In [0, 1]: how readily a fault is traced. The upper threshold on the thinned votes is the data's Otsu
        threshold times ``2 ** (1 - 2 * sensitivity)`` (twice it at 0, half of it at 1, the threshold itself at the
        default 0.5), at least ``min_vote`` times the same factor; the lower threshold is a third of the upper one.
    min_vote : float
        Floor of the upper threshold at the default sensitivity, on the absolute scale of
        :class:`~seismo3d.seismic.faults.result.FaultVotes` (about the mean likelihood of the surfaces through a
        sample): data whose votes are all weak yield no faults rather than the strongest of its noise.
    max_fault_fraction : float
        The lower threshold leaves at most this fraction of the samples on thinned faults (scaled like the
        thresholds by the sensitivity): a fault every 8 traces is already dense faulting (12 % on the Costa Rica
        sections), and denser ridges are the uniform votes of incoherent data, not faults.
    likelihood : {'scan', 'learned'}
        The fault likelihood of step 1: the fault network trained on generated sections
        (:mod:`~seismo3d.seismic.faults.likelihood.learned`, ``learned``, the default) or the scan of fault-plane
        semblance (Hale 2013, ``scan``). The default was chosen on the F3 inlines with faults drawn by a person (mean F1
        0.474 against the scan's 0.204, cross-validated, ``python benchmarks/faults.py --only f3``); against the
        published OSV faults of the Costa Rica crf section the scan finds more (recall 0.72 against 0.27).
    scan : FaultScanOptions
        The fault likelihood scan.
    learned : LearnedOptions
        The learned fault likelihood. By default its network runs on every second inline and crossline section of
        a cube, the sections between interpolated (``LearnedOptions.section_step``, 2; a 2D line is one section,
        run whole): the
        fault likelihood of a generated 256^3 cube 43.7 -> 27.7 CPU seconds on 2 threads, the whole command 73.3 ->
        54.0 (``python benchmarks/fault_speed.py``), for the same scores: the Parihaka cube 0.81 of the fault bands
        hit and 0.83 of the traced points in bands at step 1 and 2 (``python benchmarks/faults_3d.py --only
        parihaka``), the generated 128^3 cubes precision 0.983-0.998 and recall 0.916-0.990 against 0.985-0.998 and
        0.915-0.989 (``python benchmarks/faults.py --only generated``).
    voting : VotingOptions
        The optimal surface voting.
    skins : SkinOptions
        The linking into fault skins.
    dead : DeadSampleOptions
        What counts as a dead sample (mutes, dead traces, gaps), whose edges are not faults, and how far the
        likelihood is cleared around them (:mod:`~seismo3d.seismic.amplitudes`).
    evidence : EvidenceOptions or None
        What a fault must show to be kept (:func:`~seismo3d.seismic.faults.evidence.supported_faults`); None: the
        likelihood's defaults (:meth:`~seismo3d.seismic.faults.evidence.EvidenceOptions.for_likelihood`).
    min_traces : (int, int)
        Fewest traces along the longer and the shorter lateral axis (2D: along the section) for the scan and the
        voting boxes to see a fault's continuity; smaller data is refused.
    min_samples : int
        Fewest samples per trace.
    min_crossings : float
        Fewest zero crossings per 100 samples of a trace with its mean removed (median over traces): seismic
        amplitudes oscillate (a reflection every few samples), velocity or impedance models do not.
    max_saturated : float
        Largest fraction of the live samples with a likelihood above ``saturation_level``; beyond it the data has no
        lateral coherence to trace faults in (noise, or traces out of order) and is refused.
    saturation_level : float
        In (0, 1): a likelihood above it counts as saturated (0.9).
    tip_level : float or None
        2D, the learned likelihood (a probability): after the evidence, each end of a kept fault is cut back to its
        first point, from that end, where the network's probability (the largest within a trace) reaches this level
        (:func:`~seismo3d.seismic.faults.tips.trimmed_tips`; the fault count and the evidence are
        unchanged): the voting carries a fault's votes, and its skin, up to ``half_length_dip`` samples past its tips.
        The points and the throw profile are the trimmed fault's; the evidence and the summary's whole-fault values
        (median throw, step, vote ratio, mean likelihood, confidence) are those of the fault as the evidence judged it.
        None: not trimmed (the scan's likelihood, not a probability, and 3D faults are never trimmed). Measured
        2026-11-26 (``tools/dev_fault_scores.py``; None, 0.1, 0.15, 0.2, 0.3, 0.4): the Great South Basin's F1 0.829,
        0.836, 0.840, 0.841, 0.844, 0.844 (precision 0.797 -> 0.812 at 0.1, 0.828 at 0.3), F3's 0.496, 0.495, 0.496,
        0.497, 0.496, 0.492 (precision 0.615 -> 0.623 at 0.1, 0.638 at 0.3; recall 0.423 -> 0.418, 0.413):
        leave-one-survey-out the Great South Basin chooses 0.3 (F3 there 0.496), F3 0.2 (the Great South Basin there
        0.841). But the generated sections' true faults fade out too (``benchmarks/faults.py --only generated``: recall
        0.882 -> 0.881, 0.879, 0.878, 0.875; precision 0.970 -> 0.976, 0.977, 0.978, 0.979): 0.1 is the level that keeps
        their recall. Trimmed before the evidence instead, F3 fell to 0.484 at 0.3 (the trimmed skins' higher mean
        probability kept 6 more false faults on inline 400).

    Raises
    ------
    InputError
        A value out of range.
    """

    sensitivity: float = 0.5
    min_vote: float = 0.1
    max_fault_fraction: float = 0.15
    likelihood: str = "learned"
    scan: FaultScanOptions = field(default_factory=FaultScanOptions)
    learned: LearnedOptions = field(default_factory=LearnedOptions)
    voting: VotingOptions = field(default_factory=VotingOptions)
    skins: SkinOptions = field(default_factory=SkinOptions)
    dead: DeadSampleOptions = field(default_factory=DeadSampleOptions)
    evidence: EvidenceOptions | None = None
    min_traces: tuple = (32, 8)
    min_samples: int = 32
    min_crossings: float = 3.0
    max_saturated: float = 0.95
    saturation_level: float = 0.9
    tip_level: float | None = 0.1

    def __post_init__(self):
        if not 0.0 <= float(self.sensitivity) <= 1.0:
            raise InputError(f"sensitivity must be in [0, 1]; got {self.sensitivity!r}")
        if not 0.0 <= float(self.min_vote) < 1.0:
            raise InputError(f"min_vote must be in [0, 1); got {self.min_vote!r}")
        if not 0.0 < float(self.max_fault_fraction) <= 1.0:
            raise InputError(f"max_fault_fraction must be in (0, 1]; got {self.max_fault_fraction!r}")
        check_choice(self.likelihood, "likelihood", LIKELIHOODS)
        if self.evidence is None:
            object.__setattr__(self, "evidence", EvidenceOptions.for_likelihood(self.likelihood))
        for name, cls in (("scan", FaultScanOptions), ("learned", LearnedOptions), ("voting", VotingOptions),
                          ("skins", SkinOptions), ("dead", DeadSampleOptions),
                          ("evidence", EvidenceOptions)):
            if not isinstance(getattr(self, name), cls):
                raise InputError(f"{name} must be a {cls.__name__}; got {type(getattr(self, name)).__name__}")
        if (len(tuple(self.min_traces)) != 2 or any(int(v) != v or v < 3 for v in self.min_traces)):
            raise InputError(f"min_traces must be two integers >= 3; got {self.min_traces!r}")
        object.__setattr__(self, "min_traces", tuple(int(v) for v in self.min_traces))
        check_positive(self.min_samples, "min_samples")
        check_positive(self.min_crossings, "min_crossings", allow_zero=True)
        if not 0.0 < float(self.max_saturated) <= 1.0:
            raise InputError(f"max_saturated must be a fraction in (0, 1]; got {self.max_saturated!r}")
        if not 0.0 < float(self.saturation_level) < 1.0:
            raise InputError(f"saturation_level must be a likelihood in (0, 1); got {self.saturation_level!r}")
        if self.tip_level is not None and not 0.0 <= float(self.tip_level) <= 1.0:
            raise InputError(f"tip_level must be a probability in [0, 1] or None; got {self.tip_level!r}")
        if float(self.learned.orientation_floor) >= float(self.voting.seed_threshold):
            raise InputError(f"learned.orientation_floor {self.learned.orientation_floor!r} leaves the voting's seeds "
                             f"(likelihood above seed_threshold {self.voting.seed_threshold!r}) without strike and "
                             "dip; lower orientation_floor below seed_threshold")

    def with_model(self, model, *, sensitivity: float | None = None) -> "FaultTracingOptions":
        """These options tracing with a MODEL folder of ``seismo3d adapt``: the learned likelihood running its
        network (:attr:`LearnedOptions.adapted`), at ``sensitivity``, else the sensitivity MODEL records, else these
        options'; the evidence's :attr:`~seismo3d.seismic.faults.EvidenceOptions.unbroken_veto` as MODEL records it
        (else these options'). MODEL is read and its network hashed once
        (:func:`~seismo3d.seismic.adapted_network.model_tracing`).

        Parameters
        ----------
        model : str or os.PathLike
            The MODEL folder (or its ``fault_unet.onnx``).
        sensitivity : float, optional
            In [0, 1]: the sensitivity asked for (``--sensitivity``), which wins over MODEL's.

        Returns
        -------
        FaultTracingOptions

        Raises
        ------
        DataNotFoundError, InputError
            As :func:`~seismo3d.seismic.adapted_network.check_adapted_model`; a sensitivity outside [0, 1].
        """
        tracing = model_tracing(model)
        if sensitivity is None:
            sensitivity = self.sensitivity if tracing.sensitivity is None else tracing.sensitivity
        evidence = self.evidence if tracing.unbroken_veto is None else \
            replace(self.evidence, unbroken_veto=tracing.unbroken_veto)
        return replace(self, sensitivity=sensitivity, likelihood="learned", evidence=evidence,
                       learned=replace(self.learned, adapted=str(model)))

    def tip_level_for(self, ndim: int) -> float | None:
        """The level to which the ends of the faults of a ``ndim``-D image are trimmed (``tip_level``), None when they
        are not (3D, or the scan's likelihood)."""
        return None if ndim != 2 or self.likelihood != "learned" or self.tip_level is None else float(self.tip_level)

    def thresholds(self, thinned_votes: np.ndarray) -> tuple[float, float]:
        """(lower, upper) thresholds on the thinned votes (see ``sensitivity`` and ``max_fault_fraction``)."""
        values = thinned_votes[thinned_votes > 0]
        return self.thresholds_from(otsu(values), values.size, thinned_votes.size, lambda q: quantile(values, q))

    def thresholds_from(self, otsu: float, n_values: int, n_samples: int, quantile) -> tuple[float, float]:
        """(lower, upper) thresholds from statistics of the thinned votes, as :meth:`thresholds` (for a cube whose
        thinned votes are gathered block by block).

        Parameters
        ----------
        otsu : float
            Otsu's threshold of the positive thinned votes (1 when there are none).
        n_values, n_samples : int
            Number of positive thinned votes, and of samples.
        quantile : callable
            ``quantile(q)``: the q-quantile of the positive thinned votes (``numpy.quantile``'s linear method);
            called only when they are denser than ``max_fault_fraction`` allows.

        Returns
        -------
        (float, float)
        """
        factor = sensitivity_factor(self.sensitivity)
        upper = min(0.99, factor * max(float(otsu), float(self.min_vote)))
        lower = upper / 3.0
        fraction = min(1.0, float(self.max_fault_fraction) / factor)
        if n_values > fraction * n_samples:
            dense = float(quantile(1.0 - fraction * n_samples / n_values))
            if dense > lower:
                lower = min(dense, 0.99)
                upper = max(upper, min(0.99, 3.0 * lower))
        return lower, upper


