"""seismo3d.terrain.lidar: LAS/LAZ reading and writing."""

import numpy as np
import pytest

from seismo3d.errors import DataIntegrityError, DataNotFoundError, InputError
from seismo3d.terrain import read_las, write_las


@pytest.mark.slow
def test_autzen(autzen):
    assert len(autzen) == 110000
    assert autzen.crs.kind == "projected" and autzen.crs.linear_unit == "foot"
    np.testing.assert_allclose(autzen.points.min(axis=0), [636001.76, 848935.20, 406.26], atol=0.01)
    assert set(np.unique(autzen.classification)) == {1, 2}


@pytest.mark.slow
def test_write_read_round_trip_keeps_crs(autzen, tmp_path):
    pts = autzen.points[:500] + [10.0, -20.0, 1.0]
    path = write_las(tmp_path / "part.laz", pts, like=autzen, classification=np.full(500, 2))
    back = read_las(path)
    np.testing.assert_allclose(back.points, pts, atol=0.006)  # the header's 0.01 ft scale
    assert back.crs.linear_unit == "foot"
    assert len(read_las(path, classes=(2,))) == 500
    with pytest.raises(InputError, match="no points of classes"):
        read_las(path, classes=(6,))


def test_bad_files(tmp_path):
    import laspy

    laspy.LasData(laspy.LasHeader(point_format=3, version="1.2")).write(tmp_path / "empty.las")
    with pytest.raises(InputError, match="contains no points"):
        read_las(tmp_path / "empty.las")
    (tmp_path / "junk.laz").write_bytes(b"not a las file")
    with pytest.raises(DataIntegrityError, match="not a readable LAS"):
        read_las(tmp_path / "junk.laz")
    with pytest.raises(DataNotFoundError):
        read_las(tmp_path / "missing.las")
    with pytest.raises(InputError, match="must end in"):
        write_las(tmp_path / "x.txt", np.zeros((3, 3)))
