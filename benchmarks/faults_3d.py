"""The faults of a real 3D cube: the Parihaka time slices with people's fault outlines, beside the peers.

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/faults_3d.py [--only parihaka] [--check]``

``parihaka``: the 128 consecutive time slices of ``seismic/parihaka_timeslices/parihaka_timeslices_cols174_302.npz``
holding the most fault labels, as a cube (rows as inlines, columns as crosslines, slices as samples, value - 127.5), as
``../shared/tools/parihaka_dev_scores.py`` takes them, traced with :func:`~seismo3d.seismic.trace_faults` and its
defaults (what ``seismo3d faults`` runs). People outlined faults as bands a few traces wide on time slices (map view),
so a traced fault is judged where it crosses each labelled slice:

- bands hit: the share of the fault polygons (connected components of label 1 on a slice) that a traced point
  touches within 2 traces;
- in bands: the share of the traced points on labelled slices within 4 traces of a polygon.

Beside it, in the same run: 1 - semblance (5 x 5 traces x 9 samples) skeletonised slice by slice at its best single
quantile (the best product of the two scores), and FaultNet (Dou et al. 2022, its released TorchScript weights in the
data folder's ``peers/``) when torch is installed: its probability above 0.5 skeletonised slice by slice. The
project keeps another part of the same survey aside; nothing here was tuned on this file.

``--check`` asserts the issue's target (issue 74): at least 0.80 of the bands hit with at least 0.60 of the points in
bands, ahead of the semblance skeleton on both scores; and exits 1 when it is missed. Measured 2026-11-27 on 2 shared
cores: 0.81 / 0.83 (before the blank slices were filled and the slices balanced: 0.00, no fault), semblance
0.56 / 0.57, FaultNet 0.91 / 0.77; 1 min (3.5 min under heavy load).
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
from scipy import ndimage as ndi
from skimage.morphology import skeletonize

from seismo3d.data.registry import fetch
from seismo3d.seismic import trace_faults

from faultnet import NOT_RUN, faultnet_probability, load_faultnet  # benchmarks/faultnet.py: the peer

SECTIONS = ("parihaka",)
PARIHAKA = "seismic/parihaka_timeslices/parihaka_timeslices_cols174_302.npz"
TARGET = (0.80, 0.60)  # bands hit, points in bands (issue 74)


def parihaka_cube(n_slices: int = 128) -> tuple[np.ndarray, np.ndarray, int]:
    """(cube (n_inlines, n_xlines, n_samples) float32, labels (n_samples, n_inlines, n_xlines) uint8, first slice):
    the ``n_slices`` consecutive slices with the most fault labels, as the dev score takes them."""
    z = np.load(fetch(PARIHAKA))
    seis, lab = z["seismic"], z["labels"]
    counts = np.convolve((lab == 1).sum(axis=(1, 2)), np.ones(n_slices), "valid")
    k0 = int(np.argmax(counts))
    cube = np.transpose(seis[k0:k0 + n_slices].astype(np.float32) - 127.5, (1, 2, 0))
    return np.ascontiguousarray(cube), lab[k0:k0 + n_slices], k0


def band_scores(traced: np.ndarray, labels: np.ndarray) -> tuple[float, float, int, int]:
    """(bands hit, points in bands, bands, points) of a traced fault volume (n_inlines, n_xlines, n_samples) bool
    against the labelled slices (see the module)."""
    hit = bands = inside = total = 0
    for s in range(labels.shape[0]):
        if (labels[s] == 255).all():
            continue
        fault = labels[s] == 1
        near = ndi.binary_dilation(fault, iterations=4)
        ours = traced[:, :, s]
        comps, n = ndi.label(fault)
        for c in range(1, n + 1):
            bands += 1
            hit += bool((ours & ndi.binary_dilation(comps == c, iterations=2)).any())
        inside += int((ours & near).sum())
        total += int(ours.sum())
    return hit / max(bands, 1), inside / max(total, 1), bands, total


def traced_volume(faults, shape) -> np.ndarray:
    """The points of the traced faults as a bool volume."""
    out = np.zeros(shape, bool)
    if faults:
        p = np.concatenate([f.points for f in faults])
        out[p[:, 0], p[:, 1], p[:, 2]] = True
    return out


def slice_skeleton(mask: np.ndarray) -> np.ndarray:
    """``mask`` skeletonised on every time slice (faults as lines in map view, as people outlined them)."""
    return np.stack([skeletonize(mask[:, :, s]) for s in range(mask.shape[2])], axis=2)


def semblance_peer(cube: np.ndarray, labels: np.ndarray) -> tuple[float, float, float]:
    """(bands hit, in bands, quantile) of 1 - semblance (5 x 5 traces x 9 samples) skeletonised per slice at its best
    single quantile (``parihaka_dev_scores.py``'s peer)."""
    c = cube.astype(np.float64)
    num = ndi.uniform_filter(ndi.uniform_filter(c, (5, 5, 1)) ** 2, (1, 1, 9))
    den = ndi.uniform_filter(ndi.uniform_filter(c ** 2, (5, 5, 1)), (1, 1, 9)) + 1e-12
    d = 1 - num / den
    best = (0.0, 0.0, 0.0)
    for q in np.linspace(0.80, 0.99, 12):
        hit, inside, _, _ = band_scores(slice_skeleton(d > np.quantile(d, q)), labels)
        if hit * inside > best[0] * best[1]:
            best = (hit, inside, float(q))
    return best


def faultnet_peer(cube: np.ndarray, labels: np.ndarray):
    """(bands hit, in bands) of FaultNet's probability above 0.5 skeletonised per slice, or None without torch."""
    net = load_faultnet()
    if net is None:
        return None
    hit, inside, _, _ = band_scores(slice_skeleton(faultnet_probability(net, cube) > 0.5), labels)
    return hit, inside


def parihaka(check: bool) -> bool:
    cube, labels, k0 = parihaka_cube()
    started = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = trace_faults(cube, progress=False)
    seconds = time.perf_counter() - started
    hit, inside, n_bands, n_points = band_scores(traced_volume(res.faults, cube.shape), labels)
    s_hit, s_inside, q = semblance_peer(cube, labels)
    print(f"Parihaka time slices {k0}-{k0 + cube.shape[2] - 1} of the file ({cube.shape[0]} x {cube.shape[1]} traces, "
          f"{labels.shape[0]} slices, {n_bands} fault bands on the labelled ones)")
    for w in caught:
        print(f"  warning: {str(w.message)[:150]}")
    print(f"  {'method':44s} {'bands hit':>9s} {'in bands':>9s}")
    faults = f"{len(res.faults)} fault{'' if len(res.faults) == 1 else 's'}"
    print(f"  {'seismo3d faults, defaults':44s} {hit:9.2f} {inside:9.2f}   ({faults}, {n_points} "
          f"points on labelled slices, {seconds:.0f} s)")
    print(f"  {f'1-semblance skeleton (best quantile {q:.3f})':44s} {s_hit:9.2f} {s_inside:9.2f}")
    fn = faultnet_peer(cube, labels)
    if fn is None:
        print(f"  {NOT_RUN}")
    else:
        print(f"  {'FaultNet (probability > 0.5, skeleton)':44s} {fn[0]:9.2f} {fn[1]:9.2f}")
    ok = hit >= TARGET[0] and inside >= TARGET[1] and hit > s_hit and inside > s_inside
    if check:
        print(f"  check: >= {TARGET[0]:.2f} of the bands hit, >= {TARGET[1]:.2f} in bands, ahead of the semblance "
              f"skeleton on both: {'passed' if ok else 'FAILED'}")
    return ok


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default=",".join(SECTIONS), help="sections, comma-separated (default: all)")
    ap.add_argument("--check", action="store_true", help="exit 1 when a target is missed")
    args = ap.parse_args(argv)
    chosen = [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = [s for s in chosen if s not in SECTIONS]
    if unknown:
        ap.error(f"unknown section(s) {', '.join(unknown)}; choose from {', '.join(SECTIONS)}")
    ok = all([{"parihaka": parihaka}[s](args.check) for s in chosen])
    return 1 if args.check and not ok else 0


if __name__ == "__main__":
    raise SystemExit(main())
