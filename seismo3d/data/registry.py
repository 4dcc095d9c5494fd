"""Registry of the real data files used by seismo3d's tests, benchmarks and examples.

Every file has a name relative to the data directory (``"scans/bunny/bun000_clean.ply"``), a SHA-256 hash, a licence
and a public origin. :func:`fetch` resolves a name to a local path: first from the data directory named by the
environment variable ``SEISMO3D_DATA_DIR`` (hash checked once per process), otherwise by downloading the origin with
pooch into ``SEISMO3D_CACHE_DIR`` (default: the operating system's cache folder). Files marked *derived* were rebuilt
from their origin (renamed columns, cleaned rows, stacked images, added index files), so their origin would not match
the hash: they are made again from their downloaded origins by :mod:`seismo3d.data.derived` (the bunny scans and
poses, the Penobscot image stack) or from other registered files here (the 7-Scenes index files) and checked
against the registry's hash.

The registry file ``registry.txt`` beside this module (name, SHA-256, source, path in the source; package data) is
the single source of truth; ``seismo3d/data/README.md`` describes each file.

Examples
--------
>>> from seismo3d.data import fetch, list_files
>>> list_files("scans/bunny")                                  # doctest: +SKIP
['scans/bunny/bun.conf.reference.txt', 'scans/bunny/bun000_clean.ply', 'scans/bunny/bun045_clean.ply']
>>> path = fetch("seismic/f3_crop.sgy")                        # doctest: +SKIP
"""

from __future__ import annotations

import difflib
import functools
import hashlib
import importlib.resources
import os
import pathlib
import shutil
import types
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from .._atomic import atomic_path
from ..errors import DataIntegrityError, DataNotFoundError, InputError
from .derived import DERIVATIONS as _ORIGIN_DERIVATIONS
from .derived import Derivation

__all__ = ["DataFile", "REGISTRY", "data_dir", "fetch", "fetch_folder", "file_info", "list_files"]

DATA_DIR_ENV = "SEISMO3D_DATA_DIR"
CACHE_DIR_ENV = "SEISMO3D_CACHE_DIR"
_RAW_URL = "https://raw.githubusercontent.com/{repo}/{commit}/{path}"
_REGISTRY_FILE = "registry.txt"


@dataclass(frozen=True)
class _Source:
    """A public repository snapshot that files were taken from."""

    repo: str
    commit: str
    licence: str


# One snapshot per origin (owner/repo @ commit), as listed in the shared data README.
_SOURCES = types.MappingProxyType({
    "segyio": _Source("equinor/segyio", "ce7bf86e4bee75f3296a5a756fa123e981a04fea",
                      "F3 Netherlands (dGB Earth Sciences / TNO): CC BY-SA"),
    "segyio_tests": _Source("equinor/segyio", "ce7bf86e4bee75f3296a5a756fa123e981a04fea",
                            "LGPL-3.0 (segyio's test data, made by its scripts)"),
    "f3_masks": _Source("thilowrona/seismic_deep_learning", "3a616bcb6d17e041e62e4201733332c656c2bf44",
                        "AGPL-3.0 (the repository's drawings); F3 Netherlands (dGB Earth Sciences / TNO): CC BY-SA"),
    "seg2014": _Source("seg/tutorials", "7ed8c094f00962263dfb0bebcfc6c36bf3981a74", "Penobscot 3D: CC BY-SA 3.0"),
    "seg2017": _Source("seg/tutorials-2017", "b38f798866dd4e1a38c78cfd45edb7b2cfd3d785",
                       "F3 Netherlands (dGB Earth Sciences / TNO): CC BY-SA"),
    "segysak": _Source("trhallam/segysak", "798307eeaf84b63a71272ba638863c538a814f26",
                       "Equinor Volve data licence (see seismic/volve_licence.txt)"),
    "osv": _Source("xinwucwp/osv", "f4e2564fc27b9539edc4caff0944b1ddb94997b8",
                   "research code repository without a data licence; public survey data"),
    "osv_f3": _Source("xinwucwp/osv", "f4e2564fc27b9539edc4caff0944b1ddb94997b8",
                      "F3 Netherlands (dGB Earth Sciences / TNO): CC BY-SA"),
    "gsb": _Source("augustoicaro/SFD-CNN-TL", "17eb64e1a870a48991f509492cd5d502a260262e",
                   "MIT (the repository, Cunha et al. 2020); Great South Basin 3D: New Zealand public petroleum data"),
    "igi": _Source("xinwucwp/igi", "4fed4c63c56d0a421cd4c9e30c21c2740874e8aa", "Teapot Dome: public (US DOE, RMOTC)"),
    "mhe_teapot": _Source("xinwucwp/mhe", "a458d9bd5185cde0e03fc95dd4df3f91174f4872",
                          "Teapot Dome: public (US DOE, RMOTC)"),
    "mhe_f3": _Source("xinwucwp/mhe", "a458d9bd5185cde0e03fc95dd4df3f91174f4872",
                      "F3 Netherlands (dGB Earth Sciences / TNO): CC BY-SA"),
    "penobscot_labels": _Source(
        "atlan-antillia/TensorFlow-FlexUNet-Tiled-Image-Segmentation-Penobscot-Seismic-Interpretation",
        "c7a3575803572fd0235b8b31ef8681a363f7bb49",
        "CC BY 4.0 (Baroni et al. 2020, Penobscot Interpretation Dataset, doi:10.5281/zenodo.3924682)"),
    "7scenes": _Source("andyzeng/tsdf-fusion-python", "3f22a940d90f684145b1f29b1feaa92e09eb1db6",
                       "Microsoft 7-Scenes: non-commercial research use"),
    "dvo_sheng": _Source("LucasSheng/dense-rgbd-visual-odometry", "2973ca8d0dc55e636663e6fdb9bd09fd1f21a6ee",
                         "TUM RGB-D benchmark: CC BY 4.0"),
    "open3d": _Source("isl-org/Open3D", "9598f0391387dc93faab444b37ad0b89fb9609f6",
                      "MIT (Open3D); TUM RGB-D, NYU Depth v2 and SUN RGB-D frames under their datasets' terms"),
    "evo": _Source("MichaelGrupp/evo", "26d0953d4da0f0cb56f90ba6269a15e72f69d3ad", "TUM RGB-D benchmark: CC BY 4.0"),
    "bunny": _Source("danimodesti/alglin_icp_files", "c340cda257a8beba1b588c7fd92aeca9711ab496",
                     "Stanford 3D Scanning Repository: research use, credit the Stanford Computer Graphics Laboratory"),
    "laspy": _Source("laspy/laspy", "fbc5b375f9dad6bae499a81ca436bee361ecf047", "BSD-2-Clause (laspy test data)"),
    "pysheds": _Source("mdbartos/pysheds", "5fc9d9d244ee3f1a6fde04f69b5dd1000ba908ae",
                       "HydroSHEDS licence (WWF / USGS)"),
    "parihaka": _Source("zuenko/seismis_analysis", "00c8ae87c3082bc9e638bce2b0d839c90674e0f5",
                        "Parihaka 3D: New Zealand Petroleum & Minerals open data (the repository states no licence)"),
    "faultnet": _Source("douyimin/FaultNet", "8b513733ed1461a0cd1c62cd012277193473c84a",
                        "Apache-2.0 (FaultNet, Dou et al. 2022: a peer measured in benchmarks/, never a dependency)"),
})


@dataclass(frozen=True)
class DataFile:
    """One registered data file.

    Attributes
    ----------
    name : str
        Path relative to the data directory, with forward slashes, e.g. ``"scans/bunny/bun000_clean.ply"``.
    sha256 : str
        Hex SHA-256 digest of the file's bytes.
    repo, commit : str
        The public GitHub repository (``owner/name``) and commit the file, or the file it was derived from, comes from.
    origin_path : str or None
        Path of the file inside ``repo`` at ``commit``; None for a derived file (several sources, or rebuilt).
    licence : str
        The licence or terms of use of the data.
    """

    name: str
    sha256: str
    repo: str
    commit: str
    origin_path: str | None
    licence: str

    @property
    def derived(self) -> bool:
        """True when the file was rebuilt from its origin and is available only from a data directory."""
        return self.origin_path is None

    @property
    def url(self) -> str | None:
        """Raw download URL of the origin file (byte-identical to this file), or None for a derived file."""
        if self.origin_path is None:
            return None
        return _RAW_URL.format(repo=self.repo, commit=self.commit, path=self.origin_path)


def _read_registry() -> tuple[DataFile, ...]:
    """Every row of the package's ``registry.txt``, sorted by name."""
    text = importlib.resources.files(__package__).joinpath(_REGISTRY_FILE).read_text(encoding="utf-8")
    entries = []
    for line in text.splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        name, sha256, source_key, origin_path = line.split()
        source = _SOURCES[source_key]
        entries.append(DataFile(name=name, sha256=sha256, repo=source.repo, commit=source.commit,
                                origin_path=None if origin_path == "-" else origin_path, licence=source.licence))
    return tuple(sorted(entries, key=lambda entry: entry.name))


def data_dir() -> pathlib.Path | None:
    """Return the data directory named by the environment variable ``SEISMO3D_DATA_DIR``.

    Returns
    -------
    path : pathlib.Path or None
        The directory (not checked for existence), or None when the variable is unset or empty.
    """
    value = os.environ.get(DATA_DIR_ENV, "").strip()
    return pathlib.Path(value).expanduser() if value else None


def _cache_dir() -> pathlib.Path:
    value = os.environ.get(CACHE_DIR_ENV, "").strip()
    if value:
        return pathlib.Path(value).expanduser()
    import pooch

    return pathlib.Path(pooch.os_cache("seismo3d"))


def list_files(prefix: str = "") -> list[str]:
    """List the registered file names that start with ``prefix``.

    Parameters
    ----------
    prefix : str
        Start of the names, e.g. ``"rgbd/tum_fr1xyz_pair/"`` or ``"seismic/sections"``; ``""`` lists every file.

    Returns
    -------
    names : list of str
        Sorted names relative to the data directory.
    """
    if not isinstance(prefix, str):
        raise InputError(f"prefix must be a str such as 'scans/bunny/'; got {type(prefix).__name__}")
    return [entry.name for entry in REGISTRY if entry.name.startswith(prefix)]


def file_info(name: str) -> DataFile:
    """Return the registry entry of one file.

    Parameters
    ----------
    name : str
        Name relative to the data directory, e.g. ``"scans/bunny/bun000_clean.ply"``.

    Returns
    -------
    entry : DataFile
        Hash, origin, licence and ``derived`` flag of the file.

    Raises
    ------
    InputError
        If ``name`` is not registered; the message lists the closest registered names.
    """
    entry = _ENTRIES.get(name) if isinstance(name, str) else None
    if entry is not None:
        return entry
    if not isinstance(name, str):
        raise InputError(f"name must be a str such as 'scans/bunny/bun000_clean.ply'; got {type(name).__name__}")
    names = list(_ENTRIES)
    close = difflib.get_close_matches(name, names, n=5, cutoff=0.5)
    if not close:
        # compare base names too, so that 'bun000.ply' finds 'scans/bunny/bun000_clean.ply'
        by_base = {n.rsplit("/", 1)[-1]: n for n in names}
        close = [by_base[b] for b in difflib.get_close_matches(name.rsplit("/", 1)[-1], list(by_base), n=5)]
    inside = list_files(name.rstrip("/") + "/") if name else []
    if inside:
        hint = f"{name!r} is a folder; fetch one of its {len(inside)} files, e.g. {inside[0]!r} (see list_files)"
    elif close:
        hint = "did you mean " + ", ".join(repr(c) for c in close) + "?"
    else:
        hint = "see seismo3d.data.list_files() for the registered names"
    raise InputError(f"no data file named {name!r} is registered; {hint}")


def _sha256(path: pathlib.Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


@functools.lru_cache(maxsize=None)
def _verified(path: str, sha256: str, size: int, mtime_ns: int) -> str:
    """Check a file's hash once per (path, size, mtime); raise DataIntegrityError on mismatch (never cached)."""
    actual = _sha256(pathlib.Path(path))
    if actual != sha256:
        raise DataIntegrityError(
            f"{path} has SHA-256 {actual} but the registry expects {sha256}: the file is corrupt, truncated or a "
            f"different version. Restore it from its origin or a fresh copy of the data directory "
            f"(or unset {DATA_DIR_ENV} to download the registered version)"
        )
    return path


def _not_found_hint() -> str:
    return (f"set the environment variable {DATA_DIR_ENV} to a copy of the seismo3d data directory "
            f"(e.g. export {DATA_DIR_ENV}=/path/to/data)")


def fetch(name: str, *, verify: bool = True) -> pathlib.Path:
    """Return a local path to a registered data file, downloading it if needed.

    The file is looked up first in the data directory ``$SEISMO3D_DATA_DIR`` (its SHA-256 is checked the first time
    it is used in a process), then downloaded from its public origin with pooch into ``$SEISMO3D_CACHE_DIR`` (default
    ``pooch.os_cache("seismo3d")``), where pooch checks the hash.

    Parameters
    ----------
    name : str
        Name relative to the data directory, e.g. ``"scans/bunny/bun000_clean.ply"``; see :func:`list_files`.
    verify : bool, optional
        Check the SHA-256 hash (default). Pass False only for a file you have edited on purpose.

    Returns
    -------
    path : pathlib.Path
        Absolute path of the local file. Treat it as read-only.

    Raises
    ------
    InputError
        If ``name`` is not registered (the message lists close names).
    DataNotFoundError
        If the file is not in the data directory and cannot be downloaded (offline, or a derived file that exists
        only in the data directory); the message says how to set ``SEISMO3D_DATA_DIR``. A derived file with a
        derivation (:mod:`seismo3d.data.derived`) is made again from its downloaded origin.
    DataIntegrityError
        If the local or downloaded file's hash differs from the registry.
    """
    entry = file_info(name)
    root = data_dir()
    if root is not None:
        path = (root / entry.name).resolve()
        if path.is_file():
            if verify:
                stat = path.stat()
                _verified(str(path), entry.sha256, stat.st_size, stat.st_mtime_ns)
            return path
    where = f"{DATA_DIR_ENV}={root}" if root is not None else f"{DATA_DIR_ENV} is not set"
    if entry.derived:
        derivation = DERIVATIONS.get(entry.name)
        if derivation is None:
            raise DataNotFoundError(
                f"{entry.name} is not in the data directory ({where}) and cannot be downloaded: it was derived from "
                f"{entry.repo} and exists only in the seismo3d data directory; {_not_found_hint()}"
            )
        return _derive(entry, derivation, where, verify)
    folder, _, basename = entry.name.rpartition("/")
    return _download(entry.name, entry.url, entry.sha256 if verify else None, _cache_dir() / folder, basename, where)


def fetch_folder(prefix: str, *, verify: bool = True) -> pathlib.Path:
    """Return a local folder holding every registered file under ``prefix``, downloading what is missing.

    For data read as a folder (an RGB-D sequence: images, depth maps, poses and index files side by side). When the
    data directory holds all of the folder's files, its folder is returned (each file hash-checked as by
    :func:`fetch`); otherwise every file is fetched into the cache (downloaded, made again from its origin, or
    copied from the data directory) and the cache's folder is returned.

    Parameters
    ----------
    prefix : str
        A registered folder, e.g. ``"rgbd/7scenes_redkitchen_0000_0495"`` (with or without the trailing slash).
    verify : bool, optional
        Check the SHA-256 hashes (default).

    Returns
    -------
    folder : pathlib.Path
        Absolute path of the folder. Treat it as read-only.

    Raises
    ------
    InputError
        If no file is registered under ``prefix``.
    DataNotFoundError, DataIntegrityError
        As :func:`fetch`, for any of the folder's files.
    """
    folder = prefix.rstrip("/") if isinstance(prefix, str) else prefix
    names = list_files(folder + "/") if isinstance(folder, str) and folder else []
    if not names:
        raise InputError(f"no data files are registered under the folder {prefix!r}; see "
                         "seismo3d.data.list_files() for the registered names")
    root = data_dir()
    if root is not None and all((root / name).is_file() for name in names):
        for name in names:
            fetch(name, verify=verify)
        return (root / folder).resolve()
    cache = _cache_dir()
    for name in names:
        path = fetch(name, verify=verify)
        target = cache / name
        if path != target.resolve() and not (target.is_file() and _sha256(target) == file_info(name).sha256):
            # read from the data directory: copied beside the downloaded files
            target.parent.mkdir(parents=True, exist_ok=True)
            with atomic_path(str(target)) as tmp:
                shutil.copyfile(path, tmp)
    return (cache / folder).resolve()


def _download(name: str, url: str, sha256, folder: pathlib.Path, basename: str, where: str) -> pathlib.Path:
    """pooch.retrieve with seismo3d's errors: DataNotFoundError offline, DataIntegrityError on a hash mismatch."""
    import pooch

    try:
        local = pooch.retrieve(url, known_hash=None if sha256 is None else f"sha256:{sha256}", fname=basename,
                               path=folder, progressbar=False)
    except (OSError, ValueError) as exc:
        if isinstance(exc, OSError):  # requests' errors (also those that are ValueErrors) and file-system errors
            raise DataNotFoundError(
                f"{name} is not in the data directory ({where}) and downloading {url} failed ({exc}); "
                f"{_not_found_hint()}, or connect to the internet"
            ) from exc
        # pooch raises a plain ValueError when the downloaded file's hash differs
        raise DataIntegrityError(
            f"the download of {name} from {url} does not match the registered SHA-256 {sha256}; "
            f"the origin changed or the download was corrupted; {_not_found_hint()}"
        ) from exc
    return pathlib.Path(local).resolve()


def _derive(entry: DataFile, derivation, where: str, verify: bool) -> pathlib.Path:
    """Make a derived file again in the cache from its downloaded origin (seismo3d.data.derived), hash-checked."""
    out = _cache_dir() / entry.name
    if out.is_file() and (not verify or _sha256(out) == entry.sha256):
        return out.resolve()
    origins = []
    for origin_path, origin_sha256 in derivation.origins:
        url = _RAW_URL.format(repo=entry.repo, commit=entry.commit, path=origin_path)
        folder, _, basename = origin_path.rpartition("/")
        origins.append(_download(entry.name, url, origin_sha256 if verify else None,
                                 _cache_dir() / "origins" / entry.repo.replace("/", "+") / folder, basename, where))
    out.parent.mkdir(parents=True, exist_ok=True)
    derivation.build(tuple(origins), out, entry.name)
    actual = _sha256(out)
    if verify and actual != entry.sha256:
        out.unlink()
        raise DataIntegrityError(
            f"{entry.name} made again from its origin has SHA-256 {actual}, not the registered {entry.sha256}; "
            f"the origin or the derivation changed; {_not_found_hint()}"
        )
    return out.resolve()


REGISTRY: tuple[DataFile, ...] = _read_registry()
"""Every registered data file, sorted by name."""

_ENTRIES = types.MappingProxyType({entry.name: entry for entry in REGISTRY})


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


def write_7scenes_index(origins, out, name) -> None:
    """Write one TUM-style index file of the registered 7-Scenes frames (no origin: the frames are the registry's,
    the poses are fetched).

    Parameters
    ----------
    origins : tuple (empty)
    out : pathlib.Path
    name : str
        ``rgbd/7scenes_redkitchen_0000_0495/<groundtruth|rgb|depth|associations>.txt``.
    """
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


# every derivation: those of seismo3d.data.derived (made from downloaded origins) and the 7-Scenes index files (made
# from other registered files, fetched here)
DERIVATIONS = {**_ORIGIN_DERIVATIONS,
               **{f"{_7SCENES}/{kind}": Derivation((), write_7scenes_index) for kind in _7SCENES_HEADERS}}
