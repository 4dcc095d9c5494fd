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

The network ships as an ONNX model (:class:`FaultNetwork`, loaded by :func:`load_fault_network`; beside it the
same model quantised to 8 bits, ``fault_unet_int8.onnx``, :mod:`seismo3d.training.quantize_onnx`), exported from the
trained weights by :func:`seismo3d.training.export_onnx.onnx_model` (``python -m seismo3d.training.export_onnx``; the
``onnx`` package of the ``train`` extra), which computes the finest level (its encoder, decoder and the head) on the
next coarser grid, a fine tensor as its 4 phases (the same outputs up to float32 rounding, in less time). The weights
are a mapping ``name -> array``: ``'{block}.{i}.weight'`` of shape ``(c_out, c_in, 3, 3)`` (PyTorch's ``Conv2d``
layout) and ``'{block}.{i}.bias'`` ``(c_out,)``, for the blocks ``enc0, enc1, enc2, bottleneck, dec2, dec1, dec0`` and
``i`` in 0, 1; and ``'head.weight'`` ``(1, c0, 1, 1)``, ``'head.bias'`` ``(1,)``.

References
----------
Ronneberger, O., Fischer, P., and Brox, T., 2015, U-Net: Convolutional networks for biomedical image segmentation:
MICCAI 2015, LNCS 9351, 234-241. doi:10.1007/978-3-319-24574-4_28

Wu, X., Liang, L., Shi, Y., and Fomel, S., 2019, FaultSeg3D: Using synthetic data sets to train an end-to-end
convolutional neural network for 3D seismic fault segmentation: Geophysics, 84(3), IM35-IM45.
doi:10.1190/geo2018-0646.1
"""

from __future__ import annotations

import functools
import hashlib
from importlib import resources

import numpy as np

from ...._threads import map_parts
from ....errors import InputError, Seismo3dError

__all__ = ["BLOCKS", "RECEPTIVE_HALF", "POOLING_MULTIPLE", "WEIGHTS_SHA256", "INT8_SHA256", "NETWORKS",
           "FaultNetwork", "load_fault_network", "unet_forward", "normalise_section"]


BLOCKS = ("enc0", "enc1", "enc2", "bottleneck", "dec2", "dec1", "dec0")


# two 3x3 convolutions per level: 2 samples of context each at level k cost 2 * 2**k input samples; encoder and
# decoder levels 0-2 and the bottleneck (level 3): 2 * (1 + 2 + 4) * 2 + 2 * 8 = 44 (measured: 44 from an impulse at
# an aligned position), plus up to 7 from where a sample sits in the pooling grid: 51, rounded up to a multiple of 8
# so that a block starting at a multiple of it keeps the whole input's pooling grid
RECEPTIVE_HALF = 56


# three 2x2 poolings: sections are padded to a multiple of this, and blocks keep the whole input's pooling grid
# when they start at a multiple of it
POOLING_MULTIPLE = 8

WEIGHTS_FILE = "fault_unet.onnx"
WEIGHTS_SHA256 = "54014bd2fed21a4f729e41917a68b785747205b789f4f37a732781c2a63a951d"
INT8_FILE = "fault_unet_int8.onnx"
INT8_SHA256 = "621ea63082235f98e14229fcbbf2d200a5015eac5e568a28c2124680745570ea"
# the shipped models: LearnedOptions.network -> (file, sha256)
NETWORKS = {"int8": (INT8_FILE, INT8_SHA256), "float": (WEIGHTS_FILE, WEIGHTS_SHA256)}


class FaultNetwork:
    """The fault network as an ONNX Runtime session: (n, 1, H, W) float32 normalised sections -> (n, 1, H, W) fault
    probabilities, H and W multiples of 8.

    Parameters
    ----------
    model : bytes
        A serialised ONNX model (:func:`seismo3d.training.export_onnx.onnx_model`, or the shipped
        ``fault_unet.onnx``).
    calls : int, optional
        > 1: a session of one thread whose calls run their sections in that many parts at once, on threads (the same
        bits; on 2 cores 1.3 times faster than one call of two threads, which wait between operators); 1: one call.
    blocked_layout : bool, optional
        True (the default): ONNX Runtime runs the float convolutions in its blocked channel layout (NCHWc), the
        fastest for a float network. False, for the int8 network (:func:`load_fault_network`): its one float
        convolution, the first (4 channels in), then writes its output in the order the quantisation reads it, instead
        of blocks reordered after it (15-20 % of an int8 call on 256 x 256 sections; the int8 network on the 256^3
        cube of ``benchmarks/fault_speed.py`` 8.0 -> 7.3 CPU s on a quiet machine, a difference within the noise at
        load 4-11); its probability moves by 2e-6 on average, 0.019 at most (a float sum in another order, a
        quantisation step's rounding the other way), 99.9999 % of the samples on the same side of 0.5 (the horizons
        tracked across the faults of ``benchmarks/horizons.py``'s generated cubes hold either way,
        ``tests/seismic/horizons/test_fault_robustness.py``).

    Raises
    ------
    Seismo3dError
        ONNX Runtime cannot load the model (a damaged file: reinstall seismo3d).
    """

    def __init__(self, model: bytes, calls: int = 1, *, blocked_layout: bool = True):
        import onnxruntime as ort

        self._calls, options = max(1, int(calls)), ort.SessionOptions()
        options.intra_op_num_threads = 1 if self._calls > 1 else 0  # 0: ONNX Runtime's default, a thread per core
        options.enable_cpu_mem_arena = False  # no memory held between calls: the block plans count what a batch needs
        options.log_severity_level = 3
        # intra-op threads sleep between operators, not spin: the same results, the cores left to other threads and
        # processes (0.10-0.11 CPU s a 400 x 504 section against 0.13-0.15 in batches of 4 on 2 busy cores)
        options.add_session_config_entry("session.intra_op.allow_spinning", "0")
        try:
            # an optimizer name ONNX Runtime does not know is ignored: a later version that renames it loses the speed
            self._session = ort.InferenceSession(bytes(model), options, providers=["CPUExecutionProvider"],
                                                 disabled_optimizers=[] if blocked_layout else ["NchwcTransformer"])
        except Exception as exc:  # onnxruntime raises its own types for a bad model
            raise Seismo3dError(f"ONNX Runtime cannot load the fault network ({exc}); reinstall seismo3d") from exc
        self._input = self._session.get_inputs()[0].name

    def __call__(self, x: np.ndarray) -> np.ndarray:  # each section's probability is its own: the parts change no bit
        return map_parts(lambda part: self._session.run(None, {self._input: part})[0],
                         np.ascontiguousarray(x, dtype=np.float32), self._calls)


@functools.lru_cache(maxsize=4)
def load_fault_network(network: str = "int8", calls: int = 1) -> FaultNetwork:
    """A shipped network, its sha256 checked, as an ONNX Runtime session.

    Parameters
    ----------
    network : {'int8', 'float'}, optional
        'int8': ``fault_unet_int8.onnx`` (:data:`INT8_SHA256`), the float model quantised by
        :mod:`seismo3d.training.quantize_onnx`; 'float': ``fault_unet.onnx`` (:data:`WEIGHTS_SHA256`), exported from
        the trained weights ``fault_unet.npz`` by :func:`~seismo3d.training.export_onnx.onnx_model`.
    calls : int, optional
        Parts each call runs at once (:class:`FaultNetwork`).

    Returns
    -------
    FaultNetwork
        See :mod:`seismo3d.seismic.faults.likelihood.network`.

    Raises
    ------
    InputError
        ``network`` is not 'int8' or 'float'.
    Seismo3dError
        The model file is missing or its sha256 is not the recorded one (a damaged installation: reinstall
        seismo3d).
    """
    if network not in NETWORKS:
        raise InputError(f"network must be one of {', '.join(map(repr, NETWORKS))}; got {network!r}")
    name, sha256 = NETWORKS[network]
    ref = resources.files(__package__).joinpath(name)
    try:
        raw = ref.read_bytes()
    except FileNotFoundError as exc:
        raise Seismo3dError(f"the fault network {name} is missing from the installation; reinstall seismo3d") from exc
    digest = hashlib.sha256(raw).hexdigest()
    if digest != sha256:
        raise Seismo3dError(f"the fault network {name} has sha256 {digest}, not the released {sha256}; "
                            "reinstall seismo3d")
    return FaultNetwork(raw, calls, blocked_layout=network != "int8")


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
    network : FaultNetwork
        The network (:func:`~seismo3d.seismic.faults.likelihood.learned.load_fault_network`; trained weights become
        one as ``FaultNetwork(onnx_model(weights))``, :func:`seismo3d.training.export_onnx.onnx_model`).

    Returns
    -------
    (n, n_traces, n_samples) float32 ndarray
        Fault probability in [0, 1].

    Raises
    ------
    InputError
        ``sections`` is not a 3D stack, or ``network`` is not a :class:`FaultNetwork`.
    """
    x = np.asarray(sections, dtype=np.float32)
    if x.ndim != 3:
        raise InputError(f"sections must be a (n, n_traces, n_samples) stack; got shape {x.shape}")
    if not isinstance(network, FaultNetwork):
        raise InputError(f"unet_forward needs a FaultNetwork; got {type(network).__name__}: pass "
                         "load_fault_network(), or FaultNetwork(onnx_model(weights)) for trained weights "
                         "(seismo3d.training.export_onnx.onnx_model)")
    n, h, w = x.shape
    ph, pw = (-h) % POOLING_MULTIPLE, (-w) % POOLING_MULTIPLE
    if ph or pw:
        x = np.pad(x, ((0, 0), (0, ph), (0, pw)), mode="reflect" if min(h, w) > max(ph, pw) else "edge")
    prob = network(x[:, None])[:, 0]
    return np.ascontiguousarray(prob[:, :h, :w], dtype=np.float32)
