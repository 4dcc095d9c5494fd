"""The horizon job (seismo3d.jobs.horizon) through `seismo3d horizon`: a SEG-Y cube in, 'inline xline time' rows
out; seeds in line numbers and ms."""

import numpy as np
import pytest
import segyio
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.data.synthetic import synthetic_cube

runner = CliRunner()


def _write_cube(path, cube, dt_ms=4.0):
    spec = segyio.spec()
    spec.format, spec.sorting = 5, segyio.TraceSortingFormat.INLINE_SORTING
    spec.ilines = np.arange(100, 100 + cube.shape[0])
    spec.xlines = np.arange(500, 500 + 2 * cube.shape[1], 2)
    spec.samples = dt_ms * np.arange(cube.shape[2])
    with segyio.create(str(path), spec) as f:
        tr = 0
        for i, il in enumerate(spec.ilines):
            for j, xl in enumerate(spec.xlines):
                f.header[tr] = {segyio.su.iline: int(il), segyio.su.xline: int(xl), segyio.su.dt: int(dt_ms * 1000)}
                f.trace[tr] = cube[i, j].astype(np.float32)
                tr += 1
        f.bin.update({segyio.BinField.Samples: cube.shape[2], segyio.BinField.Interval: int(dt_ms * 1000)})
    return spec


def test_horizon_command_tracks_the_true_horizon(tmp_path):
    syn = synthetic_cube((16, 24, 64), n_faults=0, seed=4, noise=0.05)
    spec = _write_cube(tmp_path / "cube.sgy", syn.cube)
    k = 1
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    seed = f"{spec.ilines[8]},{spec.xlines[12]},{4.0 * ref[8, 12]:.2f}"
    out = tmp_path / "out" / "h.txt"
    out.parent.mkdir()
    res = runner.invoke(app, ["horizon", str(tmp_path / "cube.sgy"), "--seed", seed, "-o", str(out),
                              "--polarity", pol, "--surface", str(tmp_path / "out" / "h.vtp")])
    assert res.exit_code == 0, res.output
    rows = np.loadtxt(out, comments="#")
    assert len(rows) >= 0.95 * ref.size
    i = (rows[:, 0] - 100).astype(int)
    j = ((rows[:, 1] - 500) // 2).astype(int)
    err = np.abs(rows[:, 2] / 4.0 - ref[i, j])
    assert np.median(err) <= 0.3
    assert (tmp_path / "out" / "h.vtp").stat().st_size > 0


def test_horizon_command_bad_seeds(tmp_path):
    syn = synthetic_cube((16, 16, 48), n_faults=0, seed=0)
    _write_cube(tmp_path / "cube.sgy", syn.cube)
    for seed, message in (("99,500,40", "inline 99 is not in the cube"), ("100,500,999", "outside the cube"),
                          ("100,500", "IL,XL,T")):
        res = runner.invoke(app, ["horizon", str(tmp_path / "cube.sgy"), "--seed", seed, "-o",
                                  str(tmp_path / "h.txt")])
        assert res.exit_code == 2, res.output
        assert message in res.output
    assert not (tmp_path / "h.txt").exists()


@pytest.mark.slow
@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_horizon_command_with_faults_raises_no_runtime_warning(tmp_path):
    # --faults traces the faults first; the command no longer silences RuntimeWarnings, so none may be raised.
    syn = synthetic_cube((24, 32, 64), n_faults=2, seed=0)
    spec = _write_cube(tmp_path / "cube.sgy", syn.cube)
    k = 1
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    j = int(np.nonzero(np.isfinite(ref[12]))[0][16])
    seed = f"{spec.ilines[12]},{spec.xlines[j]},{4.0 * ref[12, j]:.2f}"
    out = tmp_path / "h.txt"
    res = runner.invoke(app, ["horizon", str(tmp_path / "cube.sgy"), "--seed", seed, "-o", str(out),
                              "--polarity", pol, "--faults"])
    assert res.exit_code == 0, res.output
    rows = np.loadtxt(out, comments="#")
    i = (rows[:, 0] - 100).astype(int)
    jj = ((rows[:, 1] - 500) // 2).astype(int)
    err = np.abs(rows[:, 2] / 4.0 - ref[i, jj])
    assert len(rows) >= 0.8 * np.isfinite(ref).sum()
    assert np.nanmedian(err) <= 1.0


def test_seed_index_converts_line_numbers_and_time():
    from seismo3d.jobs.horizon import seed_index

    inlines, xlines, samples = np.arange(100, 110), np.arange(500, 520, 2), 4.0 * np.arange(50) + 8.0
    assert seed_index((103, 506, 26.0), inlines, xlines, samples, "ms") == (3.0, 3.0, 4.5)
    with pytest.raises(Exception, match="crossline 507 is not in the cube"):
        seed_index((103, 507, 26.0), inlines, xlines, samples, "ms")


def _write_line(path, section, inlines, xline, dt_ms=4.0):
    """A 2D line as a SEG-Y trace list (no sorting): one trace per inline number, the same crossline number."""
    spec = segyio.spec()
    spec.format = 5
    spec.samples = dt_ms * np.arange(section.shape[1])
    spec.tracecount = section.shape[0]
    with segyio.create(str(path), spec) as f:
        for tr, il in enumerate(inlines):
            f.header[tr] = {segyio.su.iline: int(il), segyio.su.xline: int(xline), segyio.su.dt: int(dt_ms * 1000)}
            f.trace[tr] = section[tr].astype(np.float32)
        f.bin.update({segyio.BinField.Samples: section.shape[1], segyio.BinField.Interval: int(dt_ms * 1000)})


def test_horizon_command_tracks_a_2d_line(tmp_path):
    syn = synthetic_cube((120, 96), n_faults=0, seed=2, noise=0.1)
    inlines = np.arange(1000, 1120)
    _write_line(tmp_path / "line.sgy", syn.cube, inlines, 1155)
    k = 2
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    out = tmp_path / "h.txt"
    res = runner.invoke(app, ["horizon", str(tmp_path / "line.sgy"), "--ignore-geometry", "--seed",
                              f"1060,1155,{4.0 * ref[60]:.2f}", "-o", str(out), "--polarity", pol])
    assert res.exit_code == 0, res.output
    rows = np.loadtxt(out, comments="#")
    assert open(out).readline().strip() == "# inline xline time"
    assert len(rows) >= 0.95 * np.isfinite(ref).sum()
    np.testing.assert_array_equal(rows[:, 1], 1155)
    j = (rows[:, 0] - 1000).astype(int)
    assert np.median(np.abs(rows[:, 2] / 4.0 - ref[j])) <= 0.3
    # a seed that names no trace of the line, and a surface (3D only), are refused in the CLI's terms
    res = runner.invoke(app, ["horizon", str(tmp_path / "line.sgy"), "--ignore-geometry", "--seed", "1060,1156,100",
                              "-o", str(tmp_path / "x.txt")])
    assert res.exit_code == 2 and "--seed 1060,1156,100" in res.output and "crossline 1156" in res.output
    res = runner.invoke(app, ["horizon", str(tmp_path / "line.sgy"), "--ignore-geometry", "--seed",
                              f"1060,1155,{4.0 * ref[60]:.2f}", "-o", str(tmp_path / "x.txt"), "--surface",
                              str(tmp_path / "x.vtp")])
    assert res.exit_code == 2 and "--surface" in res.output
    assert not (tmp_path / "x.txt").exists()


@pytest.mark.slow
def test_horizon_command_on_penobscot_xl1155(data_dir, tmp_path):
    # the 2D target: one seed on the 2564 ms reflector at inline 1100 tracks >= 95 % of the 601 traces of
    # the real crossline with neighbouring picks smooth (median step <= 1 sample of 4 ms)
    import os

    from seismo3d.jobs.horizon import run_horizon_job

    path = os.path.join(data_dir, "seismic", "penobscot_xl1155.sgy")
    job = run_horizon_job(path, [(1100, 1155, 2564.0)], tmp_path / "h.txt", ignore_geometry=True, progress=False)
    rows = np.loadtxt(tmp_path / "h.txt", comments="#")
    assert job.horizon.times.shape == (601,)
    assert len(rows) >= 0.95 * 601
    steps = np.abs(np.diff(job.horizon.times))
    assert np.nanmedian(steps) <= 1.0
    assert abs(rows[rows[:, 0] == 1100, 2][0] - 2564.0) <= 8.0  # the seed's reflector, snapped within two samples
