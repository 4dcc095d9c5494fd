"""Export the fault network's trained weights to the ONNX model the package runs (``fault_unet.onnx``).

Run: ``python -m seismo3d.training.export_onnx WEIGHTS.npz OUT.onnx`` (needs the ``onnx`` package of the ``train``
extra). The export is deterministic: the shipped ``seismo3d/seismic/faults/likelihood/fault_unet.onnx`` is the export of
the shipped ``fault_unet.npz`` byte for byte (tested), and its sha256, printed here, is
:data:`seismo3d.seismic.faults.likelihood.learned.WEIGHTS_SHA256`.
"""

from __future__ import annotations

import argparse
import hashlib
from pathlib import Path

import numpy as np

from .._atomic import atomic_path
from ..seismic.faults.likelihood.network import onnx_model

__all__ = ["export_onnx"]


def export_onnx(weights_path, out_path) -> str:
    """Write the ONNX model of the weights in ``weights_path`` to ``out_path`` (atomically).

    Parameters
    ----------
    weights_path : str or os.PathLike
        ``.npz`` of trained weights (:func:`seismo3d.training.fault_unet.export_weights`).
    out_path : str or os.PathLike
        ``.onnx`` file written; its folder must exist.

    Returns
    -------
    str
        The sha256 of the written model.

    Raises
    ------
    InputError
        The weights miss an entry.
    Seismo3dError
        The ``onnx`` package is missing.
    """
    with np.load(weights_path) as npz:
        weights = {name: npz[name].astype(np.float32) for name in npz.files}
    model = onnx_model(weights)
    with atomic_path(Path(out_path)) as tmp:
        Path(tmp).write_bytes(model)
    return hashlib.sha256(model).hexdigest()


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("weights", help="trained weights (.npz)")
    ap.add_argument("out", help="ONNX model to write (.onnx)")
    a = ap.parse_args(argv)
    print(f"wrote {a.out}, sha256 {export_onnx(a.weights, a.out)}")


if __name__ == "__main__":
    main()
