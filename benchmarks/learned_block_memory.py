"""Peak memory per sample of the learned likelihood's two block steps (their halos included), the figures behind
``_PROBABILITY_BYTES`` and ``_ORIENTATION_BYTES`` in seismo3d/seismic/faults/learned_blocks.py.

Measured with tracemalloc (numpy reports its arrays to it): the block as read, then ``fault_probability`` on it at
the default options, after a warm-up that loads the weights; and a probability block as read, then
``orientation_from_likelihood`` and the dip mask, as ``learned_blocks._orientation_block`` runs them. Prints each
block's peak beside the constant the plan uses (the peer: the planned bytes per sample) and the load average (the
machine is shared; memory does not depend on it, time does).

    python benchmarks/learned_block_memory.py
"""

import os
import tracemalloc

import numpy as np

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic.faults import learned_blocks
from seismo3d.seismic.faults.learned import (LearnedOptions, amplitude_scale, fault_probability,
                                             orientation_from_likelihood)


def main() -> None:
    opt = LearnedOptions()
    halo = learned_blocks._probability_halo(opt)
    print(f"halo {halo} traces, planned {learned_blocks._PROBABILITY_BYTES} bytes per sample, load average "
          f"{os.getloadavg()[0]:.1f}")
    for core, nt in ((32, 128), (64, 128), (64, 256)):
        side = core + 2 * halo
        src = synthetic_cube((side, side, nt), seed=0, n_faults=2).cube
        scale = amplitude_scale(src)
        fault_probability(src[:40, :40], options=opt, scale=scale)  # warm-up: the weights loaded
        tracemalloc.start()
        block = np.ascontiguousarray(src, dtype=np.float32).copy()  # the block as read, halo included
        fault_probability(block, options=opt, scale=scale, origin=(0, 0))
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        del block
        print(f"block {core} + 2 x {halo} = {side}^2 traces x {nt} samples: peak {peak / 2**20:.1f} MiB, "
              f"{peak / (side * side * nt):.1f} bytes per sample (planned {learned_blocks._PROBABILITY_BYTES})")
    halo = learned_blocks._orientation_halo(opt)
    rng = np.random.default_rng(0)
    orientation_from_likelihood(rng.random((20, 20, 32), dtype=np.float32), sigma=float(opt.orientation_sigma))
    print(f"orientation: halo {halo} traces, planned {learned_blocks._ORIENTATION_BYTES} bytes per sample")
    for core, nt in ((32, 128), (64, 128), (64, 256)):
        side = core + 2 * halo
        prob = rng.random((side, side, nt), dtype=np.float32)
        tracemalloc.start()
        block = prob.copy()  # the probability block as read, halo included
        strike, dip = orientation_from_likelihood(block, sigma=float(opt.orientation_sigma))
        likelihood = np.where(dip < float(opt.min_dip), np.float32(0.0), block)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        del block, strike, dip, likelihood
        print(f"block {core} + 2 x {halo} = {side}^2 traces x {nt} samples: peak {peak / 2**20:.1f} MiB, "
              f"{peak / (side * side * nt):.1f} bytes per sample (planned {learned_blocks._ORIENTATION_BYTES})")


if __name__ == "__main__":
    main()
