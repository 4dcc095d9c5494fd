"""Peak memory of the learned likelihood's two block steps, the figures behind ``_NETWORK_INPUT_BYTES``,
``_NETWORK_BATCH_BYTES`` (seismo3d/seismic/faults/likelihood/learned_blocks.py) and ``_ORIENTATION_BYTES``
(seismo3d/seismic/faults/likelihood/learned.py, beside the step it plans).

Measured with tracemalloc (numpy reports its arrays to it), after a warm-up that loads the weights:

* network blocks of both directions, as ``learned.network_block`` runs them (the region as read, the
  resampling, the network on the block's sections, the write of its core to a work array), for blocks of a few
  sections and of many, narrow and as wide as the cube; printed beside the bytes the plan's model gives them;
* an interior orientation block, as ``learned.orientation_block`` runs it (both directions' probabilities
  read from their work arrays, their maximum interpolated onto the block, ``orientation_from_likelihood``, the dip
  mask, the writes), per sample of the block with its halo beside the planned constant.

The load average is printed (the machine is shared; memory does not depend on it, time does).

    python benchmarks/learned_block_memory.py
"""

import os
import tempfile
import tracemalloc

import numpy as np
import zarr

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic.faults.likelihood import learned, learned_blocks as lb
from seismo3d.seismic.faults.likelihood.learned import (
    LearnedOptions, amplitude_scale, fault_probability, orientation_from_likelihood,
)
from seismo3d.seismic.blocks.apply import BlockPlace
from seismo3d.seismic.blocks.options import ChunkOptions


def network_blocks(opt: LearnedOptions) -> None:
    factor = max(opt.cube_resample or opt.resample)  # a cube's finest grid: its largest network blocks
    batch = int(opt.sections_per_batch)
    print(f"network blocks: planned {lb._NETWORK_INPUT_BYTES} bytes per input sample read (8 of them for dask's "
          "reads, not seen here) + "
          f"{lb._NETWORK_BATCH_BYTES} per network sample of a batch of {batch} sections; load average "
          f"{os.getloadavg()[0]:.1f}")
    work = tempfile.mkdtemp(prefix="learned_memory_")
    for shape in ((200, 200, 128), (240, 240, 256)):
        cube = synthetic_cube(shape, seed=0, n_faults=2).cube.astype(np.float32)
        scale = amplitude_scale(cube)
        fault_probability(cube[:40, :40, :32], options=opt, scale=scale)  # warm-up: the weights loaded
        grid = learned.network_shape(shape, factor)
        array = f"{work}/net_{shape[2]}"
        zarr.create_array(array, shape=grid, chunks=(16, 16, grid[2]), dtype="float32", fill_value=0,
                          compressors=None)
        for axis in (0, 1):
            for across, along in ((16, 48), (16, grid[1 - axis]), (48, grid[1 - axis])):
                size = (across, along) if axis == 0 else (along, across)
                block = (16, 16 + size[0], 16, min(16 + size[1], grid[1])) if along < grid[1 - axis] else \
                    ((16, 16 + size[0], 0, grid[1]) if axis == 0 else (0, grid[0], 16, 16 + size[1]))
                a0, a1, b0, b1 = learned.network_region(block, axis, shape, factor)
                region = cube[a0:a1, b0:b1]
                tracemalloc.start()
                read = region.copy()  # the block as read
                learned.network_block(BlockPlace(block, (a0, a1, b0, b1)), read, axis, opt, factor, scale)
                _, peak = tracemalloc.get_traced_memory()
                tracemalloc.stop()
                del read
                model = lb._network_block_bytes(block, axis, shape, factor, batch)
                print(f"  {shape} axis {axis}, {across} sections x {along} traces (region {a1 - a0} x {b1 - b0}): "
                      f"peak {peak / 2**20:.1f} MiB, planned {model / 2**20:.1f} MiB ({peak / model:.2f})")


def orientation_blocks(opt: LearnedOptions) -> None:
    halo = learned.orientation_halo(opt)
    rng = np.random.default_rng(0)
    orientation_from_likelihood(rng.random((20, 20, 32), dtype=np.float32), sigma=float(opt.orientation_sigma))
    print(f"orientation: halo {halo} traces, planned {learned._ORIENTATION_BYTES} bytes per sample")
    for core, nt in ((32, 128), (64, 128), (64, 256)):
        shape = (3 * core, 3 * core, nt)
        plan = lb._plan(shape, opt, ChunkOptions(block=core, memory_limit=8 << 30), 0)
        work = tempfile.mkdtemp(prefix="learned_memory_")
        c, networks = plan["network_chunk"], []
        for k, g in enumerate(plan["grids"]):  # each grid's directions' probabilities on its network grid
            grid = tuple(g["network_shape"])
            for name in g["network_blocks"]:
                networks.append(zarr.create_array(f"{work}/network_{name}_{k}", shape=grid, chunks=(c, c, grid[2]),
                                                  dtype="float32", compressors=None))
                networks[-1][:] = rng.random(grid, dtype=np.float32)
        block = (core, 2 * core, core, 2 * core)  # an interior block: its halo on every side
        side = core + 2 * halo
        tracemalloc.start()
        region = (core - halo, 2 * core + halo, core - halo, 2 * core + halo)  # halo < core here
        learned.orientation_block(BlockPlace(block, region), *networks, plan, opt)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        print(f"  block {core} + 2 x {halo} = {side}^2 traces x {nt} samples: peak {peak / 2**20:.1f} MiB, "
              f"{peak / (side * side * nt):.1f} bytes per sample (planned {learned._ORIENTATION_BYTES})")


def main() -> None:
    opt = LearnedOptions()
    network_blocks(opt)
    orientation_blocks(opt)


if __name__ == "__main__":
    main()
