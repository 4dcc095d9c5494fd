"""seismo3d: seismic interpretation, terrain and RGB-D mapping on one fused-ICP registration engine.

Subpackages: :mod:`seismo3d.geometry` (transforms, normals, neighbours), :mod:`seismo3d.registration` (closed-form
fits, ICP family, RANSAC, fused ICP), :mod:`seismo3d.features` (HOG-pyramid and OpenCV matchers),
:mod:`seismo3d.seismic` (SEG-Y, faults, horizons), :mod:`seismo3d.mapping` (RGB-D), :mod:`seismo3d.terrain`,
:mod:`seismo3d.viz` (pyvista) and :mod:`seismo3d.data` (real-data registry and synthetic generators).
"""

__version__ = "0.1.0.dev0"
