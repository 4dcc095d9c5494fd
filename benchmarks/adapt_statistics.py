"""The fault network's feature statistics aligned to a survey (AdaBN, Li et al. 2016), without picks: measured on the
lines people drew, beside the shipped network, as ``benchmarks/adapt.py`` scores its folds.

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/adapt_statistics.py [--survey f3|gsb] [--variants ...]``

The shipped network's batch normalisations are folded into its convolutions, so AdaBN's "normalise each channel by
the target domain's statistics instead of the source's" becomes, for each 3 x 3 convolution's pre-activation channel
(before its ReLU), the affine ``z -> m_s + (s_s / s_t) (z - m_t)`` that maps the survey's mean ``m_t`` and standard
deviation ``s_t`` to those of the network's training data (``m_s``, ``s_s``: the generated sections of
:mod:`seismo3d.training.fault_unet`, 128 x 128, fixed seeds), folded back into the convolution's weights and bias.
The target statistics of a layer are measured with the layers before it already aligned (as AdaBN's forward pass in
training mode measures them), over every network grid the tracing runs the survey's line on
(:func:`seismo3d.jobs.adapt.training_grids`, the picks unused). Variants: only the first ``k`` of the seven blocks
aligned; the target statistics shrunk toward the source's by ``shrink`` (0: the shipped network, 1: full AdaBN).

Folds as ``benchmarks/adapt.py``'s: the statistics of F3 inline 100, the inlines 200-500 traced (and 500 -> 100-400);
Great South Basin crossline 2600 -> 2800 and back. Every MODEL traces at the tracing's default sensitivity and
evidence (nothing chosen on picks). ``identity`` is the folded network with no affine: it gives the shipped network's
scores exactly (the check of the folding; on F3 inline 100 ``trace_faults``' likelihood through the identity MODEL
equals the shipped one's, max difference 0.0; this forward against ONNX Runtime's, 1.5e-6). ``--tile 128``: the
target statistics over the 128 x 128 squares of the grids, the size of the source sections, so that the zero padding
weighs the same in both; ``BLOCKS:SHRINKp``: the source statistics those of a mixture of generated faulted and
unfaulted sections weighted so that the shipped network finds on it the share of probability above 0.5 it finds on
the survey's line (``prior_matched_stats``; 0.22 faulted for F3 inline 100, 0.19 for inline 500).

Results (2026-11-28, the shared 2-core machine; mean precision / recall / F1 of the lines traced, tolerance 3 samples):

=================================================  =====================  =====================
variant (all chosen on F3)                         F3 100 -> 200-500      F3 500 -> 100-400
=================================================  =====================  =====================
shipped network (and ``identity``, the same bits)  0.631 / 0.419 / 0.497  0.599 / 0.418 / 0.489
AdaBN, all 7 blocks (``7:1``)                      0.306 / 0.529 / 0.363  0.291 / 0.523 / 0.351
all 7 blocks, shrunk halfway (``7:0.5``)           0.280 / 0.465 / 0.314  0.291 / 0.490 / 0.333
the first 2 blocks (``2:1``)                       0.415 / 0.444 / 0.423  0.423 / 0.437 / 0.424
tiles: all 7 blocks (``7:1``)                      0.256 / 0.544 / 0.320
tiles: all 7 blocks shrunk to 0.25 (``7:0.25``)    0.295 / 0.496 / 0.331
tiles: the first 4 blocks (``4:1``)                0.287 / 0.477 / 0.341
tiles: the first block (``1:1``)                   0.552 / 0.443 / 0.487  0.513 / 0.393 / 0.436
tiles: the first convolution only (``0.5:1``)      0.563 / 0.425 / 0.478  0.545 / 0.462 / 0.498
tiles, fault share matched: all 7 (``7:1p``)       0.429 / 0.488 / 0.444  0.441 / 0.460 / 0.441
tiles, fault share matched: first 2 (``2:1p``)     0.475 / 0.441 / 0.448  0.470 / 0.428 / 0.443
=================================================  =====================  =====================

Reported on the Great South Basin (statistics of one crossline, the other traced): the variant best on F3 over both
folds, the first convolution only, gives 0.745 / 0.851 / 0.795 on crossline 2800 (shipped 0.781 / 0.877 / 0.826) and
0.807 / 0.886 / 0.845 on 2600 (shipped 0.843 / 0.850 / 0.847); full AdaBN 0.749 / 0.856 / 0.799 and 0.797 / 0.844 /
0.820. No variant helps F3 in both folds, and none is near issue 74's 0.62; every one costs precision.

Why (``--table``): the spread of a deep layer's features measures how many faults a section holds, not only how the
survey looks. Relative to the generated faulted sections, the mean over channels of each block's first convolution's
standard deviation, and the share of probability above 0.5:

=====================  ======  ======  ======  ==========  ======  ======  ======  =======
sections               enc0    enc1    enc2    bottleneck  dec2    dec1    dec0    p > 0.5
=====================  ======  ======  ======  ==========  ======  ======  ======  =======
generated, faulted     1.000   1.000   1.000   1.000       1.000   1.000   1.000   0.0603
generated, unfaulted   0.945   0.779   0.641   0.500       0.560   0.595   0.576   0.0004
F3 inline 100          0.831   0.757   0.601   0.575       0.652   0.626   0.645   0.0132
GSB crossline 2600     0.756   0.586   0.606   0.720       0.773   0.691   0.673   0.0484
=====================  ======  ======  ======  ==========  ======  ======  ======  =======

From the second block on, F3's features are as quiet as those of a generated section without faults: F3 holds fewer
faults than the training's sections (label shift), and AdaBN cannot tell that from a change of look. Aligning them
to the training's statistics amplifies nearly every layer (gains of 0.8-2, most above 1) and the network finds the
training's density of faults: on F3 inline 300 aligned to inline 100's statistics, 36 faults traced against 8, most
across the unbroken reflectors above 1200 ms that nobody drew, and the share of likelihood above 0.5 from 0.007 to
0.039 (``--picture PNG`` draws it: all 7 blocks, statistics on tiles). Mixing the source to the survey's estimated
share of faults cuts the loss (fold 100 on tiles: F1 0.320 -> 0.444, the shipped 0.497) but does not remove it. Only
the first convolution's alignment (the input's spectrum, which the fault content hardly moves: 0.945 unfaulted) is
about neutral in F1 (-0.019 / +0.009), and it still costs precision (0.631 -> 0.563, 0.599 -> 0.545): what F3 lacks
is not a shift of look the statistics can undo but another idea of a fault, which the picks of ``seismo3d adapt``
must teach.

Commands: ``--survey f3 --variants identity 7:1 2:1 7:0.5``; ``--survey f3 --tile 128 --folds 100 --no-default
--variants 7:1 1:1 7:0.25 4:1``; ``--survey f3 --tile 128 --no-default --variants 0.5:1 1:1``; ``--survey f3 --tile
128 --no-default --variants 7:1p 2:1p``; ``--survey gsb --tile 128 --variants identity 0.5:1 7:1``; ``--table``.
Each F3 fold of one variant takes 2-4 minutes on 2 loaded cores (four lines traced).

References
----------
Li, Y., Wang, N., Shi, J., Liu, J., and Hou, X., 2016, Revisiting batch normalization for practical domain
adaptation: arXiv:1603.04779 (AdaBN).

Lipton, Z. C., Wang, Y.-X., and Smola, A. J., 2018, Detecting and correcting for label shift with black box
predictors: ICML 2018, PMLR 80, 3122-3130, arXiv:1802.03916.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F

sys.path.insert(0, str(Path(__file__).resolve().parent))
from adapt import F3_FOLDS, GSB_FOLDS, f3_lines, traced_scores  # noqa: E402

from seismo3d.seismic.faults.likelihood.network import BLOCKS  # noqa: E402
from seismo3d.training.fault_unet import export_weights, model_from_weights  # noqa: E402

LAYERS = tuple(f"{b}.{i}" for b in BLOCKS for i in (0, 1))
SOURCE_SEED = 4_444_444  # generated sections for the source statistics (training drew seeds from 0)


def _batch_norm(model, layer: str):
    """The batch normalisation after convolution ``layer`` ('enc0.1', ...) of a :class:`FaultUNet`: the identity in a
    model of folded weights (:func:`model_from_weights`); its weight and bias hold the layer's affine."""
    name, i = layer.split(".")
    return getattr(model, name)[1 if i == "0" else 4]


class _Stop(Exception):
    def __init__(self, h):
        self.h = h


def _raise_input(module, inputs, output):
    raise _Stop(inputs[0])


def _pad8(x: np.ndarray) -> np.ndarray:
    h, w = x.shape
    ph, pw = (-h) % 8, (-w) % 8
    return np.pad(x, ((0, ph), (0, pw)), mode="reflect") if ph or pw else x


def layer_stats(model, sections: list, layer: str) -> tuple:
    """(mean, std) per channel of convolution ``layer``'s output (before its affine and ReLU) in ``model`` (a
    :class:`FaultUNet`) over every sample of ``sections`` (float64 tensors)."""
    total = sq = None
    count = 0
    hook = _batch_norm(model, layer).register_forward_hook(_raise_input)
    try:
        with torch.no_grad():
            for s in sections:
                try:
                    model(torch.from_numpy(_pad8(s)[None, None].copy()))
                except _Stop as stop:
                    h = stop.h[0].double().reshape(stop.h.shape[1], -1)
                total = h.sum(1) if total is None else total + h.sum(1)
                sq = (h ** 2).sum(1) if sq is None else sq + (h ** 2).sum(1)
                count += h.shape[1]
    finally:
        hook.remove()
    mean = total / count
    return mean, torch.sqrt(torch.clamp(sq / count - mean ** 2, min=1e-12))


def probability(model, section: np.ndarray) -> np.ndarray:
    """The network's fault probability of one normalised section."""
    with torch.no_grad():
        return torch.sigmoid(model(torch.from_numpy(_pad8(section)[None, None].copy()))).numpy()[0, 0]


def source_sections(n: int = 48, size: int = 128) -> list:
    from seismo3d.data.synthetic_sections import synthetic_fault_section
    from seismo3d.seismic.faults.likelihood.network import normalise_section

    return [normalise_section(synthetic_fault_section((size, size), seed=SOURCE_SEED + k).section) for k in range(n)]


def fault_share(model, sections: list) -> float:
    """Share of the samples of ``sections`` the network gives a probability above 0.5."""
    return float(np.mean(np.concatenate([(probability(model, s) > 0.5).ravel() for s in sections])))


def prior_matched_stats(model, targets: list, n: int = 48, size: int = 128) -> tuple:
    """Source statistics of a mixture of generated faulted and unfaulted sections, weighted so that the shipped
    network's share of probability above 0.5 in the mixture equals its share on ``targets`` (the target's share of
    faults estimated by the unadapted network, as black-box shift estimation does; Lipton et al. 2018); the
    weight of the faulted sections."""
    from seismo3d.data.synthetic_sections import FaultSectionOptions, synthetic_fault_section
    from seismo3d.seismic.faults.likelihood.network import normalise_section

    sets = [[normalise_section(synthetic_fault_section((size, size), seed=SOURCE_SEED + k,
                                                       options=FaultSectionOptions(p_unfaulted=p)).section)
             for k in range(n)] for p in (0.0, 1.0)]
    q_f, q_u, q_t = (fault_share(model, secs) for secs in (*sets, targets))
    mix = float(np.clip((q_t - q_u) / (q_f - q_u), 0.0, 1.0))
    stats = {}
    for layer in LAYERS:
        (m_f, s_f), (m_u, s_u) = (layer_stats(model, secs, layer) for secs in sets)
        mean = mix * m_f + (1 - mix) * m_u
        second = mix * (s_f ** 2 + m_f ** 2) + (1 - mix) * (s_u ** 2 + m_u ** 2)
        stats[layer] = (mean, torch.sqrt(torch.clamp(second - mean ** 2, min=1e-12)))
    return stats, mix


def target_sections(lines: list, tile: int = 0) -> list:
    """Every network grid's normalised section of each line (what the tracing feeds the network); with ``tile``,
    cut into the non-overlapping ``tile`` x ``tile`` squares the grids hold (the source sections' size, so that the
    zero padding weighs the same in both statistics)."""
    from seismo3d.jobs.adapt import training_grids

    out = []
    for section in lines:
        picks = np.zeros(section.shape, bool)
        grids = [g[0] for g in training_grids(section, picks, (0, 0))]
        if tile:
            grids = [g[i:i + tile, j:j + tile] for g in grids for i in range(0, g.shape[0] - tile + 1, tile)
                     for j in range(0, g.shape[1] - tile + 1, tile)]
        out += grids
    return out


def aligned_weights(weights: dict, source_stats: dict, targets: list, *, blocks: float = 7, shrink: float = 1.0):
    """Folded weights with the convolutions of the first ``blocks`` blocks aligned (module notes): each layer's
    affine set as its batch normalisation's weight and bias in turn (the layers before it aligned), then folded
    into the convolutions by :func:`export_weights`; and the range of each layer's gains."""
    model = model_from_weights(weights)
    gains = {}
    for layer in LAYERS[:int(round(2 * blocks))]:
        ms, ss = source_stats[layer]
        mt, st = layer_stats(model, targets, layer)
        mt, st = ms + shrink * (mt - ms), ss + shrink * (st - ss)
        a = ss / st
        with torch.no_grad():
            _batch_norm(model, layer).weight.copy_(a.float())
            _batch_norm(model, layer).bias.copy_((ms - a * mt).float())
        gains[layer] = [round(float(a.min()), 3), round(float(a.max()), 3)]
    return export_weights(model), gains


def statistics_table(shipped: dict, data: Path, work: Path) -> None:
    """Print, per block's first convolution, the mean over its channels of the pre-activation's standard deviation
    relative to the generated faulted sections', on generated sections with and without faults and on the F3 and
    Great South Basin lines; and each set's share of output probability above 0.5."""
    from seismo3d.data.synthetic_sections import synthetic_fault_section
    from seismo3d.seismic.faults.likelihood.network import normalise_section

    model = model_from_weights(shipped)
    gen = [synthetic_fault_section((128, 128), seed=SOURCE_SEED + k) for k in range(96)]
    gsb = data / "seismic" / "gsb_fault_sticks"
    sets = {"generated, faulted": [normalise_section(g.section) for g in gen if g.n_faults > 0][:48],
            "generated, unfaulted": [normalise_section(g.section) for g in gen if g.n_faults == 0],
            "F3 inline 100": target_sections([read_line(f3_lines(data, work)[100][0])], 128),
            "GSB crossline 2600": target_sections([read_line(gsb / "gsb_crl_2600.sgy")])}
    ref = {layer: layer_stats(model, sets["generated, faulted"], layer)[1] for layer in LAYERS[::2]}
    print(" " * 22 + "".join(f"{layer:>13s}" for layer in LAYERS[::2]) + "   p > 0.5")
    for name, secs in sets.items():
        ratio = [float((layer_stats(model, secs, layer)[1] / ref[layer]).mean()) for layer in LAYERS[::2]]
        print(f"{name:22s}" + "".join(f"{v:13.3f}" for v in ratio) + f"   {fault_share(model, secs):.4f}", flush=True)


def picture(shipped: dict, source_stats: dict, data: Path, work: Path, out: Path) -> None:
    """Draw F3 inline 300 (the person's faults) and the likelihood and traced faults of the shipped network and of
    the network aligned (all 7 blocks) to inline 100's statistics (128 x 128 tiles), to ``out`` (PNG); print the
    fault counts."""
    import matplotlib.pyplot as plt

    from seismo3d.seismic.faults.pipeline import trace_faults
    from seismo3d.seismic.faults.result import fault_labels

    lines = f3_lines(data, work)
    weights, _ = aligned_weights(shipped, source_stats, target_sections([read_line(lines[100][0])], 128))
    model = write_model_folder(weights, work / "picture_model")
    section, truth = read_line(lines[300][0]), lines[300][2]
    fig, axes = plt.subplots(3, 1, figsize=(12, 11), sharex=True)
    axes[0].imshow(section.T, cmap="gray", aspect="auto")
    axes[0].contour(truth.T, [0.5], colors="y", linewidths=0.6)
    axes[0].set_title("F3 inline 300 and the person's faults (yellow)")
    for ax, network, name in ((axes[1], None, "shipped"), (axes[2], model, "aligned to inline 100 (all 7 blocks)")):
        result = trace_faults(section, sample_interval=4.0, sample_unit="ms", progress=False, model=network)
        ax.imshow(result.likelihood.T, cmap="magma", vmin=0, vmax=1, aspect="auto")
        ax.contour((fault_labels(result.faults, section.shape) > 0).T, [0.5], colors="c", linewidths=0.6)
        ax.contour(truth.T, [0.5], colors="y", linewidths=0.6)
        share = float(np.mean(result.likelihood > 0.5))
        ax.set_title(f"{name}: likelihood, {len(result.faults)} faults traced (cyan), the person's (yellow); "
                     f"likelihood > 0.5: {share:.3f}")
        print(f"inline 300, {name}: {len(result.faults)} faults, likelihood > 0.5 on {share:.3f}", flush=True)
    axes[2].set_xlabel("crossline (trace)")
    fig.tight_layout()
    fig.savefig(out, dpi=70)


def write_model_folder(weights: dict, path: Path) -> Path:
    from seismo3d.jobs.adapt import write_model
    from seismo3d.jobs.runinfo import RunRecord
    from seismo3d.training.export_onnx import onnx_model

    return write_model(path, onnx_model(weights), RunRecord("adapt", {}), {},
                       {"kept": "adapted", "sensitivity": None, "unbroken_veto": None})


def read_line(segy: Path) -> np.ndarray:
    import segyio

    with segyio.open(str(segy), ignore_geometry=True) as f:
        return segyio.tools.collect(f.trace[:]).astype(np.float32)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--survey", choices=("f3", "gsb"), default="f3")
    ap.add_argument("--variants", nargs="+", default=["identity", "7:1"],
                    help="'identity' or BLOCKS:SHRINK[p] (7:1 full AdaBN, 2:1 the first two blocks, 0.5:1 the first "
                         "convolution, 7:0.5 shrunk halfway; a trailing p: the source mixed to the line's fault share)")
    ap.add_argument("--folds", nargs="+", type=int, default=None, help="the lines whose statistics are used "
                    "(default: both folds)")
    ap.add_argument("--no-default", action="store_true", help="do not trace the shipped network (its scores: nan)")
    ap.add_argument("--picture", type=Path, default=None, help="draw the picture of the module notes to this PNG")
    ap.add_argument("--table", action="store_true", help="print the statistics table only (module notes)")
    ap.add_argument("--tile", type=int, default=0, help="target statistics over tiles of this side (0: whole grids)")
    a = ap.parse_args(argv)
    data = Path(os.environ["SEISMO3D_DATA_DIR"])
    torch.set_num_threads(1)
    from importlib import resources

    with resources.files("seismo3d.seismic.faults.likelihood").joinpath("fault_unet.npz").open("rb") as fh, \
            np.load(fh) as npz:
        shipped = {k: npz[k] for k in npz.files}
    t0 = time.process_time()
    model = model_from_weights(shipped)
    src = source_sections()
    source_stats = {layer: layer_stats(model, src, layer) for layer in LAYERS}
    print(f"source statistics: {len(src)} generated sections, {time.process_time() - t0:.1f} CPU s", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        if a.table:
            return statistics_table(shipped, data, work)
        if a.picture:
            return picture(shipped, source_stats, data, work, a.picture)
        if a.survey == "f3":
            lines = f3_lines(data, work)
            folds = [(s, [(lines[t][0], {"mask": lines[t][1]}) for t in ts], lines[s][0]) for s, ts in F3_FOLDS]
        else:
            d = data / "seismic" / "gsb_fault_sticks"
            folds = [(s, [(d / f"gsb_crl_{t}.sgy", {"sticks": d / f"gsb_crl_{t}_faults_opendtect.dat"}) for t in ts],
                      d / f"gsb_crl_{s}.sgy") for s, ts in GSB_FOLDS]
        default = {}
        for source, targets, source_segy in folds:
            if a.folds and source not in a.folds:
                continue
            tgt = target_sections([read_line(source_segy)], a.tile)
            print(f"{a.survey} statistics of line {source}: {len(tgt)} sections (tile {a.tile})", flush=True)
            for variant in a.variants:
                c0 = time.process_time()
                if variant == "identity":
                    weights, gains = shipped, {}
                else:
                    k, s = variant.rstrip("p").split(":")
                    ref = source_stats
                    if variant.endswith("p"):  # the source mixed to the target's estimated share of faults
                        ref, mix = prior_matched_stats(model, tgt)
                        print(f"  {variant}: faulted generated sections weighted {mix:.3f}", flush=True)
                    weights, gains = aligned_weights(shipped, ref, tgt, blocks=float(k), shrink=float(s))
                model = write_model_folder(weights, work / f"model_{source}_{variant.replace(':', '_')}")
                cpu = time.process_time() - c0
                rows = []
                for segy, truth in targets:
                    if not a.no_default and segy not in default:
                        default[segy] = traced_scores(segy, work, **truth)
                    rows.append((default.get(segy, (np.nan,) * 3), traced_scores(segy, work, model=model, **truth)))
                    print(f"  {variant:9s} {segy.stem:16s} shipped P/R/F1 {' '.join(f'{v:.3f}' for v in rows[-1][0])}"
                          f"  aligned {' '.join(f'{v:.3f}' for v in rows[-1][1])}", flush=True)
                d_, a_ = np.mean([r[0] for r in rows], 0), np.mean([r[1] for r in rows], 0)
                print(f"MEAN {a.survey} {source} {variant:9s} shipped P {d_[0]:.3f} R {d_[1]:.3f} F1 {d_[2]:.3f}  "
                      f"aligned P {a_[0]:.3f} R {a_[1]:.3f} F1 {a_[2]:.3f}  (statistics {cpu:.1f} CPU s; gains "
                      f"{json.dumps(gains)[:300]})", flush=True)


if __name__ == "__main__":
    main()
