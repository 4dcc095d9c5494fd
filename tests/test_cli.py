"""The ``seismo3d`` command (seismo3d.cli): conventions (--version, exit codes 0 / 1 / 2 / 130, one-line errors naming
flags, progress lines in logs), and the faults and point-cloud register commands end to end."""

import csv
import logging
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import segyio
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.data.synthetic import synthetic_cube

runner = CliRunner()


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


# --------------------------------------------------------------------------------------------------------------------
# register


@pytest.fixture(scope="module")
def clouds(tmp_path_factory):
    """A bumpy surface patch and the same patch moved by a known rigid transform."""
    folder = tmp_path_factory.mktemp("clouds")
    u, v = np.meshgrid(np.linspace(0, 3, 40), np.linspace(0, 2, 30))
    src = np.column_stack([u.ravel(), v.ravel(), (0.3 * np.sin(2 * u) * np.cos(3 * v) + 0.1 * u * v).ravel()])
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("xyz", [3, -2, 4], degrees=True).as_matrix()
    T[:3, 3] = [0.05, -0.03, 0.02]
    dst = src @ T[:3, :3].T + T[:3, 3]
    np.save(folder / "src.npy", src)
    np.savetxt(folder / "dst.xyz", dst)
    np.save(folder / "flat.npy", src[:, :2])
    return folder, T


def test_register(clouds, tmp_path):
    folder, T = clouds
    out = tmp_path / "T.json"
    result = runner.invoke(app, ["register", str(folder / "src.npy"), str(folder / "dst.xyz"), "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "fitness" in result.stdout
    payload = json.loads(out.read_text())
    np.testing.assert_allclose(np.array(payload["transform"]), T, atol=1e-4)
    assert payload["method"] == "point_to_plane" and payload["converged"]


@pytest.mark.parametrize("args, message", [
    (["{f}/src.npy", "{f}/flat.npy"], "3D but"),
    (["{f}/src.npy", "{f}/missing.xyz"], "no such file"),
    (["{f}/src.npy", "{f}/dst.xyz", "--method", "fused"], "--features"),
])
def test_register_errors(clouds, tmp_path, args, message):
    folder, _ = clouds
    args = [a.format(f=folder) for a in args]
    result = runner.invoke(app, ["register", *args, "-o", str(tmp_path / "T.json")])
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ") and message in result.stderr
    assert not (tmp_path / "T.json").exists()


def test_register_usage_error(clouds, tmp_path):
    folder, _ = clouds
    result = runner.invoke(app, ["register", str(folder / "src.npy"), str(folder / "dst.xyz"), "-o",
                                 str(tmp_path / "T.json"), "--model", "banana"])
    assert result.exit_code == 2


# --------------------------------------------------------------------------------------------------------------------
# faults


@pytest.fixture(scope="module")
def cube_file(tmp_path_factory):
    """A small synthetic SEG-Y cube (48^3, 4 ms, inlines / crosslines 1..48) in a folder of its own."""
    path = tmp_path_factory.mktemp("cube") / "cube.sgy"
    syn = synthetic_cube((48, 48, 48), n_faults=2, seed=1)
    segyio.tools.from_array3D(str(path), syn.cube, format=5, dt=4000)
    return path


@pytest.mark.slow  # 2.2 s; the fast lane (budget 60 s) keeps the command: test_cli_runs.py::test_faults
def test_faults(cube_file, tmp_path):
    out = tmp_path / "out"
    before = cube_file.read_bytes()
    result = runner.invoke(app, ["faults", str(cube_file), "-o", str(out)])
    assert result.exit_code == 0, result.output
    summary = _rows(out / "fault_summary.csv")
    assert len(summary) >= 2
    assert result.stdout.startswith(f"{len(summary)} faults in cube.sgy -> {out}")
    assert "fault   1:" in result.stdout and "wrote " in result.stdout
    for name in ("fault_likelihood.sgy", "fault_strike.sgy", "fault_dip.sgy", "faults.vtp", "fault_points.csv",
                 "fault_summary.csv", "faults.png"):
        assert (out / name).is_file(), name
        assert name in result.stdout
    assert cube_file.read_bytes() == before


@pytest.mark.slow  # 2.0 s in the fast lane (budget 60 s)
def test_faults_sample_unit(cube_file, tmp_path):
    out = tmp_path / "out"
    result = runner.invoke(app, ["faults", str(cube_file), "-o", str(out), "--sample-unit", "m"])
    assert result.exit_code == 0, result.output
    points = _rows(out / "fault_points.csv")
    assert "throw_m" in points[0] and "throw_ms" not in points[0]
    assert "median_throw_m" in _rows(out / "fault_summary.csv")[0]


def test_faults_demo_arguments(tmp_path, monkeypatch):
    """--demo and --demo-seed reach the job (stubbed here; tests/jobs/test_faults.py runs the real demo)."""
    import seismo3d.jobs.faults as job

    seen = {}

    def fake_job(input_path, out_dir, **kwargs):
        seen.update(kwargs, input_path=input_path)
        row = dict(id="1", n_points="500", mean_strike_deg="30.0", mean_dip_deg="70.0", median_throw_samples="4.5",
                   median_throw_ms="18")
        return job.FaultsJobResult({"summary": Path(out_dir) / "fault_summary.csv"}, (row,), None, {})

    monkeypatch.setattr(job, "run_faults_job", fake_job)
    result = runner.invoke(app, ["faults", "--demo", "--demo-seed", "7", "-o", str(tmp_path / "d")])
    assert result.exit_code == 0, result.output
    assert seen["demo"] is True and seen["demo_seed"] == 7 and seen["input_path"] is None
    assert "1 fault in the demo cube" in result.stdout
    assert "median throw 4.5 samples (18.0 ms)" in result.stdout


@pytest.mark.slow  # 1.4 s in the fast lane (budget 60 s)
def test_faults_warnings_are_one_line(tmp_path):
    data = synthetic_cube((96, 64), n_faults=1, seed=2).cube
    data[30] = np.nan
    src = tmp_path / "section.npy"
    np.save(src, data)
    result = runner.invoke(app, ["faults", str(src), "-o", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    warn = [line for line in result.stderr.splitlines() if line.startswith("warning: ")]
    assert any("NaN" in line for line in warn)
    assert "Seismo3dWarning" not in result.stderr  # no Python warning format


@pytest.mark.slow
@pytest.mark.parametrize("case, message", [
    ("not_segy", "is not SEG-Y: its binary header holds no sample format code"),
    ("header_bytes", "no inline / crossline grid at trace header bytes --iline 1, --xline 5; --iline 189, --xline 193 "
                     "(48 inlines x 48 crosslines) give one: pass those, or --ignore-geometry to read a trace list"),
    ("same_folder", "holds the input"),
    ("no_input", "--demo"),
    ("missing", "no SEG-Y file"),
])
def test_faults_errors(cube_file, tmp_path, case, message):
    out = str(tmp_path / "out")
    if case == "not_segy":
        bad = tmp_path / "in" / "bad.sgy"
        bad.parent.mkdir()
        bad.write_bytes(b"\x00\x01 not seismic " * 400)
        args = [str(bad), "-o", out]
    elif case == "header_bytes":
        args = [str(cube_file), "-o", out, "--iline", "1", "--xline", "5"]
    elif case == "same_folder":
        args = [str(cube_file), "-o", str(cube_file.parent)]
    elif case == "no_input":
        args = ["-o", out]
    else:
        args = [str(tmp_path / "nothing.sgy"), "-o", out]
    result = runner.invoke(app, ["faults", *args])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: ") and message in result.stderr
    assert len(result.stderr.splitlines()) == 1 and "=" not in result.stderr  # one line, CLI flags not arguments
    assert "Traceback" not in result.output


@pytest.mark.slow
def test_faults_raw_section_of_unknown_shape_names_the_flag(tmp_path):
    """A raw .f32be section whose name is not a registry file: one line naming --n-samples, the flag faults has (not
    the library's n_traces=)."""
    src = tmp_path / "in" / "mysection.f32be"
    src.parent.mkdir()
    np.zeros((100, 250), ">f4").tofile(src)
    result = runner.invoke(app, ["faults", str(src), "-o", str(tmp_path / "x")])
    assert result.exit_code == 2, result.output
    assert result.stderr == ("error: the shape of mysection.f32be is unknown (a raw section of 25000 float32 values, "
                             "no header); give its number of samples per trace: --n-samples N\n")
    result = runner.invoke(app, ["faults", str(src), "-o", str(tmp_path / "x"), "--n-samples", "250",
                                 "--sensitivity", "0.5"])
    assert "--n-samples" not in result.stderr and "shape" not in result.stderr  # the shape given: read (no faults)


def test_faults_raw_section_with_its_shape_swapped_is_refused(data_dir, tmp_path):
    """A raw section read with its numbers of traces and samples swapped (campos_gx373, 550 traces of 300 samples,
    given --n-samples 550) once traced it to "0 faults" with exit 0: now one line naming --n-samples 300, exit 2,
    before any work, and no output folder left behind."""
    src = tmp_path / "in" / "line.f32be"
    src.parent.mkdir()
    shutil.copy(Path(data_dir) / "seismic" / "sections" / "campos_gx373.f32be", src)
    result = runner.invoke(app, ["faults", str(src), "-o", str(tmp_path / "x"), "--n-samples", "550"])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: line.f32be read as 300 traces of 550 samples has neighbouring traces that "
                                    "do not look alike")
    assert result.stderr.endswith("; pass --n-samples 300\n") and len(result.stderr.splitlines()) == 1
    assert not (tmp_path / "x").exists()


@pytest.mark.slow
@pytest.mark.parametrize("name, trace_list", [("penobscot_xl1155.sgy", False),
                                               ("volve_fullstack_twt_arbline.sgy", True)])
def test_faults_on_real_2d_lines_without_flags(data_dir, tmp_path, name, trace_list):
    # a line of a 3D survey (crossline 1155) and an arbitrary line without inline / crossline numbers: no flags
    path = Path(data_dir) / "seismic" / name
    result = runner.invoke(app, ["faults", str(path), "-o", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    warn = [line for line in result.stderr.splitlines() if line.startswith("warning: ")]
    listed = [line for line in warn if "read as a trace list" in line]
    assert len(listed) == (1 if trace_list else 0) and "--iline" not in result.stderr
    assert all("=" not in line for line in warn)  # flags, not argument names
    rows = _rows(tmp_path / "out" / "fault_summary.csv")
    # faults an interpreter draws on each line (issue 54's pictures): xl1155's large fault with the one at inline ~1390,
    # ~1000 ms and the shallow one at inlines 1170-1220 (3 traced: the two along the migration swings at 4300-5400 ms
    # dropped since a clear throw of unlike sides must reach their half period, the third at 3700-4350 ms since its
    # 1.5 samples are 0.21 of the reflectors' half period and no step at the fault: EvidenceOptions.drag_half_periods);
    # on Volve the fault at 1200-1570 ms and three deep ones (4 traced since branches of opposite dip are split and the
    # inverted V at 2800-3150 ms, without offset, dropped)
    assert f"{len(rows)} faults in {name}" in result.stdout and len(rows) >= (4 if trace_list else 3)
    # the points' trace columns say what they hold: a trace list's trace number (from 1, as seismo3d.open numbers
    # it), the survey's numbers otherwise
    points = _rows(tmp_path / "out" / "fault_points.csv")
    if trace_list:
        assert list(points[0])[:5] == ["trace", "x", "y", "xy_unit", "time_or_depth"]  # CDP X/Y of the trace
        assert {int(r["trace"]) for r in points} <= set(range(1, 226)) and min(int(r["trace"]) for r in points) > 0
    else:
        assert list(points[0])[:6] == ["inline", "crossline", "x", "y", "xy_unit", "time_or_depth"]
        assert {int(r["crossline"]) for r in points} == {1155}
        assert {int(r["inline"]) for r in points} <= set(range(1000, 1601))
        assert not [r for r in points if 1370 <= int(r["inline"]) <= 1460 and 3600 <= float(r["time_or_depth"]) <= 4400]
    with segyio.open(str(tmp_path / "out" / "fault_likelihood.sgy"), ignore_geometry=True) as out, \
            segyio.open(str(path), ignore_geometry=True) as src:
        assert out.tracecount == src.tracecount and len(out.samples) == len(src.samples)


def test_register_refuses_a_2d_line_in_one_line(data_dir, tmp_path):
    # not a volume: one error line saying what the file is, no warning suggesting a flag register does not have
    seismic = Path(data_dir) / "seismic"
    for name, what in (("volve_fullstack_twt_arbline.sgy", "a 2D or arbitrary line without inline / crossline "
                                                           "numbers (CDP 1-225)"),
                       ("penobscot_xl1155.sgy", "a 2D line along inlines 1000-1600 (crossline 1155)")):
        result = runner.invoke(app, ["register", str(seismic / name), str(seismic / "f3_crop.sgy"), "-o",
                                     str(tmp_path / "T.json")])
        assert result.exit_code == 2, result.output
        assert result.stderr == f"error: {name} is {what}, not a 3D cube; register two 3D cubes\n"


@pytest.mark.slow  # 1.8 s in the fast lane (budget 60 s)
def test_faults_exit_code_in_a_real_process(tmp_path):
    """The installed command exits with 2 and one line of error, no traceback."""
    bad = tmp_path / "in" / "bad.segy"
    bad.parent.mkdir()
    bad.write_text("not seismic\n" * 500)
    proc = subprocess.run([sys.executable, "-m", "seismo3d.cli", "faults", str(bad), "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stderr.startswith("error: bad.segy") and "Traceback" not in proc.stderr
    assert bad.read_text() == "not seismic\n" * 500


def test_faults_interrupted(tmp_path, monkeypatch):
    """Ctrl-C: exit code 130 and a one-line note, no traceback."""
    import seismo3d.jobs.faults as job

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(job, "run_faults_job", interrupted)
    result = runner.invoke(app, ["faults", "--demo", "-o", str(tmp_path / "d")])
    assert result.exit_code == 130
    assert result.stderr.startswith("interrupted:")


def test_an_interrupted_block_run_says_what_it_keeps_and_how_to_resume(tmp_path, monkeypatch, caplog):
    """Ctrl-C in a run by blocks: exit code 130 and one line naming the stores kept and how to resume."""
    import seismo3d.jobs.faults as job

    cube, out = tmp_path / "cube.npy", tmp_path / "out"
    np.save(cube, np.random.default_rng(0).normal(size=(40, 40, 50)).astype(np.float32))

    def interrupted(data, **kwargs):  # the likelihood's first blocks are finished when Ctrl-C comes
        partial = out / "fault_likelihood.zarr.partial"
        partial.mkdir(parents=True)
        (partial / "block").write_bytes(bytes(5 * 10 ** 6))
        raise KeyboardInterrupt

    monkeypatch.setattr(job, "trace_faults", interrupted)
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        result = runner.invoke(app, ["faults", str(cube), "-o", str(out), "--memory-limit", "100MB"])
    assert result.exit_code == 130
    assert "40 x 40 x 50 samples traced block by block" in caplog.text  # which way it runs, said before the work
    line = result.stderr.strip().splitlines()[-1]  # after the log line of how it runs
    assert line.startswith("interrupted: the blocks finished so far are kept in")
    assert "fault_likelihood.zarr.partial; 10MB" in line and "run the same command again to resume" in line
    assert [p.name for p in out.iterdir()] == ["fault_likelihood.zarr.partial"]  # no other output


def test_an_interrupted_overwrite_puts_the_earlier_stores_back_and_says_so(tmp_path, monkeypatch):
    """Ctrl-C in a run by blocks with --overwrite over another input's stores: they were set aside before the work
    and are put back, this run's partial store removed; the line says exactly that."""
    import zarr

    import seismo3d.jobs.faults as job

    cube, out = tmp_path / "cube.npy", tmp_path / "out"
    np.save(cube, np.random.default_rng(0).normal(size=(40, 40, 50)).astype(np.float32))
    earlier = zarr.open_group(str(out / "fault_likelihood.zarr"), mode="w")
    earlier.create_array("likelihood", shape=(40, 40, 50), dtype="float32")
    earlier.attrs.update({"source": "another", "likelihood": "learned"})

    def interrupted(data, **kwargs):  # the earlier store is already aside when the work starts
        assert not (out / "fault_likelihood.zarr").exists()
        (out / "fault_likelihood.zarr.partial").mkdir()
        raise KeyboardInterrupt

    monkeypatch.setattr(job, "trace_faults", interrupted)
    result = runner.invoke(app, ["faults", str(cube), "-o", str(out), "--memory-limit", "100MB", "--overwrite"])
    assert result.exit_code == 130
    line = result.stderr.strip().splitlines()[-1]
    assert line.startswith("interrupted: the earlier run's fault_likelihood.zarr are back in") and "nothing of this " \
        "run was kept" in line
    assert sorted(p.name for p in out.iterdir()) == ["fault_likelihood.zarr"]
    assert zarr.open_group(str(out / "fault_likelihood.zarr"), mode="r").attrs["source"] == "another"


def test_the_demo_seed_is_not_called_seed(tmp_path):
    # --seed is a seed pick in `seismo3d horizon`; the demo's random seed has its own name
    result = runner.invoke(app, ["faults", "--demo", "--seed", "7", "-o", str(tmp_path / "d")])
    assert result.exit_code == 2 and "--seed" in result.output


# --------------------------------------------------------------------------------------------------------------------
# conventions


def test_version():
    from seismo3d import __version__

    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0 and result.stdout.strip() == f"seismo3d {__version__}"


def test_errors_name_the_command_line_flags(clouds, tmp_path):
    folder, _ = clouds
    result = runner.invoke(app, ["register", str(folder / "src.npy"), str(folder / "dst.xyz"), "-o",
                                 str(tmp_path / "T.json"), "--max-distance", "-1"])
    assert result.exit_code == 2 and "--max-distance" in result.stderr and "max_distance" not in result.stderr
    far = tmp_path / "far.npy"
    np.save(far, np.load(folder / "src.npy") + 100.0)  # no target point within the distance
    result = runner.invoke(app, ["register", str(far), str(folder / "dst.xyz"), "-o", str(tmp_path / "T.json"),
                                 "--max-distance", "0.1"])
    assert result.exit_code == 2
    assert "within --max-distance 0.1;" in result.stderr and "raise --max-distance or pass a better --init" in \
        result.stderr, result.stderr


def test_a_registration_that_did_not_converge_exits_non_zero(tmp_path):
    # a plane slides in itself under point-to-plane ICP: the result is written, one line says why, exit code 1
    u, v = np.meshgrid(np.linspace(0, 2, 30), np.linspace(0, 2, 30))
    plane = np.column_stack([u.ravel(), v.ravel(), np.zeros(u.size)])
    np.save(tmp_path / "a.npy", plane)
    np.save(tmp_path / "b.npy", plane + [0.05, 0.02, 0.01])
    out = tmp_path / "T.json"
    result = runner.invoke(app, ["register", str(tmp_path / "a.npy"), str(tmp_path / "b.npy"), "-o", str(out)])
    assert result.exit_code == 1
    lines = [line for line in result.stderr.splitlines() if line.startswith("error:")]
    assert len(lines) == 1 and "did not converge" in lines[0] and str(out) in lines[0]
    assert "Warning:" not in result.stderr  # warnings are one line too: "warning: ..."
    assert json.loads(out.read_text())["converged"] is False


@pytest.mark.slow
def test_progress_is_one_line_per_step_when_stderr_is_not_a_terminal(tmp_path):
    # in a log (stderr not a terminal) the fault job's steps are lines, not carriage-return bars
    data = synthetic_cube((64, 48), n_faults=1, seed=2).cube
    np.save(tmp_path / "s.npy", data)
    proc = subprocess.run([sys.executable, "-m", "seismo3d.cli", "faults", str(tmp_path / "s.npy"), "-o",
                           str(tmp_path / "out")], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "\r" not in proc.stderr
    lines = proc.stderr.splitlines()
    for step in ("fault likelihood (1/7)", "ridges (2/7)", "voting (3/7)", "thinning (4/7)", "fault skins (5/7)",
                 "throw (6/7)", "evidence (7/7)"):
        assert f"faults: {step}" in lines
    # in memory a step is one block, the whole section: within it, the network reports its sections and the voting
    # its seeds
    assert any(line.startswith("fault network: ") and "section" in line for line in lines)
    assert any(line.startswith("fault voting: ") and "seed" in line for line in lines)
    assert "fault orientation: structure tensor (2/4)" in lines  # its stages, the longest silent before
    assert any(line.startswith("writing: figure") for line in lines)


# --------------------------------------------------------------------------------------------------------------------
# convert


def test_convert(cube_file, tmp_path):
    """One summary line; the store holds the cube; a second run names --overwrite; a bad byte names --iline."""
    out = tmp_path / "cube.zarr"
    result = runner.invoke(app, ["convert", str(cube_file), str(out)])
    assert result.exit_code == 0, result.output
    lines = result.stdout.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("converted cube.sgy: 48 inlines x 48 crosslines x 48 samples -> ")
    import xarray as xr

    with segyio.open(str(cube_file)) as f:
        expected = segyio.tools.cube(f)
    np.testing.assert_array_equal(xr.open_zarr(out).seismic.values, expected)
    again = runner.invoke(app, ["convert", str(cube_file), str(out)])
    assert again.exit_code == 2 and again.stderr.startswith("error: ") and "--overwrite" in again.stderr
    bad = runner.invoke(app, ["convert", str(cube_file), str(tmp_path / "b.zarr"), "--iline", "190"])
    assert bad.exit_code == 2 and "--iline" in bad.stderr and not (tmp_path / "b.zarr").exists()


@pytest.mark.parametrize("args", [
    ["register", "a.ply", "b.ply", "-o", "{missing}/t.json"],
    ["match", "a.png", "b.png", "-o", "{missing}/m.csv"],
    ["plan", "dem.tif", "--start", "1,1", "--goal", "2,2", "-o", "{missing}/p.csv"],
    ["render", "a.ply", "-o", "{missing}/r.png"],
    ["horizon", "a.sgy", "--seed", "1,1,1", "-o", "{missing}/h.txt"],
])
def test_a_missing_output_folder_is_refused_before_any_work(tmp_path, args):
    # the inputs are empty files: had the command read them first, it would fail on them, not on the output
    for name in ("a.ply", "b.ply", "a.png", "b.png", "dem.tif", "a.sgy"):
        (tmp_path / name).touch()
    missing = tmp_path / "not_made"
    args = [str(tmp_path / a) if a in ("a.ply", "b.ply", "a.png", "b.png", "dem.tif", "a.sgy") else
            a.format(missing=missing) for a in args]
    res = runner.invoke(app, args)
    assert res.exit_code == 2, res.output
    assert f"folder {missing} does not exist; create it first" in " ".join(res.output.split())
    assert not missing.exists()


def test_argument_names_inside_file_names_are_left_alone():
    """Library names become flags in messages, but not inside a path (init.json, /runs/max_distance/...)."""
    from seismo3d._cli_messages import in_flags as _in_flags

    flags = {"init": "--init", "max_distance": "--max-distance"}
    assert _in_flags("output /tmp/init.json is the input init.json itself; raise max_distance or pass init.",
                     flags) == ("output /tmp/init.json is the input init.json itself; raise --max-distance or pass "
                                "--init.")
    assert _in_flags("cannot read /runs/max_distance/init", flags) == "cannot read /runs/max_distance/init"


def test_render_accepts_the_segy_flags_of_faults():
    """Every flag of `faults` that says how to read a SEG-Y file is a flag of `render` too, with the same default
    (``--n-samples`` is for raw .f32be sections, which render does not draw)."""
    import typer.main

    commands = typer.main.get_command(app).commands
    segy = {"iline", "xline", "endian", "ignore_geometry", "sample_unit"}

    def flags(name):
        return {p.name: (tuple(p.opts), p.default) for p in commands[name].params if p.name in segy}

    assert set(flags("faults")) == segy and flags("render") == flags("faults")


@pytest.mark.slow  # 3 s: three fresh processes importing numba
def test_the_first_compilation_is_said_once_in_one_line(tmp_path):
    """compile_note: a cached numba kernel of seismo3d compiled for the first time (an empty cache, as after a fresh
    install) is said in one "note:" line, once however many compile; loaded from the cache the next time, nothing;
    a kernel that is not cached (compiled on every run) says nothing either."""
    from seismo3d._cli_messages import COMPILE_NOTE

    (tmp_path / "seismo3d_probe_kernels.py").write_text(
        "from numba import njit\n\n"
        "@njit(cache=True)\ndef one(x):\n    return x + 1\n\n"
        "@njit(cache=True)\ndef two(x):\n    return x * 2\n\n"
        "@njit\ndef uncached(x):\n    return x - 1\n")
    script = ("import sys\nfrom seismo3d._cli_messages import compile_note\nimport seismo3d_probe_kernels as k\n"
              "with compile_note():\n    k.{calls}\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), *sys.path])}

    def run(calls):
        done = subprocess.run([sys.executable, "-c", script.format(calls=calls)], capture_output=True, text=True,
                              env=env, cwd=tmp_path, timeout=120)
        assert done.returncode == 0, done.stderr
        return done.stderr

    assert run("one(1); k.two(2)") == COMPILE_NOTE + "\n"  # two kernels compiled: one line
    assert run("one(1); k.two(2)") == ""  # from numba's cache
    assert run("uncached(1)") == ""
    # a new kind of input (another signature: what a 2D line is after 3D cubes) compiles again and says so, as the
    # note says (issue 77: it promised "once per install" and came once per command)
    assert run("one(1.5)") == COMPILE_NOTE + "\n"
    assert run("one(1.5); k.one(1)") == ""


def test_every_command_that_may_compile_says_so():
    """Every command whose job imports numba (the heavy packages of each job in tests/jobs/test_job_imports.py, which
    the slow lane checks against a fresh interpreter's imports) runs its job inside compile_note, so that a first
    run on a fresh install says in one line why it is slow (issue 58); the others (convert, match, evaluate) import
    no numba and compile nothing."""
    import importlib.util
    import inspect
    import re

    import typer.main

    spec = importlib.util.spec_from_file_location("job_imports", Path(__file__).parent / "jobs" / "test_job_imports.py")
    job_imports = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = job_imports  # its dataclasses look their module up
    try:
        spec.loader.exec_module(job_imports)
    finally:
        del sys.modules[spec.name]
    compiles = {b.module.rsplit(".", 1)[-1] for b in job_imports.BUDGETS if "numba" in b.heavy}
    checked = set()
    for name, command in typer.main.get_command(app).commands.items():
        source = inspect.getsource(inspect.unwrap(command.callback))
        jobs = set(re.findall(r"from \.jobs\.(\w+) import", source))
        assert jobs, f"{name}: no job imported"
        if jobs & compiles:
            assert "compile_note()" in source, f"seismo3d {name} compiles numba kernels and does not say so"
            checked.add(name)
    assert {"faults", "horizon", "register", "map", "lineaments", "plan", "render"} <= checked, checked


def test_app_freezes_the_collector_when_the_command_ends_the_process():
    """A command that ends the process (click's sys.exit) moves the objects left out of the garbage collector's
    generations (gc.freeze, so that the interpreter's shut-down does not walk them); a call that returns
    (standalone_mode=False) leaves the collector as it was."""
    import gc

    gc.unfreeze()
    try:
        assert app(["--version"], standalone_mode=False) == 0
        assert gc.get_freeze_count() == 0
        with pytest.raises(SystemExit) as exit_:
            app(["--version"])
        assert exit_.value.code == 0
        assert gc.get_freeze_count() > 0
    finally:
        gc.unfreeze()


def test_a_ctrl_c_while_the_writers_load_leaves_no_staging_folder(tmp_path, monkeypatch, default_sigint_handler):
    """The writers' libraries are imported before the output folder's staging folder is made, a Ctrl-C held until
    their import ends: a SIGINT inside VTK's import crashed the process (a segmentation fault, no clean-up), which
    left ``.staged-*.tmp`` with the demo's input in the output folder. Here a module stands for VTK: it is imported
    whole, then the run stops as interrupted and the output folder holds nothing."""
    import seismo3d.jobs.faults as job

    (tmp_path / "vtk_like.py").write_text("import os, signal\nos.kill(os.getpid(), signal.SIGINT)\nWHOLE = True\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(job, "WRITER_MODULES", ("vtk_like",))
    monkeypatch.delitem(sys.modules, "vtk_like", raising=False)
    out = tmp_path / "out"
    result = runner.invoke(app, ["faults", "--demo", "-o", str(out)])
    assert result.exit_code == 130 and result.stderr.startswith("interrupted:"), result.output
    assert sys.modules["vtk_like"].WHOLE  # its import was not cut short
    assert not out.exists() or not any(out.iterdir())
