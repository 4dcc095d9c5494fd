"""seismo3d.viz: pictures and 3D scenes (the only package that imports matplotlib and pyvista, inside its functions).

- :func:`show_seismic`: one pyvista scene of a seismic cube (inline, crossline and time-slice planes in a seismic
  colour map) with faults, horizons and the fault likelihood, placed by a :class:`CubeGeometry`
  (:func:`cube_geometry`, :func:`geometry_of_segy`: real line numbers or CDP X/Y, time or depth downward, vertical
  exaggeration); :func:`seismic_grid` gives the cube as a pyvista grid. Off screen into a PNG with ``screenshot=``.
- :func:`plot_section`: PNG of one seismic line as an interpreter reads it (trace numbers and times on labelled axes,
  the vertical exaggeration stated, faults as lines, a horizon); :func:`section_exaggeration` chooses the exaggeration;
  :func:`plot_volume_registration`: one inline of a sub-volume registration (fixed, moving, moving registered).
- :func:`plot_fault_slices`: PNG of seismic slices with the faults drawn over them (matplotlib);
  :func:`plot_fault_evaluation`: people's and the traced faults over a line, with the precision-recall curve.
- :func:`fault_surfaces`: fault surfaces (3D) or curves (2D) as one pyvista PolyData; :func:`save_polydata` writes it.
- :func:`horizon_surface`: a tracked horizon as a pyvista surface (holes where it is empty);
  :func:`plot_horizon_section`: horizon picks over a section (matplotlib).
- :func:`show_point_clouds`: point clouds before / after a registration; :func:`plot_matches`: image matches.
- :func:`show_map` / :func:`render_map`: an RGB-D map (TSDF mesh) with the camera trajectory and keyframe frusta.
- :func:`show_terrain`: a DEM in 3D with lineaments and a planned path; :func:`plot_rose`,
  :func:`plot_lineament_map`: PNGs of terrain lineaments (rose diagram, map over a hillshade).
- :func:`show_faults`: a quick scene of a cube's middle slices and its fault surfaces in index space.
- :mod:`seismo3d.viz.plotting`: how scenes are shown (window, Jupyter with trame or a static picture, off-screen PNG
  through EGL; what a slim image needs), where their colour bars go and how the camera fills the room they leave.
"""

from .clouds import plot_matches, show_point_clouds
from .fault_meshes import fault_surfaces, save_polydata
from .fault_evaluation import plot_fault_evaluation
from .faults import plot_fault_slices, show_faults
from .horizons import horizon_surface, plot_horizon_section
from .maps import render_map, show_map
from .plotting import finish_scene, jupyter_backend, new_plotter, symmetric_clip
from .sections import plot_section, plot_volume_registration, section_exaggeration
from .geometry import CubeGeometry, cube_geometry, geometry_of_segy, grid_index, place_index_mesh, seismic_grid
from .seismic import show_seismic
from .terrain import plot_lineament_map, plot_rose
from .terrain3d import show_terrain

__all__ = ["CubeGeometry", "cube_geometry", "geometry_of_segy", "grid_index", "place_index_mesh", "seismic_grid",
           "show_seismic", "plot_fault_slices", "fault_surfaces", "horizon_surface", "save_polydata", "show_faults",
           "finish_scene", "jupyter_backend", "new_plotter", "symmetric_clip", "plot_horizon_section",
           "plot_matches", "show_point_clouds", "plot_lineament_map", "plot_rose", "render_map", "show_map",
           "show_terrain", "plot_section", "plot_volume_registration", "section_exaggeration", "plot_fault_evaluation"]
