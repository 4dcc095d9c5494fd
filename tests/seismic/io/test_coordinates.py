"""SEG-Y coordinates with their scalar, and the grid's affine map, against the headers read with segyio directly."""

import numpy as np
import pytest
import segyio
from numpy.testing import assert_allclose

from seismo3d.errors import SegyGeometryError
from seismo3d.seismic.io.coordinates import LINE_UNITS, fit_grid_map, read_survey_coordinates


def _headers(path):
    """inline, crossline, CDP X, CDP Y per trace, the scalar of bytes 71-72 applied by hand."""
    with segyio.open(str(path), ignore_geometry=True) as f:
        il = np.asarray(f.attributes(189)[:], dtype=np.float64)
        xl = np.asarray(f.attributes(193)[:], dtype=np.float64)
        scalar = np.asarray(f.attributes(71)[:], dtype=np.float64)
        x = np.asarray(f.attributes(181)[:], dtype=np.float64)
        y = np.asarray(f.attributes(185)[:], dtype=np.float64)
    factor = np.where(scalar < 0, -1.0 / np.where(scalar < 0, scalar, -1.0), np.where(scalar > 0, scalar, 1.0))
    return il, xl, x * factor, y * factor


def test_penobscot_xl1155_coordinates_are_the_headers(data_dir):
    from seismo3d.data import fetch

    path = fetch("seismic/penobscot_xl1155.sgy")
    il, xl, x, y = _headers(path)
    coords = read_survey_coordinates(path)
    assert coords.unit == "m" and coords.x.shape == (601, 1)
    line = coords.section()
    order = np.argsort(il)
    assert_allclose(line.inline, il[order])
    assert_allclose(line.x, x[order], atol=1e-6)  # exactly the headers: 735416.5, 4891905.2 at the first trace
    assert_allclose(line.y, y[order], atol=1e-6)
    assert (line.x[0], line.y[0]) == pytest.approx((735416.5, 4891905.2))
    # whole trace indices give the trace's own coordinates; the line's affine map is within the scalar's 0.1 m
    assert_allclose(np.column_stack(line.at(np.arange(601)[:, None])), np.column_stack([x[order], y[order]]),
                    atol=1e-6)
    gm = coords.grid_map
    assert gm.is_line and gm.max_residual <= 0.1
    assert_allclose(np.column_stack(gm.to_xy(il, xl)), np.column_stack([x, y]), atol=0.1)


def test_f3_grid_map_reproduces_every_trace(data_dir):
    from seismo3d.data import fetch

    path = fetch("seismic/f3_crop.sgy")
    il, xl, x, y = _headers(path)
    coords = read_survey_coordinates(path)
    gm = coords.grid_map
    assert gm is not None and not gm.is_line
    fitted = np.column_stack(gm.to_xy(il, xl))
    err = np.hypot(*(fitted - np.column_stack([x, y])).T)
    assert err.max() < 1.0  # the bound; in fact within the 0.1 m step of the coordinate scalar -10
    assert err.max() <= 0.1 and gm.max_residual == pytest.approx(err.max())
    # bins of 25 m, square axes
    assert np.linalg.norm(gm.inline_vector) == pytest.approx(25.0, abs=0.01)
    assert np.linalg.norm(gm.crossline_vector) == pytest.approx(25.0, abs=0.01)
    assert abs(gm.inline_vector @ gm.crossline_vector) < 1e-3 * 625
    # the inverse
    back = np.column_stack(gm.to_lines(x, y))
    assert_allclose(back, np.column_stack([il, xl]), atol=0.01)
    # fractional positions between traces come from the map
    xi, yi = coords.at([[0.5, 0.5]])
    assert_allclose([xi[0], yi[0]], gm.to_xy(111.5, 875.5), atol=1e-9)


def test_a_trace_off_the_grid_is_named(data_dir):
    from seismo3d.data import fetch

    il, xl, x, y = _headers(fetch("seismic/f3_crop.sgy"))
    x = x.copy()
    x[17] += 5.0
    with pytest.raises(SegyGeometryError, match=f"inline {il[17]:g}, crossline {xl[17]:g}"):
        fit_grid_map(il, xl, x, y, unit="m", tolerance=0.1)


def test_no_coordinates_falls_back_to_line_numbers(tmp_path, rng):
    path = tmp_path / "cube.sgy"
    segyio.tools.from_array3D(str(path), rng.standard_normal((5, 4, 20)).astype(np.float32), format=5)
    coords = read_survey_coordinates(path)
    assert coords.unit == LINE_UNITS and not coords.has_coordinates
    assert coords.xy_names == ("inline number", "crossline number")
    assert_allclose(coords.x, coords.inline)
    assert_allclose(coords.y, coords.crossline)
    assert_allclose(coords.grid_map.to_xy(3, 2), (3, 2))


def test_volve_arbitrary_line_is_a_trace_list(data_dir):
    from seismo3d.data import fetch

    path = fetch("seismic/volve_fullstack_twt_arbline.sgy")
    _, _, x, y = _headers(path)
    coords = read_survey_coordinates(path)
    assert coords.x.shape == (225,) and coords.grid_map is None
    assert_allclose(coords.x, x)
    assert_allclose(coords.y, y)
    xm, ym = coords.at([[10.5]])  # half-way between traces 10 and 11
    assert_allclose([xm[0], ym[0]], [(x[10] + x[11]) / 2, (y[10] + y[11]) / 2])
