"""FaultNet, the peer the fault benchmarks run in their own process: its released TorchScript weights on a cube or a
section, with torch on the CPU.

FaultNet (Dou et al. 2022, "Efficient training of 3D seismic image fault segmentation network under sparse labels
by weakening anomaly annotation", IEEE Transactions on Geoscience and Remote Sensing 60) is a 3D CNN; its weights
are the data folder's ``peers/FaultNet_Gamma0.7.pt`` (douyimin/FaultNet @ 8b51373, Apache-2.0), called as the data
README's row says: a (1, 1, n_samples, n_inlines, n_crosslines) float32 cube scaled to [0, 1], each size a multiple
of 16 (here padded by reflection and cropped back), the fault probability of the same shape. A section is run as a
cube of 16 copies of itself side by side (a fault of the section is then a fault plane across the copies), the
middle copy kept.

torch is a peer's dependency, never seismo3d's: without it :func:`load_faultnet` returns None and the benchmarks say
so in one line.

Used by ``faults.py`` (the F3 inlines, the speed profile) and ``faults_3d.py`` (the Parihaka cube).
"""

from __future__ import annotations

import numpy as np

from seismo3d.data.registry import fetch

FAULTNET = "peers/FaultNet_Gamma0.7.pt"
MULTIPLE = 16  # every size of FaultNet's input is a multiple of this (its four poolings)
NOT_RUN = "FaultNet: not run (torch is not installed; pip install torch)"


def load_faultnet(threads: int | None = 2):
    """FaultNet's released network (TorchScript, on the CPU, in evaluation mode), or None when torch is missing.

    ``threads``: torch's intra-op threads (2: the cores the benchmarks give every method; None: torch's default).
    """
    try:
        import torch
    except ImportError:
        return None
    if threads is not None:
        torch.set_num_threads(int(threads))
    return torch.jit.load(str(fetch(FAULTNET)), map_location="cpu").eval()


def faultnet_probability(net, cube: np.ndarray) -> np.ndarray:
    """FaultNet's fault probability of a cube (n_inlines, n_xlines, n_samples) or a section (n_traces, n_samples),
    float32 of the same shape: amplitudes scaled to [0, 1] by their range, every axis padded by reflection to a
    multiple of 16, the output cropped back."""
    import torch

    arr = np.asarray(cube, dtype=np.float32)
    section = arr.ndim == 2
    if section:  # 16 copies side by side: the section as one inline among identical ones
        arr = np.repeat(arr[None], MULTIPLE, axis=0)
    lo, hi = float(arr.min()), float(arr.max())
    x = (arr - lo) / max(hi - lo, 1e-12)
    pads = [(0, (-n) % MULTIPLE) for n in x.shape]
    x = np.pad(x, pads, mode="reflect" if min(x.shape) > MULTIPLE else "edge")
    x = torch.from_numpy(np.ascontiguousarray(x.transpose(2, 0, 1))[None, None])
    with torch.no_grad():
        out = net(x)
    prob = (out[0] if isinstance(out, (tuple, list)) else out).numpy()[0, 0].transpose(1, 2, 0)
    prob = np.ascontiguousarray(prob[:arr.shape[0], :arr.shape[1], :arr.shape[2]], dtype=np.float32)
    return prob[MULTIPLE // 2] if section else prob
