"""Inputs of the volume registration: spacing from SEG-Y headers, and volumes checked and read from arrays or cubes."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import as_seismic
from ...errors import InputError
from ..io.coordinates import grid_spacing_from_cdp
from ..io.segy import SeismicCube

__all__ = ["MIN_SIZE", "VolumeInput", "as_spacing", "as_volume", "volume_spacing"]

MIN_SIZE = 8  # fewest samples / traces along any axis of a volume


def volume_spacing(cube):
    """Inline bin, crossline bin and sample interval of a SEG-Y cube, from its CDP coordinates and sample interval.

    The inline bin is the median distance between the CDP positions of neighbouring inlines (same crossline), the
    crossline bin that between neighbouring crosslines, with the coordinate scalar applied (see
    :attr:`SeismicCube.cdp_x <seismo3d.seismic.io.SeismicCube.cdp_x>`).

    Parameters
    ----------
    cube : SeismicCube
        A cube opened with :func:`~seismo3d.seismic.open_segy` (open, or closed after :func:`read_segy`, which loads the
        coordinates).

    Returns
    -------
    spacing : (3,) float64 ndarray
        Inline bin and crossline bin in the survey's unit (m or ft), sample interval in ``cube.sample_unit``. A bin
        is 1.0 when the coordinates are missing or do not change along that axis (then see ``note``).
    note : str
        Where each value came from, e.g. ``'bins from CDP X/Y, sample interval 4 ms'``.

    Raises
    ------
    SegyGeometryError
        If the cube was opened as a trace list (``ignore_geometry=True``).
    InputError
        If ``cube`` is not a SeismicCube.
    """
    if not isinstance(cube, SeismicCube):
        raise InputError(f"cube must be a SeismicCube from open_segy(); got {type(cube).__name__}")
    cube.require_geometry("volume_spacing()")
    try:
        x, y = cube.cdp_x, cube.cdp_y
    except InputError:  # closed before its coordinates were read
        x = y = None
    return grid_spacing_from_cdp(x, y, cube.sample_interval, cube.sample_unit, "from the binary header")


def as_spacing(value, name: str) -> np.ndarray:
    """Three positive finite numbers (inline bin, crossline bin, sample interval) as a (3,) float64 array, or raise
    :class:`InputError`."""
    try:
        sp = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be three numbers (inline bin, crossline bin, sample interval)") from exc
    if sp.shape != (3,):
        raise InputError(f"{name} must have 3 values (inline bin m, crossline bin m, sample interval ms or m); got "
                         f"shape {sp.shape}")
    if not np.all(np.isfinite(sp)) or np.any(sp <= 0):
        raise InputError(f"{name} must be finite and > 0; got {sp.tolist()}")
    return sp


@dataclass(frozen=True, eq=False)
class VolumeInput:
    """A volume to register: float32 amplitudes, spacing and where the spacing came from."""

    data: np.ndarray  # (n_inlines, n_xlines, n_samples) float32
    spacing: np.ndarray  # (3,) float64: inline bin, crossline bin, sample interval
    note: str


def as_volume(volume, name: str, spacing) -> VolumeInput:
    """A :class:`VolumeInput` from an array or an open SeismicCube (spacing from its headers unless given).

    Parameters
    ----------
    volume : (n_inlines, n_xlines, n_samples) array_like or SeismicCube
        Amplitudes, any real dtype; finite; at least ``MIN_SIZE`` along every axis.
    name : str
        The argument's name, for messages (``'fixed'``, ``'moving'``).
    spacing : (3,) array_like of float or None
        Given spacing, or None (headers for a cube, else 1 per axis).

    Returns
    -------
    VolumeInput

    Raises
    ------
    InputError
        A closed cube, a volume that is not 3D, too small, NaN / inf, or a bad spacing.
    """
    note = "given"
    if isinstance(volume, SeismicCube):
        if not volume.is_open:
            raise InputError(f"{name} is a closed SeismicCube; pass it while open (with open_segy(path) as cube: "
                             "...) or pass the array from read_segy with fixed_spacing= / moving_spacing=")
        volume.require_geometry(f"register_volumes({name})")
        sp_file, note = volume_spacing(volume)
        data = volume.read()
        if spacing is None:
            spacing = sp_file
        else:
            note = "given"
    else:
        data = volume
        if spacing is None:
            note = "not given, 1 per axis (index units)"
    if np.ndim(data) != 3:
        raise InputError(f"{name} must be a 3D volume (n_inlines, n_xlines, n_samples); got shape "
                         f"{np.shape(data)}. A 2D section cannot be registered as a volume; stack sections along a "
                         "new first axis")
    arr = as_seismic(data, name, min_size=MIN_SIZE)
    sp = np.ones(3) if spacing is None else as_spacing(spacing, f"{name}_spacing")
    return VolumeInput(arr, sp, note)
