"""The random geology of a synthetic cube: its planar faults (:class:`FaultPlane`, :func:`draw_faults`) and its
folding (:func:`draw_folding`).

Index-space conventions (axes, strike, dip, normal, throw) and the construction that uses these draws are described in
:mod:`seismo3d.data.synthetic`, which assembles the cube.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FaultPlane", "MIN_THROW", "draw_faults", "draw_folding"]

MIN_THROW = 3.0  # smallest vertical throw of a synthetic fault, samples


@dataclass(frozen=True, eq=False)
class FaultPlane:
    """One planar fault of a synthetic cube, in index space (see :mod:`seismo3d.data.synthetic` for the conventions).

    Attributes
    ----------
    id : int
        Label in ``SyntheticCube.fault_labels`` (1..n_faults, in order of age: 1 is the oldest).
    strike_deg : float
        Degrees from +axis 0 towards +axis 1; the fault dips to the right of it. In 2D 90 or 270.
    dip_deg : float
        Degrees from the horizontal, 55-80.
    point : (d,) float64 ndarray
        A point of the plane (index coordinates, d = 3 or 2) at the time of faulting; younger faults may have moved
        the part of the plane in their hanging wall.
    normal : (d,) float64 ndarray
        Unit normal pointing into the hanging wall.
    throw_samples : float
        Vertical throw at ``point`` (samples).
    throw_gradient : float
        Change of throw per voxel along the strike direction (0 in 2D).
    kind : {'normal', 'reverse'}
    """

    id: int
    strike_deg: float
    dip_deg: float
    point: np.ndarray
    normal: np.ndarray
    throw_samples: float
    throw_gradient: float
    kind: str

    @property
    def strike_vector(self) -> np.ndarray:
        """(d,) float64 unit vector along strike (horizontal); zeros in 2D, where the strike is across the section."""
        phi = np.deg2rad(self.strike_deg)
        return np.array([np.cos(phi), np.sin(phi), 0.0]) if self.point.size == 3 else np.array([0.0, 0.0])

    @property
    def slip_vector(self) -> np.ndarray:
        """(d,) float64 hanging-wall displacement per sample of throw (vertical component +1 for a normal fault)."""
        theta = np.deg2rad(self.dip_deg)
        lateral = self.normal[:-1] / np.sin(theta)  # horizontal dip direction
        v = np.append(lateral / np.tan(theta), 1.0)
        return v if self.kind == "normal" else -v


def _plane_samples(point, normal, lat_shape, nz, n=9):
    """Points of a plane inside the (lateral..., nz) box, on an n^(d-1) grid over the other axes."""
    d = point.size
    ext = np.array(list(lat_shape) + [nz], float) - 1.0
    a = int(np.argmax(np.abs(normal)))
    others = [i for i in range(d) if i != a]
    grids = np.meshgrid(*[np.linspace(0.0, ext[i], n) for i in others], indexing="ij")
    pts = np.zeros((grids[0].size, d))
    for i, g in zip(others, grids):
        pts[:, i] = g.ravel()
    rest = sum((pts[:, i] - point[i]) * normal[i] for i in others)
    pts[:, a] = point[a] - rest / normal[a]
    inside = (pts[:, a] >= 0) & (pts[:, a] <= ext[a])
    return pts[inside]


def draw_faults(rng, n_faults, lat_shape, nz, max_throw, reverse_fraction) -> list:
    """Draw the planar dip-slip faults of a synthetic cube, oldest first (construction step 3 of
    :mod:`seismo3d.data.synthetic`).

    Parameters
    ----------
    rng : numpy.random.Generator
        Consumed in a fixed order, so a seed gives the same faults.
    n_faults : int
        Number of faults (>= 0).
    lat_shape : tuple of int
        Lateral shape: ``(n_inlines, n_xlines)`` for a cube, ``(n_traces,)`` for a section.
    nz : int
        Number of samples.
    max_throw : float
        Largest vertical throw, samples (>= ``MIN_THROW``).
    reverse_fraction : float
        Probability in [0, 1] that a fault is reverse.

    Returns
    -------
    list of FaultPlane
        Ids 1..n_faults; each new fault at least ~12% of the lateral size away from earlier near-parallel ones
        when 100 draws allow it, else the best-separated draw.
    """
    d = len(lat_shape) + 1
    ext = np.array(list(lat_shape) + [nz], float) - 1.0
    min_sep = max(8.0, 0.12 * max(lat_shape))
    faults = []
    for fid in range(1, n_faults + 1):
        best, best_score = None, -np.inf
        for _ in range(100):
            if d == 3:
                phi = rng.uniform(0.0, 360.0)
            else:
                phi = float(rng.choice([90.0, 270.0]))
            theta = rng.uniform(55.0, 80.0)
            point = rng.uniform(0.25, 0.75, size=d) * ext
            p, t = np.deg2rad(phi), np.deg2rad(theta)
            if d == 3:
                dip_dir = np.array([-np.sin(p), np.cos(p)])
            else:
                dip_dir = np.array([-np.sin(p)]).round()
            normal = np.append(np.sin(t) * dip_dir, -np.cos(t))
            score = np.inf
            pts = _plane_samples(point, normal, lat_shape, nz)
            for old in faults:
                angle = np.degrees(np.arccos(min(1.0, abs(float(normal @ old.normal)))))
                if angle >= 30.0:
                    continue
                sd = (pts - old.point) @ old.normal / np.sin(np.deg2rad(old.dip_deg))  # lateral distance
                sep = 0.0 if (sd.min() < 0 < sd.max()) else float(np.abs(sd).min())
                score = min(score, sep)
            if score >= min_sep:
                best = (phi, theta, point, normal)
                break
            if score > best_score:
                best, best_score = (phi, theta, point, normal), score
        phi, theta, point, normal = best
        # throw varies linearly along strike between two values drawn in [3, max_throw] at the cube's extremes
        t_a, t_b = rng.uniform(MIN_THROW, max_throw, size=2)
        kind = "reverse" if rng.random() < reverse_fraction else "normal"
        if d == 3:
            strike = np.array([np.cos(np.deg2rad(phi)), np.sin(np.deg2rad(phi))])
            corners = np.array(np.meshgrid([0, ext[0]], [0, ext[1]], indexing="ij")).reshape(2, -1).T
            u = (corners - point[:2]) @ strike
            u_min, u_max = u.min(), u.max()
            grad = (t_b - t_a) / (u_max - u_min)
            throw0 = t_a - grad * u_min
        else:
            grad, throw0 = 0.0, float(t_a)
        pt = point.copy()
        nm = normal.copy()
        pt.setflags(write=False)
        nm.setflags(write=False)
        faults.append(FaultPlane(id=fid, strike_deg=float(phi), dip_deg=float(theta), point=pt, normal=nm,
                                 throw_samples=float(throw0), throw_gradient=float(grad), kind=kind))
    return faults


def draw_folding(rng, lat_shape, nz, max_dip):
    """Draw the folding of a synthetic cube (construction step 2 of :mod:`seismo3d.data.synthetic`).

    Parameters
    ----------
    rng : numpy.random.Generator
    lat_shape : tuple of int
        Lateral shape: ``(n_inlines, n_xlines)`` for a cube, ``(n_traces,)`` for a section.
    nz : int
        Number of samples.
    max_dip : float
        Steepest reflector dip, degrees (< 45); the folding draws a value in [0.6, 1] * max_dip.

    Returns
    -------
    shift : callable
        ``shift(lat, z)``: the vertical folding shift in samples (array like ``z``, float32 for float32 inputs) at
        lateral index coordinates ``lat`` (a list of arrays, one per lateral axis) and sample coordinate ``z``.
    """
    d_lat = len(lat_shape)
    size = np.array(lat_shape, float)
    n_g = int(rng.integers(3, 7))
    centres = rng.uniform(-0.1, 1.1, size=(n_g, d_lat)) * (size - 1)
    sigmas = rng.uniform(0.12, 0.3, size=n_g) * size.max()
    amps = rng.uniform(-1.0, 1.0, size=n_g)
    plane_dir = rng.normal(size=d_lat)
    plane_dir /= np.linalg.norm(plane_dir)
    plane_slope = rng.uniform(0.0, 0.5)  # relative weight of the planar dip vs the bumps
    dip = rng.uniform(0.6, 1.0) * max_dip

    def gauss(lat):
        # python floats keep float32 coordinate arrays in float32
        g = 0.0
        for c, s, a in zip(centres.tolist(), sigmas.tolist(), amps.tolist()):
            r2 = sum((x - ci) ** 2 for x, ci in zip(lat, c))
            r2 *= -1.0 / (2.0 * s * s)
            g = g + a * np.exp(r2)
        return g

    # scale so the steepest slope on the lateral grid (at the bottom, where folding is strongest) is tan(dip)
    grid = np.meshgrid(*[np.arange(n, dtype=float) for n in lat_shape], indexing="ij")
    g = gauss(grid)
    gg = np.gradient(g) if d_lat > 1 else [np.gradient(g)]
    g_amp = np.sqrt(sum(x ** 2 for x in gg)).max()
    plane_grad = plane_dir * plane_slope
    bottom = [1.5 * x / max(g_amp, 1e-12) + pg for x, pg in zip(gg, plane_grad)]
    steepest = np.sqrt(sum(x ** 2 for x in bottom)).max()
    scale = np.tan(np.deg2rad(dip)) / max(steepest, 1e-12)
    g_scale = scale / max(g_amp, 1e-12)
    p_grad = plane_grad * scale
    mid = (size - 1) / 2.0

    p_grad, mid, g_scale = p_grad.tolist(), mid.tolist(), float(g_scale)

    def shift(lat, z):
        planar = sum(pg * (x - m) for pg, x, m in zip(p_grad, lat, mid))
        return (0.5 + z * (1.0 / nz)) * (g_scale * gauss(lat)) + planar

    return shift
