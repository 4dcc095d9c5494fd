"""People's fault sticks placed on a section (seismo3d.seismic.io.stick_sections): nodes by line number and time,
joined in the file's order, the samples of the reference computation (dev_fault_scores.py) on both Great South Basin
lines."""

import numpy as np
import pytest
import segyio
from skimage.draw import line as draw_line

from seismo3d.errors import InputError
from seismo3d.seismic.io.fault_sticks import FaultSticks, read_fault_sticks
from seismo3d.seismic.io.stick_sections import picked_sections, section_nodes, section_pixels

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


def _survey_sticks(rows):
    """Sticks of rows (stick, inline, crossline, z), one fault per stick."""
    rows = np.asarray(rows, float)
    stick = rows[:, 0].astype(np.int64)
    return FaultSticks(stick + 1, stick, np.full(len(rows), np.nan), np.full(len(rows), np.nan), rows[:, 3],
                       rows[:, 1], rows[:, 2], tuple(f"f{i + 1}" for i in range(stick.max() + 1)))


INLINES, CROSSLINES = np.arange(101.0, 141.0), np.arange(20.0, 116.0, 2.0)  # write_segy_cube's grid, 40 x 48


def test_picked_sections_groups_the_sticks_by_the_line_they_lie_on():
    sticks = _survey_sticks([(0, 110, 30, 10), (0, 110, 40, 200),    # inline 110
                             (1, 125, 24, 0), (1, 125, 50, 100),     # inline 125
                             (2, 110, 60, 20), (2, 110, 66, 220),    # inline 110 again
                             (3, 105, 44, 8), (3, 130, 44, 180),     # crossline 44
                             (4, 125, 90, 40), (4, 125, 90, 120)])   # one trace: on inline 125, picked already
    found = picked_sections(sticks, INLINES, CROSSLINES)
    assert [(p.fixed, p.number, p.index, p.axis) for p in found] == [
        ("inline", 110.0, 9, "crossline"), ("inline", 125.0, 24, "crossline"), ("crossline", 44.0, 12, "inline")]
    assert [sorted(p.nodes.tolist()) for p in found] == [[0, 1, 4, 5], [2, 3, 8, 9], [6, 7]]
    # a stick on one trace goes to the crossline when only that one was picked
    lone = picked_sections(_survey_sticks([(0, 105, 44, 8), (0, 130, 44, 180), (1, 112, 44, 0), (1, 112, 44, 90)]),
                           INLINES, CROSSLINES)
    assert [(p.fixed, p.number, sorted(p.nodes.tolist())) for p in lone] == [("crossline", 44.0, [0, 1, 2, 3])]


@pytest.mark.parametrize("rows, match", [
    ([(0, 110, 30, 10), (0, 112, 40, 200)], r"on no single inline or crossline \(inlines 110-112, crosslines 30-40\)"),
    ([(0, 110, 31, 10), (0, 130, 31, 200)], "crossline 31, between the survey's crosslines 30 and 32"),
    ([(0, 150, 30, 10), (0, 150, 40, 200)], "inline 150, outside the survey's inlines 101-140"),
    ([(0, 110, 30, 900), (0, 110, 40, 990)], "at 900-990 ms, outside the survey's samples 0-252 ms"),
])
def test_picked_sections_refuses_sticks_off_the_survey_s_lines(rows, match):
    with pytest.raises(InputError, match=match):
        picked_sections(_survey_sticks(rows), INLINES, CROSSLINES, np.arange(64) * 4.0)
