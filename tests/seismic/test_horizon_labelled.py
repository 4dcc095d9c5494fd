"""The horizon functions on a labelled cube (seismo3d.seismic.horizons.labelled): a seismic DataArray in, seeds in its
own numbers, the horizon out on its coordinates in its sample unit, equal to the tracker on the plain array; plain
arrays in, plain arrays out as before."""

import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import autotrack, fill_horizon, track_horizon, write_horizon_text

xr = pytest.importorskip("xarray")

T0, DT = 1000.0, 4.0  # the labelled cube's first sample and sample interval, ms
INLINES, XLINES = 100 + np.arange(16), 500 + 2 * np.arange(20)


@pytest.fixture(scope="module")
def generated():
    """A generated 16 x 20 x 64 cube without faults as a DataArray with segysak's dims, line numbers that are not
    indices, times from 1000 ms at 4 ms and CDP X / Y; its horizon 1 (the generator's truth, samples) and polarity."""
    syn = synthetic_cube((16, 20, 64), n_faults=0, seed=3, noise=0.05)
    il, xl = np.meshgrid(INLINES, XLINES, indexing="ij")
    cube = xr.DataArray(syn.cube, dims=("iline", "xline", "twt"),
                        coords={"iline": INLINES, "xline": XLINES,
                                "twt": ("twt", T0 + DT * np.arange(64), {"units": "ms"}),
                                "cdp_x": (("iline", "xline"), 600000.0 + 25.0 * il + 3.0 * xl),
                                "cdp_y": (("iline", "xline"), 6.07e6 - 3.0 * il + 25.0 * xl)})
    pol = "peak" if syn.horizon_polarity[1] > 0 else "trough"
    return syn, cube, syn.horizons[1], pol


def _in_ms(k):
    k = np.asarray(k, dtype=np.float64)
    return np.where(np.isfinite(k), T0 + DT * np.nan_to_num(k), np.nan)


def test_a_labelled_cube_gives_a_labelled_horizon_equal_to_the_plain_one(generated):
    syn, cube, truth, pol = generated
    k0 = float(truth[6, 8])
    labelled = track_horizon(cube, (INLINES[6], XLINES[8], T0 + DT * k0), polarity=pol)
    plain = track_horizon(syn.cube, (6, 8, k0), polarity=pol)
    assert isinstance(plain.times, np.ndarray) and plain.times.dtype == np.float32  # plain in, plain out
    times = labelled.times
    assert times.dims == ("iline", "xline") and times.attrs["units"] == "ms"
    assert_array_equal(times["iline"], INLINES)
    assert_array_equal(times["xline"], XLINES)
    assert_array_equal(times["cdp_x"], cube["cdp_x"])
    assert_array_equal(times["cdp_y"], cube["cdp_y"])
    assert_allclose(times.values, _in_ms(plain.times), rtol=0, atol=1e-9, equal_nan=True)
    assert_array_equal(labelled.confidence.values, plain.confidence)
    assert labelled.confidence.dims == ("iline", "xline")
    assert_array_equal(labelled.seeds, [[INLINES[6], XLINES[8], T0 + DT * k0]])
    assert labelled.coverage == plain.coverage == 1.0
    # against the generator's truth, in ms: within a fifth of a sample at the median
    assert np.nanmedian(np.abs(times.values - _in_ms(truth))) <= 0.2 * DT


def test_a_grid_of_one_line_is_tracked_as_its_section(generated):
    syn, cube, truth, pol = generated
    line = cube.isel(iline=slice(6, 7))  # (1, 20, 64): one inline on the grid
    k0 = float(truth[6, 8])
    labelled = track_horizon(line, (INLINES[6], XLINES[8], T0 + DT * k0), polarity=pol)
    plain = track_horizon(syn.cube[6], (8, k0), polarity=pol)
    assert labelled.times.shape == (1, 20) and labelled.times.dims == ("iline", "xline")
    assert_allclose(labelled.times.values[0], _in_ms(plain.times), rtol=0, atol=1e-9, equal_nan=True)


def test_a_line_with_one_lateral_dimension(generated):
    syn, cube, truth, pol = generated
    line = cube.isel(iline=6)  # dims (xline, twt), the inline a scalar coordinate: a line of seismo3d.open
    k0 = float(truth[6, 8])
    labelled = track_horizon(line, (XLINES[8], T0 + DT * k0), polarity=pol)
    plain = track_horizon(syn.cube[6], (8, k0), polarity=pol)
    assert labelled.times.dims == ("xline",) and int(labelled.times["iline"]) == INLINES[6]
    assert_allclose(labelled.times.values, _in_ms(plain.times), rtol=0, atol=1e-9, equal_nan=True)


def test_autotrack_and_fill_keep_the_labels(generated):
    syn, cube, truth, pol = generated
    k0 = float(truth[6, 8])
    labelled = autotrack(cube, (INLINES[6], XLINES[8], T0 + DT * k0), polarity=pol)
    plain = autotrack(syn.cube, (6, 8, k0), polarity=pol)
    assert_allclose(labelled.times.values, _in_ms(plain.times), rtol=0, atol=1e-9, equal_nan=True)
    holed = labelled.times.copy(data=labelled.times.values.copy())
    holed[5:8, 5:8] = np.nan
    hz = type(labelled)(holed, labelled.confidence, pol, labelled.seeds)
    filled = fill_horizon(hz)
    plain_holed = plain.times.copy()
    plain_holed[5:8, 5:8] = np.nan
    plain_filled = fill_horizon(type(plain)(plain_holed, plain.confidence, pol, plain.seeds))
    assert filled.times.dims == ("iline", "xline") and filled.times.attrs["units"] == "ms"
    assert_array_equal(filled.times["cdp_x"], cube["cdp_x"])
    # linear interpolation of times in ms is that of sample indices mapped to ms
    assert_allclose(filled.times.values, _in_ms(plain_filled.times), rtol=0, atol=1e-4, equal_nan=True)
    assert np.isnan(holed.values[6, 6])  # the input is not modified


def test_labelled_text_rows_are_those_of_the_plain_horizon_with_its_labels(generated, tmp_path):
    syn, cube, truth, pol = generated
    k0 = float(truth[6, 8])
    labelled = autotrack(cube, (INLINES[6], XLINES[8], T0 + DT * k0), polarity=pol)
    plain = autotrack(syn.cube, (6, 8, k0), polarity=pol)
    n = write_horizon_text(tmp_path / "labelled.txt", labelled)
    write_horizon_text(tmp_path / "plain.txt", plain, inlines=INLINES, xlines=XLINES, samples=T0 + DT * np.arange(64))
    assert n == 320
    assert (tmp_path / "labelled.txt").read_text() == (tmp_path / "plain.txt").read_text()
    line = autotrack(cube.isel(iline=6), (XLINES[8], T0 + DT * k0), polarity=pol)
    write_horizon_text(tmp_path / "line.txt", line)  # a line of a survey: inline xline time rows
    rows = np.loadtxt(tmp_path / "line.txt", comments="#")
    assert_array_equal(rows[:, 0], INLINES[6])
    assert_array_equal(rows[:, 1], XLINES)
    with pytest.raises(InputError, match="carries its line numbers"):
        write_horizon_text(tmp_path / "x.txt", labelled, inlines=INLINES)


def test_seeds_off_the_cube_name_its_numbers(generated):
    _, cube, _, pol = generated
    with pytest.raises(InputError, match="xline 501 is not a xline of the cube \\(500..538\\)"):
        track_horizon(cube, (105, 501, 1100.0), polarity=pol)
    with pytest.raises(InputError, match="twt 990 ms is outside the cube's samples \\(1000..1252 ms\\)"):
        track_horizon(cube, (105, 502, 990.0), polarity=pol)
    with pytest.raises(InputError, match="\\(iline, xline, twt\\) rows"):
        track_horizon(cube, (105, 1100.0), polarity=pol)


@pytest.mark.slow
def test_an_opened_segy_cube_gives_its_horizon_in_ms(data_dir):
    """F3 through seismo3d.open: the horizon on its inlines, crosslines and CDP X / Y in ms, the job's horizon."""
    import seismo3d
    from seismo3d.data import fetch
    from seismo3d.jobs.horizon import seed_index

    cube = seismo3d.open(fetch("seismic/f3_crop.sgy"))
    horizon = track_horizon(cube, (122, 883, 228.0), polarity="trough")
    values = cube.values
    samples = cube["twt"].values
    plain = track_horizon(values, seed_index((122, 883, 228.0), cube["iline"].values, cube["xline"].values, samples,
                                             "ms"), polarity="trough")
    expected = np.where(np.isfinite(plain.times), np.interp(np.nan_to_num(plain.times), np.arange(samples.size),
                                                            samples), np.nan)
    assert_allclose(horizon.times.values, expected, rtol=0, atol=1e-9, equal_nan=True)
    assert_array_equal(horizon.times["cdp_x"], cube["cdp_x"])
    assert horizon.times.attrs["units"] == "ms" and int(np.count_nonzero(horizon.mask)) == 385


@pytest.mark.slow  # 9 s on 2 shared cores
def test_track_horizon_on_segysak_dataset_equals_numpy(data_dir):
    """F3 opened by segysak's xarray engine (dims iline / xline / samples, its cdp_x / cdp_y), tracked from a seed in
    its own coordinates, equals the tracker on the numpy cube with the seed in index space."""
    pytest.importorskip("segysak")
    from seismo3d.data import fetch

    path = fetch("seismic/f3_crop.sgy")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xr.open_dataset(path, dim_byte_fields={"iline": 189, "xline": 193},
                             extra_byte_fields={"cdp_x": 181, "cdp_y": 185}).load()
    da = ds.set_coords(["cdp_x", "cdp_y"])["data"]  # segysak keeps them as variables of the Dataset
    k = 30
    seed = (120, 880, float(da["samples"][k]))
    labelled = track_horizon(da, [seed], polarity="peak")
    ref = track_horizon(np.asarray(da.values, dtype=np.float32), [(9.0, 5.0, float(k))], polarity="peak")
    samples = da["samples"].values.astype(float)
    expected = np.interp(np.nan_to_num(ref.times), np.arange(samples.size), samples)
    assert_allclose(labelled.times.values, np.where(np.isfinite(ref.times), expected, np.nan), equal_nan=True)
    assert labelled.times.dims == ("iline", "xline")
    assert_array_equal(labelled.times["cdp_x"].values, ds["cdp_x"].values)  # segysak's coordinates carried through
    with pytest.raises(InputError, match="not a iline"):
        track_horizon(da, [(99, 880, 100.0)])


def test_a_seed_error_speaks_in_the_cubes_numbers(generated):
    """A seed without a pick of the polarity near it, or on a dead trace: the error names the seed and the nearest
    position that can start a horizon in the cube's inline, crossline and time."""
    from seismo3d.errors import SeedError

    syn, cube, truth, pol = generated
    other = "trough" if pol == "peak" else "peak"
    k0 = float(truth[6, 8])
    with pytest.raises(SeedError) as caught:  # 5-sample snap: the other polarity is half a cycle away at most
        track_horizon(cube, (INLINES[6], XLINES[8], T0 + DT * k0), polarity=other, seed_snap=0.5)
    assert caught.value.seed == (INLINES[6], XLINES[8], T0 + DT * k0)
    near = caught.value.nearest
    assert near[0] in INLINES and near[1] in XLINES and T0 <= near[2] <= T0 + DT * 63
    assert f"seed ({INLINES[6]}, {XLINES[8]}, {T0 + DT * k0:g})" in str(caught.value)
    dead = cube.copy(data=cube.values.copy())
    dead[6, 8] = 0.0
    with pytest.raises(SeedError, match=f"on a dead trace; move the seed to a live trace, e.g. \\({INLINES[5]}, "
                                        f"{XLINES[8]}|{INLINES[7]}, {XLINES[8]}|{INLINES[6]}, {XLINES[7]}|"
                                        f"{INLINES[6]}, {XLINES[9]}"):
        track_horizon(dead, (INLINES[6], XLINES[8], T0 + DT * k0), polarity=pol)


def test_a_line_takes_inline_crossline_time_seeds(generated):
    syn, cube, truth, pol = generated
    line = cube.isel(iline=6)
    k0 = float(truth[6, 8])
    three = track_horizon(line, (INLINES[6], XLINES[8], T0 + DT * k0), polarity=pol)
    two = track_horizon(line, (XLINES[8], T0 + DT * k0), polarity=pol)
    assert_array_equal(three.times.values, two.times.values)
    with pytest.raises(InputError, match=f"iline {INLINES[7]} is not the line's iline \\({INLINES[6]}\\)"):
        track_horizon(line, (INLINES[7], XLINES[8], T0 + DT * k0), polarity=pol)


@pytest.mark.slow
def test_penobscot_line_through_seismo3d_open_writes_the_jobs_rows(data_dir, tmp_path):
    """Penobscot crossline 1155 opened by seismo3d.open, tracked from the guide's seed (inline 1300, crossline 1155,
    2040 ms) without faults: the rows of `seismo3d horizon --no-faults`, byte for byte."""
    import seismo3d
    from seismo3d.data import fetch
    from seismo3d.jobs.horizon import run_horizon_job

    path = fetch("seismic/penobscot_xl1155.sgy")
    line = seismo3d.open(path)
    horizon = track_horizon(line, (1300, 1155, 2040.0))
    assert horizon.times.dims == ("iline",) and int(horizon.times["xline"]) == 1155
    write_horizon_text(tmp_path / "labelled.txt", horizon)
    run_horizon_job(path, [(1300, 1155, 2040.0)], tmp_path / "job.txt", faults=False, progress=False)
    assert (tmp_path / "labelled.txt").read_text() == (tmp_path / "job.txt").read_text()
