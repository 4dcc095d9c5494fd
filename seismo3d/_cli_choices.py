"""The choices of the ``seismo3d`` command's options (typer shows them as ``[a|b|c]`` and refuses others)."""

from __future__ import annotations

from enum import Enum

__all__ = ["Compression", "Endian", "FaultColour", "Likelihood", "MatchMethod", "Method", "Model", "Polarity",
           "SampleUnit"]


class Method(str, Enum):
    point_to_point = "point_to_point"
    point_to_plane = "point_to_plane"
    fused = "fused"


class Model(str, Enum):
    rigid = "rigid"
    similarity = "similarity"
    axis_scaled = "axis_scaled"
    affine = "affine"


class Endian(str, Enum):
    big = "big"
    little = "little"


class Compression(str, Enum):
    none = "none"
    lz4 = "lz4"
    zstd = "zstd"


class SampleUnit(str, Enum):
    ms = "ms"
    m = "m"
    ft = "ft"


class Likelihood(str, Enum):
    scan = "scan"
    learned = "learned"


class MatchMethod(str, Enum):
    hog = "hog"
    sift = "sift"
    orb = "orb"
    akaze = "akaze"
    brisk = "brisk"


class Polarity(str, Enum):
    peak = "peak"
    trough = "trough"
    zero_rising = "zero_rising"
    zero_falling = "zero_falling"


class FaultColour(str, Enum):
    fault_id = "fault_id"
    throw = "throw"
