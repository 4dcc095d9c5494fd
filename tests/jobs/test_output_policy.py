"""The output policy of every command (seismo3d.jobs.outputs) through the `seismo3d` command line: an output that is an
input, an output folder holding an input, earlier results without --overwrite and unwritable destinations are refused
in one line with exit code 2, before any work and without a traceback, and leave every input byte for byte as it was;
with --overwrite the earlier results are replaced."""

from __future__ import annotations

import hashlib
import shutil
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pytest
import segyio
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.data.terrain import synthetic_scarp_dem
from seismo3d.errors import InputError
from seismo3d.jobs.outputs import check_outputs, output_file, output_folder, output_store
from seismo3d.terrain import Dem, write_dem
from seismo3d.terrain.georef import CoordinateReference

runner = CliRunner()
UTM = CoordinateReference("projected", 32614, "WGS 84 / UTM zone 14N", "metre", 1.0, "metre", 1.0)


@dataclass(frozen=True)
class Command:
    """A command, its positional inputs (names in the inputs folder), and what it writes.

    ``kind`` is 'file', 'store' or 'folder'; ``results`` the names of the files a run writes into an output folder
    (for a file: its own name); ``args(inputs, output)`` the command line."""

    name: str
    inputs: tuple
    kind: str
    results: tuple
    args: Callable


def _cube_seed(folder: Path) -> str:
    """IL,XL,T of the first peak of the cube's middle trace (a seed horizon tracking accepts)."""
    from seismo3d.seismic import reflector_picks

    with segyio.open(str(folder / "cube.sgy")) as f:
        trace = f.trace[len(f.trace) // 2]
        il, xl = f.header[len(f.trace) // 2][segyio.su.iline], f.header[len(f.trace) // 2][segyio.su.xline]
    peaks, _ = reflector_picks(trace[None], polarity="peak")
    return f"{il},{xl},{4.0 * round(float(peaks[len(peaks) // 2]))}"


FAULT_FILES = ("fault_likelihood.sgy", "fault_strike.sgy", "fault_dip.sgy", "fault_votes.sgy", "faults.vtp",
               "fault_points.csv", "fault_summary.csv", "faults.png")
COMMANDS = [
    Command("register", ("src.npy", "dst.npy"), "file", ("T.json",),
            lambda i, o: ["register", i[0], i[1], "-o", o]),
    Command("match", ("left.png", "right.png"), "file", ("matches.csv",),
            lambda i, o: ["match", i[0], i[1], "-o", o]),
    Command("plan", ("dem.tif",), "file", ("path.csv",),
            lambda i, o: ["plan", i[0], "--start", "10,10", "--goal", "12,40", "--max-slope", "89", "-o", o]),
    Command("lineaments", ("dem.tif",), "folder", ("lineaments.csv", "rose.png", "lineaments.png"),
            lambda i, o: ["lineaments", i[0], "-o", o]),
    Command("horizon", ("cube.sgy",), "file", ("h.txt",),
            lambda i, o: ["horizon", i[0], "--seed", _cube_seed(Path(i[0]).parent), "--no-faults", "-o", o]),
    Command("convert", ("cube.sgy",), "store", ("cube.zarr",), lambda i, o: ["convert", i[0], o]),
    Command("faults", ("cube.sgy",), "folder", FAULT_FILES, lambda i, o: ["faults", i[0], "-o", o]),
    Command("render", ("cube.sgy",), "file", ("picture.png",),
            lambda i, o: ["render", i[0], "-o", o, "--size", "320x240"]),
    Command("map", ("kitchen",), "folder", ("trajectory.txt", "keyframes.json", "mesh.ply"),
            lambda i, o: ["map", i[0], "-o", o, "--max-frames", "2", "--no-render", "--no-loop-closure"]),
]
BY_NAME = {c.name: c for c in COMMANDS}
SLOW = {"faults"}  # a run of it takes over 10 s


def _write_cube(path: Path) -> None:
    cube = synthetic_cube((40, 40, 64), seed=1).cube.astype(np.float32)
    segyio.tools.from_array3D(str(path), cube, format=5, dt=4000)


def _write_images(folder: Path) -> None:
    import cv2
    from scipy import ndimage as ndi

    texture = ndi.gaussian_filter(np.random.default_rng(0).random((160, 160)), 2.0)
    texture = (255 * (texture - texture.min()) / np.ptp(texture)).astype(np.uint8)
    cv2.imwrite(str(folder / "left.png"), texture[10:138, 10:138])
    cv2.imwrite(str(folder / "right.png"), texture[16:144, 12:140])


def _write_sequence(folder: Path, data_dir: str | None) -> None:
    """Three real 7-Scenes frames as a TUM-style folder (with the data directory), else an empty folder: the refusals
    read no input, only a run needs the frames."""
    folder.mkdir()
    if data_dir is None:
        return
    src = Path(data_dir) / "rgbd" / "7scenes_redkitchen_0000_0495"
    (folder / "rgb").mkdir()
    (folder / "depth").mkdir()
    shutil.copy(src / "camera-intrinsics.txt", folder)
    rows = []
    for i in range(3):
        stem, t = f"frame-{5 * i:06d}", 5 * i / 30
        shutil.copy(src / f"rgb/{stem}.color.jpg", folder / "rgb")
        shutil.copy(src / f"depth/{stem}.depth.png", folder / "depth")
        rows.append(f"{t:.6f} rgb/{stem}.color.jpg {t:.6f} depth/{stem}.depth.png")
    (folder / "associations.txt").write_text("\n".join(rows) + "\n")


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """Every command's inputs, written once; tests copy them (copies of copies: nothing here is ever written)."""
    import os

    folder = tmp_path_factory.mktemp("inputs")
    points = np.random.default_rng(0).random((200, 3))
    np.save(folder / "src.npy", points)
    np.save(folder / "dst.npy", points + [0.01, 0.0, 0.0])
    _write_images(folder)
    dem = synthetic_scarp_dem(seed=12).elevation[:64, :64]
    write_dem(folder / "dem.tif", Dem(dem, np.array([[30.0, 0, 650000.0], [0, -30.0, 3620000.0], [0, 0, 1]]), UTM))
    _write_cube(folder / "cube.sgy")
    _write_sequence(folder / "kitchen", os.environ.get("SEISMO3D_DATA_DIR"))
    return folder


@pytest.fixture
def work(inputs, tmp_path):
    """A fresh copy of the inputs in this test's folder."""
    folder = tmp_path / "in"
    shutil.copytree(inputs, folder)
    return folder


def _digest(path: Path) -> dict:
    """sha256 of a file, or of every file under a folder (by relative path)."""
    files = [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.is_file())
    return {str(p.relative_to(path.parent)): hashlib.sha256(p.read_bytes()).hexdigest() for p in files}


def _digests(folder: Path) -> dict:
    return _digest(folder) if folder.exists() else {}


def _refused(result) -> str:
    """The one error line of a refused command: exit 2, one line on stderr, no traceback."""
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit), result.exception  # not an uncaught error
    assert "Traceback" not in result.output
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    return lines[0]


def _invoke(command: Command, folder: Path, output, *extra: str):
    return runner.invoke(app, [*command.args([str(folder / n) for n in command.inputs], str(output)), *extra])


# --------------------------------------------------------------------------------------------------------------------
# an output is never an input


OUTPUT_IS_INPUT = [pytest.param(c, k, id=f"{c.name}-{c.inputs[k]}") for c in COMMANDS for k in range(len(c.inputs))]


@pytest.mark.parametrize("overwrite", [False, True], ids=["plain", "overwrite"])
@pytest.mark.parametrize("command, k", OUTPUT_IS_INPUT)
def test_output_that_is_an_input_is_refused(command, k, overwrite, work):
    before = _digest(work)
    line = _refused(_invoke(command, work, work / command.inputs[k], *(["--overwrite"] if overwrite else [])))
    assert f"is the input {command.inputs[k]}" in line
    assert _digest(work) == before


@pytest.mark.parametrize("command", [c for c in COMMANDS if c.kind != "file"], ids=lambda c: c.name)
def test_output_folder_holding_an_input_is_refused(command, work):
    before = _digest(work)
    line = _refused(_invoke(command, work, work, "--overwrite"))
    assert "holds the input" in line
    assert _digest(work) == before


@pytest.mark.parametrize("args, name", [
    (["register", "{w}/src.npy", "{w}/dst.npy", "--init", "{w}/init.json", "-o", "{w}/init.json"], "init.json"),
    (["render", "{w}/h.txt", "--seismic", "{w}/cube.sgy", "-o", "{w}/cube.sgy"], "cube.sgy"),
], ids=["register-init", "render-seismic"])
def test_output_that_is_an_option_input_is_refused(args, name, work):
    (work / "init.json").write_text('{"transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}')
    (work / "h.txt").write_text("1 1 40\n")
    before = _digest(work)
    line = _refused(runner.invoke(app, [a.format(w=work) for a in args]))
    assert line.startswith(f"error: output {work / name} is the input {name} itself")
    assert _digest(work) == before


def test_the_same_file_under_another_name_is_refused(work):
    """A symlink or a hard link to an input is the input."""
    (work / "alias.npy").symlink_to(work / "src.npy")
    (work / "hard.npy").hardlink_to(work / "dst.npy")
    before = _digest(work)
    for output, name in (("alias.npy", "src.npy"), ("hard.npy", "dst.npy")):
        line = _refused(_invoke(BY_NAME["register"], work, work / output, "--overwrite"))
        assert f"is the input {name}" in line
    assert _digest(work) == before


# --------------------------------------------------------------------------------------------------------------------
# earlier results are replaced only with --overwrite


def _earlier_results(command: Command, out: Path, work: Path) -> Path:
    """Stand-ins of an earlier run's results at ``out``; returns the output path to pass."""
    if command.kind == "folder":
        out.mkdir()
        for name in command.results:
            (out / name).write_bytes(b"earlier run")
        (out / "notes.txt").write_text("the user's own file")
        return out
    if command.kind == "store":  # only a store of the command is replaced: an earlier convert, marked
        assert _invoke(command, work, out).exit_code == 0
        (out / "earlier.txt").write_text("earlier run")
        return out
    out.mkdir()
    (out / command.results[0]).write_bytes(b"earlier run")
    return out / command.results[0]


def _earlier(command: Command, out: Path) -> dict:
    """What of the stand-ins must change once replaced."""
    if command.kind == "folder":
        return {name: out / name for name in command.results}
    if command.kind == "store":
        return {"earlier.txt": out / "earlier.txt"}
    return {command.results[0]: out}


RUNS = [pytest.param(c, id=c.name, marks=[pytest.mark.slow] if c.name in SLOW else []) for c in COMMANDS]


@pytest.mark.slow
@pytest.mark.parametrize("command", [pytest.param(c, id=c.name) for c in COMMANDS])
def test_earlier_results_are_refused_without_overwrite(command, work, tmp_path):
    output = _earlier_results(command, tmp_path / "out", work)
    inputs, earlier = _digest(work), _digests(tmp_path / "out")
    line = _refused(_invoke(command, work, output))
    assert "--overwrite" in line and str(output) in line
    assert _digest(work) == inputs and _digests(tmp_path / "out") == earlier


@pytest.mark.slow  # 0.6-1.2 s per command, 6 s in all in the fast lane, whose budget is 60 s
@pytest.mark.parametrize("command", RUNS)
def test_earlier_results_are_replaced_with_overwrite(command, work, tmp_path, request):
    if command.name == "map":
        request.getfixturevalue("data_dir")  # the frames are real data
    output = _earlier_results(command, tmp_path / "out", work)
    inputs = _digest(work)
    result = _invoke(command, work, output, "--overwrite")
    assert result.exit_code == 0, result.output
    for name, path in _earlier(command, output).items():
        assert not path.exists() or path.read_bytes() != b"earlier run", name
    if command.kind == "folder":
        assert (output / "notes.txt").read_text() == "the user's own file"  # not a result: left alone
    assert _digest(work) == inputs


# --------------------------------------------------------------------------------------------------------------------
# unwritable destinations: before the work


@pytest.mark.parametrize("destination", ["/proc/nope", "/dev/null/x"])
@pytest.mark.parametrize("command", [pytest.param(c, id=c.name) for c in COMMANDS])
def test_unwritable_destination_is_refused_at_once(command, destination, work):
    output = destination + ("/picture.png" if command.name == "render" else "")
    before = _digest(work)
    _invoke(command, work, "/dev/null/warm-up")  # imports are not the command's time
    start = time.perf_counter()
    result = _invoke(command, work, output)
    seconds = time.perf_counter() - start
    line = _refused(result)
    assert line.startswith(f"error: cannot {'create output folder' if command.kind == 'folder' else 'write'} "
                           f"{output}")
    assert seconds < 2.0
    assert _digest(work) == before


def test_unwritable_destination_is_refused_before_reading_the_input(work, monkeypatch):
    """The output is checked first: a run whose input reader would fail says what is wrong with the output."""
    import seismo3d.jobs.faults as job

    def fail(*args, **kwargs):  # pragma: no cover - must not be called
        raise AssertionError("the input was read")

    monkeypatch.setattr(job, "read_input", fail)  # the one opening of the input, lazy or whole
    line = _refused(runner.invoke(app, ["faults", str(work / "cube.sgy"), "-o", "/proc/nope"]))
    assert line.startswith("error: cannot create output folder /proc/nope: no file can be created in /proc")


@pytest.mark.parametrize("command", [pytest.param(BY_NAME[n], id=n) for n in ("faults", "render")])
def test_unwritable_destination_is_refused_in_a_fresh_process_before_the_heavy_imports(command, work, tmp_path):
    """In a new interpreter, as a user starts the command: one line, exit code 2, none of numpy, numba, scipy, pyvista
    imported (the command checks its output before it imports its job: seismo3d._cli_outputs), in under 0.75 CPU s
    (the process's user + system time, which stays near its value at any load where the wall time does not: the
    wall-clock limit of 1.5 s failed at 1.9 s at load 12 on 2 cores). Measured 0.19-0.30 CPU s (0.47-0.93 s wall)
    per command at load 12 under ``-X importtime`` (1.1-1.9 s wall before, at load 3, importing the job first)."""
    import os
    import resource
    import subprocess
    import sys

    args = command.args([str(work / n) for n in command.inputs], "/proc/nope" + ("/x.png" if command.name ==
                                                                                   "render" else ""))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)  # the working folder is not a checkout: python -m puts it
    done = subprocess.run([sys.executable, "-X", "importtime", "-m", "seismo3d.cli", *args],  # first on sys.path
                          capture_output=True, text=True, env=env, cwd=tmp_path, timeout=60)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_seconds = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    imported = {line.split("|")[-1].strip() for line in done.stderr.splitlines() if line.startswith("import time:")}
    said = [line for line in done.stderr.splitlines() if line.strip() and not line.startswith("import time:")]
    assert done.returncode == 2 and len(said) == 1 and said[0].startswith("error: cannot "), done.stderr[-2000:]
    assert "typer" in imported and not {"numpy", "numba", "scipy", "pyvista", "segyio"} & imported
    assert cpu_seconds < 0.75


@pytest.mark.slow
@pytest.mark.parametrize("command", [pytest.param(c, id=c.name) for c in COMMANDS])
def test_no_command_prints_a_traceback(command, work, tmp_path):
    """In a real process (the interpreter prints uncaught errors): a refusal is one line on stderr, exit code 2, no
    traceback. Every refusal goes through the same wrapper (``seismo3d.cli``), and the tests above check each message
    in process; here every refusal of this file for the main command (faults), and for the others the output that is
    an input and the earlier results (a process costs 2-3 s: 45 of them were over a minute of the suite)."""
    import os
    import subprocess
    import sys

    earlier = _earlier_results(command, tmp_path / "out", work)
    cases = [work / command.inputs[0], earlier]
    if command.name == "faults":
        cases += ["/proc/nope", "/dev/null/x", work]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    before = _digest(work)
    for output in cases:
        args = command.args([str(work / n) for n in command.inputs], str(output))
        done = subprocess.run([sys.executable, "-m", "seismo3d.cli", *args], capture_output=True, text=True, env=env,
                              timeout=120)
        lines = [line for line in done.stderr.splitlines() if line.strip()]
        assert done.returncode == 2 and "Traceback" not in done.stderr, (output, done.stderr)
        assert len(lines) == 1 and lines[0].startswith("error: "), (output, done.stderr)
    assert _digest(work) == before


# --------------------------------------------------------------------------------------------------------------------
# the policy itself


def test_check_outputs_rules(tmp_path):
    cube = tmp_path / "cube.sgy"
    cube.write_bytes(b"x")
    (tmp_path / "old.txt").write_text("earlier")
    check_outputs([output_file(tmp_path / "new.txt"), None], [cube, None])
    check_outputs([output_file(tmp_path / "old.txt")], [cube], overwrite=True)
    check_outputs([output_folder(tmp_path / "a" / "b", ("r.csv",))], [cube])  # created later, with its parents
    for outputs, message in (
        ([output_file(tmp_path / "old.txt")], "exists; pass overwrite=True (--overwrite)"),
        ([output_file(tmp_path / "missing" / "x.txt")], "folder " + str(tmp_path / "missing") + " does not exist"),
        ([output_file(tmp_path)], "is a folder"),
        ([output_folder(cube, ())], "is the input cube.sgy itself"),
        ([output_folder(tmp_path / "old.txt", ())], "is a file"),
        ([output_store(tmp_path, "c.zarr")], "holds the input"),
    ):
        with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
            check_outputs(outputs, [cube])


@pytest.mark.slow  # 1.8 s in the fast lane, whose budget is 60 s
def test_the_files_a_command_reads_of_an_input_folder_are_inputs(map_folder, tmp_path):
    """plan reads mesh.ply of a map folder: it is never replaced, even with --overwrite; render writes a picture into
    a folder it reads, and replaces it with --overwrite."""
    folder = tmp_path / "map_run"
    shutil.copytree(map_folder, folder)
    before = _digest(folder)
    line = _refused(runner.invoke(app, ["plan", str(folder), "--start", "20,8", "--goal", "20,56", "-o",
                                        str(folder / "mesh.ply"), "--overwrite"]))
    assert "is the input mesh.ply itself" in line
    assert _digest(folder) == before
    for extra in ([], ["--overwrite"]):
        result = runner.invoke(app, ["render", str(folder), "-o", str(folder / "view.png"), "--size", "200x150",
                                     *extra])
        assert result.exit_code == 0, result.output
