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
evidence (nothing chosen on picks). ``identity`` is the folded network with no affine: it must give the shipped
network's scores exactly (the check of the folding).

References
----------
Li, Y., Wang, N., Shi, J., Liu, J., and Hou, X., 2016, Revisiting batch normalization for practical domain
adaptation: arXiv:1603.04779 (AdaBN).
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

LAYERS = tuple(f"{b}.{i}" for b in BLOCKS for i in (0, 1))
SOURCE_SEED = 4_444_444  # generated sections for the source statistics (training drew seeds from 0)


def forward(w: dict, x: torch.Tensor, affine: dict, upto: str | None = None):
    """The network (folded weights ``w``, torch tensors) with a per-channel affine ``(a, b)`` after the convolutions
    named in ``affine``; with ``upto``, the pre-activation (before its affine) of that convolution instead."""
    def block(name, h):
        for i in (0, 1):
            key = f"{name}.{i}"
            h = F.conv2d(h, w[f"{key}.weight"], w[f"{key}.bias"], padding=1)
            if key == upto:
                raise _Stop(h)
            if key in affine:
                a, b = affine[key]
                h = h * a[None, :, None, None] + b[None, :, None, None]
            h = F.relu(h)
        return h

    up = lambda t: F.interpolate(t, scale_factor=2, mode="nearest")  # noqa: E731
    s0 = block("enc0", x)
    s1 = block("enc1", F.max_pool2d(s0, 2))
    s2 = block("enc2", F.max_pool2d(s1, 2))
    bn = block("bottleneck", F.max_pool2d(s2, 2))
    d2 = block("dec2", torch.cat([up(bn), s2], 1))
    d1 = block("dec1", torch.cat([up(d2), s1], 1))
    d0 = block("dec0", torch.cat([up(d1), s0], 1))
    return F.conv2d(d0, w["head.weight"], w["head.bias"])


class _Stop(Exception):
    def __init__(self, h):
        self.h = h


def _pad8(x: np.ndarray) -> np.ndarray:
    h, w = x.shape
    ph, pw = (-h) % 8, (-w) % 8
    return np.pad(x, ((0, ph), (0, pw)), mode="reflect") if ph or pw else x


def layer_stats(w: dict, sections: list, affine: dict, layer: str) -> tuple:
    """(mean, std) per channel of ``layer``'s pre-activation over every sample of ``sections`` (float64)."""
    total = sq = None
    count = 0
    with torch.no_grad():
        for s in sections:
            try:
                forward(w, torch.from_numpy(_pad8(s)[None, None].copy()), affine, upto=layer)
            except _Stop as stop:
                h = stop.h[0].double().reshape(stop.h.shape[1], -1)
            total = h.sum(1) if total is None else total + h.sum(1)
            sq = (h ** 2).sum(1) if sq is None else sq + (h ** 2).sum(1)
            count += h.shape[1]
    mean = total / count
    return mean, torch.sqrt(torch.clamp(sq / count - mean ** 2, min=1e-12))


def source_sections(n: int = 48, size: int = 128) -> list:
    from seismo3d.data.synthetic_sections import synthetic_fault_section
    from seismo3d.seismic.faults.likelihood.network import normalise_section

    return [normalise_section(synthetic_fault_section((size, size), seed=SOURCE_SEED + k).section) for k in range(n)]


def fault_share(w: dict, sections: list) -> float:
    """Share of the samples of ``sections`` the network (no affine) gives a probability above 0.5."""
    with torch.no_grad():
        return float(np.mean(np.concatenate([
            (torch.sigmoid(forward(w, torch.from_numpy(_pad8(s)[None, None].copy()), {})) > 0.5).numpy().ravel()
            for s in sections])))


def prior_matched_stats(w: dict, targets: list, n: int = 48, size: int = 128) -> tuple:
    """Source statistics of a mixture of generated faulted and unfaulted sections, weighted so that the shipped
    network's share of probability above 0.5 in the mixture equals its share on ``targets`` (the target's share of
    faults estimated by the unadapted network, as black-box shift estimation does; Lipton et al. 2018); the
    weight of the faulted sections."""
    from seismo3d.data.synthetic_sections import FaultSectionOptions, synthetic_fault_section
    from seismo3d.seismic.faults.likelihood.network import normalise_section

    sets = [[normalise_section(synthetic_fault_section((size, size), seed=SOURCE_SEED + k,
                                                       options=FaultSectionOptions(p_unfaulted=p)).section)
             for k in range(n)] for p in (0.0, 1.0)]
    q_f, q_u, q_t = fault_share(w, sets[0]), fault_share(w, sets[1]), fault_share(w, targets)
    mix = float(np.clip((q_t - q_u) / (q_f - q_u), 0.0, 1.0))
    stats = {}
    for layer in LAYERS:
        (m_f, s_f), (m_u, s_u) = (layer_stats(w, secs, {}, layer) for secs in sets)
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


def aligned_weights(weights: dict, source_stats: dict, targets: list, *, blocks: int = 7, shrink: float = 1.0):
    """Folded weights with the first ``blocks`` blocks' convolutions aligned (module notes)."""
    w = {k: torch.from_numpy(np.asarray(v, np.float32)) for k, v in weights.items()}
    affine = {}
    for layer in LAYERS[:int(round(2 * blocks))]:
        ms, ss = source_stats[layer]
        mt, st = layer_stats(w, targets, affine, layer)
        mt, st = ms + shrink * (mt - ms), ss + shrink * (st - ss)
        a = ss / st
        affine[layer] = (a.float(), (ms - a * mt).float())
    out = {k: np.asarray(v, np.float32).copy() for k, v in weights.items()}
    for layer, (a, b) in affine.items():
        out[f"{layer}.weight"] = (out[f"{layer}.weight"] * a.numpy()[:, None, None, None]).astype(np.float32)
        out[f"{layer}.bias"] = (out[f"{layer}.bias"] * a.numpy() + b.numpy()).astype(np.float32)
    gains = {layer: [round(float(a.min()), 3), round(float(a.max()), 3)] for layer, (a, _) in affine.items()}
    return out, gains


def statistics_table(shipped: dict, data: Path, work: Path) -> None:
    """Print, per block's first convolution, the mean over its channels of the pre-activation's standard deviation
    relative to the generated faulted sections', on generated sections with and without faults and on the F3 and
    Great South Basin lines; and each set's share of output probability above 0.5."""
    from seismo3d.data.synthetic_sections import synthetic_fault_section
    from seismo3d.seismic.faults.likelihood.network import normalise_section

    w = {k: torch.from_numpy(v) for k, v in shipped.items()}
    gen = [synthetic_fault_section((128, 128), seed=SOURCE_SEED + k) for k in range(96)]
    gsb = data / "seismic" / "gsb_fault_sticks"
    sets = {"generated, faulted": [normalise_section(g.section) for g in gen if g.n_faults > 0][:48],
            "generated, unfaulted": [normalise_section(g.section) for g in gen if g.n_faults == 0],
            "F3 inline 100": target_sections([read_line(f3_lines(data, work)[100][0])], 128),
            "GSB crossline 2600": target_sections([read_line(gsb / "gsb_crl_2600.sgy")])}
    ref = {layer: layer_stats(w, sets["generated, faulted"], {}, layer)[1] for layer in LAYERS[::2]}
    print(" " * 22 + "".join(f"{layer:>13s}" for layer in LAYERS[::2]) + "   p > 0.5")
    for name, secs in sets.items():
        ratio = [float((layer_stats(w, secs, {}, layer)[1] / ref[layer]).mean()) for layer in LAYERS[::2]]
        with torch.no_grad():
            p = np.concatenate([torch.sigmoid(forward(w, torch.from_numpy(_pad8(s)[None, None].copy()), {}))
                                .numpy().ravel() for s in secs])
        print(f"{name:22s}" + "".join(f"{v:13.3f}" for v in ratio) + f"   {np.mean(p > 0.5):.4f}", flush=True)


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
                    help="'identity' or BLOCKS:SHRINK (e.g. 7:1 full AdaBN, 2:1 the first two blocks, 7:0.5)")
    ap.add_argument("--folds", nargs="+", type=int, default=None)
    ap.add_argument("--no-default", action="store_true")
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
    w = {k: torch.from_numpy(v) for k, v in shipped.items()}
    src = source_sections()
    source_stats = {layer: layer_stats(w, src, {}, layer) for layer in LAYERS}
    print(f"source statistics: {len(src)} generated sections, {time.process_time() - t0:.1f} CPU s", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        if a.table:
            return statistics_table(shipped, data, work)
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
            c0 = time.process_time()
            tgt = target_sections([read_line(source_segy)], a.tile)
            print(f"{a.survey} statistics of line {source}: {len(tgt)} sections (tile {a.tile})", flush=True)
            for variant in a.variants:
                if variant == "identity":
                    weights, gains = shipped, {}
                else:
                    k, s = variant.rstrip("p").split(":")
                    ref = source_stats
                    if variant.endswith("p"):  # the source mixed to the target's estimated share of faults
                        ref, mix = prior_matched_stats(w, tgt)
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
