"""Tests of :mod:`seismo3d.training.adapt`'s scale-and-shift modes (PyTorch: the ``train`` extra): only the
per-channel scale and shift after each convolution are trained, and what is trained is what MODEL runs (the affine
folded into the convolutions). The command-level learning test is ``tests/jobs/test_adapt.py``'s."""

from dataclasses import replace
from importlib import resources

import numpy as np
import pytest

CONVS = [f"{b}.{i}" for b in ("enc0", "enc1", "enc2", "bottleneck", "dec2", "dec1", "dec0") for i in (0, 1)]


@pytest.fixture(scope="module")
def torch():
    """PyTorch (the ``train`` extra), imported when a test of this file runs, not when pytest collects it: each
    pytest-xdist worker collects every file, and importing torch costs about 2 CPU s."""
    return pytest.importorskip("torch")


@pytest.fixture(scope="module")
def unet(torch):
    """:mod:`seismo3d.training.fault_unet` (it imports torch)."""
    from seismo3d.training import fault_unet

    return fault_unet


@pytest.fixture(scope="module")
def shipped():
    with resources.files("seismo3d.seismic.faults.likelihood").joinpath("fault_unet.npz").open("rb") as fh, \
            np.load(fh) as npz:
        return {k: npz[k] for k in npz.files}


def _grids():
    rng = np.random.default_rng(0)
    x = rng.standard_normal((48, 40)).astype(np.float32)
    y = np.zeros_like(x)
    y[20:22] = 1.0  # a vertical fault
    return [(x, y, np.ones_like(x))]


@pytest.mark.slow  # 5-20 s: PyTorch's Adam imports torch._dynamo on first use
@pytest.mark.parametrize("layers, n_trained", [("scale_shift", 2 * 528), ("scale_shift_head", 2 * 528 + 13)])
def test_the_scale_shift_modes_train_only_the_per_channel_affine(shipped, unet, layers, n_trained):
    from seismo3d.training.adapt import AdaptOptions, _choose_trained, fine_tune

    model_from_weights, training_mode = unet.model_from_weights, unet.training_mode
    model = model_from_weights(shipped)
    model.frozen_batch_norm = True
    training_mode(model)
    _choose_trained(model, layers)
    trained = {n: p for n, p in model.named_parameters() if p.requires_grad}
    assert sum(p.numel() for p in trained.values()) == n_trained  # 14 convolutions of 528 channels in all
    assert all(n.split(".")[-2] in ("1", "4") or n.startswith("head") for n in trained)  # BatchNorm2d slots

    tuned = fine_tune(shipped, _grids(), options=AdaptOptions(layers=layers, steps=3, patch=32, learning_rate=0.05,
                                                              rehearsal=0.0), progress=False)["weights"]
    for conv in CONVS:  # each output channel's folded weights and bias: the shipped ones scaled, the bias shifted
        w0, w = shipped[f"{conv}.weight"].astype(np.float64), tuned[f"{conv}.weight"].astype(np.float64)
        scale = (w * w0).sum(axis=(1, 2, 3)) / (w0 * w0).sum(axis=(1, 2, 3))
        np.testing.assert_allclose(w, scale[:, None, None, None] * w0, rtol=1e-5, atol=1e-7)
        assert np.abs(scale - 1).max() > 1e-3  # the scales did move (learning rate 0.05, 3 steps)
    head_moved = not np.array_equal(tuned["head.weight"], shipped["head.weight"])
    assert head_moved == (layers == "scale_shift_head")


@pytest.mark.slow
def test_every_convolution_mode_leaves_the_per_channel_affine_the_identity(shipped, unet):
    from seismo3d.training.adapt import _choose_trained

    model_from_weights, training_mode = unet.model_from_weights, unet.training_mode
    model = model_from_weights(shipped)
    model.frozen_batch_norm = True
    training_mode(model)
    _choose_trained(model, "all")
    assert not any(p.requires_grad for n, p in model.named_parameters() if n.split(".")[-2] in ("1", "4"))


@pytest.mark.slow  # imports PyTorch: 2.8 s in the fast lane, whose budget is 60 s
def test_the_trained_scales_and_shifts_are_what_the_exported_network_computes(shipped, torch, unet):
    """The trained model (batch normalisations an affine with identity statistics) against the network its exported
    weights rebuild (the affine folded into the convolutions, as MODEL's ONNX network runs it)."""
    model_from_weights, export_weights = unet.model_from_weights, unet.export_weights
    model = model_from_weights(shipped)
    gen = torch.Generator().manual_seed(1)
    with torch.no_grad():
        for module in model.modules():
            if isinstance(module, torch.nn.BatchNorm2d):
                module.weight.copy_(0.5 + torch.rand(module.weight.shape, generator=gen))
                module.bias.copy_(0.2 * torch.randn(module.bias.shape, generator=gen))
        x = torch.randn((1, 1, 64, 48), generator=gen)
        trained, folded = model(x), model_from_weights(export_weights(model))(x)
    np.testing.assert_allclose(folded.numpy(), trained.numpy(), atol=1e-4 * float(trained.abs().max()))


@pytest.mark.slow  # 3 short fine-tunings
def test_the_adapted_network_is_the_mean_of_its_runs_weights(shipped, torch):
    """AdaptOptions.runs: the runs start from the shipped weights with seeds seed, seed + 1, ... and the network
    adapted is their weights' mean (a uniform model soup), each run the one a single run of its seed gives."""
    from seismo3d.training.adapt import AdaptOptions, fine_tune

    options = AdaptOptions(steps=2, patch=32, rehearsal=0.0, runs=3, seed=7, threads=1)
    soup = fine_tune(shipped, _grids(), options=options, progress=False)
    assert soup["weights"].keys() == shipped.keys() and len(soup["loss"]) == 2
    runs = [fine_tune(shipped, _grids(), options=replace(options, runs=1, seed=7 + k), progress=False)["weights"]
            for k in range(options.runs)]
    assert not np.array_equal(runs[0]["enc0.0.weight"], runs[1]["enc0.0.weight"])  # the seeds draw other patches
    for name, weights in soup["weights"].items():
        assert weights.dtype == np.float32
        np.testing.assert_allclose(weights, np.mean([run[name] for run in runs], axis=0), rtol=1e-6, atol=1e-7)
