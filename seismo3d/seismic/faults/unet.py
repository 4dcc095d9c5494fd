"""The fault network's forward pass: a compact 2D U-Net, run by ONNX Runtime (no deep-learning framework).

The architecture (Ronneberger et al. 2015; as FaultSeg3D uses it for faults, Wu et al. 2019, here in 2D and smaller),
with ``c = channels``:

* encoder level k (k = 0, 1, 2): two 3 x 3 convolutions to ``c[k]`` channels, each followed by its batch
  normalisation (folded into the convolution's weights and bias when the weights are exported) and a ReLU; a 2 x 2
  max-pooling between levels;
* bottleneck: two 3 x 3 convolutions to ``c[3]`` channels;
* decoder level k (k = 2, 1, 0): nearest-neighbour upsampling by 2, concatenation with encoder level k's output,
  two 3 x 3 convolutions to ``c[k]`` channels;
* head: a 1 x 1 convolution to one channel and a logistic sigmoid: the fault probability of each sample.

Sizes: the input's two axes must be multiples of 8 (:func:`unet_forward` pads them); the receptive field is
:data:`RECEPTIVE_HALF` samples on each side. Convolutions are zero-padded ('same'), as in the training framework,
so the weights give the same numbers here (float32, differences of the order of 1e-6).

The network ships as an ONNX model (:class:`FaultNetwork`, loaded by
:func:`~seismo3d.seismic.faults.learned.load_fault_network`), exported from the trained weights by
:func:`onnx_model` (``python -m seismo3d.training.export_onnx``; the ``onnx`` package of the ``train`` extra). The
weights are a mapping ``name -> array``: ``'{block}.{i}.weight'`` of shape ``(c_out, c_in, 3, 3)`` (PyTorch's
``Conv2d`` layout) and ``'{block}.{i}.bias'`` ``(c_out,)``, for the blocks ``enc0, enc1, enc2, bottleneck, dec2,
dec1, dec0`` and ``i`` in 0, 1; and ``'head.weight'`` ``(1, c0, 1, 1)``, ``'head.bias'`` ``(1,)``.

References
----------
Ronneberger, O., Fischer, P., and Brox, T., 2015, U-Net: Convolutional networks for biomedical image segmentation:
MICCAI 2015, LNCS 9351, 234-241. doi:10.1007/978-3-319-24574-4_28

Wu, X., Liang, L., Shi, Y., and Fomel, S., 2019, FaultSeg3D: Using synthetic data sets to train an end-to-end
convolutional neural network for 3D seismic fault segmentation: Geophysics, 84(3), IM35-IM45.
doi:10.1190/geo2018-0646.1
"""

from __future__ import annotations

import numpy as np

from ...errors import InputError, Seismo3dError

__all__ = ["BLOCKS", "RECEPTIVE_HALF", "POOLING_MULTIPLE", "FaultNetwork", "onnx_model", "unet_forward",
           "normalise_section"]

BLOCKS = ("enc0", "enc1", "enc2", "bottleneck", "dec2", "dec1", "dec0")
# two 3x3 convolutions per level: 2 samples of context each at level k cost 2 * 2**k input samples; encoder and
# decoder levels 0-2 and the bottleneck (level 3): 2 * (1 + 2 + 4) * 2 + 2 * 8 = 44 (measured: 44 from an impulse at
# an aligned position), plus up to 7 from where a sample sits in the pooling grid: 51, rounded up to a multiple of 8
# so that a block starting at a multiple of it keeps the whole input's pooling grid
RECEPTIVE_HALF = 56
# three 2x2 poolings: sections are padded to a multiple of this, and blocks keep the whole input's pooling grid
# when they start at a multiple of it
POOLING_MULTIPLE = 8
# the forward pass runs in ONNX Runtime: on batches of 1-8 sections of 184-672 x 184-328 samples it took a third of
# the time of the compiled numba loop this module used before (0.11-0.13 s against 0.33-0.39 s; onnxruntime 1.32,
# 2 cores), with the same numbers (differences of 3e-6); its output for a section does not depend on the batch


class FaultNetwork:
    """The fault network as an ONNX Runtime session: (n, 1, H, W) float32 normalised sections -> (n, 1, H, W) fault
    probabilities, H and W multiples of 8.

    Parameters
    ----------
    model : bytes
        A serialised ONNX model (:func:`onnx_model`, or the shipped ``fault_unet.onnx``).

    Raises
    ------
    Seismo3dError
        ONNX Runtime cannot load the model (a damaged file: reinstall seismo3d).
    """

    def __init__(self, model: bytes):
        import onnxruntime as ort

        options = ort.SessionOptions()
        options.enable_cpu_mem_arena = False  # no memory held between calls: the block plans count what a batch needs
        options.log_severity_level = 3
        try:
            self._session = ort.InferenceSession(bytes(model), options, providers=["CPUExecutionProvider"])
        except Exception as exc:  # onnxruntime raises its own types for a bad model
            raise Seismo3dError(f"ONNX Runtime cannot load the fault network ({exc}); reinstall seismo3d") from exc
        self._input = self._session.get_inputs()[0].name

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return self._session.run(None, {self._input: np.ascontiguousarray(x, dtype=np.float32)})[0]


def onnx_model(weights) -> bytes:
    """The ONNX model (opset 17) of the network with these weights: the architecture of this module's docstring,
    3 x 3 convolutions zero-padded, nearest-neighbour upsampling, a logistic sigmoid at the end.

    Parameters
    ----------
    weights : mapping of str to ndarray
        The trained weights (see the module docstring), float32.

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


def normalise_section(section, *, scale=None) -> np.ndarray:
    """The network's input scaling: amplitudes minus their median, divided by their standard deviation, clipped to
    +-5.

    Parameters
    ----------
    section : (..., n_traces, n_samples) array_like
        Amplitudes of one section, or a stack of sections.
    scale : (float, float), optional
        (median, standard deviation) to use for every section (those of a whole cube); default: each section's own.

    Returns
    -------
    ndarray, float32, the same shape
    """
    x = np.asarray(section, dtype=np.float32)
    if scale is None:
        centre = np.median(x, axis=(-2, -1), keepdims=True)
        std = (x - centre).std(axis=(-2, -1), keepdims=True)
        std = np.where(std > 0, std, 1.0)
    else:
        centre, std = (np.float32(v) for v in scale)
    return np.clip((x - centre) / std, -5.0, 5.0).astype(np.float32)


def unet_forward(sections: np.ndarray, network) -> np.ndarray:
    """Fault probability of each sample of a stack of (normalised) sections.

    Parameters
    ----------
    sections : (n, n_traces, n_samples) float32 ndarray
        Sections scaled by :func:`normalise_section`. Any size: each axis is padded by reflection to a multiple
        of 8 and the output cropped back.
    network : FaultNetwork or mapping of str to ndarray
        The network (:func:`~seismo3d.seismic.faults.learned.load_fault_network`), or trained weights (see the
        module docstring; turned into a :class:`FaultNetwork` by :func:`onnx_model`, which needs the ``onnx``
        package).

    Returns
    -------
    (n, n_traces, n_samples) float32 ndarray
        Fault probability in [0, 1].

    Raises
    ------
    InputError
        ``sections`` is not a 3D stack or the weights miss an entry.
    """
    x = np.asarray(sections, dtype=np.float32)
    if x.ndim != 3:
        raise InputError(f"sections must be a (n, n_traces, n_samples) stack; got shape {x.shape}")
    if not isinstance(network, FaultNetwork):
        network = FaultNetwork(onnx_model(network))
    n, h, w = x.shape
    ph, pw = (-h) % POOLING_MULTIPLE, (-w) % POOLING_MULTIPLE
    if ph or pw:
        x = np.pad(x, ((0, 0), (0, ph), (0, pw)), mode="reflect" if min(h, w) > max(ph, pw) else "edge")
    prob = network(x[:, None])[:, 0]
    return np.ascontiguousarray(prob[:, :h, :w], dtype=np.float32)
