"""Seismic interpretation: SEG-Y I/O, reflector orientation and discontinuity attributes, fault likelihood, fault
surfaces, fault throw by registration, the ``seismo3d faults`` job, and horizon tracking by registering neighbouring
slices, and registration of sub-volumes of different bin size, sample rate and orientation."""

from .attributes import ReflectorOrientation, discontinuity, eigen_coherence, semblance, structure_tensor_orientation
from .faults import (
    Fault, FaultLikelihood, evaluate_faults, fault_labels, fault_likelihood, fault_normals, link_faults, thin_faults,
)
from .horizons import (
    POLARITIES, Horizon, autotrack, fill_horizon, horizon_errors, reflector_picks, track_horizon, write_horizon_text,
)
from .io import SeismicCube, open_segy, read_ascii_lines, read_section, read_segy, write_like
from .job import FaultInterpretation, run_faults_job, trace_faults
from .throw import FaultThrow, fault_throw, fault_throws
from .volumes import (
    VolumeRegistration, reflector_points, register_volumes, registration_errors, resample_volume, volume_spacing,
)

__all__ = [
    "POLARITIES", "Horizon", "autotrack", "fill_horizon", "horizon_errors", "reflector_picks", "track_horizon",
    "write_horizon_text",
    "Fault", "FaultInterpretation", "FaultLikelihood", "FaultThrow", "ReflectorOrientation", "SeismicCube",
    "discontinuity", "eigen_coherence", "evaluate_faults", "fault_labels", "fault_likelihood", "fault_normals",
    "fault_throw", "fault_throws", "link_faults", "open_segy", "read_ascii_lines", "read_section", "read_segy",
    "run_faults_job", "semblance", "structure_tensor_orientation", "thin_faults", "trace_faults", "write_like",
    "VolumeRegistration", "reflector_points", "register_volumes", "registration_errors", "resample_volume",
    "volume_spacing",
]
