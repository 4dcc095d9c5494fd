"""The faults job (seismo3d.jobs.faults): run_faults_job on files (demo, real SEG-Y, sections, bad inputs)."""

import csv
import hashlib
import json
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest
import segyio

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import (
    DataNotFoundError, InputError, SegyFormatError, SegyGeometryError, Seismo3dWarning, UnsupportedDataError,
)
from seismo3d.jobs.faults import run_faults_job
from seismo3d.seismic.faults.likelihood.learned import LearnedOptions
from seismo3d.seismic.io import open_segy

POINT_COLUMNS = ["inline", "crossline", "x", "y", "xy_unit", "time_or_depth", "fault_id", "throw_samples"]
SUMMARY_COLUMNS = ["id", "n_points", "mean_strike_deg", "mean_dip_deg", "median_throw_samples"]
EVIDENCE_COLUMNS = ["throw_spread_samples", "throw_step_samples", "throw_alternative_samples", "throw_ambiguity",
                    "throw_correlation", "correlation_gain",
                    "side_coherence", "vote_ratio", "mean_likelihood", "confidence"]


def _sha(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _angle(a, b, period=360.0):
    d = abs(a - b) % period
    return min(d, period - d)


def _no_temp_files(folder):
    return [p.name for p in Path(folder).iterdir() if p.name.endswith(".tmp")]


# --------------------------------------------------------------------------------------------------------------------
# the demo: every output, against the synthetic cube's truth


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    with warnings.catch_warnings():
        warnings.simplefilter("error", Seismo3dWarning)  # a clean synthetic cube raises no warning
        written = run_faults_job(None, out, demo=True, demo_seed=0, progress=False).written
    return out, written


@pytest.mark.slow
def test_demo_writes_every_output(demo):
    out, written = demo
    names = {"demo_seismic.sgy", "demo_truth.csv", "fault_likelihood.sgy", "fault_strike.sgy", "fault_dip.sgy",
             "fault_votes.sgy", "faults.vtp", "fault_points.csv", "fault_summary.csv", "faults.png", "run.json",
             "fault_sticks_opendtect.txt", "fault_sticks_charisma.txt", "fault_sticks_iesx.txt",
             "fault_sticks_rms.pol", "fault_surfaces_gocad"}
    assert {p.name for p in out.iterdir()} == names
    assert {Path(p).name for p in written.values()} == names
    assert Path(written["figure"]).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_run_json_holds_the_seconds_of_each_step(demo):
    out, _ = demo
    seconds = json.loads((out / "run.json").read_text())["stage_seconds"]
    steps = ["make the demo cube", "read input", "fault likelihood", "ridges", "voting", "thinning", "fault skins",
             "throw", "evidence", "write outputs"]
    assert list(seconds) == steps
    assert all(seconds[k] > 0 for k in steps)
    # each step's own seconds: the network's pass costs more than the thinning (about 2 s vs 0.05 s); not the read
    # input, which holds the first imports of dask and xarray in a fresh process (1.3-2.0 s under load)
    assert seconds["fault likelihood"] > 5 * seconds["thinning"]


@pytest.mark.slow
def test_demo_csv_columns_and_values(demo):
    out, _ = demo
    points = _rows(out / "fault_points.csv")
    summary = _rows(out / "fault_summary.csv")
    assert list(points[0]) == POINT_COLUMNS + ["throw_ms", "throw_correlation", "correlation_gain", "side_coherence",
                                               "confidence"]
    assert list(summary[0]) == SUMMARY_COLUMNS + ["median_throw_ms", *EVIDENCE_COLUMNS]
    # every summary row counts its points; ids 1..n by decreasing size
    ids = [int(r["fault_id"]) for r in points]
    assert [int(r["id"]) for r in summary] == list(range(1, len(summary) + 1))
    assert [int(r["n_points"]) for r in summary] == [ids.count(i) for i in range(1, len(summary) + 1)]
    sizes = [int(r["n_points"]) for r in summary]
    assert sizes == sorted(sizes, reverse=True)
    # every kept fault's votes hold along it (the default evidence asks 0.9 of the upper threshold)
    assert all(float(r["vote_ratio"]) >= 0.9 and 0.0 <= float(r["mean_likelihood"]) <= 1.0 for r in summary)
    # the confidence that ranks the faults: their mean likelihood (FaultEvidence.confidence), on each point too
    assert all(r["confidence"] == r["mean_likelihood"] for r in summary)
    by_id = {r["id"]: float(r["confidence"]) for r in summary}
    assert all(abs(float(r["confidence"]) - by_id[r["fault_id"]]) <= 5e-4 * by_id[r["fault_id"]] for r in points)
    # geometry of the demo SEG-Y: inlines / crosslines 1..128, 4 ms samples from 0
    il = np.array([int(r["inline"]) for r in points])
    tz = np.array([float(r["time_or_depth"]) for r in points])
    assert il.min() >= 1 and il.max() <= 128
    np.testing.assert_allclose(tz % 4.0, 0.0, atol=1e-9)
    assert tz.max() <= 127 * 4.0
    # throw in ms is throw in samples x 4 ms
    both = [(float(r["throw_samples"]), float(r["throw_ms"])) for r in points if r["throw_samples"]]
    assert len(both) > 0.5 * len(points)
    ts, tm = np.array(both).T
    np.testing.assert_allclose(tm, 4.0 * ts, rtol=1e-4, atol=1e-3)


@pytest.mark.slow
def test_demo_finds_the_true_faults(demo):
    """The three largest traced faults are the synthetic cube's three faults: strike within 10 degrees, dip within 5,
    median throw (signed: + hanging wall down) within 1 sample of the truth at the fault's reference point."""
    out, _ = demo
    truth = _rows(out / "demo_truth.csv")
    summary = _rows(out / "fault_summary.csv")
    assert len(truth) == 3 and len(summary) >= 3
    for t in truth:
        best = min(summary[:3], key=lambda r: _angle(float(r["mean_strike_deg"]), float(t["strike_deg"])))
        assert _angle(float(best["mean_strike_deg"]), float(t["strike_deg"])) <= 10.0
        assert abs(float(best["mean_dip_deg"]) - float(t["dip_deg"])) <= 5.0
        assert abs(float(best["median_throw_samples"]) - float(t["throw_samples"])) <= 1.0


@pytest.mark.slow
def test_demo_volumes_keep_the_input_geometry(demo):
    out, _ = demo
    with open_segy(out / "demo_seismic.sgy") as src:
        for name in ("fault_likelihood.sgy", "fault_strike.sgy", "fault_dip.sgy"):
            with open_segy(out / name) as cube:
                assert cube.shape == src.shape
                np.testing.assert_array_equal(cube.inlines, src.inlines)
                np.testing.assert_array_equal(cube.samples, src.samples)
    with open_segy(out / "fault_likelihood.sgy") as c:
        fl = c.read()
    with open_segy(out / "fault_dip.sgy") as c:
        dip = c.read()
    assert fl.min() >= 0.0 and fl.max() <= 1.0 and fl.max() > 0.9
    known = dip > 0.0  # 0 (not NaN, which most SEG-Y readers refuse) where the probability (the likelihood there)
    assert np.isfinite(dip).all() and dip.max() <= 90.0  # is below the orientation floor
    assert (fl[~known] < LearnedOptions().orientation_floor).all() and known[fl > 0.3].all() and (~known).any()


@pytest.mark.slow
def test_demo_surfaces(demo):
    import pyvista as pv

    out, _ = demo
    mesh = pv.read(out / "faults.vtp")
    summary = _rows(out / "fault_summary.csv")
    assert mesh.n_points == sum(int(r["n_points"]) for r in summary)
    assert mesh.n_cells > mesh.n_points  # triangulated: about 2 triangles per point
    for name in ("fault_id", "throw", "likelihood", "inline", "crossline", "time_or_depth"):
        assert name in mesh.point_data
    ids, counts = np.unique(mesh.point_data["fault_id"], return_counts=True)
    np.testing.assert_array_equal(counts, [int(r["n_points"]) for r in summary])
    # z is minus the sample index; time_or_depth is the sample's time in ms
    np.testing.assert_allclose(mesh.point_data["time_or_depth"], -4.0 * mesh.points[:, 2], atol=1e-3)


# --------------------------------------------------------------------------------------------------------------------
# real data


@pytest.mark.slow
def _write_cube(path, cube, *, sorting=segyio.TraceSortingFormat.CROSSLINE_SORTING):
    """A 3D SEG-Y with survey-like headers: inlines from 111, crosslines from 875 (every 2nd), CDP coordinates,
    4 ms, IBM float, crossline-sorted (inline-sorted with ``sorting``)."""
    n_il, n_xl, ns = cube.shape
    spec = segyio.spec()
    spec.format = 1
    spec.samples = np.arange(ns) * 4.0
    spec.sorting = sorting
    spec.ilines, spec.xlines = np.arange(111, 111 + n_il), np.arange(875, 875 + 2 * n_xl, 2)
    order = ([(i, j) for j in range(n_xl) for i in range(n_il)] if sorting == segyio.TraceSortingFormat.CROSSLINE_SORTING
             else [(i, j) for i in range(n_il) for j in range(n_xl)])
    with segyio.create(str(path), spec) as f:
        f.text[0] = segyio.tools.wrap("C 1 seismo3d test cube with survey-like headers")
        for t, (i, j) in enumerate(order):
            f.header[t] = {segyio.su.iline: 111 + i, segyio.su.xline: 875 + 2 * j, segyio.su.cdpx: 605000 + 25 * i,
                           segyio.su.cdpy: 6073000 + 25 * j, segyio.su.scalco: 1}
            f.trace[t] = cube[i, j]
        f.bin.update(hdt=4000, hns=ns)


@pytest.mark.slow
def test_segy_outputs_keep_the_inputs_headers(tmp_path, monkeypatch):
    """The likelihood, strike, dip and votes SEG-Y read back with the input's geometry, textual, binary and trace
    headers (a crossline-sorted IBM-float cube written here); the input's headers are read twice: by seismo3d.open
    and as the first volume's template (the other three copy the first's), its samples tile by tile."""
    src = tmp_path / "in" / "cube.sgy"
    src.parent.mkdir()
    _write_cube(src, synthetic_cube((48, 40, 80), n_faults=2, seed=5).cube)
    before = _sha(src)
    opened, real_open = [], segyio.open
    monkeypatch.setattr(segyio, "open", lambda path, *a, **k: opened.append((Path(path), k.get("ignore_geometry")))
                        or real_open(path, *a, **k))
    written = run_faults_job(src, tmp_path / "out", progress=False).written
    monkeypatch.undo()
    headers = [p for p, ignore in opened if p.name == "cube.sgy" and not ignore]
    tiles = [p for p, ignore in opened if p.name == "cube.sgy" and ignore]
    assert len(headers) == 2 and len(tiles) == 4  # 2 x 2 tiles of 32 traces (6 header readings before seismo3d.open)
    assert _sha(src) == before
    with segyio.open(src) as a:
        for key in ("likelihood", "strike", "dip", "votes"):
            with segyio.open(written[key]) as b:
                np.testing.assert_array_equal(a.ilines, b.ilines)
                np.testing.assert_array_equal(a.xlines, b.xlines)
                np.testing.assert_array_equal(a.samples, b.samples)
                assert a.sorting == b.sorting and a.tracecount == b.tracecount
                assert a.text[0] == b.text[0]
                bin_a, bin_b = dict(a.bin), dict(b.bin)
                assert bin_b.pop(segyio.BinField.Format) == 5  # IEEE float
                bin_a.pop(segyio.BinField.Format)
                assert bin_a == bin_b
                for i in range(a.tracecount):
                    assert a.header[i] == b.header[i], f"trace header {i} of {key}"
    with open_segy(written["likelihood"]) as c:
        fl = c.read()
    assert fl.shape == (48, 40, 80) and fl.min() >= 0 and fl.max() <= 1
    points = _rows(written["points"])
    assert list(points[0])[:len(POINT_COLUMNS) + 1] == POINT_COLUMNS + ["throw_ms"]
    assert {int(r["inline"]) for r in points} <= set(range(111, 159))
    assert {int(r["crossline"]) for r in points} <= set(range(875, 955, 2))


@pytest.mark.parametrize("name, why", [
    ("f3_crop.sgy", "23 x 18 traces of 75 samples: fault tracing needs at least 32 traces"),
    ("volve_migvel_depth_sub3d.sgy", "not seismic amplitude data"),
])
def test_data_that_cannot_support_faults_is_refused(data_dir, tmp_path, name, why):
    """A cube too small for the scan (f3_crop, 23 x 18 traces) and a velocity model (Volve, 1480-4706 m/s): one
    clear reason, no warnings before it, and nothing written (before: 6 junk faults on f3_crop)."""
    src = Path(data_dir) / "seismic" / name
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(UnsupportedDataError, match=why):
            run_faults_job(src, tmp_path / "out", progress=False)
    assert not [w for w in caught if issubclass(w.category, Seismo3dWarning)]
    assert not (tmp_path / "out").exists()


@pytest.mark.slow  # 1.5 s in the fast lane, whose budget is 60 s
def test_real_section(data_dir, tmp_path):
    src = Path(data_dir) / "seismic" / "sections" / "teapot_tp73.f32be"
    before = _sha(src)
    written = run_faults_job(src, tmp_path / "tp73", progress=False).written
    assert _sha(src) == before
    assert np.load(written["likelihood"]).shape == (357, 240)
    points = _rows(written["points"])
    summary = _rows(written["summary"])
    assert len(summary) >= 3
    # a raw section: its traces have no inline / crossline numbers, so one "trace" column (the index); samples
    assert list(points[0]) == ["trace", *POINT_COLUMNS[2:], "throw_correlation", "correlation_gain", "side_coherence",
                               "confidence"]
    assert all(0 <= int(r["trace"]) < 357 and 0 <= float(r["time_or_depth"]) < 240 for r in points)


# --------------------------------------------------------------------------------------------------------------------
# 2D inputs made here: a SEG-Y line (n, 1, ns) like penobscot_xl1155, a .npy section


def _write_line(path, section, *, along="inline"):
    """A 2D SEG-Y line: one crossline (along='inline') or one inline, 4 ms."""
    n, ns = section.shape
    spec = segyio.spec()
    spec.format = 5
    spec.samples = np.arange(ns) * 4.0
    spec.sorting = 2
    if along == "inline":
        spec.ilines, spec.xlines = np.arange(1000, 1000 + n), [1155]
    else:
        spec.ilines, spec.xlines = [500], np.arange(10, 10 + n)
    with segyio.create(str(path), spec) as f:
        for i in range(n):
            il, xl = (1000 + i, 1155) if along == "inline" else (500, 10 + i)
            f.header[i] = {segyio.su.iline: il, segyio.su.xline: xl, segyio.su.cdpx: 100 * i}
            f.trace[i] = section[i]
        f.bin.update(hdt=4000, hns=ns)


@pytest.fixture(scope="module")
def section():
    return synthetic_cube((160, 96), n_faults=2, seed=3)


@pytest.mark.slow  # 1.3-2.0 s each in the fast lane, whose budget is 60 s
@pytest.mark.parametrize("along", ["inline", "crossline"])
def test_segy_line(section, tmp_path, along):
    src = tmp_path / "in" / "line.sgy"
    src.parent.mkdir()
    _write_line(src, section.cube, along=along)
    before = _sha(src)
    written = run_faults_job(src, tmp_path / "out", progress=False).written
    assert _sha(src) == before
    with segyio.open(src) as a, segyio.open(written["likelihood"]) as b:
        assert [dict(a.header[i]) for i in range(a.tracecount)] == [dict(b.header[i]) for i in range(b.tracecount)]
        fl = segyio.tools.collect(b.trace[:])
    assert fl.shape == (160, 96) and fl.max() > 0.5
    points = _rows(written["points"])
    assert len(points) > 0
    lateral = "inline" if along == "inline" else "crossline"
    fixed, first = ("crossline", 1000) if along == "inline" else ("inline", 10)
    assert {int(r[fixed]) for r in points} == ({1155} if along == "inline" else {500})
    assert all(first <= int(r[lateral]) < first + 160 for r in points)
    # the line's two faults are found (each at least 30 samples long)
    summary = _rows(written["summary"])
    sizes = [int(r["n_points"]) for r in summary]
    assert len(sizes) >= 2 and sizes[1] >= 30
    # a line's fault has one throw (one shift): its spread is not measured, so it is empty, not 0
    assert all(r["median_throw_samples"] != "" and r["throw_spread_samples"] == "" for r in summary)


@pytest.mark.slow  # 1.4 s in the fast lane, whose budget is 60 s
def test_npy_section_with_nan_and_dead_traces(section, tmp_path):
    data = section.cube.copy()
    data[40] = np.nan  # a NaN trace
    data[100:103] = 0.0  # dead traces
    data[:, :10] = 0.0  # a muted top
    src = tmp_path / "section.npy"
    np.save(src, data)
    before = _sha(src)
    with pytest.warns(Seismo3dWarning) as record:
        written = run_faults_job(src, tmp_path / "out", progress=False).written
    messages = " ".join(str(w.message) for w in record)
    assert "NaN" in messages and "constant" in messages
    assert _sha(src) == before
    fl = np.load(written["likelihood"])
    assert np.all(np.isfinite(fl))
    assert np.all(fl[37:44] == 0) and np.all(fl[97:106] == 0) and np.all(fl[:, :18] == 0)
    points = _rows(written["points"])
    # a 2D .npy: traces by index (no crossline column); no coordinates, which xy_unit says
    assert list(points[0])[:5] == ["trace", "x", "y", "xy_unit", "time_or_depth"]
    tr = np.array([int(r["trace"]) for r in points])
    assert not np.any((tr >= 37) & (tr <= 43)) and not np.any((tr >= 97) & (tr <= 105))


@pytest.mark.slow
def test_no_faults(tmp_path):
    """A section without faults (nor any thinned sample) still gets every output, with header-only tables."""
    import pyvista as pv

    layers = np.tile(np.sin(np.arange(64) * 0.9), (80, 1)).astype(np.float32)  # flat, perfectly coherent layers
    src = tmp_path / "flat.npy"
    np.save(src, layers)
    written = run_faults_job(src, tmp_path / "out", progress=False).written
    assert len(_rows(written["summary"])) == 0 and len(_rows(written["points"])) == 0
    assert Path(written["points"]).read_text().startswith("trace,x,y,xy_unit,time_or_depth,fault_id,throw_samples")
    assert pv.read(written["surfaces"]).n_points == 0
    assert np.load(written["likelihood"]).max() < 0.1
    assert Path(written["figure"]).stat().st_size > 1000


@pytest.mark.slow
def test_a_rerun_removes_the_staging_folder_of_a_run_killed_outright(tmp_path):
    """A run killed with ``kill -9`` leaves its ``.staged-*.tmp`` (with the files written so far) in the output
    folder; the next run into that folder removes it, and leaves a folder of that name that is not a run's alone."""
    import os
    import signal
    import subprocess
    import sys

    out = tmp_path / "out"
    killed = subprocess.Popen([sys.executable, "-c", (
        "import time\nfrom seismo3d._atomic import StagedFolder\n"
        f"with StagedFolder({str(out)!r}, owner='seismo3d faults') as stage:\n"
        "    (stage.path / 'faults.vtp').write_text('half')\n    print(flush=True)\n    time.sleep(60)\n")],
        stdout=subprocess.PIPE, text=True)
    killed.stdout.readline()
    os.kill(killed.pid, signal.SIGKILL)
    killed.wait()
    (stale,) = out.glob(".staged-*.tmp")
    (out / ".staged-notes.tmp").mkdir()  # the user's
    layers = np.tile(np.sin(np.arange(64) * 0.9), (80, 1)).astype(np.float32)
    np.save(tmp_path / "flat.npy", layers)
    run_faults_job(tmp_path / "flat.npy", out, progress=False)
    assert not stale.exists() and (out / ".staged-notes.tmp").is_dir()
    assert [p.name for p in out.glob(".staged-*")] == [".staged-notes.tmp"]


# --------------------------------------------------------------------------------------------------------------------
# bad files and folders: our errors, input untouched, nothing left half-written


def test_not_segy(tmp_path):
    src = tmp_path / "in" / "notes.sgy"
    src.parent.mkdir()
    src.write_text("this is not a seismic file\n" * 200)
    before = _sha(src)
    with pytest.raises(SegyFormatError, match="is not SEG-Y"):
        run_faults_job(src, tmp_path / "out", progress=False)
    assert _sha(src) == before


def test_truncated_segy(data_dir, tmp_path):
    raw = (Path(data_dir) / "seismic" / "f3_crop.sgy").read_bytes()
    src = tmp_path / "in" / "cut.sgy"
    src.parent.mkdir()
    src.write_bytes(raw[: len(raw) // 2 + 17])
    with pytest.raises(SegyFormatError):
        run_faults_job(src, tmp_path / "out", progress=False)


def test_wrong_header_bytes(data_dir, tmp_path):
    src = Path(data_dir) / "seismic" / "f3_crop.sgy"
    with pytest.raises(SegyGeometryError, match="ignore_geometry"):
        run_faults_job(src, tmp_path / "out", iline=1, xline=5, progress=False)


def test_missing_input(tmp_path):
    with pytest.raises(DataNotFoundError):
        run_faults_job(tmp_path / "nothing.sgy", tmp_path / "out", progress=False)
    with pytest.raises(DataNotFoundError):
        run_faults_job(tmp_path / "nothing.f32be", tmp_path / "out", progress=False)
    with pytest.raises(InputError, match="demo"):
        run_faults_job(None, tmp_path / "out", progress=False)
    with pytest.raises(InputError, match="not both"):
        run_faults_job(tmp_path / "x.sgy", tmp_path / "out", demo=True, progress=False)


def test_output_folder_is_the_input_folder(section, tmp_path):
    src = tmp_path / "section.npy"
    np.save(src, section.cube)
    before = sorted(p.name for p in tmp_path.iterdir())
    with pytest.raises(InputError, match="holds the input"):
        run_faults_job(src, tmp_path, progress=False)
    with pytest.raises(InputError, match="holds the input"):
        run_faults_job(src, tmp_path / "." / "", progress=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    (tmp_path / "afile").write_text("x")
    with pytest.raises(InputError, match="is a file"):
        run_faults_job(src, tmp_path / "afile", progress=False)


@pytest.mark.slow  # 1.3 s in the fast lane, whose budget is 60 s
def test_interrupted_run_keeps_finished_files(section, tmp_path, monkeypatch):
    """Ctrl-C while the picture of a run with overwrite=True is written: every file of the previous run stays as it
    was (the new files are moved in only when all are written), no temporary file is left behind."""
    from matplotlib.figure import Figure

    src = tmp_path / "section.npy"
    np.save(src, section.cube)
    out = tmp_path / "out"
    written = run_faults_job(src, out, progress=False).written
    before = {key: _sha(path) for key, path in written.items()}

    def interrupted_savefig(self, fname, **kwargs):
        Path(fname).write_bytes(b"half a picture")
        raise KeyboardInterrupt

    monkeypatch.setattr(Figure, "savefig", interrupted_savefig)
    with pytest.raises(KeyboardInterrupt):
        run_faults_job(src, out, overwrite=True, progress=False)
    assert {key: _sha(path) for key, path in written.items()} == before
    assert _no_temp_files(out) == []


@pytest.mark.slow
def test_a_run_in_memory_writes_its_meshes_beside_the_picture_and_waits_for_them(tmp_path, monkeypatch):
    """In memory, faults.vtp is written on a second thread while the picture is drawn on the caller's; when the
    picture fails (or is interrupted), the run waits for faults.vtp's writer before it removes its staging folder
    and lets the error through: nothing is left in the output folder."""
    import threading
    import time

    from matplotlib.figure import Figure

    from seismo3d.viz import fault_meshes

    layers = np.tile(np.sin(np.arange(64) * 0.9), (80, 1)).astype(np.float32)
    src = tmp_path / "flat.npy"
    np.save(src, layers)
    threads, finished = {}, []
    save = fault_meshes.save_polydata

    def slow_save(mesh, path):
        threads["mesh"] = threading.current_thread().name
        time.sleep(0.5)  # still writing when the picture fails
        written = save(mesh, path)
        finished.append(Path(written).exists())
        return written

    def failing_savefig(self, fname, **kwargs):
        threads["picture"] = threading.current_thread().name
        raise KeyboardInterrupt

    monkeypatch.setattr(fault_meshes, "save_polydata", slow_save)
    monkeypatch.setattr(Figure, "savefig", failing_savefig)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_faults_job(src, out, progress=False)
    assert finished == [True]  # waited for: written into the staging folder before it was removed
    assert threads["picture"] == threading.main_thread().name and threads["mesh"].startswith("seismo3d-writer")
    assert not out.exists() or list(out.iterdir()) == []


@pytest.mark.slow
def test_render_draws_the_demo_output(demo, tmp_path):
    """`seismo3d render` on the demo's folder: slices of demo_seismic.sgy, the four fault surfaces in their tab10
    colours and the likelihood volume, in a non-blank PNG."""
    from matplotlib.image import imread

    from seismo3d.jobs.render import run_render_job

    out, _ = demo
    job = run_render_job(out, tmp_path / "demo.png", window_size=(480, 360))
    assert job.kind == "faults" and job.n_faults >= 3
    img = (imread(tmp_path / "demo.png")[..., :3] * 255).round()
    # 0.275 measured: in a 480 x 360 window the colour bars' own slots take about a third, the cube fills the rest
    assert (img.min(axis=-1) < 250).mean() > 0.27
    orange = (img[..., 0] > 150) & (img[..., 0] > img[..., 2] + 80) & (img[..., 1] > 60)  # fault 2, tab10 orange
    green = (img[..., 1] > img[..., 0] + 40) & (img[..., 1] > img[..., 2] + 40)  # fault 3, tab10 green
    assert orange.mean() > 0.005 and green.mean() > 0.005
