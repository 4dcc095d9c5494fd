"""Running computations on cubes larger than memory: block by block, resumably, under a memory limit.

Generic pieces, knowing nothing of what a block computes:

- :mod:`~seismo3d.seismic.blocks.options`: :class:`BlockRunOptions`, how a cube is run (memory limit, forced choice,
  work folder, dask scheduler, the input's name and coordinates recorded in the stores);
- :mod:`~seismo3d.seismic.blocks.memory`: memory limits parsed and measured, whether a run in memory fits;
- :mod:`~seismo3d.seismic.blocks.preflight`: the checks before a run (data too small for its windows, a few blocks
  spread over a large cube read for the run to judge it from);
- :mod:`~seismo3d.seismic.blocks.plan`: steps declared once (:class:`~seismo3d.seismic.blocks.plan.BlockStep`: block
  function, map / reduce / gather, halo, bytes of a block) and the largest blocks a memory limit allows them;
- :mod:`~seismo3d.seismic.blocks.executor`: resumable runs over the blocks of a cube (markers, dask schedulers, the
  kernels' threads), :meth:`~seismo3d.seismic.blocks.executor.BlockRun.run_step` running a declared step;
- :mod:`~seismo3d.seismic.blocks.apply`: one block of a declared step: its inputs read around it (slices, not
  ``dask.array.map_overlap``: the module says why), its algorithm on arrays, the core of its outputs written into
  the run's stores, its sparse lists saved, its marker last; and :class:`~seismo3d.seismic.blocks.executor.MemoryRun`,
  the same declared steps on a whole array in memory as one block, behind the executor's interface;
- :mod:`~seismo3d.seismic.blocks.statistics`: statistics of a stored array equal to the libraries' on the values
  gathered (Otsu's threshold, exact quantiles), as dask reductions over its chunks;
- :mod:`~seismo3d.seismic.blocks.stores`: the Zarr stores of such a run (the work folder, the output assembled in
  ``OUTPUT.partial`` and renamed when complete, its coordinates);

The fault interpretation's runs by blocks are lists of declared steps run by them
(:mod:`seismo3d.seismic.faults.likelihood.scan_blocks`, :mod:`seismo3d.seismic.faults.likelihood.learned_blocks`,
:mod:`seismo3d.seismic.faults.surfaces.blocks`).
"""

from .executor import BlockRun, run_block
from .options import BlockRunOptions

__all__ = ["BlockRun", "BlockRunOptions", "run_block"]
