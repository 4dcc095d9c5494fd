"""The degradations of real seismic data, applied to clean generated sections and cubes.

Generated seismic is clean where real data is not; a fault detector trained or tested only on clean data finds
faults in every real artefact. Each function here adds one artefact seen in the data folder's real files, on a 2D
section ``(n_traces, n_samples)`` or a cube ``(n_inlines, n_xlines, n_samples)`` (last axis = sample, downward):

* :func:`add_noise`: white Gaussian noise, plus coherent noise (steeply dipping linear events, like migration
  swings and the crossing streaks of the Volve and Penobscot lines);
* :func:`dim_interval`: a band of samples, or a blob, with much weaker amplitudes (the dim zones of F3);
* :func:`chaotic_interval`: a zone where the layering is replaced by short, randomly dipping reflector segments
  (chaotic facies, salt, gas: the deep F3 and Penobscot zones), without faults;
* :func:`dead_traces`: zeroed traces and a muted top (the blank stripes at the top of the F3 inlines);
* :func:`acquisition_footprint`: an amplitude modulation periodic along an inline or crossline;
* :func:`clip_and_quantise`: amplitude clipping and 8-bit quantisation, optionally with the bilinear resampling of a
  rendered image (the F3 and Penobscot images were 8-bit pictures);
* :func:`degrade`: a random selection of them, the recipe of the training data.

Every function takes a ``numpy.random.Generator`` and returns a new float32 array; none changes its input.

References
----------
Wu, X., Liang, L., Shi, Y., and Fomel, S., 2019, FaultSeg3D: Using synthetic data sets to train an end-to-end
convolutional neural network for 3D seismic fault segmentation: Geophysics, 84(3), IM35-IM45 (noise added to the
training data). doi:10.1190/geo2018-0646.1
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import gaussian_filter, zoom

from ..errors import InputError

__all__ = ["add_noise", "dim_interval", "chaotic_interval", "dead_traces", "acquisition_footprint",
           "clip_and_quantise", "degrade"]


def _check(data) -> np.ndarray:
    arr = np.asarray(data, dtype=np.float32)
    if arr.ndim not in (2, 3):
        raise InputError(f"data must be a 2D section (n_traces, n_samples) or a 3D cube; got shape {arr.shape}")
    return arr


def _grid(shape):
    return np.meshgrid(*[np.arange(n, dtype=np.float32) for n in shape], indexing="ij")


def add_noise(data, rng: np.random.Generator, *, white: float = 0.2, coherent: float = 0.0,
              n_events: int = 20) -> np.ndarray:
    """White Gaussian noise and coherent dipping noise, relative to the data's standard deviation.

    Parameters
    ----------
    data : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) array_like
        Amplitudes.
    rng : numpy.random.Generator
        Source of randomness.
    white : float, optional
        Standard deviation of the white noise, in units of the data's standard deviation.
    coherent : float, optional
        Amplitude of the coherent noise (steep linear events crossing the layering, dips 35-85 degrees in index
        space), in units of the data's standard deviation.
    n_events : int, optional
        Number of coherent events.

    Returns
    -------
    ndarray, float32, the shape of ``data``
    """
    arr = _check(data)
    std = float(arr.std()) or 1.0
    out = arr + rng.normal(0.0, white * std, arr.shape).astype(np.float32)
    if coherent > 0 and n_events > 0:
        grid = _grid(arr.shape)
        noise = np.zeros(arr.shape, np.float32)
        period = rng.uniform(4.0, 12.0)
        for _ in range(int(n_events)):
            direction = rng.normal(size=arr.ndim - 1)
            direction /= np.linalg.norm(direction)
            slope = np.tan(np.radians(rng.uniform(35.0, 85.0))) * rng.choice([-1.0, 1.0])
            centre = rng.uniform(0, 1, arr.ndim) * np.array(arr.shape)
            lateral = sum(float(d) * (g - float(c)) for d, g, c in zip(direction, grid[:-1], centre[:-1]))
            dist = (grid[-1] - float(centre[-1])) - slope * lateral  # vertical distance to the event's line
            length = rng.uniform(0.1, 0.5) * arr.shape[-1]
            along = np.exp(-0.5 * ((grid[-1] - float(centre[-1])) / length) ** 2)
            noise += (np.cos(2 * np.pi * dist / period) * np.exp(-0.5 * (dist / (0.6 * period)) ** 2)
                      * along).astype(np.float32)
        nstd = float(noise.std()) or 1.0
        out += (coherent * std / nstd) * noise
    return out.astype(np.float32)


def _zone(shape, rng, *, min_frac=0.1, max_frac=0.4, blob: bool = False) -> np.ndarray:
    """A smooth weight in [0, 1]: a band of samples, or a blob with a wavy outline."""
    grid = _grid(shape)
    nz = shape[-1]
    top = rng.uniform(0, 1 - min_frac) * nz
    thick = rng.uniform(min_frac, max_frac) * nz
    taper = max(2.0, 0.05 * nz)
    wave = gaussian_filter(rng.normal(0, 1, shape[:-1]), max(2.0, 0.1 * max(shape[:-1]))).astype(np.float32)
    wave *= 0.1 * nz / (float(np.abs(wave).max()) or 1.0)
    z = grid[-1] - wave[..., None]
    weight = 1 / (1 + np.exp(-(z - top) / taper)) * 1 / (1 + np.exp((z - top - thick) / taper))
    if blob:
        centre = [rng.uniform(0.1, 0.9) * n for n in shape[:-1]]
        width = rng.uniform(0.15, 0.5) * max(shape[:-1])
        r2 = sum(((g - c) / width) ** 2 for g, c in zip(grid[:-1], centre))
        weight = weight * np.exp(-0.5 * r2 ** 2)
    return weight.astype(np.float32)


def dim_interval(data, rng: np.random.Generator, *, factor: float = 0.2, blob: bool = False) -> np.ndarray:
    """Weaken the amplitudes of a band of samples (or a blob) by ``factor``.

    Parameters
    ----------
    data : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) array_like
    rng : numpy.random.Generator
    factor : float, optional
        Amplitude factor inside the zone (0-1).
    blob : bool, optional
        A blob instead of a band across the whole section.

    Returns
    -------
    ndarray, float32, the shape of ``data``
    """
    arr = _check(data)
    weight = _zone(arr.shape, rng, blob=blob)
    return (arr * (1 - (1 - factor) * weight)).astype(np.float32)


def chaotic_texture(shape, rng: np.random.Generator, *, period: float = 8.0) -> np.ndarray:
    """Chaotic reflections: band-limited noise made of short segments of random dips (unit standard deviation).

    Parameters
    ----------
    shape : tuple of int
        ``(n_traces, n_samples)`` or ``(n_inlines, n_xlines, n_samples)``.
    rng : numpy.random.Generator
    period : float, optional
        Dominant vertical period, samples.

    Returns
    -------
    ndarray, float32, ``shape``
    """
    noise = rng.normal(0, 1, shape).astype(np.float32)
    sigma = [rng.uniform(1.0, 3.0)] * (len(shape) - 1) + [0.2 * period]
    tex = gaussian_filter(noise, sigma)
    tex = tex - gaussian_filter(tex, [3 * s for s in sigma])  # band-pass: no long continuous events
    return (tex / (float(tex.std()) or 1.0)).astype(np.float32)


def chaotic_interval(data, rng: np.random.Generator, *, strength: float = 1.0, period: float = 8.0,
                     blob: bool = False) -> np.ndarray:
    """Replace the layering of a zone by chaotic reflections (no faults there).

    Parameters
    ----------
    data : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) array_like
    rng : numpy.random.Generator
    strength : float, optional
        Amplitude of the chaotic reflections relative to the data's standard deviation.
    period : float, optional
        Dominant vertical period of the chaotic reflections, samples.
    blob : bool, optional
        A blob instead of a band across the whole section.

    Returns
    -------
    ndarray, float32, the shape of ``data``
    """
    arr = _check(data)
    weight = _zone(arr.shape, rng, blob=blob)
    tex = chaotic_texture(arr.shape, rng, period=period) * (strength * (float(arr.std()) or 1.0))
    return (arr * (1 - weight) + tex * weight).astype(np.float32)


def dead_traces(data, rng: np.random.Generator, *, fraction: float = 0.03, mute: float = 0.0,
                value: float = 0.0) -> np.ndarray:
    """Set some traces (runs of 1-8 adjacent traces) and a top mute to a constant.

    Parameters
    ----------
    data : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) array_like
    rng : numpy.random.Generator
    fraction : float, optional
        Fraction of the traces to kill.
    mute : float, optional
        Largest depth of the top mute, as a fraction of the samples (each trace's mute depth varies smoothly).
    value : float, optional
        The constant (0 for dead traces; the mid-grey of a rendered image is also 0 after scaling).

    Returns
    -------
    ndarray, float32, the shape of ``data``
    """
    arr = _check(data).copy()
    lat = arr.shape[:-1]
    n_traces = int(np.prod(lat))
    flat = arr.reshape(n_traces, arr.shape[-1])
    killed = 0
    while killed < fraction * n_traces:
        start = int(rng.integers(0, n_traces))
        run = int(rng.integers(1, 9))
        flat[start:start + run] = value
        killed += run
    if mute > 0:
        depth = gaussian_filter(rng.uniform(0, 1, lat), 3.0)
        depth = (depth - depth.min()) / (float(np.ptp(depth)) or 1.0)
        rows = (depth.reshape(-1) * mute * arr.shape[-1]).astype(int)
        z = np.arange(arr.shape[-1])
        flat[z[None, :] < rows[:, None]] = value
    return flat.reshape(arr.shape)


def acquisition_footprint(data, rng: np.random.Generator, *, strength: float = 0.3) -> np.ndarray:
    """Modulate the amplitudes periodically along one lateral axis (period 4-16 traces), strongest at the top.

    Parameters
    ----------
    data : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) array_like
    rng : numpy.random.Generator
    strength : float, optional
        Relative amplitude of the modulation at the top (0-1).

    Returns
    -------
    ndarray, float32, the shape of ``data``
    """
    arr = _check(data)
    axis = int(rng.integers(0, arr.ndim - 1))
    period = rng.uniform(4.0, 16.0)
    x = np.arange(arr.shape[axis], dtype=np.float32)
    phase = rng.uniform(0, 2 * np.pi)
    shape = [1] * arr.ndim
    shape[axis] = arr.shape[axis]
    mod = (np.cos(2 * np.pi * x / period + phase)).reshape(shape)
    depth = np.linspace(1.0, 0.3, arr.shape[-1], dtype=np.float32).reshape([1] * (arr.ndim - 1) + [-1])
    return (arr * (1 + strength * mod * depth)).astype(np.float32)


def clip_and_quantise(data, rng: np.random.Generator, *, clip_percentile: float = 99.0, levels: int = 256,
                      resample: float = 1.0) -> np.ndarray:
    """Clip the amplitudes, quantise them to ``levels`` values, and optionally resample like a rendered image.

    Parameters
    ----------
    data : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) array_like
    rng : numpy.random.Generator
        Unused (the recipe is deterministic); kept for a uniform signature.
    clip_percentile : float, optional
        The amplitudes are clipped at this percentile of their absolute values.
    levels : int, optional
        Number of quantisation levels over the clipped range (256: an 8-bit image).
    resample : float, optional
        When not 1, the image is resampled by this factor and back, bilinearly (the blur and the staircase of a
        picture rendered at another size).

    Returns
    -------
    ndarray, float32, the shape of ``data``, scaled to [-1, 1]
    """
    arr = _check(data)
    clip = float(np.percentile(np.abs(arr), clip_percentile)) or 1.0
    out = np.clip(arr / clip, -1.0, 1.0)
    half = (levels - 1) / 2.0
    out = np.round((out + 1.0) * half) / half - 1.0
    if resample != 1.0:
        small = zoom(out, resample, order=1)
        out = zoom(small, [a / b for a, b in zip(arr.shape, small.shape)], order=1)
        if out.shape != arr.shape:  # zoom rounds the output size: back to the input's, edge values repeated
            out = np.pad(out, [(0, max(0, a - b)) for a, b in zip(arr.shape, out.shape)], mode="edge")
            out = out[tuple(slice(0, a) for a in arr.shape)]
        out = np.round((np.clip(out, -1, 1) + 1.0) * half) / half - 1.0
    return out.astype(np.float32)


def degrade(data, rng: np.random.Generator, *, strength: float = 1.0) -> np.ndarray:
    """A random selection of the degradations of real data: the recipe of the learned likelihood's training data.

    Each degradation is applied with a fixed probability, its parameters drawn at random: white noise (always,
    0-0.4 standard deviations), coherent noise (30 %), a dim band or blob (30 %), a chaotic band or blob (30 %),
    dead traces and a top mute (25 %), an acquisition footprint (20 %), lateral smoothing (30 %), and clipping with
    8-bit quantisation and a rendering's resampling (40 %).

    Parameters
    ----------
    data : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) array_like
        Clean amplitudes.
    rng : numpy.random.Generator
    strength : float, optional
        Scales the probabilities and noise levels (0: only a little white noise; 1: the training recipe).

    Returns
    -------
    ndarray, float32, the shape of ``data``
    """
    arr = _check(data)
    s = float(strength)

    def happens(p):
        return rng.random() < p * s

    period = rng.uniform(5.0, 14.0)
    if happens(0.3):
        arr = chaotic_interval(arr, rng, strength=rng.uniform(0.5, 1.5), period=period, blob=rng.random() < 0.5)
    if happens(0.3):
        arr = dim_interval(arr, rng, factor=rng.uniform(0.05, 0.4), blob=rng.random() < 0.5)
    if happens(0.3):
        arr = add_noise(arr, rng, white=0.0, coherent=rng.uniform(0.1, 0.6), n_events=int(rng.integers(5, 40)))
    if happens(0.2):
        arr = acquisition_footprint(arr, rng, strength=rng.uniform(0.1, 0.4))
    arr = add_noise(arr, rng, white=rng.uniform(0.0, 0.4) * s)
    if happens(0.3):
        sigma = [rng.uniform(0.5, 1.5)] * (arr.ndim - 1) + [0.0]
        arr = gaussian_filter(arr, sigma).astype(np.float32)
    if happens(0.25):
        arr = dead_traces(arr, rng, fraction=rng.uniform(0.0, 0.05), mute=rng.uniform(0.0, 0.15))
    if happens(0.4):
        arr = clip_and_quantise(arr, rng, clip_percentile=rng.uniform(95.0, 99.9),
                                resample=float(rng.choice([1.0, rng.uniform(0.5, 2.0)])))
    return arr.astype(np.float32)
