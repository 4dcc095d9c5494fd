"""Statistics of values spread over the chunks of a stored array, equal to the libraries' on the values gathered:
dask reductions over the chunks, never holding the values of the cube at once.

The fault thresholds (:meth:`~seismo3d.seismic.faults.FaultTracingOptions.thresholds_from`) take Otsu's threshold of
the positive thinned votes and, for densely faulted data, one of their quantiles. In memory they come from
scikit-image (:func:`skimage.filters.threshold_otsu`) and numpy (:func:`numpy.quantile`, linear method) on the values
(:func:`otsu`, :func:`quantile`). Over the chunks of a stored array the same numbers come from streaming equivalents:

- Otsu: the counts in the 256 bins scikit-image uses (same float32 range, so the same edges: :func:`histogram_edges`),
  by :func:`dask.array.histogram` over the chunks, then scikit-image's Otsu on that histogram (:func:`streamed_otsu`,
  :func:`otsu_of_histogram`);
- the quantile: the two order statistics numpy interpolates, located by a fine histogram (:func:`quantile_window`),
  then the values of the chunks within that window gathered and sorted (:func:`streamed_quantile`,
  :func:`quantile_of_window`).

``tests/seismic/blocks/test_statistics.py`` checks that both equal the library's result on the whole values.
"""

from __future__ import annotations

import numpy as np

__all__ = ["HISTOGRAM_BINS", "QUANTILE_BINS", "histogram_edges", "otsu", "otsu_of_histogram", "quantile",
           "quantile_of_window", "quantile_window", "streamed_otsu", "streamed_quantile"]

# Bins of scikit-image's Otsu threshold (its default nbins).
HISTOGRAM_BINS = 256
# Bins of the histogram that finds the exact quantile of the thinned votes (only for densely faulted data).
QUANTILE_BINS = 1 << 16


def otsu(values: np.ndarray) -> float:
    """Otsu's threshold of ``values`` (scikit-image), their value when they are all equal, 1 when there are none.

    Parameters
    ----------
    values : (n,) float32 ndarray

    Returns
    -------
    float
    """
    from skimage.filters import threshold_otsu

    if values.size == 0 or float(values.max()) <= float(values.min()):
        return float(values.max()) if values.size else 1.0
    return float(threshold_otsu(values))


def quantile(values: np.ndarray, q: float) -> float:
    """``numpy.quantile(values, q)`` (linear method), the reference of the streaming quantile."""
    return float(np.quantile(values, q))


def histogram_edges(vmin: float, vmax: float, bins: int) -> np.ndarray:
    """The edges of ``bins`` bins over [vmin, vmax] as numpy computes them for a float32 array of that range (what
    scikit-image's Otsu threshold uses in memory): the range as float32 scalars, so the edges are float32.

    Returns
    -------
    (bins + 1,) float32 ndarray
        ``numpy.histogram(values, bins=edges)`` counts the values in the bins of ``bins=bins, range=(vmin, vmax)``;
        values outside [vmin, vmax] are not counted.
    """
    return np.histogram_bin_edges(np.array([vmin, vmax], np.float32), bins=bins,
                                  range=(np.float32(vmin), np.float32(vmax)))


def otsu_of_histogram(counts: np.ndarray, vmin: float, vmax: float) -> float:
    """Otsu's threshold from the counts of the values in the bins of :func:`histogram_edges` (``HISTOGRAM_BINS``
    bins over the values' [vmin, vmax]): :func:`otsu` of the values themselves.

    Returns
    -------
    float
    """
    from skimage.filters import threshold_otsu

    if vmax <= vmin:
        return float(vmax)
    edges = histogram_edges(vmin, vmax, len(counts))
    return float(threshold_otsu(hist=(np.asarray(counts), (edges[:-1] + edges[1:]) / 2.0)))


def quantile_window(counts: np.ndarray, n: int, q: float, vmin: float, vmax: float) -> tuple:
    """Where the ``q``-quantile of ``n`` values lies, from their fine histogram (counts in the ``QUANTILE_BINS`` bins
    of :func:`histogram_edges` over [vmin, vmax]).

    Returns
    -------
    (rank, gamma, need, lo_edge, hi_edge)
        numpy's order statistic ``rank`` and interpolation fraction ``gamma``, the order statistics needed (1 or 2),
        and the value window that holds them: the blocks' values within [lo_edge, hi_edge] are gathered with the
        number of values below ``lo_edge`` (:func:`quantile_of_window`).
    """
    bins = len(counts)
    rank, gamma = _virtual_index(n, q)
    need = 2 if rank + 1 < n else 1
    cum = np.cumsum(counts)
    edges = histogram_edges(vmin, vmax, bins)
    first = int(np.searchsorted(cum, rank + 1))
    last = int(np.searchsorted(cum, rank + need))
    # one bin more on each side: the values np.histogram puts in a bin may sit on its edges
    return rank, gamma, need, float(edges[max(first - 1, 0)]), float(edges[min(last + 2, bins)])


def quantile_of_window(window: tuple, below: int, values: np.ndarray) -> float:
    """The quantile located by :func:`quantile_window`: ``numpy.quantile`` of all the values, exactly.

    Parameters
    ----------
    window : tuple
        :func:`quantile_window`'s result.
    below : int
        Values below its ``lo_edge``, summed over the blocks.
    values : (m,) float32 ndarray
        The values within [lo_edge, hi_edge] of every block.

    Returns
    -------
    float

    Raises
    ------
    RuntimeError
        The window misses the order statistics (cannot happen: it is one bin wider than needed on each side).
    """
    rank, gamma, need, lo_edge, hi_edge = window
    k = rank - int(below)
    values = np.sort(np.asarray(values, np.float32))
    if k < 0 or k + need > values.size:  # pragma: no cover - the window is one bin wider than needed
        raise RuntimeError(f"the quantile window [{lo_edge}, {hi_edge}] missed order statistic {rank}")
    return _lerp(values[k], values[k + need - 1], gamma)


def _virtual_index(n: int, q: float) -> tuple[int, float]:
    """(rank, gamma) of numpy.quantile's linear method for ``n`` values: the q-quantile lies between the order
    statistics ``rank`` and ``rank + 1``, a fraction ``gamma`` of the way (numpy's arithmetic, Hyndman & Fan's
    method 7)."""
    v = n * q + (1.0 + q * (1.0 - 1.0 - 1.0)) - 1.0
    rank = int(np.floor(v))
    return min(max(rank, 0), n - 1), float(v - np.floor(v))


def _lerp(a, b, gamma: float) -> float:
    """numpy.quantile's interpolation between float32 order statistics ``a`` <= ``b`` (in float32, from whichever
    end is nearer)."""
    a, b = np.float32(a), np.float32(b)
    d = b - a
    return float(b - d * np.float32(1.0 - gamma)) if gamma >= 0.5 else float(a + d * np.float32(gamma))


# -- over the chunks of a stored array, by dask ------------------------------------------------------------------

def streamed_otsu(run, values, vmin: float, vmax: float) -> float:
    """Otsu's threshold of the positive values of a lazy array: :func:`otsu` of the values gathered, from the
    histogram of its chunks (a dask reduction on the run's scheduler).

    Parameters
    ----------
    run : BlockRun
        Whose scheduler computes (:meth:`~seismo3d.seismic.blocks.executor.BlockRun.reduce_cube`).
    values : dask.array.Array
        E.g. ``dask.array.from_zarr`` of a run's store.
    vmin, vmax : float
        The smallest and largest positive value (``vmin > 0``: the other values fall outside the bins).

    Returns
    -------
    float
    """
    return otsu_of_histogram(_histogram(run, values, vmin, vmax, HISTOGRAM_BINS), vmin, vmax)


def streamed_quantile(run, values, q: float, n: int, vmin: float, vmax: float) -> float:
    """``numpy.quantile(v, q)`` of the ``n`` positive values ``v`` of a lazy array, exactly: the two order statistics
    it interpolates, found by a fine histogram of its chunks, then the values of their bins gathered (dask
    reductions on the run's scheduler).

    Parameters
    ----------
    run : BlockRun
    values : dask.array.Array
    q : float
        In [0, 1].
    n : int
        Number of positive values.
    vmin, vmax : float
        Their smallest and largest.

    Returns
    -------
    float
    """
    window = quantile_window(_histogram(run, values, vmin, vmax, QUANTILE_BINS), n, q, vmin, vmax)
    lo_edge, hi_edge = window[3], window[4]  # lo_edge >= vmin > 0: the values of the window are positive
    below, inside = run.reduce_cube((((values > 0) & (values < lo_edge)).sum(),
                                     values[(values >= lo_edge) & (values <= hi_edge)]))
    return quantile_of_window(window, int(below), np.asarray(inside, np.float32))


def _histogram(run, values, vmin: float, vmax: float, bins: int) -> np.ndarray:
    """The counts of the values of ``values`` in the ``bins`` bins of :func:`histogram_edges` over [vmin, vmax]
    (:func:`dask.array.histogram` on the run's scheduler; with ``vmin > 0`` the zeros fall outside)."""
    import dask.array as da

    counts, _ = da.histogram(values, bins=histogram_edges(vmin, vmax, bins))
    (total,) = run.reduce_cube((counts,))
    return np.asarray(total, np.int64)
