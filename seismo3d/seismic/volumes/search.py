"""The global start: every candidate linear map scored at every translation at once, on the coarsest level.

For each candidate linear map (map rotation, lateral scales, the vertical scale of the trace spectra), the moving
level is resampled through it onto a grid aligned with the fixed level, and its normalised cross-correlation with the
fixed level is computed for all integer translations at once in the Fourier domain (masked NCC, Padfield 2012: the
footprint of the resampled volume and its dead traces are the mask). The best translation scores the map.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import fft, ndimage as ndi

from .model import corner_distance, transform_corners
from .pyramid import Sampled

__all__ = ["Start", "MaskedNCC", "decimated", "correlation_search", "distinct_starts", "screen_scores"]


@dataclass(frozen=True, eq=False)
class Start:
    """A candidate start: the score of its best translation (see :func:`correlation_search`) and the transform."""

    correlation: float  # Fisher z-score of the masked NCC
    transform: np.ndarray  # (4, 4) moving level index -> fixed level index
    ncc: float = float("nan")  # the masked NCC itself at the best translation


class MaskedNCC:
    """Normalised cross-correlation of the fixed volume with a masked image for every integer shift at once, in the
    Fourier domain (masked NCC, Padfield 2012, eqs. 14-20), in single precision.

    The same quantity as scikit-image's ``phase_cross_correlation(..., reference_mask=, moving_mask=)`` with every
    sample of the fixed volume valid, which returns only the best shift: the search needs every shift's correlation
    and overlap (the best one per map, then a choice among maps), an overlap threshold in samples rather than a
    fraction of the largest overlap, and the fixed volume's transforms reused for every map (real FFTs in single
    precision, three instead of six forward transforms per call); ``benchmarks/volumes.py --only masked_ncc``
    compares the two on the search's own calls.

    Parameters
    ----------
    fixed : (n0, n1, n2) array_like of float
        The fixed volume (every sample valid; dead traces count as their values).

    References
    ----------
    .. [1] D. Padfield, "Masked object registration in the Fourier domain", IEEE Trans. Image Process. 21(5),
       2706-2718, 2012, doi:10.1109/TIP.2011.2181402.
    """

    def __init__(self, fixed):
        self.f = np.asarray(fixed, np.float32)
        self.cache = {}

    def __call__(self, img, mask, min_overlap):
        """Correlation of ``img`` (n0', n1', n2') over ``mask`` (same shape, 0 / 1) with the fixed volume at every
        integer shift: (ncc, origin), ``ncc[k]`` correlating ``fixed[x + k - origin]`` with ``img[x]``
        (``ncc`` of shape ``fixed.shape + img.shape - 1``); -inf where fewer than ``min_overlap`` samples overlap or
        a side is constant."""
        ncc, _, origin = self.with_overlap(img, mask, min_overlap)
        return ncc, origin

    def with_overlap(self, img, mask, min_overlap, spectra=None, *, inside: bool = False):
        """As calling it, with the number of overlapping samples of every shift: (ncc, n, origin). ``spectra``: those
        of :meth:`moving_spectra` for this ``img`` and ``mask`` (reused for several fixed volumes of one shape).
        ``inside``: only the shifts that keep the whole image inside the fixed volume are computed (the others are
        -inf, n 0), by transforms of the fixed volume's size (a circular correlation: no wrap reaches them)."""
        origin = np.array(img.shape) - 1
        full = tuple(a + b - 1 for a, b in zip(self.f.shape, img.shape))
        shape = self._shape(img.shape, inside)
        if shape not in self.cache:
            self.cache[shape] = [fft.rfftn(a, shape) for a in (self.f, self.f * self.f, np.ones_like(self.f))]
        f1, f2, f0 = self.cache[shape]
        g1, g2, g0 = self.moving_spectra(img, mask, inside=inside) if spectra is None else spectra
        # full: every shift, from 0; inside: shifts origin to the fixed volume's end (img.shape - 1 to f.shape - 1)
        crop = tuple(slice(g - 1 if inside else 0, f if inside else m)
                     for f, g, m in zip(self.f.shape, img.shape, full))

        def corr(a, b):  # the data are normalised (mean about 0): no cancellation in single precision below
            return fft.irfftn(a * b, shape)[crop]

        n = np.round(corr(f0, g0))
        nn = np.maximum(n, np.float32(1.0))
        sum_f, sum_f2, sum_m, sum_m2 = corr(f1, g0), corr(f2, g0), corr(f0, g1), corr(f0, g2)
        num = corr(f1, g1) - sum_f * sum_m / nn
        den = np.sqrt(np.maximum(sum_f2 - sum_f ** 2 / nn, 0.0) * np.maximum(sum_m2 - sum_m ** 2 / nn, 0.0))
        ok = (n >= min_overlap) & (den > 1e-4 * nn)
        ncc = np.where(ok, num / np.where(ok, den, np.float32(1.0)), -np.inf)
        if inside:  # back into the full correlation's indices
            ncc_full, n_full = np.full(full, -np.inf, dtype=ncc.dtype), np.zeros(full, dtype=n.dtype)
            ncc_full[crop], n_full[crop] = ncc, n
            ncc, n = ncc_full, n_full
        return ncc, n, origin

    def moving_spectra(self, img, mask, *, inside: bool = False) -> tuple:
        """The three transforms of ``img`` (masked, squared and masked, the mask) :meth:`with_overlap` needs (with
        the same ``inside``), for any fixed volume of this one's shape."""
        flip = (slice(None, None, -1),) * 3
        shape = self._shape(img.shape, inside)
        return tuple(fft.rfftn(a[flip].astype(np.float32), shape) for a in (img * mask, img * img * mask, mask))

    def _shape(self, img_shape, inside: bool = False) -> tuple:
        """The transforms' shape for an image of ``img_shape``: every shift without wrapping (the fixed volume's
        shape for the shifts ``inside`` it), a fast length."""
        if inside and any(g > f for f, g in zip(self.f.shape, img_shape)):
            raise ValueError(f"an image of shape {tuple(img_shape)} fits at no shift inside {self.f.shape}")
        return tuple(fft.next_fast_len(a if inside else a + b - 1, real=True) for a, b in zip(self.f.shape, img_shape))


def _resampled_onto(target: Sampled, source: Sampled, lin):
    """``source`` resampled (linear) through ``lin`` (source index -> target index) onto the target-aligned grid
    covering its footprint: (image, mask of live source samples, grid origin)."""
    foot = lin @ transform_corners(source.shape)[:3]
    g_lo, g_hi = np.floor(foot.min(axis=1)).astype(int), np.ceil(foot.max(axis=1)).astype(int)
    shape = tuple(g_hi - g_lo + 1)
    inv = np.linalg.inv(lin)  # grid point g (from g_lo) -> source index inv (g + g_lo)
    offset = inv @ g_lo
    img = ndi.affine_transform(source.data, inv, offset=offset, output_shape=shape, order=1, mode="constant",
                               cval=0.0)
    if np.any(lin[2, :2]) or np.any(lin[:2, 2]):  # the traces tilted: the live samples resampled in 3D
        live = np.broadcast_to(source.live_weights[:, :, None], source.shape)
        mask = ndi.affine_transform(live, inv, offset=offset, output_shape=shape, order=0, mode="constant",
                                    cval=0.0)
    else:  # map view and traces apart: the live traces in map view times the samples inside (the same values)
        live = ndi.affine_transform(source.live_weights, inv[:2, :2], offset=offset[:2], output_shape=shape[:2],
                                    order=0, mode="constant", cval=0.0)
        inside = ndi.affine_transform(np.ones(source.shape[2], np.float32), inv[2:, 2:], offset=offset[2:],
                                      output_shape=shape[2:], order=0, mode="constant", cval=0.0)
        mask = live[:, :, None] * inside[None, None, :]
    return img * mask, mask, g_lo


def correlation_search(fixed: Sampled, moving: Sampled, linear_maps, min_fraction: float) -> list[Start]:
    """The best translation of each candidate linear map, by masked NCC; best first.

    Parameters
    ----------
    fixed, moving : Sampled
        The coarsest level of each volume; ``moving`` is resampled onto ``fixed``'s grid.
    linear_maps : iterable of (3, 3) ndarray
        Candidate linear parts, moving level index to fixed level index.
    min_fraction : float
        Overlap a translation needs, as a fraction of the smaller volume's live samples (counted in fixed samples).

    Returns
    -------
    list of Start
        One per map with an admissible translation, best first: ranked by the Fisher z-score
        ``sqrt(n / n_min) atanh(ncc)`` of the overlap's ``n`` samples (a high correlation over a small overlap is
        likelier by chance than over a large one), which ``Start.correlation`` holds.
    """
    return sorted((st for st in _scored(fixed, moving, list(linear_maps), min_fraction) if st is not None),
                  key=lambda st: -st.correlation)


def screen_scores(fixed: Sampled, moving: Sampled, linear_maps, min_fraction: float, factors) -> np.ndarray:
    """The scores of :func:`correlation_search` of each map (-inf without an admissible translation), in the maps'
    order, with both levels decimated by ``factors`` (3 ints: inline, crossline, sample; :func:`decimated`): a
    cheaper first scoring that tells which maps to score on the levels themselves."""
    d = np.asarray(factors, dtype=np.float64)
    scored = _scored(decimated(fixed, factors), decimated(moving, factors),
                     [np.diag(1.0 / d) @ lin @ np.diag(d) for lin in linear_maps], min_fraction)
    return np.array([-np.inf if st is None else st.correlation for st in scored])


def _scored(fixed: Sampled, moving: Sampled, linear_maps, min_fraction: float) -> list:
    """Each map's best translation as a Start (None without an admissible one), in the maps' order."""
    shifts = MaskedNCC(fixed.data)
    n_fixed = float(fixed.live.sum()) * fixed.shape[2]
    n_moving = float(moving.live.sum()) * moving.shape[2]
    out = []
    for lin in linear_maps:
        img, mask, g_lo = _resampled_onto(fixed, moving, lin)
        need = max(min_fraction * min(n_fixed, n_moving * abs(np.linalg.det(lin))), 8.0)
        ncc, n, origin = shifts.with_overlap(img, mask, need)
        z = np.sqrt(n / need) * np.arctanh(np.clip(ncc, -0.999, 0.999))
        k = np.unravel_index(int(np.argmax(z)), z.shape)
        if not np.isfinite(z[k]):
            out.append(None)
            continue
        t = np.eye(4)
        t[:3, :3], t[:3, 3] = lin, np.array(k) - origin - g_lo
        out.append(Start(float(z[k]), t, float(ncc[k])))
    return out


def decimated(level: Sampled, factors) -> Sampled:
    """A level decimated by ``factors`` (3 ints) after a Gaussian of ``factor / 2`` along each decimated axis (as
    :func:`~seismo3d.seismic.volumes.pyramid.build_level` decimates)."""
    f = [int(v) for v in factors]
    data = ndi.gaussian_filter(level.data, [0.5 * v if v > 1 else 0.0 for v in f], mode="nearest")
    return Sampled(np.ascontiguousarray(data[::f[0], ::f[1], ::f[2]], dtype=np.float32),
                   np.ascontiguousarray(level.live[::f[0], ::f[1]]), level.factors * np.array(f, dtype=np.float64),
                   level.taper)


def distinct_starts(starts: list[Start], moving_shape, n: int, separation: float) -> list[Start]:
    """The ``n`` best starts whose moving corners lie more than ``separation`` (fixed level samples) from those of
    every better one kept."""
    kept = []
    for s in starts:
        if all(corner_distance(s.transform, k.transform, moving_shape) > separation for k in kept):
            kept.append(s)
        if len(kept) == n:
            break
    return kept
