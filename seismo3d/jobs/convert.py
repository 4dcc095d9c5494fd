"""The ``seismo3d convert`` job: a 3D SEG-Y cube into a Zarr v3 store that xarray opens as is.

:func:`run_convert_job` takes the input's kind from the rule of ``seismo3d.open``
(:func:`~seismo3d.seismic.io.cube.reader_kind`: a store, a ``.npy`` array or a ``.f32be`` section is refused, since
every command reads those as they are) and opens the SEG-Y through :func:`~seismo3d.seismic.io.open_segy`, the header
reader of ``seismo3d.open`` (same flags and errors as every command; the labelled cube itself is not built, as xarray
and dask would add about 0.8 CPU s of imports to a conversion of about 1.2 CPU s). It writes the layout of
:mod:`~seismo3d.seismic.io.zarr_store` tile by tile, two threads each reading, encoding and writing a chunk (memory:
about ``chunk_mb`` MiB of amplitudes, not the cube), with progress; the amplitudes uncompressed unless
``compression`` names a compressor (float32 seismic compresses 1.1x losslessly). The input's sha256 for ``run.json``
is computed on a thread while numpy, segyio and zarr are imported (in the run, not at the top of this module) and the
cube is copied. The
store is written into a temporary directory beside OUTPUT and renamed to OUTPUT when complete, so an interrupted
convert (error, Ctrl-C, kill) never leaves something at OUTPUT that looks finished (a killed process may leave a
hidden ``.OUTPUT.*.tmp`` directory, never OUTPUT). The input is only read.

OUTPUT follows the output policy of every command (:mod:`seismo3d.jobs.outputs`): not the input nor a folder holding
it, and an existing OUTPUT only with ``overwrite=True`` (``--overwrite``), which replaces only a store written by
``seismo3d convert`` (anything else at OUTPUT is refused, so a wrong path cannot delete a folder).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass
from pathlib import Path

from .._atomic import atomic_directory
from .._progress import progress_steps
from ..errors import InputError, TraceListWarning
from .outputs import check_outputs, output_store
from .runinfo import RunRecord, run_json_output, run_json_path

__all__ = ["ConvertResult", "run_convert_job"]


@dataclass(frozen=True)
class ConvertResult:
    """What :func:`run_convert_job` wrote.

    Attributes
    ----------
    output : pathlib.Path
        The Zarr store.
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    chunks : (int, int, int)
        Chunk shape of the ``seismic`` array.
    header_fields : tuple of str
        The trace header fields kept (segyio.TraceField names; the ones not zero on every trace).
    has_cdp_coordinates : bool
        Whether ``cdp_x`` / ``cdp_y`` were written.
    seconds : float
        Wall time of the conversion.
    run_json : pathlib.Path
        The record of the run, ``OUTPUT.run.json`` beside the store (:mod:`seismo3d.jobs.runinfo`).
    stage_seconds : dict
        Wall time of each stage (``open``, ``write``).
    """

    output: Path
    shape: tuple
    chunks: tuple
    header_fields: tuple
    has_cdp_coordinates: bool
    seconds: float
    run_json: Path | None = None
    stage_seconds: dict | None = None

    @property
    def summary(self) -> str:
        """One line: what was written."""
        n_il, n_xl, ns = self.shape
        coords = ", cdp_x / cdp_y" if self.has_cdp_coordinates else ""
        return (f"{n_il} inlines x {n_xl} crosslines x {ns} samples -> {self.output} (chunks {self.chunks}, "
                f"{len(self.header_fields)} trace header fields{coords}) in {self.seconds:.1f} s")


def _check_output(input: Path, output: Path, overwrite: bool):
    """The output policy, and an existing output replaced only when it is a store of this command; the store as an
    :class:`~seismo3d.jobs.outputs.Output`."""
    main = output_store(output, input.with_suffix(".zarr").name)
    check_outputs([main, run_json_output(main)], [input], overwrite=overwrite)
    if (output.exists() or output.is_symlink()) and not _is_seismic_zarr(output):
        raise InputError(f"output {output} exists and is not a store written by seismo3d convert; overwrite=True "
                         "(--overwrite) replaces only those: remove it yourself or choose another path")
    return main


_NOT_SEGY = {"zarr": "a Zarr store", "npy": "a numpy array (.npy)", "f32be": "a raw float32 section (.f32be)"}


def _check_segy_input(input: Path, kind: str) -> None:
    """Refuse an input that ``seismo3d.open`` reads with another reader than SEG-Y's
    (:func:`~seismo3d.seismic.io.cube.reader_kind`): convert writes a SEG-Y cube's amplitudes and headers into a store,
    and every command reads those inputs as they are."""
    if kind != "segy":
        raise InputError(f"{input.name} is {_NOT_SEGY[kind]}, not SEG-Y: convert writes a 3D SEG-Y cube into a Zarr "
                         "store, and every command (seismo3d.open) reads this input as it is; pass it to the command "
                         "itself, or convert the SEG-Y it came from")


def _is_seismic_zarr(path: Path) -> bool:
    from ..seismic.io.zarr_store import is_seismic_zarr

    return is_seismic_zarr(path)


def run_convert_job(input, output, *, iline: int = 189, xline: int = 193, endian=None, sample_unit=None,
                    chunk_mb: float = 64, compression: str = "none", overwrite: bool = False,
                    progress: bool = False) -> ConvertResult:
    """Convert a 3D SEG-Y cube into a Zarr v3 store (layout of :mod:`~seismo3d.seismic.io.zarr_store`).

    Parameters
    ----------
    input : str or os.PathLike
        A 3D SEG-Y cube (inline- or crossline-sorted, big- or little-endian, any sample format segyio reads).
    output : str or os.PathLike
        The store's directory, e.g. ``cube.zarr``; its folder must exist.
    iline, xline : int
        Trace header bytes of the inline and crossline numbers (189 / 193 by default, SEG-Y rev 1).
    endian : {'big', 'little'}, optional
        Byte order; by default detected from the binary header.
    sample_unit : {'ms', 'm', 'ft'}, optional
        Unit of the sample axis; by default from the headers (see :class:`~seismo3d.seismic.io.SeismicCube`).
    chunk_mb : float
        Amplitudes read or being written at a time, and per tile (one progress step), in MiB (at least one 64 x
        64-trace chunk): the memory bound.
    compression : {'none', 'lz4', 'zstd'}
        The amplitudes' compressor, recorded in the store's metadata (every Zarr reader decodes it): none by default,
        Blosc LZ4 with byte shuffle, or Zstd level 0 (Zarr's default). Float32 seismic barely compresses
        losslessly: on the data folder's field sections (Volve's full stack, Campos, Costa Rica, Teapot, an F3
        section) LZ4 stores 1.10-1.13x fewer bytes and Zstd 1.07-1.08x, while encoding costs CPU (LZ4: 0.22-0.41
        CPU s for a 198 MB cube whose conversion takes about 1.2 CPU s in all); amplitudes that were integers or are
        smooth compress more (LZ4 1.5-1.8x on the F3 crop and another F3 section, Penobscot xl1155 and Volve's
        velocities), where a compressor may pay for the disk it saves.
    overwrite : bool
        Replace an existing ``output`` written by ``seismo3d convert``.
    progress : bool
        Report progress, one step per tile (:func:`seismo3d._progress.progress_steps`).

    Returns
    -------
    ConvertResult

    Raises
    ------
    SegyGeometryError
        The input is a 2D line or a trace list (the store holds 3D cubes), or has no grid at ``iline`` / ``xline``.
    SegyFormatError, DataNotFoundError
        The input cannot be read or does not exist (see :func:`~seismo3d.seismic.io.open_segy`).
    InputError
        ``input`` is a Zarr store, a ``.npy`` array or a ``.f32be`` section (by
        :func:`~seismo3d.seismic.io.cube.reader_kind`); ``output`` is the input or holds it, exists (without
        ``overwrite``, or is not a store of this command), or cannot be written (its folder does not exist or takes no
        files); invalid ``iline``, ``xline``, ``endian``, ``sample_unit``, ``compression``.

    References
    ----------
    Zarr v3 core specification; MDIO (TGS) for the layout idea; SEG-Y rev 1 (2002) headers.
    """
    record = RunRecord("convert", locals())  # first: the arguments as called
    input, output = Path(input), Path(output)
    started = time.perf_counter()
    # 1. outputs that must not be written, before any reading; then the input's sha256 on a background thread, while
    # numpy, segyio and zarr are imported (here, not at the top of the module: 0.3-0.4 s of one core) and the cube read
    main = _check_output(input, output, overwrite)
    record.identify_early(input)
    from .._validation import check_positive
    from ..seismic.io.cube import reader_kind
    from ..seismic.io.segy import open_segy
    from ..seismic.io.zarr_store import SeismicZarrWriter

    check_positive(chunk_mb, "chunk_mb")
    _check_segy_input(input, reader_kind(input))
    # 2. the SEG-Y's geometry through the one opening path (a trace list is refused by the writer, saying what it is)
    with warnings.catch_warnings(), record.stage("open"):
        warnings.simplefilter("ignore", TraceListWarning)
        cube = open_segy(input, iline=iline, xline=xline, sample_unit=sample_unit, endian=endian)
    # 3. tile by tile into a temporary store, renamed to OUTPUT when complete
    # (leaving the writer's block waits for its background writes, so that an interrupted store is removed whole)
    with cube, record.stage("write"), atomic_directory(output) as tmp, \
            SeismicZarrWriter(cube, tmp, chunk_mb=chunk_mb, compression=compression) as writer:
        with progress_steps(len(writer.tiles), f"convert {input.name}", unit="tile", enabled=progress) as steps:
            for tile in writer.tiles:
                writer.write_tile(tile)
                steps.advance()
        kept = writer.finish()
        chunks = tuple(int(c) for c in writer.seismic.chunks)
        has_coords = "cdp_x" in writer.root
    shape = tuple(int(n) for n in cube.shape)
    run_json = record.write(run_json_path(main), inputs={"input": input}, outputs={"store": output},
                            results=dict(shape=shape, chunks=chunks, header_fields=list(kept),
                                         has_cdp_coordinates=has_coords))
    return ConvertResult(output=output, shape=shape, chunks=chunks, header_fields=tuple(kept),
                         has_cdp_coordinates=has_coords, seconds=time.perf_counter() - started, run_json=run_json,
                         stage_seconds=dict(record.stage_seconds))
