"""seismo3d.data.interpretations: the data folder's real sections and the faults an interpreter sees on them."""

from __future__ import annotations

import numpy as np
import pytest
import segyio

from seismo3d.data import fetch
from seismo3d.data.interpretations import (REAL_SECTIONS, TEAPOT_TPD_FAULTS, XL1155_FIRST_INLINE, XL1155_LINE,
                                           XL1155_MS, load_real_sections, opposite_dip_faults, xl1155_coverage)
from seismo3d.seismic import Fault


@pytest.fixture(scope="module")
def sections(data_dir):
    return load_real_sections()


def test_every_real_section_with_its_shape_and_sample_interval(sections):
    assert set(sections) == set(REAL_SECTIONS) | {"penobscot_xl1155", "volve_fullstack_twt_arbline"}
    for name, shape in REAL_SECTIONS.items():
        arr, dt = sections[name]
        assert arr.shape == shape and arr.dtype == np.float32 and dt is None
    # the SEG-Y lines in file order, as segyio reads their traces
    for name in ("penobscot_xl1155", "volve_fullstack_twt_arbline"):
        with segyio.open(fetch(f"seismic/{name}.sgy"), ignore_geometry=True) as f:
            raw = f.trace.raw[:]
            dt_ms = segyio.tools.dt(f) / 1000.0
        arr, dt = sections[name]
        np.testing.assert_array_equal(arr, raw)
        assert dt == pytest.approx(dt_ms)
    arr, _ = sections["penobscot_xl1155"]
    with segyio.open(fetch("seismic/penobscot_xl1155.sgy"), ignore_geometry=True) as f:
        first_inline = f.header[0][segyio.TraceField.INLINE_3D]
    assert arr.shape == (601, 1501) and first_inline == XL1155_FIRST_INLINE
    assert sections["penobscot_xl1155"][1] == XL1155_MS


def test_the_lines_lie_inside_their_sections():
    (x0, k0), (x1, k1) = XL1155_LINE
    assert (x0, k0) == (385.0, 225.0) and (x1, k1) == (222.0, 637.5)  # inlines 1385 / 1222 at 900 / 2550 ms
    for line in TEAPOT_TPD_FAULTS.values():
        assert all(0 <= x < REAL_SECTIONS["teapot_tpd"][0] and 0 <= k < REAL_SECTIONS["teapot_tpd"][1] for x, k in line)


def _fault(fid, points):
    pts = np.asarray(points, np.int64)
    n = len(pts)
    return Fault(fid, pts, np.ones(n), np.full(n, 90.0), np.full(n, 60.0), np.tile([1.0, 0.0], (n, 1)))


def test_coverage_and_opposite_dip_along_the_xl1155_fault():
    (x0, k0), (x1, k1) = XL1155_LINE
    k = np.arange(225, 638)
    along = np.round(x0 + (x1 - x0) * (k - k0) / (k1 - k0)).astype(int)
    labels = np.zeros((601, 1501), np.int32)
    labels[along, k] = 1  # a fault on the line from 900 to 2550 ms
    c = xl1155_coverage(labels, span=(900.0, 2550.0))
    assert c.fault_id == 1 and c.one_fault > 0.99 and c.covered > 0.99
    same = _fault(1, np.column_stack([along, k]))
    ks = np.arange(240, 400)
    other = _fault(2, np.column_stack([np.round(x0 - (x1 - x0) * (ks - k0) / (k1 - k0)).astype(int), ks]))
    assert opposite_dip_faults([same, other], XL1155_LINE) == [2]
