"""The fault interpretation of a cube larger than memory, block by block into resumable Zarr stores.

The same steps as in memory, run over blocks with their halos by the generic pieces of :mod:`seismo3d.seismic.blocks`
(markers, budgets, schedulers, the resumable stores); :func:`~seismo3d.seismic.faults.pipeline.trace_faults_by_blocks`
runs them:

- :mod:`~seismo3d.seismic.faults.blocks.preflight`: the checks before any block (a large cube judged from a sample of
  blocks, the smallest memory limit of a run by blocks, the data's NaN, constant, clipped and dead samples);
- :mod:`~seismo3d.seismic.faults.blocks.scan_blocks`, :mod:`~seismo3d.seismic.faults.blocks.learned_blocks`: the
  likelihood (scan or fault network) of a cube by blocks;
- :mod:`~seismo3d.seismic.faults.blocks.surface_blocks` (its block steps, their halos, costs and plan in
  :mod:`~seismo3d.seismic.faults.blocks.surface_steps`): the fault surfaces of a cube by blocks.

The steps after the likelihood on a whole array in memory (one block):
:class:`~seismo3d.seismic.faults.steps.ArrayRun`.
"""

__all__: list = []
