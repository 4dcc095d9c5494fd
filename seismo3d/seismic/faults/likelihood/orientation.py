"""Fault strike and dip from the structure tensor of a fault likelihood: the orientation the voting and the skins
need, of the learned likelihood (:mod:`~seismo3d.seismic.faults.likelihood.learned`), whose network gives a
probability only.

The likelihood changes fastest across a fault: the fault normal at each sample is the eigenvector of the largest
eigenvalue of the Gaussian-smoothed outer product of the likelihood's gradient (van Vliet and Verbeek 1995), in
closed form (:func:`seismo3d.seismic._kernels.eig3`). In a cube the tensor is smoothed along the samples first and
then kept, smoothed across the traces and eigen-decomposed on every ``sample_step``-th sample only, each strike and dip
held over the samples up to the next (the smoothing leaves the tensor little to change over a sample or two; a block
of a cube never splits its traces, so this is the same in a block as in the cube). A block of a cube gets the whole
cube's bits at its core (``core``), so a run by blocks and a run in memory give the same strike and dip.

Strike and dip are computed only where the likelihood is at or above a ``floor`` (NaN elsewhere): the tensor is
smoothed whole (it needs the neighbours), then eigen-decomposed at the kept samples that hold a sample at or above
the floor only, the same bits as every sample's there.
"""

from __future__ import annotations

import numba as nb
import numpy as np
from scipy import ndimage as ndi

from ...._progress import progress_within
from ...._threads import run_threads
from ....errors import InputError
from ... import _kernels

__all__ = ["orientation_from_likelihood"]

# the tensor's Gaussian passes: truncated at 4 sigma, edges mirrored (scipy's defaults), summed in float32; the pass
# along the samples by slabs of inlines
_PASSES = dict(truncate=4.0, mode="reflect")
_SLAB = 16

# the stages reported within the step that runs a block in memory (seismo3d._progress.progress_within); in a cube
# the strike and dip are made with the normals, chunk by chunk, and the last stage holds them over the samples between
_STAGES = ("gradient", "structure tensor", "fault normals", "strike and dip")


def _normals_to_strike_dip(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Strike and dip (degrees, conventions of the fault likelihood) of (..., ndim) normals of either sign."""
    flip = normals[..., -1] < 0

    def turned(k):  # component k of the normals turned to nz >= 0, one component at a time (not the whole copy)
        c = np.array(normals[..., k])
        return np.negative(c, out=c, where=flip)

    dip = np.degrees(np.arccos(np.clip(turned(-1), 0.0, 1.0)))
    if normals.shape[-1] == 2:
        strike = np.where(turned(0) >= 0, 90.0, 270.0)
    else:
        strike = np.degrees(np.arctan2(turned(0), -turned(1))) % 360.0
    return strike.astype(np.float32), np.maximum(dip, 1e-3).astype(np.float32)


def _gradient(p: np.ndarray, axis: int) -> np.ndarray:
    """``np.gradient(p, axis=axis)`` (central differences inside, one-sided at the ends; the same bits), float32,
    written into one array without numpy's temporaries."""
    out = np.empty(p.shape, np.float32)
    inner, lo, hi = ((slice(None),) * axis + (s,) for s in (slice(1, -1), slice(None, -2), slice(2, None)))
    np.subtract(p[hi], p[lo], out=out[inner])
    np.multiply(out[inner], np.float32(0.5), out=out[inner])  # (f[i + 1] - f[i - 1]) / 2: halving is exact
    for end, a, b in ((0, 1, 0), (-1, -1, -2)):
        at = (slice(None),) * axis
        np.subtract(p[at + (a,)], p[at + (b,)], out=out[at + (end,)])
    return out


def _smoothed_at(x: np.ndarray, sigma: float, core, sample_step: int = 1, work: np.ndarray | None = None
                 ) -> np.ndarray:
    """``ndi.gaussian_filter(x, sigma)`` (truncated at 4 sigma, edges mirrored) at the samples ``core`` (slices of
    the first two axes; None: every trace) and ``::sample_step`` of the last axis, summed in float32 by OpenCV's
    separable filter (:func:`seismo3d.seismic._kernels.gaussian_pass32`): the pass along the samples first, on every
    sample, ``_SLAB`` inlines at a time, then those kept (into ``work``, an array of their shape reused between
    calls, or a new one), then the passes along axes 0 and 1, each on the lines of the traces it is asked for only,
    so a block of a cube (``core`` inside it) gets the bits of the whole cube's."""
    keep = (slice(None), slice(None)) if core is None else tuple(core)
    kept = work if work is not None and work.shape == x[..., ::sample_step].shape else np.empty(
        x[..., ::sample_step].shape, np.float32)
    slab = np.empty((min(_SLAB, x.shape[0]),) + x.shape[1:], np.float32)
    for a in range(0, x.shape[0], _SLAB):  # the samples' pass needs no lines of other inlines
        b = min(a + _SLAB, x.shape[0])
        kept[a:b] = _kernels.gaussian_pass32(x[a:b], x.ndim - 1, sigma, out=slab[:b - a], **_PASSES)[..., ::sample_step]
    x = kept
    for axis in range(x.ndim - 1):
        lo, hi, _ = keep[axis].indices(x.shape[axis])
        x = _kernels.gaussian_pass32(x, axis, sigma, keep=(lo, hi), **_PASSES)
    return x


def orientation_from_likelihood(likelihood: np.ndarray, *, sigma: float = 2.0, core=None,
                                sample_step: int = 1, floor: float = 0.0) -> tuple:
    """Strike and dip of the faults of a likelihood image, from its structure tensor.

    The normal at each sample is the eigenvector of the largest eigenvalue of the Gaussian-smoothed outer product of
    the likelihood's gradient (van Vliet and Verbeek 1995; Hale 2013 uses it on amplitudes), in closed form.

    Parameters
    ----------
    likelihood : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) ndarray
        Fault likelihood.
    sigma : float, optional
        Smoothing of the tensor, samples.
    core : (slice, slice), optional
        A cube's inlines and crosslines whose strike and dip are returned (a block's core inside the region read
        with the smoothing's halo, ``ceil(4 sigma) + 1``, around it): the same bits as the whole array's there, the
        tensor smoothed along the crosslines and samples and eigen-decomposed at ``core``'s traces only.
    sample_step : int, optional
        In a cube: the tensor is eigen-decomposed on every ``sample_step``-th sample (after its smoothing along the
        samples; the smoothing across the traces is on those samples only), and each strike and dip is held over the
        ``sample_step - 1`` samples after it; 1: every sample. A Gaussian of ``sigma`` 2 keeps 0.7 % of the
        amplitude of a period of 4 samples, the shortest that 2 holds. Not used on a 2D image.
    floor : float, optional
        Likelihood below which strike and dip are not computed (NaN there); the tensor is eigen-decomposed only at
        the kept samples whose held samples reach it. 0 (the default): every sample.

    Returns
    -------
    strike_deg, dip_deg : ndarray, float32, the shape of ``likelihood`` (of ``likelihood[core]`` when given)
        Degrees (conventions of :mod:`seismo3d.seismic.faults.likelihood.scan`: strike in [0, 360), dip in (0, 90],
        index space); NaN where the likelihood is below ``floor``, elsewhere the bits of ``floor=0``.

    Raises
    ------
    InputError
        ``core`` is given for a 2D image, ``sample_step`` is not an integer >= 1, or ``floor`` is not in [0, 1].

    References
    ----------
    L. J. van Vliet and P. W. Verbeek, "Estimators for orientation and anisotropy in digitized images", ASCI'95,
    442-450, 1995. O. K. Smith, "Eigenvalues of a symmetric 3 x 3 matrix", Communications of the ACM 4(4), 168,
    1961, doi:10.1145/355578.366316.
    """
    p = np.asarray(likelihood, dtype=np.float32)
    if core is not None and p.ndim != 3:
        raise InputError("orientation_from_likelihood: core is for a cube's (rows, cols); got a 2D image")
    if isinstance(sample_step, bool) or int(sample_step) != sample_step or sample_step < 1:
        raise InputError(f"orientation_from_likelihood: sample_step must be an integer >= 1; got {sample_step!r}")
    if not 0.0 <= float(floor) <= 1.0:
        raise InputError(f"orientation_from_likelihood: floor must be a likelihood in [0, 1]; got {floor!r}")
    with progress_within(len(_STAGES), unit="stage") as stages:  # reported in a run in memory only
        stages.start(_STAGES[0])
        grads = np.gradient(p) if min(p.shape) < 3 else [_gradient(p, axis) for axis in range(p.ndim)]
        stages.advance()
        nd = p.ndim
        pairs, comps = [(a, b) for a in range(nd) for b in range(a, nd)], {}
        step = int(sample_step) if nd == 3 else 1

        def smooth(t: int, n: int) -> None:  # the filters release the GIL: the components on the cores at once
            product = np.empty(p.shape, np.float32)  # each thread's product and kept samples, reused
            work = None if nd == 2 else np.empty(p[..., ::step].shape, np.float32)
            for a, b in pairs[t::n]:
                np.multiply(grads[a], grads[b], out=product)
                comps[a, b] = (ndi.gaussian_filter(product, sigma) if nd == 2
                               else _smoothed_at(product, sigma, core, step, work))

        stages.start(_STAGES[1])
        run_threads(smooth, min(nb.get_num_threads(), len(pairs)))
        stages.advance()
        del grads
        stages.start(_STAGES[2])
        below = _below_floor(p if core is None or nd == 2 else p[tuple(core)], float(floor))
        if nd == 2:
            normals = _normals(comps)
            del comps
            strike, dip = _normals_to_strike_dip(normals)
        else:  # strike and dip of each chunk of normals as it is decomposed: no cube of normals, nor temporaries
            strike, dip = _strike_dip_of_tensors(comps, _skipped(below, step))
            del comps
        stages.advance()
        stages.start(_STAGES[3])
        if step > 1:  # each held over the samples up to the next computed one
            strike, dip = (_held(a, step, p.shape[-1]) for a in (strike, dip))
        if below is not None:
            strike[below], dip[below] = np.nan, np.nan
        stages.advance()
    return strike, dip


def _below_floor(p: np.ndarray, floor: float):
    """Samples of ``p`` below ``floor`` (bool, ``p``'s shape), or None when there are none to leave out."""
    if floor <= 0.0:
        return None
    below = p < np.float32(floor)
    return below if below.any() else None


def _skipped(below, step: int):
    """The kept samples (every ``step``-th) not to eigen-decompose: those whose held samples are all ``below`` the
    floor; None (every one) when there are none or when they are fewer than half (gathering the others would cost
    more memory than a run by blocks plans for an orientation block, and save little)."""
    if below is None:
        return None
    skip = ~_held_reach(~below, step)
    return skip if np.count_nonzero(skip) > skip.size // 2 else None


def _held_reach(wanted: np.ndarray, step: int) -> np.ndarray:
    """The kept samples (every ``step``-th of the last axis) whose value is held over (:func:`_held`) a sample of
    ``wanted`` (bool, (..., n_samples)): (..., ceil(n_samples / step)) bool."""
    reach = wanted[..., ::step].copy()
    for k in range(1, step):
        held = wanted[..., k::step]
        reach[..., :held.shape[-1]] |= held
    return reach


def _normals(comps: dict) -> np.ndarray:
    """(..., 2) unit normals of a 2D image: the eigenvector of the largest eigenvalue of the smoothed tensor
    ``comps`` (its components by their axes ``(a, b)``, ``a <= b``), in closed form."""
    angle = 0.5 * np.arctan2(2.0 * comps[0, 1], comps[0, 0] - comps[1, 1])  # the largest eigenvalue's vector
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def _strike_dip_of_tensors(comps: dict, skip: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Strike and dip (float32, degrees) of the 3D tensors ``comps`` (components by their axes ``(a, b)``,
    ``a <= b``): each chunk's unit normals (:func:`seismo3d.seismic._kernels.eig3`) rounded to float32 and turned
    into angles (:func:`_normals_to_strike_dip`) while in the processor's cache, on the threads that decompose it.
    ``skip`` (bool, the components' shape): tensors left out, NaN in the result; the others are gathered (``comps``
    emptied as they are), decomposed (each tensor on its own: the same bits) and scattered back."""
    shape = comps[0, 0].shape
    keys = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
    at = None if skip is None else np.flatnonzero(~skip.reshape(-1))
    if at is None:
        strike, dip = np.empty(shape, np.float32), np.empty(shape, np.float32)
        tensors = [comps[k] for k in keys]
        kept_strike, kept_dip = strike.reshape(-1), dip.reshape(-1)
    else:
        strike, dip = np.full(shape, np.nan, np.float32), np.full(shape, np.nan, np.float32)
        tensors = [comps.pop(k).reshape(-1)[at] for k in keys]  # each whole component let go once gathered
        kept_strike, kept_dip = np.empty(at.size, np.float32), np.empty(at.size, np.float32)

    def write(part, vx, vy, vz):
        normals = np.empty((vx.size, 3), np.float32)
        normals[:, 0], normals[:, 1], normals[:, 2] = vx, vy, vz
        kept_strike[part], kept_dip[part] = _normals_to_strike_dip(normals)

    if tensors[0].size:
        _kernels.eig_vectors(*tensors, write)
    if at is not None:
        strike.reshape(-1)[at], dip.reshape(-1)[at] = kept_strike, kept_dip
    return strike, dip


def _held(values: np.ndarray, step: int, n_samples: int) -> np.ndarray:
    """``values`` of every ``step``-th sample held over the ``step - 1`` samples after it: (..., n_samples),
    C-contiguous."""
    out = np.empty(values.shape[:-1] + (n_samples,), values.dtype)
    for k in range(step):
        out[..., k::step] = values[..., :len(range(k, n_samples, step))]
    return out
