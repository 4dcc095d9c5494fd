"""The throw's window source of an in-memory cube (seismo3d.seismic.faults.throw_windows): its slopes decomposed only
where they are read, bit for bit those of the whole cube's structure tensor (issue 76)."""

from types import SimpleNamespace

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import fault_throws
from seismo3d.seismic.faults.windows import ArrayWindows
from seismo3d.seismic.faults.throw_windows import TensorWindows


@pytest.fixture(scope="module")
def cube():
    return synthetic_cube((40, 36, 60), seed=1, noise=0.1).cube


def test_reads_equal_the_whole_cubes_slopes_bit_for_bit(cube):
    """Positions inside, on the last sample and trace, on integers and beyond every edge (clamped reads)."""
    whole = ArrayWindows(cube).window(0, 1, 0, 1)
    source = TensorWindows(cube)
    win = source.window(0, 1, 0, 1)
    rng = np.random.default_rng(0)
    il, xl, t = rng.uniform(-2, 42, 4000), rng.uniform(-2, 38, 4000), rng.uniform(-3, 63, 4000)
    il[:10], xl[:10], t[:10] = np.arange(10) * 4.0, 35.0, 59.0
    for direction in ([1.0, 0.0], [0.0, 1.0], [0.6, -0.8]):
        np.testing.assert_array_equal(win.slope_along(il, xl, t, direction),
                                      whole.slope_along(il, xl, t, direction))
    decomposed = np.isfinite(win.slope_inline)
    assert 0.05 < decomposed.mean() < 0.6  # only the samples read: the others are NaN, never read
    np.testing.assert_array_equal(win.slope_inline[decomposed], whole.slope_inline[decomposed])
    np.testing.assert_array_equal(win.slope_xline[decomposed], whole.slope_xline[decomposed])
    assert source.window(5, 9, 5, 9) is win  # every window is the whole cube, decomposed once


@pytest.mark.slow
def test_throws_equal_those_of_the_whole_cubes_slopes():
    """fault_throws on an in-memory cube (TensorWindows) and on ArrayWindows: the same throws, bit for bit."""
    syn = synthetic_cube((64, 64, 96), n_faults=2, seed=1, noise=0.1)
    faults = [SimpleNamespace(id=f.id, points=np.argwhere(syn.fault_labels == f.id),
                              normals=np.tile(f.normal, (int((syn.fault_labels == f.id).sum()), 1)))
              for f in syn.faults]
    ours, whole = fault_throws(syn.cube, faults), fault_throws(ArrayWindows(syn.cube), faults)
    assert sum(int(np.isfinite(r.throw).sum()) for r in whole) > 1000  # there are throws to compare
    for a, b in zip(ours, whole):
        np.testing.assert_array_equal(a.throw, b.throw)
        np.testing.assert_array_equal(a.correlation, b.correlation)
        np.testing.assert_array_equal(a.registered, b.registered)


def test_the_tensor_is_smoothed_at_the_traces_read_only_with_the_whole_cubes_bits():
    """prepare() smooths the tensor at its boxes' traces (by slabs of inlines and runs of crosslines, two runs here);
    a read elsewhere smooths its own traces when it comes; every slope read equals the whole cube's, bit for bit."""
    cube = synthetic_cube((96, 80, 40), seed=2, noise=0.1).cube
    whole = ArrayWindows(cube).window(0, 1, 0, 1)
    source = TensorWindows(cube)
    source.prepare([(10, 20, 5, 15), (70, 90, 60, 70)])
    assert source._done.sum() == 10 * 10 + 20 * 10  # those traces only
    win = source.window(0, 1, 0, 1)
    rng = np.random.default_rng(1)
    for lo, hi in (((10, 5), (19, 14)), ((70, 60), (89, 69)), ((40, 30), (50, 40))):  # in each box, then elsewhere
        il, xl = rng.uniform(lo[0], hi[0], 500), rng.uniform(lo[1], hi[1], 500)
        t = rng.uniform(0, 39, 500)
        for d in ([1.0, 0.0], [0.6, -0.8]):
            np.testing.assert_array_equal(win.slope_along(il, xl, t, d), whole.slope_along(il, xl, t, d))
    assert source._done.mean() < 0.2  # the third read added its own traces (and their corners) only


def test_a_section_is_refused(cube):
    with pytest.raises(InputError, match="3D cube"):
        TensorWindows(cube[:, 0, :])
