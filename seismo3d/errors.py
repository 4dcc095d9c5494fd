"""The exception and warning tree of seismo3d.

Every error raised on purpose by seismo3d derives from :class:`Seismo3dError` and from the built-in exception a
caller would naturally catch (``ValueError`` for bad arguments, ``OSError`` for files), so both
``except Seismo3dError`` and ``except ValueError`` work. Messages state the problem and the fix.
"""

from __future__ import annotations

__all__ = [
    "Seismo3dError",
    "InputError",
    "EarlierStoresError",
    "SeedError",
    "DataNotFoundError",
    "DataIntegrityError",
    "SegyFormatError",
    "SegyGeometryError",
    "UnsupportedDataError",
    "RegistrationError",
    "PlanningError",
    "MissingDependencyError",
    "Seismo3dWarning",
    "DegenerateGeometryWarning",
    "TraceListWarning",
    "FrameSkippedWarning",
]


class Seismo3dError(Exception):
    """Base class of every error seismo3d raises on purpose."""


class InputError(Seismo3dError, ValueError):
    """An argument has the wrong shape, dtype, size or value (NaN, too few points, unknown option)."""


class EarlierStoresError(InputError):
    """A resumable block-by-block run found, where it writes, the stores or work folders of another run (another
    input, likelihood or options), which it neither reuses nor replaces.

    Parameters
    ----------
    message : str
    paths : iterable of str or os.PathLike
        The stores or work folders in the way (a caller that may replace them moves them aside: see
        :class:`seismo3d._atomic.SetAside`).
    """

    def __init__(self, message: str, paths):
        super().__init__(message)
        self.paths = tuple(str(p) for p in paths)


class SeedError(InputError):
    """A horizon seed cannot start a horizon: it lies on a dead trace, or has no reflector of the requested polarity
    near it.

    Parameters
    ----------
    message : str
        The message, in the terms the library was given: index space, or a DataArray cube's own numbers.
    seed : tuple of float
        The seed, index space: ``(inline, xline, sample)`` or ``(trace, sample)``; in the cube's own numbers
        (inline, crossline, time or depth) when the horizon function was given a DataArray.
    nearest : tuple of float or None
        The nearest position (same axes) that can start a horizon (a reflector pick of the requested polarity, or a
        live trace), for a caller to offer in its own terms; None when the data has none.
    window : float or None
        The snapping distance searched, samples; None for a seed on a dead trace.
    """

    def __init__(self, message: str, seed, nearest=None, window=None):
        super().__init__(message)
        self.seed = tuple(float(v) for v in seed)
        self.nearest = None if nearest is None else tuple(float(v) for v in nearest)
        self.window = None if window is None else float(window)


class DataNotFoundError(Seismo3dError, FileNotFoundError):
    """A file is missing: an input path that does not exist, or a registered data file neither in the data directory
    nor downloadable."""


class DataIntegrityError(Seismo3dError, OSError):
    """A data file exists but its content is not what the registry says (hash mismatch, truncated)."""


class SegyFormatError(Seismo3dError, OSError):
    """A file is not SEG-Y, or is truncated or corrupt."""


class SegyGeometryError(Seismo3dError, ValueError):
    """A SEG-Y file's inline / crossline geometry cannot be read with the given header bytes or sorting."""


class UnsupportedDataError(Seismo3dError, ValueError):
    """The data cannot support what was asked: e.g. fault tracing on too few traces, on incoherent data, or on a
    velocity model instead of seismic amplitudes."""


class RegistrationError(Seismo3dError, RuntimeError):
    """A registration could not produce a transform (e.g. RANSAC found no consensus)."""


class PlanningError(Seismo3dError, RuntimeError):
    """No path exists between a start and a goal through traversable cells."""


class MissingDependencyError(Seismo3dError, ImportError):
    """An optional package that what was asked needs is not installed; the message names the package and the
    ``pip install`` that brings it."""


class Seismo3dWarning(UserWarning):
    """Base class of seismo3d's warnings."""


class DegenerateGeometryWarning(Seismo3dWarning):
    """The data does not constrain every degree of freedom of the transform (e.g. a plane under point-to-plane ICP)."""


class TraceListWarning(Seismo3dWarning):
    """A SEG-Y file without an inline / crossline grid at the default header bytes was read as a trace list (a 2D or
    arbitrary line, an unsorted or irregular survey); the message says what its trace headers show."""


class FrameSkippedWarning(Seismo3dWarning):
    """A frame of a sequence could not be used (missing file, wrong depth dtype or size, no valid depth, tracking
    lost) and was skipped; the map and trajectory go on from the other frames."""
