"""Lazy cubes: the dask array of a SEG-Y file equals read_segy value for value, in either trace order, on the
threaded scheduler and on a dask.distributed cluster; 2D lines and foreign Zarr stores are refused."""

import pickle
import shutil
import warnings

import dask
import numpy as np
import pytest
import segyio
from numpy.testing import assert_array_equal

from seismo3d.errors import InputError, SegyFormatError, SegyGeometryError
from seismo3d.seismic.io import read_segy
from seismo3d.seismic.io.lazy import SegyGrid, inline_block_size, open_lazy, read_segy_block, read_segy_block_headers

SHAPE = (13, 11, 40)  # inlines, crosslines, samples


@pytest.fixture(scope="module")
def amplitudes():
    return np.random.default_rng(7).standard_normal(SHAPE).astype(np.float32)


@pytest.fixture(scope="module", params=[("inline", 5), ("crossline", 1), ("crossline", 5)],
                ids=["inline-sorted", "crossline-sorted", "crossline-sorted-ieee"])
def segy(request, amplitudes, tmp_path_factory, write_segy_cube):
    sorting, fmt = request.param
    return write_segy_cube(tmp_path_factory.mktemp(sorting) / "cube.sgy", amplitudes, sorting=sorting, fmt=fmt)


def test_lazy_segy_equals_read_segy(segy):
    ref, cube = read_segy(segy)
    lazy = open_lazy(segy, chunk_mb=3 * 11 * 40 * 4 / 2**20)  # 3 inlines per chunk
    assert lazy.format == "segy" and lazy.source == segy and lazy.sample_unit == "ms"
    assert lazy.data.dtype == np.float32 and lazy.shape == SHAPE
    assert lazy.data.chunks == ((3, 3, 3, 3, 1), (11,), (40,))
    assert_array_equal(lazy.inlines, cube.inlines)
    assert_array_equal(lazy.xlines, cube.xlines)
    assert_array_equal(lazy.samples, cube.samples)
    assert lazy.sample_interval == 4.0
    with dask.config.set(scheduler="threads"):
        assert_array_equal(lazy.data.compute(), ref)
        assert_array_equal(lazy.data[4:8, 2:5].compute(), ref[4:8, 2:5])  # reads only chunks 1 and 2


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
    lazy = open_lazy(segy, chunk_mb=0.01)
    restored = pickle.loads(pickle.dumps(lazy.data))
    assert_array_equal(restored.compute(scheduler="sync"), read_segy(segy)[0])


@pytest.mark.slow
def test_distributed_cluster_of_processes(segy):
    """On a dask.distributed cluster whose worker is another process (the file opened there, by path)."""
    distributed = pytest.importorskip("distributed")
    lazy = open_lazy(segy, chunk_mb=0.01)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cl, \
            distributed.Client(cl) as client:
        assert_array_equal(client.compute(lazy.data).result(), read_segy(segy)[0])


def test_real_f3_crop(data_dir):
    from seismo3d.data import fetch

    path = fetch("seismic/f3_crop.sgy")
    ref, cube = read_segy(path)
    lazy = open_lazy(path, chunk_mb=0.05)
    assert len(lazy.data.chunks[0]) > 1 and lazy.data.chunks[1:] == ((cube.xlines.size,), (cube.samples.size,))
    assert_array_equal(lazy.data.compute(), ref)
    assert_array_equal(lazy.inlines, cube.inlines)


@pytest.mark.parametrize("along", ["inline", "crossline"])
def test_2d_line_is_refused(along, amplitudes, tmp_path, write_segy_cube):
    line = amplitudes[:, :1] if along == "inline" else amplitudes[:1]
    path = write_segy_cube(tmp_path / "line.sgy", line)
    with pytest.raises(SegyGeometryError, match="chunked processing needs a 3D cube"):
        open_lazy(path)


def test_trace_list_is_refused(amplitudes, tmp_path, write_segy_cube):
    path = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    headers = np.memmap(path, dtype=np.uint8, mode="r+", offset=3600).reshape(-1, 240 + SHAPE[2] * 4)
    headers[:, 188:196] = 0  # no inline / crossline numbers (bytes 189-196): a trace list with CDP coordinates
    headers.flush()
    del headers
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no TraceListWarning on top of the error
        with pytest.raises(SegyGeometryError, match="needs a 3D cube"):
            open_lazy(path)


def test_changed_file_is_reported(amplitudes, tmp_path, write_segy_cube):
    path = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    lazy = open_lazy(path)
    with open(path, "r+b") as fh:  # cut the last trace off after the geometry was read
        fh.truncate(path.stat().st_size - (240 + SHAPE[2] * 4))
    with pytest.raises(SegyFormatError, match="open it again"):
        lazy.data.compute(scheduler="sync")


def test_foreign_zarr_and_folders_are_refused(tmp_path):
    zarr = pytest.importorskip("zarr")
    zarr.open_group(str(tmp_path / "other.zarr"), mode="w", zarr_format=3).create_array("x", shape=(2,), dtype="f4")
    with pytest.raises(InputError, match="not a seismic Zarr store written by 'seismo3d convert'"):
        open_lazy(tmp_path / "other.zarr")
    (tmp_path / "folder").mkdir()
    with pytest.raises(InputError, match="seismo3d convert INPUT.sgy folder"):
        open_lazy(tmp_path / "folder")
    shutil.rmtree(tmp_path / "folder")


@pytest.mark.parametrize("chunk_mb", [0, -1, float("nan"), "big"])
def test_bad_chunk_size(chunk_mb, segy):
    with pytest.raises(InputError, match="chunk_mb"):
        open_lazy(segy, chunk_mb=chunk_mb)


def test_inline_block_size():
    assert inline_block_size(100, 250, 1) == 10  # 1 MiB / (100 * 250 * 4 bytes) = 10.49 inlines
    assert inline_block_size(1000, 2000, 1) == 1  # at least one inline


def test_tiles_equal_inline_blocks(write_segy_cube, tmp_path):
    """Chunks of 16 x 16 traces (partial at the far edges) read the same amplitudes as blocks of whole inlines."""
    cube = np.random.default_rng(3).standard_normal((40, 35, 12)).astype(np.float32)
    for sorting in ("inline", "crossline"):
        path = write_segy_cube(tmp_path / f"{sorting}.sgy", cube, sorting=sorting)
        lazy = open_lazy(path, tile=16)
        assert lazy.data.chunks[:2] == ((16, 16, 8), (16, 16, 3))
        np.testing.assert_array_equal(lazy.data.compute(), cube)
        np.testing.assert_array_equal(lazy.data[5:30, 10:20].compute(), cube[5:30, 10:20])
