"""Fault meshes and their writer (:mod:`seismo3d.viz.fault_meshes`)."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic import Fault
from seismo3d.viz import fault_surfaces, save_polydata


def _fault(fid, n=24, offset=0):
    """A planar fault of n x n samples dipping along the crosslines (one sample per inline and time)."""
    i, k = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    points = np.column_stack([i.ravel(), (k.ravel() // 2 + offset), k.ravel()])
    rng = np.random.default_rng(fid)
    m = len(points)
    return Fault(id=fid, points=points, likelihood=rng.uniform(0.5, 1.0, m).astype(np.float32),
                 strike_deg=np.zeros(m, np.float32), dip_deg=np.full(m, 63.4, np.float32),
                 normals=np.tile(np.float32([0, 0.89, -0.45]), (m, 1)))


def test_a_vtp_reads_back_equal_in_raw_appended_zlib(tmp_path):
    """faults.vtp: VTK's reader gives back the points, triangles and every point array bit for bit; the arrays are
    stored raw after the XML, zlib-compressed (save_polydata's docstring)."""
    import pyvista as pv

    mesh = fault_surfaces([_fault(1), _fault(2, offset=30)], axes=(np.arange(100, 124), np.arange(2000, 2100, 2),
                                                                   4.0 * np.arange(24)))
    path = save_polydata(mesh, tmp_path / "faults.vtp")
    back = pv.read(path)
    assert mesh.n_cells > mesh.n_points > 0
    np.testing.assert_array_equal(back.points, mesh.points)
    np.testing.assert_array_equal(back.faces, mesh.faces)
    assert set(back.point_data) == set(mesh.point_data)
    for name in mesh.point_data:
        assert back.point_data[name].dtype == mesh.point_data[name].dtype
        np.testing.assert_array_equal(back.point_data[name], mesh.point_data[name])
    head = path.read_bytes()[:400].decode("ascii", errors="replace")
    assert 'compressor="vtkZLibDataCompressor"' in head
    assert '<AppendedData encoding="raw">' in path.read_bytes().decode("latin-1")
    assert not list(tmp_path.glob("*.tmp"))  # written atomically: nothing left beside it


def test_save_polydata_refuses_another_extension(tmp_path):
    with pytest.raises(InputError, match=r"\.vtp"):
        save_polydata(fault_surfaces([_fault(1)]), tmp_path / "faults.obj")
