"""Loaders of the real seismic data with people's interpretation: Penobscot (18 consecutive inlines with horizons),
F3 (five inlines with faults drawn by a person) and Parihaka (a 3D cube of time slices with people's fault
outlines)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .registry import fetch

__all__ = ["F3FaultSections", "ParihakaTimeSlices", "PenobscotSections", "load_f3_fault_sections",
           "load_parihaka_timeslices", "load_penobscot_sections"]

_PENOBSCOT = "seismic/penobscot_sections/penobscot_sections_1075_1092.npz"
_F3_MASKS = "seismic/f3_fault_masks/{kind}_inline_{inline}.png"
F3_MASK_INLINES = (100, 200, 300, 400, 500)
_F3_SHAPE = (951, 462)  # crosslines x samples of the interpreter's masks
_PARIHAKA = "seismic/parihaka_timeslices/parihaka_timeslices_cols174_302.npz"
_PARIHAKA_WINDOW = 128  # samples of the faulted window (as /work/shared/tools/parihaka_dev_scores.py picks it)

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


@dataclass(frozen=True, eq=False)
class F3FaultSections:
    """Five real F3 inlines with faults drawn by a person (see :func:`load_f3_fault_sections`).

    Attributes
    ----------
    sections : (5, 951, 462) float32 ndarray
        Amplitudes (inline, crossline, sample), the 8-bit grey rendering mapped to [-1, 1) about the grey level 128
        (zero amplitude, as ``tools/dev_fault_scores.py`` reads the pictures); samples are 4 ms from 0 ms.
    faults : (5, 951, 462) bool ndarray
        The interpreter's fault lines (True on fault samples).
    inlines : (5,) int ndarray
        The inline numbers, 100 to 500.
    sample_interval : float
        4.0, milliseconds.
    """

    sections: np.ndarray
    faults: np.ndarray
    inlines: np.ndarray
    sample_interval: float = 4.0


def load_f3_fault_sections() -> F3FaultSections:
    """Load five real inlines of the Netherlands F3 block with the fault lines an interpreter drew on them.

    Each inline's seismic is an 8-bit grey rendering (1114 x 541 pixels) that the interpreter's drawing stretched
    onto the inline's 951 crosslines x 462 samples; it is resampled onto that grid (Pillow's bilinear filter, which
    low-passes as it shrinks; the reading of ``tools/dev_fault_scores.py``, by which the project's fault targets are
    checked) so that it lines up with the drawn mask (alpha > 0 = fault). Most of each inline is unfaulted layering
    above a faulted deep interval: the fault scores of ``benchmarks/faults.py`` are measured on them (tolerant
    precision and recall, :func:`seismo3d.seismic.evaluate_faults`, tolerance 3 samples).

    Returns
    -------
    F3FaultSections
        ``sections`` (5, 951, 462) float32 in [-1, 1], ``faults`` (5, 951, 462) bool, ``inlines`` (100, ..., 500).
        Arrays are read-only.

    Raises
    ------
    DataNotFoundError
        If an image is neither in the data directory nor downloadable (offline): set ``SEISMO3D_DATA_DIR``.
    DataIntegrityError
        If an image does not match its registered SHA-256.

    References
    ----------
    .. [1] T. Wrona, seismic_deep_learning, tutorial 3 (fault masks of F3 inlines 100-500), github.com/thilowrona.
    .. [2] F3 Netherlands, dGB Earth Sciences / TNO (CC BY-SA).
    """
    from PIL import Image

    sections, faults = [], []
    for inline in F3_MASK_INLINES:
        with Image.open(fetch(_F3_MASKS.format(kind="seismic", inline=inline))) as picture:
            # shrunk with Pillow's bilinear filter, whose support widens by the shrink factor (a low-pass before the
            # resampling, as tools/dev_fault_scores.py reads the pictures); OpenCV's INTER_LINEAR keeps two taps
            # and aliases the rendering's fine texture: with it the defaults' mean F1 read 0.496 instead of 0.474
            grey = np.asarray(picture.convert("L").resize(_F3_SHAPE, Image.BILINEAR))  # (samples, crosslines)
        with Image.open(fetch(_F3_MASKS.format(kind="mask", inline=inline))) as drawing:
            alpha = np.asarray(drawing.convert("RGBA"))[..., 3]
        sections.append(((grey.astype(np.float32) - 128.0) / 128.0).T)
        faults.append((alpha > 0).T)
    out = F3FaultSections(sections=np.ascontiguousarray(np.stack(sections)), faults=np.stack(faults),
                          inlines=np.array(F3_MASK_INLINES))
    for array in (out.sections, out.faults, out.inlines):
        array.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False)
class ParihakaTimeSlices:
    """A real 3D cube of the Parihaka survey with people's fault outlines (see :func:`load_parihaka_timeslices`).

    Attributes
    ----------
    cube : (256, 128, 591) float32 ndarray
        Amplitudes (inline, crossline, sample): the 8-bit values of the time-slice images minus 127.5, so in
        [-127.5, 127.5]. Each slice was rendered by its own minimum and maximum: treat the values as 8-bit data
        whose scale jumps a little from sample to sample, not as calibrated amplitudes.
    faults : (256, 128, 591) bool ndarray
        People's fault polygons (bands a few traces wide, drawn on time slices in map view); False on unlabelled
        slices.
    labelled : (591,) bool ndarray
        The samples (time slices) people labelled; on the others ``faults`` says nothing.
    slices : (591,) int ndarray
        The time-slice numbers of the origin (70 to 660), one per sample; the origin gives no time for them.
    fault_window : slice
        The 128 consecutive samples holding the most fault labels (samples 45-172): the window where the faults
        are, as the project's 3D fault scores (``parihaka_dev_scores.py``) cut it.
    """

    cube: np.ndarray
    faults: np.ndarray
    labelled: np.ndarray
    slices: np.ndarray
    fault_window: slice


def load_parihaka_timeslices() -> ParihakaTimeSlices:
    """Load a real 3D cube of the Parihaka 3D survey (Taranaki Basin, New Zealand) with the faults people outlined.

    The cube is 256 x 128 traces (rows 471-727 and columns 174-302 of the origin's time-slice images, taken as
    inlines and crosslines) by 591 time slices of the PSTM near stack; people outlined faults, channels and amplitude
    anomalies as polygons on 391 of the slices (faults mostly in the first 175 slices), as bands a few traces wide in
    map view.

    Returns
    -------
    ParihakaTimeSlices
        ``cube`` (256, 128, 591) float32, ``faults`` (256, 128, 591) bool, ``labelled`` (591,) bool, ``slices``
        (591,) int, ``fault_window`` (a slice of 128 samples). Arrays are read-only.

    Raises
    ------
    DataNotFoundError
        If the file is not in the data directory (``SEISMO3D_DATA_DIR``): it is derived from the origin's images
        and is not downloaded.
    DataIntegrityError
        If the file does not match its registered SHA-256.

    References
    ----------
    .. [1] Parihaka 3D, New Zealand Petroleum & Minerals open data; the slices and fault polygons of
           github.com/zuenko/seismis_analysis (commit 00c8ae87, no licence stated).
    """
    with np.load(fetch(_PARIHAKA)) as z:
        seismic, labels, first = z["seismic"], z["labels"], int(z["first_slice"])
    cube = np.ascontiguousarray(seismic.transpose(1, 2, 0), dtype=np.float32)
    cube -= np.float32(127.5)
    labelled = (labels != 255).any(axis=(1, 2))
    faults = np.ascontiguousarray((labels == 1).transpose(1, 2, 0))
    per_sample = faults.sum(axis=(0, 1))
    start = int(np.argmax(np.convolve(per_sample, np.ones(_PARIHAKA_WINDOW), "valid")))
    slices = np.arange(first, first + cube.shape[2])
    for array in (cube, faults, labelled, slices):
        array.setflags(write=False)
    return ParihakaTimeSlices(cube=cube, faults=faults, labelled=labelled, slices=slices,
                              fault_window=slice(start, start + _PARIHAKA_WINDOW))
