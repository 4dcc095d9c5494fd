"""Tests of SEG-Y, raw-section and ASCII reading and of SEG-Y writing, on the real files of the data directory."""

import hashlib
import os
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest
import segyio
from numpy.testing import assert_allclose, assert_array_equal

from seismo3d.errors import DataNotFoundError, InputError, SegyFormatError, SegyGeometryError, TraceListWarning
from seismo3d.seismic.io import (SeismicCube, open_segy, read_ascii_lines, read_section, read_segy,
                                 write_like)


@pytest.fixture(scope="module")
def seismic_dir():
    root = os.environ.get("SEISMO3D_DATA_DIR")
    if not root:
        pytest.skip("SEISMO3D_DATA_DIR is not set")
    return Path(root) / "seismic"


@pytest.fixture(scope="module")
def f3(seismic_dir):
    return seismic_dir / "f3_crop.sgy"


def _sha(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


# --- reading --------------------------------------------------------------------------------------------------------
def test_f3_geometry_and_values(f3):
    with open_segy(f3) as cube:
        assert isinstance(cube, SeismicCube)
        assert_array_equal(cube.inlines, np.arange(111, 134))
        assert_array_equal(cube.xlines, np.arange(875, 893))
        assert_allclose(cube.samples, 4.0 + 4.0 * np.arange(75))
        assert cube.sample_interval == 4.0 and cube.sample_unit == "ms"
        assert cube.format == 3 and cube.format_name == "2-byte signed integer"
        assert cube.sorting == "inline" and cube.is_3d and cube.shape == (23, 18, 75) and cube.n_traces == 414
        data = cube.read()
        assert data.dtype == np.float32 and data.shape == cube.shape
        assert_array_equal(cube.inline(120), data[9])
        assert_array_equal(cube.xline(880), data[:, 5])
        assert_array_equal(cube.time_slice(30), data[:, :, 30])
        assert_array_equal(cube.traces[18 * 2 + 3], data[2, 3])
        assert_array_equal(cube.traces[5:9], data.reshape(-1, 75)[5:9])
        assert_array_equal(cube.traces[[0, 413]], data.reshape(-1, 75)[[0, 413]])
        # coordinate scalar -10 divides: raw CDP_X 6201972 -> 620197.2
        assert cube.cdp_x.shape == (23, 18)
        h = cube.segyfile.header[0]
        assert h[segyio.TraceField.SourceGroupScalar] == -10
        assert_allclose(cube.cdp_x[0, 0], h[segyio.TraceField.CDP_X] / 10.0)
        assert_allclose(cube.cdp_y[0, 0], h[segyio.TraceField.CDP_Y] / 10.0)
    with segyio.open(str(f3)) as f:
        assert_array_equal(data, segyio.tools.cube(f).astype(np.float32))


def test_open_without_mmap_reads_the_same(f3, seismic_dir):
    """mmap=False (file reads: a pass over every header does not map the whole file) reads the same traces,
    coordinates and lines as the default memory-mapped file, a grid and a trace list alike."""
    for path in (f3, seismic_dir / "volve_fullstack_twt_arbline.sgy"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TraceListWarning)
            with open_segy(path) as mapped, open_segy(path, mmap=False) as read:
                assert_array_equal(read.read(), mapped.read())
                assert_array_equal(read.cdp_x, mapped.cdp_x)
                assert_array_equal(read.cdp_y, mapped.cdp_y)
                assert (read.inlines is None) == (mapped.inlines is None)
                if mapped.inlines is not None:
                    assert_array_equal(read.inlines, mapped.inlines)
                    assert_array_equal(read.xlines, mapped.xlines)


def test_f3_alternative_header_bytes(f3):
    # F3 also stores the inline in bytes 9 (field record) and the crossline in bytes 21 (CDP)
    with open_segy(f3, iline=9, xline=21) as cube:
        assert_array_equal(cube.inlines, np.arange(111, 134))
        assert_array_equal(cube.xlines, np.arange(875, 893))


def test_wrong_header_bytes_raise_geometry_error(f3):
    with pytest.raises(SegyGeometryError, match="ignore_geometry=True") as err:
        open_segy(f3, iline=9, xline=13)
    assert "iline=189, xline=193 (23 inlines x 18 crosslines)" in str(err.value)  # the working bytes are suggested
    assert err.value.__cause__ is not None
    with pytest.raises(InputError, match="iline"):
        open_segy(f3, iline=190)


def test_penobscot_crossline_is_a_2d_line(seismic_dir):
    with open_segy(seismic_dir / "penobscot_xl1155.sgy") as cube:
        assert cube.shape == (601, 1, 1501) and not cube.is_3d
        assert_array_equal(cube.inlines, np.arange(1000, 1601)) and cube.xlines.tolist() == [1155]
        assert cube.format == 1 and cube.sorting == "crossline"
        assert_allclose(cube.samples[[0, -1]], [0.0, 6000.0]) and cube.sample_unit == "ms"
        section = cube.xline(1155)
        assert section.shape == (601, 1501) and section.dtype == np.float32
        data = cube.read()
        assert_array_equal(data[:, 0], section)
        assert_array_equal(cube.traces[:], section)
        assert_array_equal(cube.inline(1300), data[300])
        assert_array_equal(cube.time_slice(700), data[:, :, 700])
        assert np.abs(section).max() > 0


def test_volve_depth_cube_ieee(seismic_dir):
    path = seismic_dir / "volve_migvel_depth_sub3d.sgy"
    with open_segy(path, sample_unit="m") as cube:
        assert cube.shape == (18, 52, 226) and cube.format == 5 and cube.sample_unit == "m"
        assert_array_equal(cube.inlines, np.arange(10087, 10156, 4))
        assert_array_equal(cube.xlines, np.arange(2148, 2353, 4))
        assert_allclose(cube.samples, 20.0 * np.arange(226))
        v = cube.read()
        assert 1400 < v.min() and v.max() < 5400  # interval velocity, m/s (textual header: 1480-5313)
        assert cube.cdp_x[0, 0] == pytest.approx(436415.70, abs=0.01)  # scalar -100
    # SEG-Y rev1 has no time/depth flag and this textual header speaks of "Time": the default unit is ms
    with open_segy(path) as cube:
        assert cube.sample_unit == "ms"


def test_unsorted_arbitrary_line(seismic_dir):
    # no inline / crossline numbers (bytes 189 / 193 hold 0), CDP numbers 1-225: read as a trace list, one line says so
    path = seismic_dir / "volve_fullstack_twt_arbline.sgy"
    with pytest.warns(TraceListWarning) as record:
        open_segy(path).close()
    assert len(record) == 1
    message = str(record[0].message)
    assert "\n" not in message and "trace list of 225 traces" in message and "CDP 1-225" in message
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # asked for: no warning
        cube = open_segy(path, ignore_geometry=True)
    with cube:
        assert cube.kind == "trace list" and "2D or arbitrary line" in cube.description
        assert cube.shape == (225, 850) and cube.inlines is None and cube.sorting is None and not cube.is_3d
        data = cube.read()
        assert data.shape == (225, 850) and data.dtype == np.float32
        assert_array_equal(cube.traces[100], data[100])
        assert cube.cdp_x.shape == (225,) and cube.cdp_x[0] == pytest.approx(434245.37)
        for call in (lambda: cube.inline(1), lambda: cube.xline(1), lambda: cube.time_slice(0)):
            with pytest.raises(SegyGeometryError, match="cube.traces"):
                call()


def test_read_segy_and_closed_cube(f3):
    data, cube = read_segy(f3)
    assert data.shape == cube.shape == (23, 18, 75)
    assert cube.cdp_x.shape == (23, 18)  # loaded before closing
    with pytest.raises(InputError, match="closed"):
        cube.read()


def test_bad_requests(f3):
    with open_segy(f3) as cube:
        with pytest.raises(InputError, match="111..133"):
            cube.inline(5)
        with pytest.raises(InputError, match="875..892"):
            cube.xline(5)
        with pytest.raises(InputError):
            cube.time_slice(75)
        with pytest.raises(IndexError):
            cube.traces[414]
    with pytest.raises(InputError):
        open_segy(f3, sample_unit="s")


@pytest.mark.parametrize("make, reason", [
    ("text", "is not SEG-Y: its binary header holds no sample format code"),
    ("empty", "has 0 bytes, fewer than the 3600 bytes"),
    ("truncated", "is not a whole number of traces: 161360 bytes after the headers make 413 traces of 390 bytes"),
    ("half", "the file is cut short"),
    ("header_only", "has no traces: the file ends after its headers"),
])
def test_not_segy_or_truncated(f3, tmp_path, make, reason):
    raw = f3.read_bytes()
    content = {"text": b"inline xline amplitude\n" * 500, "empty": b"", "truncated": raw[:-100],
               "half": raw[: len(raw) // 2], "header_only": raw[:3600]}[make]
    path = tmp_path / f"{make}.sgy"
    path.write_bytes(content)
    for kwargs in ({}, {"ignore_geometry": True}):
        with pytest.raises(SegyFormatError, match=reason) as err:
            open_segy(path, **kwargs)
        assert "\n" not in str(err.value) and str(err.value).startswith(f"{make}.sgy ")


def test_missing_file(tmp_path):
    with pytest.raises(DataNotFoundError):
        open_segy(tmp_path / "nope.sgy")
    with pytest.raises(DataNotFoundError):
        open_segy(tmp_path)


# --- writing --------------------------------------------------------------------------------------------------------
def _assert_same_headers(a_path, b_path, endian_a="big"):
    with segyio.open(str(a_path), ignore_geometry=True, endian=endian_a) as a, \
            segyio.open(str(b_path), ignore_geometry=True) as b:
        assert a.tracecount == b.tracecount
        assert a.text[0] == b.text[0]
        assert all(dict(a.header[i]) == dict(b.header[i]) for i in range(a.tracecount))
        bin_a, bin_b = dict(a.bin), dict(b.bin)
        assert bin_b.pop(segyio.BinField.Format) == 5
        bin_a.pop(segyio.BinField.Format)
        assert bin_a == bin_b


def test_write_like_f3_round_trip(f3, tmp_path):
    before = _sha(f3)
    data, cube = read_segy(f3)
    attr = (data / 1000.0 + 0.125).astype(np.float32)  # not representable as int16: needs the IEEE format
    out = write_like(f3, tmp_path / "attr.sgy", attr)
    assert out == tmp_path / "attr.sgy"
    back, geom = read_segy(out)
    assert_array_equal(back, attr)
    assert_array_equal(geom.inlines, cube.inlines)
    assert_array_equal(geom.xlines, cube.xlines)
    assert_array_equal(geom.samples, cube.samples)
    assert geom.format == 5 and geom.sorting == cube.sorting
    assert_array_equal(geom.cdp_x, cube.cdp_x)
    _assert_same_headers(f3, out)
    assert _sha(f3) == before  # the template is never modified
    assert sorted(p.name for p in tmp_path.iterdir()) == ["attr.sgy"]  # no temporary file left


@pytest.mark.parametrize("name,kw", [("penobscot_xl1155.sgy", {}),
                                     ("volve_fullstack_twt_arbline.sgy", {"ignore_geometry": True})])
def test_write_like_lines_per_trace(seismic_dir, tmp_path, name, kw):
    src = seismic_dir / name
    with open_segy(src, **kw) as cube:
        traces = cube.traces[:]
    out = write_like(src, tmp_path / name, -traces, **kw)  # (n_traces, n_samples) in file order
    with open_segy(out, **kw) as back:
        assert_array_equal(back.traces[:], -traces)
        assert back.shape == cube.shape
    _assert_same_headers(src, out)


def test_write_like_refuses_template_and_bad_data(f3, tmp_path):
    template = tmp_path / "t.sgy"
    shutil.copy(f3, template)
    before = _sha(template)
    data, _ = read_segy(template)
    with pytest.raises(InputError, match="template"):
        write_like(template, tmp_path / "." / "t.sgy", data)
    link = tmp_path / "link.sgy"
    link.symlink_to(template)
    with pytest.raises(InputError, match="template"):
        write_like(template, link, data)
    with pytest.raises(InputError, match="shape"):
        write_like(template, tmp_path / "o.sgy", data[:, :, :10])
    bad = data.copy()
    bad[0, 0, 0] = np.nan
    with pytest.raises(InputError, match="NaN"):
        write_like(template, tmp_path / "o.sgy", bad)
    with pytest.raises(InputError, match="does not exist"):
        write_like(template, tmp_path / "missing" / "o.sgy", data)
    assert _sha(template) == before
    assert not (tmp_path / "o.sgy").exists()


def test_write_like_interrupted_leaves_old_output(f3, tmp_path, monkeypatch):
    data, _ = read_segy(f3)
    out = tmp_path / "attr.sgy"
    out.write_bytes(b"previous finished result")

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "replace", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_like(f3, out, data)
    assert out.read_bytes() == b"previous finished result"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["attr.sgy"]


# --- raw sections and ASCII lines ------------------------------------------------------------------------------------
SECTIONS = {"campos_gx373": (550, 300), "costarica_gx808": (825, 210), "costarica_gx809": (825, 210),
            "f3_f3d75s": (440, 222), "teapot_tpd": (357, 315), "teapot_tp73": (357, 240),
            "f3_f3d178sub2": (951, 242)}


@pytest.mark.parametrize("stem", sorted(SECTIONS))
def test_read_section_known_shapes(seismic_dir, stem):
    path = seismic_dir / "sections" / f"{stem}.f32be"
    sec = read_section(path)
    assert sec.shape == SECTIONS[stem] and sec.dtype == np.float32 and sec.dtype.isnative
    assert_array_equal(sec, np.fromfile(path, ">f4").reshape(SECTIONS[stem]))
    assert np.all(np.isfinite(sec)) and sec.std() > 0


def test_known_section_shape_by_name():
    from seismo3d.seismic.io.sections import known_section_shape

    assert {stem: known_section_shape(f"/any/folder/{stem}.f32be") for stem in SECTIONS} == SECTIONS
    assert known_section_shape("mysection.f32be") is None


def test_read_section_unknown_file(seismic_dir, tmp_path):
    path = tmp_path / "line.f32be"
    shutil.copy(seismic_dir / "sections" / "campos_gx373.f32be", path)
    with pytest.raises(InputError, match="n_traces"):
        read_section(path)
    assert read_section(path, n_traces=550).shape == (550, 300)
    assert read_section(path, n_samples=300).shape == (550, 300)
    assert read_section(path, n_traces=550, n_samples=300).shape == (550, 300)
    with pytest.raises(InputError, match="shape"):
        read_section(path, n_traces=500, n_samples=300)
    with pytest.raises(InputError):
        read_section(path, n_traces=7)
    (tmp_path / "odd.f32be").write_bytes(b"123")
    with pytest.raises(InputError, match="truncated"):
        read_section(tmp_path / "odd.f32be", n_traces=1)


@pytest.mark.parametrize("stem", sorted(SECTIONS))
def test_read_section_refuses_its_shape_swapped(seismic_dir, tmp_path, stem):
    """Each real section copied under an unknown name and read with its numbers of traces and samples swapped: refused
    before the read is used, naming the shape whose neighbouring traces look alike (the right one); its right shape
    read. The threshold was chosen on campos_gx373 and costarica_gx808; the other sections are the check."""
    n_traces, n_samples = SECTIONS[stem]
    path = tmp_path / "line.f32be"
    shutil.copy(seismic_dir / "sections" / f"{stem}.f32be", path)
    with pytest.raises(InputError, match=rf"read as {n_samples} traces of {n_traces} samples .* pass "
                                         rf"n_samples={n_samples}$"):
        read_section(path, n_samples=n_traces)
    with pytest.raises(InputError, match=rf"pass n_traces={n_traces}$"):
        read_section(path, n_traces=n_samples)
    assert read_section(path, n_samples=n_samples).shape == (n_traces, n_samples)


def test_trace_length_correlations_of_a_generated_section():
    """A generated section (reflectors continuous along its traces): its neighbouring traces correlate at its own
    trace length, hardly at the swapped one; white noise correlates at no length."""
    from seismo3d.data.synthetic import synthetic_cube
    from seismo3d.seismic.io.sections import trace_length_correlations

    section = synthetic_cube((120, 90), seed=3).cube
    r = trace_length_correlations(section.ravel())
    assert max(r, key=r.get) == 90 and r[90] > 0.8 and abs(r[120]) < 0.2, (r[90], r[120])
    noise = trace_length_correlations(np.random.default_rng(0).standard_normal(120 * 90))
    assert max(abs(v) for v in noise.values()) < 0.05
    assert all(120 * 90 % m == 0 and 32 <= m <= 120 * 90 // 8 for m in r)


def test_read_ascii_lines(seismic_dir, tmp_path):
    path = seismic_dir / "f3_inline362.ascii"
    il, xl, traces = read_ascii_lines(path)
    assert il.dtype == np.int32 and np.all(il == 362)
    assert_array_equal(xl, np.arange(300, 1251))
    assert traces.shape == (951, 463) and traces.dtype == np.float32
    first = path.read_text().splitlines()[0].split()
    assert_array_equal(traces[0], np.array(first[2:], dtype=np.float32))
    bad = tmp_path / "bad.ascii"
    bad.write_text("362 300 1 2 3\n362 301 1 2\n")
    with pytest.raises(InputError):
        read_ascii_lines(bad)
    bad.write_text("362.5 300 1 2 3\n")
    with pytest.raises(InputError, match="integer"):
        read_ascii_lines(bad)


def _small_segy(path, *, text, endian="big", fmt=5):
    spec = segyio.spec()
    spec.iline, spec.xline = 189, 193
    spec.ilines, spec.xlines, spec.offsets = [1, 2, 3], [10, 11], [1]
    spec.samples = np.arange(20) * 5.0
    spec.sorting = segyio.TraceSortingFormat.INLINE_SORTING
    spec.format = fmt
    spec.endian = endian
    data = np.arange(6 * 20, dtype=np.float32).reshape(6, 20)
    with segyio.create(str(path), spec) as f:
        f.text[0] = segyio.tools.create_text_header({1: text})
        for i, (il, xl) in enumerate([(a, b) for a in (1, 2, 3) for b in (10, 11)]):
            f.header[i] = {segyio.TraceField.INLINE_3D: il, segyio.TraceField.CROSSLINE_3D: xl}
            f.trace[i] = data[i]
        f.bin.update({segyio.BinField.Interval: 5000})
    return data.reshape(3, 2, 20)


def test_sample_unit_from_textual_header(tmp_path):
    _small_segy(tmp_path / "z.sgy", text="PSDM DEPTH VOLUME, SAMPLE INTERVAL 5 M")
    _small_segy(tmp_path / "t.sgy", text="PSTM TWT VOLUME")
    _small_segy(tmp_path / "tz.sgy", text="Trace start time/depth: bytes 109-110")
    with open_segy(tmp_path / "z.sgy") as z, open_segy(tmp_path / "t.sgy") as t, open_segy(tmp_path / "tz.sgy") as tz:
        assert (z.sample_unit, t.sample_unit, tz.sample_unit) == ("m", "ms", "ms")
        assert_allclose(z.samples, 5.0 * np.arange(20))
    with open_segy(tmp_path / "t.sgy", sample_unit="m") as t:
        assert t.sample_unit == "m"


def test_little_endian_file(tmp_path):
    path = tmp_path / "le.sgy"
    expected = _small_segy(path, text="little-endian test", endian="little")
    for endian in (None, "little"):  # detected from the binary header, or given
        with open_segy(path, endian=endian) as cube:
            assert cube.shape == (3, 2, 20) and cube.endian == "little"
            assert cube.layout.endian_from == ("format code" if endian is None else "given")
            assert_array_equal(cube.read(), expected)
    with pytest.raises(SegyFormatError, match="it reads as little-endian .*omit endian .*or pass endian='little'"):
        open_segy(path, endian="big")
    out = write_like(path, tmp_path / "le_out.sgy", expected * 2)  # written big-endian, the standard's byte order
    with open_segy(out) as back:
        assert back.endian == "big" and back.shape == (3, 2, 20)
        assert_array_equal(back.read(), expected * 2)
    _assert_same_headers(path, out, endian_a="little")


def _segyio_copy(template, values, path):
    """segyio's copy-a-file recipe: ``template``'s headers (format 5, big-endian) with ``values`` as its traces."""
    with open_segy(template) as cube:
        traces, endian = cube._to_traces(values), cube.endian
    with segyio.open(str(template), ignore_geometry=True, endian=endian) as src:
        spec = segyio.tools.metadata(src)
        spec.format, spec.endian = 5, "big"
        with segyio.create(str(path), spec) as dst:
            dst.text[0] = src.text[0]
            dst.bin = src.bin
            dst.bin.update({segyio.BinField.Format: 5})
            dst.header = src.header
            for i in range(src.tracecount):
                dst.trace[i] = traces[i]
    return path.read_bytes()


@pytest.mark.parametrize("name", ["f3.sgy", "f3-lsb.sgy"])
def test_written_files_equal_segyios_header_copy(tmp_path, name, data_dir):
    """Both writers write the traces themselves, the headers from the template's bytes (byte-swapped per field from
    a little-endian one): the file is byte for byte the one segyio's field-by-field copy writes."""
    from seismo3d.data import fetch
    from seismo3d.seismic.io import write_like_blocks

    template = fetch(f"seismic/segyio_test_data/{name}")
    with open_segy(template) as cube:
        values = np.random.default_rng(0).random(cube.shape, dtype=np.float32)
    expected = _segyio_copy(template, values, tmp_path / "segyio.sgy")
    assert write_like(template, tmp_path / "a.sgy", values).read_bytes() == expected
    assert write_like_blocks(template, tmp_path / "b.sgy", values, inlines_per_block=5).read_bytes() == expected


def test_written_crossline_sorted_file_equals_segyios_copy(tmp_path, write_segy_cube):
    """A crossline-sorted IBM-float template: the blocks of inlines are scattered runs of single traces in the file,
    written in place; both writers' files are byte for byte segyio's copy."""
    from seismo3d.seismic.io import write_like_blocks

    values = np.random.default_rng(1).random((7, 5, 12), dtype=np.float32)
    template = write_segy_cube(tmp_path / "xl.sgy", values, sorting="crossline", fmt=1)
    expected = _segyio_copy(template, values[::-1] * 3, tmp_path / "segyio.sgy")
    assert write_like(template, tmp_path / "a.sgy", values[::-1] * 3).read_bytes() == expected
    assert write_like_blocks(template, tmp_path / "b.sgy", values[::-1] * 3, inlines_per_block=2).read_bytes() \
        == expected
