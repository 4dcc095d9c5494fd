"""Reading and writing seismic data: SEG-Y cubes, lines and trace lists, raw sections, ASCII lines, and the Zarr v3
store of ``seismo3d convert``; :func:`open_cube` (``seismo3d.open``) opens any of them lazily as the one cube type.

- :mod:`~seismo3d.seismic.io.cube`: :func:`open_cube` (``seismo3d.open``), any seismic input as the one cube type, a
  lazy ``xarray.DataArray`` with segysak's dimensions; :func:`seismic_axes` of any such DataArray, and the helpers a
  function uses to take one and give labelled results (positions in its numbers to index space, maps on its lateral
  coordinates).
- :mod:`~seismo3d.seismic.io.segy`: :func:`open_segy`, :func:`read_segy`.
- :mod:`~seismo3d.seismic.io.sections`: raw sections (:func:`read_section`), ASCII lines (:func:`read_ascii_lines`).
- :mod:`~seismo3d.seismic.io.layout`: byte order, sample format and the rev-2 headers of a SEG-Y file
  (:func:`read_segy_layout`).
- :mod:`~seismo3d.seismic.io.geometry`: what the traces of a file without an inline / crossline grid are
  (:func:`trace_geometry`), coordinates with their SEG-Y scalars (:func:`scale_coordinates`).
- :mod:`~seismo3d.seismic.io.blocks`: a SEG-Y cube read by blocks of traces (:class:`SegyGrid`,
  :func:`read_segy_block`), the dask array of ``seismo3d.open``'s SEG-Y inputs (:func:`segy_dask_array`).
- :mod:`~seismo3d.seismic.io.zarr_store`: the Zarr v3 layout of ``seismo3d convert`` (xarray opens it as is).
- :mod:`~seismo3d.seismic.io.writer`: :func:`write_like` and :func:`write_like_blocks` (block by block): SEG-Y written
  with the headers of a template file.
- :mod:`~seismo3d.seismic.io.coordinates`: CDP X/Y with their scalar and the affine map of the inline / crossline grid
  (:func:`read_survey_coordinates`, :class:`SurveyCoordinates`, :class:`GridMap`).
- :mod:`~seismo3d.seismic.io.fault_sticks`: OpendTect and Charisma fault sticks in and out (:class:`FaultSticks`);
  :mod:`~seismo3d.seismic.io.stick_sections`: the one placement of sticks on a section's traces and samples;
  :mod:`~seismo3d.seismic.io.traced_sticks`: sticks drawn from traced faults as interpreters draw them.
- :mod:`~seismo3d.seismic.io.tsurf`: GOCAD TSurf fault surfaces, one per file (:func:`write_tsurf`,
  :func:`write_tsurf_folder`).
- :mod:`~seismo3d.seismic.io.horizon_grids`: horizons as IRAP / ZMAP+ grids and x y z points through xtgeo, picks in
  (:func:`write_horizon_grids`, :func:`read_horizon_picks`).
"""

from typing import TYPE_CHECKING

from ..._lazy import lazy_exports

# the public names, imported on first use (seismo3d._lazy): `seismo3d convert` imports the SEG-Y reader and the Zarr
# writer without the lazy dask cube, the SEG-Y writer, fault sticks, TSurf and horizon grids (~15-25 ms)
if TYPE_CHECKING:
    from .cube import open_cube, seismic_axes
    from .segy import SeismicCube, open_segy, read_segy
    from .sections import read_section, read_ascii_lines
    from .geometry import TraceGeometry, trace_geometry, span, scale_coordinates
    from .layout import SegyLayout, read_segy_layout, segyio_failure, FORMAT_NAMES, READABLE_FORMATS
    from .blocks import SegyGrid, read_segy_block, read_segy_block_headers, segyio_handle
    from .zarr_store import (
        LAYOUT, TILE_TRACES, SeismicZarrWriter, consolidate, open_seismic_group, is_seismic_zarr,
    )
    from .writer import write_like, write_like_blocks
    from .coordinates import GridMap, SurveyCoordinates, cube_coordinates, read_survey_coordinates
    from .fault_sticks import FaultSticks, read_fault_sticks, write_fault_sticks
    from .tsurf import TriangulatedSurface, write_tsurf, write_tsurf_folder
    from .horizon_grids import HorizonPicks, read_horizon_picks, write_horizon_grids

__all__ = [
    "open_cube", "seismic_axes", "SeismicCube", "open_segy", "read_segy", "write_like", "read_section",
    "read_ascii_lines", "scale_coordinates",
    "TraceGeometry", "trace_geometry", "span", "SegyLayout", "read_segy_layout", "segyio_failure", "FORMAT_NAMES",
    "READABLE_FORMATS", "SegyGrid", "read_segy_block", "read_segy_block_headers", "segyio_handle", "LAYOUT",
    "TILE_TRACES", "SeismicZarrWriter", "consolidate",
    "open_seismic_group", "is_seismic_zarr", "write_like_blocks", "GridMap", "SurveyCoordinates", "cube_coordinates",
    "read_survey_coordinates", "FaultSticks", "read_fault_sticks", "write_fault_sticks", "TriangulatedSurface",
    "write_tsurf", "write_tsurf_folder", "HorizonPicks", "read_horizon_picks", "write_horizon_grids",
]

__getattr__, __dir__ = lazy_exports(__name__, __file__)
