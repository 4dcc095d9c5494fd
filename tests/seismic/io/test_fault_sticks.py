"""Fault sticks: the interpreter's OpendTect sticks of the Great South Basin lines read and placed, our two layouts
written and read back (Charisma also by an independent reader of its columns), and the sticks of traced faults at
their traces' own coordinates."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.errors import InputError
from seismo3d.seismic.faults import Fault
from seismo3d.seismic.io.coordinates import read_survey_coordinates, survey_coordinates
from seismo3d.seismic.io.fault_sticks import FaultSticks, read_fault_sticks, write_fault_sticks

GSB = "seismic/gsb_fault_sticks/"


@pytest.fixture(scope="module")
def gsb2800(data_dir):
    from seismo3d.data import fetch

    segy = fetch(GSB + "gsb_crl_2800.sgy")
    coords = read_survey_coordinates(segy)
    return segy, coords, read_fault_sticks(fetch(GSB + "gsb_crl_2800_faults_opendtect.dat"), coordinates=coords)


def test_gsb_sticks_are_read_and_placed(gsb2800, data_dir):
    from seismo3d.data import fetch

    _, coords, sticks = gsb2800
    raw = np.loadtxt(fetch(GSB + "gsb_crl_2800_faults_opendtect.dat"))
    assert (sticks.n_faults, sticks.n_sticks, sticks.n_nodes) == (13, 13, 26)
    assert_allclose(sticks.z, raw[:, 2])
    assert_allclose(sticks.inline, raw[:, 6])
    assert np.all(sticks.crossline == 2800)
    # the file's X / Y are undefined (1e30); filled from the line's CDP X/Y = inline * 100, crossline * 100
    assert np.all(raw[:, :2] == 1e30)
    assert_allclose(sticks.x, raw[:, 6] * 100, atol=1e-6)
    assert_allclose(sticks.y, 280000.0, atol=1e-6)
    line = coords.section()
    at_trace = np.searchsorted(line.inline, sticks.inline)
    assert_allclose(sticks.x, line.x[at_trace], atol=1e-6)  # the header coordinates of each stick's trace
    lines2600 = read_fault_sticks(fetch(GSB + "gsb_crl_2600_faults_opendtect.dat"))
    assert lines2600.n_sticks == 18 and np.isnan(lines2600.x).all()  # no coordinates given: X / Y unknown


def test_gsb_sticks_against_the_second_mask(gsb2800, data_dir):
    """The sticks drawn on the section as the fault evaluation's labels agree with a second person's drawing of the
    same faults (the data folder's README: about F1 0.80 at a 3-sample tolerance)."""
    from skimage.io import imread

    from seismo3d.data import fetch
    from seismo3d.seismic import evaluate_faults, fault_line_coverage

    segy, coords, sticks = gsb2800
    line = coords.section()
    samples = 1000.0 + 4.0 * np.arange(76)
    mask = sticks.section_mask(line.inline, samples)
    second = imread(fetch(GSB + "gsb_crl_2800_second_mask.png")).T > 0  # (traces, samples)
    assert mask.shape == second.shape == (484, 76)
    scores = evaluate_faults(mask > 0, second.astype(int), tolerance=3.0)
    f1 = 2 * scores.precision * scores.recall / (scores.precision + scores.recall)
    assert f1 > 0.7, (scores, f1)
    # each stick as a line for fault_line_coverage: covered by its own drawing
    for fid, vertices in zip([f for f, _ in sticks.sticks()], sticks.section_lines(line.inline, samples)):
        cov = fault_line_coverage(np.where(mask == fid, fid, 0), vertices, tolerance=1.0)
        assert cov.covered > 0.95


@pytest.mark.parametrize("fmt", ["opendtect", "charisma", "iesx"])
def test_written_sticks_read_back(gsb2800, tmp_path, fmt):
    _, coords, sticks = gsb2800
    path = write_fault_sticks(tmp_path / f"sticks_{fmt}.txt", sticks, format=fmt, source="gsb_crl_2800")
    back = read_fault_sticks(path, coordinates=coords)  # IESX rows hold no line numbers: placed by X / Y
    assert (back.n_faults, back.n_sticks, back.n_nodes) == (13, 13, 26)
    assert_allclose(back.x, sticks.x, atol=5e-4)  # written with 3 decimals
    assert_allclose(back.y, sticks.y, atol=5e-4)
    assert_allclose(back.z, sticks.z, atol=5e-3 if fmt == "iesx" else 5e-5)  # IESX: %9.2f; else 4 decimals
    assert_allclose(back.inline, sticks.inline, atol=1e-6)
    assert back.names == sticks.names


def test_charisma_read_by_its_column_spec(gsb2800, tmp_path):
    """An independent reader: seismiqb's Charisma fault-stick columns (INLINE-, inline, crossline, CDP X, CDP Y,
    depth, name, number) through pandas."""
    import pandas as pd

    _, _, sticks = gsb2800
    path = write_fault_sticks(tmp_path / "sticks.txt", sticks, format="charisma")
    df = pd.read_csv(path, sep=r"\s+", header=None,
                     names=["INLINE", "iline", "xline", "cdp_x", "cdp_y", "height", "name", "number"])
    assert (df["INLINE"] == "INLINE-").all() and len(df) == 26
    assert_allclose(df["iline"], sticks.inline)
    assert_allclose(df["cdp_x"], sticks.x, atol=5e-4)
    assert_allclose(df["height"], sticks.z, atol=5e-5)
    assert df.groupby(["name", "number"]).ngroups == 13


def test_sticks_of_traced_faults_are_at_their_traces():
    """3D: a fault striking along the inlines is cut by inlines; every node a fault point at its trace's X / Y."""
    il, xl = np.meshgrid(np.arange(100.0, 110.0), np.arange(20.0, 26.0), indexing="ij")
    x, y = 1000.0 + 25.0 * il + 3.0 * xl, 5000.0 - 3.0 * il + 25.0 * xl
    x[4, 2] += 0.04  # header rounding: the node keeps its trace's own value
    coords = survey_coordinates(il, xl, x, y, unit="m", resolution=0.1)
    points = np.array([[i, 2 + (k > 5), k] for i in range(10) for k in range(3, 9)], dtype=np.int64)
    fault = Fault(1, points, np.ones(len(points), np.float32), np.zeros(len(points), np.float32),
                  np.zeros(len(points), np.float32), np.zeros((len(points), 3), np.float32))
    samples = 500.0 + 4.0 * np.arange(12)
    sticks = FaultSticks.from_faults([fault], coords, samples, line_step=1)
    assert sticks.n_sticks == 10 and sticks.n_nodes == 20  # a stick on each inline, from its top to its bottom
    i, j = (sticks.inline - 100).astype(int), (sticks.crossline - 20).astype(int)
    assert_allclose(sticks.x, x[i, j]) and sticks.x[(i == 4) & (j == 2)].size == 1
    assert {(a, b, round(z)) for a, b, z in zip(i, j, (sticks.z - 500) / 4)} <= set(map(tuple, points.tolist()))
    for _, nodes in sticks.sticks():
        assert_allclose(sticks.z[nodes], [512.0, 532.0])  # ordered down the stick, its two ends
        assert np.unique(sticks.inline[nodes]).size == 1
    # every 10th inline: inline 100 alone of the fault's, so its first and last inlines
    assert np.array_equal(np.unique(FaultSticks.from_faults([fault], coords, samples).inline), [100.0, 109.0])
    with pytest.raises(InputError, match="do not fit"):
        FaultSticks.from_faults([fault], survey_coordinates(il[:, 0], xl[:, 0]), samples)  # a line's


def test_unknown_layout_is_refused(tmp_path):
    path = tmp_path / "x.txt"
    path.write_text("hello world\n")
    with pytest.raises(InputError, match="not a fault-stick file"):
        read_fault_sticks(path)


def test_iesx_rows_follow_the_fixed_columns(gsb2800, tmp_path):
    """IESX node rows as DUG Insight's import reads them: X [0-16), Y [16-32), stick index [32-35), Z [38-47);
    a PROFILE line per fault, EOD at the end."""
    _, _, sticks = gsb2800
    lines = write_fault_sticks(tmp_path / "s.txt", sticks, format="iesx").read_text().splitlines()
    assert lines[-1] == "EOD" and sum(line.startswith("PROFILE") for line in lines) == 13
    rows = [line for line in lines if line[:1] == " "]
    assert len(rows) == 26 and all(len(r) >= 47 for r in rows)
    assert_allclose([float(r[0:16]) for r in rows], sticks.x)
    assert_allclose([float(r[16:32]) for r in rows], sticks.y)
    assert_allclose([float(r[38:47]) for r in rows], sticks.z, atol=5e-3)
    assert {int(r[32:35]) for r in rows} == {1}  # one stick per fault on a line


@pytest.mark.slow
def test_rms_polygons_read_by_xtgeo(gsb2800, tmp_path):
    """The interpreter's 13 sticks written as RMS XYZ polygons: xtgeo reads a polygon per stick, its nodes' X / Y / Z
    those of the sticks (3 and 4 decimals); sticks without X / Y are refused before anything is written."""
    import warnings

    xtgeo = pytest.importorskip("xtgeo")
    _, _, sticks = gsb2800
    path = write_fault_sticks(tmp_path / "s.pol", sticks, format="rms")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # xtgeo's pandas deprecation warnings
        df = xtgeo.polygons_from_file(path, fformat="xyz").get_dataframe()
    assert df["POLY_ID"].nunique() == sticks.n_sticks == 13
    assert len(df) == sticks.n_nodes
    for (_, nodes), (_, poly) in zip(sticks.sticks(), df.groupby("POLY_ID", sort=True)):
        assert_allclose(poly.iloc[:, :3].to_numpy(), np.column_stack([sticks.x, sticks.y, sticks.z])[nodes],
                        atol=6e-4)
    no_xy = FaultSticks(sticks.fault_id, sticks.stick, np.full(sticks.n_nodes, np.nan), sticks.y, sticks.z,
                        sticks.inline, sticks.crossline, sticks.names)
    with pytest.raises(InputError, match="RMS fault sticks need X / Y"):
        write_fault_sticks(tmp_path / "t.pol", no_xy, format="rms")
    assert not (tmp_path / "t.pol").exists()
