"""Export the fault network's trained weights to the ONNX model the package runs (``fault_unet.onnx``): the graph
(:func:`onnx_model`) of the architecture of :mod:`seismo3d.seismic.faults.likelihood.network`, and the file
(:func:`export_onnx`).

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
from ..errors import InputError, Seismo3dError
from ..seismic.faults.likelihood.network import BLOCKS

__all__ = ["export_onnx", "onnx_model"]


def onnx_model(weights) -> bytes:
    """The ONNX model (opset 17) of the network with these weights: the architecture of
    :mod:`seismo3d.seismic.faults.likelihood.network`, 3 x 3 convolutions zero-padded, nearest-neighbour upsampling,
    a logistic sigmoid at the end.

    Parameters
    ----------
    weights : mapping of str to ndarray
        The trained weights (see :mod:`seismo3d.seismic.faults.likelihood.network`), float32.

    Returns
    -------
    bytes
        The serialised model: input ``sections`` (n, 1, H, W) float32, output ``probability`` of the same shape.

    Raises
    ------
    InputError
        The weights miss an entry.
    Seismo3dError
        The ``onnx`` package is missing (``pip install 'seismo3d[train]'``).
    """
    try:
        import onnx
        from onnx import TensorProto, helper, numpy_helper
    except ImportError as exc:
        raise Seismo3dError("exporting the fault network needs the onnx package: pip install 'seismo3d[train]'") \
            from exc
    _check_weights(weights)
    nodes, initialisers = [], []

    def conv(x: str, name: str, relu: bool = True) -> str:
        w = np.asarray(weights[f"{name}.weight"], np.float32)
        initialisers.extend([numpy_helper.from_array(w, f"{name}.weight"),
                             numpy_helper.from_array(np.asarray(weights[f"{name}.bias"], np.float32), f"{name}.bias")])
        k = int(w.shape[-1])
        out = f"{name}.conv" if relu else f"{name}.out"
        nodes.append(helper.make_node("Conv", [x, f"{name}.weight", f"{name}.bias"], [out], kernel_shape=[k, k],
                                      pads=[k // 2] * 4))
        if relu:
            nodes.append(helper.make_node("Relu", [out], [f"{name}.out"]))
        return f"{name}.out"

    def block(x: str, name: str) -> str:
        return conv(conv(x, f"{name}.0"), f"{name}.1")

    x, skips = "sections", []
    for k in range(3):
        x = block(x, f"enc{k}")
        skips.append(x)
        nodes.append(helper.make_node("MaxPool", [x], [f"pool{k}"], kernel_shape=[2, 2], strides=[2, 2]))
        x = f"pool{k}"
    x = block(x, "bottleneck")
    initialisers.append(numpy_helper.from_array(np.array([1, 1, 2, 2], np.float32), "up_scales"))
    for k in (2, 1, 0):
        nodes.append(helper.make_node("Resize", [x, "", "up_scales"], [f"up{k}"], mode="nearest"))
        nodes.append(helper.make_node("Concat", [f"up{k}", skips[k]], [f"cat{k}"], axis=1))
        x = block(f"cat{k}", f"dec{k}")
    logits = conv(x, "head", relu=False)
    nodes.append(helper.make_node("Sigmoid", [logits], ["probability"]))
    shape = ["n", 1, "height", "width"]
    graph = helper.make_graph(nodes, "seismo3d_fault_unet",
                              [helper.make_tensor_value_info("sections", TensorProto.FLOAT, shape)],
                              [helper.make_tensor_value_info("probability", TensorProto.FLOAT, shape)], initialisers)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)], producer_name="seismo3d")
    model.ir_version = 8
    onnx.checker.check_model(model)
    return model.SerializeToString()


def _check_weights(weights) -> None:
    missing = [f"{b}.{i}.{p}" for b in BLOCKS for i in (0, 1) for p in ("weight", "bias")
               if f"{b}.{i}.{p}" not in weights] + [n for n in ("head.weight", "head.bias") if n not in weights]
    if missing:
        raise InputError(f"the fault network's weights miss {missing}")


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
