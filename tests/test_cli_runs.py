"""``run.json`` beside the outputs of every command (seismo3d.jobs.runinfo), through the command line on small
generated inputs: the version, the command line and arguments, every option, each input's sha256, the start time,
the stage times and the outputs; the output policy applies to it. (``seismo3d map`` is checked in
tests/jobs/test_map.py, on the real frames it needs.)"""

import csv
import json
import time

import cv2
import numpy as np
import pytest
import segyio
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.terrain import Dem, write_dem
from seismo3d.terrain.georef import CoordinateReference

runner = CliRunner()
METRES = CoordinateReference("projected", None, "", "metre", 1.0, "metre", 1.0)


def _invoke(args):
    since = time.time()
    result = runner.invoke(app, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    return since


@pytest.fixture(scope="module")
def cube_file(tmp_path_factory):
    """A 16 x 24 x 64 synthetic SEG-Y cube without faults (4 ms), and its synthetic truth."""
    path = tmp_path_factory.mktemp("cube") / "cube.sgy"
    syn = synthetic_cube((16, 24, 64), n_faults=0, seed=4, noise=0.05)
    segyio.tools.from_array3D(str(path), syn.cube, format=5, dt=4000)
    return path, syn


@pytest.fixture(scope="module")
def wall_dem(tmp_path_factory):
    """A 40 x 40 DEM of 10 m cells with a steep wall across it, open at its northern end."""
    z = np.zeros((40, 40))
    z[5:, 18:23] = 50.0
    affine = np.array([[10.0, 0.0, 1000.0], [0.0, -10.0, 5000.0], [0, 0, 1.0]])
    return write_dem(tmp_path_factory.mktemp("dem") / "wall.tif", Dem(z, affine, METRES))


def test_register(tmp_path, check_run_json):
    u, v = np.meshgrid(np.linspace(0, 3, 30), np.linspace(0, 2, 20))
    src = np.column_stack([u.ravel(), v.ravel(), (0.3 * np.sin(2 * u) * np.cos(3 * v)).ravel()])
    R = Rotation.from_euler("xyz", [2, -1, 3], degrees=True).as_matrix()
    np.save(tmp_path / "src.npy", src)
    np.savetxt(tmp_path / "dst.xyz", src @ R.T + [0.02, -0.01, 0.0])
    out = tmp_path / "t.json"
    since = _invoke(["register", tmp_path / "src.npy", tmp_path / "dst.xyz", "-o", out, "--max-distance", "0.2"])
    record = check_run_json(tmp_path / "t.json.run.json", "register",
                            {"source": tmp_path / "src.npy", "target": tmp_path / "dst.xyz"}, ["transform"],
                            ["method", "model", "init", "max_distance", "features", "alpha", "overwrite"], since)
    assert record["options"]["max_distance"] == [0.2]
    assert record["cli"]["arguments"]["max_distance"] == [0.2]
    assert set(record["stage_seconds"]) == {"read", "register", "write"}
    assert record["results"]["converged"] is True and record["results"]["kind"] == "point_clouds"


# 1.3 s: the one run of the main command the fast lane keeps (its budget is 60 s)
def test_faults(tmp_path, check_run_json):
    section = synthetic_cube((16, 96, 96), n_faults=1, seed=3).cube[0]  # one inline: a 2D section
    np.save(tmp_path / "line.npy", section)
    out = tmp_path / "out"
    since = _invoke(["faults", tmp_path / "line.npy", "-o", out, "--sensitivity", "0.6"])
    record = check_run_json(out / "run.json", "faults", {"input": tmp_path / "line.npy"},
                            ["likelihood", "summary", "figure"],
                            ["sensitivity", "likelihood", "memory_limit", "iline", "n_samples"], since)
    assert record["options"]["sensitivity"] == 0.6
    assert record["options"]["tracing_options"]["sensitivity"] == 0.6  # the FaultTracingOptions dataclass
    with open(out / "fault_summary.csv", newline="") as fh:
        assert record["results"]["n_faults"] == len(list(csv.DictReader(fh)))


def test_convert(cube_file, tmp_path, check_run_json):
    path, _ = cube_file
    since = _invoke(["convert", path, tmp_path / "c.zarr", "--chunk-mb", "1"])
    record = check_run_json(tmp_path / "c.zarr.run.json", "convert", {"input": path}, ["store"],
                            ["chunk_mb", "iline", "xline", "endian", "sample_unit"], since)
    assert record["results"]["shape"] == [16, 24, 64] and set(record["stage_seconds"]) == {"open", "write"}


@pytest.mark.slow
def test_match(tmp_path, check_run_json):
    rng = np.random.default_rng(5)
    image = cv2.GaussianBlur((rng.random((200, 240)) * 255).astype(np.uint8), (0, 0), 2.0)
    image = cv2.normalize(image, None, 0, 255, cv2.NORM_MINMAX)
    cv2.imwrite(str(tmp_path / "a.png"), image)
    cv2.imwrite(str(tmp_path / "b.png"), np.roll(image, (6, 9), axis=(0, 1)))
    since = _invoke(["match", tmp_path / "a.png", tmp_path / "b.png", "-o", tmp_path / "m.csv", "--method", "orb"])
    record = check_run_json(tmp_path / "m.csv.run.json", "match",
                            {"image1": tmp_path / "a.png", "image2": tmp_path / "b.png"}, ["matches"],
                            ["method", "ratio", "threshold"], since)
    assert record["options"]["method"] == "orb"
    assert record["results"]["n_verified"] == len(np.loadtxt(tmp_path / "m.csv", delimiter=",", skiprows=1, ndmin=2))


@pytest.mark.slow  # 1.4 s in the fast lane, whose budget is 60 s
def test_lineaments(tmp_path, check_run_json):
    from seismo3d.data.terrain import synthetic_scarp_dem

    truth = synthetic_scarp_dem(seed=12)
    affine = np.array([[30.0, 0.0, 650000.0], [0.0, -30.0, 3620000.0], [0.0, 0.0, 1.0]])
    dem = write_dem(tmp_path / "scarps.tif", Dem(truth.elevation, affine, METRES))
    out = tmp_path / "out"
    since = _invoke(["lineaments", dem, "-o", out])
    record = check_run_json(out / "run.json", "lineaments", {"dem": dem}, ["csv", "rose", "map"], ["options"],
                            since)
    assert record["results"]["n_lineaments"] == len(np.loadtxt(out / "lineaments.csv", delimiter=",", skiprows=1,
                                                               ndmin=2))


def test_plan(wall_dem, tmp_path, check_run_json):
    out = tmp_path / "p.csv"
    since = _invoke(["plan", wall_dem, "--start", "35,5", "--goal", "35,35", "-o", out, "--max-slope", "10"])
    record = check_run_json(tmp_path / "p.csv.run.json", "plan", {"grid": wall_dem}, ["path"],
                            ["max_slope_deg", "corner_cutting", "start", "goal"], since)
    assert record["options"]["max_slope_deg"] == 10.0 and record["options"]["start"] == [35, 5]
    assert record["results"]["cells"] == len(np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2))


def test_plan_refuses_an_earlier_record_without_overwrite(wall_dem, tmp_path):
    """The record follows the output policy: an earlier one is replaced only with --overwrite."""
    (tmp_path / "p.csv.run.json").write_text("{}")
    args = ["plan", str(wall_dem), "--start", "35,5", "--goal", "35,35", "-o", str(tmp_path / "p.csv")]
    refused = runner.invoke(app, args)
    assert refused.exit_code == 2 and "p.csv.run.json exists" in refused.stderr and "--overwrite" in refused.stderr
    assert not (tmp_path / "p.csv").exists()
    assert runner.invoke(app, [*args, "--overwrite"]).exit_code == 0
    assert json.loads((tmp_path / "p.csv.run.json").read_text())["command"] == "plan"


def test_horizon(cube_file, tmp_path, check_run_json):
    path, syn = cube_file
    k = 1
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    seed = f"8,12,{4.0 * syn.horizons[k][7, 11]:.2f}"  # inline / crossline numbers from 1
    out = tmp_path / "h.txt"
    since = _invoke(["horizon", path, "--seed", seed, "-o", out, "--polarity", pol, "--no-faults"])
    record = check_run_json(tmp_path / "h.txt.run.json", "horizon", {"input": path}, ["horizon"],
                            ["seeds", "polarity", "faults", "fill", "surface"], since)
    assert record["options"]["faults"] is False and record["options"]["polarity"] == pol
    assert set(record["stage_seconds"]) == {"read", "track", "write"}
    assert record["results"]["n_rows"] == len(np.loadtxt(out, comments="#", ndmin=2))


@pytest.mark.slow
def test_render(wall_dem, tmp_path, check_run_json):
    since = _invoke(["render", wall_dem, "-o", tmp_path / "r.png", "--size", "200x150"])
    record = check_run_json(tmp_path / "r.png.run.json", "render", {"input": wall_dem}, ["picture"],
                            ["window_size", "vertical_exaggeration", "color_by"], since)
    assert record["options"]["window_size"] == [200, 150] and record["results"]["kind"] == "dem"


def test_large_inputs_are_identified_by_size_and_time(tmp_path, monkeypatch):
    """Above the hashing limit an input is not read through: size and modification time, and the record says so."""
    from seismo3d.jobs import runinfo

    path = tmp_path / "big.bin"
    path.write_bytes(b"x" * 2048)
    monkeypatch.setattr(runinfo, "HASH_LIMIT", 1024)
    entry = runinfo.input_identity(path)
    assert entry["identity"] == "size+mtime" and entry["sha256"] is None and entry["bytes"] == 2048
    monkeypatch.setattr(runinfo, "HASH_LIMIT", 4096)
    assert runinfo.input_identity(path)["identity"] == "sha256"


def test_inputs_identified_early_are_recorded_as_identified(tmp_path):
    """RunRecord.identify_early hashes on a background thread from the start of the job: the record holds the
    identity of the file as it was then (here: before it changed), the same entry input_identity gives."""
    import hashlib

    from seismo3d.jobs import runinfo

    path = tmp_path / "input.bin"
    path.write_bytes(b"abc" * 1000)
    before = runinfo.input_identity(path)
    record = runinfo.RunRecord("convert", {"input": path})
    record.identify_early(path, None)
    record._identities[str(path)].result()  # the hash done, then the file changes
    path.write_bytes(b"changed")
    written = json.loads(record.write(tmp_path / "r.run.json", inputs={"input": path}, outputs={}).read_text())
    assert written["inputs"]["input"] == before
    assert before["sha256"] == hashlib.sha256(b"abc" * 1000).hexdigest()
