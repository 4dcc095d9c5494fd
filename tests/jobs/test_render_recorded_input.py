"""`seismo3d render` of a faults folder or horizon file without --seismic draws the input its run recorded in run.json
(seismo3d.jobs.runinfo), read with the run's SEG-Y flags, while it is the file the run read; a changed or missing
input is one warning naming --seismic and a picture without seismic."""

import warnings

import numpy as np
import pytest
import segyio
from matplotlib.image import imread
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import Seismo3dWarning
from seismo3d.jobs.faults import run_faults_job
from seismo3d.jobs.render import run_render_job
from seismo3d.jobs.runinfo import write_run_json

runner = CliRunner()
SIZE = (400, 300)


def _write_line(path, section, *, iline=189, xline=193):
    """A 2D line (inlines 1000.., crossline 1155, 4 ms) with its line numbers at trace header bytes ``iline`` and
    ``xline``."""
    n, ns = section.shape
    spec = segyio.spec()
    spec.format, spec.sorting = 5, segyio.TraceSortingFormat.INLINE_SORTING
    spec.samples, spec.ilines, spec.xlines = 4.0 * np.arange(ns), np.arange(1000, 1000 + n), [1155]
    with segyio.create(str(path), spec) as f:
        for i in range(n):
            f.header[i] = {iline: 1000 + i, xline: 1155}
            f.trace[i] = section[i].astype(np.float32)
        f.bin.update(hdt=4000, hns=ns)
    return path


def _seismic_pixels(path) -> float:
    """In the middle of the section's panel (rows 45-85 %, columns 20-70 % of the picture), the fraction of pixels
    whose grey level changes by more than 25 from one row to the next: the reflectors of a seismic section (a line
    is drawn as a grey section), little else (fault lines, a horizon, the fault likelihood drawn without seismic)."""
    grey = (imread(path)[..., :3] * 255).round().mean(axis=-1)
    h, w = grey.shape
    middle = grey[int(0.45 * h):int(0.85 * h), int(0.2 * w):int(0.7 * w)]
    return float((np.abs(np.diff(middle, axis=0)) > 25).mean())


@pytest.fixture(scope="module")
def faults_run(tmp_path_factory):
    """A faults run on a small generated SEG-Y line (about 3 s): its input and output folder."""
    work = tmp_path_factory.mktemp("recorded")
    line = _write_line(work / "line.sgy", synthetic_cube((160, 96), n_faults=2, seed=3).cube)
    run_faults_job(line, work / "faults", progress=False)
    return line, work / "faults"


@pytest.mark.slow
def test_the_runs_input_is_drawn_by_default(faults_run, tmp_path):
    line, folder = faults_run
    default = run_render_job(folder, tmp_path / "default.png", window_size=SIZE)
    given = run_render_job(folder, tmp_path / "given.png", seismic=line, window_size=SIZE)
    assert default.seismic == line and given.seismic == line
    # the same picture as with --seismic: every pixel
    assert np.array_equal(imread(tmp_path / "default.png"), imread(tmp_path / "given.png"))
    # and seismic in it: measured 0.34; 0.06 without (below: the fault lines over the likelihood)
    assert _seismic_pixels(tmp_path / "default.png") > 0.2


@pytest.mark.slow
@pytest.mark.parametrize("change", ["changed", "gone"])
def test_a_changed_or_missing_input_is_not_drawn_and_said_once(faults_run, tmp_path, change):
    line, folder = faults_run
    copy = tmp_path / "line.sgy"
    copy.write_bytes(line.read_bytes())
    moved = tmp_path / "faults"
    moved.mkdir()
    for f in folder.iterdir():
        if f.is_file() and f.name != "run.json":
            (moved / f.name).write_bytes(f.read_bytes())
    (moved / "run.json").write_text((folder / "run.json").read_text().replace(str(line), str(copy)))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the intact copy: drawn, no warning
        assert run_render_job(moved, tmp_path / "intact.png", window_size=SIZE).seismic == copy
    if change == "changed":
        data = bytearray(copy.read_bytes())
        data[5000] ^= 0xFF  # one byte of a trace: same size, another sha256
        copy.write_bytes(bytes(data))
    else:
        copy.unlink()
    res = runner.invoke(app, ["render", str(moved), "-o", str(tmp_path / "no.png"), "--size", "400x300"])
    assert res.exit_code == 0, res.output
    lines = [t for t in res.stderr.splitlines() if t.strip()]
    reason = "has changed (its sha256 differs)" if change == "changed" else "no longer exists"
    assert lines == [f"warning: the run's input {copy} {reason}: drawn without seismic; pass --seismic CUBE.sgy to "
                     "draw one under it"]
    assert _seismic_pixels(tmp_path / "no.png") < 0.12  # measured 0.06 (the faults over the likelihood); 0.34 with seismic
    with pytest.warns(Seismo3dWarning, match="pass seismic=CUBE.sgy"):
        assert run_render_job(moved, tmp_path / "no2.png", window_size=SIZE).seismic is None


@pytest.mark.slow
def test_a_horizon_is_drawn_over_its_input_read_with_the_runs_flags(tmp_path):
    """A line whose numbers are at bytes 9 and 21: the run's --iline 9 --xline 21 (from its run.json) read it; given
    with --seismic and render's default bytes 189 / 193, it is a trace list the horizon's rows do not fall on."""
    line = _write_line(tmp_path / "line.sgy", synthetic_cube((160, 96), n_faults=0, seed=3).cube, iline=9, xline=21)
    horizon = tmp_path / "h.txt"
    np.savetxt(horizon, [(1000 + i, 1155, 120.0 + 0.2 * i) for i in range(160)], fmt="%g")
    write_run_json(tmp_path / "h.txt.run.json", command="horizon", started=0.0, seconds=1.0, stage_seconds={},
                   options=dict(input_path=line, iline=9, xline=21, ignore_geometry=False, endian=None,
                                sample_unit=None), inputs={"input": line}, outputs={"horizon": horizon})
    job = run_render_job(horizon, tmp_path / "h.png", window_size=SIZE)
    assert job.seismic == line and "inlines 1000-1159" in job.caption
    assert _seismic_pixels(tmp_path / "h.png") > 0.2  # measured 0.33
    res = runner.invoke(app, ["render", str(horizon), "--seismic", str(line), "-o", str(tmp_path / "x.png")])
    assert res.exit_code == 2 and "bytes 189 / 193" in res.stderr and "no row of h.txt" in res.stderr, res.output
    res = runner.invoke(app, ["render", str(horizon), "--seismic", str(line), "--iline", "9", "--xline", "21", "-o",
                              str(tmp_path / "x.png"), "--size", "400x300"])
    assert res.exit_code == 0, res.output
    assert np.array_equal(imread(tmp_path / "h.png"), imread(tmp_path / "x.png"))
