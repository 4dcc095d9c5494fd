"""Peak memory per sample of the learned likelihood's probability step on one block (its halo included), the figure
behind ``_PROBABILITY_BYTES`` in seismo3d/seismic/faults/learned_blocks.py.

Measured with tracemalloc (numpy reports its arrays to it): the block as read, then ``fault_probability`` on it at
the default options, after a warm-up that loads the weights. Prints each block's peak beside the constant the plan
uses (the peer: the planned bytes per sample) and the load average (the machine is shared; memory does not depend
on it, time does).

    python benchmarks/learned_block_memory.py
"""

import os
import tracemalloc

import numpy as np

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic.faults import learned_blocks
from seismo3d.seismic.faults.learned import LearnedOptions, amplitude_scale, fault_probability


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


if __name__ == "__main__":
    main()
