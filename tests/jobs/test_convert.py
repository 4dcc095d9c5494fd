"""The convert job: a 3D SEG-Y into the Zarr v3 layout that xarray opens as is; round trip to the SEG-Y's amplitudes,
coordinates and headers; atomic output (an interrupted convert leaves no OUTPUT); refusals."""

import contextlib
import re
import shutil

import numpy as np
import pytest
import segyio
from numpy.testing import assert_allclose, assert_array_equal

import seismo3d
import seismo3d.jobs.convert as convert_job
from seismo3d.errors import InputError, SegyGeometryError
from seismo3d.jobs.convert import run_convert_job
from seismo3d.seismic.io import read_segy

xr = pytest.importorskip("xarray")

SHAPE = (70, 66, 12)  # > 64 inlines and crosslines: 2 x 2 chunks of 64 x 64 traces, edge chunks partial


@pytest.fixture(scope="module")
def amplitudes():
    return np.random.default_rng(3).standard_normal(SHAPE).astype(np.float32)


@pytest.fixture(scope="module", params=["inline", "crossline"])
def converted(request, amplitudes, tmp_path_factory, write_segy_cube):
    """(SEG-Y path, store path, ConvertResult), one tile per 64 x 64 chunk (chunk_mb below one chunk)."""
    folder = tmp_path_factory.mktemp(request.param)
    src = write_segy_cube(folder / "cube.sgy", amplitudes, sorting=request.param, fmt=1)
    result = run_convert_job(src, folder / "cube.zarr", chunk_mb=0.01)
    return src, folder / "cube.zarr", result


def _no_temporaries(folder):
    return [p.name for p in folder.iterdir() if p.name.startswith(".")]


@pytest.mark.slow
def test_xarray_opens_the_store_as_is(converted):
    src, store, result = converted
    ref, cube = read_segy(src)
    ds = xr.open_zarr(store)
    assert ds.seismic.dims == ("inline", "crossline", "sample") and ds.seismic.dtype == np.float32
    assert_array_equal(ds.seismic.values, ref)
    assert_array_equal(ds.inline.values, cube.inlines)
    assert_array_equal(ds.crossline.values, cube.xlines)
    assert_array_equal(ds.sample.values, cube.samples)
    assert ds.sample.attrs["units"] == "ms"
    # headers: CDP_X as written (centimetres), cdp_x with the scalar -100 applied (metres), as SeismicCube.cdp_x
    i, j = np.meshgrid(np.arange(SHAPE[0]), np.arange(SHAPE[1]), indexing="ij")
    assert ds.CDP_X.dims == ("inline", "crossline")
    assert_array_equal(ds.CDP_X.values, 60_500_000 + 2500 * i + 7 * j)
    assert_array_equal(ds.INLINE_3D.values, cube.inlines[:, None] + 0 * j)
    assert_allclose(ds.cdp_x.values, cube.cdp_x, rtol=0, atol=1e-9)
    assert_allclose(ds.cdp_y.values, 6_073_000 + 25.0 * j, rtol=0, atol=1e-9)
    assert {"cdp_x", "cdp_y"} <= set(ds.seismic.coords)
    # the fields that are zero on every trace are not stored
    assert "SourceX" not in ds and "CDP_X" in result.header_fields and "SourceX" not in result.header_fields
    assert ds.attrs["text_header"].startswith("C 1 seismo3d generated cube")
    assert ds.attrs["binary_header"]["Samples"] == SHAPE[2] and ds.attrs["binary_header"]["Interval"] == 4000
    assert ds.attrs["seismo3d"]["layout"] == "seismic-zarr"
    assert result.shape == SHAPE and result.chunks == (64, 64, SHAPE[2]) and result.has_cdp_coordinates


def test_the_store_opens_as_the_segy(converted):
    src, store, _ = converted
    ref, _ = read_segy(src)
    lazy = seismo3d.open(store, tile=20)
    segy = seismo3d.open(src)
    assert lazy.attrs["kind"] == "store" and lazy.attrs["sample_unit"] == "ms"
    assert lazy.data.chunks == ((20, 20, 20, 10), (20, 20, 20, 6), (SHAPE[2],))  # the store's chunks regrouped
    assert_array_equal(lazy.data.compute(), ref)
    for name in ("iline", "xline", "twt", "cdp_x", "cdp_y"):
        assert_array_equal(lazy[name].values, segy[name].values)


@pytest.mark.slow
def test_progress_one_step_per_tile(amplitudes, tmp_path, write_segy_cube, caplog):
    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    with caplog.at_level("INFO", logger="seismo3d"):
        run_convert_job(src, tmp_path / "out.zarr", chunk_mb=0.01, progress=True)
    assert "convert cube.sgy: 4/4 tile" in caplog.text


@pytest.mark.slow
def test_real_f3_crop(data_dir, tmp_path):
    from seismo3d.data import fetch

    src = fetch("seismic/f3_crop.sgy")
    ref, cube = read_segy(src)
    run_convert_job(src, tmp_path / "f3.zarr")
    ds = xr.open_zarr(tmp_path / "f3.zarr")
    assert_array_equal(ds.seismic.values, ref)
    assert_array_equal(ds.inline.values, cube.inlines)
    assert_allclose(ds.cdp_x.values, cube.cdp_x, rtol=0, atol=1e-9)
    with segyio.open(str(src), "r") as f:
        assert_array_equal(ds.CDP_X.values.ravel(), f.attributes(segyio.TraceField.CDP_X)[:])  # inline-sorted
    assert_array_equal(seismo3d.open(tmp_path / "f3.zarr").data.compute(), ref)


class _Interrupted:
    """progress_steps stand-in raising KeyboardInterrupt (Ctrl-C) after the first tile."""

    def __init__(self):
        self.done = 0

    def advance(self, n=1, status=None):
        self.done += n
        if self.done == 2:
            raise KeyboardInterrupt


@pytest.mark.slow
def test_interrupted_convert_leaves_no_output(amplitudes, tmp_path, write_segy_cube, monkeypatch):
    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    monkeypatch.setattr(convert_job, "progress_steps", lambda *a, **k: contextlib.nullcontext(_Interrupted()))
    with pytest.raises(KeyboardInterrupt):
        run_convert_job(src, tmp_path / "out.zarr", chunk_mb=0.01)
    assert not (tmp_path / "out.zarr").exists()
    assert _no_temporaries(tmp_path) == []


@pytest.mark.slow
def test_interrupted_overwrite_keeps_the_earlier_store(amplitudes, tmp_path, write_segy_cube, monkeypatch):
    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    run_convert_job(src, tmp_path / "out.zarr", chunk_mb=0.01)
    monkeypatch.setattr(convert_job, "progress_steps", lambda *a, **k: contextlib.nullcontext(_Interrupted()))
    with pytest.raises(KeyboardInterrupt):
        run_convert_job(src, tmp_path / "out.zarr", chunk_mb=0.01, overwrite=True)
    assert_array_equal(xr.open_zarr(tmp_path / "out.zarr").seismic.values, amplitudes)
    assert _no_temporaries(tmp_path) == []


def test_failed_background_write_leaves_no_output(amplitudes, tmp_path, write_segy_cube, monkeypatch):
    """A chunk write that fails on a background thread (disk full) ends the convert with its error, whole store
    removed."""
    import seismo3d.seismic.io.zarr_store as zarr_store

    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)

    def disk_full(self, values, *start):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(zarr_store._ChunkFiles, "write", disk_full)
    with pytest.raises(OSError, match="No space left"):
        run_convert_job(src, tmp_path / "out.zarr", chunk_mb=0.01)
    assert not (tmp_path / "out.zarr").exists()
    assert _no_temporaries(tmp_path) == []


def test_amplitudes_are_stored_uncompressed_by_default(converted):
    """The default: no compressor in the array's metadata, and every chunk file the chunk's float32 values as they are
    (little-endian bytes, edge chunks padded with zeros)."""
    import zarr

    _, store, _ = converted
    seismic = zarr.open_group(str(store), mode="r")["seismic"]
    assert seismic.metadata.to_dict()["codecs"] == ({"name": "bytes", "configuration": {"endian": "little"}},)
    values = seismic[:]
    padded = np.zeros((128, 128, SHAPE[2]), "<f4")
    padded[:SHAPE[0], :SHAPE[1]] = values
    for i in range(2):
        for j in range(2):
            raw = (store / "seismic" / "c" / str(i) / str(j) / "0").read_bytes()
            assert raw == padded[64 * i:64 * i + 64, 64 * j:64 * j + 64].tobytes()


@pytest.mark.slow
@pytest.mark.parametrize("compression", ["none", "lz4", "zstd"])
def test_chunk_files_are_the_bytes_zarr_writes(amplitudes, tmp_path, write_segy_cube, compression):
    """convert encodes and writes the amplitude chunks itself (zarr's array API costs a quarter to a half more CPU):
    with each compressor, every chunk file, edge chunks included, holds the bytes zarr's own write of the same values
    gives, under the same key, and the array's metadata names the compressor."""
    import zarr

    from seismo3d.seismic.io.zarr_store import AMPLITUDE_COMPRESSORS

    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    store = tmp_path / "cube.zarr"
    run_convert_job(src, store, chunk_mb=0.01, compression=compression)
    ours = zarr.open_group(str(store), mode="r")["seismic"]
    values = ours[:]
    assert_array_equal(values, amplitudes)
    theirs = zarr.create_array(str(tmp_path / "zarr.zarr"), shape=values.shape, chunks=ours.chunks, dtype="float32",
                               fill_value=0.0, compressors=AMPLITUDE_COMPRESSORS[compression])
    theirs[:] = values
    assert ours.metadata.to_dict()["codecs"] == theirs.metadata.to_dict()["codecs"]
    assert [c["name"] for c in ours.metadata.to_dict()["codecs"]] == ["bytes"] + {"none": [], "lz4": ["blosc"],
                                                                                  "zstd": ["zstd"]}[compression]
    files = sorted(p.relative_to(store / "seismic") for p in (store / "seismic").rglob("*") if p.is_file()
                   and p.name != "zarr.json")
    assert [str(p) for p in files] == ["c/0/0/0", "c/0/1/0", "c/1/0/0", "c/1/1/0"]  # 2 x 2 chunks, 3 at an edge
    for name in files:
        assert (store / "seismic" / name).read_bytes() == (tmp_path / "zarr.zarr" / name).read_bytes(), name


def test_unknown_compression_is_refused(amplitudes, tmp_path, write_segy_cube):
    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    with pytest.raises(InputError, match="compression must be one of 'none', 'lz4', 'zstd'; got 'gzip'"):
        run_convert_job(src, tmp_path / "out.zarr", compression="gzip")
    assert not (tmp_path / "out.zarr").exists() and _no_temporaries(tmp_path) == []


@pytest.mark.slow
def test_existing_output(amplitudes, tmp_path, write_segy_cube):
    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    run_convert_job(src, tmp_path / "out.zarr", chunk_mb=0.01)
    with pytest.raises(InputError, match=r"exists; pass overwrite=True \(--overwrite\) to replace it"):
        run_convert_job(src, tmp_path / "out.zarr")
    changed = write_segy_cube(tmp_path / "changed.sgy", -amplitudes, sorting="crossline")
    run_convert_job(changed, tmp_path / "out.zarr", overwrite=True)
    assert_array_equal(xr.open_zarr(tmp_path / "out.zarr").seismic.values, -amplitudes)
    (tmp_path / "notes").mkdir()
    (tmp_path / "notes" / "keep.txt").write_text("mine")
    with pytest.raises(InputError, match="not a store written by seismo3d convert"):
        run_convert_job(src, tmp_path / "notes", overwrite=True)
    assert (tmp_path / "notes" / "keep.txt").read_text() == "mine"
    assert _no_temporaries(tmp_path) == []


def test_refuses_to_overwrite_the_input(amplitudes, tmp_path, write_segy_cube):
    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    before = src.read_bytes()
    for output in (src, tmp_path):
        with pytest.raises(InputError, match="input"):
            run_convert_job(src, output, overwrite=True)
    assert src.read_bytes() == before


def test_2d_line_is_refused(amplitudes, tmp_path, write_segy_cube):
    src = write_segy_cube(tmp_path / "line.sgy", amplitudes[:1])
    with pytest.raises(SegyGeometryError, match="needs a 3D cube"):
        run_convert_job(src, tmp_path / "line.zarr")
    assert not (tmp_path / "line.zarr").exists() and _no_temporaries(tmp_path) == []


@pytest.mark.parametrize("name, kind", [("cube.npy", "a numpy array (.npy)"), ("cube.zarr", "a Zarr store")])
def test_inputs_of_another_reader_are_refused(converted, amplitudes, tmp_path, name, kind):
    """By the kind seismo3d.open gives the input (a .npy array, a store of convert), before anything is written."""
    src = tmp_path / name
    if name.endswith(".npy"):
        np.save(src, amplitudes)
    else:
        shutil.copytree(converted[1], src)
    with pytest.raises(InputError, match=re.escape(f"{name} is {kind}, not SEG-Y: convert writes a 3D SEG-Y cube")):
        run_convert_job(src, tmp_path / "out.zarr")
    assert not (tmp_path / "out.zarr").exists() and _no_temporaries(tmp_path) == []


def _chunk_files(folder):
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()
            and p.name != "zarr.json"}


def _assert_zarr_writes_the_same(store, tmp_path):
    """Every array of the store written again by zarr's array API from its values (same shape, chunks, dtype, fill
    value and codecs) gives the same chunk files: the same keys (no file for a chunk of fill values) and bytes."""
    import zarr

    group = zarr.open_group(str(store), mode="r")
    names = [name for name, _ in group.arrays()]
    for name in names:
        ours = group[name]
        theirs = zarr.create_array(str(tmp_path / "zarr" / name), shape=ours.shape, chunks=ours.chunks,
                                   dtype=ours.dtype, fill_value=ours.fill_value,
                                   compressors=ours.metadata.to_dict()["codecs"][1:])
        theirs[:] = ours[:]
        assert _chunk_files(store / name) == _chunk_files(tmp_path / "zarr" / name), name
    return names


@pytest.mark.slow
def test_header_and_coordinate_chunks_are_the_bytes_zarr_writes(amplitudes, tmp_path, write_segy_cube):
    """The header fields and cdp_x / cdp_y are written as chunk files on the copy threads (not through zarr's array
    API): each file is the one zarr writes, and a row of zeros (cdp_y of inlines whose CDP Y is 0) has none."""
    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    with segyio.open(src, "r+", ignore_geometry=True) as f:  # CDP Y zero on the first 64 inlines: one row of chunks
        for t in range(64 * SHAPE[1]):
            f.header[t] = {segyio.TraceField.CDP_Y: 0}
    store = tmp_path / "cube.zarr"
    run_convert_job(src, store, chunk_mb=0.01)
    names = _assert_zarr_writes_the_same(store, tmp_path)
    assert {"seismic", "CDP_X", "CDP_Y", "INLINE_3D", "cdp_x", "cdp_y"} <= set(names)
    assert sorted(_chunk_files(store / "cdp_y")) == ["c/1/0"] and sorted(_chunk_files(store / "cdp_x")) == ["c/0/0",
                                                                                                          "c/1/0"]


@pytest.mark.slow
def test_source_coordinates_are_the_bytes_zarr_writes(amplitudes, tmp_path, write_segy_cube):
    """CDP X / Y zero on every trace, source X / Y not: cdp_x / cdp_y from source X / Y, as zarr writes them."""
    src = write_segy_cube(tmp_path / "cube.sgy", amplitudes)
    with segyio.open(src, "r+", ignore_geometry=True) as f:
        for t in range(f.tracecount):
            h = f.header[t]
            f.header[t] = {segyio.TraceField.SourceX: h[segyio.TraceField.CDP_X],
                           segyio.TraceField.SourceY: h[segyio.TraceField.CDP_Y], segyio.TraceField.CDP_X: 0,
                           segyio.TraceField.CDP_Y: 0}
    store = tmp_path / "cube.zarr"
    result = run_convert_job(src, store, chunk_mb=0.01)
    assert result.has_cdp_coordinates and "SourceX" in result.header_fields and "CDP_X" not in result.header_fields
    _assert_zarr_writes_the_same(store, tmp_path)
    ref, cube = read_segy(src)
    assert_allclose(xr.open_zarr(store).cdp_x.values, cube.cdp_x, rtol=0, atol=1e-9)


def test_converting_again_writes_the_same_metadata_files(converted):
    """Every zarr.json of a second conversion of the same SEG-Y equals the first's byte for byte (keys in the same
    order: the consolidated metadata, the attributes, the header fields' arrays made as their rows complete)."""
    src, store, _ = converted
    again = store.with_name("again.zarr")
    run_convert_job(src, again, chunk_mb=0.01)
    first = {str(p.relative_to(store)): p.read_bytes() for p in store.rglob("zarr.json")}
    second = {str(p.relative_to(again)): p.read_bytes() for p in again.rglob("zarr.json")}
    assert len(first) > 5 and first == second
