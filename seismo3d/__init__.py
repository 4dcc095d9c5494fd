"""seismo3d: seismic interpretation, terrain and RGB-D mapping on one fused-ICP registration engine.

:func:`seismo3d.open` opens a seismic input (SEG-Y cube or line, Zarr store of ``seismo3d convert``, ``.npy`` array,
raw section) as the project's one cube type, a lazy ``xarray.DataArray`` with segysak's dimensions
(:func:`seismo3d.seismic.io.cube.open_cube`), which every seismic function takes.

Subpackages: :mod:`seismo3d.geometry` (transforms, normals, neighbours), :mod:`seismo3d.registration` (closed-form
fits, ICP family, RANSAC, fused ICP), :mod:`seismo3d.features` (HOG-pyramid and OpenCV matchers),
:mod:`seismo3d.seismic` (SEG-Y, faults, horizons), :mod:`seismo3d.mapping` (RGB-D), :mod:`seismo3d.terrain`,
:mod:`seismo3d.viz` (pyvista) and :mod:`seismo3d.data` (real-data registry and synthetic generators).
"""

__version__ = "0.1.0.dev0"

__all__ = ["__version__", "open"]


def __getattr__(name: str):
    """``seismo3d.open``: :func:`~seismo3d.seismic.io.cube.open_cube`, imported on first use (PEP 562), so that
    ``import seismo3d`` stays light."""
    if name == "open":
        from .seismic.io.cube import open_cube

        return open_cube
    raise AttributeError(f"module 'seismo3d' has no attribute {name!r}")
