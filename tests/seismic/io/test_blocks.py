"""SEG-Y read by blocks of traces: the dask array of seismo3d.open (segy_dask_array) equals read_segy value for value,
in either trace order, on the threaded scheduler and on a dask.distributed cluster, its graph holding no open file;
a block's amplitudes and trace headers equal segyio's; a file cut short after opening is reported; foreign Zarr
stores are refused."""

import pickle
import shutil

import dask
import numpy as np
import pytest
import segyio
from numpy.testing import assert_array_equal

import seismo3d
from seismo3d.errors import InputError, SegyFormatError
from seismo3d.seismic.io import read_segy
from seismo3d.seismic.io.blocks import SegyGrid, read_segy_block, read_segy_block_headers

SHAPE = (13, 11, 40)  # inlines, crosslines, samples


@pytest.fixture(scope="module")
def amplitudes():
    return np.random.default_rng(7).standard_normal(SHAPE).astype(np.float32)


@pytest.fixture(scope="module", params=[("inline", 5), ("crossline", 1), ("crossline", 5)],
                ids=["inline-sorted", "crossline-sorted", "crossline-sorted-ieee"])
def segy(request, amplitudes, tmp_path_factory, write_segy_cube):
    sorting, fmt = request.param
    return write_segy_cube(tmp_path_factory.mktemp(sorting) / "cube.sgy", amplitudes, sorting=sorting, fmt=fmt)


@pytest.mark.slow
def test_lazy_segy_equals_read_segy(segy):
    ref, cube = read_segy(segy)
    lazy = seismo3d.open(segy, tile=3)
    assert lazy.attrs["sample_unit"] == "ms" and lazy.attrs["sample_interval"] == 4.0
    assert lazy.data.dtype == np.float32 and lazy.shape == SHAPE
    assert lazy.data.chunks == ((3, 3, 3, 3, 1), (3, 3, 3, 2), (40,))
    assert_array_equal(lazy["iline"].values, cube.inlines)
    assert_array_equal(lazy["xline"].values, cube.xlines)
    assert_array_equal(lazy["twt"].values, cube.samples)
    with dask.config.set(scheduler="threads"):
        assert_array_equal(lazy.data.compute(), ref)
        assert_array_equal(lazy.data[4:8, 2:5].compute(), ref[4:8, 2:5])  # reads only the tiles around it


def test_block_of_inlines_and_crosslines(segy, amplitudes):
    ref, cube = read_segy(segy)
    grid = SegyGrid.from_cube(cube)
    assert grid.sorting in {"inline", "crossline"} and grid.n_traces == 13 * 11
    assert_array_equal(read_segy_block(grid, 2, 9, 3, 7), ref[2:9, 3:7])
    assert_array_equal(read_segy_block(grid, 12, 13), ref[12:13])
    with pytest.raises(InputError, match="inside the grid"):
        read_segy_block(grid, 5, 14)


def _segyio_fields(path, endian="big"):
    """Every trace header field of the file as segyio decodes it, one array per field, in file order."""
    with segyio.open(str(path), "r", ignore_geometry=True, endian=endian) as f:
        return {int(k): f.attributes(int(k))[:] for k in segyio.TraceField.enums()}


def _on_grid(values, grid, sorting):
    return values.reshape(grid) if sorting == "inline" else values.reshape(grid[::-1]).T


def test_block_headers_equal_segyio(segy, tmp_path):
    """Every field of trace headers full of random bytes (but the grid's bytes), decoded as segyio does: 2- and
    4-byte signed integers at their byte positions, on any block of inlines and crosslines."""
    path = shutil.copy(segy, tmp_path / "random_headers.sgy")
    ns = SHAPE[2]
    raw = np.memmap(path, np.uint8, mode="r+", offset=3600, shape=(13 * 11, 240 + 4 * ns))
    keep = np.zeros(240, bool)
    keep[[*range(36, 40), *range(114, 118), *range(188, 196)]] = True  # offset, samples, interval, inline, crossline
    noise = np.random.default_rng(5).integers(0, 256, size=(raw.shape[0], 240), dtype=np.uint8)
    raw[:, :240] = np.where(keep, raw[:, :240], noise)
    raw.flush()
    del raw
    _, cube = read_segy(path)
    grid = SegyGrid.from_cube(cube)
    expected = _segyio_fields(path)
    assert sum(v.min() < 0 for v in expected.values()) > 40  # negative values of 2- and 4-byte fields
    fields = [int(k) for k in segyio.TraceField.enums()]
    for block in [(0, 13, 0, 11), (2, 9, 3, 7), (12, 13, 10, 11)]:
        headers = read_segy_block_headers(grid, fields, *block)
        a, b, c, d = block
        for k in fields:
            assert_array_equal(headers[k], _on_grid(expected[k], (13, 11), grid.sorting)[a:b, c:d], err_msg=str(k))
    with pytest.raises(InputError, match="not trace header fields"):
        read_segy_block_headers(grid, [2], 0, 1)


@pytest.mark.parametrize("name", ["f3-lsb.sgy", "multiformats/Format5lsb.sgy"])
def test_block_little_endian(name, data_dir):
    from seismo3d.data import fetch

    path = fetch(f"seismic/segyio_test_data/{name}")
    ref, cube = read_segy(path, endian="little")
    grid = SegyGrid.from_cube(cube)
    assert grid.endian == "little"
    assert_array_equal(read_segy_block(grid, 3, 20, 2, 17), ref[3:20, 2:17])
    expected = _segyio_fields(path, endian="little")
    headers = read_segy_block_headers(grid, expected, 3, 20, 2, 17)
    shape = (cube.inlines.size, cube.xlines.size)
    for k, values in expected.items():
        assert_array_equal(headers[k], _on_grid(values, shape, grid.sorting)[3:20, 2:17], err_msg=str(k))


def test_graph_holds_no_open_file(segy):
    """Every task of the graph pickles (plain values, no segyio handle) and the array computes after unpickling."""
    lazy = seismo3d.open(segy, tile=4)
    restored = pickle.loads(pickle.dumps(lazy.data))
    assert_array_equal(restored.compute(scheduler="sync"), read_segy(segy)[0])


@pytest.mark.slow
def test_distributed_cluster_of_processes(segy):
    """On a dask.distributed cluster whose worker is another process (the file opened there, by path)."""
    distributed = pytest.importorskip("distributed")
    lazy = seismo3d.open(segy, tile=4)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cl, \
            distributed.Client(cl) as client:
        assert_array_equal(client.compute(lazy.data).result(), read_segy(segy)[0])


def test_real_f3_crop(data_dir):
    from seismo3d.data import fetch

    path = fetch("seismic/f3_crop.sgy")
    ref, cube = read_segy(path)
    lazy = seismo3d.open(path, tile=8)
    assert len(lazy.data.chunks[0]) > 1 and lazy.data.chunks[2] == (cube.samples.size,)
    assert_array_equal(lazy.data.compute(), ref)
    assert_array_equal(lazy["iline"].values, cube.inlines)


def test_changed_file_is_reported(amplitudes, tmp_path, write_segy_cube):
    path = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    lazy = seismo3d.open(path)
    with open(path, "r+b") as fh:  # cut the last trace off after the geometry was read
        fh.truncate(path.stat().st_size - (240 + SHAPE[2] * 4))
    with pytest.raises(SegyFormatError, match="open it again"):
        lazy.data.compute(scheduler="sync")


def test_foreign_zarr_and_folders_are_refused(tmp_path):
    zarr = pytest.importorskip("zarr")
    zarr.open_group(str(tmp_path / "other.zarr"), mode="w", zarr_format=3).create_array("x", shape=(2,), dtype="f4")
    with pytest.raises(InputError, match="not a seismic Zarr store written by 'seismo3d convert'"):
        seismo3d.open(tmp_path / "other.zarr")
    (tmp_path / "folder").mkdir()
    with pytest.raises(InputError, match="seismo3d convert INPUT.sgy folder"):
        seismo3d.open(tmp_path / "folder")
    shutil.rmtree(tmp_path / "folder")
