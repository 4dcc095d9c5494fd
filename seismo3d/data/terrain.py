"""Generated terrain with known truth, for tests and benchmarks: DEMs with linear scarps, scan pairs cut from a real
LiDAR tile and moved by a known rigid transform, DEM crops moved by a known rotation and shift, and a room mesh with
obstacles for occupancy grids, and occupancy grids of generated rolling terrain for path planning.

Arrays in, arrays out (no file formats): ``seismo3d.terrain`` wraps them into scans and DEMs.

Conventions: grids are north-up (row 0 at the top, rows running south, columns east); an azimuth is a compass
direction in degrees clockwise from north. A lineament's azimuth is taken in [0, 180).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from scipy.special import erf
from scipy.spatial.transform import Rotation

from .._validation import as_points, check_positive
from ..errors import InputError

__all__ = ["Scarp", "ScarpDem", "synthetic_scarp_dem", "ScanPair", "cut_scan_pair", "MovedGrid", "moved_grid",
           "SyntheticRoom", "synthetic_room", "TerrainGrid", "synthetic_occupancy"]


@dataclass(frozen=True)
class Scarp:
    """A straight scarp of a generated DEM.

    Attributes
    ----------
    row0, col0, row1, col1 : float
        End points of the scarp's trace, pixel indices.
    azimuth_deg : float
        Strike of the trace, degrees clockwise from north, in [0, 180).
    height : float
        Largest offset across it (at its middle), metres.
    """

    row0: float
    col0: float
    row1: float
    col1: float
    azimuth_deg: float
    height: float

    @property
    def length_px(self) -> float:
        """Length of the trace, pixels."""
        return float(np.hypot(self.row1 - self.row0, self.col1 - self.col0))


@dataclass(frozen=True)
class ScarpDem:
    """A generated DEM and its scarps.

    Attributes
    ----------
    elevation : (H, W) float64 ndarray
        Heights, metres.
    pixel_size : float
        Square pixel side, metres.
    scarps : tuple of Scarp
    """

    elevation: np.ndarray
    pixel_size: float
    scarps: tuple


def _fractal_surface(shape, rng, beta, relief):
    """Gaussian random surface with a power-law spectrum ``1 / f^beta`` (spectral synthesis), std = relief."""
    h, w = shape
    fy = np.fft.fftfreq(h)[:, None]
    fx = np.fft.rfftfreq(w)[None, :]
    f = np.hypot(fy, fx)
    f[0, 0] = 1.0
    amp = f ** (-beta / 2.0)
    amp[0, 0] = 0.0
    spec = amp * (rng.normal(size=amp.shape) + 1j * rng.normal(size=amp.shape))
    z = np.fft.irfft2(spec, s=shape)
    return relief * (z - z.mean()) / z.std()


def synthetic_scarp_dem(shape=(256, 256), *, n_scarps: int = 8, seed=0, pixel_size: float = 30.0,
                        relief: float = 20.0, beta: float = 4.0, heights=(8.0, 20.0), lengths=(0.25, 0.5),
                        width_px: float = 1.0, min_separation_px: float = 12.0) -> ScarpDem:
    """A DEM of random rolling terrain cut by straight scarps of known position, strike and height.

    The background is a Gaussian random surface with a ``1 / f^beta`` power spectrum (``beta = 4``: rolling hills
    with a smooth, self-affine surface of Hurst exponent 1) and standard deviation ``relief``. Each scarp is a
    dip-slip offset along a straight trace: across it the height steps by ``h * taper(s) * (1 + erf(d / width)) / 2``
    (``d`` the signed distance from the trace, ``s`` the position along it), with a bell-shaped taper
    ``cos(pi s / L)`` that closes the offset at the tips, and the raised block tilting back to zero over a distance
    L / 2 (a back-tilted footwall; the taper keeps its side slopes below ``h pi / L``). Traces are drawn in the
    middle of the grid, at least ``min_separation_px`` apart (no crossings).

    Parameters
    ----------
    shape : (int, int)
        (rows, cols), each >= 64.
    n_scarps : int
        Number of scarps (1-30).
    seed : int or numpy.random.Generator
    pixel_size : float
        Pixel side, metres.
    relief : float
        Standard deviation of the background, metres.
    beta : float
        Spectral exponent of the background.
    heights : (float, float)
        Range of the scarps' largest offsets, metres.
    lengths : (float, float)
        Range of the trace lengths as fractions of the smaller side.
    width_px : float
        Half-width of the scarp's face, pixels.
    min_separation_px : float
        Smallest distance between two traces, pixels.

    Returns
    -------
    ScarpDem

    Raises
    ------
    InputError
        Bad shape or counts, or scarps that cannot be placed apart.

    References
    ----------
    Saupe, D. (1988). Algorithms for random fractals. In The Science of Fractal Images, Springer, 71-136 (spectral
    synthesis). Kim, Y.-S., Sanderson, D. J. (2005). The relationship between displacement and length of faults.
    Earth-Sci. Rev. 68, 317-334. doi:10.1016/j.earscirev.2004.06.003 (offset largest mid-trace, closing at the tips)
    """
    h, w = (int(v) for v in shape)
    if h < 64 or w < 64:
        raise InputError(f"shape must be at least (64, 64); got {shape}")
    if not 1 <= int(n_scarps) <= 30:
        raise InputError(f"n_scarps must be in [1, 30]; got {n_scarps}")
    check_positive(pixel_size, "pixel_size")
    rng = np.random.default_rng(seed)
    z = _fractal_surface((h, w), rng, float(beta), float(relief))
    rows, cols = np.mgrid[0:h, 0:w].astype(np.float64)
    scarps = []
    side = min(h, w)
    for _ in range(int(n_scarps)):
        for _attempt in range(500):
            length = rng.uniform(*lengths) * side
            az = rng.uniform(0.0, 180.0)
            centre = np.array([rng.uniform(0.2, 0.8) * h, rng.uniform(0.2, 0.8) * w])
            direction = np.array([-np.cos(np.radians(az)), np.sin(np.radians(az))])  # (d row, d col) of the strike
            a, b = centre - 0.5 * length * direction, centre + 0.5 * length * direction
            if min(a[0], b[0]) < 8 or max(a[0], b[0]) > h - 9 or min(a[1], b[1]) < 8 or max(a[1], b[1]) > w - 9:
                continue
            if all(_segment_distance(a, b, np.array([s.row0, s.col0]), np.array([s.row1, s.col1]))
                   >= min_separation_px for s in scarps):
                break
        else:
            raise InputError(f"could not place {n_scarps} scarps {min_separation_px} pixels apart in {shape}; "
                             "use fewer or shorter scarps")
        height = rng.uniform(*heights)
        normal = np.array([direction[1], -direction[0]])  # to the right of the strike: the raised block
        d = (rows - centre[0]) * normal[0] + (cols - centre[1]) * normal[1]
        s = (rows - centre[0]) * direction[0] + (cols - centre[1]) * direction[1]
        taper = np.where(np.abs(s) < 0.5 * length, np.cos(np.pi * s / length), 0.0)
        step = 0.5 * (1.0 + erf(d / float(width_px)))
        tilt = np.exp(-2.0 * np.clip(d, 0.0, None) / length)
        z += height * taper * step * tilt
        scarps.append(Scarp(float(a[0]), float(a[1]), float(b[0]), float(b[1]), float(az % 180.0), float(height)))
    return ScarpDem(z, float(pixel_size), tuple(scarps))


def _segment_distance(a, b, c, d) -> float:
    """Smallest distance between segments ab and cd (2D); 0 when they cross."""
    def cross(o, p, q):
        """z of (p - o) x (q - o): the side of line o-p that q lies on."""
        return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])

    if cross(a, b, c) * cross(a, b, d) < 0 and cross(c, d, a) * cross(c, d, b) < 0:
        return 0.0

    def point_segment(p, u, v):
        """Distance from point p to segment uv."""
        t = np.clip(np.dot(p - u, v - u) / max(np.dot(v - u, v - u), 1e-300), 0.0, 1.0)
        return float(np.linalg.norm(p - (u + t * (v - u))))

    return min(point_segment(a, c, d), point_segment(b, c, d), point_segment(c, a, b), point_segment(d, a, b))


@dataclass(frozen=True)
class ScanPair:
    """Two overlapping scans cut from one point cloud, the source moved by a known rigid transform.

    Attributes
    ----------
    source : (N, 3) float64 ndarray
        The moved scan (with noise), in the cloud's coordinates.
    target : (M, 3) float64 ndarray
        The fixed scan.
    transform : (4, 4) float64 ndarray
        The truth: maps ``source`` onto ``target`` (the inverse of the motion applied).
    motion : (4, 4) float64 ndarray
        The motion applied to the source part (a rotation about an axis through its centroid, then a translation).
    """

    source: np.ndarray
    target: np.ndarray
    transform: np.ndarray
    motion: np.ndarray


def cut_scan_pair(points, *, angle_deg: float = 20.0, tilt_deg: float = 2.0, translation=(40.0, -30.0, 0.0),
                  noise: float = 0.1, overlap: float = 0.3, seed=0) -> ScanPair:
    """Cut a 2.5D point cloud into two overlapping strips along x and move the second by a known rigid transform.

    The target is the points with ``x`` below ``x_min + (1 + overlap) / 2 * extent``, the source those above
    ``x_min + (1 - overlap) / 2 * extent``; the source is rotated by ``angle_deg`` about an axis through its centroid
    tilted ``tilt_deg`` from the vertical towards a random azimuth, translated by ``translation`` and given Gaussian
    noise of standard deviation ``noise`` on each coordinate.

    Parameters
    ----------
    points : (N, 3) array_like
        The cloud (e.g. a LiDAR tile), any unit.
    angle_deg : float
        Rotation angle, degrees.
    tilt_deg : float
        Angle between the rotation axis and the vertical, degrees.
    translation : (3,) array_like
        Translation, the points' unit.
    noise : float
        Standard deviation of the added noise, the points' unit (0 for none).
    overlap : float
        Overlap of the two strips as a fraction of the x extent, in (0, 1).
    seed : int or numpy.random.Generator

    Returns
    -------
    ScanPair

    Raises
    ------
    InputError
        Bad points or options.
    """
    pts = as_points(points, "points", dims=(3,), min_points=10)
    if not 0.0 < float(overlap) < 1.0:
        raise InputError(f"overlap must be in (0, 1); got {overlap!r}")
    check_positive(noise, "noise", allow_zero=True)
    rng = np.random.default_rng(seed)
    x = pts[:, 0]
    lo, extent = x.min(), np.ptp(x)
    target = pts[x < lo + 0.5 * (1.0 + overlap) * extent]
    part = pts[x > lo + 0.5 * (1.0 - overlap) * extent]
    az = rng.uniform(0.0, 2.0 * np.pi)
    tilt = np.radians(float(tilt_deg))
    axis = np.array([np.sin(tilt) * np.cos(az), np.sin(tilt) * np.sin(az), np.cos(tilt)])
    r = Rotation.from_rotvec(axis * np.radians(float(angle_deg))).as_matrix()
    c = part.mean(axis=0)
    motion = np.eye(4)
    motion[:3, :3] = r
    motion[:3, 3] = c - r @ c + np.asarray(translation, dtype=np.float64)
    source = part @ r.T + motion[:3, 3] + rng.normal(scale=float(noise), size=part.shape) * (noise > 0)
    return ScanPair(source, np.ascontiguousarray(target), np.linalg.inv(motion), motion)


@dataclass(frozen=True)
class MovedGrid:
    """A crop of a height grid, rotated about the vertical and shifted by a known amount, and its truth.

    Attributes
    ----------
    elevation : (h, w) float64 ndarray
        The moved crop's heights (NaN where the motion brought in cells from outside the grid).
    row0, col0 : int
        Top-left cell of the crop in the original grid (the moved crop is georeferenced as that crop).
    transform : (4, 4) float64 ndarray
        The truth in metres, x east, y north, z up, about the crop's centre: maps a point of the moved crop onto the
        same terrain point in the original.
    """

    elevation: np.ndarray
    row0: int
    col0: int
    transform: np.ndarray


def moved_grid(elevation, spacing, *, crop, angle_deg: float, shift=(0.0, 0.0), order: int = 3) -> MovedGrid:
    """Cut ``elevation[crop]`` and move its terrain by a rotation about the vertical through its centre and a shift.

    The moved crop keeps the crop's cells (and so its georeferencing), but shows the terrain rotated by
    ``angle_deg`` (counter-clockwise seen from above) and shifted by ``shift`` metres (east, north): cell q shows the
    original terrain at ``R^-1 (q - c - shift) + c``, interpolated with a cubic spline (``order``).

    Parameters
    ----------
    elevation : (H, W) array_like
        Heights (NaN = nodata), metres.
    spacing : (dy, dx)
        Cell height and width in metres (north-up grid).
    crop : (slice, slice)
        The crop (unit-step slices).
    angle_deg : float
        Rotation, degrees counter-clockwise seen from above.
    shift : (float, float)
        Shift east and north, metres.
    order : int
        Spline order of the interpolation.

    Returns
    -------
    MovedGrid

    Raises
    ------
    InputError
        Bad grid, spacing or crop.
    """
    z = np.asarray(elevation, dtype=np.float64)
    if z.ndim != 2:
        raise InputError(f"elevation must be 2D; got shape {z.shape}")
    dy, dx = (check_positive(v, "spacing") for v in spacing)
    rows, cols = crop
    r0, c0 = rows.start or 0, cols.start or 0
    h = len(range(*rows.indices(z.shape[0])))
    w = len(range(*cols.indices(z.shape[1])))
    if h < 8 or w < 8:
        raise InputError(f"the crop must be at least 8 x 8 cells; got {h} x {w}")
    th = np.radians(float(angle_deg))
    rot = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    sx, sy = (float(v) for v in shift)
    rr, cc = np.mgrid[0:h, 0:w].astype(np.float64)
    # metric position in the crop about its centre (x east, y north)
    qx = (cc - (w - 1) / 2.0) * dx
    qy = -(rr - (h - 1) / 2.0) * dy
    px = rot[0, 0] * (qx - sx) + rot[1, 0] * (qy - sy)  # R^T (q - shift)
    py = rot[0, 1] * (qx - sx) + rot[1, 1] * (qy - sy)
    src_c = c0 + (w - 1) / 2.0 + px / dx
    src_r = r0 + (h - 1) / 2.0 - py / dy
    valid = np.isfinite(z)
    filled = np.where(valid, z, np.nanmean(z))
    out = ndimage.map_coordinates(filled, [src_r, src_c], order=int(order), mode="nearest")
    inside = (src_r >= 0) & (src_r <= z.shape[0] - 1) & (src_c >= 0) & (src_c <= z.shape[1] - 1)
    support = ndimage.map_coordinates(valid.astype(np.float64), [src_r, src_c], order=1, mode="constant")
    out[~inside | (support < 0.999)] = np.nan
    motion = np.eye(4)
    motion[:2, :2] = rot
    motion[:2, 3] = (sx, sy)
    return MovedGrid(out, int(r0), int(c0), np.linalg.inv(motion))


@dataclass(frozen=True)
class SyntheticRoom:
    """A room for occupancy-grid tests: a marching-cubes mesh, camera poses, and what stands where.

    The frame is a camera's (x right, y DOWN, z forward); the floor is the plane ``y = floor_y``. The room spans
    x in [0, 3] m and z in [0, 2] m inside walls 1 m high; a box 0.6 m high stands across most of its depth
    (x 1.0-1.3 m, z 0.2-1.6 m), so a robot must go around its end; a table (x 1.8-2.4 m, z 0.6-1.4 m) has its top
    0.72-0.76 m above the floor on four 5 cm legs, so a robot lower than that passes under it.

    Attributes
    ----------
    vertices : (N, 3) float64 ndarray
        Mesh vertices, metres.
    faces : (M, 3) int64 ndarray
        Triangles (vertex indices).
    camera_poses : (K, 4, 4) float64 ndarray
        Camera-to-world poses 1.2 m above the floor, pitched 15 degrees down.
    floor_y : float
    """

    vertices: np.ndarray
    faces: np.ndarray
    camera_poses: np.ndarray
    floor_y: float

    box = dict(x=(1.0, 1.3), z=(0.2, 1.6), height=0.6)
    table = dict(x=(1.8, 2.4), z=(0.6, 1.4), top=(0.72, 0.76), leg=0.05)
    extent = dict(x=(0.0, 3.0), z=(0.0, 2.0), wall=0.05, wall_height=1.0)

    @classmethod
    def solid(cls, x, h, z):
        """Indicator of the solid parts at points (x, height above the floor, z), metres (broadcast)."""
        x, h, z = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in (x, h, z)))
        e, b, t = cls.extent, cls.box, cls.table
        walls = ((x < e["x"][0] + e["wall"]) | (x > e["x"][1] - e["wall"]) | (z < e["z"][0] + e["wall"])
                 | (z > e["z"][1] - e["wall"])) & (h < e["wall_height"])
        box = (x >= b["x"][0]) & (x <= b["x"][1]) & (z >= b["z"][0]) & (z <= b["z"][1]) & (h <= b["height"])
        top = (x >= t["x"][0]) & (x <= t["x"][1]) & (z >= t["z"][0]) & (z <= t["z"][1]) & (h >= t["top"][0]) & \
              (h <= t["top"][1])
        legs = np.zeros(x.shape, bool)
        half = t["leg"] / 2
        for cx in (t["x"][0] + half, t["x"][1] - half):
            for cz in (t["z"][0] + half, t["z"][1] - half):
                legs |= (np.abs(x - cx) <= half) & (np.abs(z - cz) <= half) & (h <= t["top"][1])
        return (h < 0) | walls | box | top | legs

    @classmethod
    def obstacle(cls, x, z, *, step_height: float = 0.05, robot_height: float = 0.5):
        """Truth of an occupancy grid: does something stand between ``step_height`` and ``robot_height`` above the
        floor at (x, z)?"""
        heights = np.linspace(step_height + 0.01, robot_height, 12)
        return np.any([cls.solid(x, np.full(np.shape(x), h), z) for h in heights], axis=0)


def synthetic_room(*, voxel: float = 0.02, floor_y: float = 0.3) -> SyntheticRoom:
    """Build the :class:`SyntheticRoom` mesh: marching cubes of its solid parts on a ``voxel`` grid.

    Parameters
    ----------
    voxel : float
        Grid step, metres (the mesh's vertices are about this far apart).
    floor_y : float
        y of the floor (y points down).

    Returns
    -------
    SyntheticRoom

    References
    ----------
    Lorensen, W. E., Cline, H. E. (1987). Marching cubes. SIGGRAPH '87, 163-169 (scikit-image's
    ``measure.marching_cubes``, Lewiner et al. 2003).
    """
    from skimage.measure import marching_cubes

    step = check_positive(voxel, "voxel")
    xs = np.arange(-0.1, 3.1 + step, step)
    hs = np.arange(-0.1, 1.1 + step, step)
    zs = np.arange(-0.1, 2.1 + step, step)
    volume = SyntheticRoom.solid(*np.meshgrid(xs, hs, zs, indexing="ij")).astype(np.float32)
    verts, faces, _, _ = marching_cubes(volume, 0.5, spacing=(step, step, step))
    verts = verts + [xs[0], hs[0], zs[0]]
    vertices = np.column_stack([verts[:, 0], floor_y - verts[:, 1], verts[:, 2]])  # height up -> y down
    poses = []
    for x, yaw in ((0.4, 0.0), (1.0, 20.0), (2.0, 60.0), (2.6, 90.0)):
        pose = np.eye(4)
        pose[:3, :3] = Rotation.from_euler("yx", [yaw, -15.0], degrees=True).as_matrix()
        pose[:3, 3] = (x, floor_y - 1.2, 1.0)
        poses.append(pose)
    return SyntheticRoom(vertices, faces.astype(np.int64), np.array(poses), float(floor_y))


@dataclass(frozen=True)
class TerrainGrid:
    """An occupancy grid of generated terrain and a query across it.

    Attributes
    ----------
    free : (H, W) bool ndarray
        True where the slope is gentle enough to drive.
    spacing : (float, float)
        (dy, dx): cell height and width, metres.
    start, goal : (int, int)
        (row, col) of the free cells of the largest 8-connected free region nearest to the top-left and the
        bottom-right corners.
    """

    free: np.ndarray
    spacing: tuple
    start: tuple
    goal: tuple


def synthetic_occupancy(shape=(400, 400), *, spacing=(30.0, 25.0), free_fraction: float = 0.7, beta: float = 4.0,
                        seed=0) -> TerrainGrid:
    """Occupancy grid of rolling terrain: a Gaussian random surface with a ``1 / f^beta`` power spectrum (as in
    :func:`synthetic_scarp_dem`), blocked where its slope (central differences) is among the steepest
    ``1 - free_fraction`` of the cells. With ``beta = 4`` the blocked cells gather into winding ridges and patches
    with narrow gaps between them, as a slope limit does on a real DEM.

    Parameters
    ----------
    shape : (int, int)
        (rows, cols), each >= 16.
    spacing : (dy, dx)
        Cell height and width, metres.
    free_fraction : float
        Fraction of cells left traversable, in (0, 1).
    beta : float
        Spectral exponent of the surface (larger: smoother, fewer and larger obstacles).
    seed : int or numpy.random.Generator

    Returns
    -------
    TerrainGrid

    Raises
    ------
    InputError
        A shape below 16 x 16 or a fraction outside (0, 1).

    References
    ----------
    Saupe, D. (1988). Algorithms for random fractals. In The Science of Fractal Images, Springer, 71-136.
    """
    h, w = (int(v) for v in shape)
    if h < 16 or w < 16:
        raise InputError(f"shape must be at least (16, 16); got {shape}")
    if not 0.0 < free_fraction < 1.0:
        raise InputError(f"free_fraction must be in (0, 1); got {free_fraction}")
    dy, dx = (check_positive(float(v), "spacing") for v in spacing)
    z = _fractal_surface((h, w), np.random.default_rng(seed), float(beta), 20.0)
    grad_r, grad_c = np.gradient(z, dy, dx)
    slope = np.hypot(grad_r, grad_c)
    free = slope <= np.quantile(slope, free_fraction)
    labels, n = ndimage.label(free, structure=np.ones((3, 3), bool))
    largest = labels == 1 + int(np.argmax(ndimage.sum(free, labels, index=np.arange(1, n + 1))))
    cells = np.argwhere(largest)
    start = cells[np.argmin(cells.sum(axis=1))]
    goal = cells[np.argmin((h - 1 - cells[:, 0]) + (w - 1 - cells[:, 1]))]
    return TerrainGrid(free, (dy, dx), tuple(int(v) for v in start), tuple(int(v) for v in goal))
