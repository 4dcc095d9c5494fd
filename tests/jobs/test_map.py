"""The map job and ``seismo3d map``: outputs, bad frames skipped with warnings, Ctrl-C keeps what was done."""

import json
import shutil
import time

import numpy as np
import pytest
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.errors import FrameSkippedWarning
from seismo3d.jobs.map import run_map_job
from seismo3d.mapping import read_tum_trajectory

N_FRAMES = 10


@pytest.fixture(scope="module")
def sequence(tmp_path_factory, data_dir):
    """Ten real 7-Scenes frames copied into a TUM-style folder, with a missing depth image (frame 4), an 8-bit depth
    image (frame 6) and a 2-second gap in the timestamps before frame 8."""
    from seismo3d.data import fetch

    src = fetch("rgbd/7scenes_redkitchen_0000_0495/associations.txt").parent
    root = tmp_path_factory.mktemp("seq") / "kitchen"
    (root / "rgb").mkdir(parents=True)
    (root / "depth").mkdir()
    shutil.copy(src / "camera-intrinsics.txt", root)
    rows, gt = [], []
    gt_lines = {line.split()[0]: line for line in (src / "groundtruth.txt").read_text().splitlines()
                if line and not line.startswith("#")}
    for i in range(N_FRAMES):
        stem = f"frame-{5 * i:06d}"
        t_src = f"{5 * i / 30.0:.6f}"
        t = 5 * i / 30.0 + (2.0 if i >= 8 else 0.0)
        shutil.copy(src / f"rgb/{stem}.color.jpg", root / "rgb")
        if i != 4:
            shutil.copy(src / f"depth/{stem}.depth.png", root / "depth")
        rows.append(f"{t:.6f} rgb/{stem}.color.jpg {t:.6f} depth/{stem}.depth.png")
        gt.append(f"{t:.6f} " + " ".join(gt_lines[t_src].split()[1:]))
    import cv2

    cv2.imwrite(str(root / "depth/frame-000030.depth.png"), np.full((480, 640), 100, np.uint8))
    (root / "associations.txt").write_text("\n".join(rows) + "\n")
    (root / "groundtruth.txt").write_text("\n".join(gt) + "\n")
    return root


@pytest.mark.slow
def test_job_writes_every_output_and_skips_bad_frames(sequence, tmp_path):
    with pytest.warns(UserWarning) as record:
        written = run_map_job(sequence, tmp_path / "out", progress=False).written
    skipped = [w for w in record if issubclass(w.category, FrameSkippedWarning)]
    assert len(skipped) == 2
    assert any("gap" in str(w.message) for w in record)
    t, poses = read_tum_trajectory(written["trajectory"])
    assert len(t) == N_FRAMES  # one line per input frame: the two skipped ones carry the motion prediction
    assert np.all(np.diff(t) > 0)
    payload = json.loads(written["keyframes"].read_text())
    assert [s["index"] for s in payload["skipped_frames"]] == [4, 6]
    assert "missing" in payload["skipped_frames"][0]["reason"] and "16-bit" in payload["skipped_frames"][1]["reason"]
    assert payload["summary"]["frames_tracked"] == N_FRAMES - 2 and len(payload["keyframes"]) >= 1
    assert payload["evaluation"]["ate_rmse_m"] < 0.03
    header = written["mesh"].read_bytes()[:400].decode("ascii", "ignore")
    assert header.startswith("ply") and int(header.split("element vertex ")[1].split()[0]) > 10000
    from matplotlib.image import imread

    image = imread(written["map"])
    assert image.shape[:2] == (960, 1280) and image[..., :3].std() > 0.05  # something was drawn


@pytest.mark.slow
def test_interrupt_keeps_the_frames_done(sequence, tmp_path, monkeypatch):
    from seismo3d.mapping import RGBDMapper

    original = RGBDMapper.process
    calls = {"n": 0}

    def interrupted(self, frame, *, index=None):
        calls["n"] += 1
        if calls["n"] == 4:
            raise KeyboardInterrupt
        return original(self, frame, index=index)

    monkeypatch.setattr(RGBDMapper, "process", interrupted)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_map_job(sequence, out, progress=False, render=False)
    t, _ = read_tum_trajectory(out / "trajectory.txt")
    assert len(t) == 3
    payload = json.loads((out / "keyframes.json").read_text())
    assert payload["summary"]["interrupted"] is True and payload["summary"]["frames_processed"] == 3
    assert (out / "mesh.ply").stat().st_size > 1000
    assert not list(out.glob(".*.tmp"))  # no half-written file left behind


@pytest.mark.slow
def test_cli(sequence, tmp_path, check_run_json):
    runner = CliRunner()
    out = tmp_path / "cli"
    since = time.time()
    result = runner.invoke(app, ["map", str(sequence), "-o", str(out), "--max-frames", "3", "--no-render"])
    assert result.exit_code == 0, result.output
    record = check_run_json(out / "run.json", "map", {"sequence": sequence}, ["trajectory", "keyframes", "mesh"],
                            ["max_frames", "options", "render", "overwrite"], since)
    assert record["options"]["max_frames"] == 3 and record["options"]["options"]["tsdf"]["voxel_size"] == 0.01
    assert record["results"]["frames_processed"] == 3 and set(record["stage_seconds"]) == {"map", "write"}
    assert "3 of the first 3 frames tracked (--max-frames 3; the sequence has 10)" in result.output
    assert "ATE" in result.output
    assert (out / "trajectory.txt").is_file() and not (out / "map.png").exists()
    bad = runner.invoke(app, ["map", str(tmp_path / "absent"), "-o", str(tmp_path / "new")])
    assert bad.exit_code == 2 and "does not exist" in bad.output
    same = runner.invoke(app, ["map", str(sequence), "-o", str(sequence)])
    assert same.exit_code == 2 and "is the input" in same.output


def test_mesh_ply_is_written_through_vtk_and_read_back(tmp_path):
    """mesh.ply (binary little-endian, float32 positions and normals, faces) reads back the same through pyvista
    (render) and seismo3d's point reader (plan); an empty map still writes a valid file."""
    import pyvista as pv

    from seismo3d.data.pointclouds import read_points
    from seismo3d.jobs.map import write_ply
    from seismo3d.mapping.tsdf import TriangleMesh

    rng = np.random.default_rng(0)
    vertices = rng.random((6, 3))
    normals = rng.standard_normal((6, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    faces = np.array([[0, 1, 2], [2, 3, 4], [3, 4, 5]])
    write_ply(tmp_path / "mesh.ply", TriangleMesh(vertices, faces, normals))
    header = (tmp_path / "mesh.ply").read_bytes().split(b"end_header")[0].decode("ascii")
    assert "format binary_little_endian 1.0" in header and "element vertex 6" in header
    assert "property float nx" in header and "element face 3" in header
    mesh = pv.read(tmp_path / "mesh.ply")
    np.testing.assert_allclose(mesh.points, vertices.astype(np.float32), rtol=0, atol=0)  # float32, as before
    np.testing.assert_array_equal(mesh.regular_faces, faces)
    np.testing.assert_allclose(mesh.point_data["Normals"], normals.astype(np.float32), rtol=0, atol=0)
    np.testing.assert_array_equal(read_points(tmp_path / "mesh.ply"), vertices.astype(np.float32))
    write_ply(tmp_path / "empty.ply", TriangleMesh(np.zeros((0, 3)), np.zeros((0, 3), np.int64), np.zeros((0, 3))))
    assert pv.read(tmp_path / "empty.ply").n_points == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["empty.ply", "mesh.ply"]  # no temporary file left
