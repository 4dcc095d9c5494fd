"""Tests of seismo3d.seismic.blocks.stores: the output of a run by blocks is assembled beside its final path and
appears there only when finished; an existing output or a missing folder is refused; coordinates are written with
their unit, and a coordinate of the wrong length is refused."""

from __future__ import annotations

import numpy as np
import pytest
import zarr

from seismo3d.errors import EarlierStoresError, InputError
from seismo3d.seismic.blocks.options import ChunkOptions
from seismo3d.seismic.blocks.stores import StoreRun, write_coords


def test_the_output_appears_only_when_finished(tmp_path):
    run = StoreRun(tmp_path / "out.zarr", ChunkOptions(tile=4), progress=False, outputs=("a", "b"))
    run.start_output({"shape": [8, 6, 5]}, (8, 6, 5), 4, (("work_key", "int32", 3),))
    assert not run.out.exists() and run.partial.is_dir()
    assert zarr.open_array(str(run.work / "work_key")).shape == (8, 6, 3)
    group = zarr.open_group(str(run.partial), mode="r+")
    assert sorted(group.array_keys()) == ["a", "b"] and group["a"].chunks == (4, 4, 5)
    group["a"][:] = 1.0
    run.finish()
    assert not run.partial.exists() and not run.work.exists()
    done = zarr.open_group(str(run.out), mode="r")
    assert done.attrs["complete"] is True
    np.testing.assert_array_equal(done["a"][:], np.ones((8, 6, 5), np.float32))


def test_an_unfinished_run_of_other_work_or_an_existing_output_is_refused(tmp_path):
    run = StoreRun(tmp_path / "out.zarr", ChunkOptions(), progress=False)
    run.start_output({"shape": [4, 4, 4]}, (4, 4, 4), 32, ())
    with pytest.raises(EarlierStoresError, match="unfinished run of another cube"):
        StoreRun(tmp_path / "out.zarr", ChunkOptions(), progress=False).start_output({"shape": [5, 4, 4]},
                                                                                   (5, 4, 4), 32, ())
    run.finish()
    with pytest.raises(InputError, match="already exists; pick another output or delete it"):
        StoreRun(tmp_path / "out.zarr", ChunkOptions(), progress=False).start_output({}, (4, 4, 4), 32, ())
    with pytest.raises(InputError, match="does not exist; create it first"):
        StoreRun(tmp_path / "no" / "out.zarr", ChunkOptions(), progress=False).start_output({}, (4, 4, 4), 32, ())


def test_coordinates_are_written_with_their_unit_and_checked(tmp_path):
    group = zarr.open_group(str(tmp_path / "g.zarr"), mode="w")
    write_coords(group, (3, 2, 4), {"inline": [10, 11, 12], "sample": [0.0, 4.0, 8.0, 12.0], "sample_unit": "ms"})
    np.testing.assert_array_equal(group["inline"][:], [10, 11, 12])
    np.testing.assert_array_equal(group["crossline"][:], [0, 1])  # left out: indices
    assert group["sample"].attrs["units"] == "ms"
    with pytest.raises(InputError, match="coordinate 'crossline' must have 2 values"):
        write_coords(group, (3, 2, 4), {"crossline": [1, 2, 3]})
