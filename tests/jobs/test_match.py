"""The match job (seismo3d.jobs.match) through ``seismo3d match``: a photo and its rotated copy, bad images."""

import numpy as np
import pytest
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.jobs.match import read_image, run_match_job

runner = CliRunner()


@pytest.mark.slow
def test_match_recovers_a_known_homography(tmp_path):
    """`seismo3d match` on a photo and its rotated copy: the printed homography is the true one."""
    import cv2
    from skimage import data

    image = data.camera()
    h, w = image.shape
    truth = np.vstack([cv2.getRotationMatrix2D((w / 2 - 0.5, h / 2 - 0.5), 30.0, 1.0), [0, 0, 1]])
    cv2.imwrite(str(tmp_path / "a.png"), image)
    cv2.imwrite(str(tmp_path / "b.png"), cv2.warpPerspective(image, truth, (w, h)))
    out = tmp_path / "m.csv"
    result = runner.invoke(app, ["match", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "-o", str(out),
                                 "--method", "sift"])
    assert result.exit_code == 0, result.output
    rows = np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2)
    assert open(out).readline().strip() == "x1,y1,x2,y2,score" and len(rows) > 50
    pred = cv2.perspectiveTransform(rows[:, None, :2].astype(np.float64), truth)[:, 0]
    assert np.median(np.linalg.norm(pred - rows[:, 2:4], axis=1)) < 1.0


@pytest.mark.parametrize("make,message", [
    (lambda p: None, "no such file"),
    (lambda p: p.write_text("not an image"), "not an image"),
])
def test_match_errors(tmp_path, make, message):
    bad = tmp_path / "bad.png"
    make(bad)
    result = runner.invoke(app, ["match", str(bad), str(bad), "-o", str(tmp_path / "m.csv")])
    assert result.exit_code == 2 and message in result.output


@pytest.mark.slow
def test_run_match_job_writes_the_verified_matches(tmp_path):
    import cv2
    from skimage import data

    image = data.astronaut()  # colour: read back as RGB
    cv2.imwrite(str(tmp_path / "a.png"), image[..., ::-1])
    np.testing.assert_array_equal(read_image(tmp_path / "a.png"), image)
    job = run_match_job(tmp_path / "a.png", tmp_path / "a.png", tmp_path / "m.csv", method="orb")
    rows = np.loadtxt(tmp_path / "m.csv", delimiter=",", skiprows=1, ndmin=2)
    assert job.n_written == len(rows) > 50
    np.testing.assert_allclose(rows[:, :2], rows[:, 2:4], atol=1e-6)  # an image onto itself
    # beside the CSV: the matches drawn between the two images, and the homography (the identity here)
    import json

    from matplotlib.image import imread

    assert job.picture == tmp_path / "m.png" and job.homography_file == tmp_path / "m.homography.json"
    picture = imread(job.picture)
    assert picture.shape[1] > 2 * image.shape[1] * 0.9  # the two images side by side, at about their size
    saved = json.loads(job.homography_file.read_text())
    np.testing.assert_allclose(saved["homography"], np.eye(3), atol=1e-6)
    assert saved["n_verified"] == job.n_written
