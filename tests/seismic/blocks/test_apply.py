"""Tests of seismo3d.seismic.blocks.apply: a declared step's algorithm on arrays, run block by block by the executor,
writes exactly what it computes on the whole array in memory (the core of each block, read with its halo), combines
with what is stored, saves and gathers its sparse lists, and a resumed run skips the finished blocks; the same
declared steps on the whole array in memory, one block without markers, give what the blocks wrote."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from seismo3d.seismic.blocks.apply import BlockOutput, BlockPlace, gather, load_lists, whole_place
from seismo3d.seismic.blocks.executor import BlockRun, MemoryRun
from seismo3d.seismic.blocks.plan import CUBE, BlockStep, lateral_blocks

zarr = pytest.importorskip("zarr")
da = pytest.importorskip("dask.array")

SHAPE = (11, 9, 5)
HALO = 2


def _smoothed(f) -> BlockOutput:
    """A lateral box mean of radius HALO over the region read (clamped at its edges), and the count of its values."""
    return BlockOutput({"smooth": ndi.uniform_filter(f, size=(2 * HALO + 1, 2 * HALO + 1, 1), mode="nearest")},
                       {"n": int(f.size)})


def _peaks(place, smooth, level) -> BlockOutput:
    """The core's samples of ``smooth`` above ``level`` as a list of cube indices; doubled values written back."""
    core = smooth[place.core]
    points = np.argwhere(core > level) + np.array([place.block[0], place.block[2], 0])
    return BlockOutput({"double": 2 * smooth}, {"count": int(len(points))}, {"points": points.astype(np.int64)})


def _run(tmp_path, cube, *steps_and_args):
    run = BlockRun(tmp_path / "work", scheduler="synchronous")
    run.open({"shape": list(cube.shape)})
    run.shape = cube.shape
    for name in ("smooth", "double"):
        path = tmp_path / name
        if not path.exists():
            zarr.create_array(str(path), shape=cube.shape, chunks=(4, 4, 5), dtype="float32", fill_value=0)
        run.arrays[name] = str(path)
    source = da.from_array(cube, chunks=(4, 9, 5))
    results = []
    for step, args in steps_and_args:
        results.append(run.run_step(step, lateral_blocks(cube.shape, 4, 4), *args,
                                    source=source if CUBE in step.inputs else None))
    return run, results


def _cube():
    return np.random.default_rng(0).standard_normal(SHAPE).astype(np.float32)


@pytest.mark.slow
def test_a_declared_step_writes_the_whole_array_result_block_by_block(tmp_path):
    cube = _cube()
    smooth = BlockStep("smooth", "map", HALO, function=_smoothed, inputs=(CUBE,), outputs=("smooth",))
    peaks = BlockStep("peaks", "gather", HALO, function=_peaks, inputs=("smooth",), outputs=("double",), place=True)
    run, (sizes, counts) = _run(tmp_path, cube, (smooth, ()), (peaks, (0.2,)))
    # the same mean over the whole cube: every block's core equals it (its halo covers the filter's reach)
    whole = ndi.uniform_filter(cube, size=(2 * HALO + 1, 2 * HALO + 1, 1), mode="nearest")
    np.testing.assert_array_equal(zarr.open_array(str(tmp_path / "smooth"))[:], whole)
    np.testing.assert_array_equal(zarr.open_array(str(tmp_path / "double"))[:], 2 * whole)
    # the regions read: each block grown by HALO, clipped to the cube
    assert sum(r["n"] for r in sizes) == sum((min(i1 + HALO, 11) - max(i0 - HALO, 0)) *
                                             (min(j1 + HALO, 9) - max(j0 - HALO, 0)) * 5
                                             for i0, i1, j0, j1 in lateral_blocks(SHAPE, 4, 4))
    # the lists of every block gathered: the samples above the level, each once
    points = run.gathered_lists("peaks", lateral_blocks(SHAPE, 4, 4), ("points",))["points"]
    np.testing.assert_array_equal(np.sort(np.ravel_multi_index(tuple(points.T), SHAPE)),
                                  np.flatnonzero(whole > 0.2))
    assert sum(r["count"] for r in counts) == int(np.count_nonzero(whole > 0.2))
    assert load_lists(tmp_path / "work" / "peaks", (0, 4, 0, 4), ("points",), mmap_mode="r")["points"].ndim == 2


def test_outputs_combine_with_what_is_stored_and_a_resumed_run_skips_finished_blocks(tmp_path):
    cube = _cube()
    smooth = BlockStep("smooth", "map", HALO, function=_smoothed, inputs=(CUBE,), outputs=("smooth",),
                       combine=np.maximum)
    zarr.create_array(str(tmp_path / "smooth"), shape=SHAPE, chunks=(4, 4, 5), dtype="float32", fill_value=0.5)
    run, _ = _run(tmp_path, cube, (smooth, ()))
    whole = ndi.uniform_filter(cube, size=(2 * HALO + 1, 2 * HALO + 1, 1), mode="nearest")
    np.testing.assert_array_equal(zarr.open_array(str(tmp_path / "smooth"))[:], np.maximum(whole, 0.5))
    assert run.computed == {"smooth": 9} and run.resumed == {"smooth": 0}

    (tmp_path / "work" / "done" / "smooth-4-4.json").unlink()  # as if interrupted before this block's marker
    again, _ = _run(tmp_path, cube, (smooth, ()))
    assert again.computed == {"smooth": 1} and again.resumed == {"smooth": 8}


def test_a_block_place_names_its_core_within_the_region_read():
    place = BlockPlace((4, 8, 0, 4), (2, 10, 0, 6))
    assert place.origin == (2, 0)
    assert place.core == (slice(2, 6), slice(0, 4))
    assert place.read == (slice(2, 10), slice(0, 6)) and place.target == (slice(4, 8), slice(0, 4))


@pytest.mark.slow
def test_the_same_steps_on_the_whole_array_in_memory_are_one_block(tmp_path):
    """MemoryRun, the executor in memory: the declared steps on one block, the whole array, give what the blocks of
    the run by blocks give; its lists in the executor's interface; several blocks refused."""
    cube = _cube()
    smooth = BlockStep("smooth", "map", HALO, function=_smoothed, inputs=(CUBE,), outputs=("smooth",))
    peaks = BlockStep("peaks", "gather", HALO, function=_peaks, inputs=("smooth",), outputs=("double",), place=True)
    by_blocks, _ = _run(tmp_path, cube, (smooth, ()), (peaks, (0.2,)))
    run = MemoryRun(SHAPE)
    whole = [whole_place(SHAPE).block]
    assert whole_place(SHAPE) == BlockPlace((0, 11, 0, 9), (0, 11, 0, 9))
    sized = run.run_step(smooth, whole, source=cube)
    found = run.run_step(peaks, whole, 0.2)
    assert set(run.arrays) == {"smooth", "double"} and sized == [{"n": cube.size}]
    assert run.computed == {"smooth": 1, "peaks": 1}
    np.testing.assert_array_equal(run.arrays["smooth"], zarr.open_array(str(tmp_path / "smooth"))[:])
    np.testing.assert_array_equal(run.arrays["double"], zarr.open_array(str(tmp_path / "double"))[:])
    blocks = gather(by_blocks.lists_reader("peaks"), lateral_blocks(SHAPE, 4, 4), ("points",))["points"]
    points = run.gathered_lists("peaks", whole, ("points",))["points"]
    np.testing.assert_array_equal(points, blocks[np.lexsort(blocks.T[::-1])])  # in C order
    np.testing.assert_array_equal(run.step_lists("peaks", whole[0], ("points",))["points"], points)
    assert found == [{"count": len(blocks)}]
    # a declared combine applies to what the run holds
    run.run_step(BlockStep("smooth", "map", HALO, function=_smoothed, inputs=(CUBE,), outputs=("smooth",),
                           combine=np.maximum), whole, source=cube)
    np.testing.assert_array_equal(run.arrays["smooth"], zarr.open_array(str(tmp_path / "smooth"))[:])
    with pytest.raises(ValueError, match="one block per step"):
        run.run_step(smooth, lateral_blocks(SHAPE, 4, 4), source=cube)


@pytest.mark.slow
def test_a_memory_run_is_the_block_run_of_the_same_steps_on_one_block(tmp_path):
    """MemoryRun.run_step, the run in memory of the likelihoods, gives what BlockRun.run_step writes block by block:
    the same declared steps, one block (the whole cube), the summaries as a list, no work folder."""
    cube = _cube()
    smooth = BlockStep("smooth", "map", HALO, function=_smoothed, inputs=(CUBE,), outputs=("smooth",))
    peaks = BlockStep("peaks", "gather", HALO, function=_peaks, inputs=("smooth",), outputs=("double",), place=True)
    _, (_, by_blocks) = _run(tmp_path, cube, (smooth, ()), (peaks, (0.2,)))
    run = MemoryRun(SHAPE)
    whole = lateral_blocks(SHAPE, 11, 11)
    assert whole == [(0, 11, 0, 9)]
    assert run.run_step(smooth, whole, source=cube) == [{"n": cube.size}]
    found = run.run_step(peaks, whole, 0.2)
    assert found == [{"count": sum(r["count"] for r in by_blocks)}]
    assert set(run.arrays) == {"smooth", "double"} and run.computed == {"smooth": 1, "peaks": 1}
    np.testing.assert_array_equal(run.arrays["smooth"], zarr.open_array(str(tmp_path / "smooth"))[:])
    np.testing.assert_array_equal(run.arrays["double"], zarr.open_array(str(tmp_path / "double"))[:])
    run.release("smooth")
    assert set(run.arrays) == {"double"}
    # a plan of several blocks, or a region short of the whole cube, is a plan for a run by blocks
    with pytest.raises(ValueError, match="one block per step"):
        run.run_step(smooth, lateral_blocks(SHAPE, 4, 4), source=cube)
    with pytest.raises(ValueError, match="not the whole cube"):
        run.run_step(smooth, [(0, 4, 0, 4)], source=cube)
