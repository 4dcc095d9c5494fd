"""The interchange files of the faults, horizon and render jobs: map coordinates from the SEG-Y headers, read back by
the formats' readers (xtgeo for grids, points and TSurf; the Charisma column spec; seismo3d's stick reader)."""

import csv
import warnings
from pathlib import Path

import numpy as np
import pytest
import segyio
from numpy.testing import assert_allclose

from seismo3d.seismic.io.fault_sticks import read_fault_sticks

pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning", "ignore::FutureWarning",
                                        "ignore:The inplace keyword", "ignore::seismo3d.errors.Seismo3dWarning")


def _cdp(path):
    """inline, crossline -> CDP X, CDP Y of every trace, the scalar of bytes 71-72 applied by hand."""
    with segyio.open(str(path), ignore_geometry=True) as f:
        il, xl = f.attributes(189)[:], f.attributes(193)[:]
        s = f.attributes(71)[:].astype(float)
        factor = np.where(s < 0, -1.0 / np.where(s < 0, s, -1.0), np.where(s > 0, s, 1.0))
        x, y = f.attributes(181)[:] * factor, f.attributes(185)[:] * factor
    return {(int(a), int(b)): (float(c), float(d)) for a, b, c, d in zip(il, xl, x, y)}


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def penobscot_faults(data_dir, tmp_path_factory):
    from seismo3d.data import fetch
    from seismo3d.jobs.faults import run_faults_job

    src = fetch("seismic/penobscot_xl1155.sgy")
    out = tmp_path_factory.mktemp("pen") / "faults"
    return src, run_faults_job(src, out, progress=False)


@pytest.mark.slow  # the faults job on the line: 25 s on 2 shared cores
def test_penobscot_fault_points_are_at_their_traces_cdp(penobscot_faults):
    src, job = penobscot_faults
    cdp = _cdp(src)
    points = _rows(job.written["points"])
    assert len(points) > 100 and {r["xy_unit"] for r in points} == {"m"}
    for r in points:  # every fault point: the CDP X/Y of its trace, to the file's 3 decimals
        x, y = cdp[(int(r["inline"]), int(r["crossline"]))]
        assert abs(float(r["x"]) - x) < 5e-4 and abs(float(r["y"]) - y) < 5e-4
    # the sticks: one per fault on a line, every node a fault point, read back by seismo3d and by the Charisma spec
    import pandas as pd

    odt = read_fault_sticks(job.written["sticks_opendtect"])
    cha = read_fault_sticks(job.written["sticks_charisma"])
    assert odt.n_faults == odt.n_sticks == job.n_faults
    assert odt.n_nodes == cha.n_nodes < len(points) / 10  # nodes where the faults bend: 40 of 887 points
    fault_points = {(int(r["inline"]), round(float(r["time_or_depth"]), 3)) for r in points}
    assert set(zip(np.round(odt.inline).astype(int).tolist(), np.round(odt.z, 3).tolist())) <= fault_points
    for _, nodes in odt.sticks():
        assert np.all(np.diff(odt.z[nodes]) > 0)  # down the stick, one node a time
    from seismo3d.seismic.io import read_survey_coordinates

    iesx = read_fault_sticks(job.written["sticks_iesx"], coordinates=read_survey_coordinates(src))
    assert iesx.n_nodes == odt.n_nodes and np.abs(iesx.inline - np.round(iesx.inline)).max() < 0.01
    iesx = type(iesx)(iesx.fault_id, iesx.stick, iesx.x, iesx.y, iesx.z, np.round(iesx.inline), iesx.crossline,
                      iesx.names)
    for s in (odt, cha, iesx):
        for il, xl, x, y in zip(s.inline, s.crossline, s.x, s.y):
            assert np.hypot(x - cdp[(int(il), int(xl))][0], y - cdp[(int(il), int(xl))][1]) < 1e-3
    df = pd.read_csv(job.written["sticks_charisma"], sep=r"\s+", header=None,
                     names=["INLINE", "iline", "xline", "cdp_x", "cdp_y", "height", "name", "number"])
    assert_allclose(df["cdp_x"], cha.x)
    assert len(df) == cha.n_nodes
    assert "surfaces_tsurf" not in job.written  # a line's faults are curves: sticks only


# The demo cube (128^3) traced and a horizon tracked in it (50 s under load): `python benchmarks/fault_blocks.py --only
# demo_interchange --check`; here a smaller cube written as the demo is (SEG-Y, lines from 1, 4 ms), without
# coordinates or with CDP X / Y on a rotated grid
SMALL = (48, 56, 48)
# the rotated survey: inline 1, crossline 1 at (ORIGIN), inlines 25 m apart along AZIMUTH degrees from north (X east),
# crosslines 12.5 m apart at right angles; the headers store centimetres (scalar -100)
ORIGIN, AZIMUTH, BINS = (612345.67, 6078901.23), 32.0, (25.0, 12.5)


def _map_xy(inline, crossline):
    """The survey's map X / Y of (fractional) inline and crossline numbers, from its definition above."""
    a = np.radians(AZIMUTH)
    il, xl = np.asarray(inline, float) - 1, np.asarray(crossline, float) - 1
    x = ORIGIN[0] + il * BINS[0] * np.sin(a) + xl * BINS[1] * np.cos(a)
    y = ORIGIN[1] + il * BINS[0] * np.cos(a) - xl * BINS[1] * np.sin(a)
    return x, y


def _map_lines(x, y):
    """The inverse of :func:`_map_xy`: fractional inline and crossline numbers of map X / Y."""
    a = np.radians(AZIMUTH)
    dx, dy = np.asarray(x, float) - ORIGIN[0], np.asarray(y, float) - ORIGIN[1]
    return 1 + (dx * np.sin(a) + dy * np.cos(a)) / BINS[0], 1 + (dx * np.cos(a) - dy * np.sin(a)) / BINS[1]


def _small_cube(path, coordinates: bool):
    from seismo3d.data.synthetic import synthetic_cube

    segyio.tools.from_array3D(str(path), synthetic_cube(SMALL, seed=0).cube.astype(np.float32), format=5, dt=4000)
    if coordinates:
        with segyio.open(str(path), "r+") as f:
            il, xl = f.attributes(189)[:], f.attributes(193)[:]
            x, y = _map_xy(il, xl)
            for i in range(f.tracecount):
                f.header[i].update({segyio.TraceField.SourceGroupScalar: -100,
                                    segyio.TraceField.CDP_X: int(round(x[i] * 100)),
                                    segyio.TraceField.CDP_Y: int(round(y[i] * 100))})
            f.bin.update({segyio.BinField.MeasurementSystem: 1})
    return path


@pytest.fixture(scope="module", params=[False, True], ids=["line-numbers", "rotated-map"])
def small_faults(request, tmp_path_factory):
    from seismo3d.jobs.faults import run_faults_job

    tmp = tmp_path_factory.mktemp("small")
    src = _small_cube(tmp / "cube.sgy", request.param)
    return request.param, src, run_faults_job(src, tmp / "faults", progress=False)


@pytest.mark.slow  # a 48 x 56 x 48 cube traced (twice: without and with coordinates)
def test_every_fault_surface_read_by_xtgeo(small_faults):
    """A TSurf file per traced fault, each read by xtgeo's reader; its vertices are faults.vtp's points of the fault
    at their trace's map X / Y (the rotated survey's CDP X / Y, scalar -100 applied; inline / crossline numbers
    without coordinates, the axes named so) and two-way time in ms; run.json names the unit."""
    import json

    import pyvista as pv
    import xtgeo

    coordinates, _, job = small_faults
    assert job.n_faults > 0
    folder = Path(job.written["surfaces_tsurf"])
    vtp = pv.read(job.written["surfaces"])
    ids = np.asarray(vtp.point_data["fault_id"])
    assert sorted(p.name for p in folder.iterdir()) == sorted(f"fault_{i}.ts" for i in np.unique(ids))
    assert len(list(folder.iterdir())) == job.n_faults
    n_triangles = 0
    for fid in np.unique(ids):
        path = folder / f"fault_{fid}.ts"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # xtgeo: 'uncommon AXIS_UNIT combination' (m, m, ms)
            surf = xtgeo.triangulated_surface_from_file(path, fformat="tsurf")
        points = vtp.points[ids == fid]  # (inline index, crossline index, -sample index), in the file's order
        il, xl, t = points[:, 0] + 1, points[:, 1] + 1, -points[:, 2] * 4.0
        x, y = _map_xy(il, xl) if coordinates else (il, xl)
        assert surf.num_vertices == len(points)
        assert_allclose(surf.vertices[:, 0], x, atol=0.006)  # the headers' 0.01 m steps, the file's 3 decimals
        assert_allclose(surf.vertices[:, 1], y, atol=0.006)
        assert_allclose(surf.vertices[:, 2], t, atol=5e-5)
        n_triangles += surf.num_triangles
        unit = '"m" "m" "ms"' if coordinates else '"none" "none" "ms"'
        assert f"AXIS_UNIT {unit}" in path.read_text()
    assert n_triangles == vtp.n_cells
    record = json.loads(Path(job.run_json).read_text())
    assert record["results"]["xy_unit"] == ("m" if coordinates else "inline/crossline")


@pytest.mark.slow  # the cubes of small_faults; a horizon tracked in each (1 s)
def test_small_cube_sticks_and_grids(small_faults, tmp_path):
    """The same runs: the fault sticks' nodes are fault points (a few a stick) at their map X / Y, read back by xtgeo
    from the RMS polygons; a horizon's IRAP / ZMAP+ grids read back by xtgeo hold the text rows' times, on the survey's rotated grid at the traces' X / Y."""
    import xtgeo

    from seismo3d.jobs.horizon import run_horizon_job

    coordinates, src, job = small_faults
    points = _rows(job.written["points"])
    assert {r["xy_unit"] for r in points} == {"m" if coordinates else "inline/crossline"}
    sticks = read_fault_sticks(job.written["sticks_opendtect"])
    assert sticks.n_faults == job.n_faults
    assert sticks.n_nodes < len(points) / 10 and {(int(a), int(b), round(z, 3)) for a, b, z in zip(
        sticks.inline, sticks.crossline, sticks.z)} <= {(int(r["inline"]), int(r["crossline"]),
                                                         round(float(r["time_or_depth"]), 3)) for r in points}
    x, y = _map_xy(sticks.inline, sticks.crossline) if coordinates else (sticks.inline, sticks.crossline)
    assert_allclose(sticks.x, x, atol=0.006)
    assert_allclose(sticks.y, y, atol=0.006)
    # the same sticks as RMS polygons, read by xtgeo: a polygon per stick, its nodes in the OpendTect file's order
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # xtgeo's pandas deprecation warnings
        rms = xtgeo.polygons_from_file(job.written["sticks_rms"], fformat="xyz").get_dataframe()
    assert rms["POLY_ID"].nunique() == sticks.n_sticks
    order = np.argsort(sticks.stick, kind="stable")  # the files' order: stick by stick
    assert_allclose(rms.iloc[:, :3].to_numpy(), np.column_stack([sticks.x, sticks.y, sticks.z])[order], atol=6e-4)
    # a horizon of the cube as IRAP / ZMAP+ grids, read back by xtgeo
    n_il, n_xl = SMALL[:2]
    horizon = run_horizon_job(src, [_peak_seed(src, n_il // 2, n_xl // 2)], tmp_path / "h.txt", faults=False,
                              maps=True, progress=False)
    rows = np.loadtxt(tmp_path / "h.txt", ndmin=2)
    truth = np.full((n_il, n_xl), np.nan)
    truth[rows[:, 0].astype(int) - 1, rows[:, 1].astype(int) - 1] = rows[:, 2]
    for fmt in ("irap_ascii", "irap_binary"):
        surf = xtgeo.surface_from_file(horizon.maps[fmt])
        assert surf.ncol * surf.nrow == n_il * n_xl
        gx, gy, gz = surf.get_xyz_values()
        gx, gy, gz = np.ma.getdata(gx).ravel(), np.ma.getdata(gy).ravel(), np.ma.filled(gz, np.nan).ravel()
        # each node's inline and crossline from its X / Y by the survey's definition: whole lines (IRAP binary's
        # float32 origin: 0.5 m at 6 million), every trace once, the text rows' time there (3 decimals)
        il, xl = _map_lines(gx, gy) if coordinates else (gx, gy)
        tol = (0.6 if fmt == "irap_binary" else 0.01) / min(BINS) if coordinates else 1e-6
        assert np.abs(il - np.round(il)).max() < tol and np.abs(xl - np.round(xl)).max() < tol
        il, xl = np.round(il).astype(int), np.round(xl).astype(int)
        assert len(set(zip(il.tolist(), xl.tolist()))) == n_il * n_xl
        assert_allclose(gz, truth[il - 1, xl - 1], atol=5e-4, equal_nan=True)
        if not coordinates:
            assert (surf.ncol, surf.nrow, surf.xori, surf.yori, surf.rotation) == (n_il, n_xl, 1.0, 1.0, 0.0)
    if not coordinates:  # ZMAP+ holds no rotation: the unrotated grid only
        surf = xtgeo.surface_from_file(horizon.maps["zmap"])
        assert_allclose(np.ma.filled(surf.values, np.nan), truth, atol=5e-4, equal_nan=True)


def _peak_seed(path, il, xl):
    from seismo3d.seismic import reflector_picks

    with segyio.open(str(path)) as f:
        trace = f.iline[il][list(f.xlines).index(xl)]
        samples = np.asarray(f.samples)
    peaks, _ = reflector_picks(trace[None], polarity="peak")
    k = int(round(float(peaks[len(peaks) // 2])))
    return (il, xl, float(samples[k]))


@pytest.mark.slow
def test_f3_horizon_maps_and_seed_file(data_dir, tmp_path):
    """F3: the horizon written as IRAP / ZMAP+ / xyz (read back by xtgeo equal to the text rows, at the traces' CDP
    X/Y), then tracked again from its own .xyz as --seed-file: the same horizon."""
    import xtgeo

    from seismo3d.data import fetch
    from seismo3d.jobs.horizon import run_horizon_job

    src = fetch("seismic/f3_crop.sgy")
    cdp = _cdp(src)
    seed = _peak_seed(src, 122, 883)
    job = run_horizon_job(src, [seed], tmp_path / "h.txt", faults=False, maps=True, progress=False)
    assert sorted(p.suffix for p in job.maps.values()) == [".fgr", ".gri", ".xyz", ".zmap"]
    rows = np.loadtxt(tmp_path / "h.txt", ndmin=2)
    truth = {(int(a), int(b)): t for a, b, t in rows}
    assert len(truth) > 300
    for fmt in ("irap_ascii", "irap_binary"):
        surf = xtgeo.surface_from_file(job.maps[fmt])
        x, y, z = surf.get_xyz_values()
        x, y, z = np.ma.getdata(x), np.ma.getdata(y), np.ma.filled(z, np.nan)  # every node's X / Y; z masked: NaN
        got = 0
        for (il, xl), t in truth.items():  # each tracked trace's node: at its CDP X/Y
            d = np.hypot(x - cdp[(il, xl)][0], y - cdp[(il, xl)][1])
            node = np.unravel_index(np.argmin(d), d.shape)
            assert d[node] < 0.5 and abs(z[node] - t) < 1e-3
            got += 1
        assert got == len(truth) == np.isfinite(z).sum()
    pts = xtgeo.points_from_file(job.maps["xyz"]).get_dataframe().to_numpy()[:, :3]
    assert len(pts) == len(truth)
    for x, y, z in pts:
        (il, xl), _ = min(cdp.items(), key=lambda kv: np.hypot(kv[1][0] - x, kv[1][1] - y))
        assert cdp[(il, xl)] == pytest.approx((x, y), abs=1e-3) and truth[(il, xl)] == pytest.approx(z, abs=1e-3)
    again = run_horizon_job(src, [], tmp_path / "h2.txt", faults=False, seed_file=job.maps["xyz"], progress=False)
    rows2 = np.loadtxt(tmp_path / "h2.txt", ndmin=2)
    assert 50 <= len(again.horizon.seeds) <= 64  # at most 64 picks of the file, spread through it
    # every seed from the file snaps to the first horizon's pick on its trace
    for i, j, k in again.horizon.seeds:
        assert abs(k - job.horizon.times[int(i), int(j)]) < 0.05
    # the horizon tracked from the picks: the same picks on most traces both track (97 % measured from the CLI)
    both = np.isfinite(again.horizon.times) & np.isfinite(job.horizon.times)
    same = np.abs(again.horizon.times - job.horizon.times)[both] < 0.05
    assert both.sum() > 0.9 * np.isfinite(job.horizon.times).sum() and same.mean() > 0.9, (both.sum(), same.mean())
    assert abs(len(rows2) - len(rows)) < 0.1 * len(rows)


@pytest.mark.slow  # the tracker on the 601 x 1501 line: 2 s, up to 40 s while numba compiles on a cold cache
def test_penobscot_horizon_points(data_dir, tmp_path):
    import xtgeo

    from seismo3d.data import fetch
    from seismo3d.jobs.horizon import run_horizon_job

    src = fetch("seismic/penobscot_xl1155.sgy")
    cdp = _cdp(src)
    job = run_horizon_job(src, [_peak_seed(src, 1300, 1155)], tmp_path / "h.txt", faults=False, maps=True,
                          progress=False)
    assert list(job.maps) == ["xyz"]  # a line: points only
    rows = np.loadtxt(tmp_path / "h.txt", ndmin=2)
    pts = xtgeo.points_from_file(job.maps["xyz"]).get_dataframe().to_numpy()[:, :3]
    assert len(pts) == len(rows)
    for (il, xl, t), (x, y, z) in zip(rows[np.argsort(rows[:, 0])], _by_trace(pts, cdp, rows)):
        assert cdp[(int(il), int(xl))] == pytest.approx((x, y), abs=1e-3) and z == pytest.approx(t, abs=1e-3)


def _by_trace(pts, cdp, rows):
    where = {v: k for k, v in cdp.items()}
    by = {where[min(where, key=lambda v: np.hypot(v[0] - x, v[1] - y))]: (x, y, z) for x, y, z in pts}
    return [by[(int(il), int(xl))] for il, xl, _ in rows[np.argsort(rows[:, 0])]]


@pytest.mark.slow
def test_render_gsb_sticks_over_their_line(data_dir, tmp_path):
    from seismo3d.data import fetch
    from seismo3d.jobs.render import run_render_job

    segy = fetch("seismic/gsb_fault_sticks/gsb_crl_2800.sgy")
    sticks = fetch("seismic/gsb_fault_sticks/gsb_crl_2800_faults_opendtect.dat")
    job = run_render_job(segy, tmp_path / "gsb.png", sticks=sticks, window_size=(800, 500))
    assert job.n_faults == 0 and job.n_stick_faults == 13  # the SEG-Y line has no traced faults; 13 people's
    assert job.picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    from seismo3d.jobs.interchange import sticks_mesh
    from seismo3d.viz.geometry import cube_geometry

    geometry = cube_geometry((484, 1, 76), inlines=np.arange(1565, 2532, 2), xlines=[2800],
                             samples=1000.0 + 4.0 * np.arange(76), sample_unit="ms")
    mesh = sticks_mesh(sticks, geometry, segy)
    raw = np.loadtxt(sticks)
    assert mesh.n_lines == 13 and mesh.n_points == 26
    assert_allclose(mesh.points[:, 0], (raw[:, 6] - 1565) / 2)  # inline index of every node
    assert_allclose(-mesh.points[:, 2], (raw[:, 2] - 1000) / 4)  # fractional sample of its two-way time


@pytest.mark.slow
def test_cli_maps_seed_file_and_sticks(data_dir, tmp_path):
    """The command line: `horizon --maps`, `horizon --seed-file` and `render --sticks` reach the jobs."""
    from typer.testing import CliRunner

    from seismo3d.cli import app
    from seismo3d.data import fetch

    runner = CliRunner()
    src = fetch("seismic/f3_crop.sgy")
    il, xl, t = _peak_seed(src, 122, 883)
    out = tmp_path / "h.txt"
    result = runner.invoke(app, ["horizon", str(src), "--seed", f"{il},{xl},{t:g}", "-o", str(out), "--maps",
                                 "--no-faults"])
    assert result.exit_code == 0, result.output
    assert all((tmp_path / f"h{suffix}").is_file() for suffix in (".fgr", ".gri", ".zmap", ".xyz"))
    assert "map -> " in result.output
    result = runner.invoke(app, ["horizon", str(src), "--seed-file", str(tmp_path / "h.xyz"), "-o",
                                 str(tmp_path / "h2.txt"), "--no-faults"])
    assert result.exit_code == 0, result.output
    assert np.loadtxt(tmp_path / "h2.txt").shape[0] > 300
    result = runner.invoke(app, ["horizon", str(src), "-o", str(tmp_path / "h3.txt")])
    assert result.exit_code != 0 and "--seed-file" in result.output
    segy = fetch("seismic/gsb_fault_sticks/gsb_crl_2600.sgy")
    sticks = fetch("seismic/gsb_fault_sticks/gsb_crl_2600_faults_opendtect.dat")
    result = runner.invoke(app, ["render", str(segy), "--sticks", str(sticks), "-o", str(tmp_path / "g.png"),
                                 "--size", "600x400"])
    assert result.exit_code == 0, result.output
    assert "SEG-Y line and the --sticks file's 18 faults of gsb_crl_2600.sgy" in result.stdout
    assert (tmp_path / "g.png").stat().st_size > 1000


@pytest.mark.slow  # the faults job on the 225-trace arbitrary line: 3-4 s
def test_arbitrary_line_fault_points_at_their_traces(data_dir, tmp_path):
    """A trace list (the Volve arbitrary line, no inline / crossline numbers): each fault point at the CDP X/Y of its
    trace (fault_points.csv's `trace` column numbers the traces from 1 in file order, as seismo3d.open does), in the
    CSV and the sticks."""
    from seismo3d.data import fetch
    from seismo3d.jobs.faults import run_faults_job

    src = fetch("seismic/volve_fullstack_twt_arbline.sgy")
    with segyio.open(str(src), ignore_geometry=True) as f:
        x = f.attributes(181)[:] / 100.0  # scalar -100 on every trace
        y = f.attributes(185)[:] / 100.0
        assert set(f.attributes(71)[:]) == {-100}
    job = run_faults_job(src, tmp_path / "out", progress=False)
    points = _rows(job.written["points"])
    assert points and "inline" not in points[0] and "crossline" not in points[0]  # one `trace` column
    for r in points:
        t = int(r["trace"]) - 1
        assert t >= 0 and abs(float(r["x"]) - x[t]) < 5e-4 and abs(float(r["y"]) - y[t]) < 5e-4
    sticks = read_fault_sticks(job.written["sticks_opendtect"])
    t = sticks.inline.astype(int) - 1
    assert t.min() >= 0
    assert_allclose(sticks.x, x[t], atol=5e-4)
    assert_allclose(sticks.y, y[t], atol=5e-4)
