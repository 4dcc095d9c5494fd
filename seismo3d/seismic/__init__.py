"""Seismic interpretation on the registration engine, in three sub-packages and a few modules shared by them.

Sub-packages:

- :mod:`~seismo3d.seismic.io`: reading and writing seismic data.

  - :mod:`~seismo3d.seismic.io.segy`: SEG-Y cubes and lines (sections: raw sections, ASCII lines; writer: SEG-Y like a
    template).
  - :mod:`~seismo3d.seismic.io.layout`: byte order, sample format and rev-2 headers of a SEG-Y file.
  - :mod:`~seismo3d.seismic.io.geometry`: the traces of a file without an inline / crossline grid.
  - :mod:`~seismo3d.seismic.io.blocks`: a SEG-Y cube read by blocks of traces (:class:`SegyGrid`), the dask array
    of ``seismo3d.open``'s SEG-Y inputs.
  - :mod:`~seismo3d.seismic.io.zarr_store`: the Zarr v3 layout of ``seismo3d convert`` (xarray opens it as is).
  - :mod:`~seismo3d.seismic.io.writer`: a SEG-Y file written block by block like another.

- :mod:`~seismo3d.seismic.faults`: fault interpretation.

  - :mod:`~seismo3d.seismic.faults.likelihood`: the fault likelihood (the fault network, or the scan of strikes and
    dips).
  - :mod:`~seismo3d.seismic.faults.surfaces`: dead samples, ridges and thinning, voting, fault skins.
  - :mod:`~seismo3d.seismic.faults.throw`: throw by registering the reflectors on both sides of a fault;
    :mod:`~seismo3d.seismic.faults.evidence`: the evidence a fault must show.
  - :mod:`~seismo3d.seismic.faults.pipeline`: the whole fault interpretation (:func:`trace_faults`).

- :mod:`~seismo3d.seismic.horizons`: horizon tracking.

  - :mod:`~seismo3d.seismic.horizons.result`: the horizon result, seeds, gap filling, text export.
  - :mod:`~seismo3d.seismic.horizons.options`: :class:`TrackingOptions`.
  - :mod:`~seismo3d.seismic.horizons.fault_crossings`: which faults a horizon step crosses and the jump there.
  - :mod:`~seismo3d.seismic.horizons.tracking`: :func:`track_horizon`; horizon tracking by registering neighbouring
    slices.
  - :mod:`~seismo3d.seismic.horizons.lsq`: least-squares horizons from correlations of near and distant traces (the
    default method), the cycle-skip self-check.
  - :mod:`~seismo3d.seismic.horizons.correlation`: correlation of trace windows pair by pair.
  - :mod:`~seismo3d.seismic.horizons.dp`: dynamic programming over candidate picks along each line, swept over
    inlines and crosslines in a cube.
  - :mod:`~seismo3d.seismic.horizons.cycle_cut`: regions a cycle off moved by a minimum cut.
  - :mod:`~seismo3d.seismic.horizons.autotracker`: the plain amplitude autotracker (the peer).

- :mod:`~seismo3d.seismic.volumes`: registration of sub-volumes of different bin size, sample rate and orientation.

Modules shared by the sub-packages:

- :mod:`~seismo3d.seismic.attributes`: structure tensor (reflector orientation), semblance, coherence.
- :mod:`~seismo3d.seismic.traces`: trace primitives (sub-sample peaks, waveform windows, NCC, lag search).
- :mod:`~seismo3d.seismic.reflectors`: reflector picks along traces, reflector slices, reflector points.
- :mod:`~seismo3d.seismic.blocks`: running a cube larger than memory block by block into resumable Zarr stores
  (options, memory, the resumable block run, windows of a cube).
- :mod:`~seismo3d.seismic.evaluation`: fault scores, horizon errors, registration errors against ground truth.
- ``seismo3d.seismic._kernels``: the numba kernels shared by attributes, faults and horizons (private).
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

# the public names, imported on first use (seismo3d._lazy): importing one module of the package (the SEG-Y reader of
# `seismo3d convert`) runs neither the fault and horizon modules nor scipy and numba
if TYPE_CHECKING:
    from .attributes import (
        ReflectorOrientation, discontinuity, eigen_coherence, semblance, structure_tensor_orientation,
        structure_tensor_slopes,
    )
    from .evaluation import (
        FaultLineCoverage, FaultScores, HorizonErrors, HorizonOffsets, RegistrationErrors, evaluate_faults,
        fault_line_coverage, horizon_errors, horizon_offsets, registration_errors,
    )
    from .faults import (
        EvidenceOptions, Fault, FaultEvidence, FaultInterpretation, FaultLikelihood, FaultScanOptions, FaultThrow,
        FaultTracingOptions, FaultVotes, LearnedOptions, SkinOptions, ThrowOptions, VotingOptions, fault_likelihood,
        fault_skins, fault_throws, learned_fault_likelihood, thin_faults, trace_faults, vote_faults,
    )
    from .faults.evidence import supported_faults
    from .faults.result import fault_labels, fault_normals
    from .amplitudes import CleanTraces, clean_traces, dead_samples, fill_values, near_dead_samples
    from .faults.throw import fault_throw
    from .blocks import BlockRunOptions
    from .horizons import (
        CycleCut, FaultCrossings, Horizon, TrackingOptions, autotrack, fill_horizon, reliable_throw, track_horizon,
        write_horizon_text,
    )
    from .horizons.cycle_cut import cycle_cut
    from .io import (
        SegyLayout, SeismicCube, TraceGeometry, open_segy, read_ascii_lines, read_section, read_segy, read_segy_layout,
        trace_geometry, write_like,
    )
    from .reflectors import POLARITIES, reflector_picks, reflector_points
    from .volumes import VolumeOptions, VolumeRegistration, register_volumes, resample_volume, volume_spacing

__all__ = [
    # exported before the sub-packages
    "POLARITIES", "Fault", "FaultCrossings", "FaultInterpretation", "FaultLikelihood", "FaultScanOptions",
    "FaultTracingOptions", "FaultVotes", "SkinOptions", "VotingOptions", "fault_skins",
    "vote_faults", "FaultScores", "FaultThrow", "Horizon", "HorizonErrors", "ReflectorOrientation",
    "RegistrationErrors", "SeismicCube", "ThrowOptions", "TrackingOptions", "VolumeOptions", "VolumeRegistration",
    "autotrack", "discontinuity", "eigen_coherence", "evaluate_faults", "FaultLineCoverage", "fault_line_coverage",
    "fault_labels", "fault_likelihood",
    "fault_normals", "fault_throw", "fault_throws", "fill_horizon", "horizon_errors", "HorizonOffsets",
    "horizon_offsets", "open_segy",
    "read_ascii_lines", "read_section", "read_segy", "reflector_picks", "reflector_points", "register_volumes",
    "registration_errors", "reliable_throw", "resample_volume", "semblance", "structure_tensor_orientation",
    "structure_tensor_slopes", "thin_faults", "trace_faults", "track_horizon", "volume_spacing", "write_horizon_text",
    "write_like",
    # io: SEG-Y layout and geometry (reading and writing by blocks, the Zarr store of `seismo3d convert`: in
    # seismo3d.seismic.io, behind seismo3d.open and the commands)
    "SegyLayout", "read_segy_layout", "TraceGeometry", "trace_geometry",
    # faults: dead samples, the learned likelihood
    "CleanTraces", "clean_traces", "dead_samples", "near_dead_samples", "fill_values",
    "LearnedOptions", "learned_fault_likelihood",
    # faults: how trace_faults runs a cube (in memory or by blocks; the executor itself is seismo3d.seismic.blocks')
    "BlockRunOptions",
    # faults: the evidence a fault must show
    "EvidenceOptions", "FaultEvidence", "supported_faults",
    # horizons: the cycle-skip cut
    "CycleCut", "cycle_cut",
]

__getattr__, __dir__ = lazy_exports(__name__, __file__)
