"""Refinement of the map: a Levenberg-Marquardt maximisation of the two volumes' correlation over its parameters.

The correlation is taken both ways: at samples of the moving volume with the fixed one interpolated through the map,
and at samples of the fixed volume with the moving one interpolated through its inverse. Their sum does not change
when the two volumes swap roles (and the map is inverted), so neither argument order is favoured, and neither
volume's interpolation error (a coarser volume interpolated at finer positions) is trusted alone.

Each way is a zero-normalised cross-correlation written as a residual, ``sqrt(w / W) (v^ - m^)`` with ``v^`` and ``m^``
the weighted zero-mean, unit-variance values of the two volumes (``sum r^2 = 2 (1 - NCC)``), whose Jacobian
includes the derivative of the normalisation; each way is weighted by the inverse of its misfit at the start of the
refinement (the way that interpolates an aliased volume correlates less and leads less); the steps are Gauss-Newton
with Marquardt's damping.

References
----------
.. [1] D. W. Marquardt, "An algorithm for least-squares estimation of nonlinear parameters", J. Soc. Ind. Appl. Math.
   11(2), 431-441, 1963, doi:10.1137/0111030.
.. [2] S. Baker, I. Matthews, "Lucas-Kanade 20 years on: a unifying framework", Int. J. Comput. Vis. 56(3), 221-255,
   2004, doi:10.1023/B:VISI.0000011205.11775.fd.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import check_choice
from .model import Reparam, model_matrix, model_params, point_derivatives, transform_corners
from .pyramid import GRADIENTS, Sampled

WAYS = ("forward", "backward")
ALIASING_POWER = 4  # of the high-frequency content in the way weights (PairCorrelation.weigh_ways)

__all__ = ["PairCorrelation", "Evaluation", "Refined", "refine"]


@dataclass(frozen=True, eq=False)
class Evaluation:
    """The two-way correlation at one parameter vector."""

    residuals: np.ndarray  # (N,)
    jacobian: np.ndarray | None  # (N, n_params); None when not asked for
    correlations: np.ndarray  # (n_ways,): forward (moving samples), backward (fixed samples); NaN without overlap
    overlaps: np.ndarray  # (n_ways,): fraction of each way's points inside the other volume (summed weights)

    @property
    def cost(self) -> float:
        """``sum r^2``: 2 (1 - NCC) per way, times the way's weight."""
        # einsum: OpenBLAS's threaded dot takes 400 times as long on a loaded machine (7.6 ms CPU against 0.02 ms
        # for 40,000 values, 2 cores at load 14)
        return float(np.einsum("n,n->", self.residuals, self.residuals))


def _ncc_residuals(src, samples, dv):
    """Residuals, Jacobian ((N, n); None without ``dv``) and NCC of one way; ``dv`` ((N, n)) the derivatives of the
    sampled values."""
    w, v = samples.weights, samples.values
    total = w.sum()
    m = src - np.sum(w * src) / total
    m /= max(np.sqrt(np.sum(w * m * m) / total), 1e-12)
    vm = v - np.sum(w * v) / total
    sig = max(np.sqrt(np.sum(w * vm * vm) / total), 1e-12)
    vh = vm / sig
    sw = np.sqrt(w / total)
    jac = None
    if dv is not None:
        dvm = dv - np.einsum("n,np->p", w, dv) / total  # einsum: no BLAS threads for these thin products
        dsig = np.einsum("n,np->p", w * vh, dvm) / total
        jac = sw[:, None] * (dvm / sig - vh[:, None] * (dsig / sig)[None, :])
    return sw * (vh - m), jac, float(np.sum(w * vh * m) / total)


class PairCorrelation:
    """The two-way correlation of a fixed and a moving level through the model, as residuals and their Jacobian.

    Parameters
    ----------
    fixed, moving : Sampled
        The two volumes at one level.
    reparam : Reparam
        The model's parameters (affine or rigid) at this level.
    n_points : int
        About this many samples of each volume (a regular subset of the live traces) are correlated.
    min_points : int
        Fewest overlapping points (summed weights) per way; with fewer, the way counts as uncorrelated (NCC 0).
    ways : tuple of {'forward', 'backward'}
        The ways correlated: ``'forward'`` at the moving samples (MOVING onto FIXED), ``'backward'`` at the fixed
        samples (FIXED onto MOVING); both by default.
    gradient : {'central', 'spline'}
        The volumes' gradients in the Jacobian (:meth:`~seismo3d.seismic.volumes.pyramid.Sampled.sample`).

    Raises
    ------
    InputError
        An unknown way or gradient.
    """

    def __init__(self, fixed: Sampled, moving: Sampled, reparam: Reparam, n_points: int, min_points: float = 50.0,
                 ways: tuple = WAYS, gradient: str = "central"):
        self.fixed, self.moving, self.reparam = fixed, moving, reparam
        self.ways = tuple(check_choice(way, "ways", WAYS) for way in ways)
        self.gradient = check_choice(gradient, "gradient", GRADIENTS)
        self.xm, self.vm = moving.points(n_points)
        self.xf, self.vf = fixed.points(n_points)
        self.centre = moving.hi / 2.0
        self.min_points = float(min_points)
        self.way_weights = np.ones(len(self.ways))
        self._cache = (None, None, {})

    def weigh_ways(self, misfits) -> None:
        """Weight each way's residuals by :meth:`way_weights` of its misfit ``1 - NCC`` ((n_ways,), at the start of a
        refinement)."""
        self.way_weights = self.weights_for(misfits)
        self._cache = (self._cache[0], None, self._cache[2])  # the samples hold, the weighted residuals not

    def weights_for(self, misfits) -> np.ndarray:
        """The ways' weights for their misfits ``1 - NCC`` ((n_ways,) array_like; NaN: no overlap): the inverse of
        the misfit and of the ``ALIASING_POWER``-th power of the high-frequency content of the volume the way
        interpolates (:attr:`~seismo3d.seismic.volumes.pyramid.Sampled.high_frequency`: the fixed one for
        ``'forward'``, the moving one for ``'backward'``), normalised to a mean of 1; (n_ways,) float64.

        The two ways are two estimates of one map, and the one that interpolates an aliased volume (coarser bins, or
        resampled without a low-pass) is biased: on the Volve velocity pairs of ``benchmarks/volumes.py``, each way's
        optimum alone is within 0.4 % of the true scales when it interpolates the less aliased volume and up to 7.8 %
        off when it interpolates the other, while the misfits of the two ways differ by less than a factor 2, too
        little to let the unbiased one lead. Swapping the volumes swaps the ways and their weights, so the cost stays
        symmetric."""
        m = np.maximum(np.nan_to_num(np.asarray(misfits, dtype=np.float64), nan=2.0), 1e-4)
        interpolated = {"forward": self.fixed, "backward": self.moving}
        h = np.array([max(interpolated[way].high_frequency, 1e-6) for way in self.ways])
        w = 1.0 / (m * h ** ALIASING_POWER)
        return w * len(w) / w.sum()

    def params(self, t_level) -> np.ndarray:
        """The fitted parameters nearest to a (4, 4) level transform."""
        return self.reparam.start(model_params(t_level, self.centre))

    def transform(self, q) -> np.ndarray:
        """The (4, 4) level transform of the fitted parameters ``q``."""
        return model_matrix(self.reparam.affine(q)[0], self.centre)

    def evaluate(self, q, *, jacobian: bool = True) -> Evaluation:
        """Residuals, Jacobian (None without ``jacobian``: a trial step needs only its cost), correlations and
        overlaps at ``q`` (the last evaluation is cached; its samples serve a Jacobian asked for afterwards)."""
        key = np.asarray(q, dtype=np.float64).tobytes()
        cached_key, cached, samples = self._cache
        if cached_key == key and cached is not None and (cached.jacobian is not None or not jacobian):
            return cached
        if cached_key != key:
            samples = {}
        p, dp = self.reparam.affine(q)
        t = model_matrix(p, self.centre)
        t_inv = np.linalg.inv(t)
        parts = []
        for way in self.ways:
            if way == "forward":  # moving samples, the fixed volume interpolated at their images
                volume, src, x = self.fixed, self.vm, self.xm
                pts = t[:3, :3] @ x + t[:3, 3:]
            else:
                # fixed samples, the moving volume at their pre-images x = A^-1 (y - b) + c,
                # dx/dp = -A^-1 (dA/dp (x - c) + db/dp)
                volume, src = self.moving, self.vf
                pts = x = t_inv[:3, :3] @ self.xf + t_inv[:3, 3:]
            s = samples.get(way) or volume.sample(pts, self.gradient, gradients=jacobian)
            dv = None
            if jacobian:
                if s.gradients is None:
                    s = volume.with_gradients(pts, s, self.gradient)
                grads = s.gradients if way == "forward" else -(t_inv[:3, :3].T @ s.gradients)
                dv = np.einsum("kn,pkn->np", grads, point_derivatives(x, self.centre))
            samples[way] = s
            parts.append((src, s, dv))
        res, jac, corr, over = [], [], [], []
        for src, smp, dv in parts:
            total = float(smp.weights.sum())
            over.append(total / len(src))
            if total < self.min_points:  # too little overlap: uncorrelated, and no direction out of it
                n = len(src)
                res.append(np.full(n, np.sqrt(2.0 / n)))
                jac.append(np.zeros((n, len(q))))
                corr.append(np.nan)
                continue
            # einsum: a thin (N, 8) x (8, n) product, 5 times faster than OpenBLAS's threaded one under load
            r, j, c = _ncc_residuals(src, smp, None if dv is None else np.einsum("np,pq->nq", dv, dp))
            w = np.sqrt(self.way_weights[len(res)])
            res.append(w * r)
            jac.append(None if j is None else w * j)
            corr.append(c)
        out = Evaluation(np.concatenate(res), np.vstack(jac) if jacobian else None, np.array(corr), np.array(over))
        self._cache = (key, out, samples)
        return out


@dataclass(frozen=True, eq=False)
class Refined:
    """Result of :func:`refine` (at the level of its :class:`PairCorrelation`)."""

    transform: np.ndarray  # (4, 4) moving level index -> fixed level index
    correlations: np.ndarray  # (n_ways,) forward, backward
    overlaps: np.ndarray  # (n_ways,) fraction of each way's points inside the other volume
    n_iterations: int
    converged: bool  # the last step moved the corners less than the tolerance

    @property
    def correlation(self) -> float:
        """The mean of the two ways' correlations (-1 when a way has no overlap)."""
        c = np.where(np.isfinite(self.correlations), self.correlations, -1.0)
        return float(c.mean())


def refine(pair: PairCorrelation, t_level, *, max_iterations: int, tolerance: float,
           min_overlap_ratio: float = 0.5) -> Refined:
    """Levenberg-Marquardt steps on the two-way correlation from the (4, 4) level transform ``t_level``, each way
    weighted by the inverse of its misfit there (:meth:`PairCorrelation.weigh_ways`).

    Stops when a step moves no corner of the moving volume by more than ``tolerance`` (level samples), after
    ``max_iterations`` steps, or when no damped step lowers the cost. A step that shrinks either way's overlap below
    ``min_overlap_ratio`` of the start's is refused: a small overlap can correlate by chance.
    """
    q = pair.params(t_level)
    if len(pair.ways) > 1:
        pair.weigh_ways(1.0 - pair.evaluate(q, jacobian=False).correlations)
    ev = pair.evaluate(q)
    floor = min_overlap_ratio * ev.overlaps
    corners = transform_corners(pair.moving.shape)

    def moved(step):  # the largest displacement of a moving corner by a step, level samples
        return np.abs((pair.transform(q + step) - pair.transform(q))[:3] @ corners).max()

    lam, n_it, converged = 1e-3, 0, False
    for n_it in range(1, max_iterations + 1):
        h = ev.jacobian.T @ ev.jacobian
        g = ev.jacobian.T @ ev.residuals
        diag = np.diag(np.diag(h)) + 1e-12 * np.eye(len(q))
        accepted = False
        for _ in range(8):  # Marquardt: raise the damping until a step lowers the cost
            step = -np.linalg.solve(h + lam * diag, g)
            if moved(step) < tolerance:
                converged = True  # the next step would not move the corners: a (local) maximum
                break
            trial = pair.evaluate(q + step, jacobian=False)  # its Jacobian only when the step is taken
            if trial.cost < ev.cost and np.all(trial.overlaps >= floor):
                accepted = True
                lam = max(lam / 3.0, 1e-7)
                break
            lam *= 4.0
        if not accepted:
            converged = converged or lam > 1e2  # damped to a standstill
            break
        move = moved(step)
        q, ev = q + step, pair.evaluate(q + step)
        if move < tolerance:
            converged = True
            break
    return Refined(pair.transform(q), ev.correlations, ev.overlaps, n_it, converged)
