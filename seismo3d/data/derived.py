"""Derived data files made again from their public origin, byte for byte (see :func:`seismo3d.data.fetch`).

A *derived* file of the data directory was rebuilt from its origin (cleaned, renamed, given a header). When the data
directory does not hold it, :func:`~seismo3d.data.fetch` downloads the origin with pooch (hash-checked), repeats the
derivation here into the cache and checks the result against the registry's hash. Files whose derivation is not
written here (image stacks, files with synthetic timestamps) are available from the data directory only.

- ``scans/bunny/bun000_clean.ply``, ``bun045_clean.ply``: the origin (danimodesti/alglin_icp_files, the Stanford
  3D Scanning Repository's scans) is headerless text, one ``x y z `` row per point followed by rows of other data;
  the derivation keeps the leading rows of exactly three numbers, drops their trailing blank and adds a PLY header.
- ``scans/bunny/bun.conf.reference.txt``: the two scans' poses from the repository's ``bun.conf`` with a comment on
  their convention; written from the values below (the Stanford ``bun.conf`` is not in a registered repository).
- ``rgbd/7scenes_redkitchen_0000_0495/`` ``groundtruth.txt``, ``rgb.txt``, ``depth.txt``, ``associations.txt``: the
  TUM-style index files of the registered 7-Scenes frames (every 5th), with synthetic timestamps (frame number / 30 s);
  the ground truth is each registered ``pose/frame-NNNNNN.pose.txt`` (fetched, hash-checked) as ``tx ty tz qx qy qz
  qw`` with ``qw >= 0``.
  That derivation fetches other registered files, so it is written in :mod:`seismo3d.data.registry` (its
  ``DERIVATIONS`` adds it to the ones here).

- ``seismic/penobscot_sections/penobscot_sections_1075_1092.npz``: the 18 section images (8-bit PNGs) and interval
  masks (RGB PNGs, one colour per interval, anti-aliased at the boundaries) of inlines 1075-1092 in
  atlan-antillia's copy of the Penobscot Interpretation Dataset, stacked; each mask pixel snapped to the nearest
  class colour (ties to the lower class), and horizon ``k`` on each trace = the first row of an interval ``> k``
  (-1 where there is none); written by ``numpy.savez_compressed``, which gives the same bytes for the same arrays.
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .._atomic import atomic_path
from ..errors import DataIntegrityError

__all__ = ["Derivation", "DERIVATIONS", "clean_bunny_scan", "write_bunny_poses", "stack_penobscot_sections",
           "PENOBSCOT_CLASS_COLOURS"]


@dataclass(frozen=True)
class Derivation:
    """How one derived file is made again.

    Attributes
    ----------
    origins : tuple of (str, str)
        ``(path, sha256)`` of each origin file in the entry's repository and commit, in the order ``build`` takes
        them; empty when the file is made from values in this module or from other registered files. Each is
        downloaded with pooch, which checks its SHA-256.
    build : callable
        ``build(origins, out, name)``: write the derived file ``out`` (a pathlib.Path) from the downloaded origins
        (a tuple of pathlib.Path, in the order of ``origins``) for the registry name ``name``.
    """

    origins: tuple
    build: Callable


def clean_bunny_scan(origins, out, name) -> None:
    """Write a cleaned PLY of a headerless bunny scan: the leading ``x y z`` rows, then nothing else.

    Parameters
    ----------
    origins : tuple of one pathlib.Path
        The origin text file (``bun000.ply`` of danimodesti/alglin_icp_files: rows of three numbers and a
        trailing blank, followed by rows of one number).
    out : pathlib.Path
        The PLY to write (atomically).
    name : str
        Registry name of ``out`` (its base name gives the origin's name in the header comment).

    Raises
    ------
    DataIntegrityError
        The origin does not start with rows of three numbers.
    """
    (origin,) = origins
    rows = []
    with open(origin, encoding="ascii") as stream:
        for line in stream:
            parts = line.split()
            if len(parts) != 3:
                break
            rows.append(" ".join(parts))
    if not rows:
        raise DataIntegrityError(f"{origin} does not start with 'x y z' rows; it is not the bunny scan registered "
                                 f"for {name}")
    source = pathlib.PurePosixPath(name).name.replace("_clean", "")
    header = ["ply", "format ascii 1.0",
              f"comment cleaned from {source} (first {len(rows)} xyz rows; trailing non-xyz rows dropped)",
              f"element vertex {len(rows)}", "property float x", "property float y", "property float z",
              "end_header"]
    with atomic_path(out) as tmp:
        tmp.write_text("\n".join(header + rows) + "\n", encoding="ascii")


# the two poses of the Stanford 3D Scanning Repository's bunny/data/bun.conf (tx ty tz qx qy qz qw)
_BUNNY_POSES = (
    "bmesh bun000.ply 0 0 0 0 0 0 1",
    "bmesh bun045.ply -0.0520211 -0.000383981 -0.0109223 0.00548449 -0.294635 -0.0038555 0.955586",
)
_BUNNY_POSES_COMMENT = (
    "# Poses of the two scans from the Stanford 3D Scanning Repository's bunny/data/bun.conf",
    "# format: bmesh <file> tx ty tz qx qy qz qw.  VERIFIED convention (median NN 0.33 mm, 91% < 1 mm):",
    "#   world = R(q)^T @ p + t  with R = scipy Rotation.from_quat([qx,qy,qz,qw]).as_matrix()",
    "# Values re-typed from the well-known bun.conf, NOT copied from a repository file;",
    "# the bun045 translation is corroborated by a comment in the VXL sources,",
    "# and the pair was verified by nearest-neighbour residuals between the two scans.",
)


def write_bunny_poses(origins, out, name) -> None:
    """Write ``bun.conf.reference.txt``: the bunny scans' poses (no origin: the values are above).

    Parameters
    ----------
    origins : tuple (empty)
    out : pathlib.Path
    name : str
    """
    with atomic_path(out) as tmp:
        tmp.write_text("\n".join(_BUNNY_POSES_COMMENT + _BUNNY_POSES) + "\n", encoding="ascii")


_PENOBSCOT = "seismic/penobscot_sections/penobscot_sections_1075_1092.npz"
_PENOBSCOT_FOLDER = "projects/TensorFlowFlexUNet/Penobscot/mini_test"
# RGB colour of each interval class 0..7 in the origin's masks (0 = above the first horizon)
PENOBSCOT_CLASS_COLOURS = ((0, 0, 0), (20, 70, 245), (40, 90, 235), (60, 110, 225), (80, 130, 215), (100, 150, 205),
                           (120, 170, 195), (140, 190, 185))
# sha256 and path (under _PENOBSCOT_FOLDER at the registry's commit) of the images and masks of inlines 1075-1092
_PENOBSCOT_ORIGINS = """
69acccbb3733313181f5c6580ca59bfb90e674eece5ad95763f1a6176be6ad85 images/1075.png
c9a8a7d3f9565b136b69b6af3953802ab27781af2989eb7e15c87df5402117fa images/1076.png
1228c74014bcc39edf1ee229893d8f36a78786420d94a4c1fb7f4a72287e7343 images/1077.png
4bf333d5c6a625d7527a17e42929fddfc7c1aca0a2a6b9eed08e57c1699bdfa6 images/1078.png
c7b2300b57b944ce95e2badd5db61f1ca2af2534b9504d590ddbc5d381b5c515 images/1079.png
a3097988d912cda8954739974b8a7906f28cbb336389b6b1f319fea9602b5538 images/1080.png
3a6a565c2a9c321ee14c91e871e85163e50e58cdbcdd8224d1aa0abfdbac55d2 images/1081.png
8482dab7d0235141e180bfd11536427e1a53c5c93906ad975023099ca40752f2 images/1082.png
eab0dfaeaa9e82b86a62bab2fcfebc1978f98e0949a45a01b8c65853e791b512 images/1083.png
162218464d04aeb671a5ea3b4e706683fc79b1e5bf83c51004a7a4a4a15b0ac3 images/1084.png
221b6a6f58b9372daca2c34ba612bdd9b542934b77fae0c1b48ff6aa7cef989f images/1085.png
00bff40a7d506bc4be57c13522f3af72fe7a178dc204c902a950faeeb72bba63 images/1086.png
296478623cd2e6871188f371c17b676c082f97ef69b78c63caf0273f93cd9046 images/1087.png
0583de237759fe8964975f9bfc709f4a753bd655b5811f56583606cd2f889e85 images/1088.png
39aad5bb45430866d3fc93e9bb1c446d90945e181784d8e1442af8e484ba8b1a images/1089.png
80ecb138d99124077e0d40b9ed332519293de4c58c44fe268f047f79af7e69f3 images/1090.png
17785cb7e26d60b5f1fb675343308edf1bda7cff9096e4891b75df8c002c53fd images/1091.png
6fbfe4a1a66534e00a5995da6e59cf06e2fdd7e472692454d457b3a2f4c14f23 images/1092.png
b628c6ebd5011e742878ac175d9b11ac1580eff42c26f61d2409d9cba4e0e905 masks/1075.png
20f7ee48032191923ba0437f6675cbe69ffd2159173b83d8451511ad0b903f19 masks/1076.png
d291a459a5d4f3d361bc32a1a9c7d2640a93f02af30d9f374ee565c93b218c37 masks/1077.png
1fae916393e572baf23b0df5216c823092468861c7601c464b6f96d1181af2fe masks/1078.png
433584e6342fec7ed070da3aab54426dfa19c0a89b2d7c725b8df1f9d0d14252 masks/1079.png
f3d52f2e991c435892c9d460164aae1ad41b5ea2004a7dc6ff4444347b850490 masks/1080.png
87fd622ecfd876167a579ed37128657fdfe38d0b0a83431c73ec6267a72115ee masks/1081.png
9926e733597badabab201389e01f09feda86ee8e18f1851b2f7bfcfc91c59481 masks/1082.png
ddf4d14055c17a206b9bc032a938e5e2eb9c598ec64f8dc06fba77ced50413b0 masks/1083.png
91d819d16063579e16e1995c44a6a1dc0d68e81cb6f013f5a703f9817795443f masks/1084.png
d2f8e2686c9305c888cbf27c2664850c1e9868555786f92a014616830da9c624 masks/1085.png
18880aacd28c55931e0834299863edafc416767066b1b36f457013d4abf7f688 masks/1086.png
f3284d029c38a4eb15ff4b4b5b085d767eff4b6406fcfbba70f09ca1ebcf6965 masks/1087.png
973e1fe7efd4d90a0f0b0239f93c530e043c1e652345910051d24514a2aa6de9 masks/1088.png
a542e72056afcba0064238b40296d9e7fbceee0c037c9eb90a0afe91d6566464 masks/1089.png
b8ee66c5ad5c70468800fa6509c72ff08fe5297a2285f3744d72ac1f9b6913cd masks/1090.png
b06b39e3833a0a9e0cf92daa5e99414d2c7431998435791e30be1ff7e2e6a970 masks/1091.png
ccff03e5dac2df5d5391900dd72d31d70a30ce591f99f00d99b4f223536a6c63 masks/1092.png
"""


def _read_png(path, *, color: bool):
    import cv2

    image = cv2.imread(str(path), cv2.IMREAD_COLOR if color else cv2.IMREAD_UNCHANGED)
    if image is None:
        raise DataIntegrityError(f"{path}: OpenCV could not decode the image; the file is corrupt or not a PNG")
    return image[:, :, ::-1] if color else image  # OpenCV decodes colour to BGR


def stack_penobscot_sections(origins, out, name) -> None:
    """Write the Penobscot sections npz from its section images and interval masks.

    Parameters
    ----------
    origins : tuple of pathlib.Path
        The 18 section images (8-bit grey PNG, 1536 samples x 512 traces) of inlines 1075-1092, then their 18
        interval masks (RGB PNG of the same size, one colour of :data:`PENOBSCOT_CLASS_COLOURS` per interval,
        anti-aliased at the boundaries).
    out : pathlib.Path
        The npz to write (atomically): ``seismic`` uint8 (18, 1536, 512), ``labels`` uint8 (18, 1536, 512) in 0..7
        (each mask pixel's nearest class colour, ties to the lower class), ``horizons`` int16 (18, 7, 512) (horizon
        ``k`` on a trace: the first sample row whose class is above ``k``, -1 where none is), ``section_ids`` int64
        (18,).
    name : str
        Registry name of ``out``.

    Raises
    ------
    DataIntegrityError
        An image cannot be decoded, or an image and its mask differ in size or are not grey / RGB.
    """
    half = len(origins) // 2
    ids = [int(pathlib.PurePath(path).stem) for path in origins[:half]]
    colours = np.asarray(PENOBSCOT_CLASS_COLOURS, np.int32)
    seismic, labels, horizons = [], [], []
    for image_path, mask_path in zip(origins[:half], origins[half:]):
        image, mask = _read_png(image_path, color=False), _read_png(mask_path, color=True)
        if image.ndim != 2 or image.dtype != np.uint8 or mask.shape != image.shape + (3,):
            raise DataIntegrityError(f"{image_path} and {mask_path} are not an 8-bit grey section and its RGB mask "
                                     f"of the same size (got {image.dtype} {image.shape} and {mask.shape}); they are "
                                     f"not the origin registered for {name}")
        distance = ((mask.astype(np.int32)[:, :, None, :] - colours) ** 2).sum(axis=-1)
        label = np.argmin(distance, axis=-1).astype(np.uint8)
        below = label[None] > np.arange(len(colours) - 1, dtype=np.uint8)[:, None, None]  # (7, rows, traces)
        top = np.where(below.any(axis=1), below.argmax(axis=1), -1).astype(np.int16)
        seismic.append(image)
        labels.append(label)
        horizons.append(top)
    with atomic_path(out) as tmp:
        with open(tmp, "wb") as stream:
            np.savez_compressed(stream, seismic=np.stack(seismic), labels=np.stack(labels),
                                horizons=np.stack(horizons), section_ids=np.asarray(ids, np.int64))


def _penobscot_origins() -> tuple:
    rows = [line.split() for line in _PENOBSCOT_ORIGINS.split("\n") if line.strip()]
    return tuple((f"{_PENOBSCOT_FOLDER}/{path}", sha256) for sha256, path in rows)


DERIVATIONS = {
    "scans/bunny/bun000_clean.ply": Derivation(
        (("bun000.ply", "41d3662ce48f055e254806ea699edb71a06afde88876d37e2cece8e496dcb12b"),), clean_bunny_scan),
    "scans/bunny/bun045_clean.ply": Derivation(
        (("bun045.ply", "960756d05262231c5fb372a5003475b0282b90800f562deb4d60282b0db336cd"),), clean_bunny_scan),
    "scans/bunny/bun.conf.reference.txt": Derivation((), write_bunny_poses),
    _PENOBSCOT: Derivation(_penobscot_origins(), stack_penobscot_sections),
}
