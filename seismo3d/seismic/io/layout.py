"""The layout of a SEG-Y file read from its binary header: byte order, sample format, samples per trace, extended
textual headers, trace size and count.

:func:`read_segy_layout` reads the 400-byte binary header itself (before segyio opens the file) so that the byte order
is detected rather than assumed, and so that every file segyio cannot read is refused with the reason, one line,
instead of segyio's internal message.

Byte order
----------
SEG-Y is big-endian by the standard, but workstation and PC exports are often little-endian. The order is the one in
which the data sample format code (binary header bytes 3225-3226) is a SEG-Y code (1-12, 15, 16). A code ``c`` read
in the other order is ``256 c``, never a code, so at most one order qualifies. The samples per trace (bytes
3221-3222, or 3269-3272 in SEG-Y rev 2) must then make the file a whole number of traces in that order; a file that
is not is refused as cut short. When neither order holds a code, the SEG-Y rev 2 byte-order constant 16909060
(bytes 3297-3300, ``0x01020304`` as written) names the order; with neither, the file is not SEG-Y.

Where the rule can be fooled: a file whose samples are in another byte order than its headers (the samples are read
byte-swapped; nothing in the headers shows it), and a file whose format code is wrong (e.g. 1 for IEEE samples).

Field positions follow SEG-Y rev 1 (SEG Technical Standards Committee, 2002) and rev 2.0 (2017), binary file header.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import SegyFormatError

__all__ = ["SegyLayout", "read_segy_layout", "segyio_failure", "FORMAT_NAMES", "READABLE_FORMATS", "SAMPLE_BYTES",
           "TRACE_HEADER_BYTES"]

TEXT_HEADER_BYTES = 3200
BINARY_HEADER_BYTES = 400
TRACE_HEADER_BYTES = 240
HEADER_BYTES = TEXT_HEADER_BYTES + BINARY_HEADER_BYTES

FORMAT_NAMES = {
    1: "4-byte IBM float",
    2: "4-byte signed integer",
    3: "2-byte signed integer",
    4: "4-byte fixed point with gain",
    5: "4-byte IEEE float",
    6: "8-byte IEEE float",
    7: "3-byte signed integer",
    8: "1-byte signed integer",
    9: "8-byte signed integer",
    10: "4-byte unsigned integer",
    11: "2-byte unsigned integer",
    12: "8-byte unsigned integer",
    15: "3-byte unsigned integer",
    16: "1-byte unsigned integer",
}
# Bytes per sample of each sample format code (SEG-Y rev 2 Table 1; binary header bytes 3225-3226)
SAMPLE_BYTES = {1: 4, 2: 4, 3: 2, 4: 4, 5: 4, 6: 8, 7: 3, 8: 1, 9: 8, 10: 4, 11: 2, 12: 8, 15: 3, 16: 1}
# The codes segyio's Python reader decodes (it reads 4, 7 and 15 as IBM floats, with a warning).
READABLE_FORMATS = frozenset({1, 2, 3, 5, 6, 8, 9, 10, 11, 12, 16})

_BYTE_ORDER_CONSTANT = 16909060  # 0x01020304, SEG-Y rev 2 bytes 3297-3300
_END_TEXT = re.compile(r"\(\(\s*SEG\s*:\s*EndText\s*\)\)", re.IGNORECASE)
_ORDER = {"big": ">", "little": "<"}


@dataclass(frozen=True)
class SegyLayout:
    """What the binary header says about a file, in the byte order it was written in.

    Attributes
    ----------
    endian : {'big', 'little'}
        The file's byte order.
    endian_from : {'format code', 'byte-order constant', 'given'}
        How it was decided: the order in which bytes 3225-3226 hold a sample format code, the SEG-Y rev 2 constant
        of bytes 3297-3300, or the caller's ``endian``.
    format : int
        Data sample format code (bytes 3225-3226).
    n_samples : int
        Samples per trace: bytes 3221-3222, or the SEG-Y rev 2 extended count (bytes 3269-3272) when that one is
        positive and either the revision (byte 3501) is 2 or more or bytes 3221-3222 are 0 (segyio's rule).
    extended_sample_count : bool
        Whether ``n_samples`` came from bytes 3269-3272.
    n_text_headers : int
        Extended textual headers after the binary header (bytes 3505-3506).
    n_traces : int
        Traces in the file, from its size.
    trace_bytes : int
        Bytes per trace: the 240-byte trace header and ``n_samples`` samples.
    data_offset : int
        Byte offset of the first trace.
    revision : int
        SEG-Y major revision (byte 3501; 0 for most rev 0 and rev 1 files, which wrote 0x0100 in bytes 3501-3502).
    file_size : int
        Bytes.
    """

    endian: str
    endian_from: str
    format: int
    n_samples: int
    extended_sample_count: bool
    n_text_headers: int
    n_traces: int
    trace_bytes: int
    data_offset: int
    revision: int
    file_size: int

    @property
    def format_name(self) -> str:
        """E.g. ``'4-byte IBM float'``."""
        return FORMAT_NAMES.get(self.format, f"format {self.format}")


@dataclass(frozen=True)
class _Reading:
    """The binary header's fields read in one byte order."""

    endian: str
    format: int
    n_samples: int
    extended_sample_count: bool
    n_text_headers: int
    extra_trace_headers: int
    revision: int
    byte_order_constant: int

    @property
    def has_format_code(self) -> bool:
        return self.format in SAMPLE_BYTES


def _read_fields(binary: bytes, endian: str) -> _Reading:
    """The fields of a 400-byte binary header (file bytes 3201-3600) in byte order ``endian``."""
    order = _ORDER[endian]

    def field(byte: int, dtype: str) -> int:  # ``byte``: the 1-based file byte of the field, as in the standard
        return int(np.frombuffer(binary, dtype=order + dtype, count=1, offset=byte - 3201)[0])

    revision = binary[3501 - 3201]  # one byte in rev 2; rev 1 wrote 0x0100 in 3501-3502, i.e. 1 here (big-endian)
    n_samples = field(3221, "u2")
    extended = field(3269, "i4")
    use_extended = extended > 0 and (n_samples == 0 or revision >= 2)
    return _Reading(endian=endian, format=field(3225, "u2"), n_samples=extended if use_extended else n_samples,
                    extended_sample_count=use_extended, n_text_headers=field(3505, "i2"),
                    extra_trace_headers=field(3507, "u2") if revision >= 2 else 0, revision=revision,
                    byte_order_constant=field(3297, "i4"))


def _choose_byte_order(readings: dict, name: str, endian) -> tuple:
    """(the reading in the file's byte order, how it was decided); raise SegyFormatError when no order fits."""
    big, little = readings["big"], readings["little"]
    if endian is not None:
        chosen = readings[endian]
        if not chosen.has_format_code:
            other = "little" if endian == "big" else "big"
            hint = (f"it reads as {other}-endian (format {readings[other].format}): omit endian to detect the byte "
                    f"order, or pass endian='{other}'") if readings[other].has_format_code else \
                "no byte order gives a SEG-Y sample format code: the file is not SEG-Y"
            raise SegyFormatError(f"{name} read as {endian}-endian has sample format code {chosen.format} (binary "
                                  f"header bytes 3225-3226), not a SEG-Y code; {hint}")
        return chosen, "given"
    coded = [r for r in (big, little) if r.has_format_code]
    if len(coded) == 1:
        return coded[0], "format code"
    for reading in (big, little):
        if reading.byte_order_constant == _BYTE_ORDER_CONSTANT:
            raise SegyFormatError(
                f"{name} is {reading.endian}-endian SEG-Y (byte-order constant of bytes 3297-3300) but its sample "
                f"format code is {reading.format} (bytes 3225-3226), not a SEG-Y code; fix the binary header")
    raise SegyFormatError(
        f"{name} is not SEG-Y: its binary header holds no sample format code (bytes 3225-3226 read {big.format} "
        f"big-endian, {little.format} little-endian); a Seismic Unix (.su) file, for one, has no SEG-Y headers")


def _count_text_headers(raw: memoryview, name: str) -> int:
    """The number of extended textual headers of a file that declares a variable count (-1): the 3200-byte blocks
    after the binary header up to the one holding ``((SEG: EndText))`` (ASCII or EBCDIC)."""
    k = 0
    while HEADER_BYTES + (k + 1) * TEXT_HEADER_BYTES <= len(raw) and k < 1000:
        block = bytes(raw[HEADER_BYTES + k * TEXT_HEADER_BYTES: HEADER_BYTES + (k + 1) * TEXT_HEADER_BYTES])
        k += 1
        if any(_END_TEXT.search(block.decode(enc, errors="replace")) for enc in ("ascii", "cp500")):
            return k
    raise SegyFormatError(f"{name} declares a variable number of extended textual headers (-1 in binary header bytes "
                          "3505-3506) but none ends with ((SEG: EndText)); the file is damaged")


def _stanza_start(block: bytes) -> str | None:
    """The first line of a 3200-byte block that begins like an extended textual header (``((...``, ASCII or
    EBCDIC), else None."""
    for encoding in ("ascii", "cp500"):
        text = block.decode(encoding, errors="replace").lstrip()
        if text.startswith("(("):
            return text.split("\n", 1)[0][:60].rstrip()
    return None


def _refuse_undeclared_text_headers(path: Path, chosen: _Reading, data_offset: int, rest: int,
                                    trace_bytes: int) -> None:
    """Raise SegyFormatError when extended textual headers that bytes 3505-3506 do not count explain why the file
    is not a whole number of traces (SEG-Y rev 1 section 3.3: each begins with a ``((...))`` stanza name)."""
    k, first = 0, None
    with open(path, "rb") as fh:
        fh.seek(data_offset)
        while (k + 1) * TEXT_HEADER_BYTES <= rest and k < 100:
            start = _stanza_start(fh.read(TEXT_HEADER_BYTES))
            if start is None:
                break
            first = first or start
            k += 1
    if k and (rest - k * TEXT_HEADER_BYTES) % trace_bytes == 0 and rest > k * TEXT_HEADER_BYTES:
        n = chosen.n_text_headers
        raise SegyFormatError(
            f"{path.name} has {n + k} extended textual header{'s' if n + k > 1 else ''} (the "
            f"{'first' if n == 0 else 'next'} begins "
            f"{first!r}) but binary header bytes 3505-3506 say {n}; write {n + k} there in a copy of the file")


def _segyio_version() -> str:
    from importlib import metadata  # here: 10-15 ms to import, for a message only

    try:
        return metadata.version("segyio")
    except metadata.PackageNotFoundError:  # pragma: no cover - segyio imported from a source tree
        return "(unknown version)"


def read_segy_layout(path, *, endian=None) -> SegyLayout:
    """Read a SEG-Y file's layout from its binary header and size, detecting the byte order.

    Parameters
    ----------
    path : str or os.PathLike
        The file; only its first 3600 bytes (and the extended textual headers of a file that declares a variable
        number of them) are read.
    endian : {'big', 'little'}, optional
        The byte order, when known; by default detected (see the module docstring).

    Returns
    -------
    SegyLayout

    Raises
    ------
    SegyFormatError
        One line naming the reason: the file is shorter than the 3600 bytes of headers, holds no sample format code in
        either byte order (not SEG-Y), declares a variable number of extended textual headers (segyio needs the
        count), has SEG-Y rev 2 additional trace headers, 0 samples per trace or no traces, is not a whole number of
        traces (cut short, or extended textual headers that bytes 3505-3506 do not count), or uses a sample format
        segyio does not decode (4, 7, 15).
    """
    path = Path(path)
    name = path.name
    with open(path, "rb") as fh:
        head = fh.read(HEADER_BYTES)
    size = path.stat().st_size
    if len(head) < HEADER_BYTES:
        raise SegyFormatError(f"{name} has {size} bytes, fewer than the 3600 bytes of a SEG-Y file's textual and "
                              "binary headers: it is not SEG-Y, or it was cut short")
    binary = head[TEXT_HEADER_BYTES:]
    readings = {e: _read_fields(binary, e) for e in ("big", "little")}
    chosen, endian_from = _choose_byte_order(readings, name, endian)

    n_text = chosen.n_text_headers
    if n_text == -1:
        with open(path, "rb") as fh:
            found = _count_text_headers(memoryview(fh.read(HEADER_BYTES + 1000 * TEXT_HEADER_BYTES)), name)
        raise SegyFormatError(
            f"{name} declares a variable number of extended textual headers (-1 in binary header bytes 3505-3506), "
            f"which segyio {_segyio_version()} cannot read; it has {found}: write {found} in bytes 3505-3506 of a copy")
    if n_text < 0:
        raise SegyFormatError(f"{name} declares {n_text} extended textual headers (binary header bytes 3505-3506); "
                              "the binary header is damaged")
    if chosen.extra_trace_headers:
        raise SegyFormatError(
            f"{name} is SEG-Y rev {chosen.revision} with {chosen.extra_trace_headers} additional 240-byte trace "
            f"header(s) per trace (binary header bytes 3507-3508), which segyio {_segyio_version()} cannot read; "
            "export it as SEG-Y rev 1")
    if chosen.n_samples <= 0:
        raise SegyFormatError(f"{name} declares 0 samples per trace (binary header bytes 3221-3222); the binary "
                              "header is damaged or the file is not SEG-Y")

    data_offset = HEADER_BYTES + TEXT_HEADER_BYTES * n_text
    trace_bytes = TRACE_HEADER_BYTES + chosen.n_samples * SAMPLE_BYTES[chosen.format]
    rest = size - data_offset
    if rest <= 0:
        where = "its headers" if n_text == 0 else f"its headers and {n_text} extended textual headers"
        raise SegyFormatError(f"{name} has no traces: the file ends after {where} ({size} bytes)"
                              if rest == 0 else f"{name} is cut short: it ends inside {where} ({size} bytes)")
    n_traces, extra = divmod(rest, trace_bytes)
    if extra:
        _refuse_undeclared_text_headers(path, chosen, data_offset, rest, trace_bytes)
        raise SegyFormatError(
            f"{name} is not a whole number of traces: {rest} bytes after the headers make {n_traces} traces of "
            f"{trace_bytes} bytes ({chosen.n_samples} samples of {SAMPLE_BYTES[chosen.format]} bytes) and {extra} "
            f"bytes more; the file is cut short, or its headers do not describe it ({chosen.endian}-endian, "
            f"{n_text} extended textual headers)")
    if chosen.format not in READABLE_FORMATS:
        raise SegyFormatError(
            f"{name} holds samples in format {chosen.format} ({FORMAT_NAMES[chosen.format]}), which segyio "
            f"{_segyio_version()} cannot decode; convert it to 4-byte IEEE float (format 5)")
    return SegyLayout(endian=chosen.endian, endian_from=endian_from, format=chosen.format,
                      n_samples=chosen.n_samples, extended_sample_count=chosen.extended_sample_count,
                      n_text_headers=n_text, n_traces=int(n_traces), trace_bytes=trace_bytes,
                      data_offset=data_offset, revision=chosen.revision, file_size=size)


def segyio_failure(layout: SegyLayout, name: str) -> str:
    """One line saying why segyio could not open a file whose layout :func:`read_segy_layout` accepted."""
    version = _segyio_version()
    if layout.endian == "little" and layout.extended_sample_count:
        return (f"{name} is little-endian SEG-Y rev {layout.revision} whose samples per trace are in the extended "
                f"field (binary header bytes 3269-3272), which segyio {version} reads in the wrong byte order; "
                "convert the file to big-endian")
    return (f"segyio {version} cannot open {name} although its binary header describes {layout.n_traces} traces of "
            f"{layout.n_samples} samples ({layout.format_name}, {layout.endian}-endian); the trace headers may be "
            "damaged")
