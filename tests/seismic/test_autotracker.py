"""The plain amplitude autotracker (seismo3d.seismic.horizons.autotracker): the generator's horizon on a clean cube, bad
input."""

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import autotrack, horizon_errors


def _seed_on(ref, i0=None):
    if ref.ndim == 1:
        ok = np.nonzero(np.isfinite(ref))[0]
        j0 = int(ok[np.argmin(np.abs(ok - ref.size // 2))])
        return (j0, float(ref[j0]))
    ok = np.nonzero(np.isfinite(ref[i0]))[0]
    j0 = int(ok[np.argmin(np.abs(ok - ref.shape[1] // 2))])
    return (i0, j0, float(ref[i0, j0]))


def test_plain_autotracker_on_a_clean_section_and_its_bfs_in_3d():
    syn = synthetic_cube((16, 40, 64), n_faults=0, seed=3, noise=0.0)
    k = 1
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    hz = autotrack(syn.cube, _seed_on(ref, 8), polarity=pol)
    assert hz.coverage == 1.0
    assert horizon_errors(hz.times, ref).median_abs <= 0.2


def test_autotrack_in_2d_and_bad_input():
    syn = synthetic_cube((80, 64), n_faults=0, seed=5, noise=0.0)
    ref = syn.horizons[2]
    pol = "peak" if syn.horizon_polarity[2] > 0 else "trough"
    hz = autotrack(syn.cube, _seed_on(ref), polarity=pol)
    assert hz.times.shape == (80,) and horizon_errors(hz.times, ref).median_abs <= 0.2
    with pytest.raises(InputError, match="one seed"):
        autotrack(syn.cube, [_seed_on(ref), _seed_on(ref)])
    with pytest.raises(InputError, match="window must be an int >= 1"):
        autotrack(syn.cube, _seed_on(ref), window=0)
    with pytest.raises(InputError, match="polarity"):
        autotrack(syn.cube, _seed_on(ref), polarity="max")
