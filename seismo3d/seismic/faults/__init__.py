"""Fault interpretation: the fault-likelihood scan, thinning, voting, fault skins, throw, and the whole pipeline in
memory or by blocks of a cube stored on disk.

- :mod:`~seismo3d.seismic.faults.likelihood`: the scan over fault strikes and dips (:func:`fault_likelihood`); its
  numba kernels in :mod:`~seismo3d.seismic.faults.scan_kernels`, the planes' normals in
  :mod:`~seismo3d.seismic.faults.fault_planes`.
- :mod:`~seismo3d.seismic.faults.learned`: the learned fault likelihood, a U-Net trained on generated sections
  (:func:`learned_fault_likelihood`); its forward pass (ONNX Runtime) in :mod:`~seismo3d.seismic.faults.unet`.
- :mod:`~seismo3d.seismic.faults.dead_samples`: dead traces and dead samples, and their fill values.
- :mod:`~seismo3d.seismic.faults.windows`: windows of a cube around points (in memory, lazy or stored).
- :mod:`~seismo3d.seismic.faults.surfaces`: faults as point sets, thinning (and the older region-growing linker).
- :mod:`~seismo3d.seismic.faults.voting`: optimal surface voting (Wu & Fomel 2018); its kernels in
  :mod:`~seismo3d.seismic.faults.voting_kernels`.
- :mod:`~seismo3d.seismic.faults.skins`: thinned faults linked into fault skins (Hale 2013); the closest cells of
  different skins in :mod:`~seismo3d.seismic.faults.skin_pairs`.
- :mod:`~seismo3d.seismic.faults.throw`: throw by registering the reflectors on both sides of a fault; its patches in
  :mod:`~seismo3d.seismic.faults.throw_patches`.
- :mod:`~seismo3d.seismic.faults.evidence`: the evidence a fault must show (reflectors displaced or broken across it).
- :mod:`~seismo3d.seismic.faults.pipeline`: the whole fault interpretation (:func:`trace_faults`), in memory or block
  by block (:mod:`~seismo3d.seismic.faults.cube_run`) as :mod:`~seismo3d.seismic.faults.memory` decides
  (:func:`fits_in_memory`) with the options of :mod:`~seismo3d.seismic.faults.block_run` (:class:`BlockRunOptions`);
  its options and result in :mod:`~seismo3d.seismic.faults.interpretation`, its refusals
  in :mod:`~seismo3d.seismic.faults.checks`, the step functions both runs share in
  :mod:`~seismo3d.seismic.faults.steps`, the thresholds' statistics (in memory and streamed) in
  :mod:`~seismo3d.seismic.faults.thresholds`.
- :mod:`~seismo3d.seismic.faults.surface_steps`: the one sequence of the steps after the likelihood
  (:func:`surface_cells`, :func:`faults_from_cells`) over a :class:`SurfaceRun`: the whole array in memory
  (:class:`ArrayRun`, :mod:`~seismo3d.seismic.faults.array_run`) or the blocks of a cube
  (:mod:`~seismo3d.seismic.faults.pipeline_blocks`).
- :mod:`~seismo3d.seismic.faults.likelihood_blocks`: the likelihood scan of a cube by blocks, resumable
  (:func:`chunked_fault_likelihood`).
- :mod:`~seismo3d.seismic.faults.learned_blocks`: the learned likelihood of a cube by blocks, resumable
  (:func:`chunked_learned_likelihood`).
- :mod:`~seismo3d.seismic.faults.pipeline_blocks`: the fault surfaces of a cube by blocks
  (:func:`chunked_fault_surfaces`); their blocks and halos in :mod:`~seismo3d.seismic.faults.surface_plan`.
- :mod:`~seismo3d.seismic.faults.preflight`: a large cube judged from a sample of blocks before its full computation
  (:func:`judge_sample`), and the smallest memory limit of a run by blocks (:func:`minimum_memory_limit`).

The function :func:`~seismo3d.seismic.faults.dead_samples.dead_samples` is not re-exported here: its name is its
module's.
"""

from .likelihood import FaultLikelihood, FaultScanOptions, fault_likelihood, fault_normals, fault_strike_dip
from .learned import LearnedOptions, learned_fault_likelihood, load_fault_network
from .dead_samples import CleanTraces, clean_traces, fill_values, near_dead_samples, DEAD_REACH
from .windows import ArrayWindows, CubeWindow, LazyWindows, StoredWindows, cube_windows, is_dask_array
from .surfaces import Fault, check_fault_arrays, thin_faults, link_faults, fault_labels
from .voting import (VotingOptions, FaultVotes, vote_faults, fault_frames, greedy_seeds, image_seeds, seed_votes,
                     surface_votes)
from .skins import SkinOptions, fault_skins, image_cells, skins_from_cells
from .throw import FaultThrow, ThrowOptions, fault_throw, fault_throws, hanging_wall_normals
from .evidence import EvidenceOptions, FaultEvidence, fault_evidence, sensitivity_factor, supported_faults
from .surface_steps import SurfaceCells, SurfaceRun, faults_from_cells, surface_cells
from .array_run import ArrayRun
from .pipeline import FaultInterpretation, FaultTracingOptions, trace_faults
from .block_run import BlockRunOptions
from .likelihood_blocks import ChunkOptions, ChunkedLikelihood, chunked_fault_likelihood
from .memory import (default_memory_limit, fits_in_memory, in_memory_bytes, parse_memory_limit, resident_memory,
                     worker_baseline)
from .learned_blocks import chunked_learned_likelihood
from .pipeline_blocks import ChunkedFaults, chunked_fault_surfaces, RIDGE_HALO
from .preflight import CubeSample, SampleOptions, judge_sample, minimum_memory_limit

__all__ = [
    "FaultLikelihood", "FaultScanOptions", "fault_likelihood", "fault_normals", "fault_strike_dip", "LearnedOptions",
    "learned_fault_likelihood", "load_fault_network", "chunked_learned_likelihood", "CleanTraces",
    "clean_traces", "fill_values", "near_dead_samples", "DEAD_REACH", "ArrayWindows", "CubeWindow", "LazyWindows",
    "StoredWindows", "cube_windows", "is_dask_array", "Fault", "check_fault_arrays", "thin_faults", "link_faults",
    "fault_labels", "VotingOptions", "FaultVotes", "vote_faults", "fault_frames", "greedy_seeds", "image_seeds",
    "seed_votes", "surface_votes", "SkinOptions", "fault_skins", "image_cells", "skins_from_cells", "FaultThrow",
    "ThrowOptions", "fault_throw", "fault_throws",
    "hanging_wall_normals", "EvidenceOptions", "FaultEvidence", "fault_evidence", "sensitivity_factor",
    "supported_faults", "SurfaceCells", "SurfaceRun", "faults_from_cells", "surface_cells", "ArrayRun",
    "FaultInterpretation", "FaultTracingOptions", "trace_faults", "BlockRunOptions", "ChunkOptions",
    "ChunkedLikelihood", "chunked_fault_likelihood", "default_memory_limit", "in_memory_bytes", "resident_memory",
    "worker_baseline", "fits_in_memory", "parse_memory_limit", "ChunkedFaults", "chunked_fault_surfaces", "RIDGE_HALO", "CubeSample", "SampleOptions",
    "judge_sample", "minimum_memory_limit",
]
