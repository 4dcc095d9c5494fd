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


def onnx_model(weights, *, channels_last: bool = False) -> bytes:
    """The ONNX model (opset 17) of the network with these weights: the architecture of
    :mod:`seismo3d.seismic.faults.likelihood.network`, 3 x 3 convolutions zero-padded, nearest-neighbour upsampling,
    a logistic sigmoid at the end; the finest level (its encoder, decoder and the head) computed on the next coarser
    grid, the same outputs up to float32 rounding (:func:`_coarse_weights`).

    Parameters
    ----------
    weights : mapping of str to ndarray
        The trained weights (see :mod:`seismo3d.seismic.faults.likelihood.network`), float32.
    channels_last : bool, optional
        False (the default): the float model the package ships, every tensor in ONNX's (n, channels, height, width)
        order. True: the model :mod:`seismo3d.training.quantize_onnx` quantises, the same operations and the same
        outputs (the same bits in ONNX Runtime 1.32), written so that ONNX Runtime's integer kernels, which hold
        their tensors channels last, need no rearrangement between them: the pooling of the finest level's phases,
        the upsamplings (a broadcast of each sample to its 2 x 2 fine samples instead of ``Resize``, which ONNX
        Runtime computes sample by sample) and the head (a matrix product over the channels) on channels-last
        tensors (:func:`_pool_phases`, :func:`_upsample`, :func:`_head`). The int8 network's calls on 256 x 256
        sections take 5-19 % less time (medians of alternated runs on a loaded machine; on the 256^3 cube of
        ``benchmarks/fault_speed.py`` 9.1 -> 8.1 CPU s); the float network's would take more (its convolutions run
        channels first, in ONNX Runtime's blocked layout).

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

    def conv(x: str, name: str, relu: bool = True, weight=None) -> str:
        w, b = weight or (weights[f"{name}.weight"], weights[f"{name}.bias"])
        w = np.asarray(w, np.float32)
        initialisers.extend([numpy_helper.from_array(w, f"{name}.weight"),
                             numpy_helper.from_array(np.asarray(b, np.float32), f"{name}.bias")])
        k = int(w.shape[-1])
        out = f"{name}.conv" if relu else f"{name}.out"
        nodes.append(helper.make_node("Conv", [x, f"{name}.weight", f"{name}.bias"], [out], kernel_shape=[k, k],
                                      pads=[k // 2] * 4))
        if relu:
            nodes.append(helper.make_node("Relu", [out], [f"{name}.out"]))
        return f"{name}.out"

    def block(x: str, name: str) -> str:
        return conv(conv(x, f"{name}.0"), f"{name}.1")

    # the finest level (encoder and decoder) on the next coarser grid, a fine tensor held as its 4 phases (its
    # SpaceToDepth) from the sections' to the probability's (_coarse_weights): its convolutions of few channels there
    # with 4 times the channels, its pooling the largest of the 4 phases; on 256 x 256 sections the int8 network
    # 41 % less time, the float32 one 27 %
    n_skip = int(np.shape(weights["enc0.1.weight"])[0])
    nodes.append(helper.make_node("SpaceToDepth", ["sections"], ["phases"], blocksize=2))
    x = conv("phases", "enc0.0", weight=_coarse_weights(weights["enc0.0.weight"], weights["enc0.0.bias"], 1))
    x = conv(x, "enc0.1", weight=_coarse_weights(weights["enc0.1.weight"], weights["enc0.1.bias"], n_skip))
    skips = [x]
    x = _pool_phases(x, n_skip, channels_last, nodes, initialisers)
    for k in (1, 2):
        x = block(x, f"enc{k}")
        skips.append(x)
        nodes.append(helper.make_node("MaxPool", [x], [f"pool{k}"], kernel_shape=[2, 2], strides=[2, 2]))
        x = f"pool{k}"
    x = block(x, "bottleneck")
    for k in (2, 1):
        up = _upsample(x, k, int(np.shape(weights[f"{'bottleneck' if k == 2 else 'dec2'}.1.weight"])[0]),
                       channels_last, nodes, initialisers)
        nodes.append(helper.make_node("Concat", [up, skips[k]], [f"cat{k}"], axis=1))
        x = block(f"cat{k}", f"dec{k}")
    # the finest decoder level: the coarse input itself (not upsampled) beside the skip's phases, the head per phase,
    # the probability's phases put in place last
    nodes.append(helper.make_node("Concat", [x, skips[0]], ["cat0"], axis=1))
    x = conv("cat0", "dec0.0", weight=_coarse_weights(weights["dec0.0.weight"], weights["dec0.0.bias"], n_skip))
    x = conv(x, "dec0.1", weight=_coarse_weights(weights["dec0.1.weight"], weights["dec0.1.bias"], n_skip))
    head = np.asarray(weights["head.weight"], np.float32)[:, :, 0, 0]  # (1, c0): the same 1 x 1 head on each phase
    head = (np.kron(np.eye(4, dtype=np.float32), head), np.tile(np.asarray(weights["head.bias"], np.float32), 4))
    if channels_last:
        _head(x, *head, nodes, initialisers)
    else:
        logits = conv(x, "head", relu=False, weight=(head[0][:, :, None, None], head[1]))
        nodes.append(helper.make_node("Sigmoid", [logits], ["head.probability"]))
        nodes.append(helper.make_node("DepthToSpace", ["head.probability"], ["probability"], blocksize=2, mode="DCR"))
    shape = ["n", 1, "height", "width"]
    graph = helper.make_graph(nodes, "seismo3d_fault_unet",
                              [helper.make_tensor_value_info("sections", TensorProto.FLOAT, shape)],
                              [helper.make_tensor_value_info("probability", TensorProto.FLOAT, shape)], initialisers)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)], producer_name="seismo3d")
    model.ir_version = 8
    onnx.checker.check_model(model)
    return model.SerializeToString()


def _pool_phases(x: str, n_skip: int, channels_last: bool, nodes: list, initialisers: list) -> str:
    """The finest level's 2 x 2 max-pooling: the largest of its 4 phases (channels ``(2 i + j) n_skip + c``) per
    channel; channels last, the phases are the second-to-last axis of (n, h, w, 4, n_skip) (no rearrangement around
    ONNX Runtime's integer convolutions, which hold their tensors so)."""
    from onnx import helper, numpy_helper

    if channels_last:
        initialisers.append(numpy_helper.from_array(np.array([0, 0, 0, 4, n_skip], np.int64), "pool0.by_phase"))
        nodes.append(helper.make_node("Transpose", [x], ["pool0.nhwc"], perm=[0, 2, 3, 1]))
        nodes.append(helper.make_node("Reshape", ["pool0.nhwc", "pool0.by_phase"], ["pool0.phases"]))
        nodes.append(helper.make_node("ReduceMax", ["pool0.phases"], ["pool0.flat"], axes=[3], keepdims=0))
        nodes.append(helper.make_node("Transpose", ["pool0.flat"], ["pool0"], perm=[0, 3, 1, 2]))
        return "pool0"
    initialisers.append(numpy_helper.from_array(np.array([0, 4, -1, 0], np.int64), "pool0.by_phase"))
    initialisers.append(numpy_helper.from_array(np.array([0, n_skip, -1, 0], np.int64), "pool0.shape"))
    nodes.append(helper.make_node("Reshape", [x, "pool0.by_phase"], ["pool0.phases"]))
    nodes.append(helper.make_node("ReduceMax", ["pool0.phases"], ["pool0.flat"], axes=[1], keepdims=1))
    nodes.append(helper.make_node("Reshape", ["pool0.flat", "pool0.shape"], ["pool0"]))
    return "pool0"


def _upsample(x: str, k: int, channels: int, channels_last: bool, nodes: list, initialisers: list) -> str:
    """Nearest-neighbour upsampling by 2 of ``x`` (``channels`` channels) to level ``k``'s grid: ``Resize``; channels
    last, each sample broadcast to its 2 x 2 fine samples (Unsqueeze, Expand, Reshape: the same values), the fine
    grid's size that of the sections divided by ``2**k``."""
    from onnx import helper, numpy_helper

    out = f"up{k}"
    if not channels_last:
        if "up_scales" not in {t.name for t in initialisers}:
            initialisers.append(numpy_helper.from_array(np.array([1, 1, 2, 2], np.float32), "up_scales"))
        nodes.append(helper.make_node("Resize", [x, "", "up_scales"], [out], mode="nearest"))
        return out
    initialisers.extend([numpy_helper.from_array(np.array([2, 4], np.int64), f"{out}.axes"),
                         numpy_helper.from_array(np.array([1, 1, 2, 1, 2, 1], np.int64), f"{out}.repeats"),
                         numpy_helper.from_array(np.array([2 ** k, 2 ** k], np.int64), f"{out}.divisor"),
                         numpy_helper.from_array(np.array([0], np.int64), f"{out}.n"),
                         numpy_helper.from_array(np.array([channels], np.int64), f"{out}.channels")])
    nodes.extend([
        helper.make_node("Transpose", [x], [f"{out}.nhwc"], perm=[0, 2, 3, 1]),
        helper.make_node("Unsqueeze", [f"{out}.nhwc", f"{out}.axes"], [f"{out}.unsqueezed"]),  # (n, h, 1, w, 1, c)
        helper.make_node("Expand", [f"{out}.unsqueezed", f"{out}.repeats"], [f"{out}.expanded"]),  # (n, h, 2, w, 2, c)
        helper.make_node("Shape", ["sections"], [f"{out}.sections_hw"], start=2),
        helper.make_node("Div", [f"{out}.sections_hw", f"{out}.divisor"], [f"{out}.hw"]),
        helper.make_node("Concat", [f"{out}.n", f"{out}.hw", f"{out}.channels"], [f"{out}.shape"], axis=0),
        helper.make_node("Reshape", [f"{out}.expanded", f"{out}.shape"], [f"{out}.fine"]),  # (n, 2 h, 2 w, c)
        helper.make_node("Transpose", [f"{out}.fine"], [out], perm=[0, 3, 1, 2])])
    return out


def _head(x: str, weight: np.ndarray, bias: np.ndarray, nodes: list, initialisers: list) -> None:
    """The head channels last: the logits of the 4 phases a matrix product of each sample's channels with
    ``weight`` (4, c0) plus ``bias``, the sigmoid, then the phases put in place, ``probability`` (n, 1, H, W)."""
    from onnx import helper, numpy_helper

    initialisers.extend([numpy_helper.from_array(np.ascontiguousarray(weight.T), "head.weight"),
                         numpy_helper.from_array(bias, "head.bias"),
                         numpy_helper.from_array(np.array([0, 0, 0, 2, 2], np.int64), "head.by_phase")])
    nodes.extend([
        helper.make_node("Transpose", [x], ["head.nhwc"], perm=[0, 2, 3, 1]),
        helper.make_node("MatMul", ["head.nhwc", "head.weight"], ["head.product"]),
        helper.make_node("Add", ["head.product", "head.bias"], ["head.out"]),
        helper.make_node("Sigmoid", ["head.out"], ["head.probability"]),
        helper.make_node("Reshape", ["head.probability", "head.by_phase"], ["head.phases"]),  # (n, h, w, i, j)
        helper.make_node("Transpose", ["head.phases"], ["head.placed"], perm=[0, 1, 3, 2, 4]),  # (n, h, i, w, j)
        helper.make_node("Shape", ["sections"], ["head.shape"]),
        helper.make_node("Reshape", ["head.placed", "head.shape"], ["probability"])])


def _coarse_weights(weight, bias, n_skip: int) -> tuple[np.ndarray, np.ndarray]:
    """A 3 x 3 convolution (zero-padded) of the finest level moved onto the coarser one: the same outputs, computed
    where they are cheaper.

    The convolution reads the concatenation of a coarse tensor upsampled by 2 (nearest neighbour; ``c_up`` channels,
    the decoder's) and of a fine one (``n_skip`` channels: the encoder's skip, or with ``c_up`` 0 any fine input: the
    sections, an encoder's or decoder's first convolution's output).
    Its output at fine sample ``(2h + i, 2w + j)`` reads fine samples ``2h + i + d`` (``d`` in -1, 0, 1): coarse
    sample ``h + (i + d) // 2`` and, of the fine tensor, its phase ``(i + d) % 2``. So it equals one 3 x 3
    convolution on the coarse grid of the coarse tensor (not upsampled) and the fine tensor's SpaceToDepth (its 4
    phases as channels, ONNX's DCR order), with 4 times the outputs, a set per phase ``(i, j)`` in the same order (a
    DepthToSpace puts them in place; zero padding falls on zero padding at both levels). The weights of taps that land
    on the same coarse sample are summed: the sums run in another order, so the outputs differ from the trained
    convolution's by float32 rounding (1e-6 on the probability).

    ONNX Runtime's slowest operators in this network were its finest level's convolutions of few channels (36 to 12
    channels on 256 x 256 samples: a third of the int8 network's time); on the coarse grid, with 4 times the
    channels, the same outputs cost less although the multiplications double or quadruple (the sub-pixel convolution
    of Shi et al. 2016).

    Parameters
    ----------
    weight : (c_out, c_up + n_skip, 3, 3) array_like
        The trained convolution, its inputs the upsampled coarse tensor then the fine one.
    bias : (c_out,) array_like
    n_skip : int
        Channels of the fine tensor.

    Returns
    -------
    weight : (4 c_out, c_up + 4 n_skip, 3, 3) float32 ndarray
        Outputs by phase, ``(2 i + j) c_out + c``; inputs the coarse tensor, then the fine one's phases
        ``(2 i + j) n_skip + c``.
    bias : (4 c_out,) float32 ndarray

    References
    ----------
    Shi, W., Caballero, J., Huszar, F., Totz, J., Aitken, A. P., Bishop, R., Rueckert, D., and Wang, Z., 2016,
    Real-time single image and video super-resolution using an efficient sub-pixel convolutional neural network:
    CVPR 2016, 1874-1883. doi:10.1109/CVPR.2016.207
    """
    w = np.asarray(weight, np.float64)
    c_out, n_up = w.shape[0], w.shape[1] - int(n_skip)
    out = np.zeros((4 * c_out, n_up + 4 * int(n_skip), 3, 3))
    for i in range(2):
        for j in range(2):
            phase = slice((2 * i + j) * c_out, (2 * i + j + 1) * c_out)
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    ky, kx = (i + dy) // 2 + 1, (j + dx) // 2 + 1  # the coarse tap
                    skip = n_up + (2 * ((i + dy) % 2) + (j + dx) % 2) * int(n_skip)  # the skip's phase
                    out[phase, :n_up, ky, kx] += w[:, :n_up, dy + 1, dx + 1]
                    out[phase, skip:skip + int(n_skip), ky, kx] += w[:, n_up:, dy + 1, dx + 1]
    return out.astype(np.float32), np.tile(np.asarray(bias, np.float32), 4)


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
