"""From a fault likelihood to fault surfaces (curves in 2D sections).

Dead traces and samples, whose edges are not faults, are the amplitudes' (:mod:`seismo3d.seismic.amplitudes`).

- :mod:`~seismo3d.seismic.faults.surfaces.ridges`: ridges (non-maximum suppression across the fault) and thinning.
- :mod:`~seismo3d.seismic.faults.surfaces.voting`: optimal surface voting (Wu & Fomel 2018); its loops in
  :mod:`~seismo3d.seismic.faults.surfaces.voting_kernels`.
- :mod:`~seismo3d.seismic.faults.surfaces.skins`: thinned votes linked into fault skins (Hale 2013); the skins
  that continue each other merged in :mod:`~seismo3d.seismic.faults.surfaces.skin_merging`, the 2D skins that linked
  two faults split apart in :mod:`~seismo3d.seismic.faults.surfaces.skin_splits`.
- :mod:`~seismo3d.seismic.faults.surfaces.blocks`: these steps declared once (halos, inputs and outputs, costs, plan;
  each one's algorithm on a block beside its algorithm) and run once (``SurfaceRun``): block by block by the
  executor of :mod:`seismo3d.seismic.blocks` for a cube larger than memory, or on the whole array as one block in
  memory.
"""

from .ridges import thin_faults
from .skins import SkinOptions, fault_skins
from .voting import VotingOptions, vote_faults

__all__ = ["SkinOptions", "VotingOptions", "fault_skins", "thin_faults", "vote_faults"]
