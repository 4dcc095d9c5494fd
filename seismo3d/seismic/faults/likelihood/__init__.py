"""Step 1 of the fault interpretation, the fault likelihood of every sample with the strike and dip of its fault.

- :mod:`~seismo3d.seismic.faults.likelihood.learned`: the fault network's probability (the default), a U-Net trained on
  generated sections, run by ONNX Runtime on the mean of three network grids; its forward pass in
  :mod:`~seismo3d.seismic.faults.likelihood.network`, its grids in
  :mod:`~seismo3d.seismic.faults.likelihood.network_grid`.
- :mod:`~seismo3d.seismic.faults.likelihood.scan`: the scan of fault strikes and dips of the semblance of balanced
  amplitudes (Hale 2013); its numba kernels in :mod:`~seismo3d.seismic.faults.likelihood.scan_kernels`.
- :mod:`~seismo3d.seismic.faults.likelihood.scan_blocks`, :mod:`~seismo3d.seismic.faults.likelihood.learned_blocks`:
  either likelihood of a cube larger than memory, as its declared steps (block functions, halos, costs) run block by
  block by the executor of :mod:`seismo3d.seismic.blocks`.
"""

from .learned import LearnedOptions, learned_fault_likelihood
from .scan import FaultScanOptions, fault_likelihood

__all__ = ["FaultScanOptions", "LearnedOptions", "fault_likelihood", "learned_fault_likelihood"]
