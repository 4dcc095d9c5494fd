"""The render job (seismo3d.jobs.render) through `seismo3d render`: SEG-Y cubes with CDP coordinates, faults
folders and horizon files rendered off screen into non-blank PNGs."""

import numpy as np
import pytest
import segyio
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.jobs.render import run_render_job

runner = CliRunner()
SHAPE = (12, 20, 48)


def _cube():
    i, _, k = np.meshgrid(*(np.arange(n) for n in SHAPE), indexing="ij")
    return np.sin(2 * np.pi * (k - 0.5 * i) / 10.0).astype(np.float32)


def _write_segy(path, cube, *, coordinates=True):
    """A crossline-step-2 cube, inlines 100.., crosslines 500.., 4 ms, with CDP X/Y of a survey rotated 40 deg
    (25 m x 12.5 m bins, coordinate scalar -100: centimetres)."""
    spec = segyio.spec()
    spec.format, spec.sorting = 5, segyio.TraceSortingFormat.INLINE_SORTING
    spec.ilines = np.arange(100, 100 + cube.shape[0])
    spec.xlines = np.arange(500, 500 + 2 * cube.shape[1], 2)
    spec.samples = 4.0 * np.arange(cube.shape[2])
    t = np.deg2rad(40.0)
    with segyio.create(str(path), spec) as f:
        tr = 0
        for i, il in enumerate(spec.ilines):
            for j, xl in enumerate(spec.xlines):
                x = 600_000 + 25 * i * np.cos(t) - 12.5 * j * np.sin(t)
                y = 5_000_000 + 25 * i * np.sin(t) + 12.5 * j * np.cos(t)
                head = {segyio.su.iline: int(il), segyio.su.xline: int(xl), segyio.su.dt: 4000}
                if coordinates:
                    head.update({segyio.su.cdpx: int(round(x * 100)), segyio.su.cdpy: int(round(y * 100)),
                                 segyio.su.scalco: -100})
                f.header[tr] = head
                f.trace[tr] = cube[i, j]
                tr += 1
        f.bin.update({segyio.BinField.Samples: cube.shape[2], segyio.BinField.Interval: 4000})
    return spec


def _not_blank(path, min_fraction=0.1):
    from matplotlib.image import imread

    img = (imread(path)[..., :3] * 255).round()
    return (img.min(axis=-1) < 250).mean() > min_fraction, img


@pytest.mark.slow
def test_segy_cube_is_placed_by_its_cdp_coordinates(tmp_path):
    _write_segy(tmp_path / "cube.sgy", _cube())
    out = tmp_path / "cube.png"
    res = runner.invoke(app, ["render", str(tmp_path / "cube.sgy"), "-o", str(out), "--size", "400x300",
                              "--vertical-exaggeration", "2"])
    assert res.exit_code == 0, res.output
    assert "inlines 100-111, crosslines 500-538, time 0-188 ms" in res.stdout
    ok, img = _not_blank(out)
    assert ok and img.shape == (300, 400, 3)
    red = (img[..., 0] > 150) & (img[..., 1] < 60) & (img[..., 2] < 60)
    blue = (img[..., 2] > 150) & (img[..., 0] < 60) & (img[..., 1] < 60)
    assert red.mean() > 0.01 and blue.mean() > 0.01


def test_geometry_of_the_segy_headers(tmp_path):
    from seismo3d.seismic import open_segy
    from seismo3d.viz.geometry import geometry_of_segy

    _write_segy(tmp_path / "cube.sgy", _cube())
    with open_segy(tmp_path / "cube.sgy") as segy:
        geo = geometry_of_segy(segy, vertical_exaggeration=1.0)
    np.testing.assert_allclose(np.linalg.norm(geo.axes[:2], axis=1), [25.0, 12.5], atol=0.01)
    assert np.degrees(np.arctan2(geo.axes[0, 1], geo.axes[0, 0])) == pytest.approx(40.0, abs=0.05)
    np.testing.assert_allclose(geo.origin, [600_000, 5_000_000, 0], atol=0.01)
    assert geo.axes[2, 2] == pytest.approx(-4.0)  # 4 ms at 2000 m/s two-way


@pytest.mark.slow
def test_faults_folder_and_horizon_file(tmp_path):
    from seismo3d.viz import fault_surfaces, save_polydata
    from seismo3d.seismic import Fault

    folder = tmp_path / "faults"
    folder.mkdir()
    j, k = np.meshgrid(np.arange(SHAPE[1]), np.arange(SHAPE[2]), indexing="ij")
    pts = np.column_stack([np.round(6 + 0.2 * j.ravel()), j.ravel(), k.ravel()]).astype(np.int64)
    n = pts.shape[0]
    fault = Fault(id=2, points=pts, likelihood=np.ones(n, np.float32), strike_deg=np.zeros(n, np.float32),
                  dip_deg=np.full(n, 90, np.float32), normals=np.tile(np.float32([1, 0, 0]), (n, 1)))
    save_polydata(fault_surfaces([fault]), folder / "faults.vtp")
    ii = np.arange(SHAPE[0])[:, None, None] + np.zeros(SHAPE)
    np.save(folder / "fault_likelihood.npy", np.exp(-((ii - 6) ** 2) / 2.0).astype(np.float32))
    out = tmp_path / "faults.png"
    job = run_render_job(folder, out, window_size=(400, 300))
    assert job.kind == "faults" and job.n_faults == 1
    ok, img = _not_blank(out, 0.02)
    orange = (img[..., 0] > 150) & (img[..., 0] > img[..., 2] + 80)  # fault 2 in tab10 orange (255, 127, 14)
    assert ok and orange.mean() > 0.01

    # a horizon file on the lines of a SEG-Y cube, and alone
    _write_segy(tmp_path / "cube.sgy", _cube(), coordinates=False)
    rows = [(100 + i, 500 + 2 * j, 40.0 + 2.0 * i) for i in range(SHAPE[0]) for j in range(SHAPE[1])]
    np.savetxt(tmp_path / "h.txt", rows, fmt="%g")
    for seismic in (tmp_path / "cube.sgy", None):
        out = tmp_path / f"h_{seismic is None}.png"
        job = run_render_job(tmp_path / "h.txt", out, seismic=seismic, window_size=(400, 300))
        ok, img = _not_blank(out, 0.02)
        greenish = img[..., 1] > img[..., 2] + 40  # viridis' upper half (green to yellow); none in seismic colours
        assert job.kind == "horizon" and ok and greenish.mean() > 0.01


@pytest.mark.parametrize("name, args, match", [
    ("missing", ["nothing.sgy"], "does not exist"),
    ("extension", ["x.las"], "extension"),
    ("png", ["cube.sgy", "-o", "x.jpg"], "PNG"),
    ("size", ["cube.sgy", "--size", "big"], "--size"),
])
def test_bad_inputs_are_one_line_errors(tmp_path, name, args, match):
    _write_segy(tmp_path / "cube.sgy", _cube())
    (tmp_path / "x.las").write_text("")
    if "-o" not in args:
        args = args + ["-o", str(tmp_path / "x.png")]
    args = [str(tmp_path / a) if a in {"nothing.sgy", "x.las", "cube.sgy"} else a for a in args]
    res = runner.invoke(app, ["render", *args])
    assert res.exit_code == 2, res.output
    assert match in res.stderr and len(res.stderr.strip().splitlines()) == 1


@pytest.mark.slow
def test_segy_flags_reach_the_one_opening_path(tmp_path):
    # render opens SEG-Y like faults / horizon / register: byte order detected (big here), --endian to force it, the
    # header bytes by --iline / --xline; a wrong forced byte order is one clear line naming the flag
    _write_segy(tmp_path / "cube.sgy", _cube())
    out = tmp_path / "cube.png"
    res = runner.invoke(app, ["render", str(tmp_path / "cube.sgy"), "-o", str(out), "--size", "400x300",
                              "--endian", "big", "--iline", "189", "--xline", "193"])
    assert res.exit_code == 0, res.output
    assert _not_blank(out)[0]
    res = runner.invoke(app, ["render", str(tmp_path / "cube.sgy"), "-o", str(tmp_path / "x.png"), "--endian",
                              "little"])
    errors = [line for line in res.output.splitlines() if line.startswith("error: ")]
    assert res.exit_code == 2 and len(errors) == 1 and "--endian" in errors[0], res.output
    assert not (tmp_path / "x.png").exists()


def _write_trace_list(path, section):
    """A SEG-Y file of (n_traces, n_samples) without inline / crossline numbers (a trace list), 4 ms."""
    spec = segyio.spec()
    spec.format, spec.tracecount, spec.samples = 5, section.shape[0], 4.0 * np.arange(section.shape[1])
    with segyio.create(str(path), spec) as f:
        for k, trace in enumerate(section):
            f.header[k] = {segyio.su.cdp: k + 1, segyio.su.dt: 4000}
            f.trace[k] = trace.astype(np.float32)
        f.bin.update({segyio.BinField.Samples: section.shape[1], segyio.BinField.Interval: 4000})


@pytest.mark.slow
def test_a_trace_list_is_drawn_as_one_section(tmp_path):
    """A file without an inline / crossline grid: one section, traces numbered in file order; the warning names
    --ignore-geometry, which render has: with it, the same picture and no warning."""
    _write_trace_list(tmp_path / "line.sgy", _cube()[:, 0, :].repeat(3, axis=0))
    res = runner.invoke(app, ["render", str(tmp_path / "line.sgy"), "-o", str(tmp_path / "a.png"), "--size",
                              "400x300"])
    assert res.exit_code == 0, res.output
    assert "traces 1-36, time 0-188 ms" in res.stdout
    assert res.stderr.startswith("warning: ") and "--ignore-geometry" in res.stderr
    assert _not_blank(tmp_path / "a.png")[0]
    quiet = runner.invoke(app, ["render", str(tmp_path / "line.sgy"), "-o", str(tmp_path / "b.png"), "--size",
                                "400x300", "--ignore-geometry"])
    assert quiet.exit_code == 0 and quiet.stderr == "", quiet.output


@pytest.mark.slow
def test_a_trace_list_horizon_is_drawn_over_its_section(tmp_path):
    """'trace time' rows (seismo3d horizon on a trace list) over the trace list, drawn as a section: the horizon a
    yellow curve at its one time, across the section."""
    section = _cube()[:, 0, :].repeat(3, axis=0)
    _write_trace_list(tmp_path / "line.sgy", section)
    np.savetxt(tmp_path / "h.txt", [(k + 1, 80.0) for k in range(section.shape[0])], fmt="%g")
    res = runner.invoke(app, ["render", str(tmp_path / "h.txt"), "--seismic", str(tmp_path / "line.sgy"),
                              "--ignore-geometry", "-o", str(tmp_path / "h.png"), "--size", "400x300"])
    assert res.exit_code == 0, res.output
    img = _not_blank(tmp_path / "h.png")[1]
    assert img.shape[1] == 400  # the picture's width as asked; its height follows from the exaggeration
    yellow = (img[..., 0] > 200) & (img[..., 1] > 150) & (img[..., 2] < 80)  # the horizon's colour, #ffcc00
    rows, cols = np.nonzero(yellow)
    assert rows.size > 100 and np.ptp(cols) > 0.3 * 400 and np.ptp(rows) <= 12


@pytest.mark.slow
def test_a_faults_folder_of_a_line_renders_quickly(tmp_path):
    """The likelihood of a 2D line of a survey is drawn as a plane (a volume one voxel thick, its crossline step zero,
    took minutes to ray-cast)."""
    import time

    from seismo3d.seismic import Fault
    from seismo3d.viz import fault_surfaces, save_polydata

    folder = tmp_path / "faults"
    folder.mkdir()
    n_traces, n_samples = 601, 1501
    k = np.arange(200, 1200)
    pts = np.column_stack([300 + (k - 200) // 10, np.zeros_like(k), k]).astype(np.int64)
    n = pts.shape[0]
    fault = Fault(id=1, points=pts, likelihood=np.ones(n, np.float32), strike_deg=np.zeros(n, np.float32),
                  dip_deg=np.full(n, 84, np.float32), normals=np.tile(np.float32([1, 0, 0]), (n, 1)))
    save_polydata(fault_surfaces([fault]), folder / "faults.vtp")
    likelihood = np.random.default_rng(0).random((n_traces, 1, n_samples), dtype=np.float32) ** 8
    _write_segy(folder / "fault_likelihood.sgy", likelihood)  # a line of a survey placed by its CDP X/Y
    start = time.perf_counter()
    job = run_render_job(folder, tmp_path / "f.png", window_size=(400, 300))
    assert time.perf_counter() - start < 15.0
    assert job.n_faults == 1 and _not_blank(tmp_path / "f.png", 0.02)[0]


def _line_faults_folder(tmp_path, throw):
    """A faults folder of a 2D line (80 traces, 120 samples): one fault whose points carry ``throw`` (samples)."""
    from seismo3d.seismic import Fault
    from seismo3d.viz import fault_surfaces, save_polydata

    folder = tmp_path / "faults"
    folder.mkdir()
    k = np.arange(10, 110)
    pts = np.column_stack([30 + k // 5, k]).astype(np.int64)  # (trace, sample): a fault of a section
    n = pts.shape[0]
    fault = Fault(id=1, points=pts, likelihood=np.ones(n, np.float32), strike_deg=np.zeros(n, np.float32),
                  dip_deg=np.full(n, 80, np.float32), normals=np.tile(np.float32([1, 0]), (n, 1)))
    mesh = fault_surfaces([fault])
    mesh.point_data["throw"] = np.interp(-mesh.points[:, 2], [10, 109], throw)  # along the fault, by sample
    save_polydata(mesh, folder / "faults.vtp")
    np.save(folder / "fault_likelihood.npy", np.zeros((80, 120), np.float32))
    return folder


@pytest.mark.slow
def test_a_line_s_faults_coloured_by_throw(tmp_path):
    """--color-by throw on a line: the fault drawn point by point in the throw's colours (PuOr: purple where
    the throw is negative, orange where positive) with its colour bar; by fault id it stays tab10 blue. Before, the
    option left the line's picture as by fault id."""
    folder = _line_faults_folder(tmp_path, [-8.0, 8.0])
    pictures = {}
    for how in ("fault_id", "throw"):
        job = run_render_job(folder, tmp_path / f"{how}.png", color_by=how, window_size=(600, 400))
        assert job.section and job.n_faults == 1
        pictures[how] = (imread_rgb(tmp_path / f"{how}.png"))
    blue = lambda img: (img[..., 2] > 150) & (img[..., 0] < 80) & (img[..., 1] > 90)  # tab10 blue (31, 119, 180)
    orange = lambda img: (img[..., 0] > 170) & (img[..., 2] < 90) & (img[..., 1] > 60) & (img[..., 1] < 170)
    purple = lambda img: (img[..., 2] > img[..., 1] + 40) & (img[..., 0] > img[..., 1] + 20) & (img[..., 0] < 160)
    by_id, by_throw = pictures["fault_id"], pictures["throw"]
    assert blue(by_id).sum() > 100 and not orange(by_id).any() and not purple(by_id).any()
    assert orange(by_throw).sum() > 100 and purple(by_throw).sum() > 100 and blue(by_throw).sum() < 20


def imread_rgb(path):
    from matplotlib.image import imread

    return (imread(path)[..., :3] * 255).round()


def test_color_by_throw_refused_before_the_work_without_throws(tmp_path):
    """Where there is no throw to colour by (a SEG-Y file, faults without a measured throw): one line, exit 2,
    no picture."""
    _write_segy(tmp_path / "cube.sgy", _cube())
    folder = _line_faults_folder(tmp_path, [np.nan, np.nan])
    for given, match in ((tmp_path / "cube.sgy", "colours traced faults by their throw, and cube.sgy is a SEG-Y"),
                         (folder, "carry no measured throw")):
        res = runner.invoke(app, ["render", str(given), "-o", str(tmp_path / "x.png"), "--color-by", "throw"])
        assert res.exit_code == 2, res.output
        assert match in res.stderr and "--color-by" in res.stderr and len(res.stderr.strip().splitlines()) == 1
        assert not (tmp_path / "x.png").exists()
