"""People's fault sticks placed on a section (seismo3d.seismic.io.stick_sections): nodes by line number and time,
joined in the file's order, the samples of the reference computation (dev_fault_scores.py) on both Great South Basin
lines."""

import numpy as np
import pytest
import segyio
from skimage.draw import line as draw_line

from seismo3d.errors import InputError
from seismo3d.seismic.io.fault_sticks import FaultSticks, read_fault_sticks
from seismo3d.seismic.io.stick_sections import section_nodes, section_pixels

GSB = "seismic/gsb_fault_sticks/"


def _sticks(inline, z):
    """One stick of one fault through the nodes (inline, z), on crossline 2600."""
    n = len(inline)
    return FaultSticks(np.ones(n, np.int64), np.zeros(n, np.int64), np.full(n, np.nan), np.full(n, np.nan),
                       np.asarray(z, float), np.asarray(inline, float), np.full(n, 2600.0), ("f",))


def test_nodes_are_joined_in_the_files_order():
    """A stick from (trace 235.24, sample 34) up to (232.24, 66) (crossline 2600's first stick): drawn from its first
    node, as the file lists them, a Bresenham line differs by a sample from the same line drawn backwards."""
    labels = 1565.0 + 2.0 * np.arange(484)
    samples = 1000.0 + 4.0 * np.arange(76)
    sticks = _sticks([2035.48, 2029.48], [1136.0001, 1264.0001])
    (fid, nodes), = section_nodes(sticks, labels, samples)
    np.testing.assert_allclose(nodes, [[235.24, 34.000025], [232.24, 66.000025]], atol=1e-9)
    (_, pixels), = section_pixels(sticks, labels, samples)
    forward = np.column_stack(draw_line(235, 34, 232, 66))
    backward = np.column_stack(draw_line(232, 66, 235, 34))
    assert fid == 1 and pixels.tolist() == forward.tolist()
    assert {tuple(p) for p in forward} != {tuple(p) for p in backward}
    assert sticks.section_mask(labels, samples)[tuple(forward.T)].all()


def test_samples_beyond_the_section_are_dropped_and_missing_numbers_refused():
    labels, samples = np.arange(10.0), np.arange(5.0)
    (_, pixels), = section_pixels(_sticks([2.0, 2.0], [-3.0, 9.0]), labels, samples)  # clamped to the edges
    assert pixels.tolist() == [[2, k] for k in range(5)]
    with pytest.raises(InputError, match="no crossline number"):
        nan = FaultSticks(np.ones(2, np.int64), np.zeros(2, np.int64), *[np.full(2, np.nan)] * 2, np.zeros(2),
                          np.zeros(2), np.full(2, np.nan), ("f",))
        section_pixels(nan, labels, samples, axis="crossline")


@pytest.mark.parametrize("line", [2600, 2800])
def test_gsb_sticks_fall_on_the_samples_of_the_reference_computation(line, data_dir):
    """dev_fault_scores.py's drawing of the interpreter's sticks (its lines, here as written there)."""
    from seismo3d.data import fetch

    with segyio.open(fetch(GSB + f"gsb_crl_{line}.sgy")) as f:
        il, t = np.asarray(f.ilines, float), np.asarray(f.samples, float)
    path = fetch(GSB + f"gsb_crl_{line}_faults_opendtect.dat")
    rows = np.loadtxt(path)
    truth = np.zeros((il.size, t.size), bool)
    for a, b in zip(rows[0::2], rows[1::2]):
        c0, c1 = np.interp([a[6], b[6]], il, np.arange(len(il)))
        r0, r1 = np.interp([a[2], b[2]], t, np.arange(len(t)))
        rr, cc = draw_line(int(round(c0)), int(round(r0)), int(round(c1)), int(round(r1)))
        ok = (rr >= 0) & (rr < truth.shape[0]) & (cc >= 0) & (cc < truth.shape[1])
        truth[rr[ok], cc[ok]] = True
    mask = read_fault_sticks(path).section_mask(il, t)
    assert ((mask > 0) == truth).all() and truth.sum() == {2600: 752, 2800: 563}[line]
