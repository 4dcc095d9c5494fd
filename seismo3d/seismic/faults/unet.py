"""The fault network's forward pass: a compact 2D U-Net, run without a deep-learning framework (numpy, and numba
for its 3 x 3 convolutions).

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

The weights are a mapping ``name -> array``: ``'{block}.{i}.weight'`` of shape ``(c_out, c_in, 3, 3)`` (PyTorch's
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

import numba as nb
import numpy as np

from ...errors import InputError

__all__ = ["BLOCKS", "RECEPTIVE_HALF", "POOLING_MULTIPLE", "unet_forward", "normalise_section"]

BLOCKS = ("enc0", "enc1", "enc2", "bottleneck", "dec2", "dec1", "dec0")
# two 3x3 convolutions per level: 2 samples of context each at level k cost 2 * 2**k input samples; encoder and
# decoder levels 0-2 and the bottleneck (level 3): 2 * (1 + 2 + 4) * 2 + 2 * 8 = 44 (measured: 44 from an impulse at
# an aligned position), plus up to 7 from where a sample sits in the pooling grid: 51, rounded up to a multiple of 8
# so that a block starting at a multiple of it keeps the whole input's pooling grid
RECEPTIVE_HALF = 56
# three 2x2 poolings: sections are padded to a multiple of this, and blocks keep the whole input's pooling grid
# when they start at a multiple of it
POOLING_MULTIPLE = 8
# the convolutions run as a compiled loop (:func:`_conv3x3_relu_rows`) rather than as a matrix product of gathered
# columns (BLAS): on a batch of 8 sections of 179 x 183 samples the whole network took 0.81-0.88 CPU s instead of
# 1.93-2.01 (numba 0.68, OpenBLAS 0.3.31, 2 cores); the matrix product is slow here because the first and last
# levels have few channels (1 to 36) and their columns are gathered from strided memory
@nb.njit(cache=True, parallel=True)
def _conv3x3_relu_rows(xp, w, b, out):  # pragma: no cover - compiled
    """ReLU of the 'same' 3 x 3 convolution of padded NHWC ``xp`` (B, H + 2, W + 2, C) by ``w`` (3, 3, C, C_out) plus
    ``b``, into ``out`` (B, H, W, C_out). One output row per parallel iteration; four output samples at a time share
    each weight read, the output channels innermost (vectorised)."""
    n_b, hp, wp, c = xp.shape
    h, w_out = hp - 2, wp - 2
    c_out = w.shape[3]
    for row in nb.prange(n_b * h):
        k = row // h
        r = row - k * h
        acc = np.empty((w_out + 3, c_out), np.float32)
        for col in range(w_out + 3):
            for o in range(c_out):
                acc[col, o] = b[o]
        for i in range(3):
            for j in range(3):
                for col in range(0, w_out, 4):
                    for ci in range(c):
                        v0 = xp[k, r + i, col + j, ci]
                        v1 = xp[k, r + i, min(col + 1 + j, wp - 1), ci]
                        v2 = xp[k, r + i, min(col + 2 + j, wp - 1), ci]
                        v3 = xp[k, r + i, min(col + 3 + j, wp - 1), ci]
                        for o in range(c_out):
                            wv = w[i, j, ci, o]
                            acc[col, o] += v0 * wv
                            acc[col + 1, o] += v1 * wv
                            acc[col + 2, o] += v2 * wv
                            acc[col + 3, o] += v3 * wv
        for col in range(w_out):
            for o in range(c_out):
                out[k, r, col, o] = max(acc[col, o], np.float32(0.0))


def _conv3x3_relu(x: np.ndarray, weight: np.ndarray, bias: np.ndarray) -> np.ndarray:
    """ReLU of the 'same' 3 x 3 convolution of NHWC float32 ``x`` (zero padding), by a compiled loop."""
    b, h, w, c = x.shape
    xp = np.zeros((b, h + 2, w + 2, c), np.float32)
    xp[:, 1:h + 1, 1:w + 1] = x
    out = np.empty((b, h, w, weight.shape[0]), np.float32)
    _conv3x3_relu_rows(xp, np.ascontiguousarray(weight.transpose(2, 3, 1, 0), dtype=np.float32),
                       np.ascontiguousarray(bias, dtype=np.float32), out)
    return out


def _block(x: np.ndarray, weights, name: str) -> np.ndarray:
    for i in (0, 1):
        x = _conv3x3_relu(x, weights[f"{name}.{i}.weight"], weights[f"{name}.{i}.bias"])
    return x


def _pool(x: np.ndarray) -> np.ndarray:
    b, h, w, c = x.shape
    return x.reshape(b, h // 2, 2, w // 2, 2, c).max(axis=(2, 4))


def _up(x: np.ndarray) -> np.ndarray:
    return x.repeat(2, axis=1).repeat(2, axis=2)


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


def unet_forward(sections: np.ndarray, weights) -> np.ndarray:
    """Fault probability of each sample of a stack of (normalised) sections.

    Parameters
    ----------
    sections : (n, n_traces, n_samples) float32 ndarray
        Sections scaled by :func:`normalise_section`. Any size: each axis is padded by reflection to a multiple
        of 8 and the output cropped back.
    weights : mapping of str to ndarray
        The network's weights (see the module docstring), float32.

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
    missing = [f"{b}.{i}.weight" for b in BLOCKS for i in (0, 1) if f"{b}.{i}.weight" not in weights]
    if missing or "head.weight" not in weights:
        raise InputError(f"the fault network's weights miss {missing or ['head.weight']}")
    n, h, w = x.shape
    ph, pw = (-h) % POOLING_MULTIPLE, (-w) % POOLING_MULTIPLE
    if ph or pw:
        x = np.pad(x, ((0, 0), (0, ph), (0, pw)), mode="reflect" if min(h, w) > max(ph, pw) else "edge")
    x = x[..., None]
    skips = []
    for k in range(3):
        x = _block(x, weights, f"enc{k}")
        skips.append(x)
        x = _pool(x)
    x = _block(x, weights, "bottleneck")
    for k in (2, 1, 0):
        x = np.concatenate([_up(x), skips[k]], axis=-1)
        x = _block(x, weights, f"dec{k}")
    logits = x @ weights["head.weight"].reshape(1, -1).T + weights["head.bias"]
    prob = 1.0 / (1.0 + np.exp(-logits[..., 0]))
    return prob[:, :h, :w].astype(np.float32)
