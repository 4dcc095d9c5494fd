"""seismo3d.viz: pictures and 3D scenes (the only package that imports matplotlib and pyvista, inside its functions).

- :func:`plot_fault_slices`: PNG of seismic slices with the faults drawn over them (matplotlib).
- :func:`fault_surfaces`: fault surfaces (3D) or curves (2D) as one pyvista PolyData; :func:`save_polydata` writes it.
- :func:`horizon_surface`: a tracked horizon as a pyvista surface (holes where it is empty).
- :func:`plot_rose`, :func:`plot_lineament_map`: PNGs of terrain lineaments (rose diagram, map over a hillshade).
- :func:`render_map`: an RGB-D map (TSDF mesh) with the camera trajectory and keyframes, rendered off screen to PNG.
- :func:`show_faults`: a pyvista scene of the cube's slices and its fault surfaces (notebooks; off screen with
  ``screenshot=``).
"""

from .faults import fault_surfaces, plot_fault_slices, save_polydata, show_faults
from .horizons import horizon_surface
from .maps import render_map
from .terrain import plot_lineament_map, plot_rose

__all__ = ["plot_fault_slices", "fault_surfaces", "horizon_surface", "plot_lineament_map", "plot_rose",
           "render_map", "save_polydata", "show_faults"]
