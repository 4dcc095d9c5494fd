"""Fault throw on a lazy (dask) cube, read one patch window at a time, against the in-memory run (issue 19: "throw
across chunk borders gives the same faults as the in-memory run").

The windowed path reads, per patch, only the traces the patch reads plus the halo of the structure tensor; its
throws must equal the in-memory ones (<= 1e-4 samples, NaN at the same points, the same registered points) on
faults that touch the cube's edges, for any chunking of the dask array.
"""

from types import SimpleNamespace

import dask
import dask.array as da
import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import fault_throw, fault_throws

ATOL = 1e-4  # samples


def _assert_same(lazy, memory):
    assert len(lazy) == len(memory)
    for a, b in zip(lazy, memory):
        assert a.fault_id == b.fault_id
        np.testing.assert_array_equal(np.isnan(a.throw), np.isnan(b.throw))
        np.testing.assert_allclose(a.throw, b.throw, atol=ATOL, rtol=0)
        np.testing.assert_array_equal(a.registered, b.registered)
        np.testing.assert_allclose(a.correlation, b.correlation, atol=1e-5, rtol=0)
        assert a.n_points_used == b.n_points_used


def _touches_edge(points, shape):
    lateral = np.asarray(points)[:, :2]
    return bool(np.any(lateral.min(axis=0) < 0.5) or np.any(lateral.max(axis=0) > np.array(shape[:2]) - 1.5))


@pytest.mark.slow
def test_lazy_equals_in_memory_on_traced_faults(traced_cube):
    """128^3 cube, faults from trace_faults (all reach the cube's sides): chunks of whole traces, blocks of 16
    inlines and tiles of 24 x 24 traces (as seismo3d.open makes them)."""
    c = traced_cube(0)
    cube = c.syn.cube
    assert len(c.faults) >= 3 and all(_touches_edge(f.points, cube.shape) for f in c.faults)
    memory = fault_throws(cube, c.faults, orientation=c.orientation)
    assert sum(int(np.isfinite(r.throw).sum()) for r in memory) > 10000  # the comparison has throws to compare
    assert sum(int(r.registered.sum()) for r in memory) > 5000
    with dask.config.set(scheduler="threads"):
        for chunks in [(16, 128, 128), (24, 24, 128)]:
            _assert_same(fault_throws(da.from_array(cube, chunks=chunks), c.faults), memory)


@pytest.fixture(scope="module")
def small():
    """A 64 x 64 x 96 cube and its true fault voxels as Fault-like inputs (plane normals), with in-memory throws."""
    syn = synthetic_cube((64, 64, 96), n_faults=2, seed=1, noise=0.1)
    faults = [SimpleNamespace(id=f.id, points=np.argwhere(syn.fault_labels == f.id),
                              normals=np.tile(f.normal, (int((syn.fault_labels == f.id).sum()), 1)))
              for f in syn.faults]
    return syn.cube, faults, fault_throws(syn.cube, faults)


@pytest.mark.slow
def test_chunks_split_along_samples_give_the_same_throws(small):
    """Chunks that do not hold whole traces are read window by window all the same."""
    cube, faults, memory = small
    assert any(_touches_edge(f.points, cube.shape) for f in faults)
    assert any(np.isfinite(r.throw).any() for r in memory)
    lazy = da.from_array(cube, chunks=(10, 13, 17))
    _assert_same(fault_throws(lazy, faults), memory)
    _assert_same([fault_throw(lazy, faults[0])], memory[:1])


@pytest.mark.slow
def test_lazy_with_given_orientation(small):
    """A whole-cube orientation given with a lazy cube is sliced, not recomputed: the same throws."""
    from seismo3d.seismic import structure_tensor_orientation

    cube, faults, memory = small
    lazy = da.from_array(cube.astype(np.float64), chunks=(16, 64, 96))  # any numeric dtype, read as float32
    _assert_same(fault_throws(lazy, faults, orientation=structure_tensor_orientation(cube)), memory)


def test_lazy_bad_input(small):
    cube, faults, _ = small
    bad = cube.copy()
    bad[tuple(faults[0].points[len(faults[0].points) // 2, :2].astype(int))] = np.nan  # a NaN trace on the fault
    with pytest.raises(InputError, match="NaN"):
        fault_throws(da.from_array(bad, chunks=(16, 64, 96)), faults[:1])
    with pytest.raises(InputError, match="every axis"):
        fault_throws(da.zeros((64, 2, 96), chunks=(16, 2, 96)), faults[:1])
    with pytest.raises(InputError, match="orientation"):
        fault_throws(da.from_array(cube), faults, orientation=np.zeros((2, 4, 4, 4), np.float32))
