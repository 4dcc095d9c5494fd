"""SEG-Y conformance: segyio's own test data (equinor/segyio ``test-data/``, 90 files; its README says what each file
tests), fetched through the data registry (``seismic/segyio_test_data/...``, in the data directory; skipped when it
can be neither found there nor downloaded).

Every file is read or refused in one line naming the reason that segyio's README gives for the file; what is read
matches segyio's own reading of the file, opened with the byte order that the file's name states (so the byte order
detection is checked, not assumed); every little-endian twin reads exactly as its big-endian twin and gives the same
fault likelihood; the ``faults`` job reads or refuses every file in one line, without a traceback, and no file is
modified.
"""

from __future__ import annotations

import functools
import hashlib
import re
import warnings

import numpy as np
import pytest
import segyio
from numpy.testing import assert_allclose, assert_array_equal

from seismo3d.data import fetch, file_info, list_files
from seismo3d.errors import (DataNotFoundError, SegyFormatError, SegyGeometryError, Seismo3dError, Seismo3dWarning,
                             TraceListWarning)
from seismo3d.seismic import fault_likelihood, open_segy

PREFIX = "seismic/segyio_test_data/"
NAMES = [name.removeprefix(PREFIX) for name in list_files(PREFIX) if name.endswith((".sgy", ".su"))]

# What each file is, from segyio's test-data/README.md, and what seismo3d must do with it.
SMALL, F3, TINY = (5, 5, 50), (23, 18, 75), (3, 2, 4)  # small.sgy, f3.sgy, tiny.sgy: inlines x crosslines x samples
ROTATED = ("normal", "acute", "right", "obtuse", "straight", "reflex", "left", "inv-acute")  # small.sgy rotated
READ_FORMATS = (1, 2, 3, 5, 6, 8, 9, 10, 11, 12, 16)  # the f3.sgy copies in multiformats/ that segyio decodes
PRESTACK = r"holds prestack gathers \({}\); seismo3d reads post-stack data: stack it first"
REV2_TRACE_HEADERS = (r"is SEG-Y rev 2 with \d additional 240-byte trace header\(s\) per trace .*cannot read; export "
                      "it as SEG-Y rev 1")
EXPECTED = {
    # read with the inline / crossline grid: ("cube", shape)
    **{f"{r}-small.sgy": ("cube", SMALL) for r in ROTATED},
    **{name: ("cube", SMALL) for name in ("small.sgy", "small-lsb.sgy", "text-embed-null.sgy", "小文件.sgy")},
    "f3.sgy": ("cube", F3),
    "f3-lsb.sgy": ("cube", F3),
    **{f"multiformats/Format{c}{e}.sgy": ("cube", F3) for c in READ_FORMATS for e in ("lsb", "msb")},
    "tiny.sgy": ("cube", TINY),
    "stanzas-known-count.sgy": ("cube", TINY),  # 3 extended textual headers, counted in the binary header
    # rev 2.1 layout stanzas in counted extended textual headers, standard trace headers: segyio 1.9 reads them
    **{f"mapping-{m}.sgy": ("cube", TINY) for m in ("default", "invalid-attribute", "invalid-root", "invalid-value",
                                                   "multiple-stanzas", "unparsable")},
    "multi-text.sgy": ("cube", (1, 1, 1)),  # 4 extended textual headers, 1 trace of 1 sample
    "delay-scalar.sgy": ("cube", (1, 1, 251)),
    **{f"interval-{v}.sgy": ("cube", (1, 1, 1)) for v in ("neg-bin-neg-trace", "neg-bin-pos-trace",
                                                          "pos-bin-neg-trace")},
    # no grid at bytes 189 / 193: a trace list, announced by one TraceListWarning: ("trace list", shape)
    "decrement.sgy": ("trace list", (5, 4)),  # header values at their maxima: no grid
    "increment.sgy": ("trace list", (5, 4)),  # header values at their minima
    "long.sgy": ("trace list", (3, 60000)),  # 60000 samples; its "trace headers" are sample values
    "mapping-minimal.sgy": ("trace list", (6, 4)),  # inline / crossline numbers elsewhere (its rev 2.1 mapping)
    "mapping-unsupported-type.sgy": ("trace list", (6, 4)),
    "mapping-shifted.sgy": ("trace list", (6, 4)),  # every header field shifted by one byte
    # refused in one line: (error type, what the line must say)
    **{name: (SegyGeometryError, PRESTACK.format("4 offsets per inline / crossline position"))
       for name in ("1x1.sgy", "1xN.sgy", "Mx1.sgy")},
    **{name: (SegyGeometryError, PRESTACK.format("2 offsets per inline / crossline position"))
       for name in ("small-ps.sgy", "small-ps-dec-il-inc-xl-off.sgy", "small-ps-dec-il-off-inc-xl.sgy",
                    "small-ps-dec-il-xl-inc-off.sgy", "small-ps-dec-il-xl-off.sgy", "small-ps-dec-off-inc-il-xl.sgy",
                    "small-ps-dec-xl-inc-il-off.sgy", "small-ps-dec-xl-off-inc-il.sgy")},
    "shot-gather.sgy": (SegyGeometryError, PRESTACK.format(r"4 field records \(trace header bytes 9-12\) and no CDP "
                                                           "numbers or coordinates")),
    "broken.sgy": (SegyFormatError, "is not a whole number of traces: .*the file is cut short"),
    "mapping-empty.sgy": (SegyFormatError, r"has 1 extended textual header \(the first begins '\(\(SEG:Layout:text/xml"
                                           r"\)\)'\) but binary header bytes 3505-3506 say 0; write 1 there"),
    "text.sgy": (SegyFormatError, r"has no traces: the file ends after its headers \(3600 bytes\)"),
    "stanzas-unknown-count.sgy": (SegyFormatError, r"declares a variable number of extended textual headers \(-1 "
                                                   r".*cannot read; it has 3: write 3 in bytes 3505-3506"),
    **{name: (SegyFormatError, REV2_TRACE_HEADERS)
       for name in ("rotated-small-rev2.sgy", "trace-header-extension1.sgy", "trace-header-extensions.sgy",
                    "mapping-all-types.sgy", "mapping-all-types-lsb.sgy", "mapping-encoding-ext1.sgy",
                    "mapping-encoding-private.sgy", "mapping-mixed-order.sgy", "mapping-no-extension1.sgy")},
    # segyio 1.9 reads a little-endian extended sample count (bytes 3269-3272) big-endian
    **{name: (SegyFormatError, r"is little-endian SEG-Y rev \d+ whose samples per trace are in the extended field "
                               r"\(binary header bytes 3269-3272\), which segyio .* reads in the wrong byte order")
       for name in ("decrement-lsb.sgy", "increment-lsb.sgy")},
    **{f"multiformats/Format{c}{e}.sgy": (SegyFormatError, rf"holds samples in format {c} \(.*\), which segyio .* "
                                                          r"cannot decode; convert it to 4-byte IEEE float")
       for c in (4, 7, 15) for e in ("lsb", "msb")},
    **{name: (SegyFormatError, r"is not SEG-Y: its binary header holds no sample format code .*Seismic Unix")
       for name in ("small.su", "small-lsb.su")},
}

# (big-endian, little-endian) copies of one file; both read, or both refused for the same reason, except the two
# whose little-endian copy segyio cannot read (see EXPECTED)
TWINS = [("f3.sgy", "f3-lsb.sgy"), ("small.sgy", "small-lsb.sgy"),
         ("mapping-all-types.sgy", "mapping-all-types-lsb.sgy"), ("small.su", "small-lsb.su"),
         *[(f"multiformats/Format{c}msb.sgy", f"multiformats/Format{c}lsb.sgy")
           for c in sorted((*READ_FORMATS, 4, 7, 15))]]
SEGYIO_READS_BIG_ONLY = [("decrement.sgy", "decrement-lsb.sgy"), ("increment.sgy", "increment-lsb.sgy")]


def _byte_order_of_name(name: str) -> str:
    return "little" if "lsb" in name else "big"


@functools.lru_cache(maxsize=None)
def _fetch_all():
    """({name: local path}, None), or (None, why not): one attempt per session, even offline."""
    try:
        return {name: fetch(PREFIX + name) for name in NAMES}, None
    except DataNotFoundError as exc:
        return None, str(exc)


@pytest.fixture
def conformance_files():
    """{name: local path} of segyio's test data, through the registry (pooch cache or download)."""
    files, why_not = _fetch_all()
    if files is None:
        pytest.skip(f"segyio's test data is neither cached nor downloadable here: {why_not}")
    return files


def _open(path):
    """open_segy with no options; (cube, the warnings it gave) or the Seismo3dError raised."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            cube = open_segy(path)
        except Seismo3dError as exc:
            return exc, [w.message for w in caught]
    return cube, [w.message for w in caught]


def _segyio_reading(path, endian: str, with_grid: bool) -> dict:
    """What segyio reads from the file in the byte order its name states."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with segyio.open(str(path), "r", ignore_geometry=True, endian=endian) as f:
            reading = {"traces": np.asarray(f.trace.raw[:]).reshape(f.tracecount, -1), "samples": np.asarray(f.samples),
                       "dt": segyio.tools.dt(f) / 1000.0, "format": int(f.format)}
            if with_grid:
                reading["iline"] = np.asarray(f.attributes(segyio.TraceField.INLINE_3D)[:])
                reading["xline"] = np.asarray(f.attributes(segyio.TraceField.CROSSLINE_3D)[:])
    return reading


def test_the_table_covers_the_registered_files():
    assert len(NAMES) == 90 and set(EXPECTED) == set(NAMES)
    outcomes = [EXPECTED[n][0] for n in NAMES]
    assert (outcomes.count("cube"), outcomes.count("trace list")) == (49, 6)  # 55 read, 35 refused


@pytest.mark.parametrize("name", NAMES)
def test_read_or_refused_in_one_line(conformance_files, name):
    path = conformance_files[name]
    outcome, detail = EXPECTED[name]
    result, warned = _open(path)
    if isinstance(outcome, type):  # a refusal: the expected type, one line, the file's name and the true reason
        assert isinstance(result, outcome), f"{name}: expected {outcome.__name__}, got {result!r}"
        message = str(result)
        assert "\n" not in message and message.startswith(path.name), message
        assert re.search(detail, message), message
        assert not warned
    else:
        assert not isinstance(result, Exception), f"{name} was refused: {result}"
        with result as cube:
            assert cube.shape == detail and cube.endian == _byte_order_of_name(name)
            assert cube.layout.endian_from == "format code"
            traces = cube.traces[:]
            data = cube.read()
            ref = _segyio_reading(path, _byte_order_of_name(name), with_grid=outcome == "cube")
            assert cube.format == ref["format"]
            assert_array_equal(traces, ref["traces"].astype(np.float32))
            assert_allclose(cube.samples, ref["samples"], rtol=0, atol=1e-9)
            expected_dt = np.diff(ref["samples"])[0] if ref["samples"].size > 1 else ref["dt"]
            assert cube.sample_interval == pytest.approx(expected_dt)
            if outcome == "trace list":
                assert cube.inlines is None and data.shape == detail
                assert_array_equal(data, traces)
                assert len(warned) == 1 and isinstance(warned[0], TraceListWarning)
                line = str(warned[0])
                assert "\n" not in line and f"read as a trace list of {detail[0]} traces" in line
            else:
                assert not warned
                assert sorted(set(ref["iline"].tolist())) == sorted(cube.inlines.tolist())
                assert sorted(set(ref["xline"].tolist())) == sorted(cube.xlines.tolist())
                il = [int(np.flatnonzero(cube.inlines == v)[0]) for v in ref["iline"]]
                xl = [int(np.flatnonzero(cube.xlines == v)[0]) for v in ref["xline"]]
                assert_array_equal(data[il, xl], ref["traces"].astype(np.float32))  # every trace in its grid cell
    assert hashlib.sha256(path.read_bytes()).hexdigest() == file_info(PREFIX + name).sha256  # not modified


@pytest.mark.parametrize("big, little", TWINS + SEGYIO_READS_BIG_ONLY, ids=lambda n: n.split("/")[-1])
def test_little_endian_twin_reads_as_its_big_endian_twin(conformance_files, big, little):
    a, _ = _open(conformance_files[big])
    b, _ = _open(conformance_files[little])
    if (big, little) in SEGYIO_READS_BIG_ONLY:
        assert not isinstance(a, Exception) and isinstance(b, SegyFormatError)
        a.close()
        return
    if isinstance(a, Exception) or isinstance(b, Exception):  # refused alike, for the same reason
        assert type(a) is type(b)
        assert str(b).replace(conformance_files[little].name, "X") == str(a).replace(conformance_files[big].name, "X")
        return
    with a, b:
        assert (a.endian, b.endian) == ("big", "little")
        assert a.shape == b.shape and a.format == b.format
        assert_array_equal(a.samples, b.samples)
        assert_array_equal(a.read(), b.read())


def _same_fault_likelihood(conformance_files, big, little):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)  # too small a cube for reliable faults: said, not tested
        likelihoods = []
        for name in (big, little):
            with open_segy(conformance_files[name]) as cube:
                likelihoods.append(fault_likelihood(cube.read()))
    be, le = likelihoods
    for field in ("likelihood", "strike_deg", "dip_deg"):
        assert_allclose(getattr(le, field), getattr(be, field), rtol=0, atol=1e-5)
    assert float(be.likelihood.max()) > 0


@pytest.mark.slow  # 22 s at load 12; the fast lane keeps its premise: the twins read as the same bits (above)
def test_little_endian_twin_gives_the_same_fault_likelihood(conformance_files):
    _same_fault_likelihood(conformance_files, "small.sgy", "small-lsb.sgy")


READ_TWINS = [(big, little) for big, little in TWINS if EXPECTED[big][0] == "cube" and big != "small.sgy"]


@pytest.mark.slow
@pytest.mark.parametrize("big, little", READ_TWINS, ids=lambda n: n.split("/")[-1])
def test_every_little_endian_twin_gives_the_same_fault_likelihood(conformance_files, big, little):
    _same_fault_likelihood(conformance_files, big, little)


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_faults_job_reads_or_refuses_in_one_line(conformance_files, tmp_path, name):
    from seismo3d.jobs.faults import run_faults_job

    out = tmp_path / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TraceListWarning)
        try:
            written = run_faults_job(conformance_files[name], out, progress=False)
        except Seismo3dError as exc:
            assert "\n" not in str(exc), str(exc)
            assert not out.exists()  # a refusal leaves nothing behind
        else:  # pragma: no cover - every file here is too small to trace faults in (32 traces, 32 samples)
            assert written.written["likelihood"].is_file()  # FaultsJobResult.written: output name -> path
    assert hashlib.sha256(conformance_files[name].read_bytes()).hexdigest() == file_info(PREFIX + name).sha256
