"""A first run of the fault skins and seeds (numba's cache empty) compiles no array constructor of numba's of its own
(issue 58: np.full, np.ones, np.zeros and np.empty inside the kernels each compiled one, 0.1-0.4 CPU s of the demo's
first run), nor int()."""

import json
import os
import subprocess
import sys

import pytest

_COMPILES = r"""
import json, sys
import numpy as np
from numba.core import event
library = set()
class Compiles(event.Listener):
    def on_start(self, ev):
        pass
    def on_end(self, ev):
        f = ev.data["dispatcher"].py_func
        if not f.__module__.startswith("seismo3d"):
            library.add(f.__module__ + "." + f.__qualname__)
event.register("numba:compile", Compiles())
from seismo3d.seismic import fault_normals, fault_skins
from seismo3d.seismic.faults.surfaces.voting_kernels import greedy_seeds
shape = (32, 32, 32)
i, j, k = np.meshgrid(*(np.arange(n) for n in shape), indexing="ij")
thin = np.zeros(shape, np.float32)
strike = np.zeros(shape, np.float32)
dip = np.zeros(shape, np.float32)
for s, d, value in ((0.0, 80.0, 0.6), (90.0, 70.0, 0.8)):
    n = fault_normals(np.array([s]), np.array([d]))[0]
    plane = np.abs((i - 16) * n[0] + (j - 16) * n[1] + (k - 16) * n[2]) < 0.5
    thin[plane], strike[plane], dip[plane] = value, s, d
thin[:, :, 14:17] = 0.0  # a gap, bridged by the edge pairs
faults = fault_skins(thin, strike, dip, lower=0.3, upper=0.5)
pts = np.argwhere(thin > 0.3)
greedy_seeds(pts, thin[tuple(pts.T)], shape, 3)
json.dump({"faults": len(faults), "library": sorted(library)}, sys.stdout)
"""


@pytest.mark.slow
def test_skins_and_seeds_compile_no_array_constructor_of_numbas(tmp_path):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", _COMPILES], env=env, check=True, capture_output=True, text=True)
    record = json.loads(out.stdout)
    assert record["faults"] >= 2
    constructors = [name for name in record["library"] if any(word in name for word in ("full", "ones", "zeros"))]
    assert constructors == [], record["library"]
    # nor np.empty / np.empty_like (and numba's allocator) or int(): the work arrays come from the callers, and
    # math.floor replaces int(np.floor()) (main compiled all four: 0.5-0.9 CPU s); min() and max() are kept (a
    # comparison in their place costs more to compile at every site than their one compile)
    assert sorted(name.split(".")[-3] for name in record["library"]) == ["ol_max", "ol_min"], record["library"]
