"""seismo3d.jobs.lineaments: the files of `seismo3d lineaments`, on a generated DEM written as a GeoTIFF and through the
command on the real DEM."""

import csv

import numpy as np
import pytest

from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.data.terrain import synthetic_scarp_dem
from seismo3d.errors import InputError
from seismo3d.jobs.lineaments import run_lineaments_job
from seismo3d.terrain import Dem, evaluate_lineaments, write_dem
from seismo3d.terrain.georef import CoordinateReference

UTM = CoordinateReference("projected", 32614, "WGS 84 / UTM zone 14N", "metre", 1.0, "metre", 1.0)


@pytest.mark.slow
def test_outputs_in_the_rasters_crs(tmp_path):
    truth = synthetic_scarp_dem(seed=12)
    affine = np.array([[30.0, 0.0, 650000.0], [0.0, -30.0, 3620000.0], [0.0, 0.0, 1.0]])
    path = write_dem(tmp_path / "scarps.tif", Dem(truth.elevation, affine, UTM))
    result = run_lineaments_job(path, tmp_path / "out")
    assert evaluate_lineaments(result.lineaments, truth.scarps).n_found_visible >= 7
    with open(result.written["csv"], newline="") as fh:
        rows = list(csv.DictReader(fh))
    first = rows[0]
    x0, y0 = float(first["x0"]), float(first["y0"])
    # CRS coordinates of pixel centres: (row, col) -> (650000 + 30 col, 3620000 - 30 row) (Dem.affine)
    col, row = (x0 - 650000.0) / 30.0, (3620000.0 - y0) / 30.0
    assert col == pytest.approx(result.lineaments.cols0[0]) and row == pytest.approx(result.lineaments.rows0[0])
    assert float(first["length_m"]) == pytest.approx(result.lineaments.length_m[0], abs=0.05)
    for key in ("rose", "map"):
        assert result.written[key].read_bytes()[:4] == b"\x89PNG"


def test_output_folder_is_a_file(tmp_path):
    (tmp_path / "out").write_text("")
    with pytest.raises(InputError, match="is a file"):
        run_lineaments_job(tmp_path / "missing.tif", tmp_path / "out")


@pytest.mark.slow  # 1.2 s in the fast lane, whose budget is 60 s
def test_lineaments_command(dfw, tmp_path):
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["lineaments", str(dfw.path), "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "lineaments in dem_hydrosheds_dfw.tif" in result.stdout and "strongest strikes" in result.stdout
    for name in ("lineaments.csv", "rose.png", "lineaments.png"):
        assert (out / name).stat().st_size > 0
    with open(out / "lineaments.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and all(0 <= float(r["azimuth_deg"]) < 180 for r in rows)
