"""Loader of the real seismic sections with people's interpretation (Penobscot, 18 consecutive inlines)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .registry import fetch

__all__ = ["PenobscotSections", "load_penobscot_sections"]

_PENOBSCOT = "seismic/penobscot_sections/penobscot_sections_1075_1092.npz"


@dataclass(frozen=True, eq=False)
class PenobscotSections:
    """18 consecutive Penobscot inlines with 7 horizons picked by people (see :func:`load_penobscot_sections`).

    Attributes
    ----------
    cube : (18, 512, 1536) float32 ndarray
        Amplitudes (inline, trace, sample), the 8-bit values mapped to [-1, 1] about the grey level 127.5.
    horizons : (18, 7, 512) float64 ndarray
        People's pick of horizon ``k`` (the top of interval ``k + 1``) on each trace, in samples; NaN where the
        horizon is absent and on dead traces (whose "picks" are mask artefacts).
    live : (18, 512) bool ndarray
        Traces holding data (dead traces are constant).
    section_ids : (18,) ndarray
        The sections' ids in the Penobscot Interpretation Dataset.
    """

    cube: np.ndarray
    horizons: np.ndarray
    live: np.ndarray
    section_ids: np.ndarray


def load_penobscot_sections() -> PenobscotSections:
    """Load 18 consecutive real Penobscot inlines (Nova Scotia) with the 7 horizons people picked on them.

    The sections are 8-bit images (heavily clipped: about two thirds of the samples sit at 0 or 255, and 1501 x 481
    samples upscaled to 1536 x 512) of inlines 1075-1092 of the Penobscot 3D survey; the horizons come from the
    dataset's interval labels (the first sample of interval ``k + 1`` on each trace).

    Returns
    -------
    PenobscotSections
        ``cube`` (18, 512, 1536) float32 in [-1, 1], ``horizons`` (18, 7, 512) float64 samples (NaN where absent or
        on dead traces), ``live`` (18, 512) bool, ``section_ids``. Arrays are read-only.

    Raises
    ------
    DataNotFoundError
        If the file is neither in the data directory nor made again from its downloaded origin images
        (offline): set ``SEISMO3D_DATA_DIR``.
    DataIntegrityError
        If the file, or an origin image, does not match its registered SHA-256.

    References
    ----------
    .. [1] L. Baroni, R. M. Silva, R. S. Ferreira, D. Civitarese, D. Szwarcman and E. V. Brazil, "Penobscot
           Interpretation Dataset", Zenodo, 2020, doi:10.5281/zenodo.3924682 (CC BY 4.0).
    """
    with np.load(fetch(_PENOBSCOT)) as z:
        raw, picks, ids = z["seismic"], z["horizons"], z["section_ids"]
    cube = np.ascontiguousarray(((raw.astype(np.float32) - 127.5) / 127.5).transpose(0, 2, 1))
    live = np.ptp(cube, axis=2) > 0
    horizons = picks.astype(np.float64)
    horizons[(horizons < 0) | ~live[:, None, :]] = np.nan
    for array in (cube, horizons, live, ids):
        array.setflags(write=False)
    return PenobscotSections(cube=cube, horizons=horizons, live=live, section_ids=ids)
