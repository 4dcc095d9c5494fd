"""The streamed statistics of values over blocks (seismo3d.seismic.blocks.statistics) equal the libraries' on
the whole values: Otsu's threshold from summed block histograms equals scikit-image's, the quantile from a fine
histogram and a
window of gathered values equals numpy's, to the bit."""

import numpy as np
import pytest
from skimage.filters import threshold_otsu

from seismo3d.seismic.faults import FaultTracingOptions
from seismo3d.seismic.blocks.statistics import (
    HISTOGRAM_BINS, QUANTILE_BINS, histogram_edges, otsu, otsu_of_histogram, quantile_of_window, quantile_window,
)


def block_histogram(values, vmin, vmax, bins):
    """One block's counts in the bins of the whole values' [vmin, vmax], as each chunk's in dask.array.histogram."""
    return np.histogram(values, bins=histogram_edges(vmin, vmax, bins))[0]


def _values(seed: int, n: int) -> np.ndarray:
    """Positive float32 values like thinned votes: a skewed bulk, a few strong ones, repeated values."""
    rng = np.random.default_rng(seed)
    values = np.concatenate([rng.gamma(2.0, 0.05, n), rng.uniform(0.3, 0.9, n // 20)]).astype(np.float32)
    values[::7] = values[min(3, values.size - 1)]  # ties
    return values[values > 0]


def _blocks(values: np.ndarray, n_blocks: int) -> list:
    return np.array_split(values, n_blocks)


@pytest.mark.parametrize("seed, n, n_blocks", [(0, 1000, 3), (1, 50_000, 7), (2, 200_001, 16), (3, 5, 2)])
def test_otsu_of_summed_block_histograms_is_skimages(seed, n, n_blocks):
    values = _values(seed, n)
    vmin, vmax = float(values.min()), float(values.max())
    counts = np.sum([block_histogram(b, vmin, vmax, HISTOGRAM_BINS) for b in _blocks(values, n_blocks)], axis=0)
    assert counts.sum() == values.size
    assert otsu_of_histogram(counts, vmin, vmax) == float(threshold_otsu(values)) == otsu(values)


def test_otsu_of_equal_values_and_of_none():
    equal = np.full(10, 0.25, np.float32)
    assert otsu(equal) == otsu_of_histogram(block_histogram(equal, 0.25, 0.25, HISTOGRAM_BINS), 0.25, 0.25) == 0.25
    assert otsu(np.zeros(0, np.float32)) == 1.0


@pytest.mark.parametrize("q", [0.0, 0.013, 0.5, 0.8731, 0.999, 1.0])
@pytest.mark.parametrize("seed, n, n_blocks", [(0, 1000, 3), (4, 120_000, 9), (5, 2, 2)])
def test_streamed_quantile_is_numpys(q, seed, n, n_blocks):
    values = _values(seed, n)
    vmin, vmax = float(values.min()), float(values.max())
    blocks = _blocks(values, n_blocks)
    counts = np.sum([block_histogram(b, vmin, vmax, QUANTILE_BINS) for b in blocks], axis=0)
    window = quantile_window(counts, values.size, q, vmin, vmax)
    lo_edge, hi_edge = window[3], window[4]
    below = sum(int(np.count_nonzero(b < lo_edge)) for b in blocks)
    gathered = np.concatenate([b[(b >= lo_edge) & (b <= hi_edge)] for b in blocks])
    assert gathered.size < values.size or values.size < 10  # a window, not all the values
    assert quantile_of_window(window, below, gathered) == float(np.quantile(values, q))


def test_thresholds_from_streamed_statistics_are_the_in_memory_ones():
    """FaultTracingOptions.thresholds (numpy, scikit-image on the array) and thresholds_from fed the streamed
    statistics give the same pair, also when the quantile sets the lower threshold (dense faults)."""
    rng = np.random.default_rng(7)
    thin = np.where(rng.random((40, 30, 50)) < 0.3, rng.gamma(2.0, 0.08, (40, 30, 50)), 0).astype(np.float32)
    for opt in (FaultTracingOptions(), FaultTracingOptions(max_fault_fraction=0.02)):
        blocks = [thin[i:i + 16] for i in range(0, 40, 16)]
        positive = [b[b > 0] for b in blocks]
        vmin = min(float(p.min()) for p in positive)
        vmax = max(float(p.max()) for p in positive)
        n = sum(p.size for p in positive)
        counts = np.sum([block_histogram(p, vmin, vmax, HISTOGRAM_BINS) for p in positive], axis=0)

        def streamed(q):
            fine = np.sum([block_histogram(p, vmin, vmax, QUANTILE_BINS) for p in positive], axis=0)
            window = quantile_window(fine, n, q, vmin, vmax)
            below = sum(int(np.count_nonzero(p < window[3])) for p in positive)
            return quantile_of_window(window, below, np.concatenate(
                [p[(p >= window[3]) & (p <= window[4])] for p in positive]))

        expected = opt.thresholds(thin)
        assert opt.thresholds_from(otsu_of_histogram(counts, vmin, vmax), n, thin.size, streamed) == expected
    assert expected[0] > FaultTracingOptions().thresholds(thin)[0]  # the dense case took the quantile


@pytest.mark.parametrize("q", [0.1, 0.5, 0.97])
def test_otsu_and_quantile_over_the_chunks_of_a_stored_array_are_the_whole_arrays(tmp_path, q):
    zarr = pytest.importorskip("zarr")
    da = pytest.importorskip("dask.array")
    from seismo3d.seismic.blocks.executor import BlockRun
    from seismo3d.seismic.blocks.statistics import streamed_otsu, streamed_quantile

    rng = np.random.default_rng(4)
    cube = np.where(rng.random((10, 7, 6)) < 0.4, rng.gamma(2.0, 0.05, (10, 7, 6)), 0.0).astype(np.float32)
    zarr.create_array(str(tmp_path / "values"), shape=cube.shape, chunks=(4, 4, 6), dtype="float32")[:] = cube
    values = da.from_zarr(str(tmp_path / "values"))
    assert values.numblocks == (3, 2, 1)  # the statistics of 6 chunks, reduced
    run = BlockRun(tmp_path / "work", scheduler="synchronous")
    positive = cube[cube > 0]
    vmin, vmax = float(positive.min()), float(positive.max())
    assert streamed_otsu(run, values, vmin, vmax) == otsu(positive)
    assert streamed_quantile(run, values, q, positive.size, vmin, vmax) == float(np.quantile(positive, q))
