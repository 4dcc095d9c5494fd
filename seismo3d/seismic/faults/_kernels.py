"""Numba kernels of the fault sub-package only (a private module): region growing of fault samples by their mean
normal, used by the thinned-fault linker (:mod:`~seismo3d.seismic.faults.surfaces`) and the fault skins
(:mod:`~seismo3d.seismic.faults.skins`). The kernels shared with the attributes and the horizons are in
``seismo3d/seismic/_kernels.py``. Compiled on first call and cached on disk.
"""

from __future__ import annotations

import numba as nb
import numpy as np


@nb.njit(cache=True)
def grow_by_mean_normal(indptr, indices, normals, order, cos_mean):
    # Region growing over the neighbour graph (whose edges already join only compatible normals): from the
    # unassigned sample of highest likelihood, add neighbours whose normal is within acos(cos_mean) of the growing
    # fault's mean normal, breadth first. The mean keeps a fault from drifting into another one through samples of
    # intermediate orientation where two faults meet.
    n_pts, dim = normals.shape
    label = -np.ones(n_pts, np.int64)
    queue = np.empty(n_pts, np.int64)
    mean = np.zeros(dim)
    n_lab = 0
    for seed in order:
        if label[seed] >= 0:
            continue
        label[seed] = n_lab
        for d in range(dim):
            mean[d] = normals[seed, d]
        head = 0
        tail = 1
        queue[0] = seed
        while head < tail:
            i = queue[head]
            head += 1
            for e in range(indptr[i], indptr[i + 1]):
                j = indices[e]
                if label[j] >= 0:
                    continue
                dot = 0.0
                nm = 0.0
                for d in range(dim):
                    dot += normals[j, d] * mean[d]
                    nm += mean[d] * mean[d]
                if abs(dot) < cos_mean * np.sqrt(nm):
                    continue
                label[j] = n_lab
                sgn = 1.0 if dot >= 0 else -1.0
                for d in range(dim):
                    mean[d] += sgn * normals[j, d]
                queue[tail] = j
                tail += 1
        n_lab += 1
    return label
