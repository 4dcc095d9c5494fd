"""Seismic attributes: reflector orientation, semblance and discontinuity.

Every function takes a 3D cube ``(n_inlines, n_xlines, n_samples)`` or a 2D section ``(n_traces, n_samples)``; the
last axis is always the sample (two-way time or depth, increasing downward). Distances are in samples and traces
(index space: one trace spacing and one sample interval both count as 1).

The methods:

- :func:`structure_tensor_orientation`: reflector normals, slopes and planarity from the eigen-decomposition of the
  smoothed gradient outer product (the structure tensor; van Vliet & Verbeek 1995, Fehmers & Hoecker 2003).
- :func:`semblance`: the ratio of the energy of the summed traces to the summed energy of the traces in a window of
  neighbouring traces (Marfurt et al. 1998), optionally following reflector slopes (structure-oriented semblance,
  Hale 2009).
- :func:`eigen_coherence`: the share of the window's energy in the first principal component of its traces, the
  largest eigenvalue of the trace covariance matrix divided by its trace (Gersztenkorn & Marfurt 1999).
- :func:`discontinuity`: one minus either coherence, high at faults and other lateral breaks of reflectors.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from .._validation import as_seismic, as_sigma_pair, check_choice, check_positive
from ..errors import InputError
from . import _kernels

__all__ = [
    "ReflectorOrientation",
    "structure_tensor_orientation",
    "structure_tensor_slopes",
    "section_slopes",
    "structure_tensor_halo",
    "semblance",
    "eigen_coherence",
    "discontinuity",
]

# --------------------------------------------------------------------------------------------------------------------
# structure tensor


@dataclass(frozen=True, eq=False)
class ReflectorOrientation:
    """Local reflector orientation from the structure tensor.

    Attributes
    ----------
    normals : (*shape, ndim) float32 ndarray
        Unit reflector normals in index space (components along inline, [xline,] sample), with a non-negative
        sample component (pointing down).
    slopes : (ndim - 1, *shape) float32 ndarray
        Reflector slopes in samples per trace: ``slopes[0]`` along the inline axis (axis 0, the trace axis of a 2D
        section), ``slopes[1]`` along the crossline axis (3D only). ``slope_k = -normal_k / normal_sample``, clipped
        to +-5 samples per trace.
    planarity : shape float32 ndarray
        ``(l1 - l2) / l1`` in [0, 1] from the tensor eigenvalues ``l1 >= l2 >= l3``: near 1 on clean planar
        reflectors (linear ones in 2D), low at faults, noise and chaotic zones.
    """

    normals: np.ndarray
    slopes: np.ndarray
    planarity: np.ndarray

    @property
    def dip_deg(self) -> np.ndarray:
        """Reflector dip in degrees in index space, the angle between the normal and the sample axis."""
        return np.degrees(np.arccos(np.clip(self.normals[..., -1], 0.0, 1.0))).astype(np.float32)


def structure_tensor_orientation(data, *, sigma_gradient=1.0, sigma_tensor=(2.0, 6.0)) -> ReflectorOrientation:
    """Reflector normals, slopes and planarity from the structure tensor.

    The gradient ``g`` is taken with Gaussian derivative filters of width ``sigma_gradient``; the tensor
    ``T = G_sigma * (g g^T)`` is smoothed with a Gaussian of ``sigma_tensor`` (lateral, vertical); its largest
    eigenvector is the reflector normal ``n``, from which the slopes are ``p_k = -n_k / n_sample``.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes; the last axis is the sample axis. Converted to float32. Must be finite.
    sigma_gradient : float, optional
        Width of the Gaussian derivative filters, in samples (and traces).
    sigma_tensor : float or (float, float), optional
        Width of the Gaussian that smooths the tensor: (lateral in traces, vertical in samples). A larger vertical
        than lateral width keeps slopes sharp across faults while averaging along each trace (as Hale's slope
        finder does).

    Returns
    -------
    ReflectorOrientation
        ``normals (*shape, ndim) float32``, ``slopes (ndim - 1, *shape) float32`` in samples per trace and
        ``planarity (*shape) float32`` in [0, 1].

    Raises
    ------
    InputError
        If ``data`` is not a finite 2D or 3D numeric array with at least 3 samples per axis, or a width is not > 0.

    References
    ----------
    .. [1] L. J. van Vliet and P. W. Verbeek, "Estimators for orientation and anisotropy in digitized images",
       ASCI 1995.
    .. [2] G. C. Fehmers and C. F. W. Hoecker, "Fast structural interpretation with structure-oriented filtering",
       Geophysics 68(4), 2003, doi:10.1190/1.1598121.
    .. [3] D. Hale, "Structure-oriented smoothing and semblance", CWP Report 635, 2009.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(64.0)
    >>> section = np.sin(0.5 * (t[None, :] - 0.3 * np.arange(40.0)[:, None]))   # reflectors dipping 0.3
    >>> o = structure_tensor_orientation(section)
    >>> round(float(np.median(o.slopes[0])), 2)
    0.3
    """
    arr = as_seismic(data)
    check_positive(sigma_gradient, "sigma_gradient")
    sig_t = as_sigma_pair(sigma_tensor, "sigma_tensor")
    two_d = arr.ndim == 2
    normals, planarity = _kernels.tensor_eig(_kernels.as_3d(arr), float(sigma_gradient), sig_t, two_d)
    p0, p1 = _kernels.slopes_from_normals(normals)
    if two_d:
        normals = normals[:, 0, :, :][..., [0, 2]]
        slopes = p0[None, :, 0, :]
        planarity = planarity[:, 0, :]
    else:
        slopes = np.stack([p0, p1])
    return ReflectorOrientation(np.ascontiguousarray(normals), np.ascontiguousarray(slopes), planarity)


def structure_tensor_slopes(data, *, sigma_gradient=1.0, sigma_tensor=(2.0, 6.0), core=None,
                            float32: bool = False) -> np.ndarray:
    """Reflector slopes from the structure tensor: ``structure_tensor_orientation(data).slopes`` bit for bit, without
    the normals and planarity (about half the time on a 110 x 110 x 500 block, two thirds on 400 x 400 x 500).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes; the last axis is the sample axis. Converted to float32. Must be finite.
    sigma_gradient, sigma_tensor : float, optional
        As in :func:`structure_tensor_orientation` (samples and traces).
    core : (slice, slice), optional
        A cube's inlines and crosslines whose slopes are returned, e.g. a block's core inside the region read
        with :func:`structure_tensor_halo` around it: each smoothing pass keeps the lines its later passes read,
        the tensor's at ``core`` only, eigen-decomposed there (1.1 against 1.5 CPU s, 64^2 of 82^2 traces), the
        same bits as ``structure_tensor_slopes(data)[:, rows, cols]``.
    float32 : bool, optional
        The tensor's Gaussian passes summed in float32 (OpenCV, a third of the CPU seconds; slopes within float
        rounding of the default's), as the fault surfaces and the throw read them; default: scipy's passes in double
        precision, bit for bit :func:`structure_tensor_orientation`'s.

    Returns
    -------
    (ndim - 1, *data.shape) float32 ndarray
        Slopes along each lateral axis, samples per trace (clipped to +-5), as
        :attr:`ReflectorOrientation.slopes` (of ``core``'s traces when given).

    Raises
    ------
    InputError
        If ``data`` is not a finite 2D / 3D numeric array or a width is not > 0.

    References
    ----------
    As :func:`structure_tensor_orientation`.
    """
    arr = as_seismic(data)
    check_positive(sigma_gradient, "sigma_gradient")
    sig_t = as_sigma_pair(sigma_tensor, "sigma_tensor")
    two_d = arr.ndim == 2
    if core is not None and two_d:
        raise InputError("structure_tensor_slopes: core is for a 3D cube's (rows, cols); got a 2D section")
    p0, p1 = _kernels.reflector_slopes(_kernels.as_3d(arr), two_d, float(sigma_gradient), sig_t,
                                       as_float32_normals=True, core=core, float32=float32)
    if two_d:
        return np.ascontiguousarray(p0[None, :, 0, :])
    return np.stack([p0, p1])


def section_slopes(data, axis: int, *, sigma_gradient=1.0, sigma_tensor=(2.0, 6.0),
                   max_lines: int = 256) -> np.ndarray:
    """Reflector slopes of every 2D section of a cube along one lateral axis: the slopes of
    :func:`structure_tensor_orientation` on each inline (``axis=1``: along the crosslines) or each crossline
    (``axis=0``: along the inlines), all sections at once.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) array_like
        Seismic amplitudes. Converted to float32. Must be finite.
    axis : {0, 1}
        The lateral axis the slopes run along (the sections are the cube's lines along it).
    sigma_gradient, sigma_tensor : float, optional
        As in :func:`structure_tensor_orientation` (traces, samples).
    max_lines : int, optional
        Sections computed together (bounds the memory: 12 bytes per sample of them).

    Returns
    -------
    (n_inlines, n_xlines, n_samples) float32 ndarray
        Slopes along ``axis``, samples per trace (clipped to +-5), equal to ``structure_tensor_orientation(section)
        .slopes[0]`` of each section.

    Raises
    ------
    InputError
        If ``data`` is not a finite 3D numeric array, ``axis`` is not 0 or 1, or a width is not > 0.

    References
    ----------
    As :func:`structure_tensor_orientation` (the 2D tensor filters along ``axis`` and the sample axis only).
    """
    arr = as_seismic(data, min_size=1)
    if arr.ndim != 3:
        raise InputError(f"data must be a cube (n_inlines, n_xlines, n_samples); got shape {arr.shape}")
    if axis not in (0, 1):
        raise InputError(f"axis must be 0 (slopes along the inlines) or 1 (along the crosslines); got {axis!r}")
    check_positive(sigma_gradient, "sigma_gradient")
    sig_t = as_sigma_pair(sigma_tensor, "sigma_tensor")
    lines = arr if axis == 0 else arr.transpose(1, 0, 2)  # (n along the slopes, n sections, n_samples)
    out = np.empty(lines.shape, np.float32)
    for a in range(0, lines.shape[1], max(1, int(max_lines))):
        block = np.ascontiguousarray(lines[:, a:a + max_lines])
        normals, _ = _kernels.tensor_eig(block, float(sigma_gradient), sig_t, True)
        out[:, a:a + max_lines] = _kernels.slopes_from_normals(normals)[0]
    return out if axis == 0 else np.ascontiguousarray(out.transpose(1, 0, 2))


def structure_tensor_halo(sigma_gradient=1.0, sigma_tensor=(2.0, 6.0)) -> tuple[int, int]:
    """Reach of :func:`structure_tensor_orientation`: how far a sample's result depends on the data around it.

    The orientation is a chain of separable Gaussian filters truncated at 3 sigma (``_kernels.gaussian_pass``): along
    each axis one Gaussian (derivative) pass of width ``sigma_gradient`` for the gradient, then one Gaussian pass of
    ``sigma_tensor`` for the tensor. Its value at a sample therefore depends only on the data within the sum of the
    two kernel radii along each axis, and the orientation of a block of a cube equals the whole cube's at every
    sample at least that far from each block side that is not the cube's edge (at the cube's edges both clamp the
    same way, ``scipy.ndimage`` mode ``'nearest'``).

    Parameters
    ----------
    sigma_gradient : float, optional
        As in :func:`structure_tensor_orientation`, samples (and traces).
    sigma_tensor : float or (float, float), optional
        As in :func:`structure_tensor_orientation`: (lateral in traces, vertical in samples).

    Returns
    -------
    (int, int)
        The halo along each lateral axis, in traces, and along the sample axis, in samples.

    Raises
    ------
    InputError
        If a width is not > 0.

    References
    ----------
    .. [1] Dask documentation, "Overlapping computations" (``dask.array.map_overlap``): the halo (ghost cells) a
       block needs for a neighbourhood operation.
    """
    check_positive(sigma_gradient, "sigma_gradient")
    lateral, vertical = as_sigma_pair(sigma_tensor, "sigma_tensor")

    grad = _kernels.gaussian_radius(sigma_gradient)  # its smoothing and derivative passes
    return grad + _kernels.gaussian_radius(lateral), grad + _kernels.gaussian_radius(vertical)


# --------------------------------------------------------------------------------------------------------------------
# semblance and coherence


def _window_args(data, half_traces, half_samples, structure_oriented, sigma_gradient, sigma_tensor):
    arr = as_seismic(data)
    half_traces = int(check_positive(half_traces, "half_traces"))
    half_samples = int(check_positive(half_samples, "half_samples", allow_zero=True))
    two_d = arr.ndim == 2
    f3 = _kernels.as_3d(arr)
    if structure_oriented:
        check_positive(sigma_gradient, "sigma_gradient")
        p0, p1 = _kernels.reflector_slopes(f3, two_d, float(sigma_gradient),
                                           as_sigma_pair(sigma_tensor, "sigma_tensor"))
    else:
        p0 = p1 = np.zeros(f3.shape, dtype=np.float32)
    r1 = 0 if two_d else half_traces
    return arr, f3, p0, p1, half_traces, r1, half_samples


def _semblance3(f3, p0, p1, r0, r1, h):
    num = np.empty(f3.shape, dtype=np.float32)
    den = np.empty(f3.shape, dtype=np.float32)
    _kernels.semblance_num_den(f3, p0, p1, r0, r1, num, den)
    if h > 0:
        num = ndi.uniform_filter1d(num, 2 * h + 1, axis=2, mode="constant")
        den = ndi.uniform_filter1d(den, 2 * h + 1, axis=2, mode="constant")
    tiny = 1e-12 * float(den.mean()) + np.finfo(np.float32).tiny
    s = np.where(den > tiny, num / np.maximum(den, tiny), 1.0)
    return np.clip(s, 0.0, 1.0).astype(np.float32)


def semblance(data, *, half_traces=1, half_samples=4, structure_oriented=True, sigma_gradient=1.0,
              sigma_tensor=(2.0, 6.0)) -> np.ndarray:
    """Semblance of neighbouring traces, plain or along reflectors.

    ``s = sum_t (sum_k f_k(t))^2 / (J sum_t sum_k f_k(t)^2)`` (Marfurt et al. 1998) over the J traces of a
    (2 ``half_traces`` + 1) square of traces (a line in 2D) and 2 ``half_samples`` + 1 samples. With
    ``structure_oriented=True`` trace k is read at ``t + p . d_k`` (linear interpolation), ``p`` the reflector slopes of
    :func:`structure_tensor_orientation` at the centre sample and ``d_k`` the trace offset, so dipping reflectors stay
    coherent (Hale 2009). Traces beyond the edge of the data are left out; windows with no energy get s = 1.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes (last axis = sample). Must be finite.
    half_traces : int, optional
        Half-width of the trace window, in traces (1 gives the usual 3 x 3 traces, 3 traces in 2D).
    half_samples : int, optional
        Half-height of the vertical window, in samples.
    structure_oriented : bool, optional
        Follow the reflector slopes (True) or use flat windows (False, Marfurt's plain semblance at zero dip).
    sigma_gradient, sigma_tensor : float, (float, float), optional
        Widths for the slopes, as in :func:`structure_tensor_orientation` (unused when not structure-oriented).

    Returns
    -------
    (*data.shape) float32 ndarray
        Semblance in [0, 1]; 1 = identical traces.

    Raises
    ------
    InputError
        If ``data`` is not a finite 2D/3D array or a window size is not a positive integer.

    References
    ----------
    .. [1] K. J. Marfurt, R. L. Kirlin, S. L. Farmer and M. S. Bahorich, "3-D seismic attributes using a
       semblance-based coherency algorithm", Geophysics 63(4), 1998, doi:10.1190/1.1444415.
    .. [2] D. Hale, "Structure-oriented smoothing and semblance", CWP Report 635, 2009.
    """
    _, f3, p0, p1, r0, r1, h = _window_args(data, half_traces, half_samples, structure_oriented, sigma_gradient,
                                            sigma_tensor)
    s = _semblance3(f3, p0, p1, r0, r1, h)
    return s[:, 0, :] if np.ndim(data) == 2 else s


def eigen_coherence(data, *, half_traces=1, half_samples=4, structure_oriented=True, sigma_gradient=1.0,
                    sigma_tensor=(2.0, 6.0)) -> np.ndarray:
    """Eigenstructure coherence: the share of the window's energy in its first principal component.

    ``c = lambda_1(C) / trace(C)`` with ``C_kl = sum_t f_k(t) f_l(t)`` the covariance of the J traces of the window
    over 2 ``half_samples`` + 1 samples (Gersztenkorn & Marfurt 1999). Windows as in :func:`semblance`.
    It costs about 4x :func:`semblance` (a J x J eigenproblem per sample; 3.3 vs 0.9 CPU s on a 128^3 cube).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes (last axis = sample). Must be finite.
    half_traces, half_samples, structure_oriented, sigma_gradient, sigma_tensor
        As in :func:`semblance`.

    Returns
    -------
    (*data.shape) float32 ndarray
        Coherence in [0, 1]; 1 = traces equal up to a scale factor.

    Raises
    ------
    InputError
        If ``data`` is not a finite 2D/3D array or a window size is not a positive integer.

    References
    ----------
    .. [1] A. Gersztenkorn and K. J. Marfurt, "Eigenstructure-based coherence computations as an aid to 3-D
       structural and stratigraphic mapping", Geophysics 64(5), 1999, doi:10.1190/1.1444651.
    """
    _, f3, p0, p1, r0, r1, h = _window_args(data, half_traces, half_samples, structure_oriented, sigma_gradient,
                                            sigma_tensor)
    out = np.empty(f3.shape, dtype=np.float32)
    _kernels.eigen_coherence_kernel(f3, p0, p1, r0, r1, h, out)
    return out[:, 0, :] if np.ndim(data) == 2 else out


def discontinuity(data, *, method="semblance", half_traces=1, half_samples=4, structure_oriented=True,
                  sigma_gradient=1.0, sigma_tensor=(2.0, 6.0)) -> np.ndarray:
    """Discontinuity = 1 - coherence: high at faults and other lateral breaks of reflectors.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes (last axis = sample). Must be finite.
    method : {'semblance', 'eigen'}, optional
        ``'semblance'``: 1 - :func:`semblance`; ``'eigen'``: 1 - :func:`eigen_coherence`.
    half_traces, half_samples, structure_oriented, sigma_gradient, sigma_tensor
        As in :func:`semblance`.

    Returns
    -------
    (*data.shape) float32 ndarray
        Discontinuity in [0, 1].

    Raises
    ------
    InputError
        On bad input or an unknown ``method``.

    References
    ----------
    .. [1] K. J. Marfurt et al., Geophysics 63(4), 1998, doi:10.1190/1.1444415.
    .. [2] A. Gersztenkorn and K. J. Marfurt, Geophysics 64(5), 1999, doi:10.1190/1.1444651.
    """
    check_choice(method, "method", {"semblance", "eigen"})
    fn = semblance if method == "semblance" else eigen_coherence
    c = fn(data, half_traces=half_traces, half_samples=half_samples, structure_oriented=structure_oriented,
           sigma_gradient=sigma_gradient, sigma_tensor=sigma_tensor)
    return (1.0 - c).astype(np.float32)
