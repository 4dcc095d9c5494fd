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

The Penobscot image stack (``seismic/penobscot_sections/...npz``) has no derivation here: it is available from the
data directory only.
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass
from typing import Callable

from .._atomic import atomic_path
from ..errors import DataIntegrityError

__all__ = ["Derivation", "DERIVATIONS", "clean_bunny_scan", "write_bunny_poses", "write_7scenes_index"]


@dataclass(frozen=True)
class Derivation:
    """How one derived file is made again.

    Attributes
    ----------
    origin_path : str or None
        Path of the origin file in the entry's repository and commit (None: made from values in this module).
    origin_sha256 : str or None
        SHA-256 of the origin file (checked by pooch on download).
    build : callable
        ``build(origin, out, name)``: write the derived file ``out`` (a pathlib.Path) from the downloaded origin
        (a pathlib.Path, or None) for the registry name ``name``.
    """

    origin_path: str | None
    origin_sha256: str | None
    build: Callable


def clean_bunny_scan(origin, out, name) -> None:
    """Write a cleaned PLY of a headerless bunny scan: the leading ``x y z`` rows, then nothing else.

    Parameters
    ----------
    origin : pathlib.Path
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


def write_bunny_poses(origin, out, name) -> None:
    """Write ``bun.conf.reference.txt``: the bunny scans' poses (``origin`` is unused: the values are above).

    Parameters
    ----------
    origin : None
    out : pathlib.Path
    name : str
    """
    with atomic_path(out) as tmp:
        tmp.write_text("\n".join(_BUNNY_POSES_COMMENT + _BUNNY_POSES) + "\n", encoding="ascii")


_7SCENES = "rgbd/7scenes_redkitchen_0000_0495"
_7SCENES_HEADERS = {
    "groundtruth.txt": ("# ground truth trajectory (derived from 7-Scenes redkitchen frame-XXXXXX.pose.txt, "
                        "camera-to-world, KinectFusion-tracked)",
                        "# timestamps are synthetic: original_frame_index / 30.0 s (7-Scenes has no timestamps)",
                        "# timestamp tx ty tz qx qy qz qw"),
    "rgb.txt": ("# color images (NOTE: 7-Scenes color is NOT registered to depth)", "# timestamp filename"),
    "depth.txt": ("# depth maps (uint16 mm, 0 = invalid; depth intrinsics fx=fy=585 cx=320 cy=240)",
                  "# timestamp filename"),
    "associations.txt": (),
}


def write_7scenes_index(origin, out, name) -> None:
    """Write one TUM-style index file of the registered 7-Scenes frames (``origin`` is unused: the frames are the
    registry's, the poses are fetched).

    Parameters
    ----------
    origin : None
    out : pathlib.Path
    name : str
        ``rgbd/7scenes_redkitchen_0000_0495/<groundtruth|rgb|depth|associations>.txt``.
    """
    import numpy as np
    from scipy.spatial.transform import Rotation

    from .registry import fetch, list_files  # registry imports this module: import it when a file is made

    kind = pathlib.PurePosixPath(name).name
    frames = sorted(int(f.rsplit("frame-", 1)[1][:6]) for f in list_files(f"{_7SCENES}/depth/"))
    lines = list(_7SCENES_HEADERS[kind])
    for frame in frames:
        stamp = f"{frame / 30.0:.6f}"
        rgb, depth = f"rgb/frame-{frame:06d}.color.jpg", f"depth/frame-{frame:06d}.depth.png"
        if kind == "groundtruth.txt":
            pose = np.loadtxt(fetch(f"{_7SCENES}/pose/frame-{frame:06d}.pose.txt"))
            q = Rotation.from_matrix(pose[:3, :3]).as_quat()  # qx qy qz qw
            q = -q if q[3] < 0 else q
            lines.append(" ".join([stamp, *(f"{v:.7f}" for v in pose[:3, 3]), *(f"{v:.7f}" for v in q)]))
        elif kind == "associations.txt":
            lines.append(f"{stamp} {rgb} {stamp} {depth}")
        else:
            lines.append(f"{stamp} {rgb if kind == 'rgb.txt' else depth}")
    with atomic_path(out) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="ascii")


DERIVATIONS = {
    "scans/bunny/bun000_clean.ply": Derivation(
        "bun000.ply", "41d3662ce48f055e254806ea699edb71a06afde88876d37e2cece8e496dcb12b", clean_bunny_scan),
    "scans/bunny/bun045_clean.ply": Derivation(
        "bun045.ply", "960756d05262231c5fb372a5003475b0282b90800f562deb4d60282b0db336cd", clean_bunny_scan),
    "scans/bunny/bun.conf.reference.txt": Derivation(None, None, write_bunny_poses),
    **{f"{_7SCENES}/{kind}": Derivation(None, None, write_7scenes_index) for kind in _7SCENES_HEADERS},
}
