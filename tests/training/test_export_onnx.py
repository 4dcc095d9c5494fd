"""Tests of :mod:`seismo3d.training.export_onnx` that need no training framework (the exported network against the
stored PyTorch output: ``tests/seismic/faults/likelihood/test_learned.py``)."""

from pathlib import Path

import numpy as np
import pytest
from scipy.ndimage import correlate

from seismo3d.data.synthetic_sections import synthetic_fault_section
from seismo3d.seismic.faults.likelihood.network import FaultNetwork, normalise_section
from seismo3d.training.export_onnx import _coarse_weights, onnx_model

WEIGHTS = Path(__file__).parents[2] / "seismo3d" / "seismic" / "faults" / "likelihood" / "fault_unet.npz"


def _conv(x, w, b):
    """The trained 3 x 3 convolution, zero-padded (ONNX's Conv with pads 1, a cross-correlation), in float64."""
    return np.stack([b[o] + sum(correlate(x[c], w[o, c].astype(np.float64), mode="constant")
                                for c in range(x.shape[0])) for o in range(w.shape[0])])


def _space_to_depth(x):
    """ONNX's SpaceToDepth (DCR): channel ``(2 i + j) C + c`` holds ``x[c, 2 h + i, 2 w + j]``."""
    return np.concatenate([x[:, i::2, j::2] for i in (0, 1) for j in (0, 1)])


def _depth_to_space(y, c):
    """ONNX's DepthToSpace (DCR), the inverse of :func:`_space_to_depth`."""
    out = np.empty((c, 2 * y.shape[1], 2 * y.shape[2]))
    for i in (0, 1):
        for j in (0, 1):
            out[:, i::2, j::2] = y[(2 * i + j) * c:(2 * i + j + 1) * c]
    return out


@pytest.mark.parametrize("n_up", [3, 0])  # a decoder's first convolution; a fine convolution alone (its second)
def test_a_fine_convolution_on_the_coarser_grid_gives_the_same_outputs(n_up):
    rng = np.random.default_rng(n_up)
    n_skip, c_out = 2, 4
    coarse, fine = rng.standard_normal((n_up, 5, 6)), rng.standard_normal((n_skip, 10, 12))
    w = rng.standard_normal((c_out, n_up + n_skip, 3, 3)).astype(np.float32)
    b = rng.standard_normal(c_out).astype(np.float32)
    upsampled = coarse.repeat(2, axis=1).repeat(2, axis=2)  # nearest neighbour
    expected = _conv(np.concatenate([upsampled, fine]), w, b)
    w4, b4 = _coarse_weights(w, b, n_skip)
    assert w4.shape == (4 * c_out, n_up + 4 * n_skip, 3, 3) and w4.dtype == b4.dtype == np.float32
    got = _depth_to_space(_conv(np.concatenate([coarse, _space_to_depth(fine)]), w4, b4), c_out)
    np.testing.assert_allclose(got, expected, atol=1e-5)  # the summed taps rounded to float32


@pytest.mark.slow
def test_the_channels_last_export_gives_the_float_export_s_probability():
    # the model quantize_onnx quantises: the shipped float model's operations laid out channels last (pooling of the
    # phases, upsampling by broadcast, the head a matrix product); the same outputs up to float32 rounding (measured:
    # the same bits in ONNX Runtime 1.32), on sections of two sizes, a batch of 3 (every axis a multiple of 8)
    pytest.importorskip("onnx")
    with np.load(WEIGHTS) as npz:
        weights = {k: npz[k] for k in npz.files}
    first, last = FaultNetwork(onnx_model(weights)), FaultNetwork(onnx_model(weights, channels_last=True))
    for shape in ((96, 128), (64, 40)):
        x = np.stack([normalise_section(synthetic_fault_section(shape, seed=7 + k).section) for k in range(3)])
        a, b = first(x[:, None]), last(x[:, None])
        assert a.shape == b.shape == (3, 1) + shape
        np.testing.assert_allclose(b, a, rtol=0, atol=2e-6)
        assert a.max() > 0.9  # the faults are there
