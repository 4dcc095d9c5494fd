"""Train the fault network of the learned fault likelihood on generated sections (PyTorch, CPU).

Run (the ``train`` extra installs PyTorch)::

    python -m seismo3d.training.fault_unet --out /tmp/fault_unet --steps 1200

writes ``fault_unet.npz`` (the weights, batch normalisation folded in, float32: what
:mod:`seismo3d.seismic.faults.likelihood.network` runs), ``fault_unet.json`` (options, seed, time, the loss every
``--log-every`` steps and the validation scores), ``fault_unet_check.npz`` (a small section and PyTorch's output for
it) and ``train.log``. To ship a retrained network: copy the two ``fault_unet.*`` files to
``seismo3d/seismic/faults/likelihood/``, the check file to ``tests/seismic/data/``, export the weights to the ONNX model
the package runs (``python -m seismo3d.training.export_onnx seismo3d/seismic/faults/likelihood/fault_unet.npz
seismo3d/seismic/faults/likelihood/fault_unet.onnx``) and put the sha256 it prints into
:data:`seismo3d.seismic.faults.likelihood.learned.WEIGHTS_SHA256`.

``--init-weights NPZ`` fine-tunes exported weights (e.g. the shipped ``fault_unet.npz``) instead of starting
from random ones; the record keeps their sha256.

``--teacher NPZ`` distils (Hinton et al. 2015): a network of ``--channels`` (e.g. ``8,16,32,64``, the cubes'
student of issue 58) learns the teacher's probability on the same sections as a soft target beside the labels, the
loss ``(1 - w) * L(labels) + w * L(teacher)`` with ``w`` = ``--distill-weight`` and ``L`` the loss below; the record
keeps the teacher's sha256 and its validation scores on the same validation sections.

Data: every step draws a new batch of sections from :func:`seismo3d.data.synthetic_sections.synthetic_fault_section`
(seeds ``seed * 1_000_003 + i`` for the i-th training section), so the network never sees a section twice; the
validation sections use seeds of another range (``VALIDATION_SEED``) that training never draws.

Loss: binary cross-entropy with the fault samples weighted by ``--positive-weight`` plus the soft Dice loss
(Milletari et al. 2016), as thin labels are a few percent of the samples (FaultSeg3D balances its cross-entropy for
the same reason).

Validation scores: tolerant precision, recall and F1 (a predicted fault sample within 2 samples of a labelled one,
and the converse) of the probability above 0.5, on ``--n-validation`` generated sections of 128 x 128.

References
----------
Wu, X., Liang, L., Shi, Y., and Fomel, S., 2019, FaultSeg3D: Using synthetic data sets to train an end-to-end
convolutional neural network for 3D seismic fault segmentation: Geophysics, 84(3), IM35-IM45.
doi:10.1190/geo2018-0646.1

Hinton, G., Vinyals, O., and Dean, J., 2015, Distilling the knowledge in a neural network: NIPS 2014 Deep
Learning Workshop, arXiv:1503.02531.

Milletari, F., Navab, N., and Ahmadi, S.-A., 2016, V-Net: Fully convolutional neural networks for volumetric medical
image segmentation: 3DV 2016, 565-571. doi:10.1109/3DV.2016.79
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import json
import logging
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import torch
from torch import nn

from ..data.synthetic_sections import FaultSectionOptions, synthetic_fault_section
from ..seismic.evaluation import evaluate_faults
from ..seismic.faults.likelihood.network import BLOCKS, normalise_section

__all__ = ["TrainingOptions", "FaultUNet", "train", "export_weights", "model_from_weights", "write_check",
           "validate", "main", "segmentation_loss", "training_mode"]

VALIDATION_SEED = 7_777_777
log = logging.getLogger("seismo3d.training")


@dataclass(frozen=True)
class TrainingOptions:
    """Options of :func:`train`.

    Attributes
    ----------
    channels : tuple of int
        Channels of encoder levels 0-2 and the bottleneck.
    steps : int
        Optimiser steps (each on a new batch).
    batch_size : int
        Sections per step.
    patch : int
        Side of the square training sections, samples (a multiple of 8).
    learning_rate : float
        Adam's initial learning rate (cosine decay to 5 % of it).
    positive_weight : float
        Weight of the fault samples in the cross-entropy.
    seed : int
        Seed of the sections drawn and of the network's initialisation.
    n_validation : int
        Generated validation sections.
    log_every : int
        Steps between loss log lines (and validation every 10 of them).
    threads : int
        PyTorch threads.
    init_weights : str or None
        Exported weights (``fault_unet.npz``) to start from: fine-tuning. Their batch normalisations are folded
        into the convolutions, so they stay the identity (frozen) while the convolutions train; ``None`` trains a
        new network from a random start.
    teacher : str or None
        Exported weights of a trained network to distil (``fault_unet.npz``): its probability on each batch is a
        soft target beside the labels; ``None``: the labels alone.
    distill_weight : float
        Weight ``w`` in [0, 1] of the teacher's target in the loss (``(1 - w)`` for the labels' one).
    """

    channels: tuple = (12, 24, 48, 96)
    steps: int = 1200
    batch_size: int = 16
    patch: int = 128
    learning_rate: float = 2e-3
    positive_weight: float = 4.0
    seed: int = 0
    n_validation: int = 96
    log_every: int = 50
    threads: int = 2
    init_weights: str | None = None
    teacher: str | None = None
    distill_weight: float = 0.5


def _conv_block(c_in: int, c_out: int) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(c_in, c_out, 3, padding=1), nn.BatchNorm2d(c_out), nn.ReLU(inplace=True),
                         nn.Conv2d(c_out, c_out, 3, padding=1), nn.BatchNorm2d(c_out), nn.ReLU(inplace=True))


class FaultUNet(nn.Module):
    """The U-Net of :mod:`seismo3d.seismic.faults.likelihood.network` in PyTorch (logits out; the sigmoid is in the
    loss).

    Parameters
    ----------
    channels : tuple of 4 int
        Channels of encoder levels 0-2 and the bottleneck.
    """

    def __init__(self, channels=(12, 24, 48, 96)):
        super().__init__()
        c = tuple(int(v) for v in channels)
        self.channels = c
        self.enc0, self.enc1, self.enc2 = _conv_block(1, c[0]), _conv_block(c[0], c[1]), _conv_block(c[1], c[2])
        self.bottleneck = _conv_block(c[2], c[3])
        self.dec2 = _conv_block(c[3] + c[2], c[2])
        self.dec1 = _conv_block(c[2] + c[1], c[1])
        self.dec0 = _conv_block(c[1] + c[0], c[0])
        self.head = nn.Conv2d(c[0], 1, 1)

    def forward(self, x):
        pool = nn.functional.max_pool2d
        up = nn.functional.interpolate
        s0 = self.enc0(x)
        s1 = self.enc1(pool(s0, 2))
        s2 = self.enc2(pool(s1, 2))
        b = self.bottleneck(pool(s2, 2))
        d2 = self.dec2(torch.cat([up(b, scale_factor=2, mode="nearest"), s2], 1))
        d1 = self.dec1(torch.cat([up(d2, scale_factor=2, mode="nearest"), s1], 1))
        d0 = self.dec0(torch.cat([up(d1, scale_factor=2, mode="nearest"), s0], 1))
        return self.head(d0)


def export_weights(model: FaultUNet) -> dict:
    """The weights of ``model`` as numpy float32 arrays for
    :func:`~seismo3d.seismic.faults.likelihood.network.unet_forward`, each batch normalisation folded into the
    convolution before it (evaluation statistics).

    Returns
    -------
    dict of str to ndarray
    """
    out = {}
    for name in BLOCKS:
        seq = getattr(model, name)
        for i, (conv, bn) in enumerate(((seq[0], seq[1]), (seq[3], seq[4]))):
            scale = bn.weight.detach() / torch.sqrt(bn.running_var + bn.eps)
            weight = conv.weight.detach() * scale[:, None, None, None]
            bias = (conv.bias.detach() - bn.running_mean) * scale + bn.bias.detach()
            out[f"{name}.{i}.weight"] = weight.numpy().astype(np.float32)
            out[f"{name}.{i}.bias"] = bias.numpy().astype(np.float32)
    out["head.weight"] = model.head.weight.detach().numpy().astype(np.float32)
    out["head.bias"] = model.head.bias.detach().numpy().astype(np.float32)
    return out


def model_from_weights(weights: dict) -> FaultUNet:
    """A :class:`FaultUNet` (evaluation mode) that computes what exported ``weights`` compute: the folded convolutions
    loaded, each batch normalisation an identity. Used to check the ONNX forward pass against PyTorch's.

    Parameters
    ----------
    weights : dict of str to ndarray
        Output of :func:`export_weights` (or the shipped ``fault_unet.npz``).

    Returns
    -------
    FaultUNet
    """
    c = tuple(int(weights[f"{b}.0.weight"].shape[0]) for b in ("enc0", "enc1", "enc2", "bottleneck"))
    model = FaultUNet(c)
    with torch.no_grad():
        for name in BLOCKS:
            seq = getattr(model, name)
            for i, (conv, bn) in enumerate(((seq[0], seq[1]), (seq[3], seq[4]))):
                conv.weight.copy_(torch.from_numpy(weights[f"{name}.{i}.weight"]))
                conv.bias.copy_(torch.from_numpy(weights[f"{name}.{i}.bias"]))
                bn.weight.fill_(1.0), bn.bias.zero_(), bn.running_mean.zero_()
                bn.running_var.fill_(1.0 - bn.eps)
        model.head.weight.copy_(torch.from_numpy(weights["head.weight"]))
        model.head.bias.copy_(torch.from_numpy(weights["head.bias"]))
    return model.eval()


def write_check(weights: dict, path: Path, *, shape=(96, 64), seed: int = 20261123) -> None:
    """A small generated section and PyTorch's fault probability of it (``section``, ``probability``, float32):
    the stored input and output the ONNX inference is tested against.

    Parameters
    ----------
    weights : dict of str to ndarray
    path : pathlib.Path
        ``.npz`` written.
    shape : (int, int), optional
        Multiples of 8 (PyTorch is not padded here).
    seed : int, optional
    """
    section = normalise_section(synthetic_fault_section(shape, seed=seed).section)
    with torch.no_grad():
        prob = torch.sigmoid(model_from_weights(weights)(torch.from_numpy(section)[None, None])).numpy()[0, 0]
    np.savez(path, section=section, probability=prob.astype(np.float32))


def _batch(seed: int, first: int, n: int, patch: int, options: FaultSectionOptions):
    sections = [synthetic_fault_section((patch, patch), seed=seed * 1_000_003 + first + i, options=options)
                for i in range(n)]
    x = normalise_section(np.stack([s.section for s in sections]))[:, None]
    y = np.stack([s.faults for s in sections]).astype(np.float32)[:, None]
    if n > 1:  # half the sections mirrored left-right (faults dip both ways; the generator is symmetric anyway)
        x[::2], y[::2] = x[::2, :, ::-1].copy(), y[::2, :, ::-1].copy()
    return torch.from_numpy(x), torch.from_numpy(y)


def segmentation_loss(logits, target, positive_weight):
    """Binary cross-entropy with the fault samples weighted by ``positive_weight`` plus the soft Dice loss (Milletari
    et al. 2016), of logits against targets in [0, 1] (tensors of one shape); ``positive_weight`` a float, or a tensor
    of the targets' shape (each fault sample's weight: binary targets only)."""
    if torch.is_tensor(positive_weight):  # per sample: pos_weight's terms for binary targets
        bce = nn.functional.binary_cross_entropy_with_logits(logits, target, weight=1.0 + (positive_weight - 1.0) *
                                                             target)
    else:
        bce = nn.functional.binary_cross_entropy_with_logits(logits, target,
                                                             pos_weight=torch.tensor(float(positive_weight)))
    prob = torch.sigmoid(logits)
    inter = (prob * target).sum()
    dice = 1 - (2 * inter + 1) / (prob.sum() + target.sum() + 1)
    return bce + dice


def training_mode(model: FaultUNet) -> None:
    """Training mode, except for a fine-tuned network's batch normalisations: folded weights leave them the
    identity, which batch statistics would undo (their running statistics stay those of the identity)."""
    model.train()
    if getattr(model, "frozen_batch_norm", False):
        for module in model.modules():
            if isinstance(module, nn.BatchNorm2d):
                module.eval()
                module.weight.requires_grad_(False)
                module.bias.requires_grad_(False)


def validate(model: FaultUNet, x: torch.Tensor, y: np.ndarray) -> dict:
    """Tolerant precision / recall / F1 (2 samples) of the probability above 0.5 on the validation sections, and
    the share of unfaulted sections with no sample above 0.5."""
    model.eval()
    with torch.no_grad():
        prob = torch.sigmoid(torch.cat([model(x[i:i + 16]) for i in range(0, len(x), 16)])).numpy()[:, 0]
    training_mode(model)
    hits_p = hits_r = n_pred = n_label = 0.0
    clean, n_unfaulted = 0, 0
    for p, lab in zip(prob > 0.5, y):
        if not lab.any():
            n_unfaulted += 1
            clean += int(p.sum() < 10)
            n_pred += p.sum()
            continue
        scores = evaluate_faults(p, lab, tolerance=2)
        hits_p += scores.precision * p.sum()
        hits_r += scores.recall * lab.sum()
        n_pred, n_label = n_pred + p.sum(), n_label + lab.sum()
    precision = hits_p / n_pred if n_pred else 0.0
    recall = hits_r / n_label if n_label else 0.0
    f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
    return {"precision": round(precision, 4), "recall": round(recall, 4), "f1": round(f1, 4),
            "unfaulted_clean": f"{clean}/{n_unfaulted}"}


def train(options: TrainingOptions, out_dir: Path, *, section_options: FaultSectionOptions | None = None) -> dict:
    """Train the fault network and write its weights and log to ``out_dir``.

    Parameters
    ----------
    options : TrainingOptions
    out_dir : pathlib.Path
        Output folder (created); ``fault_unet.npz``, ``fault_unet.json`` and ``train.log`` are written there.
    section_options : FaultSectionOptions, optional
        The generator's ranges (default: its defaults).

    Returns
    -------
    dict
        The record written to ``fault_unet.json``.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    handler = logging.FileHandler(out_dir / "train.log", mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(message)s"))
    log.addHandler(handler)
    log.setLevel(logging.INFO)
    sec = section_options or FaultSectionOptions()
    torch.manual_seed(options.seed)
    torch.set_num_threads(options.threads)
    if options.init_weights:
        with np.load(options.init_weights) as start:
            model = model_from_weights(dict(start))
        model.frozen_batch_norm = True
        options = dataclasses.replace(options, channels=model.channels)  # the start's, whatever was asked
        start_sha256 = hashlib.sha256(Path(options.init_weights).read_bytes()).hexdigest()
        log.info("fine-tuning from %s (sha256 %s)", options.init_weights, start_sha256)
    else:
        model, start_sha256 = FaultUNet(options.channels), None
    teacher, teacher_sha256 = None, None
    if options.teacher:
        with np.load(options.teacher) as npz:
            teacher = model_from_weights(dict(npz))
        teacher.requires_grad_(False)
        teacher_sha256 = hashlib.sha256(Path(options.teacher).read_bytes()).hexdigest()
        log.info("distilling %s (sha256 %s), weight %.2f", options.teacher, teacher_sha256, options.distill_weight)
    training_mode(model)
    optimiser = torch.optim.Adam([p for p in model.parameters() if p.requires_grad], lr=options.learning_rate)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(optimiser, options.steps, eta_min=0.05 * options.learning_rate)
    xv, yv = _batch(VALIDATION_SEED, 0, options.n_validation, options.patch, sec)
    yv = yv.numpy()[:, 0] > 0.5
    teacher_validation = validate(teacher, xv, yv) if teacher is not None else None
    if teacher is not None:
        teacher.eval()
        log.info("teacher validation %s", json.dumps(teacher_validation))
    n_params = sum(p.numel() for p in model.parameters())
    log.info("fault U-Net %s, %d parameters; %d steps of %d sections of %d^2", options.channels, n_params,
             options.steps, options.batch_size, options.patch)
    history, t0, running = [], time.perf_counter(), []
    for step in range(1, options.steps + 1):
        x, y = _batch(options.seed, (step - 1) * options.batch_size, options.batch_size, options.patch, sec)
        logits = model(x)
        loss = segmentation_loss(logits, y, options.positive_weight)
        if teacher is not None:
            with torch.no_grad():
                soft = torch.sigmoid(teacher(x))
            w = float(options.distill_weight)
            loss = (1 - w) * loss + w * segmentation_loss(logits, soft, options.positive_weight)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        schedule.step()
        running.append(loss.item())
        if step % options.log_every == 0 or step == options.steps:
            entry = {"step": step, "loss": round(float(np.mean(running)), 5),
                     "minutes": round((time.perf_counter() - t0) / 60, 2)}
            running = []
            if step % (10 * options.log_every) == 0 or step == options.steps:
                entry["validation"] = validate(model, xv, yv)
                model.eval()
                np.savez(out_dir / "checkpoint.npz", **export_weights(model))  # partial result of a long run
                training_mode(model)
            history.append(entry)
            log.info(json.dumps(entry))
    model.eval()
    weights = export_weights(model)
    npz = out_dir / "fault_unet.npz"
    np.savez(npz, **weights)
    digest = hashlib.sha256(npz.read_bytes()).hexdigest()
    write_check(weights, out_dir / "fault_unet_check.npz")
    record = {"training": {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(options).items()},
              "generator": {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(sec).items()},
              "parameters": n_params, "init_weights_sha256": start_sha256, "teacher_sha256": teacher_sha256,
              "teacher_validation": teacher_validation, "torch": torch.__version__,
              "minutes": round((time.perf_counter() - t0) / 60, 2),
              "validation": history[-1].get("validation"), "weights_sha256": digest, "history": history}
    (out_dir / "fault_unet.json").write_text(json.dumps(record, indent=1))
    log.info("weights %s sha256 %s", npz, digest)
    log.removeHandler(handler)
    return record


def _generator_options(items) -> FaultSectionOptions:
    """The generator's options from ``NAME=VALUE`` strings (values parsed as JSON: numbers, lists)."""
    fields = {f.name: f for f in dataclasses.fields(FaultSectionOptions)}
    given = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or name not in fields:
            raise SystemExit(f"--generator {item!r}: expected NAME=VALUE with NAME one of {', '.join(fields)}")
        parsed = json.loads(value)
        given[name] = tuple(parsed) if isinstance(parsed, list) else parsed
    return FaultSectionOptions(**given)


def main(argv=None) -> None:
    """Command line: ``python -m seismo3d.training.fault_unet --out DIR [--steps N] ...``."""
    defaults = TrainingOptions()
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, type=Path, help="output folder")
    parser.add_argument("--steps", type=int, default=defaults.steps)
    parser.add_argument("--batch-size", type=int, default=defaults.batch_size)
    parser.add_argument("--patch", type=int, default=defaults.patch)
    parser.add_argument("--channels", default=",".join(map(str, defaults.channels)))
    parser.add_argument("--learning-rate", type=float, default=defaults.learning_rate)
    parser.add_argument("--seed", type=int, default=defaults.seed)
    parser.add_argument("--threads", type=int, default=defaults.threads)
    parser.add_argument("--n-validation", type=int, default=defaults.n_validation)
    parser.add_argument("--log-every", type=int, default=defaults.log_every)
    parser.add_argument("--init-weights", default=None, metavar="NPZ",
                        help="fine-tune from these exported weights (e.g. seismo3d/seismic/faults/likelihood/fault_unet.npz)")
    parser.add_argument("--teacher", default=None, metavar="NPZ",
                        help="distil these exported weights (e.g. seismo3d/seismic/faults/likelihood/fault_unet.npz) "
                             "into a network of --channels")
    parser.add_argument("--distill-weight", type=float, default=defaults.distill_weight,
                        help="weight of the teacher's probability in the loss (the labels': 1 - it)")
    parser.add_argument("--generator", action="append", default=[], metavar="NAME=VALUE",
                        help="a FaultSectionOptions field of the generated sections (repeatable), e.g. "
                             "p_fault_system=0.7")
    a = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(message)s")
    options = TrainingOptions(channels=tuple(int(v) for v in a.channels.split(",")), steps=a.steps,
                              batch_size=a.batch_size, patch=a.patch, learning_rate=a.learning_rate, seed=a.seed,
                              threads=a.threads, n_validation=a.n_validation, log_every=a.log_every,
                              init_weights=a.init_weights, teacher=a.teacher, distill_weight=a.distill_weight)
    record = train(options, a.out, section_options=_generator_options(a.generator))
    print(f"validation {record['validation']}; weights sha256 {record['weights_sha256']}")


if __name__ == "__main__":
    main()
