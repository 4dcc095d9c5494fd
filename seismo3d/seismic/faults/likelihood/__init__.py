"""Step 1 of the fault interpretation, the fault likelihood of every sample with the strike and dip of its fault.

- :mod:`~seismo3d.seismic.faults.likelihood.learned`: the fault network's probability (the default), a U-Net trained on
  generated sections, run by ONNX Runtime on the mean of its network grids (three on a section, two on a cube); its
  forward pass in :mod:`~seismo3d.seismic.faults.likelihood.network`, its grids in
  :mod:`~seismo3d.seismic.faults.likelihood.network_grid`.
- :mod:`~seismo3d.seismic.faults.likelihood.scan`: the scan of fault strikes and dips of the semblance of balanced
  amplitudes (Hale 2013); its numba kernels in :mod:`~seismo3d.seismic.faults.likelihood.scan_kernels`.
- Each likelihood declares its steps once beside its algorithm (``block_steps``: block functions, halos, costs) and
  runs them in their order in one function of a run (``run_scan``, ``run_learned``): in memory on one block, the
  whole cube (:class:`~seismo3d.seismic.blocks.executor.MemoryRun`), or block by block
  (:mod:`~seismo3d.seismic.faults.likelihood.scan_blocks`, :mod:`~seismo3d.seismic.faults.likelihood.learned_blocks`:
  the blocks planned under a memory limit; :mod:`~seismo3d.seismic.faults.likelihood.runs`: the one driver of both
  into a resumable Zarr group).
"""

from .learned import LearnedOptions, learned_fault_likelihood
from .scan import FaultScanOptions, fault_likelihood

__all__ = ["FaultScanOptions", "LearnedOptions", "fault_likelihood", "learned_fault_likelihood"]
