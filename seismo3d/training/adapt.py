"""Fine-tune the fault network on an interpreter's faults on a few lines (PyTorch, CPU): what ``seismo3d adapt``
trains (:mod:`seismo3d.jobs.adapt` holds the picks back, validates and writes the model).

The shipped weights (``fault_unet.npz``, batch normalisations folded in and kept the identity) start; every
convolution is trained (``AdaptOptions.layers='all'``, the default), or the decoder and head only (``'decoder'``), or
the last decoder level and head (``'last'``), or, every convolution frozen, only the per-channel scale and shift after
each convolution (``'scale_shift'``, with the head ``'scale_shift_head'``: the batch normalisations' affine, their
statistics kept the identity, folded into the convolutions by :func:`~seismo3d.training.fault_unet.export_weights`;
BitFit, Ben Zaken et al. 2022), on patches of the picked lines drawn on each network grid the tracing
runs (:class:`~seismo3d.seismic.faults.LearnedOptions`'s ``resample``: the line resampled as
:func:`~seismo3d.seismic.faults.likelihood.network_grid.to_network_grid` does, the picks with it), mirrored left-right
at random, with the loss of the original training (binary cross-entropy with the fault samples weighted, plus the soft
Dice loss; :mod:`seismo3d.training.fault_unet`). Every sample of a picked line counts: a sample away from the picks is
taught as no fault (the line is taken as fully interpreted); the held-back samples count for nothing (``weight`` 0).

Against forgetting: most patches are placed around a picked fault (``focus``), since most of a line holds none and
patches drawn anywhere teach mostly "no fault"; a share of each batch is generated sections of the network's own
training with their true faults (``rehearsal``; Robins 1995), so the network keeps its idea of a fault while it
learns the interpreter's. ``anchor`` adds the L2-SP penalty (Li et al. 2018), and ``labels='thin'`` trains on the
picks' skeleton with the samples beside it not counted; neither is on by default.

The defaults were chosen on the F3 inlines a person drew, adapted on inline 100 and scored on inlines 200-500
(``docs/guide/faults.md``, Teaching it your survey): mean F1 0.50 with the shipped network, 0.57 with the defaults
(traced at ``sensitivity`` 0.35), 0.34 with every layer at a learning rate of 0.002 and patches drawn anywhere, 0.37
with the decoder alone, 0.31 with thin labels, 0.55 with the L2-SP penalty (``anchor`` 0.001) added, 0.28 with a
linear head on the frozen last decoder features, 0.47 with the picked faults weighted to the training's share of
faults (``balance``), 0.51 with only the scales and shifts and the head trained (learning rate 0.03; 0.48 at 0.01,
and at 0.003 the held-back band kept the shipped network). Adapted on inline 500, the
same defaults scored 0.40 on inlines 100-400 against the shipped network's 0.49: what one line teaches does not
always carry to the next.

References
----------
Wu, X., Liang, L., Shi, Y., and Fomel, S., 2019, FaultSeg3D: Using synthetic data sets to train an end-to-end
convolutional neural network for 3D seismic fault segmentation: Geophysics, 84(3), IM35-IM45 (fine-tuning the
synthetic-trained network on a few field labels). doi:10.1190/geo2018-0646.1

Yosinski, J., Clune, J., Bengio, Y., and Lipson, H., 2014, How transferable are features in deep neural networks?:
NIPS 2014, arXiv:1411.1792.

Li, X., Grandvalet, Y., and Davoine, F., 2018, Explicit inductive bias for transfer learning with convolutional
networks: ICML 2018, PMLR 80, 2825-2834, arXiv:1802.01483 (L2-SP).

Ben Zaken, E., Goldberg, Y., and Ravfogel, S., 2022, BitFit: Simple parameter-efficient fine-tuning for
transformer-based masked language-models: ACL 2022 (short papers), 1-9. doi:10.18653/v1/2022.acl-short.1

Perez, E., Strub, F., de Vries, H., Dumoulin, V., and Courville, A., 2018, FiLM: Visual reasoning with a general
conditioning layer: AAAI 2018, 3942-3951. arXiv:1709.07871

Robins, A., 1995, Catastrophic forgetting, rehearsal and pseudorehearsal: Connection Science, 7(2), 123-146.
doi:10.1080/09540099550039318

Wortsman, M., Ilharco, G., Gadre, S. Y., Roelofs, R., Gontijo-Lopes, R., Morcos, A. S., Namkoong, H., Farhadi, A.,
Carmon, Y., Kornblith, S., and Schmidt, L., 2022, Model soups: averaging weights of multiple fine-tuned models
improves accuracy without increasing inference time: ICML 2022, PMLR 162, 23965-23998, arXiv:2203.05482
(``AdaptOptions.runs``).
"""

from __future__ import annotations

import numpy as np
import torch

from .._progress import progress_steps
from ..errors import InputError
from .adapt_options import LAYERS, SCALE_SHIFT, AdaptOptions
from .fault_unet import export_weights, model_from_weights, segmentation_loss, training_mode

__all__ = ["AdaptOptions", "LAYERS", "fine_tune", "generated_fault_odds"]

REHEARSAL_SEED = 5_555_555  # generated sections drawn for rehearsal (the shipped training drew seeds from 0)


def _patch(rng, x, y, w, size: int, focus: float = 0.0):
    """A random patch (multiple of 8 along both axes) of one grid's section, labels and weights, mirrored at
    random; with probability ``focus`` placed around a counted fault sample (any place when there is none)."""
    ph, pw = (min(size, n // 8 * 8) for n in x.shape)
    i, j = rng.integers(0, x.shape[0] - ph + 1), rng.integers(0, x.shape[1] - pw + 1)
    if focus > 0 and rng.random() < focus:
        faults = np.flatnonzero((y > 0) & (w > 0))
        if faults.size:
            fi, fj = np.unravel_index(faults[rng.integers(faults.size)], x.shape)
            i = int(np.clip(fi - rng.integers(ph // 4, 3 * ph // 4 + 1), 0, x.shape[0] - ph))
            j = int(np.clip(fj - rng.integers(pw // 4, 3 * pw // 4 + 1), 0, x.shape[1] - pw))
    cut = (slice(i, i + ph), slice(j, j + pw))
    xp, yp, wp = x[cut], y[cut], w[cut]
    if rng.random() < 0.5:
        xp, yp, wp = xp[::-1], yp[::-1], wp[::-1]
    return xp, yp, wp


def fine_tune(weights: dict, grids: list, *, options: AdaptOptions | None = None, progress: bool = True) -> dict:
    """The fault network fine-tuned on labelled sections.

    Parameters
    ----------
    weights : dict of str to ndarray
        The starting weights (the shipped ``fault_unet.npz``; the module docstring of
        :mod:`~seismo3d.seismic.faults.likelihood.network`).
    grids : list of (x, y, w)
        Each a section on one network grid: ``x`` (n_traces, n_samples) float32 normalised amplitudes
        (:func:`~seismo3d.seismic.faults.likelihood.network.normalise_section`), ``y`` the same shape, 1 on faults
        and 0 elsewhere, ``w`` the same shape, the weight of each sample in the loss (0: not counted). Each at least
        16 x 16. Patches are drawn from the grids in turn.
    options : AdaptOptions, optional
    progress : bool, optional
        A progress bar over the steps of every run (:func:`seismo3d._progress.progress_steps`).

    Returns
    -------
    dict
        ``'weights'``: the fine-tuned weights (float32, the layout of ``weights``; with ``options.runs`` > 1 the
        mean of the runs' weights, a uniform model soup: Wortsman et al. 2022, ICML, arXiv:2203.05482);
        ``'loss'``: the mean loss of every tenth of the steps, averaged over the runs (list of float);
        ``'picked_positive_weight'``: the weight of the picked fault samples in the cross-entropy (float).

    Raises
    ------
    InputError
        A section smaller than 16 x 16, or shapes that differ.
    """
    opt = options or AdaptOptions()
    for x, y, w in grids:
        if x.shape != y.shape or x.shape != w.shape or min(x.shape) < 16:
            raise InputError(f"each section must be at least 16 x 16 with labels and weights of its shape; got "
                             f"{x.shape}, {y.shape}, {w.shape}")
    picked_weight = float(opt.positive_weight)
    if opt.balance:  # the picks weighted to the generated training's odds of a fault sample
        picked_weight *= generated_fault_odds(int(opt.patch)) / _picked_fault_odds(grids)
    threads = torch.get_num_threads()
    torch.set_num_threads(int(opt.threads))
    runs, losses = [], []
    try:
        with progress_steps(int(opt.runs) * int(opt.steps), "adapting the fault network", unit="step",
                            enabled=progress) as bar:
            for run in range(int(opt.runs)):
                tuned, loss = _fine_tune_run(weights, grids, opt, int(opt.seed) + run, picked_weight, bar)
                runs.append(tuned)
                losses.append(loss)
    finally:
        torch.set_num_threads(threads)
    soup = {name: np.mean([run[name] for run in runs], axis=0, dtype=np.float64).astype(np.float32)
            for name in runs[0]}  # the uniform soup (Wortsman et al. 2022): one network, the runs' mean weights
    return {"weights": soup, "loss": [round(float(v), 5) for v in np.mean(losses, axis=0)],
            "picked_positive_weight": picked_weight}


def _fine_tune_run(weights: dict, grids: list, opt: AdaptOptions, seed: int, picked_weight: float, bar) -> tuple:
    """One run of :func:`fine_tune` from ``weights`` with its own ``seed`` (of the patches drawn, the generated
    sections of the rehearsal and PyTorch): its exported weights (float32) and the mean loss of every tenth of its
    steps; ``bar`` advanced once a step."""
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    model = model_from_weights(weights)
    model.frozen_batch_norm = True  # folded weights: the batch normalisations' statistics stay the identity
    training_mode(model)
    _choose_trained(model, opt.layers)
    trained = [p for p in model.parameters() if p.requires_grad]
    start = [p.detach().clone() for p in trained]
    optimiser = torch.optim.Adam(trained, lr=float(opt.learning_rate))
    n_generated = int(round(float(opt.rehearsal) * int(opt.batch_size)))
    n_picked = int(opt.batch_size) - n_generated
    positive = torch.tensor([picked_weight] * n_picked + [float(opt.positive_weight)] * n_generated)
    losses, running, every = [], [], max(1, int(opt.steps) // 10)
    for step in range(int(opt.steps)):
        parts = [_patch(rng, *grids[(step * n_picked + b) % len(grids)], int(opt.patch), float(opt.focus))
                 for b in range(n_picked)]
        parts += [_generated_patch(seed, step * n_generated + b, int(opt.patch)) for b in range(n_generated)]
        shape = min(p[0].shape[0] for p in parts), min(p[0].shape[1] for p in parts)
        x, y, w = (torch.from_numpy(np.stack([p[k][:shape[0], :shape[1]] for p in parts])[:, None].copy())
                   for k in range(3))
        loss = _weighted_loss(model(x), y, w, positive if opt.balance else float(opt.positive_weight))
        if float(opt.anchor) > 0:  # L2-SP: the distance to the shipped weights (Li et al. 2018, eq. 3)
            loss = loss + float(opt.anchor) * sum(((p - p0) ** 2).sum() for p, p0 in zip(trained, start))
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        running.append(loss.item())
        if (step + 1) % every == 0:
            losses.append(float(np.mean(running)))
            running = []
        bar.advance()
    model.eval()
    return export_weights(model), losses


def _choose_trained(model, layers: str) -> None:
    """Freeze the convolutions ``layers`` keeps frozen (:data:`~seismo3d.training.adapt_options.LAYERS`); in the
    scale-and-shift modes, train the batch normalisations' per-channel affine instead (their statistics stay the
    identity, so each is ``z -> scale * z + shift`` on a convolution's output, before its ReLU)."""
    from torch import nn

    for name in LAYERS[layers]:
        getattr(model, name).requires_grad_(False)
    if layers in SCALE_SHIFT:
        for module in model.modules():
            if isinstance(module, nn.BatchNorm2d):
                module.weight.requires_grad_(True)
                module.bias.requires_grad_(True)


def generated_fault_odds(size: int, n: int = 32) -> float:
    """The odds of a fault sample (faults / the rest) in ``n`` generated sections of ``size`` x ``size`` samples of
    the network's training kind (the rehearsal's first seeds; :func:`_generated_patch`).

    Parameters
    ----------
    size : int
        Side of the sections, samples.
    n : int, optional
        Sections measured.

    Returns
    -------
    float
        Dimensionless, > 0 (0.055 at 128: 5.2 % of the samples are faults).
    """
    fraction = float(np.mean([_generated_patch(0, k, size)[1].mean() for k in range(n)]))
    return fraction / (1.0 - fraction)


def _picked_fault_odds(grids: list) -> float:
    """The odds of a fault sample among the counted samples (weight > 0) of the picked sections."""
    faults = sum(float(((y > 0) & (w > 0)).sum()) for _, y, w in grids)
    counted = sum(float((w > 0).sum()) for _, _, w in grids)
    return max(faults, 1.0) / max(counted - faults, 1.0)


def _generated_patch(seed: int, index: int, size: int):
    """A generated section of the network's training kind (``size`` x ``size``), its true faults and unit weights,
    mirrored left-right on odd indices; seeds of a range the training of the shipped network never drew."""
    from ..data.synthetic_sections import synthetic_fault_section
    from ..seismic.faults.likelihood.network import normalise_section

    generated = synthetic_fault_section((size, size), seed=REHEARSAL_SEED + seed * 1_000_003 + index)
    x, y = normalise_section(generated.section), generated.faults.astype(np.float32)
    if index % 2:
        x, y = x[::-1], y[::-1]
    return x, y, np.ones_like(y)


def _weighted_loss(logits, target, weight, positive_weight):
    """:func:`~seismo3d.training.fault_unet.segmentation_loss` on the counted samples only (``weight`` > 0);
    ``positive_weight`` a float, or a tensor of one per patch (each fault sample weighted by its patch's)."""
    if torch.is_tensor(positive_weight):
        positive_weight = positive_weight.view(-1, 1, 1, 1).expand_as(target)
    keep = weight > 0
    if bool(keep.all()):
        return segmentation_loss(logits, target, positive_weight)
    if torch.is_tensor(positive_weight):
        positive_weight = positive_weight[keep]
    return segmentation_loss(logits[keep], target[keep], positive_weight)
