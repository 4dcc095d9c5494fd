"""`seismo3d register FIXED.sgy MOVING.sgy -o transform.json`: sub-volume registration from the command line."""

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
    fixed, moving, truth = resampled_pair(big, (56, 56, 72), scales=(1.0, 1.25, 0.8), angle_deg=12.0,
                                          offset=(2, -1, 1))
    folder = tmp_path_factory.mktemp("volumes")
    paths = folder / "fixed.sgy", folder / "moving.sgy"
    segyio.tools.from_array(str(paths[0]), fixed, dt=4000)
    segyio.tools.from_array(str(paths[1]), moving, dt=4000)
    return paths, truth, moving.shape


def test_register_segy_cubes_writes_both_transforms(pair, tmp_path):
    (fixed, moving), truth, moving_shape = pair
    before = [p.read_bytes() for p in (fixed, moving)]
    out = tmp_path / "transform.json"
    res = CliRunner().invoke(app, ["register", str(fixed), str(moving), "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "map rotation" in res.output
    payload = json.loads(out.read_text())
    t = np.array(payload["transform_index"])
    err = registration_errors(t, truth, moving_shape)
    assert err["rotation_deg"] <= 0.5 and err["max_scale_pct"] <= 1.0 and err["centre_error"] <= 0.5
    assert payload["model"] == "axis_scaled"
    assert payload["index_axes"] == ["inline", "crossline", "sample"]
    # no CDP coordinates in these files: bins of 1, sample interval 4 ms from the binary header
    assert payload["fixed_spacing"] == [1.0, 1.0, 4.0]
    np.testing.assert_allclose(np.array(payload["transform_physical"]),
                               np.diag([1, 1, 4.0, 1]) @ t @ np.diag([1, 1, 1 / 4.0, 1]), atol=1e-9)
    assert 0 < payload["fitness"] <= 1 and payload["inlier_rmse"] >= 0
    assert [p.read_bytes() for p in (fixed, moving)] == before  # inputs untouched


def test_register_mixed_inputs_and_bad_model_are_clear_errors(pair, tmp_path):
    (fixed, moving), _, _ = pair
    cloud = tmp_path / "cloud.xyz"
    np.savetxt(cloud, np.random.default_rng(0).normal(size=(50, 3)))
    res = CliRunner().invoke(app, ["register", str(fixed), str(cloud), "-o", str(tmp_path / "t.json")])
    assert res.exit_code == 2 and "not one of each" in res.output
    res = CliRunner().invoke(app, ["register", str(fixed), str(moving), "-o", str(tmp_path / "t.json"),
                                   "--model", "similarity"])
    assert res.exit_code == 2 and "not available for SEG-Y" in res.output
    assert not (tmp_path / "t.json").exists()
