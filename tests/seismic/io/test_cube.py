"""seismo3d.open: every seismic input as one lazy, labelled cube (segysak's dimensions), its headers read once, its
values those of the readers it replaces (read_segy, the Zarr store, numpy)."""

import warnings

import numpy as np
import pytest
import segyio
from numpy.testing import assert_allclose, assert_array_equal

import seismo3d
from seismo3d.errors import InputError, TraceListWarning
from seismo3d.seismic.io import read_segy
from seismo3d.seismic.io.coordinates import cube_coordinates, read_survey_coordinates
from seismo3d.seismic.io.cube import index_positions, seismic_axes

xr = pytest.importorskip("xarray")
da = pytest.importorskip("dask.array")


@pytest.fixture(scope="module")
def segy_cube(tmp_path_factory):
    """A generated 40 x 36 x 48 cube as a 3D SEG-Y with CDP X / Y (seismo3d.data.synthetic.write_segy_cube)."""
    from seismo3d.data.synthetic import write_segy_cube

    cube = np.random.default_rng(5).standard_normal((40, 36, 48)).astype(np.float32)
    return write_segy_cube(tmp_path_factory.mktemp("cube") / "cube.sgy", cube, sorting="crossline"), cube


def test_a_segy_cube_opens_lazily_with_its_coordinates(segy_cube, monkeypatch):
    path, amplitudes = segy_cube
    opened = []
    real_open = segyio.open
    monkeypatch.setattr(segyio, "open", lambda *a, **k: opened.append(a[0]) or real_open(*a, **k))
    cube = seismo3d.open(path)
    assert len(opened) == 1  # the headers, geometry and coordinates: one opening; no sample read yet
    assert isinstance(cube.data, da.Array)
    assert cube.dims == ("iline", "xline", "twt") and cube.shape == amplitudes.shape
    assert {"cdp_x", "cdp_y"} <= set(cube.coords) and cube["cdp_x"].dims == ("iline", "xline")
    ref, segy = read_segy(path)
    assert_array_equal(cube["iline"].values, segy.inlines)
    assert_array_equal(cube["xline"].values, segy.xlines)
    assert_array_equal(cube["twt"].values, segy.samples)
    assert_allclose(cube["cdp_x"].values, segy.cdp_x)  # the coordinate scalar (-100) applied
    assert_allclose(cube["cdp_y"].values, segy.cdp_y)
    assert cube.attrs["sample_interval"] == 4.0 and cube.attrs["sample_unit"] == "ms"
    assert cube.attrs["kind"] == "cube" and cube.attrs["segy_sorting"] == "crossline"
    assert cube.attrs["xy_unit"] == "m" and cube.attrs["xy_resolution"] == 0.01
    assert_array_equal(cube.values, ref)
    assert_array_equal(cube.values, amplitudes)
    # the same coordinates and grid map as read from the file again
    mine, theirs = cube_coordinates(cube), read_survey_coordinates(path)
    assert_array_equal(mine.x, theirs.x)
    assert_array_equal(mine.y, theirs.y)
    assert mine.unit == theirs.unit and mine.source == theirs.source
    assert_allclose(mine.grid_map.inline_vector, theirs.grid_map.inline_vector)


def test_a_tile_reads_only_its_traces(segy_cube):
    path, amplitudes = segy_cube
    cube = seismo3d.open(path, tile=16)
    assert cube.data.chunks[:2] == ((16, 16, 8), (16, 16, 4))
    assert_array_equal(cube[17:30, 3:20].values, amplitudes[17:30, 3:20])


def test_lines_and_trace_lists_have_one_lateral_dimension(data_dir):
    from seismo3d.data import fetch

    line = seismo3d.open(fetch("seismic/penobscot_xl1155.sgy"))
    assert line.dims == ("iline", "twt") and line.shape == (601, 1501)
    assert int(line["xline"]) == 1155 and line["cdp_x"].dims == ("iline",)
    ref, _ = read_segy(fetch("seismic/penobscot_xl1155.sgy"))
    assert_array_equal(line.values, ref[:, 0, :])
    arb = fetch("seismic/volve_fullstack_twt_arbline.sgy")
    with pytest.warns(TraceListWarning):
        traces = seismo3d.open(arb)
    assert traces.dims == ("trace", "twt") and traces.shape == (225, 850) and traces.attrs["kind"] == "trace list"
    # its traces numbered from 1 in file order, as the commands number them (horizon --seed TRACE,T, its rows)
    assert_array_equal(traces["trace"].values, np.arange(1, 226))
    t0 = float(traces["twt"][0])
    assert_array_equal(index_positions(traces, seismic_axes(traces), [[1, t0], [225, t0]]), [[0, 0], [224, 0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error", TraceListWarning)  # ignore_geometry: the same, without the warning
        quiet = seismo3d.open(arb, ignore_geometry=True)
    ref, segy = read_segy(arb, ignore_geometry=True)
    assert_array_equal(quiet.values, ref)
    assert_allclose(quiet["cdp_x"].values, segy.cdp_x)


@pytest.mark.slow
def test_a_convert_store_is_the_same_cube(data_dir, tmp_path):
    from seismo3d.data import fetch
    from seismo3d.jobs.convert import run_convert_job

    path = fetch("seismic/f3_crop.sgy")
    cube = seismo3d.open(path)
    assert cube.dims == ("iline", "xline", "twt") and cube.shape == (23, 18, 75)
    assert float(cube["cdp_x"][0, 0]) == pytest.approx(620197.2)
    run_convert_job(path, tmp_path / "f3.zarr", progress=False)
    store = seismo3d.open(tmp_path / "f3.zarr")
    assert store.dims == cube.dims and isinstance(store.data, da.Array)
    assert_array_equal(store.values, cube.values)
    assert_allclose(store["cdp_x"].values, cube["cdp_x"].values)
    assert_array_equal(store["iline"].values, cube["iline"].values)
    assert store["twt"].attrs["units"] == "ms" and store.attrs["sample_interval"] == 4.0


def test_arrays_and_raw_sections_are_in_samples(tmp_path):
    cube = np.arange(4 * 5 * 6, dtype=np.float32).reshape(4, 5, 6)
    np.save(tmp_path / "cube.npy", cube)
    opened = seismo3d.open(tmp_path / "cube.npy")
    assert opened.dims == ("iline", "xline", "samples") and opened.attrs["sample_unit"] == "samples"
    assert_array_equal(opened.values, cube)
    cube[0].astype(">f4").tofile(tmp_path / "line.f32be")
    section = seismo3d.open(tmp_path / "line.f32be", n_samples=6)
    assert section.dims == ("trace", "samples")
    assert_array_equal(section.values, cube[0])
    with pytest.raises(InputError, match="no sample interval"):
        seismo3d.open(tmp_path / "cube.npy", sample_unit="ms")
    with pytest.raises(InputError, match="n_samples=N"):
        seismo3d.open(tmp_path / "line.f32be")


def test_grid_spacing_is_that_of_the_segy_headers(data_dir, tmp_path):
    """The bins from a cube's CDP X / Y and its sample interval: those volume_spacing reads from the open SEG-Y (the
    register job's spacing before it read through seismo3d.open); without coordinates, 1 and said so."""

    from seismo3d.seismic import open_segy, volume_spacing
    from seismo3d.seismic.io.cube import grid_spacing

    path = f"{data_dir}/seismic/f3_crop.sgy"
    spacing, note = grid_spacing(seismo3d.open(path))
    with open_segy(path) as cube:
        reference = volume_spacing(cube)
    assert_array_equal(spacing, reference[0])
    assert note == reference[1] == "bins 25.01 x 25.01 from CDP X/Y, sample interval 4 ms from the binary header"
    bare = tmp_path / "bare.sgy"
    segyio.tools.from_array(str(bare), np.zeros((9, 8, 10), np.float32), dt=2000)
    spacing, note = grid_spacing(seismo3d.open(bare))
    assert_array_equal(spacing, [1.0, 1.0, 2.0])
    assert note.startswith("inline and crossline bin unknown (no CDP coordinates), set to 1")
    with pytest.raises(InputError, match="3D cube"):
        grid_spacing(seismo3d.open(bare).isel(iline=0))
