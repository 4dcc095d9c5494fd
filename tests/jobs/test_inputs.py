"""seismo3d.jobs.inputs: the one reader of the jobs' seismic inputs (SEG-Y cube, line, trace list; .npy; .f32be) and
the one rule for what an input file is."""

import numpy as np
import pytest
import segyio

from seismo3d.errors import DataNotFoundError, InputError, SegyFormatError
from seismo3d.jobs.inputs import input_kind, read_seismic


@pytest.fixture(scope="module")
def cube(tmp_path_factory):
    """A 5 x 4 x 30 SEG-Y cube, inlines 1..5, crosslines 1..4, 2 ms; and its amplitudes."""
    path = tmp_path_factory.mktemp("segy") / "c.sgy"
    data = np.random.default_rng(0).standard_normal((5, 4, 30)).astype(np.float32)
    segyio.tools.from_array3D(str(path), data, format=5, dt=2000)
    return path, data


def test_a_cube_with_its_grid_and_coordinates(cube):
    path, data = cube
    seismic = read_seismic(path)
    assert seismic.kind == "cube" and seismic.is_segy and seismic.grid_shape == (5, 4, 30)
    np.testing.assert_array_equal(seismic.data, data)
    np.testing.assert_array_equal(seismic.inlines, np.arange(1, 6))
    assert seismic.sample_unit == "ms" and seismic.sample_interval == 2.0
    assert seismic.cdp_x is None  # segyio.tools.from_array3D writes no coordinates (render tests read real ones)


def test_a_trace_list_keeps_the_header_numbers_of_each_trace(cube):
    path, data = cube
    seismic = read_seismic(path, ignore_geometry=True)
    assert seismic.kind == "trace list" and seismic.inlines is None and seismic.data.shape == (20, 30)
    np.testing.assert_array_equal(seismic.trace_inlines, np.repeat(np.arange(1, 6), 4))
    np.testing.assert_array_equal(seismic.data, data.reshape(20, 30))


def test_arrays_and_raw_sections_are_in_samples(tmp_path):
    section = np.arange(12, dtype=np.float32).reshape(3, 4)
    np.save(tmp_path / "s.npy", section)
    section.astype(">f4").tofile(tmp_path / "s.f32be")
    for name, kind in (("s.npy", "array"), ("s.f32be", "section")):
        seismic = read_seismic(tmp_path / name, n_samples=4)
        assert seismic.kind == kind and seismic.sample_unit == "samples" and not seismic.is_segy
        np.testing.assert_array_equal(seismic.data, section)
        np.testing.assert_array_equal(seismic.samples, [0, 1, 2, 3])


def test_the_jobs_error_messages(tmp_path):
    np.save(tmp_path / "flat.npy", np.zeros(5))
    with pytest.raises(InputError, match=r"flat.npy holds an array of shape \(5,\); expected a 2D section"):
        read_seismic(tmp_path / "flat.npy")
    np.save(tmp_path / "s.npy", np.zeros((3, 4)))
    with pytest.raises(InputError, match="no sample interval, so --sample-unit cannot be used"):
        read_seismic(tmp_path / "s.npy", sample_unit="ms")
    with pytest.raises(DataNotFoundError, match="no input file at"):
        read_seismic(tmp_path / "absent.npy")
    with pytest.raises(SegyFormatError):  # a SEG-Y-only command opens every file as SEG-Y, which says what it is not
        read_seismic(tmp_path / "s.npy", arrays=False)


@pytest.mark.parametrize("name, kind", [("a.SGY", "segy"), ("a.segy", "segy"), ("a.f32be", "f32be"), ("a.npy", "npy"),
                                        ("a.laz", "terrain"), ("a.tif", "terrain"), ("a.ply", "points"),
                                        ("a.xyz", "points"), ("a.zarr", "zarr"), ("a.png", "unknown")])
def test_input_kind(name, kind, tmp_path):
    assert input_kind(tmp_path / name) == kind


def test_terrain_suffixes_are_the_terrain_readers():
    """input_kind keeps its own list (importing seismo3d.terrain costs a second that SEG-Y commands do not pay):
    it must stay the readers' list."""
    from seismo3d.jobs import inputs
    from seismo3d.terrain.inputs import TERRAIN_SUFFIXES

    assert set(inputs._TERRAIN_SUFFIXES) == set(TERRAIN_SUFFIXES)
