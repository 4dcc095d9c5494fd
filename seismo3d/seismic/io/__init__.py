"""Reading and writing seismic data: SEG-Y cubes, lines and trace lists, raw sections, ASCII lines, a cube read lazily
as a dask array, and the Zarr v3 store of ``seismo3d convert``.

- :mod:`~seismo3d.seismic.io.segy`: :func:`open_segy`, :func:`read_segy`.
- :mod:`~seismo3d.seismic.io.sections`: raw sections (:func:`read_section`), ASCII lines (:func:`read_ascii_lines`).
- :mod:`~seismo3d.seismic.io.layout`: byte order, sample format and the rev-2 headers of a SEG-Y file
  (:func:`read_segy_layout`).
- :mod:`~seismo3d.seismic.io.geometry`: what the traces of a file without an inline / crossline grid are
  (:func:`trace_geometry`), coordinates with their SEG-Y scalars (:func:`scale_coordinates`).
- :mod:`~seismo3d.seismic.io.blocks`: a 3D SEG-Y cube read by blocks of inlines (:class:`SegyGrid`,
  :func:`read_segy_block`).
- :mod:`~seismo3d.seismic.io.lazy`: :func:`open_lazy`, a 3D cube (SEG-Y or Zarr) as a dask array by inline blocks.
- :mod:`~seismo3d.seismic.io.zarr_store`: the Zarr v3 layout of ``seismo3d convert`` (xarray opens it as is).
- :mod:`~seismo3d.seismic.io.writer`: :func:`write_like` and :func:`write_like_blocks` (block by block): SEG-Y written
  with the headers of a template file.
"""

from .segy import SeismicCube, open_segy, read_segy
from .sections import read_section, read_ascii_lines
from .geometry import TraceGeometry, trace_geometry, span, scale_coordinates
from .layout import SegyLayout, read_segy_layout, segyio_failure, FORMAT_NAMES, READABLE_FORMATS
from .blocks import SegyGrid, read_segy_block, read_segy_block_headers, segyio_handle
from .lazy import LazyCube, open_lazy, inline_block_size
from .zarr_store import (
    LAYOUT, TILE_TRACES, SeismicZarr, SeismicZarrWriter, consolidate, open_seismic_zarr, is_seismic_zarr,
)
from .writer import write_like, write_like_blocks

__all__ = [
    "SeismicCube", "open_segy", "read_segy", "write_like", "read_section", "read_ascii_lines", "scale_coordinates",
    "TraceGeometry", "trace_geometry", "span", "SegyLayout", "read_segy_layout", "segyio_failure", "FORMAT_NAMES",
    "READABLE_FORMATS", "SegyGrid", "read_segy_block", "read_segy_block_headers", "segyio_handle", "LazyCube",
    "open_lazy", "inline_block_size", "LAYOUT", "TILE_TRACES", "SeismicZarr", "SeismicZarrWriter", "consolidate",
    "open_seismic_zarr", "is_seismic_zarr", "write_like_blocks",
]
