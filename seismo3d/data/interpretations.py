"""What interpreters see on the data folder's real 2D sections, defined once for the tests and the benchmarks.

- :func:`load_real_sections`: every real 2D section of the data folder (the raw ``.f32be`` sections and the two SEG-Y
  lines) as (traces x samples) arrays with their sample interval.
- The faults an interpreter sees there (issue 35), as (trace, sample) ends of a line in each section's indices:
  :data:`XL1155_LINE` (the large normal fault of ``penobscot_xl1155.sgy``), :data:`TEAPOT_TPD_FAULTS` (the three
  visible faults of ``teapot_tpd``), and :data:`VOLVE_CONTINUOUS_MS` (a package of continuous reflectors of the Volve
  arbitrary line that no fault crosses).
- :func:`xl1155_coverage`, :func:`opposite_dip_faults`: how traced faults follow those lines.

They were read off the sections by eye (the section pictures of ``benchmarks/faults.py``); they are checks of what a
person sees, not a full interpretation.
"""

from __future__ import annotations

import warnings

import numpy as np

from .registry import fetch

__all__ = ["REAL_SECTIONS", "TEAPOT_TPD_FAULTS", "VOLVE_CONTINUOUS_MS", "XL1155_LINE", "load_real_sections",
           "opposite_dip_faults", "xl1155_coverage"]

# every raw 2D section of the data folder (big-endian float32, trace after trace): name -> (n_traces, n_samples)
REAL_SECTIONS = {
    "campos_gx373": (550, 300), "costarica_crf": (500, 180), "costarica_gx808": (825, 210),
    "costarica_gx809": (825, 210), "f3_f3d178sub2": (951, 242), "f3_f3d75s": (440, 222), "teapot_tp73": (357, 240),
    "teapot_tpd": (357, 315),
}
_SEGY_LINES = ("penobscot_xl1155", "volve_fullstack_twt_arbline")

# penobscot_xl1155: (inline, ms) of the large fault's two ends, and its axes (inlines from 1000, 4 ms from 0)
XL1155_ENDS = ((1385.0, 900.0), (1222.0, 2550.0))
XL1155_FIRST_INLINE, XL1155_MS = 1000.0, 4.0
XL1155_LINE = tuple((il - XL1155_FIRST_INLINE, t / XL1155_MS) for il, t in XL1155_ENDS)

# teapot_tpd's three visible faults, (trace, sample) vertices
TEAPOT_TPD_FAULTS = {"near trace 20 below sample 240": ((20, 240), (20, 314)),
                     "trace 115 at sample 20 to 145 at 280": ((115, 20), (145, 280)),
                     "near-vertical at traces 210-220": ((208, 0), (222, 314))}

# two-way times (ms) of the Volve arbitrary line's continuous reflectors, crossed by no fault
VOLVE_CONTINUOUS_MS = (2300.0, 2500.0)


def load_real_sections() -> dict:
    """Load every real 2D section of the data folder.

    Returns
    -------
    dict of str to (ndarray, float or None)
        Name (the file's stem) -> ((n_traces, n_samples) float32 array, sample interval in ms, or None for the raw
        ``.f32be`` sections, whose sample interval is not known). The SEG-Y lines are read by
        :func:`seismo3d.seismic.open_segy` in file order (``volve_fullstack_twt_arbline`` as a trace list).

    Raises
    ------
    DataNotFoundError
        If a file is neither in the data directory nor downloadable: set ``SEISMO3D_DATA_DIR``.
    DataIntegrityError
        If a file does not match its registered SHA-256.
    """
    from ..seismic.io import open_segy  # only for the two SEG-Y lines

    sections = {name: (np.fromfile(fetch(f"seismic/sections/{name}.f32be"), ">f4").reshape(shape)
                       .astype(np.float32), None) for name, shape in REAL_SECTIONS.items()}
    for name in _SEGY_LINES:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the arbitrary line is read as a trace list, with a warning
            with open_segy(fetch(f"seismic/{name}.sgy")) as cube:
                arr = cube.read()
                dt = float(cube.samples[1] - cube.samples[0])
        sections[name] = (arr.reshape(-1, arr.shape[-1]), dt)
    return sections


def xl1155_coverage(labels: np.ndarray, span=(1000.0, 2400.0)):
    """How traced faults follow the large fault of ``penobscot_xl1155.sgy`` between two times.

    Parameters
    ----------
    labels : (601, 1501) int ndarray
        Fault ids of the line's samples (:func:`seismo3d.seismic.fault_labels`), 0 off faults.
    span : (float, float)
        Two-way times (ms) of the part of :data:`XL1155_LINE` measured.

    Returns
    -------
    FaultLineCoverage
        :func:`seismo3d.seismic.fault_line_coverage` of that part of the line, 10 traces either side.
    """
    from ..seismic.evaluation import fault_line_coverage

    (x0, k0), (x1, k1) = XL1155_LINE
    ends = [(x0 + (x1 - x0) * (t / XL1155_MS - k0) / (k1 - k0), t / XL1155_MS) for t in span]
    return fault_line_coverage(labels, ends, tolerance=10)


def opposite_dip_faults(faults, line, *, upper_ms: float = 1700.0, sample_ms: float = 4.0) -> list:
    """Ids of the faults along the upper part of an interpreter's fault line that dip the other way.

    Parameters
    ----------
    faults : sequence of Fault
        Traced faults of a 2D section (``points`` (n, 2) int: trace, sample).
    line : ((float, float), (float, float))
        The line's (trace, sample) ends, top first (e.g. :data:`XL1155_LINE`).
    upper_ms : float
        Two-way time (ms) where the upper part ends.
    sample_ms : float
        Sample interval (ms).

    Returns
    -------
    list of int
        Ids of the faults with at least 10 points within 20 traces of the line between its top and ``upper_ms``
        whose trend (traces per sample, least squares) has the other sign than the line's.
    """
    (x0, k0), (x1, k1) = line
    slope = (x1 - x0) / (k1 - k0)
    out = []
    for f in faults:
        x, k = f.points[:, 0].astype(float), f.points[:, -1].astype(float)
        near = (k >= k0) & (k <= upper_ms / sample_ms) & (np.abs(x - (x0 + slope * (k - k0))) <= 20)
        if np.count_nonzero(near) >= 10 and np.ptp(k[near]) > 0 and np.polyfit(k[near], x[near], 1)[0] * slope < 0:
            out.append(f.id)
    return out
