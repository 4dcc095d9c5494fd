"""Blocks with a halo read by ``dask.array.map_overlap``, as dask slices of the region around each block, or by
``dask.array.map_blocks`` whose function slices its region from the store (``block_info``): the peak memory of each,
and the input arrays dask holds between tasks (why :mod:`seismo3d.seismic.blocks.apply` reads regions by slicing).

Run: ``python benchmarks/block_reads.py [--side 768] [--block 128] [--halo 16] [--samples 128]``

A float32 Zarr array of ``side x side x samples`` (chunks of 32 x 32 traces, every sample) in a temporary folder; a
block function holding about 3 copies of its block (its float64 square root, summed); the blocks computed on dask's
threaded scheduler with one worker, each mode in its own process (the peak resident memory above the process before
the blocks, ``ru_maxrss``; and the largest bytes of arrays in dask's cache after a task, a scheduler callback).
``map_overlap`` cuts each block's halo from its neighbours' chunks: a chunk is read whole and held until the last of
the (up to 9) blocks that need it has run, and each block's halo is concatenated into a new array.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile

import numpy as np


MODES = ("map_overlap", "slices", "map_blocks")


def _work(block):
    return float(np.sqrt(block.astype(np.float64) + 1.0).sum())


def _run(mode: str, path: str, side: int, block: int, halo: int) -> float:
    import dask
    import dask.array as da
    import zarr
    from dask.callbacks import Callback

    z = zarr.open_array(path, mode="r")
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    held = [0]

    class Held(Callback):
        def _posttask(self, key, result, dsk, state, worker_id):
            arrays = [v for v in state["cache"].values() if isinstance(v, np.ndarray) and v.dtype != object]
            held[0] = max(held[0], sum(v.nbytes for v in arrays))

    n = -(-side // block)
    if mode == "map_overlap":
        def one(a):
            out = np.empty((1, 1), object)
            out[0, 0] = _work(a)
            return out

        x = da.from_zarr(z, chunks=(block, block, -1))
        y = da.map_overlap(one, x, depth={0: halo, 1: halo, 2: 0}, boundary="none", trim=False, allow_rechunk=False,
                           chunks=((1,) * n, (1,) * n), drop_axis=2, dtype=object, meta=np.empty((0, 0), object))
        with Held():
            y.compute(scheduler="threads", num_workers=1)
    elif mode == "map_blocks":
        def region(g, block_info=None):  # the block's region read from the store by its function
            (i0, i1), (j0, j1) = block_info[0]["array-location"]
            out = np.empty((1, 1), object)
            out[0, 0] = _work(z[max(i0 - halo, 0):i1 + halo, max(j0 - halo, 0):j1 + halo])
            return out

        grid = da.zeros((side, side), chunks=(block, block), dtype=np.uint8)
        y = da.map_blocks(region, grid, chunks=((1,) * n, (1,) * n), dtype=object, meta=np.empty((0, 0), object))
        with Held():
            y.compute(scheduler="threads", num_workers=1)
    else:
        x = da.from_zarr(z)
        tasks = [dask.delayed(_work)(x[max(i - halo, 0):i + block + halo, max(j - halo, 0):j + block + halo])
                 for i in range(0, side, block) for j in range(0, side, block)]
        with Held():
            dask.compute(*tasks, scheduler="threads", num_workers=1)
    return (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base) / 1024, held[0] / 2**20  # KiB on Linux


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--side", type=int, default=768)
    p.add_argument("--block", type=int, default=128)
    p.add_argument("--halo", type=int, default=16)
    p.add_argument("--samples", type=int, default=128)
    p.add_argument("--mode", choices=MODES, help=argparse.SUPPRESS)
    p.add_argument("--path", help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    if a.mode:
        print("{:.0f} {:.0f}".format(*_run(a.mode, a.path, a.side, a.block, a.halo)))
        return 0
    import zarr

    with tempfile.TemporaryDirectory() as tmp:
        path = f"{tmp}/cube.zarr"
        z = zarr.create_array(path, shape=(a.side, a.side, a.samples), chunks=(32, 32, a.samples), dtype="float32",
                              fill_value=0, compressors=None)
        rng = np.random.default_rng(0)
        for i in range(0, a.side, 128):
            z[i:i + 128] = rng.random((min(128, a.side - i), a.side, a.samples), dtype=np.float32)
        one = (a.block + 2 * a.halo) ** 2 * a.samples * 4 / 2**20
        print(f"{a.side} x {a.side} x {a.samples} float32, blocks of {a.block} traces, halo {a.halo} "
              f"({one:.1f} MiB a block with its halo), one worker")
        for mode in MODES:
            out = subprocess.run([sys.executable, __file__, "--mode", mode, "--path", path, "--side", str(a.side),
                                  "--block", str(a.block), "--halo", str(a.halo)],
                                 capture_output=True, text=True, check=True)
            peak, held = out.stdout.split()
            print(f"  {mode:12s} peak {peak} MiB above the process, dask held {held} MiB of arrays between tasks")
    return 0


if __name__ == "__main__":
    sys.exit(main())
