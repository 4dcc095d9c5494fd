"""Statistics of values spread over the blocks of a run, equal to the libraries' on the values gathered: what a
``'reduce'`` step's blocks return and the caller combines, never holding the values of the cube at once.

The fault thresholds (:meth:`~seismo3d.seismic.faults.FaultTracingOptions.thresholds_from`) take Otsu's threshold of
the positive thinned votes and, for densely faulted data, one of their quantiles. In memory they come from
scikit-image (:func:`skimage.filters.threshold_otsu`) and numpy (:func:`numpy.quantile`, linear method) on the values
(:func:`otsu`, :func:`quantile`). Block by block the same numbers come from streaming equivalents:

- Otsu: the counts of every block in the 256 bins scikit-image uses (same float32 range, so the same edges), summed,
  then scikit-image's Otsu on that histogram (:func:`histogram_edges`, :func:`block_histogram`,
  :func:`otsu_of_histogram`);
- the quantile: the two order statistics numpy interpolates, located by a fine histogram (:func:`quantile_window`),
  then the values of the blocks within that window gathered and sorted (:func:`quantile_of_window`).

``tests/seismic/blocks/test_statistics.py`` checks that both equal the library's result on the whole values.
"""

from __future__ import annotations

import numpy as np

from .apply import BlockOutput
from .plan import BlockStep

__all__ = ["HISTOGRAM_BINS", "QUANTILE_BINS", "block_histogram", "histogram_block", "histogram_edges", "otsu",
           "otsu_of_histogram", "positive_values", "quantile", "quantile_of_window", "quantile_window",
           "statistic_steps", "streamed_otsu", "streamed_quantile", "window_block"]

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
    scikit-image's Otsu threshold uses in memory).

    Returns
    -------
    (bins + 1,) ndarray
    """
    return np.histogram_bin_edges(np.array([vmin, vmax], np.float32), bins=bins, range=_float32_range(vmin, vmax))


def block_histogram(values: np.ndarray, vmin: float, vmax: float, bins: int) -> np.ndarray:
    """Counts of one block's ``values`` in the ``bins`` bins over the whole data's [vmin, vmax].

    Returns
    -------
    (bins,) int64 ndarray
        Summed over the blocks: the histogram of all the values.
    """
    counts, _ = np.histogram(values, bins=bins, range=_float32_range(vmin, vmax))
    return counts.astype(np.int64)


def otsu_of_histogram(counts: np.ndarray, vmin: float, vmax: float) -> float:
    """Otsu's threshold from the summed :func:`block_histogram` counts (``HISTOGRAM_BINS`` bins over the values'
    [vmin, vmax]): :func:`otsu` of the values themselves.

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
    """Where the ``q``-quantile of ``n`` values lies, from their fine histogram (``QUANTILE_BINS`` summed
    :func:`block_histogram` counts over [vmin, vmax]).

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


def _float32_range(vmin: float, vmax: float) -> tuple:
    """The histogram range as float32 scalars: numpy then computes the bin edges in float32, as for the range of a
    float32 array (what skimage's Otsu threshold uses in memory)."""
    return np.float32(vmin), np.float32(vmax)


# -- over the blocks of a run --------------------------------------------------------------------------------------

def positive_values(values) -> np.ndarray:
    """The positive values of an array, flattened.

    Parameters
    ----------
    values : ndarray

    Returns
    -------
    (k,) ndarray
        Of the array's dtype.
    """
    return values[values > 0]


def histogram_block(values, vmin: float, vmax: float, bins: int) -> BlockOutput:
    """The counts of one block's positive values in ``bins`` bins over ``[vmin, vmax]`` (:func:`block_histogram`).

    Parameters
    ----------
    values : ndarray
    vmin, vmax : float
    bins : int

    Returns
    -------
    BlockOutput
        Summary ``counts``: a list of ``bins`` ints.
    """
    return BlockOutput(summary={"counts": block_histogram(positive_values(values), vmin, vmax, bins).tolist()})


def window_block(values, lo_edge: float, hi_edge: float) -> BlockOutput:
    """One block's positive values below ``lo_edge`` counted and those in ``[lo_edge, hi_edge]`` listed.

    Parameters
    ----------
    values : ndarray
    lo_edge, hi_edge : float

    Returns
    -------
    BlockOutput
        Summary ``below`` (int) and ``values`` (list of floats).
    """
    values = positive_values(values)
    return BlockOutput(summary={"below": int(np.count_nonzero(values < lo_edge)),
                                "values": values[(values >= lo_edge) & (values <= hi_edge)].tolist()})


def statistic_steps(array: str, what: str) -> dict:
    """The steps that reduce the positive values of a stored ``array`` over blocks: ``'histogram'`` (Otsu's bins),
    ``'quantile_histogram'`` (the quantile's fine bins) and ``'quantile'`` (the values of its window gathered).

    Parameters
    ----------
    array : str
        The name of the array in the run's stores.
    what : str
        What its values are, in the progress reports' labels (e.g. ``'the thinned votes'``).

    Returns
    -------
    dict
        ``{name: BlockStep}``.
    """
    label = f"histogram of {what}"
    return {"histogram": BlockStep("histogram", "reduce", function=histogram_block, label=label, inputs=(array,)),
            "quantile_histogram": BlockStep("quantile_histogram", "reduce", function=histogram_block, label=label,
                                            inputs=(array,)),
            "quantile": BlockStep("quantile", "gather", function=window_block, label=f"quantile of {what}",
                                  inputs=(array,))}


def streamed_otsu(run, steps: dict, blocks, vmin: float, vmax: float) -> float:
    """Otsu's threshold of the positive values of an array over the blocks of a run: :func:`otsu` of the values
    gathered, from the blocks' histograms (:func:`statistic_steps`).

    Parameters
    ----------
    run : BlockRun
    steps : dict
        Of :func:`statistic_steps`.
    blocks : list of tuple
    vmin, vmax : float
        The smallest and largest positive value.

    Returns
    -------
    float
    """
    return otsu_of_histogram(_summed_histogram(run, steps["histogram"], blocks, vmin, vmax, HISTOGRAM_BINS),
                             vmin, vmax)


def streamed_quantile(run, steps: dict, blocks, q: float, n: int, vmin: float, vmax: float) -> float:
    """``numpy.quantile(values, q)`` of the ``n`` positive values of an array over the blocks of a run, exactly: the
    two order statistics it interpolates, found by a fine histogram and a pass that gathers the values of their bins.

    Parameters
    ----------
    run : BlockRun
    steps : dict
        Of :func:`statistic_steps`.
    blocks : list of tuple
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
    counts = _summed_histogram(run, steps["quantile_histogram"], blocks, vmin, vmax, QUANTILE_BINS)
    window = quantile_window(counts, n, q, vmin, vmax)
    results = run.run_step(steps["quantile"], blocks, window[3], window[4])
    values = np.concatenate([np.asarray(r["values"], np.float32) for r in results])
    return quantile_of_window(window, sum(r["below"] for r in results), values)


def _summed_histogram(run, step, blocks, vmin, vmax, bins) -> np.ndarray:
    results = run.run_step(step, blocks, vmin, vmax, bins)
    return np.sum([np.asarray(r["counts"], np.int64) for r in results], axis=0)
