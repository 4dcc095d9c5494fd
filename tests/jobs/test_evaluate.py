"""The ``seismo3d evaluate`` command (seismo3d.jobs.evaluate): a generated faults folder on a generated crossline with
known answers (through the command line, sticks and masks), the refusals and their messages, the reproduction of the
reference computation (dev_fault_scores.py) on the Great South Basin lines, and the command end to end after a real
``seismo3d faults`` run there."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import segyio
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.errors import InputError
from seismo3d.jobs.evaluate import run_evaluate_job
from seismo3d.jobs.runinfo import write_run_json
from seismo3d.seismic.fault_scoring import FaultScoringOptions

runner = CliRunner()
GSB = "seismic/gsb_fault_sticks/"
N_TRACES, N_SAMPLES = 40, 20  # crossline 500: inlines 101, 103, ... 179; 4 ms from 1000 ms
INLINES = 101 + 2 * np.arange(N_TRACES)
TIMES = 1000.0 + 4.0 * np.arange(N_SAMPLES)
# people's sticks: (inline, top ms, bottom ms); the traced faults: (inline, first sample, last sample, confidence).
# Traced fault 1 lies 2 traces from stick 1, fault 2 10 traces from both, fault 3 1 trace from stick 2: precision
# 20 / 30, recall 1, F1 0.8; adding them by confidence: P 1, 0.5, 2/3 at R 0.5, 0.5, 1, AP 0.5 + 0.5 * 2/3.
STICKS = [(111, 1000.0, 1036.0), (161, 1040.0, 1076.0)]
TRACED = [(115, 0, 9, 0.9), (141, 0, 9, 0.8), (163, 10, 19, 0.7)]


def _write_line(path: Path, crossline: int = 500, *, iline: int = 189, xline: int = 193, xy: bool = False) -> Path:
    """The line's traces, their inline / crossline numbers at the bytes ``iline`` / ``xline``; with ``xy``, CDP X / Y
    of :func:`_line_xy` (decimetres: coordinate scalar -10)."""
    rng = np.random.default_rng(0)
    spec = segyio.spec()
    spec.format, spec.sorting = 5, segyio.TraceSortingFormat.INLINE_SORTING
    spec.samples, spec.ilines, spec.xlines = TIMES, INLINES, [crossline]
    with segyio.create(str(path), spec) as f:
        for i, il in enumerate(INLINES):
            header = {iline: int(il), xline: crossline, segyio.TraceField.DelayRecordingTime: 1000,
                      segyio.TraceField.TRACE_SAMPLE_INTERVAL: 4000, segyio.TraceField.TRACE_SAMPLE_COUNT: N_SAMPLES}
            if xy:
                x, y = _line_xy(il, crossline)
                header.update({segyio.TraceField.CDP_X: round(x * 10), segyio.TraceField.CDP_Y: round(y * 10),
                               segyio.TraceField.SourceGroupScalar: -10})
            f.header[i] = header
            f.trace[i] = rng.standard_normal(N_SAMPLES).astype(np.float32)
        f.bin.update(hdt=4000, hns=N_SAMPLES)
    return path


def _line_xy(inline, crossline) -> tuple:
    """Map X / Y (m) of a trace of the generated line: a grid rotated 30 degrees, bins 12.5 m."""
    c, s = np.cos(np.radians(30.0)), np.sin(np.radians(30.0))
    return 600000.0 + 12.5 * (c * inline - s * crossline), 6500000.0 + 12.5 * (s * inline + c * crossline)


def _write_faults_folder(folder: Path, segy: Path, *, traced=TRACED, crossline=500, confidence=None,
                         segy_options=None) -> Path:
    """What 'seismo3d faults' writes and evaluate reads: fault_points.csv, fault_summary.csv, run.json."""
    folder.mkdir()
    with open(folder / "fault_points.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["inline", "crossline", "time_or_depth", "fault_id", "throw_samples"])
        for fid, (il, k0, k1, _) in enumerate(traced, start=1):
            w.writerows([il, crossline, f"{TIMES[k]:g}", fid, "1.5"] for k in range(k0, k1 + 1))
    with open(folder / "fault_summary.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["id", "n_points", "mean_likelihood"] + (["confidence"] if confidence else []))
        for fid, (_, k0, k1, c) in enumerate(traced, start=1):
            w.writerow([fid, k1 - k0 + 1, c] + ([confidence[fid - 1]] if confidence else []))
    write_run_json(folder / "run.json", command="faults", options=segy_options or {"iline": 189, "xline": 193},
                   inputs={"input": segy},
                   started=0.0, seconds=1.0, stage_seconds={}, outputs={})
    return folder


def _write_sticks(path: Path, sticks=STICKS, crossline=500) -> Path:
    """The interpreter's layout of the data folder: x y z o1 o2 o3 inline crossline, two rows per stick."""
    rows = [f"1e30\t1e30\t{z}\t0.02\t1.57\t-0.47\t{il}\t{crossline}" for il, top, bottom in sticks
            for z in (top, bottom)]
    path.write_text("\n".join(rows) + "\n")
    return path


def _people_labels() -> np.ndarray:
    out = np.zeros((N_TRACES, N_SAMPLES), np.int64)
    for n, (il, top, bottom) in enumerate(STICKS, start=1):
        out[(il - 101) // 2, int((top - 1000) / 4):int((bottom - 1000) / 4) + 1] = n
    return out


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    folder = tmp_path_factory.mktemp("made")
    segy = _write_line(folder / "line.sgy")
    _write_faults_folder(folder / "faults", segy)
    _write_sticks(folder / "sticks.dat")
    return folder


@pytest.fixture
def work(made, tmp_path):
    """A copy of the made inputs (the faults folder's run.json records the copied line)."""
    folder = tmp_path / "in"
    folder.mkdir()
    segy = shutil.copy(made / "line.sgy", folder / "line.sgy")
    shutil.copy(made / "sticks.dat", folder)
    _write_faults_folder(folder / "faults", Path(segy))
    return folder


def _invoke(*args) -> object:
    return runner.invoke(app, ["evaluate", *map(str, args)])


def _error(result) -> str:
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.exit_code == 2 and len(lines) == 1 and lines[0].startswith("error: "), result.output
    return lines[0]


@pytest.mark.slow
def test_the_command_on_a_generated_line(work):
    result = _invoke(work / "faults", "--sticks", work / "sticks.dat", "-o", work / "ev")
    assert result.exit_code == 0, result.output
    out = result.stdout
    assert "crossline 500 of line.sgy: precision 0.667  recall 1.000  F1 0.800" in out
    assert "by mean_likelihood: average precision 0.833" in out
    with open(work / "ev" / "evaluation.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["drawing"], r["fault_id"], r["recall"], r["precision"], r["matches"]) for r in rows] == [
        ("people", "1", "1", "", "1"), ("people", "2", "1", "", "3"),
        ("traced", "1", "", "1", "1"), ("traced", "2", "", "0", ""), ("traced", "3", "", "1", "2")]
    summary = json.loads((work / "ev" / "evaluation.json").read_text())
    assert summary["precision"] == pytest.approx(2 / 3) and summary["recall"] == 1.0 and summary["f1"] == 0.8
    assert summary["average_precision"] == pytest.approx(0.5 + 0.5 * 2 / 3)
    assert summary["precision_recall_curve"]["fault_ids"] == [[1], [2], [3]]
    assert summary["confidence_column"] == "mean_likelihood" and summary["tolerance_samples"] == 3.0
    record = json.loads((work / "ev" / "run.json").read_text())
    assert record["command"] == "evaluate" and record["inputs"]["seismic"]["path"] == str(work / "line.sgy")
    from PIL import Image

    with Image.open(work / "ev" / "evaluation.png") as image:
        grey = np.asarray(image.convert("RGB"), dtype=float)
    cyan = (grey[..., 0] < 60) & (grey[..., 1] > 170) & (grey[..., 2] > 220)  # people's faults' colour
    red = (grey[..., 0] > 220) & (grey[..., 1] < 90) & (grey[..., 2] < 60)  # the traced faults'
    assert cyan.sum() > 100 and red.sum() > 100


def test_a_confidence_column_comes_first_and_the_tolerance_is_an_option(work, tmp_path):
    from seismo3d.jobs.evaluate import evaluation_table

    faults = _write_faults_folder(tmp_path / "faults", work / "line.sgy", confidence=[0.9, 0.1, 0.8])
    job = run_evaluate_job(faults, sticks=work / "sticks.dat", out=tmp_path / "ev", picture=False)
    assert job.confidence_column == "confidence" and job.scores.curve.average_precision == 1.0
    assert sorted(p.name for p in (tmp_path / "ev").iterdir()) == ["evaluation.csv", "evaluation.json", "run.json"]
    job = run_evaluate_job(faults, sticks=work / "sticks.dat", out=tmp_path / "ev1", picture=False,
                           options=FaultScoringOptions(tolerance=1.0))
    assert "precision 0.333  recall 0.500  F1 0.400  (within 1 samples" in evaluation_table(job)[0]


@pytest.mark.parametrize("kind", ["npy labels", "npy bool", "png grey", "png alpha"])
def test_a_mask_scores_as_the_sticks(work, kind):
    from PIL import Image

    labels = _people_labels()
    path = work / ("mask.npy" if kind.startswith("npy") else "mask.png")
    if kind == "npy labels":
        np.save(path, labels.astype(np.int16))
    elif kind == "npy bool":
        np.save(path, labels > 0)
    elif kind == "png grey":
        Image.fromarray(((labels > 0) * 255).astype(np.uint8).T).save(path)
    else:
        rgba = np.zeros((N_SAMPLES, N_TRACES, 4), np.uint8)
        rgba[..., 3] = (labels > 0).T * 3
        Image.fromarray(rgba, "RGBA").save(path)
    job = run_evaluate_job(work / "faults", mask=path, out=work / "ev", picture=False)
    s = job.scores
    assert (s.precision, s.recall, s.n_people) == (pytest.approx(2 / 3), 1.0, 20)
    assert [(f.fault_id, f.n_samples, f.matches) for f in s.people] == [(1, 10, (1,)), (2, 10, (3,))]


def test_wrong_masks_are_refused_with_the_users_numbers(work):
    np.save(work / "wide.npy", np.zeros((N_TRACES + 1, N_SAMPLES)))
    line = _error(_invoke(work / "faults", "--mask", work / "wide.npy", "-o", work / "ev"))
    assert "the mask wide.npy is 41 x 20, but crossline 500 of line.sgy has 40 traces and 20 samples" in line
    np.save(work / "flipped.npy", np.zeros((N_SAMPLES, N_TRACES)))
    line = _error(_invoke(work / "faults", "--mask", work / "flipped.npy", "-o", work / "ev"))
    assert "(transposed: save mask.T)" in line
    (work / "text.png").write_text("not an image")
    assert "neither a .npy array nor an image" in _error(_invoke(work / "faults", "--mask", work / "text.png", "-o",
                                                                 work / "ev"))
    assert not (work / "ev").exists()


def test_refusals_say_what_to_do(work, tmp_path):
    faults, sticks = work / "faults", work / "sticks.dat"
    assert "--sticks or --mask, one of them" in _error(_invoke(faults, "-o", work / "ev"))
    assert "--sticks or --mask, one of them" in _error(_invoke(faults, "--sticks", sticks, "--mask", sticks, "-o",
                                                               work / "ev"))
    assert "no fault-stick file at" in _error(_invoke(faults, "--sticks", work / "nope.dat", "-o", work / "ev"))
    assert "holds no fault_points.csv" in _error(_invoke(work, "--sticks", sticks, "-o", tmp_path / "ev"))
    assert "is the input faults itself" in _error(_invoke(faults, "--sticks", sticks, "-o", faults))
    other = _write_sticks(work / "other.dat", crossline=700)
    assert "none of the 2 fault sticks of other.dat lies on crossline 500" in _error(
        _invoke(faults, "--sticks", other, "-o", work / "ev"))
    elsewhere = _write_line(work / "xl700.sgy", crossline=700)  # points of crossline 500 on crossline 700
    assert "are on crossline 500, not on crossline 700 of xl700.sgy; pass --seismic" in _error(
        _invoke(faults, "--sticks", sticks, "-o", work / "ev", "--seismic", elsewhere))
    (work / "line.sgy").write_bytes((work / "line.sgy").read_bytes()[:-4])  # the recorded line changed
    line = _error(_invoke(faults, "--sticks", sticks, "-o", work / "ev"))
    assert "has changed" in line and "pass --seismic" in line
    assert not (work / "ev").exists()


def test_sticks_of_other_lines_are_left_out_with_a_warning(work):
    from seismo3d.errors import Seismo3dWarning

    both = work / "both.dat"
    both.write_text(_write_sticks(work / "a.dat").read_text()
                    + _write_sticks(work / "b.dat", sticks=[(121, 1000.0, 1076.0)], crossline=700).read_text())
    with pytest.warns(Seismo3dWarning, match="1 of the 3 fault sticks of both.dat are not on crossline 500"):
        job = run_evaluate_job(work / "faults", sticks=both, out=work / "ev", picture=False)
    assert [f.name for f in job.scores.people] == ["stick_1", "stick_2"] and job.scores.recall == 1.0


def test_iesx_sticks_are_placed_by_the_lines_own_coordinates(tmp_path):
    """IESX sticks hold only X / Y: placed on the line through its cube's CDP X / Y, read with the faults run's header
    bytes (here 9 and 21), they score as the same sticks given by line numbers."""
    from seismo3d.seismic.io.fault_sticks import FaultSticks, read_fault_sticks, write_fault_sticks

    segy = _write_line(tmp_path / "line.sgy", iline=9, xline=21, xy=True)
    faults = _write_faults_folder(tmp_path / "faults", segy, segy_options={"iline": 9, "xline": 21})
    by_lines = read_fault_sticks(_write_sticks(tmp_path / "sticks.dat"))
    x, y = _line_xy(by_lines.inline, by_lines.crossline)
    placed = FaultSticks(by_lines.fault_id, by_lines.stick, x, y, by_lines.z, by_lines.inline, by_lines.crossline,
                         by_lines.names, by_lines.z_unit, "m")
    iesx = write_fault_sticks(tmp_path / "sticks_iesx.txt", placed, format="iesx")
    assert np.isnan(read_fault_sticks(iesx).inline).all()  # nothing but X / Y to place them by
    expected = run_evaluate_job(faults, sticks=tmp_path / "sticks.dat", out=tmp_path / "ev", picture=False)
    job = run_evaluate_job(faults, sticks=iesx, out=tmp_path / "ev_iesx", picture=False)
    np.testing.assert_array_equal(job.people.points, expected.people.points)
    assert (job.scores.precision, job.scores.recall) == (expected.scores.precision, expected.scores.recall) == (
        pytest.approx(20 / 30, abs=1e-12), 1.0)


def test_earlier_results_need_overwrite(work):
    faults, sticks, out = work / "faults", work / "sticks.dat", work / "faults" / "evaluation"
    run_evaluate_job(faults, sticks=sticks, picture=False)  # default: OUTPUT/evaluation
    before = (out / "evaluation.json").read_bytes()
    line = _error(_invoke(faults, "--sticks", sticks))
    assert "holds the results of an earlier run" in line and "--overwrite" in line
    assert (out / "evaluation.json").read_bytes() == before
    run_evaluate_job(faults, sticks=sticks, picture=False, overwrite=True, options=FaultScoringOptions(tolerance=1))
    assert (out / "evaluation.json").read_bytes() != before


def test_a_cube_is_refused(tmp_path):
    from seismo3d.jobs.evaluate import read_line

    segyio.tools.from_array3D(str(tmp_path / "cube.sgy"), np.zeros((4, 5, 10), np.float32), dt=4000)
    with pytest.raises(InputError, match="not one line: evaluate scores the faults of one seismic line"):
        read_line(tmp_path / "cube.sgy")


# --------------------------------------------------------------------------------------------------------------------
# the Great South Basin lines: the reference computation, line for line


def _dev_scores(segy: Path, sticks: Path, points: Path) -> tuple:
    """dev_fault_scores.py's placement of the sticks and of fault_points.csv and fault_scores.py's tolerant scores, as
    written there."""
    from scipy.ndimage import distance_transform_edt
    from skimage.draw import line as draw_line

    with segyio.open(segy) as f:
        n_traces, n_samples = len(f.ilines), len(f.samples)
        il, t = np.asarray(f.ilines, float), np.asarray(f.samples, float)
    rows = np.loadtxt(sticks)
    truth = np.zeros((n_traces, n_samples), bool)
    for a, b in zip(rows[0::2], rows[1::2]):
        c0, c1 = np.interp([a[6], b[6]], il, np.arange(len(il)))
        r0, r1 = np.interp([a[2], b[2]], t, np.arange(len(t)))
        rr, cc = draw_line(int(round(c0)), int(round(r0)), int(round(c1)), int(round(r1)))
        ok = (rr >= 0) & (rr < truth.shape[0]) & (cc >= 0) & (cc < truth.shape[1])
        truth[rr[ok], cc[ok]] = True
    ours = np.zeros(truth.shape, bool)
    with open(points) as fh:
        for r in csv.DictReader(fh):
            j = int(np.searchsorted(il, float(r["inline"])))
            k = int(round((float(r["time_or_depth"]) - t[0]) / (t[1] - t[0])))
            if 0 <= j < len(il) and 0 <= k < len(t):
                ours[j, k] = True
    p = float((distance_transform_edt(~truth)[ours] <= 3).mean())
    r = float((distance_transform_edt(~ours)[truth] <= 3).mean())
    return p, r, (2 * p * r / (p + r) if p + r else 0.0)


def _dev_tool(data_dir: str):
    """dev_fault_scores.py from the tools folder beside the data folder, or None."""
    import importlib.util
    import sys

    path = Path(data_dir).parent / "tools" / "dev_fault_scores.py"
    if not path.is_file():
        return None
    sys.path.insert(0, str(path.parent))
    try:
        spec = importlib.util.spec_from_file_location("dev_fault_scores", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(path.parent))
    return module


def _gsb_folder(tmp_path: Path, line: int, data_dir: str) -> tuple:
    """A faults folder on a GSB line whose points are the interpreter's sticks moved 2 traces and 1 sample, thinned
    and joined by scattered points (seeded), in three faults: the same fault points for both computations."""
    from seismo3d.data import fetch
    from seismo3d.seismic.fault_scoring import SectionFaults
    from seismo3d.seismic.io.fault_sticks import read_fault_sticks

    segy, sticks = Path(fetch(GSB + f"gsb_crl_{line}.sgy")), Path(fetch(GSB + f"gsb_crl_{line}_faults_opendtect.dat"))
    with segyio.open(segy) as f:
        il, t = np.asarray(f.ilines, float), np.asarray(f.samples, float)
    people = SectionFaults.from_sticks(read_fault_sticks(sticks), il, t).points
    rng = np.random.default_rng(line)
    moved = np.clip(people + [2, 1], 0, [il.size - 1, t.size - 1])[rng.random(len(people)) < 0.6]
    stray = np.column_stack([rng.integers(0, il.size, 60), rng.integers(0, t.size, 60)])
    points = np.concatenate([moved, stray])
    traced = [(il[j], 2600 if line == 2600 else 2800, t[k], 1 + n % 3) for n, (j, k) in enumerate(points)]
    folder = tmp_path / f"faults_{line}"
    folder.mkdir()
    with open(folder / "fault_points.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["inline", "crossline", "time_or_depth", "fault_id"])
        w.writerows([f"{a:g}", b, f"{c:g}", d] for a, b, c, d in traced)
    write_run_json(folder / "run.json", command="faults", options={}, inputs={"input": segy}, started=0.0,
                   seconds=1.0, stage_seconds={}, outputs={})
    return folder, segy, sticks


@pytest.mark.parametrize("line", [2600, 2800])
def test_gsb_scores_are_those_of_the_reference_computation(line, data_dir, tmp_path):
    folder, segy, sticks = _gsb_folder(tmp_path, line, data_dir)
    job = run_evaluate_job(folder, sticks=sticks, out=tmp_path / "ev", picture=False)
    s = job.scores
    expected = _dev_scores(segy, sticks, folder / "fault_points.csv")
    np.testing.assert_allclose((s.precision, s.recall, s.f1), expected, rtol=0, atol=1e-9)
    assert 0.2 < s.precision < 1 and 0.2 < s.recall < 1  # a case that tells placements apart
    dev = _dev_tool(data_dir)
    if dev is not None:  # the tool's own drawing of the sticks
        (_, _, truth, _), = [x for x in dev.gsb_lines(Path(data_dir)) if x[0].endswith(str(line))]
        assert (job.people.mask() == truth).all()


@pytest.mark.slow  # 'seismo3d faults' on a GSB line and the command: 6-10 s each
@pytest.mark.parametrize("line", [2600, 2800])
def test_the_command_after_a_real_faults_run(line, data_dir, tmp_path):
    from seismo3d.data import fetch

    segy, sticks = fetch(GSB + f"gsb_crl_{line}.sgy"), fetch(GSB + f"gsb_crl_{line}_faults_opendtect.dat")
    done = runner.invoke(app, ["faults", str(segy), "-o", str(tmp_path / "faults")])
    assert done.exit_code == 0, done.output
    result = _invoke(tmp_path / "faults", "--sticks", sticks)
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "faults" / "evaluation" / "evaluation.json").read_text())
    expected = _dev_scores(Path(segy), Path(sticks), tmp_path / "faults" / "fault_points.csv")
    np.testing.assert_allclose([summary[k] for k in ("precision", "recall", "f1")], expected, rtol=0, atol=1e-9)
    assert f"crossline {line} of gsb_crl_{line}.sgy: precision {expected[0]:.3f}  recall {expected[1]:.3f}" in \
        result.stdout
    assert summary["confidence_column"] == "confidence" and 0 < summary["average_precision"] <= 1
