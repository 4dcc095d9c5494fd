"""One place for checking arrays at the public boundary.

Public functions call these helpers once on entry; internal code trusts its inputs.
"""

from __future__ import annotations

import numpy as np

from .errors import InputError

__all__ = ["as_points", "as_pair", "as_weights", "as_image", "as_normals", "as_intrinsics", "as_seismic",
           "as_sigma_pair", "check_choice", "check_core", "check_int", "check_positive"]


def as_points(points, name: str = "points", *, dims=(2, 3), min_points: int = 1) -> np.ndarray:
    """Return ``points`` as a C-contiguous (N, d) float64 array, or raise :class:`InputError`.

    Parameters
    ----------
    points : (N, d) array_like
        Coordinates; d must be one of ``dims``.
    name : str
        The argument's name, used in error messages.
    dims : tuple of int
        Allowed dimensions.
    min_points : int
        Smallest allowed N.
    """
    try:
        arr = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be a numeric (N, d) array; got {type(points).__name__}") from exc
    if arr.ndim != 2 or arr.shape[1] not in dims:
        allowed = " or ".join(f"(N, {d})" for d in dims)
        raise InputError(f"{name} must have shape {allowed}; got {arr.shape}. Pass one point per row.")
    if arr.shape[0] < min_points:
        raise InputError(
            f"{name} has {arr.shape[0]} points but at least {min_points} are needed; pass more points "
            "(or a smaller model, e.g. model='rigid')"
        )
    if not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr).all(axis=1)))
        raise InputError(f"{name} has {bad} rows with NaN or inf; drop them first, e.g. points[np.isfinite(points).all(1)]")
    return np.ascontiguousarray(arr)


def as_pair(source, target, *, dims=(2, 3), min_points: int = 1, names=("source", "target")):
    """Validate two paired point sets of equal shape (N, d); return both as float64."""
    src = as_points(source, names[0], dims=dims, min_points=min_points)
    dst = as_points(target, names[1], dims=dims, min_points=min_points)
    if src.shape != dst.shape:
        raise InputError(
            f"{names[0]} {src.shape} and {names[1]} {dst.shape} must be paired row by row with the same shape"
        )
    return src, dst


def as_weights(weights, n: int, name: str = "weights") -> np.ndarray:
    """Return (n,) non-negative finite float64 weights (ones when ``weights`` is None)."""
    if weights is None:
        return np.ones(n)
    w = np.asarray(weights, dtype=np.float64)
    if w.shape != (n,):
        raise InputError(f"{name} must have shape ({n},), one weight per point; got {w.shape}")
    if not np.all(np.isfinite(w)) or np.any(w < 0):
        raise InputError(f"{name} must be finite and non-negative")
    if not np.any(w > 0):
        raise InputError(f"{name} are all zero; at least one point must carry weight")
    return w


def as_image(image, name: str = "image", *, min_size: int = 2) -> np.ndarray:
    """Return a 2D float64 image, rejecting empty, tiny, NaN and multi-channel input with a clear message."""
    arr = np.asarray(image)
    if arr.ndim == 3 and arr.shape[2] in (3, 4):
        raise InputError(f"{name} has {arr.shape[2]} channels but a single-channel image is expected; "
                         "convert it first, e.g. skimage.color.rgb2gray(image)")
    if arr.ndim != 2:
        raise InputError(f"{name} must be a 2D (rows, cols) array; got shape {arr.shape}")
    if min(arr.shape) < min_size:
        raise InputError(f"{name} is {arr.shape[0]}x{arr.shape[1]} pixels; at least {min_size}x{min_size} is needed")
    arr = arr.astype(np.float64, copy=False)
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} contains NaN or inf; fill them first, e.g. np.nan_to_num(image)")
    return arr


def check_choice(value, name: str, choices) -> str:
    """Raise :class:`InputError` unless ``value`` is one of ``choices``."""
    if value not in choices:
        raise InputError(f"{name}={value!r} is not supported; use one of {sorted(choices)}")
    return value


def check_positive(value, name: str, *, allow_zero: bool = False) -> float:
    """Raise :class:`InputError` unless ``value`` is a finite number > 0 (>= 0 with ``allow_zero``)."""
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be a number; got {value!r}") from exc
    if not np.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise InputError(f"{name} must be {'>= 0' if allow_zero else '> 0'}; got {value!r}")
    return v


def check_core(core, shape) -> tuple[int, int, int, int]:
    """The traces ``(i0, i1, j0, j1)`` of a block's core in a cube, or raise :class:`InputError`.

    Parameters
    ----------
    core : (slice, slice)
        The core's inlines and crosslines (``rows, cols``): slices of step 1 (or None) whose bounds are None or
        integers within the cube's first two axes, selecting at least one trace.
    shape : tuple of int
        Of the cube, ``(n_inlines, n_xlines, n_samples)`` (a 2D section's shape is refused: it has no core).

    Returns
    -------
    (int, int, int, int)
        ``(i0, i1, j0, j1)``, half-open, ``0 <= i0 < i1 <= n_inlines`` and ``0 <= j0 < j1 <= n_xlines``.
    """
    if len(shape) != 3:
        raise InputError(f"core is for a cube's (rows, cols); got an array of shape {tuple(shape)}")
    if not (isinstance(core, tuple) and len(core) == 2
            and all(isinstance(s, slice) and s.step in (None, 1) for s in core)):
        raise InputError(f"core must be two slices of step 1, (rows, cols); got {core!r}")
    box = []
    for s, n in zip(core, shape[:2]):
        a, b = (0 if s.start is None else s.start), (n if s.stop is None else s.stop)
        if not (isinstance(a, (int, np.integer)) and isinstance(b, (int, np.integer)) and 0 <= a < b <= n):
            raise InputError(f"core {core!r} must select at least one trace within a cube of shape {tuple(shape)}")
        box += [int(a), int(b)]
    return tuple(box)


def check_int(value, name: str, *, minimum: int | None = None, maximum: int | None = None,
              allow_none: bool = False) -> int | None:
    """Return ``value`` as an int, or raise :class:`InputError` unless it is an integer (not a bool, not a float)
    within ``[minimum, maximum]`` (None with ``allow_none``)."""
    if value is None and allow_none:
        return None
    ok = not isinstance(value, bool) and isinstance(value, (int, np.integer))
    ok = ok and (minimum is None or value >= minimum) and (maximum is None or value <= maximum)
    if not ok:
        if minimum is not None and maximum is not None:
            need = f"an int in [{minimum}, {maximum}]"
        elif minimum is not None:
            need = f"an int >= {minimum}"
        elif maximum is not None:
            need = f"an int <= {maximum}"
        else:
            need = "an int"
        raise InputError(f"{name} must be {need}{' or None' if allow_none else ''}; got {value!r}")
    return int(value)


def check_seismic_layout(shape, dtype, name: str = "data", *, min_size: int = 3) -> None:
    """Raise :class:`InputError` unless an array of ``shape`` and ``dtype`` is a numeric 2D section or 3D cube whose
    axes hold at least ``min_size`` samples (without reading it: also for lazy dask / Zarr arrays)."""
    dtype = np.dtype(dtype)
    if dtype == object or not (np.issubdtype(dtype, np.number) or dtype == bool):
        raise InputError(f"{name} must be a numeric array; got dtype {dtype}")
    if len(shape) not in (2, 3):
        raise InputError(
            f"{name} must be a 2D section (n_traces, n_samples) or a 3D cube (n_inlines, n_xlines, n_samples); "
            f"got shape {tuple(shape)}"
        )
    if min(shape) < min_size:
        raise InputError(f"{name} has shape {tuple(shape)}; every axis needs at least {min_size} samples")


def as_seismic(data, name: str = "data", *, min_size: int = 3) -> np.ndarray:
    """Return ``data`` as a C-contiguous float32 2D section (n_traces, n_samples) or 3D cube (n_inlines, n_xlines,
    n_samples), or raise :class:`InputError` (not numeric, not 2D / 3D, an axis shorter than ``min_size``, NaN or
    inf)."""
    try:
        arr = np.asarray(data)
    except (TypeError, ValueError) as exc:  # pragma: no cover - numpy accepts almost anything
        raise InputError(f"{name} must be a numeric array; got {type(data).__name__}") from exc
    check_seismic_layout(arr.shape, arr.dtype, name, min_size=min_size)
    arr = np.ascontiguousarray(arr, dtype=np.float32)
    if not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        raise InputError(f"{name} has {bad} NaN or inf samples; fill them first, e.g. np.nan_to_num({name})")
    return arr


def as_sigma_pair(value, name: str) -> tuple[float, float]:
    """Parse a (lateral in traces, vertical in samples) pair of Gaussian widths > 0; a scalar sets both."""
    vals = np.atleast_1d(np.asarray(value, dtype=np.float64)).ravel()
    if vals.size == 1:
        vals = np.repeat(vals, 2)
    if vals.size != 2:
        raise InputError(f"{name} must be a number or a pair (lateral in traces, vertical in samples); got {value!r}")
    for v in vals:
        check_positive(v, name)
    return float(vals[0]), float(vals[1])


def as_normals(normals, name: str, shape: tuple, *, of: str = "point") -> np.ndarray:
    """Return ``normals`` normalised to unit length, checking one per point and no zero vectors.

    Parameters
    ----------
    normals : (N, d) array_like
    name : str
        The argument's name, used in error messages.
    shape : tuple
        The required shape (N, d): that of the points the normals belong to.
    of : str
        What the points are, for the message (e.g. ``'target point'``).
    """
    v = as_points(normals, name, dims=(shape[1],), min_points=0)
    if v.shape != tuple(shape):
        raise InputError(f"{name} {v.shape} must have one normal per {of} {tuple(shape)}")
    length = np.linalg.norm(v, axis=1)
    if np.any(length < 1e-12):
        raise InputError(f"{name} contains zero vectors; drop those points or recompute them")
    return v / length[:, None]


def as_intrinsics(intrinsics):
    """Return pinhole intrinsics ``(fx, fy, cx, cy)`` in pixels from a (3, 3) matrix, four numbers or an object with
    ``.matrix`` (e.g. :class:`seismo3d.data.CameraIntrinsics`); raise :class:`InputError` otherwise."""
    if hasattr(intrinsics, "matrix"):
        intrinsics = intrinsics.matrix
    k = np.asarray(intrinsics, dtype=np.float64)
    if k.shape == (3, 3):
        fx, fy, cx, cy = k[0, 0], k[1, 1], k[0, 2], k[1, 2]
    elif k.shape == (4,):
        fx, fy, cx, cy = k
    else:
        raise InputError(f"intrinsics must be a (3, 3) camera matrix or (fx, fy, cx, cy); got shape {k.shape}")
    if not (np.isfinite([fx, fy, cx, cy]).all() and fx > 0 and fy > 0):
        raise InputError(f"intrinsics need finite values and fx, fy > 0; got fx={fx}, fy={fy}")
    return float(fx), float(fy), float(cx), float(cy)
