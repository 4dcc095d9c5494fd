"""The register job (seismo3d.jobs.register): `seismo3d register MOVING.sgy FIXED.sgy -o transform.json` (source onto
target, as for point clouds), mixed inputs, models; point clouds through run_register_job."""

import json

import numpy as np
import pytest
import segyio
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.data import resampled_pair, synthetic_cube
from seismo3d.seismic import registration_errors


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    big = synthetic_cube((96, 96, 104), n_faults=2, seed=3).cube
    # a rigid pair registered with --model rigid: the command's wiring (tests/seismic/volumes/ and
    # benchmarks/volumes.py measure the scaled models)
    fixed, moving, truth = resampled_pair(big, (56, 56, 72), angle_deg=12.0, offset=(2, -1, 1))
    folder = tmp_path_factory.mktemp("volumes")
    paths = folder / "fixed.sgy", folder / "moving.sgy"
    segyio.tools.from_array(str(paths[0]), fixed, dt=4000)
    segyio.tools.from_array(str(paths[1]), moving, dt=4000)
    return paths, truth, moving.shape


@pytest.mark.slow  # 1.9 s in the fast lane, whose budget is 60 s
def test_register_segy_cubes_writes_both_transforms(pair, tmp_path):
    (fixed, moving), truth, moving_shape = pair
    before = [p.read_bytes() for p in (fixed, moving)]
    out = tmp_path / "transform.json"
    res = CliRunner().invoke(app, ["register", str(moving), str(fixed), "-o", str(out), "--model", "rigid"])
    assert res.exit_code == 0, res.output
    assert "map rotation" in res.output and "seconds: prepare" in res.output
    payload = json.loads(out.read_text())
    t = np.array(payload["transform_index"])
    err = registration_errors(t, truth, moving_shape)
    assert err.rotation_deg <= 0.5 and err.max_scale_pct <= 1.0 and err.corner_error <= 0.5
    assert payload["model"] == "rigid" and payload["converged"] is True and payload["reason"] == ""
    assert payload["moving"] == str(moving) and payload["fixed"] == str(fixed)
    assert payload["index_axes"] == ["inline", "crossline", "sample"]
    assert set(payload["stage_seconds"]) == {"prepare", "search", "coarse", "fine", "check"}
    assert payload["check"]["disagreement"] <= 0.5
    # no CDP coordinates in these files: bins of 1, sample interval 4 ms from the binary header
    assert payload["fixed_spacing"] == [1.0, 1.0, 4.0]
    np.testing.assert_allclose(np.array(payload["transform_physical"]),
                               np.diag([1, 1, 4.0, 1]) @ t @ np.diag([1, 1, 1 / 4.0, 1]), atol=1e-9)
    assert abs(payload["rotation_deg"] - 12.0) <= 0.5 and 0 < payload["overlap"] <= 1
    assert [p.read_bytes() for p in (fixed, moving)] == before  # inputs untouched


@pytest.mark.slow
def test_register_f3_onto_its_shifted_copy_and_unrelated_cubes(data_dir, tmp_path):
    from seismo3d.seismic import read_segy

    f3, _ = read_segy(f"{data_dir}/seismic/f3_crop.sgy")
    paths = {name: tmp_path / f"{name}.sgy" for name in ("f3", "copy", "other")}
    segyio.tools.from_array(str(paths["f3"]), f3, dt=4000)
    segyio.tools.from_array(str(paths["copy"]), np.ascontiguousarray(f3[4:, 4:, 5:]), dt=4000)
    segyio.tools.from_array(str(paths["other"]), synthetic_cube((24, 24, 80), n_faults=1, seed=4).cube, dt=4000)
    out = tmp_path / "t.json"
    res = CliRunner().invoke(app, ["register", str(paths["f3"]), str(paths["copy"]), "-o", str(out)])
    assert res.exit_code == 0, res.output
    payload = json.loads(out.read_text())
    np.testing.assert_allclose(np.array(payload["transform_index"])[:3, 3], [-4, -4, -5], atol=0.1)
    assert payload["model"] == "affine"
    # unrelated data: written, not converged, the reason in one line, exit 1
    out = tmp_path / "unrelated.json"
    res = CliRunner().invoke(app, ["register", str(paths["other"]), str(paths["f3"]), "-o", str(out)])
    assert res.exit_code == 1
    payload = json.loads(out.read_text())
    assert payload["converged"] is False and payload["reason"]
    assert f"did not converge ({payload['reason']})" in res.output


@pytest.mark.slow
def test_register_mixed_inputs_and_bad_model_are_clear_errors(pair, tmp_path):
    (fixed, moving), _, _ = pair
    cloud = tmp_path / "cloud.xyz"
    np.savetxt(cloud, np.random.default_rng(0).normal(size=(50, 3)))
    res = CliRunner().invoke(app, ["register", str(cloud), str(fixed), "-o", str(tmp_path / "t.json")])
    assert res.exit_code == 2 and "not one of each" in res.output
    for model in ("similarity", "axis_scaled"):  # a scale on one volume's axes cannot express two surveys' bins
        res = CliRunner().invoke(app, ["register", str(moving), str(fixed), "-o", str(tmp_path / "t.json"),
                                       "--model", model])
        assert res.exit_code == 2 and "not available for SEG-Y" in res.output and "affine" in res.output
    assert not (tmp_path / "t.json").exists()


def test_point_clouds_through_the_job(tmp_path):
    from scipy.spatial.transform import Rotation

    from seismo3d.jobs.register import run_register_job

    u, v = np.meshgrid(np.linspace(0, 3, 40), np.linspace(0, 2, 30))
    src = np.column_stack([u.ravel(), v.ravel(), (0.3 * np.sin(2 * u) * np.cos(3 * v) + 0.1 * u * v).ravel()])
    truth = np.eye(4)
    truth[:3, :3] = Rotation.from_euler("xyz", [2, -3, 4], degrees=True).as_matrix()
    truth[:3, 3] = [0.04, -0.02, 0.03]
    np.save(tmp_path / "src.npy", src)
    np.save(tmp_path / "dst.npy", src @ truth[:3, :3].T + truth[:3, 3])
    (tmp_path / "init.json").write_text(json.dumps({"transform": np.eye(4).tolist()}))
    job = run_register_job(tmp_path / "src.npy", tmp_path / "dst.npy", tmp_path / "T.json", init=tmp_path / "init.json",
                           max_distance=[0.3, 0.1, 0.03])
    assert job.kind == "point_clouds" and job.converged
    np.testing.assert_allclose(np.array(json.loads((tmp_path / "T.json").read_text())["transform"]), truth,
                               atol=1e-4)


def test_points_with_nan_are_named_by_file_and_row(tmp_path):
    """A NaN coordinate: the message names SOURCE's file and the rows (from 1), and suggests no NumPy expression."""
    points = np.random.default_rng(0).random((50, 3))
    points[[3, 17]] = np.nan
    np.save(tmp_path / "holes.npy", points)
    np.save(tmp_path / "dst.npy", np.random.default_rng(1).random((50, 3)))
    res = CliRunner().invoke(app, ["register", str(tmp_path / "holes.npy"), str(tmp_path / "dst.npy"), "-o",
                                   str(tmp_path / "T.json")])
    assert res.exit_code == 2
    assert res.stderr == ("error: SOURCE holes.npy has 2 of 50 rows with NaN or infinite coordinates (rows 4, 18, "
                          "counting from 1); remove or fix those rows in the file and run again\n")
    assert "np." not in res.stderr and not (tmp_path / "T.json").exists()
