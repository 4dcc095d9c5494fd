"""Seismic interpretation on the registration engine, one module per concept.

- :mod:`~seismo3d.seismic.io`: SEG-Y cubes and lines, raw sections, ASCII lines.
- :mod:`~seismo3d.seismic.lazy_cube`: :func:`open_lazy`, a 3D cube (SEG-Y or Zarr) as a dask array by inline blocks.
- :mod:`~seismo3d.seismic.seismic_zarr`: the Zarr v3 layout of ``seismo3d convert`` (xarray opens it as is).
- :mod:`~seismo3d.seismic.attributes`: structure tensor (reflector orientation), semblance, coherence.
- :mod:`~seismo3d.seismic.traces`: trace primitives (sub-sample peaks, waveform windows, NCC, lag search).
- :mod:`~seismo3d.seismic.reflectors`: reflector picks along traces, reflector slices, reflector points.
- :mod:`~seismo3d.seismic.fault_likelihood`: the scan over fault strikes and dips.
- :mod:`~seismo3d.seismic.fault_surfaces`: faults as point sets, thinning (and the older region-growing linker).
- :mod:`~seismo3d.seismic.fault_voting`: optimal surface voting (Wu & Fomel 2018).
- :mod:`~seismo3d.seismic.fault_skins`: thinned faults linked into fault skins (Hale 2013).
- :mod:`~seismo3d.seismic.fault_throw`: throw by registering the reflectors on both sides of a fault.
- :mod:`~seismo3d.seismic.faults`: the whole fault interpretation of an array (:func:`trace_faults`).
- :mod:`~seismo3d.seismic.fault_crossings`: which faults a horizon step crosses and the jump there.
- :mod:`~seismo3d.seismic.horizons`: the horizon result, seeds, gap filling, text export.
- :mod:`~seismo3d.seismic.horizon_tracking`: :func:`track_horizon`; horizon tracking by registering neighbouring slices.
- :mod:`~seismo3d.seismic.horizon_lsq`: least-squares horizons from correlations of near and distant traces (the
  default method), the cycle-skip self-check.
- :mod:`~seismo3d.seismic.horizon_dp`: dynamic programming over candidate picks along each line, swept over inlines
  and crosslines in a cube.
- :mod:`~seismo3d.seismic.tracking_options`: :class:`TrackingOptions`.
- :mod:`~seismo3d.seismic.autotracker`: the plain amplitude autotracker (the peer).
- :mod:`~seismo3d.seismic.volumes`: registration of sub-volumes of different bin size, sample rate and orientation.
- :mod:`~seismo3d.seismic.evaluation`: fault scores, horizon errors, registration errors against ground truth.
"""

from .attributes import ReflectorOrientation, discontinuity, eigen_coherence, semblance, structure_tensor_orientation
from .autotracker import autotrack
from .evaluation import (
    FaultScores, HorizonErrors, RegistrationErrors, evaluate_faults, horizon_errors, registration_errors,
)
from .fault_crossings import FaultCrossings, reliable_throw
from .fault_likelihood import FaultLikelihood, FaultScanOptions, fault_likelihood, fault_normals
from .fault_skins import SkinOptions, fault_skins
from .fault_surfaces import Fault, fault_labels, link_faults, thin_faults
from .fault_throw import FaultThrow, ThrowOptions, fault_throw, fault_throws
from .fault_voting import FaultVotes, VotingOptions, vote_faults
from .faults import FaultInterpretation, FaultTracingOptions, trace_faults
from .horizon_tracking import TrackingOptions, track_horizon
from .horizons import Horizon, fill_horizon, write_horizon_text
from .io import SeismicCube, open_segy, read_ascii_lines, read_section, read_segy, write_like
from .lazy_cube import LazyCube, open_lazy
from .reflectors import POLARITIES, reflector_picks, reflector_points
from .volumes import VolumeOptions, VolumeRegistration, register_volumes, resample_volume, volume_spacing

__all__ = [
    "POLARITIES", "Fault", "FaultCrossings", "FaultInterpretation", "FaultLikelihood", "FaultScanOptions",
    "FaultTracingOptions", "FaultVotes", "LazyCube", "open_lazy", "SkinOptions", "VotingOptions", "fault_skins", "vote_faults",
    "FaultScores", "FaultThrow", "Horizon", "HorizonErrors", "ReflectorOrientation", "RegistrationErrors",
    "SeismicCube", "ThrowOptions", "TrackingOptions", "VolumeOptions", "VolumeRegistration",
    "autotrack", "discontinuity", "eigen_coherence", "evaluate_faults", "fault_labels", "fault_likelihood",
    "fault_normals", "fault_throw", "fault_throws", "fill_horizon", "horizon_errors", "link_faults", "open_segy",
    "read_ascii_lines", "read_section", "read_segy", "reflector_picks", "reflector_points", "register_volumes",
    "registration_errors", "reliable_throw", "resample_volume", "semblance", "structure_tensor_orientation",
    "thin_faults", "trace_faults", "track_horizon", "volume_spacing", "write_horizon_text", "write_like",
]
