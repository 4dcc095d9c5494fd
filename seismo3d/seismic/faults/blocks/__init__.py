"""The fault interpretation of a cube larger than memory, block by block into resumable Zarr stores.

The same steps as in memory, run over blocks with their halos by the generic pieces of :mod:`seismo3d.seismic.blocks`:

- :mod:`~seismo3d.seismic.faults.blocks.cube_run`: the whole interpretation of a cube by blocks, with its checks;
- :mod:`~seismo3d.seismic.faults.blocks.preflight`: a large cube judged from a sample of blocks, and the smallest
  memory limit of a run by blocks;
- :mod:`~seismo3d.seismic.faults.blocks.scan_blocks`, :mod:`~seismo3d.seismic.faults.blocks.learned_blocks`: the
  likelihood (scan or fault network) of a cube by blocks;
- :mod:`~seismo3d.seismic.faults.blocks.surface_blocks` (the work of each block in
  :mod:`~seismo3d.seismic.faults.blocks.surface_block_steps`, the plan in
  :mod:`~seismo3d.seismic.faults.blocks.surface_plan`): the fault surfaces of a cube by blocks;
- :mod:`~seismo3d.seismic.faults.blocks.array_run`: the steps after the likelihood on a whole array (one block).
"""

__all__: list = []
