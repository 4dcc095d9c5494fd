"""Blocks with a halo read by ``dask.array.map_overlap`` or as slices of the region around each block: the peak memory
of each (why :mod:`seismo3d.seismic.blocks.apply` reads regions by slicing).

Run: ``python benchmarks/block_reads.py [--side 768] [--block 128] [--halo 16] [--samples 128]``

A float32 Zarr array of ``side x side x samples`` (chunks of 32 x 32 traces, every sample) in a temporary folder; a
block function holding about 3 copies of its block (its float64 square root, summed); the blocks computed on dask's
threaded scheduler with one worker, each mode in its own process (the peak resident memory above the process before
the blocks, ``ru_maxrss``).
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile

import numpy as np


def _work(block):
    return float(np.sqrt(block.astype(np.float64) + 1.0).sum())


def _run(mode: str, path: str, side: int, block: int, halo: int) -> float:
    import dask
    import dask.array as da
    import zarr

    z = zarr.open_array(path, mode="r")
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    if mode == "map_overlap":
        def one(a):
            out = np.empty((1, 1), object)
            out[0, 0] = _work(a)
            return out

        x = da.from_zarr(z, chunks=(block, block, -1))
        n = -(-side // block)
        da.map_overlap(one, x, depth={0: halo, 1: halo, 2: 0}, boundary="none", trim=False, allow_rechunk=False,
                       chunks=((1,) * n, (1,) * n), drop_axis=2, dtype=object,
                       meta=np.empty((0, 0), object)).compute(scheduler="threads", num_workers=1)
    else:
        x = da.from_zarr(z)
        tasks = [dask.delayed(_work)(x[max(i - halo, 0):i + block + halo, max(j - halo, 0):j + block + halo])
                 for i in range(0, side, block) for j in range(0, side, block)]
        dask.compute(*tasks, scheduler="threads", num_workers=1)
    return (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base) / 1024  # KiB on Linux


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--side", type=int, default=768)
    p.add_argument("--block", type=int, default=128)
    p.add_argument("--halo", type=int, default=16)
    p.add_argument("--samples", type=int, default=128)
    p.add_argument("--mode", choices=("map_overlap", "slices"), help=argparse.SUPPRESS)
    p.add_argument("--path", help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    if a.mode:
        print(f"{_run(a.mode, a.path, a.side, a.block, a.halo):.0f}")
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
        for mode in ("map_overlap", "slices"):
            out = subprocess.run([sys.executable, __file__, "--mode", mode, "--path", path, "--side", str(a.side),
                                  "--block", str(a.block), "--halo", str(a.halo)],
                                 capture_output=True, text=True, check=True)
            print(f"  {mode:12s} peak {out.stdout.strip()} MiB above the process")
    return 0


if __name__ == "__main__":
    sys.exit(main())
