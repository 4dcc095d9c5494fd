"""GOCAD TSurf written by seismo3d, a file per surface, read back by a parser of the format's description and by
xtgeo's reader."""

import io
import re
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from seismo3d.errors import InputError
from seismo3d.seismic.io.tsurf import TriangulatedSurface, write_tsurf, write_tsurf_folder


def parse_tsurf(text: str) -> list:
    """A reader of GOCAD ASCII TSurf objects, from the format's description: each object starts with
    'GOCAD TSurf 1', has a HEADER {...} block with 'name:', an optional GOCAD_ORIGINAL_COORDINATE_SYSTEM block
    (AXIS_NAME, AXIS_UNIT, ZPOSITIVE), then TFACE with 'VRTX id x y z' (or PVRTX) and 'TRGL a b c' lines (vertex
    ids), and ends with END."""
    objects, current, in_header, in_crs = [], None, False, False
    for line in text.splitlines():
        words = line.split()
        if not words or line.startswith("#"):
            continue
        if words[:3] == ["GOCAD", "TSurf", "1"]:
            current = {"name": None, "ids": [], "xyz": [], "trgl": [], "axis_unit": None, "zpositive": None}
        elif words[0] == "HEADER":
            in_header = True
        elif in_header:
            if words[0] == "}":
                in_header = False
            elif line.startswith("name:"):
                current["name"] = line.split(":", 1)[1].strip()
        elif words[0] == "GOCAD_ORIGINAL_COORDINATE_SYSTEM":
            in_crs = True
        elif words[0] == "END_ORIGINAL_COORDINATE_SYSTEM":
            in_crs = False
        elif in_crs:
            if words[0] == "AXIS_UNIT":
                current["axis_unit"] = re.findall(r'"([^"]*)"', line)
            elif words[0] == "ZPOSITIVE":
                current["zpositive"] = words[1]
        elif words[0] in ("VRTX", "PVRTX"):
            current["ids"].append(int(words[1]))
            current["xyz"].append([float(v) for v in words[2:5]])
        elif words[0] == "TRGL":
            current["trgl"].append([int(v) for v in words[1:4]])
        elif words[0] == "END":
            ids = {v: i for i, v in enumerate(current["ids"])}
            current["vertices"] = np.array(current["xyz"])
            current["triangles"] = np.vectorize(ids.get)(np.array(current["trgl"]))
            objects.append(current)
            current = None
    return objects


@pytest.fixture
def surfaces(rng):
    a = TriangulatedSurface("fault_1", np.array([[620000.0, 6070000.0, 400.0], [620025.0, 6070000.0, 404.0],
                                                 [620000.0, 6070025.0, 408.0], [620025.5, 6070025.25, 412.0]]),
                            np.array([[0, 1, 2], [1, 3, 2]]), "m", "ms")
    pts = np.column_stack([rng.uniform(0, 1000, 30) + 735000.0, rng.uniform(0, 1000, 30) + 4890000.0,
                           rng.uniform(500, 2000, 30)])
    tri = np.array([[i, i + 1, i + 2] for i in range(28)])
    b = TriangulatedSurface("fault 2", pts, tri, "m", "ms")
    return [a, b]


def test_tsurf_read_back_by_a_spec_parser(surfaces, tmp_path):
    folder = write_tsurf_folder(tmp_path / "faults", surfaces, source="test")
    assert sorted(p.name for p in folder.iterdir()) == ["fault_1.ts", "fault_2.ts"]  # white space in names replaced
    for s in surfaces:
        objects = parse_tsurf((folder / f"{s.name.replace(' ', '_')}.ts").read_text())
        assert len(objects) == 1  # one object per file
        o = objects[0]
        assert o["name"] == s.name.replace(" ", "_")
        assert_allclose(o["vertices"][:, :2], s.vertices[:, :2], atol=5e-4)  # 3 decimals
        assert_allclose(o["vertices"][:, 2], s.vertices[:, 2], atol=5e-5)  # 4 decimals
        assert_array_equal(o["triangles"], s.triangles)
        assert o["axis_unit"] == ["m", "m", "ms"] and o["zpositive"] == "Depth"


@pytest.mark.slow
def test_tsurf_files_read_by_xtgeo(surfaces, tmp_path):
    """Every file of the folder read by xtgeo's own reader from its path (the reader refuses a second object in a
    file), vertices and triangles as written."""
    xtgeo = pytest.importorskip("xtgeo")
    folder = write_tsurf_folder(tmp_path / "faults", surfaces)
    for s in surfaces:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # xtgeo: 'uncommon AXIS_UNIT combination' (m, m, ms)
            surf = xtgeo.triangulated_surface_from_file(folder / f"{s.name.replace(' ', '_')}.ts", fformat="tsurf")
        assert_allclose(surf.vertices, s.vertices, atol=5e-4)
        assert_array_equal(surf.triangles, s.triangles)
    # the layout it replaces, every surface in one file: xtgeo reads no further than the first object
    two = "".join((folder / f"{n}.ts").read_text() for n in ("fault_1", "fault_2"))
    with pytest.raises(ValueError, match=r"Failing line: '\['GOCAD', 'TSurf', '1'\]'"), warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        xtgeo.triangulated_surface_from_file(io.BytesIO(two.encode()), fformat="tsurf")


def test_tsurf_folder_replaces_an_earlier_one_whole(surfaces, tmp_path):
    folder = write_tsurf_folder(tmp_path / "faults", surfaces)
    write_tsurf_folder(folder, surfaces[1:])
    assert [p.name for p in folder.iterdir()] == ["fault_2.ts"]  # no file of the earlier run left
    with pytest.raises(InputError, match="fault_2 more than once"):
        write_tsurf_folder(tmp_path / "twice", [surfaces[1], surfaces[1]])
    assert not (tmp_path / "twice").exists()


def test_tsurf_in_line_units_names_them(tmp_path):
    s = TriangulatedSurface("f", np.array([[1.0, 2, 3], [2, 2, 3], [1, 3, 4]]), np.array([[0, 1, 2]]),
                            "inline/crossline", "ms")
    text = write_tsurf(tmp_path / "f.ts", s).read_text()
    assert 'AXIS_NAME "INLINE" "CROSSLINE" "Z"' in text and 'AXIS_UNIT "none" "none" "ms"' in text


def test_tsurf_refuses_nothing_to_write(tmp_path):
    s = TriangulatedSurface("f", np.zeros((2, 3)), np.zeros((0, 3), np.int64))
    with pytest.raises(InputError, match="no surface with triangles"):
        write_tsurf_folder(tmp_path / "f", [s])
    with pytest.raises(InputError, match="has no triangles"):
        write_tsurf(tmp_path / "f.ts", s)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(InputError, match="indices"):
        TriangulatedSurface("g", np.zeros((2, 3)), np.array([[0, 1, 2]]))


def test_tsurf_written_by_chunks_of_rows_is_the_same_file(surfaces, tmp_path, monkeypatch):
    """The writer streams its rows a chunk at a time (a large run's text is never held whole): chunks of 7 rows
    give the bytes of one chunk, and every row is the format of numpy's own scalars."""
    import seismo3d.seismic.io.text_rows as text_rows

    b = surfaces[1]
    whole = write_tsurf(tmp_path / "whole.ts", b, source="test").read_bytes()
    monkeypatch.setattr(text_rows, "ROWS", 7)
    assert write_tsurf(tmp_path / "chunks.ts", b, source="test").read_bytes() == whole
    rows = [f"VRTX {i} {p[0]:.3f} {p[1]:.3f} {p[2]:.4f} CNXYZ" for i, p in enumerate(b.vertices, start=1)]
    rows += [f"TRGL {x} {y} {z}" for x, y, z in b.triangles + 1]
    assert whole.decode().endswith("\n".join(rows + ["END"]) + "\n")
