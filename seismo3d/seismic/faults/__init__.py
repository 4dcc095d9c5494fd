"""Fault interpretation: fault likelihood -> optimal surface voting -> fault skins -> throw -> evidence.

After Hale (2013, 2014) and Wu & Fomel (2018). :func:`trace_faults` runs the whole interpretation of a cube or
section (:mod:`~seismo3d.seismic.faults.pipeline`); the names below are what a user calls or receives. The
algorithms live in folders that name them:

- :mod:`~seismo3d.seismic.faults.likelihood`: step 1, the fault likelihood: the fault network
  (:func:`learned_fault_likelihood`, :mod:`~seismo3d.seismic.faults.likelihood.learned`, its forward pass in
  :mod:`~seismo3d.seismic.faults.likelihood.network`, its grids in ``network_grid``) or the scan of fault strikes and
  dips (:func:`fault_likelihood`, :mod:`~seismo3d.seismic.faults.likelihood.scan`, its kernels in ``scan_kernels``).
- :mod:`~seismo3d.seismic.faults.surfaces`: from likelihood to fault surfaces (the likelihood cleared near the dead
  samples of :mod:`~seismo3d.seismic.amplitudes`): ridges and thinning (:func:`thin_faults`,
  :mod:`~seismo3d.seismic.faults.surfaces.ridges`), optimal surface voting (:func:`vote_faults`,
  :mod:`~seismo3d.seismic.faults.surfaces.voting`, its loops in ``voting_kernels``), fault skins (:func:`fault_skins`,
  :mod:`~seismo3d.seismic.faults.surfaces.skins`, its merges in ``skin_merging``, its 2D splits in ``skin_splits``).
- :mod:`~seismo3d.seismic.faults.throw`: throw by registering the reflectors on both sides (:func:`fault_throws`;
  its patches in :mod:`~seismo3d.seismic.faults.throw_patches`, the cube read near a fault, in memory, lazy or
  stored, in :mod:`~seismo3d.seismic.faults.windows`); :mod:`~seismo3d.seismic.faults.evidence`: the
  evidence a fault must show, with the reflectors' half period it compares a throw with
  (:mod:`~seismo3d.seismic.faults.reflector_period`); :mod:`~seismo3d.seismic.faults.tips`: the tips of the kept 2D
  faults cut back to where the likelihood holds.
- :mod:`~seismo3d.seismic.faults.options` (:class:`FaultTracingOptions`), :mod:`~seismo3d.seismic.faults.result`
  (the results and the index-space conventions), :mod:`~seismo3d.seismic.faults.steps` (the steps after the likelihood,
  over any run, and the refusals: before the work, between the steps, from a sample of blocks),
  :mod:`~seismo3d.seismic.faults.pipeline` (:func:`trace_faults`, in memory or by blocks).

How a cube is run, in memory or by blocks into resumable Zarr stores under a memory limit, is the executor's
(:mod:`seismo3d.seismic.blocks`, its options :class:`~seismo3d.seismic.blocks.BlockRunOptions`): the algorithms here
know nothing of memory limits, stores or resumption.
"""

from .evidence import EvidenceOptions, FaultEvidence
from .likelihood import FaultScanOptions, LearnedOptions, fault_likelihood, learned_fault_likelihood
from .options import FaultTracingOptions
from .pipeline import trace_faults
from .result import Fault, FaultInterpretation, FaultLikelihood, FaultVotes
from .surfaces import SkinOptions, VotingOptions, fault_skins, thin_faults, vote_faults
from .throw import FaultThrow, ThrowOptions, fault_throws

__all__ = [
    "trace_faults", "FaultTracingOptions", "FaultInterpretation", "Fault", "FaultLikelihood", "FaultScanOptions",
    "fault_likelihood", "LearnedOptions", "learned_fault_likelihood", "thin_faults", "VotingOptions", "FaultVotes",
    "vote_faults", "SkinOptions", "fault_skins", "ThrowOptions", "FaultThrow", "fault_throws", "EvidenceOptions",
    "FaultEvidence",
]
