"""Text rows formatted a block at a time: the same characters as the per-row f-strings the writers used, whatever
the block size, NaN / inf handed to a column's fallback, constant fields written as they are (``%`` included); the
fault-stick files byte for byte as the per-row writers wrote them."""

import math

import numpy as np
import pytest

import seismo3d.seismic.io.text_rows as text_rows
from seismo3d.seismic.io.fault_sticks import FaultSticks, write_fault_sticks
from seismo3d.seismic.io.text_rows import TextColumn, format_rows


def _values(n, seed=0):
    rng = np.random.default_rng(seed)
    v = rng.normal(0.0, 1.0, n) * 10.0 ** rng.integers(-8, 12, n)
    v[::17] = np.round(v[::17], 3) + 0.0005  # near the rounding boundary of .3f
    v[3], v[5], v[8], v[13] = np.nan, np.inf, -0.0, -np.inf
    return v


def _blank(block):
    return ["" if v != v else format(v, ".5g") for v in block.tolist()]


@pytest.mark.parametrize("rows", [1, 7, 1 << 14])
def test_rows_are_the_f_strings_of_each_row(rows):
    v, w = _values(1000), _values(1000, seed=1)
    k = np.arange(1000) * 37 - 500
    text = "".join(format_rows([TextColumn(k, "d"), TextColumn("a%b"), TextColumn(v, ".3f"), TextColumn(w, "16.8E"),
                                TextColumn(v, ".5g", _blank), TextColumn(w, "g")], 1000, sep=",", rows=rows))
    expected = "".join(f"{a},a%b,{b:.3f},{c:16.8E},{'' if b != b else format(b, '.5g')},{c:g}\n"
                       for a, b, c in zip(k.tolist(), v.tolist(), w.tolist()))
    assert text == expected


def test_blocks_follow_rows_read_at_each_call(monkeypatch):
    v = np.arange(10.0)
    monkeypatch.setattr(text_rows, "ROWS", 4)
    blocks = list(format_rows([TextColumn(v, ".1f")], 10))
    assert [b.count("\n") for b in blocks] == [4, 4, 2]
    assert list(format_rows([TextColumn(v, ".1f")], 0)) == []


def _fmt(v):
    return "1e30" if not math.isfinite(v) else f"{v:.3f}"


def _reference(sticks, fmt):
    """The per-row writers the block writers replaced (seismo3d before issue 58's writing), rows only."""
    per_fault, out, current = {}, [], None
    for fid, nodes in sticks.sticks():
        stick_no = per_fault.get(fid, -1) + 1
        per_fault[fid] = stick_no
        cols = (sticks.x, sticks.y, sticks.z, sticks.inline, sticks.crossline)
        for node_no, (x, y, z, il, xl) in enumerate(zip(*(c[nodes].tolist() for c in cols))):
            name = sticks.names[fid - 1]
            if fmt == "opendtect":
                out.append("\t".join([f'"{name}"', _fmt(x), _fmt(y), f"{z:.4f}", str(stick_no), str(node_no),
                                      f"{il:g}", f"{xl:g}"]))
            elif fmt == "charisma":
                out.append(" ".join(["INLINE-", str(int(round(il))), str(int(round(xl))), _fmt(x), _fmt(y),
                                     f"{z:.4f}", name, str(stick_no + 1)]))
            else:
                if fid != current:
                    out.append(f"PROFILE {name[:17]:<17s}TYPE 1  4 {'fault sticks, seismo3d':<45s}3d_ci7m.ifdf     "
                               "m  ms")
                    out.append("SNAPPING PARAMETERS 5     0 1")
                    current = fid
                out.append(f"{x:16.8E}{y:16.8E}{(stick_no + 1) % 1000:3d}{14:3d}{z:9.2f}")
    if fmt == "iesx":
        out.append("EOD")
    return "".join(line + "\n" for line in out)


@pytest.fixture
def sticks():
    """Three faults whose sticks interleave (fault 2's sticks on both sides of fault 3's), stick numbers out of
    order, half-way line numbers (rounded half to even), undefined X / Y on a few nodes, 1003 sticks of fault 1
    (IESX's stick index wraps at 1000)."""
    rng = np.random.default_rng(3)
    stick = np.concatenate([np.repeat(np.arange(1003), 3), [1500, 1500, 1200, 1200, 1300, 1300, 1300]])
    fault = np.concatenate([np.ones(3009, np.int64), [2, 2, 2, 2, 3, 3, 3]])
    n = stick.size
    perm = rng.permutation(n)
    x = rng.uniform(4e5, 7e5, n)
    y = rng.uniform(6e6, 7e6, n)
    z = rng.uniform(0.0, 4000.0, n)
    il = np.round(rng.uniform(100, 900, n) * 2) / 2
    xl = rng.integers(1000, 2000, n).astype(np.float64)
    return FaultSticks(fault[perm], stick[perm], x[perm], y[perm], z[perm], il[perm], xl[perm],
                       names=("f1", "f2", "fault_3"))


@pytest.mark.parametrize("fmt", ["opendtect", "charisma", "iesx"])
def test_stick_files_keep_the_bytes_of_the_row_by_row_writers(sticks, tmp_path, monkeypatch, fmt):
    if fmt != "iesx":  # X / Y undefined on some nodes: 1e30 (IESX refuses them)
        x = sticks.x.copy()
        x[[5, 6, 3012]] = np.nan
        sticks = FaultSticks(sticks.fault_id, sticks.stick, x, sticks.y, sticks.z, sticks.inline, sticks.crossline,
                             names=sticks.names)
    whole = write_fault_sticks(tmp_path / "whole.txt", sticks, format=fmt).read_text()
    rows = "".join(line + "\n" for line in whole.splitlines() if not line.startswith("#"))
    assert rows == _reference(sticks, fmt)
    monkeypatch.setattr(text_rows, "ROWS", 5)
    assert write_fault_sticks(tmp_path / "blocks.txt", sticks, format=fmt).read_text() == whole


@pytest.mark.slow
@pytest.mark.parametrize("spec", ["f", ".f", ".0f", ".3f", ".4f", "g", ".g", ".0g", ".1g", ".5g", ".6g", ".12g"])
@pytest.mark.parametrize("rows", [1, 3, 1 << 14])
def test_whole_numbers_keep_the_characters_of_their_float_format(spec, rows):
    """Blocks of whole numbers are formatted as integers: the same text as the float format, -0.0, magnitudes at
    the g formats' exponent limits and at 2**53, NaN and a fraction in a block included (those blocks as floats)."""
    powers = 10.0 ** np.arange(0, 17)
    cases = [np.arange(-1000.0, 1000.0), np.concatenate([powers - 1, powers, -powers]), np.array([0.0, -0.0, 5.0]),
             np.array([2.0 ** 53 - 1, -(2.0 ** 53) + 1, 2.0 ** 53, 1e20]), np.array([1.5, 2.0, 3.0]),
             np.array([np.nan, 1.0, 2.0]), np.arange(0.0, 4000.0, 4.0, dtype=np.float32)]
    for v in cases:
        text = "".join(format_rows([TextColumn(v, spec), TextColumn(v, spec)], v.size, sep=" ",
                                   rows=rows))
        assert text == "".join(f"{'%' + spec} {'%' + spec}\n" % (x, x) for x in v.tolist())  # as floats
