"""Tests of seismo3d.seismic.blocks.stores: the output of a run by blocks is assembled beside its final path and
appears there only when finished; an existing output or a missing folder is refused; coordinates are written with
their unit, and a coordinate of the wrong length is refused; what an earlier run left is told reused, resumed or
refused by what it recorded."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
import zarr

from seismo3d.errors import EarlierStoresError, InputError
from seismo3d.seismic.blocks.options import ChunkOptions
from seismo3d.seismic.blocks.stores import StoreRun, earlier_run, write_coords


@dataclass(frozen=True)
class _Options:
    sigma: float = 1.0


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


def test_an_earlier_run_is_reused_when_finished_resumed_when_not_and_another_one_refused(tmp_path):
    out = tmp_path / "out.zarr"
    manifest = {"shape": [4, 4, 4], "options": {"sigma": 1.0}, "plan": {"tile": 32}}
    assert earlier_run(out, manifest).state == "none"
    run = StoreRun(out, ChunkOptions(), progress=False)
    run.start_output(manifest, (4, 4, 4), 32, ())
    # unfinished: the same work (another block plan aside) resumed with its plan, other work refused
    resumed = earlier_run(out, dict(manifest, plan={"tile": 16}))
    assert resumed.state == "unfinished" and resumed.record["plan"] == {"tile": 32}
    # the manifest of a run: an unfinished run's plan in place of a new one, the options as JSON reads them back
    assert run.manifest_for((4, 4, 4), _Options(), {"tile": 16}, source="a") == dict(manifest, source="a")
    fresh = StoreRun(tmp_path / "other.zarr", ChunkOptions(), progress=False)
    assert fresh.manifest_for((4, 4, 4), _Options(), {"tile": 16}) == dict(manifest, plan={"tile": 16})
    assert earlier_run(out, dict(manifest, options={"sigma": 2.0})).state == "another"
    assert {p.name for p in earlier_run(out, {"shape": [5, 4, 4]}).paths} == {"out.zarr.work", "out.zarr.partial"}
    run.finish()
    zarr.open_group(str(out), mode="r+").attrs["source"] = "a"  # as the fault pipeline records its input
    # finished: the run recorded in the store; a caller knowing only part of it asks with that part
    assert earlier_run(out, manifest).state == "finished"
    assert earlier_run(out, {"source": "a", "shape": [4, 4, 4], "options": {"sigma": 1.0}}).state == "finished"
    for other in ({"source": "b"}, {"shape": [4, 4, 5]}, {"options": {"sigma": 2.0}}):
        found = earlier_run(out, dict(manifest, **other))
        assert found.state == "another" and [p.name for p in found.paths] == ["out.zarr"]
    assert run.finished_output(manifest, "test") is not None
    with pytest.raises(EarlierStoresError, match="not the finished output of this test"):
        run.finished_output(dict(manifest, shape=[5, 4, 4]), "test")
    # a store that records no run (another tool's, or an older version's) is not this run's
    zarr.open_group(str(tmp_path / "bare.zarr"), mode="w").attrs["complete"] = True
    assert earlier_run(tmp_path / "bare.zarr", manifest).state == "another"
