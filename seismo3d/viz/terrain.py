"""Pictures of terrain: the rose diagram of lineament strikes and the lineament map over a hillshade (matplotlib,
imported inside the functions)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._atomic import atomic_path
from ..errors import InputError

__all__ = ["plot_rose", "plot_lineament_map"]


def plot_rose(azimuth_deg, length_m, path, *, bin_deg: float = 10.0, title: str = "", dpi: int = 120) -> Path:
    """Write a length-weighted rose diagram of lineament strikes (PNG, atomically).

    Strikes are axial (a strike of 30 degrees is also 210), so each bin is drawn twice, opposite each other; north is
    up and azimuths run clockwise. The radius is the total length per bin in kilometres.

    Parameters
    ----------
    azimuth_deg : (K,) array_like
        Strikes in [0, 180), degrees clockwise from north.
    length_m : (K,) array_like
        Lengths, metres (the weights).
    path : str or os.PathLike
        PNG to write; its folder must exist.
    bin_deg : float
        Bin width, degrees (dividing 180).
    title : str
    dpi : int

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        Arrays of different lengths or a bin width that does not divide 180.

    References
    ----------
    Nemec, W. (1988). The shape of the rose. Sedimentary Geology 59, 149-152 (length-weighted, axial roses).
    """
    from matplotlib.figure import Figure

    az = np.asarray(azimuth_deg, dtype=np.float64).ravel()
    weights = np.asarray(length_m, dtype=np.float64).ravel()
    if az.shape != weights.shape:
        raise InputError(f"azimuth_deg {az.shape} and length_m {weights.shape} must have one value per lineament")
    n = 180.0 / float(bin_deg)
    if not bin_deg > 0 or abs(n - round(n)) > 1e-9:
        raise InputError(f"bin_deg must divide 180; got {bin_deg!r}")
    edges = np.linspace(0.0, 180.0, int(round(n)) + 1)
    hist, _ = np.histogram(np.mod(az, 180.0), bins=edges, weights=weights)
    km = np.concatenate([hist, hist]) / 1000.0
    centres = np.radians(np.concatenate([edges[:-1], edges[:-1] + 180.0]) + bin_deg / 2.0)
    fig = Figure(figsize=(5.5, 5.8), dpi=dpi, layout="constrained")
    ax = fig.add_subplot(projection="polar")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.bar(centres, km, width=np.radians(bin_deg) * 0.95, color="tab:orange", edgecolor="k", linewidth=0.4)
    ax.set_title(title or f"lineament strikes, length-weighted ({len(az)} lineaments, {weights.sum() / 1000:.1f} km)",
                 fontsize=10)
    ax.set_ylabel("km per bin", labelpad=28)
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    return path


def plot_lineament_map(shade, extent, segments, azimuth_deg, path, *, aspect: float = 1.0, axis_labels=("x", "y"),
                       title: str = "", dpi: int = 120) -> Path:
    """Write a map of lineaments drawn over a hillshade, coloured by strike (PNG, atomically).

    Parameters
    ----------
    shade : (H, W) array_like
        Hillshade (NaN drawn white), row 0 at the top; shown with its 1st-99th percentiles stretched over the grey
        scale, so gentle terrain (slopes of a degree) keeps its contrast.
    extent : (left, right, bottom, top)
        Map coordinates of the raster's outer edges (as matplotlib's ``imshow``).
    segments : (K, 4) array_like
        ``x0, y0, x1, y1`` in the same map coordinates.
    azimuth_deg : (K,) array_like
        Strikes in [0, 180) (the colour, a cyclic colour map).
    path : str or os.PathLike
        PNG to write; its folder must exist.
    aspect : float
        Data aspect ratio (``1 / cos(latitude)`` for longitude / latitude axes).
    axis_labels : (str, str)
    title : str
    dpi : int

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        Wrong shapes.
    """
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure

    img = np.asarray(shade, dtype=np.float64)
    if img.ndim != 2:
        raise InputError(f"shade must be a 2D image; got shape {img.shape}")
    segs = np.asarray(segments, dtype=np.float64).reshape(-1, 4)
    az = np.asarray(azimuth_deg, dtype=np.float64).ravel()
    if len(az) != len(segs):
        raise InputError(f"{len(segs)} segments but {len(az)} azimuths")
    h, w = img.shape
    width_in = 9.0
    height_in = float(np.clip(width_in * h / w * aspect, 4.0, 14.0)) + 0.8
    fig = Figure(figsize=(width_in + 1.2, height_in), dpi=dpi, layout="constrained")
    ax = fig.add_subplot()
    finite = img[np.isfinite(img)]
    lo, hi = np.percentile(finite, [1.0, 99.0]) if finite.size else (0.0, 1.0)
    ax.imshow(img, cmap="gray", vmin=lo, vmax=max(hi, lo + 1e-12), extent=extent, interpolation="bilinear")
    # a dark casing under saturated colours (a cyclic map: strike 0 and 180 are one direction) stands out on grey
    ax.add_collection(LineCollection(segs.reshape(-1, 2, 2), colors="black", linewidths=4.2, alpha=0.8))
    lines = LineCollection(segs.reshape(-1, 2, 2), array=az, cmap="hsv", linewidths=2.4)
    lines.set_clim(0.0, 180.0)
    ax.add_collection(lines)
    ax.set_aspect(aspect)
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(extent[2], extent[3])
    ax.set_xlabel(axis_labels[0])
    ax.set_ylabel(axis_labels[1])
    ax.set_title(title or f"{len(segs)} lineaments over the multidirectional hillshade", fontsize=10)
    bar = fig.colorbar(lines, ax=ax, shrink=0.7)
    bar.set_label("strike, degrees from north")
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    return path
