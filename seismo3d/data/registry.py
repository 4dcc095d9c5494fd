"""Registry of the real data files used by seismo3d's tests, benchmarks and examples.

Every file has a name relative to the data directory (``"scans/bunny/bun000_clean.ply"``), a SHA-256 hash, a licence
and a public origin. :func:`fetch` resolves a name to a local path: first from the data directory named by the
environment variable ``SEISMO3D_DATA_DIR`` (hash checked once per process), otherwise by downloading the origin with
pooch into ``SEISMO3D_CACHE_DIR`` (default: the operating system's cache folder). Files marked *derived* were rebuilt
from their origin (renamed columns, cleaned rows, stacked images, added index files), so their origin would not match
the hash: they are made again from their downloaded origins by :mod:`seismo3d.data.derived` (the bunny scans and
poses, the 7-Scenes index files, the Penobscot image stack) and checked against the registry's hash.

The tables at the bottom of this module are the single source of truth; ``seismo3d/data/README.md`` describes each
file. The second table lists files that are not in the data directory and are always downloaded (segyio's own test
data, for the SEG-Y conformance test; ``DataFile.in_data_directory`` is False).

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
import os
import pathlib
import shutil
import types
from dataclasses import dataclass

from .._atomic import atomic_path
from ..errors import DataIntegrityError, DataNotFoundError, InputError
from .derived import DERIVATIONS

__all__ = ["DataFile", "REGISTRY", "data_dir", "fetch", "fetch_folder", "file_info", "list_files"]

DATA_DIR_ENV = "SEISMO3D_DATA_DIR"
CACHE_DIR_ENV = "SEISMO3D_CACHE_DIR"
_RAW_URL = "https://raw.githubusercontent.com/{repo}/{commit}/{path}"


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
    "seg2014": _Source("seg/tutorials", "7ed8c094f00962263dfb0bebcfc6c36bf3981a74", "Penobscot 3D: CC BY-SA 3.0"),
    "seg2017": _Source("seg/tutorials-2017", "b38f798866dd4e1a38c78cfd45edb7b2cfd3d785",
                       "F3 Netherlands (dGB Earth Sciences / TNO): CC BY-SA"),
    "segysak": _Source("trhallam/segysak", "798307eeaf84b63a71272ba638863c538a814f26",
                       "Equinor Volve data licence (see seismic/volve_licence.txt)"),
    "osv": _Source("xinwucwp/osv", "f4e2564fc27b9539edc4caff0944b1ddb94997b8",
                   "research code repository without a data licence; public survey data"),
    "osv_f3": _Source("xinwucwp/osv", "f4e2564fc27b9539edc4caff0944b1ddb94997b8",
                      "F3 Netherlands (dGB Earth Sciences / TNO): CC BY-SA"),
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
    in_data_directory : bool
        False for a file that is not part of the seismo3d data directory and is always downloaded from its origin
        (segyio's own test data, ``seismic/segyio_test_data/...``, read by the SEG-Y conformance test).
    """

    name: str
    sha256: str
    repo: str
    commit: str
    origin_path: str | None
    licence: str
    in_data_directory: bool = True

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


def _parse_table(table: str, *, in_data_directory: bool = True) -> tuple[DataFile, ...]:
    entries = []
    for line in table.strip().splitlines():
        sha256, source_key, name, origin_path = line.split()
        source = _SOURCES[source_key]
        entries.append(DataFile(name=name, sha256=sha256, repo=source.repo, commit=source.commit,
                                origin_path=None if origin_path == "-" else origin_path, licence=source.licence,
                                in_data_directory=in_data_directory))
    return tuple(entries)


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


# sha256, source key (see _SOURCES), name relative to the data directory, path in the source ('-' = derived).
_TABLE = """
deb3572e682900caa0fc2d7a154e49ae40d655c30d6bd492786d07564e9742fc 7scenes rgbd/7scenes_redkitchen_0000_0495/associations.txt -
f378f3bf812663ff5d4cd4a6bfcba7dd824639e67b11c59f52729b607cffc061 7scenes rgbd/7scenes_redkitchen_0000_0495/camera-intrinsics.txt data/camera-intrinsics.txt
ffd600796e76eebc43617c48380442cb11175e7efe30a39ddb9acc546cfc20fe 7scenes rgbd/7scenes_redkitchen_0000_0495/depth.txt -
6987ac7d8ad5b5758ce1a80b12891ab0386821a45b35b5d89e1f719a41f5db70 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000000.depth.png data/frame-000000.depth.png
d727ada0af7fc68a5e51e15a91e21c28c8384d32ddb42bdf38a47c2daaa8e8ae 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000005.depth.png data/frame-000005.depth.png
4197dd6c35fa9c7c2de7ada1994040ff1e3448d00a1c33b3a081c422d9cea87d 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000010.depth.png data/frame-000010.depth.png
63fce95be9bc9e0abbe5525b456cb4cc73bb472d4239fdecb1b240ccb693e03b 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000015.depth.png data/frame-000015.depth.png
571c7cdbce8faecef6a61fedb21f1ecc3ab31662475bd2f7f618eb368308f799 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000020.depth.png data/frame-000020.depth.png
7f6fa592d29a1072cdb11e12415ca898567355601d341021af65e40bae78a634 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000025.depth.png data/frame-000025.depth.png
514b502487476f1156c357cbb05fb7d4563284125e007a67b9b7e8d3b7307a59 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000030.depth.png data/frame-000030.depth.png
68edc913e0dfee74f4da67751da87e1cc8e2aeb12d78abd371f098ab9a23c63e 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000035.depth.png data/frame-000035.depth.png
c1c9f15175a956770539be95406b7214c56b7b0c9b0b1c1a741607b689a6727d 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000040.depth.png data/frame-000040.depth.png
78fa507cc3902b5c927f310a3bce2a6ed803ddb3e5cf7531f6848574ad9a6028 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000045.depth.png data/frame-000045.depth.png
2c417aed5f2165c28a29871a1fc47d518d782485eaad38e94d0ff1f494d82299 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000050.depth.png data/frame-000050.depth.png
d230ec13d41725db2b8abf7c389af3de0e99fcf4c7fcc7e3b92d750c5df92e9c 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000055.depth.png data/frame-000055.depth.png
36d70c3956e49bf99032ef68fc1e45baa1b252986a66fcfa53267172f59e1750 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000060.depth.png data/frame-000060.depth.png
8c5b984776ac5469282ced016584d7934b2d57ef8e6dd0730d1110c65d711977 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000065.depth.png data/frame-000065.depth.png
89c1baebd1aa9edc3334c0ee840f915f692dbb22064b64f1dd14bb77a9fb2b52 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000070.depth.png data/frame-000070.depth.png
2840d8c198b6d2d2c00feaa5e9c4404be3ad03ee3f84dba17379cd9bd7b92bb3 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000075.depth.png data/frame-000075.depth.png
7a65f9e246fe06a6210e3b4ad3814601eb9bf146a54c1a4d3a5ddb6c9a9ac139 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000080.depth.png data/frame-000080.depth.png
633c9dc0a4630adf61b13da16bb23d17dbc5b90b1e83345014db57350cfce4ee 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000085.depth.png data/frame-000085.depth.png
a2a34e022d4923c4ebcb1993fd5ac72a033ed2e8fb4cb4e0713117a94bc378ad 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000090.depth.png data/frame-000090.depth.png
3a16c8df675f356747c8b500e39876af6dffb60799e7d0465af9f6e6da356167 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000095.depth.png data/frame-000095.depth.png
28dd5c26ca531ac05a5f6e66aceb899039b047eace8d4e48d6ea6de9b50d4c2d 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000100.depth.png data/frame-000100.depth.png
3c4e5808539b85495b28957e71c2b94edc72a84bae04ac8e18fc40f7869151e5 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000105.depth.png data/frame-000105.depth.png
3fc7d51c1886f998960f82ef6115fee3a58388eb5572491e28d5f9d2dcba3e16 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000110.depth.png data/frame-000110.depth.png
48909b40051f3b2538146d6a6774a9932fba28b11a77eb8623833a88141fa4d5 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000115.depth.png data/frame-000115.depth.png
be38da87b86d5af32419c7458935dc6067469cf679d586d5c0f73bbaa61d8e9d 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000120.depth.png data/frame-000120.depth.png
815ee924a07c72f55cba630a1606eadc8acbcc002b711c9e8db5cb999440712c 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000125.depth.png data/frame-000125.depth.png
3c5499b0858e78080458eb8d0af9e8811252611b7dfba0e8772598ec3f1fb6d4 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000130.depth.png data/frame-000130.depth.png
04d282fde0d602bdc52198120fd460bc1ebb9123d043c47f2ff1a258147c5b40 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000135.depth.png data/frame-000135.depth.png
d2fb774c526170d06bd1ac01b029ff15cf5618b8d9c8f6a12863e017e65b96cd 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000140.depth.png data/frame-000140.depth.png
9c7b0c817965a678927d5ea60b3ae4f482dc18c2b0ea281bc5dc38b797527e05 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000145.depth.png data/frame-000145.depth.png
940daa0f0977dfd91e35f63ee66ccefb04889cd98d68091a86a9bdfa6fe7ba84 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000150.depth.png data/frame-000150.depth.png
e05b8f7b83f8e8bef95248aa195f4ab5f15d549fd08e7a7b71f090c680d238dc 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000155.depth.png data/frame-000155.depth.png
485e2c2cc0f042a163bfb95f15c5c914e387b91095bb784310ed77381bec4233 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000160.depth.png data/frame-000160.depth.png
d179e0fcaf315708e786da34ef7e2cf5ffb5fa7e18de2a9b88ebf9acbef1be20 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000165.depth.png data/frame-000165.depth.png
7a59f91264c0bfec0b3b4dd8f2c630ae9e421ba6734aee6e7810ba45406fc06b 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000170.depth.png data/frame-000170.depth.png
42adee26ec57289f8c74347ab0b43da7fef80e0a7f6010fd3d57a5bf4651ffec 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000175.depth.png data/frame-000175.depth.png
3b73c0988e83591ad2bf43bd97515053d4cd9d79c548f8f59485c37fa1980006 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000180.depth.png data/frame-000180.depth.png
2dbadad3d8fea537bd419c1de693ae76650c2e9c9e7d302bfcf12e05a052eaf6 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000185.depth.png data/frame-000185.depth.png
7a8edd9511cc45075dba0654fd5ceac5182348b50eeabc85793ea816f3fceacf 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000190.depth.png data/frame-000190.depth.png
5a609d607dda27f3bb2c8bffde1ddcd2ab52ea7669a1eb05f0df9f3430dac730 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000195.depth.png data/frame-000195.depth.png
2b0ad8e7e266a1f8ef6c9cc36c117b7170d6dac084e403e42118136842e75d52 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000200.depth.png data/frame-000200.depth.png
6899477fcf4ce691d7fe0a9ff496b5234e1e3787976c165196261bce08a2baad 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000205.depth.png data/frame-000205.depth.png
df003f765e8e82548f829a01ca061c9f718fac4f7abb9a6423ab86d063e447d6 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000210.depth.png data/frame-000210.depth.png
50b2aa1c940e4fb593bd48c45cea9e8748b97e28fe975e703d459fde9536cc70 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000215.depth.png data/frame-000215.depth.png
2a6773f0c014157e7f27679f09bee1c0d37af119f8e595535de0837daf68b120 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000220.depth.png data/frame-000220.depth.png
4cbbfabb22fc41ac261dd40c5034278fc6ff9e1f3cf66effd3dbd65a91d3b0b2 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000225.depth.png data/frame-000225.depth.png
03162d5797effd3ba7843f15f7eaaa9a1a7c8c6440328e137bdce16579f1b983 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000230.depth.png data/frame-000230.depth.png
9cdba2897dc399f09f58506c3c95329fbb9722d432e21b6c67320978b53c832a 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000235.depth.png data/frame-000235.depth.png
212bffc9b486071217989688f878e39fe14eb337ae597f41db5fb9590bb6580c 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000240.depth.png data/frame-000240.depth.png
bcdc16dbe28f65fbef0fdcce13c34bbe1e8f3441f2aefa17c18c081a2bb6103b 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000245.depth.png data/frame-000245.depth.png
909155bb59912fe219723e1a5d930e3d192c04124d51aa33fda090d2626c889a 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000250.depth.png data/frame-000250.depth.png
748a3dd46dac6b5f60b58a715fb1e3645b236301eda24c7d36e89a36e86981f2 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000255.depth.png data/frame-000255.depth.png
cbca60fa2a38d1188f066497f5a9c252fc499257af22815c6933cb8aed7f632b 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000260.depth.png data/frame-000260.depth.png
9c46f8c16d19cf10e17d16063631d6d78820866dda7e612e4ab8b36012d9991b 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000265.depth.png data/frame-000265.depth.png
7f056a99890436a57c16afe9180f48f3198dcc68c252c3d0c3c7babdd2fe77f8 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000270.depth.png data/frame-000270.depth.png
7a511fe8d0bc9bc29e73329cf258f317b622ab28b30773b4ba00173bd933f053 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000275.depth.png data/frame-000275.depth.png
6c258dcba84e1c7148f844d1ab36149760771e7cf262ab8000a37f727813aa7e 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000280.depth.png data/frame-000280.depth.png
e799e01b2736a6ed89537fcb477d413582fd4791a40817aa0d7f4f617cf344a3 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000285.depth.png data/frame-000285.depth.png
5c23994c4ed293017ee6678c74beba027d3422ab3b91a22a9b748c3986d7549b 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000290.depth.png data/frame-000290.depth.png
e297afeb2cdea3506f023c348714f55c35079305e53cc5cb10ea4d42c755b6c2 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000295.depth.png data/frame-000295.depth.png
a79512ba4b3a7ca7a7cb4fc6066f97a1cfdd2203ecc40ad6caa10a268a2bfa11 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000300.depth.png data/frame-000300.depth.png
4012a1eb36863ea7afe23a7debf77c7af9b79e328166b109f7f63df1ae203785 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000305.depth.png data/frame-000305.depth.png
ab1a07a34bb634e1599f029de17928a733bbf89b08b3163e009132135e1dca4e 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000310.depth.png data/frame-000310.depth.png
3558fd0009d05b5c75486404e8ebea585b12a9763274adb63c4c30bb5a64e45a 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000315.depth.png data/frame-000315.depth.png
5caffa4662514092bf151d1c487349a6ad4bb585e7f4d1184bdccfb8a3160102 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000320.depth.png data/frame-000320.depth.png
d46cdeb65d57d018182483766b4deb1066a42ab24441c176e7c31ce03ddadaae 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000325.depth.png data/frame-000325.depth.png
1ea4939100923b709da404f92d0dc436687c1aeae917fed80efea906b0b306d9 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000330.depth.png data/frame-000330.depth.png
67e42728cb87eedb92af6d7950f58086d0f8ed420f62877fbfbf86280d0498e1 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000335.depth.png data/frame-000335.depth.png
be4f9bc127403beda574caf515dc99eb921852e98f526aabd01fe5e61921ce37 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000340.depth.png data/frame-000340.depth.png
6ae7727a8dcd65f081fb3c5f601e5726fe6600e647fa9a7c6e9e7fe1d64bb50a 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000345.depth.png data/frame-000345.depth.png
a7b34fa27d497a90b8a4e679d171e7d8375b2f95456fc4a8a6033c7d191744c8 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000350.depth.png data/frame-000350.depth.png
732199eae47a68ea18093acb94f94aa37c5b22d5beb6ab3283fc9605b61e300a 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000355.depth.png data/frame-000355.depth.png
2435ccf6882eaf99364cefa388576e43020a562d420cd5f6508207f263b28dac 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000360.depth.png data/frame-000360.depth.png
def1903653fcb3fe015349456cf0dfcaebec1240241b61cc4a739193c52cb0b8 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000365.depth.png data/frame-000365.depth.png
05b83ed62cefbac780e2e092a3b8950416fe6473a40237d11da9a650047afb7e 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000370.depth.png data/frame-000370.depth.png
39e12be584ad540000c78a748a7d9b7180026baff8e86847a0d6dec0ed850674 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000375.depth.png data/frame-000375.depth.png
f5ef73eea1bd6b20a920940ccd2b1e8baef804f168c3a16b735003e954650e98 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000380.depth.png data/frame-000380.depth.png
d0a8e945fcc7ae1da39558f919d469b21db6d1cfbc229e4bc7480d9843a777cc 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000385.depth.png data/frame-000385.depth.png
9618d6d9a30d30ef20d3f17d9bd0f9a3ed64844186837541b4498dde691ee86d 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000390.depth.png data/frame-000390.depth.png
74f74a69213a34672bbb5b43136c703e8744ec361da72b13697df4123adb49a4 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000395.depth.png data/frame-000395.depth.png
f277e26c5a22f14b269abd8924fda3db3a26ad62c3f3c77bf1770d88df4a5f1f 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000400.depth.png data/frame-000400.depth.png
3a2463fdb5374863df259508f51ad81cb6bc92d81b869dda85cffd32c6adc8f1 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000405.depth.png data/frame-000405.depth.png
e2972e22a2fc1a803c3388ddba4913c064c323e19652294dc2475b6e3d4e5b42 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000410.depth.png data/frame-000410.depth.png
939c7cde10aad8bbbbc2998b408f0b8c74911488a73e8ec40d76b1015cf09d35 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000415.depth.png data/frame-000415.depth.png
77f8e5768335ad5f368c08f32649f8317f88a9f5a6a0e3b67caf8a5785066e8f 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000420.depth.png data/frame-000420.depth.png
35eb5ed1377ba47250964047cef97aa19ed19620a0f8bb456fc98712d5ec831b 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000425.depth.png data/frame-000425.depth.png
d5c33af650be9aaf7397b8ddb06f2ec4a7567a820aa4387e0dbd639310adc572 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000430.depth.png data/frame-000430.depth.png
0ea98528f861399ee81ac584a44e8a832b62c5c8ab747c03cce75612dc8101a1 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000435.depth.png data/frame-000435.depth.png
d8e11c21fa25c9e809da882ad27fe027a654028522d95a3e991e596fed18a228 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000440.depth.png data/frame-000440.depth.png
81325ceae6dfc5fa8c173e5070f7942d43e72bfd095fa1d5a996867ea3da9f69 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000445.depth.png data/frame-000445.depth.png
3c8abd5df644fe93c4480247395e75ff2317903da495fb438a227c6f6f5c76b5 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000450.depth.png data/frame-000450.depth.png
3bf1cca3fdd93f0d3c946158e6028bcfd3ebfb2d324dcdde79fa7e4c984d4294 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000455.depth.png data/frame-000455.depth.png
249fa2c03870abb056bd09be5c391af9a12ce521756fa68b41229bc07a953dd2 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000460.depth.png data/frame-000460.depth.png
833715967fa802b7e3289547bc0aaf8fdd4db9c959e44d4e65ca41dd917addf4 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000465.depth.png data/frame-000465.depth.png
449b6ce4e00d51d0d2fe6c82d016481279a58fecba2bab058c5b7d7bb26cb0a6 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000470.depth.png data/frame-000470.depth.png
5a2be0a2369e05b94b0fe377ff1dc1b9076b6932788b84e8122c7bd77db7a6de 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000475.depth.png data/frame-000475.depth.png
d673f92af52ae97f43c19a51afe41d04b066a4cb4270ea518a835c12b3a1419f 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000480.depth.png data/frame-000480.depth.png
ad21cfeda245dc3ee8a9d9c8e6d55cdb03105848412e108c09416e82af229b4e 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000485.depth.png data/frame-000485.depth.png
69e2bb6426cfea1b17b5cc5b123ae28eecfe855463a2d8c9fb4eedde15fc7aa3 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000490.depth.png data/frame-000490.depth.png
d55a4a366767d6d36b89626f422ddb0b1f1c04345a9f82d7bd5e0487b610b131 7scenes rgbd/7scenes_redkitchen_0000_0495/depth/frame-000495.depth.png data/frame-000495.depth.png
1c0ccfba757b765cc94da54c9cf20645e6772ddd6d2e355dfea22d60dd68ea6c 7scenes rgbd/7scenes_redkitchen_0000_0495/groundtruth.txt -
f44d9f50a49294d26c21a4f1b5dab966fca472c9abfdcb375c480f39a91cd58a 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000000.pose.txt data/frame-000000.pose.txt
a666ea45200229cbab4049c7798611f7099edf7751e76fa003b42e11abbb20bf 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000005.pose.txt data/frame-000005.pose.txt
48ed0b02bc24bef0a48023f04f3c3602f9d03c629684b1730830211148837b84 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000010.pose.txt data/frame-000010.pose.txt
1dca63aa1686d4adab8821da1cee813f101ad4bd6f9beb4b8715a26ac3409cd1 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000015.pose.txt data/frame-000015.pose.txt
4a978d8af6560b4f64ee5bdbd878915a78e3740377df6639b19aaf166df99125 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000020.pose.txt data/frame-000020.pose.txt
cb7007c0db14e305afea6ac905fe1d0e4b11edb7c023ec020b1ec9039d22eec7 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000025.pose.txt data/frame-000025.pose.txt
7e3660b9fbf2a933004a62fa5f74051c8735885052200ba535938de8a1505b6b 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000030.pose.txt data/frame-000030.pose.txt
c0f3833c1e6dbd29b8b10fa2d62a5cb2ac06873f6ffa6f0d954cec87e175a05a 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000035.pose.txt data/frame-000035.pose.txt
5bb27de4117424fca2a86dd3717d3461738c25769761621bb446e5d114f8817c 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000040.pose.txt data/frame-000040.pose.txt
aaacd2dc9ea0a9eaf1c816aeaf1c53f1629c75fc2729e1da83baa200e8d98428 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000045.pose.txt data/frame-000045.pose.txt
3c8a592abfbb9b6b80dc72c756031ececba1cc6b1bb336944c9014acf3e16897 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000050.pose.txt data/frame-000050.pose.txt
1457d765afc54db5bcf8eac77fb341da4a8e86f01e707115be793f76ee317d81 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000055.pose.txt data/frame-000055.pose.txt
af6ef8b96426079473430cac467e373588618a7f0d391e35a53dd4832c360b28 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000060.pose.txt data/frame-000060.pose.txt
6ad093db9473ee52e8c2e99bd105626d278db73f5b111f88b571006d4e180a48 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000065.pose.txt data/frame-000065.pose.txt
3611292b77350c4328941e3f8eb37c8c1b8ce986cffa7cf5e2287dbf9b296c46 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000070.pose.txt data/frame-000070.pose.txt
a6fe9c1727c12e4bc7ce7022032e936da0f274da79d18ecd666d241d42c8f966 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000075.pose.txt data/frame-000075.pose.txt
9d5f43b90753ee68349b03e01c8e167a9e72bb2cd2c62af011736f2de205a127 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000080.pose.txt data/frame-000080.pose.txt
b436b60fd8607381df57cc0edc31e5045b842c829757cb018798dc5228fdd578 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000085.pose.txt data/frame-000085.pose.txt
6ada92e1bf7a5b646d47ce09eb9decc20f0512a4a02306782b3a4de771598021 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000090.pose.txt data/frame-000090.pose.txt
c4ceef435d7ae2da623b2a5afeba20055da7ffa830a6fbf9638f7d9bc68f19ec 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000095.pose.txt data/frame-000095.pose.txt
2be5ebbf6aaa4e836f64879d52225c6c26d18b42186bd4b582fda65d3ad7ce30 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000100.pose.txt data/frame-000100.pose.txt
50ac6d24f47f3b39fc995aba00005a62262f71d17286533621b19c503aea1141 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000105.pose.txt data/frame-000105.pose.txt
6ba6bf8370f0beafaf639e946b7abf309dff25568d997ad47a4441254eab8d3f 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000110.pose.txt data/frame-000110.pose.txt
99c2c0a1cf943b58776ce3594325ae8d2966e9385e8d1610f194a0670e693589 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000115.pose.txt data/frame-000115.pose.txt
eb4d9fd56ef8c1de0046ab6949c9a32a7ff71c3edccb24bcebf58576f33a6d58 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000120.pose.txt data/frame-000120.pose.txt
4ea3b6c47ade7f98e02809962ee7214bda22b1c1a14872f5b6d35c1c4b0b758a 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000125.pose.txt data/frame-000125.pose.txt
fdd56e1a73d5c49d74af5c0771596d585c05b03ea43c65a7e71c9671c9138d0e 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000130.pose.txt data/frame-000130.pose.txt
659139af33b8c4ad71a42ce01a63d61bb717f6e8557286e6583579554ba3e2e5 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000135.pose.txt data/frame-000135.pose.txt
17f50ee7424341909bc41b9525c55b2bab4af813a4e001ca4ee309c8b2cf8959 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000140.pose.txt data/frame-000140.pose.txt
c2693e31f9055d72885ad4528274e8b9f1014c8a2192a30a8aa95ce67d1fcbfa 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000145.pose.txt data/frame-000145.pose.txt
4edaea7f28e43cc5d81d1d238df7c3804b38becafdbbb3083db9472d306caae3 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000150.pose.txt data/frame-000150.pose.txt
8ec5ddf22c0c89b72c205cc8447e2eb2121b77f6e1539f812c28a72d7b75b819 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000155.pose.txt data/frame-000155.pose.txt
91a81c67f205c539f24a6cab17a72c769031ede28404cf3cc0b6547ae63d83cc 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000160.pose.txt data/frame-000160.pose.txt
5ef4a1e865dd1d43e91d151e38f75b8d20dd5d2a94b32c5b058e9f04b9091fcb 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000165.pose.txt data/frame-000165.pose.txt
e719f57c0cbb0d93b9c394766b6d3518104a0621775f75bef65c4c4673c7842a 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000170.pose.txt data/frame-000170.pose.txt
fe315d022ae67e78cfc4ae11db59f15522f9dbdb006f262de50e6200aaee4763 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000175.pose.txt data/frame-000175.pose.txt
afc01d2fdd04d50eb583519b2c19ec5f128e3af393bcb9f3a28ba4b4761ef526 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000180.pose.txt data/frame-000180.pose.txt
4aeb84630bf194fa75bfb94fe964dc942de2ecbb46f146b0e4a6e2a97afa7e8e 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000185.pose.txt data/frame-000185.pose.txt
552a582dbbe109b62b06356e4e5008df2ad1ae7dee2ec55c2485d389e89331f4 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000190.pose.txt data/frame-000190.pose.txt
3558e953b138f6c2a71da472322837a8e433b8ca4081c336c7f2e56c2f3f4634 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000195.pose.txt data/frame-000195.pose.txt
21aa2d716fe6cd1cea2ad179ca6d9adf7dff72b234bc9d8477b1d62eae41da19 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000200.pose.txt data/frame-000200.pose.txt
9c268f3f88be65052bbe4fc6778276e6b4abf4234eec5e3121a22aa142e10b8d 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000205.pose.txt data/frame-000205.pose.txt
5d0b3daf326ad08cab107b09842419e569e91d456acf007ce21acf54e7a79a0b 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000210.pose.txt data/frame-000210.pose.txt
4a4ff321a7e1d48d5ee0c4884b45994e9940d59342212e392116d163b63c61fd 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000215.pose.txt data/frame-000215.pose.txt
44190d29a0f7ae096647a9623857aeab6210709e0e09f20b1b15da4619b621a7 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000220.pose.txt data/frame-000220.pose.txt
8a06fb1f109f2c330dce4dcd1c83d40e00b6a6c4ed295bab44a46a7caa1354cb 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000225.pose.txt data/frame-000225.pose.txt
9b6bcfec928239af165a24e6990c15a728da58c4a26e8be4ce70daab8ece82e3 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000230.pose.txt data/frame-000230.pose.txt
7b592bdc94b489af52aee352220310974921582aae44b4a5fa4067b21afd4c64 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000235.pose.txt data/frame-000235.pose.txt
f4e3fa64805b55034272a74ad495e5def5c36fcadf546cf25d81079cc98ddf29 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000240.pose.txt data/frame-000240.pose.txt
c9abab08fc7726549015f50443ec0c1a23c04dcf9169a09bd45413b1e27002db 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000245.pose.txt data/frame-000245.pose.txt
d910413671c467235ee43e58b75a92b6f40e00241cfaa05b28ffe2e9472e40fa 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000250.pose.txt data/frame-000250.pose.txt
cc2fcb78c28a90953fa832621fa4bfdabdb424ddfd7fff415db069ca16d21f6e 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000255.pose.txt data/frame-000255.pose.txt
6dd6b2c3c46c64642f1dc161a1edd71dbfa1581478bd71e90fcc090ed8e036c2 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000260.pose.txt data/frame-000260.pose.txt
e540ce89684104690711d84d6d882b33bfbfb6dfcb4f62bfcb684af479b92e48 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000265.pose.txt data/frame-000265.pose.txt
a393efda5cae5f438ec2b4636d557fa33e77571d7a0d0e1d5bf708d09aa5dc80 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000270.pose.txt data/frame-000270.pose.txt
d0daa4ae2fabab885039636c19a0f30a794c3232b946d594a11da56500a889b1 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000275.pose.txt data/frame-000275.pose.txt
f5c00f68eaa4b4a25e55409f7561ef37d86a117a3d1822c7169f30b367d8462a 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000280.pose.txt data/frame-000280.pose.txt
73c85a1e12b942233fc8bbffaac711ec362fc5331722ed5af04bc105acad0ae2 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000285.pose.txt data/frame-000285.pose.txt
567a75681a4835963b49c5bc66645856f6aea922ce0e2fec81c6e63b3da63086 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000290.pose.txt data/frame-000290.pose.txt
f9db0cc8f89e3d6de2df1fe4755b5dc0100afd8497f68ef887ee767d1b057264 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000295.pose.txt data/frame-000295.pose.txt
661b99bb36a717ddac779701472eb71f4e6b1757dcdc2827341143b2d614c3fc 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000300.pose.txt data/frame-000300.pose.txt
9970a5094b1332115a05e55e8e8f19a881ac63f64f23d6ae5e48c013191171d4 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000305.pose.txt data/frame-000305.pose.txt
657a211ee36537226a468e50dd7b411c0bfb7ff0b67858e4e154bd72d600a1c8 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000310.pose.txt data/frame-000310.pose.txt
d10633eb4272d361ccb229f4d5eedc410b1bf80b63a29e8f831531654377ee6d 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000315.pose.txt data/frame-000315.pose.txt
83df42b19218482cc2f1f2837cb5c24a8b3191edb60425b43482bddbe3c68e29 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000320.pose.txt data/frame-000320.pose.txt
1b63cc1225a6b7a8b80eb6f7082c6338118a1fd00635542aefc735a3afa0a6d4 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000325.pose.txt data/frame-000325.pose.txt
a28e85b1e9643280f8e156be2dde74e071818a8b9186ce0d7ae60c2d1f5bb2ec 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000330.pose.txt data/frame-000330.pose.txt
de542ec49b27c3cc4ba8cf4ed35849606cba7c61cb3da543e288d2dc6a71b470 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000335.pose.txt data/frame-000335.pose.txt
a169558e3e290837f1a9432d6e0c71c138d23fa4ba6a7d8669c74c4c8a249e45 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000340.pose.txt data/frame-000340.pose.txt
c33edf12d603ae54161cca43838f2872f6b650d7cbbe712c52b876e130761e88 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000345.pose.txt data/frame-000345.pose.txt
24560ecdcd7e686c3a4b8ff78408c71d160e8c298dba0025f67fd5dc618fb93f 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000350.pose.txt data/frame-000350.pose.txt
0ac3d077c51d2b79c7c00af0dc372f699124e04f802c946cb08bb478a0772572 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000355.pose.txt data/frame-000355.pose.txt
5739f69a701e7a47cb1a57c132da44f6778d3aa451c22e93f03fa3db90c274f9 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000360.pose.txt data/frame-000360.pose.txt
5587cc6b806a5ba5def7bdd607118784ef57ca49b0d3197ef4fbc6c2438c632f 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000365.pose.txt data/frame-000365.pose.txt
6a681436c8e79bb303f81857436a6f6e3ffaaa2c6ee69424fa7c54eb0377c063 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000370.pose.txt data/frame-000370.pose.txt
b89f0ad2861174b1e30c8d1d02c106c9a2672d41c51b7d00dad2803afcd4ab71 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000375.pose.txt data/frame-000375.pose.txt
9a2b8bdf5fb5b2854fb1a05b7861d7e95c0bc0623a3321f3d2f0fe0b4a7d71e5 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000380.pose.txt data/frame-000380.pose.txt
0b9d7c0133e75fef387b810d3824b71aa2cfda4d5c71c13505cb7fec53fb9f16 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000385.pose.txt data/frame-000385.pose.txt
e0b4137dea216d15f8fb4c1412f35977ffd0a4c9204cc0bf1be3825845380440 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000390.pose.txt data/frame-000390.pose.txt
6e18c75994933a2ff163c25b5bdcf49888ca49a0f9a5eaba21159b085f955ca3 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000395.pose.txt data/frame-000395.pose.txt
a0823691d5f3b17e1289b518c265415616fc8f41272ef0412d5745b0f925cbc9 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000400.pose.txt data/frame-000400.pose.txt
21c1d67595690edc4fa43bc09cef93a4eb765e644a4bdc9e28d62fa61a445b09 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000405.pose.txt data/frame-000405.pose.txt
249444ba7d7e2c6a53af790fb2cabdc6ac955a2c70215c401b6c3e4854a93a87 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000410.pose.txt data/frame-000410.pose.txt
6de6c53746697ed5cc0aca88acedf4af838ab887c60f638cc0fa77bf608b6d4c 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000415.pose.txt data/frame-000415.pose.txt
2b3d9b07876289136a8255d804dfff6f2ed31e550d64b7cef919a7363a8fe116 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000420.pose.txt data/frame-000420.pose.txt
f90b799e685f65d4ed0ac0837fd73d7cfd579102d48dac75178bfe60b194bf55 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000425.pose.txt data/frame-000425.pose.txt
a9fab74ba757017c46f9ce2547e31a02fb7a5c2774965db6c7646fd8e114520c 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000430.pose.txt data/frame-000430.pose.txt
e448977103ad4a7da9cf5466ee912edd770f5e68984d24c7dbb7ddc385cfa3c1 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000435.pose.txt data/frame-000435.pose.txt
b1f7bf44caf9de3e285ab330ab41ec806fd9b9d8d02dfab3c3c6b20f1c3cabaa 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000440.pose.txt data/frame-000440.pose.txt
700be8cdee7e57d92d5cb9a7bbc66f69abcf8224f98ebce3dbf3f4b70d20a03a 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000445.pose.txt data/frame-000445.pose.txt
e7a75daf7d5aee0f43fffc9b6bfd35388bfa5217f0e7b9b6d2291d8969293a05 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000450.pose.txt data/frame-000450.pose.txt
e6a27c2801999d2d3413d1899e26976588857cc77108a7d55e123c257a8cc870 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000455.pose.txt data/frame-000455.pose.txt
a3e989202073d8940e7d75c58fa3b886679b4691d1ed7fbdc145aba8ab860254 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000460.pose.txt data/frame-000460.pose.txt
374cc2e90b8f5c5725710a22521255e8311f135526a2c4a415da7d44d45f2627 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000465.pose.txt data/frame-000465.pose.txt
2b2513124462704d3b13f9c5fad13242a15b075385905654a0e783e3012865fc 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000470.pose.txt data/frame-000470.pose.txt
f3c8560f74f3bf61e3ef3ede2f700b729a4ed4dd971788a74d866f05157cedd8 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000475.pose.txt data/frame-000475.pose.txt
5d42c650c5d6c37fa09c310dff780f21ba849fb22202f3f30f6878893a569879 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000480.pose.txt data/frame-000480.pose.txt
5a903f23a2098aa509d53fc0267d1e79ac33db9022e97056d06584d1d354873f 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000485.pose.txt data/frame-000485.pose.txt
50252096bdf85fff46486eafbdaed3b6f35efd73480c15a798b96975cf24c8f1 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000490.pose.txt data/frame-000490.pose.txt
1d0ba2607d4f85cf20b266c97cab82dbd948c65d58c28f4924beb19a77c4adc6 7scenes rgbd/7scenes_redkitchen_0000_0495/pose/frame-000495.pose.txt data/frame-000495.pose.txt
fef1a8be9ee2fcbeede4fc2667891d53df01d1708c0bc89c26c4836948722b13 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb.txt -
15ccc31803e19e7371e9b5ac12fcf1fca77934b3780620a26c5edb4cc738c43f 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000000.color.jpg data/frame-000000.color.jpg
e125633b564bab8b32d2d7fc3a1210d9fc08ebf4074e83571592334d54159f8a 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000005.color.jpg data/frame-000005.color.jpg
e110f83c35a4638c7bad820e6a5d428ccb27dd0b6bfb5c216346088c5bff3eba 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000010.color.jpg data/frame-000010.color.jpg
bf8b9b9283dbac01da411162864056d566f3dd43dd585f74c62a9292dd322d03 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000015.color.jpg data/frame-000015.color.jpg
78a203d0a4ce0dd3fff465e78eb9cfea44c482cca3d57e4a4bd7f2ff9ebeeb10 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000020.color.jpg data/frame-000020.color.jpg
034c366af21743efd5c1d47610bcc75f311712c5de377edd553ada6d6e6b1153 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000025.color.jpg data/frame-000025.color.jpg
41e1a7195c75ea3d51056958c8da00dd32c1306debf82df7137852653e4427ad 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000030.color.jpg data/frame-000030.color.jpg
215c4d8a9db948c03d0cb0693167be5add8d72274f2a403e6a01d404b1b302a0 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000035.color.jpg data/frame-000035.color.jpg
d98aaf5372ffd8bc46c8f7ea5f945c21445dd7f6a4c935587c99f0af9622b991 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000040.color.jpg data/frame-000040.color.jpg
dc014bcd28cc16ff8f5106ef50f41aa2df359b85dbba98d56fe45743c52086b3 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000045.color.jpg data/frame-000045.color.jpg
c353fdecb25c0ed8df6541b5c61eeb11f705a327c09fa6070c9e671a69a29788 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000050.color.jpg data/frame-000050.color.jpg
d03fdabc93699074c40c2effe2f6905c577287f841de8710ce1b659ff54f32b6 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000055.color.jpg data/frame-000055.color.jpg
c01dc8de8e0caa272c916795097b6af4bd9459fc370c674832421642f225f35d 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000060.color.jpg data/frame-000060.color.jpg
0aefd058e340dd388299acec169910d806716b39b6639cf18b76b9089dfb833a 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000065.color.jpg data/frame-000065.color.jpg
0db92fb1fba55c561f59a551179a5e514c63cea32b5558a3276e17395b8da3a7 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000070.color.jpg data/frame-000070.color.jpg
9299ac838e0cce0245becbee1dd8958d953d8017c0873bb82ebb63493b05f983 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000075.color.jpg data/frame-000075.color.jpg
087e43435a48522ba4a55e953c6862a6283221d63210693580cb6efa60c3b8c2 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000080.color.jpg data/frame-000080.color.jpg
5e4903a982927e4668be04230fa17feec9fa6c1f5d718c21729cd626206cc782 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000085.color.jpg data/frame-000085.color.jpg
c222e5ce301511f7010a892c911aba72788a60bbafa8c6b103a328a72f411552 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000090.color.jpg data/frame-000090.color.jpg
e62a77179374069f902175308de548494b8ff69956dc4bd51f0afef4dff4b7b4 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000095.color.jpg data/frame-000095.color.jpg
d20c8a0eaaba6acb7643399faeb90ebecb9fbada90ba913a974be110e77d0581 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000100.color.jpg data/frame-000100.color.jpg
6e97fec7ab12ab7edd28229dd91acea6b7a06fc680b830939107c45f5a90b8b0 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000105.color.jpg data/frame-000105.color.jpg
dc66b671e89a8cf638dfbce11dee3619f3d22dc2223e42891a9d0cc9034c689e 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000110.color.jpg data/frame-000110.color.jpg
10b79f6e4e9fb2a1ba30b533ec8f11eb8551c1ba1215a4edf3c85b2f71ed75f1 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000115.color.jpg data/frame-000115.color.jpg
9c01aebc6a714d867756baefcd9b3629345f0dbfb2f6f453c4cf4a70c1108875 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000120.color.jpg data/frame-000120.color.jpg
09b26c4fee705c0a5b9d6e6c806cb2d7d0943b43f4a37d1035a9d7d78b1bf37c 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000125.color.jpg data/frame-000125.color.jpg
51ee5ebb2533f31118adba351a89d96d64698465d8c8ce4b96801b8f30cf8021 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000130.color.jpg data/frame-000130.color.jpg
b6c68204c634f66fa11f59bca84ae48dce6ba66fa609714873d20d83f1aab57f 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000135.color.jpg data/frame-000135.color.jpg
307aa8f5e5e5057887ccd02e101abb57c2a0fe2aebbfbf8edddc37931c80fdb7 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000140.color.jpg data/frame-000140.color.jpg
bd56aef98bb7ecbf9071b1728d44f7c2d743edaf844b6e32512c0ef0433f9b09 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000145.color.jpg data/frame-000145.color.jpg
28cdbb1f55283b597126d74e754be3ace008f6ed96904601627ba7174bae894a 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000150.color.jpg data/frame-000150.color.jpg
bbd26727f496aeee25c4a74fd00b982bb0b13797c80167888b1fe771e0231475 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000155.color.jpg data/frame-000155.color.jpg
57b8f8e2c7be6f8cdc3efe17c4ea579bd57d6303bc7ce2d9758d4c0ce2940408 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000160.color.jpg data/frame-000160.color.jpg
f0d994de4c96ec239744f07a7e0ea6b86fface688c1eee768fc420323f1bb8c6 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000165.color.jpg data/frame-000165.color.jpg
49c1b11d64eac66863dfbf0d15b5356d20ddd8c075bd99ed459c0f4472465398 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000170.color.jpg data/frame-000170.color.jpg
15480112b4b88488e0305af1ac4651364dc9c5f2dae2204e74c8481e1d5b59ed 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000175.color.jpg data/frame-000175.color.jpg
fc7c087cf27114a4e4db8dec99c2e61b895ddb4bbe72762a7c2c332a5c2a0626 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000180.color.jpg data/frame-000180.color.jpg
20013eb67067767d9b546d42a630c9b6ee81346605f9be4ddeaf26b7fba4842a 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000185.color.jpg data/frame-000185.color.jpg
77304a1b17579e8c72a93c3ebcda1fcac4c37f963d4a87154bf5d8bc7cf55dc0 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000190.color.jpg data/frame-000190.color.jpg
b61b07fd204358dfc8decc8d0c99ec6fb8441573d890933117194208eb7c52d5 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000195.color.jpg data/frame-000195.color.jpg
7badf5f3d53337343b47589cf7690230be35e2ee495c2f7e3207a42a20b23d8c 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000200.color.jpg data/frame-000200.color.jpg
2754fc9872bd3311b87cd85f8cb31be86a06f44982520a750e80effb9678c46b 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000205.color.jpg data/frame-000205.color.jpg
a09a99e051248002c1b76668e98847555c870cd1295af583484d68a8025f0186 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000210.color.jpg data/frame-000210.color.jpg
b680b1a99459858ee491c3876248d2beeb459f11fa539b13aeb057b34e2d9c27 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000215.color.jpg data/frame-000215.color.jpg
29a32c1c954e0c1aba8f0b5e590f60e001b14d5dac6163c9bf5623ebe5c3cf4b 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000220.color.jpg data/frame-000220.color.jpg
5497f4e04d9bda03470d60d48fc73b9501616c67a410f5c685f89506fb61c822 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000225.color.jpg data/frame-000225.color.jpg
78312b181b3ee849d6ec6d03f2ea8c9f9695e91f380552f00bf7b01bbe7e8b3f 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000230.color.jpg data/frame-000230.color.jpg
e3d703142b895c8a067407cfd899f0720586e2e261c62c6a967c8efaa6bbba9d 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000235.color.jpg data/frame-000235.color.jpg
3a782d81c096f2558805e1607e695307165fc51b9d42252d4690b92315091948 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000240.color.jpg data/frame-000240.color.jpg
2c4128e12467487b1fe030e2920e8222e16f6fcab757a48be26d488f84541cb3 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000245.color.jpg data/frame-000245.color.jpg
87e351e4f865eb69d03a2833417fd558076a98dec1b12cf53fde204b6a55697f 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000250.color.jpg data/frame-000250.color.jpg
24a6d9c104ebf6077ac38615ba53270945a4114b3f896f161a28ea37156f4b44 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000255.color.jpg data/frame-000255.color.jpg
59e821e708792819a40dd6bda835afd9dcafe470585fe84cb04d617baf3827f2 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000260.color.jpg data/frame-000260.color.jpg
6198fb1c99c705e68a8360bd892dca3ec4e31dda63bf7c5f83e6696c6912352d 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000265.color.jpg data/frame-000265.color.jpg
65702bae84fc555a6b07cfddd6a6e522d8303d8ad748f07062f5adc9ac3995e2 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000270.color.jpg data/frame-000270.color.jpg
20760cb3fa155e4c0e54ceb47ae79bab07d4db80763755d6c555e49cbd8d2957 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000275.color.jpg data/frame-000275.color.jpg
4927904c45e6fbd356497970e656a4d90db9caaff653dce3a30896406a780c7c 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000280.color.jpg data/frame-000280.color.jpg
9f5037c879cb59bcb5fb07a13a2d65225343954eedd0343e477d699e6aa7f55f 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000285.color.jpg data/frame-000285.color.jpg
fa2838015d316568bda2ec80d660ab8b9e24ed57c239ab86ca7d1a9d55d92375 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000290.color.jpg data/frame-000290.color.jpg
b246612550f9fc43a9056ace2785bab77c99675e940b41d678a9568d84d9c139 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000295.color.jpg data/frame-000295.color.jpg
e19fddc790f8ce4f93363739d7882c9d6bb28f2f107fb4a43121fda23d763d90 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000300.color.jpg data/frame-000300.color.jpg
a133f99ee3d792ab592b352eeb6eda3f91ef258dfff400ced298775c02a73994 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000305.color.jpg data/frame-000305.color.jpg
98a57ca4a01c2b5c125cc886e62ebc3586d0e90b638e091392be34c11bc12c85 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000310.color.jpg data/frame-000310.color.jpg
d27781b4d7773f174ce92d296ac68f7e950fc5fcd5750e341d93625ac0cd34be 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000315.color.jpg data/frame-000315.color.jpg
231b0ba696d3db345797d893ec186f4348190d948422554a014aa65ab1a842a7 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000320.color.jpg data/frame-000320.color.jpg
1f4c7f9aa6e0564fa91a67f6048bf9d6e8910a83f1eeda4ebbff7f1c7d4efec5 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000325.color.jpg data/frame-000325.color.jpg
2c4d1956b48f738d6509007fe4506c11036d4d8a021836bd387b44aa7adde238 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000330.color.jpg data/frame-000330.color.jpg
7383337dc8e093699f908e7e5b927543ef73c098a41d8950c9a5de2cbd84fc7e 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000335.color.jpg data/frame-000335.color.jpg
fad4b7f9eb52650d9473332ff6d21b02044c409962c9b0d28fdedf4a6bd58816 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000340.color.jpg data/frame-000340.color.jpg
229e5a5034a58557fc74af90df5822b492daa7eca9318862238d2a3d56c0e55e 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000345.color.jpg data/frame-000345.color.jpg
b1f1d73755ce4f24d710f812c6a8da578d62211748d2269df77b13ed3c9582b9 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000350.color.jpg data/frame-000350.color.jpg
3f9d6641f2da679fc3e2f46553169fb48ea4bc9ecd4cab311cb6814eca642bc2 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000355.color.jpg data/frame-000355.color.jpg
a971dbe6c2a23e06e9b51c4d10e589b2485adf8942d30b375e3d44ade35993d4 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000360.color.jpg data/frame-000360.color.jpg
c0696c6ec6818fff5d24a5484c60b2595dea947376fefc99dd3823c0a9c94059 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000365.color.jpg data/frame-000365.color.jpg
672d7e96ad6bba40ccb519d7f5b5509a883a2bb75a79df9fea16f85327daa549 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000370.color.jpg data/frame-000370.color.jpg
733c2cbfe6d1f37f48506918bb9e476f7be7d113759c6452945b47398b1a701d 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000375.color.jpg data/frame-000375.color.jpg
0309e50c99d14ab0d051cff1f01347d20185f586b5ba1e660189667a3d5a571b 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000380.color.jpg data/frame-000380.color.jpg
c253a48446c9f590632adb677745b0e57ad3016c4dde7abdfc59429ebf7e9feb 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000385.color.jpg data/frame-000385.color.jpg
a9b73013c991df03d74d9aa05dff9ea2edbf1b9991367a3759c1c897c17023bf 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000390.color.jpg data/frame-000390.color.jpg
277a64fe2b2150378f7ab94947bb06527388a1d9559ca0493f93aac6a52db6e0 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000395.color.jpg data/frame-000395.color.jpg
5178336bc285848e35c08557be9c49f1324ec620e3104279d1cdd68f653ccad1 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000400.color.jpg data/frame-000400.color.jpg
3ab9a0388750db15a551139ffbd2f11dee425301fb81b179ead12ab468286697 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000405.color.jpg data/frame-000405.color.jpg
056dde71cbe052d72df3d6f31726cb41416281c0d627b7d21b2f10ffb3462f21 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000410.color.jpg data/frame-000410.color.jpg
cbdea2d1c2c5247e3c16a7ad3e0540cb4504bcb03f96076506b11c28b0b28630 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000415.color.jpg data/frame-000415.color.jpg
063d9a7bf466aed1fea4d39f17b486dc53ccfec068f079d44d7138fbc0a18a1f 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000420.color.jpg data/frame-000420.color.jpg
3f0abe630b5e6bbc8059878cd61021593a72fd8725a080bbf38a1ab537cfc0c6 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000425.color.jpg data/frame-000425.color.jpg
bd331048c951f81b7876b19824a0fc19ce596c28cfdf60b49624842785f94897 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000430.color.jpg data/frame-000430.color.jpg
27048abeee5c0c21c5416ad77f05fe84bc23d1e3dd626d61c7e78b99185198e7 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000435.color.jpg data/frame-000435.color.jpg
1f9d767599180cf0f5908c621493603e2f403e7dea77a0f6de388e8b4029690b 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000440.color.jpg data/frame-000440.color.jpg
97cb3a7231864bc8cb631f5433a7d02e745a911eab7641fd1d822cd5761d704f 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000445.color.jpg data/frame-000445.color.jpg
981d5ab49a57eb3e7570f7b7d556b04f51083da75ec11bac583936e601fd330d 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000450.color.jpg data/frame-000450.color.jpg
e0e5ab9f4e640b76ad7f3820a35678a3a9245f5c88e0285d49efa19c79f383f6 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000455.color.jpg data/frame-000455.color.jpg
c6633e0f2e12ea639407e4a89681c6073034d80191834b039d216356f7c1bbd4 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000460.color.jpg data/frame-000460.color.jpg
32c0badb7a69ccc7f8cdfcce154b927fba927c20307657fafe31abaa8a775dfa 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000465.color.jpg data/frame-000465.color.jpg
7b3342f5a66c4d4b1c23160ddf5f8c8d3fe187a445d0680e6631837ad6cacc5d 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000470.color.jpg data/frame-000470.color.jpg
f0a2b31e696333b48a586cbc6e649aff337dae95053f4e7abbb79f3d00dd951f 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000475.color.jpg data/frame-000475.color.jpg
f01f2810bca0465cd912264936f2610cfab1dd162416763c8e2e30caaa27450b 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000480.color.jpg data/frame-000480.color.jpg
2d2ae2a74758ca5b0c5f8a31688c1bd26156e9939132176e7e24dcba17fb5cdf 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000485.color.jpg data/frame-000485.color.jpg
941a493360b5b6485e66887870269d47c1b2362206dc0aeef0a8a14499678dbd 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000490.color.jpg data/frame-000490.color.jpg
2d8bfec11f2283ae990e5b65272ffb21507acd0767b8b7acd7bd870de90c31dd 7scenes rgbd/7scenes_redkitchen_0000_0495/rgb/frame-000495.color.jpg data/frame-000495.color.jpg
791e03916e7d06371132fac4d4a7d98c6324760306855cf2b7878352386b19a3 open3d rgbd/single_frames/NYU_color.ppm examples/TestData/RGBD/other_formats/NYU_color.ppm
da8fa137043ca8a516a7393a2a2a85abb920479201110292b149904ea607440b open3d rgbd/single_frames/NYU_depth.pgm examples/TestData/RGBD/other_formats/NYU_depth.pgm
c9e33818fdac30f2a1227e92b4f0c7677dbb2ded3aa4e117793a0d133495efc9 open3d rgbd/single_frames/SUN_color.jpg examples/TestData/RGBD/other_formats/SUN_color.jpg
4192a2f8d50bd0b81ed439fbcbf5cb068f15c0fc1e5391b3803a2b36b2e78c8f open3d rgbd/single_frames/SUN_depth.png examples/TestData/RGBD/other_formats/SUN_depth.png
a84f24b35cfa73f3180d63a6f6068cbae637ff5c3612c8ef05882ce3979607cc open3d rgbd/single_frames/TUM_color.png examples/TestData/RGBD/other_formats/TUM_color.png
a27d96e82731bc84a7af16704837ff7c5492c132ca875af6dcf47685ee6c94a4 open3d rgbd/single_frames/TUM_depth.png examples/TestData/RGBD/other_formats/TUM_depth.png
dc59fc59500000a718cc8d083251c8a6993bc478f4602de6301b2dd4aa664c8c dvo_sheng rgbd/tum_fr1xyz_pair/dep_curr.png examples/case_1/dep_curr.png
e4b6c068330d03b3b4cb6aed0a4f1e61c0467a27364b3133948770b883c70510 dvo_sheng rgbd/tum_fr1xyz_pair/dep_prev.png examples/case_1/dep_prev.png
a11f2cdbe8db9a88c22ec7996317f62a538d0b90ce3852e53f59a85965fb422f dvo_sheng rgbd/tum_fr1xyz_pair/img_curr.png examples/case_1/img_curr.png
cd3f24c9902586ae22d303092d12c208e024b30130147c198fcd3b01a29f5682 dvo_sheng rgbd/tum_fr1xyz_pair/img_prev.png examples/case_1/img_prev.png
fb0aa231cd261784f75f937279ec24198fdde7297f959188a40a053c9d637f8c dvo_sheng rgbd/tum_fr1xyz_pair/kinect_params.txt examples/kinect_params.txt
364a8ecef1bdc84b3a7e1652957138eeb63a886498e25ff9658c59b6ead5335f dvo_sheng rgbd/tum_fr1xyz_pair/pose_curr.txt examples/case_1/pose_curr.txt
b96c82152cc2215068912dea904b0d7bde1657b8c4a7249ac3041a326a9f1adf dvo_sheng rgbd/tum_fr1xyz_pair/pose_prev.txt examples/case_1/pose_prev.txt
9601009dd5124a841ce58f5d9681f28cdaadde651db02e2e9151e335f4aa5ef4 evo rgbd/tum_trajectories/fr2_desk_ORB.txt test/data/fr2_desk_ORB.txt
bf5550abc204be564b9922375c2e3a53570867faaf96adcace0bdc07a3affaac evo rgbd/tum_trajectories/fr2_desk_ORB_kf_mono.txt test/data/fr2_desk_ORB_kf_mono.txt
0d8e0119a4e9592b886c5ca954472c3270c01814dd2059fbe196d5c24c8f3d17 evo rgbd/tum_trajectories/fr2_desk_groundtruth.txt test/data/fr2_desk_groundtruth.txt
f73ff3643d5fd38f99d01eaf96227a1af6437ca90aa2d2d35ab2f794bc36d5de evo rgbd/tum_trajectories/freiburg1_xyz-ORB_kf_mono.txt test/data/freiburg1_xyz-ORB_kf_mono.txt
aac0319a6ef4e1cdf61e779d2152b95aa7e9f7b1749d6d18717b43ddabffede2 evo rgbd/tum_trajectories/freiburg1_xyz-groundtruth.txt test/data/freiburg1_xyz-groundtruth.txt
bbcd66c6e19e6037ee550c66d307c9a008ed29ef8bd9baa6bbda119a1a51a3ee evo rgbd/tum_trajectories/freiburg1_xyz-rgbdslam.txt test/data/freiburg1_xyz-rgbdslam.txt
12f5c812792498ba6a9d3968590af8908d094e8bb8ddb183f1ce7c8f33048a44 evo rgbd/tum_trajectories/freiburg1_xyz-rgbdslam_drift.txt test/data/freiburg1_xyz-rgbdslam_drift.txt
6bcf823af144d5c60cb789a6319a98bed195c194d509a0152be006f386f006a9 bunny scans/bunny/bun.conf.reference.txt -
b83b21f3fb4d4581aebafebeb9c8cfbfe8eb94210b785342b4cc5ec71f18de07 bunny scans/bunny/bun000_clean.ply -
bbbeb1912fef9171389e0f9dddb2598909cc604710f44886b567e995a2ff9e63 bunny scans/bunny/bun045_clean.ply -
6008d05547c6b8f6050cea7ca4683f1be3fac260235cad47eb5e61ee05d2ce23 segyio seismic/f3_crop.sgy test-data/f3.sgy
a4a03b1e452c93d8dfcf8cde151b89b28bf6df4fc1382500ceffdc440027caa5 seg2017 seismic/f3_inline362.ascii 1710_Colored_inversion/data/export_inline362.ascii
d91e4801b7b51193e1ca4bdf4b13d33e0c8caf11a8250ed75f64dc8ab94cef33 penobscot_labels seismic/penobscot_sections/penobscot_sections_1075_1092.npz -
649957719731a841e274e2ef497b6331370bbe79fe6f1b9f5d644b32c2173d0c osv seismic/references/costarica_crf_ft.f32be data/2d/crf/ft.dat
424aecbb4f0c472d0dd018e4866e340b64e894d1da814e76dac53b2f110cc6a0 osv seismic/references/costarica_crf_osv_fvt.f32be data/2d/crf/fvt.dat
6387e1422bacc8e65a58e59d3b73f23b796cb94c2c92611dec1440f99ebfbe0d seg2014 seismic/penobscot_xl1155.sgy 1410_Phase/data/penobscot_xl1155.sgy
2b6eb2d759256d51e54a8dbd1c247ef89d0a2aafb1c08a72731981373702f1fb osv seismic/sections/campos_gx373.f32be data/2d/campos/gx373.dat
14af1bf28d3fbaabd78643967ebbb07b0d381f1a51faccb367d07be61922007c osv seismic/sections/costarica_crf.f32be data/2d/crf/gx3366.dat
af7b5654c8c6b5689d2f78d7a4c3f22cb1bddff86b0664cf82cb02f5fec3f539 osv seismic/sections/costarica_gx808.f32be data/2d/crf/gx808.dat
615c7cc1cbdbd19ff011a3848484aee094edb491efef29f93b065245ae623a14 osv seismic/sections/costarica_gx809.f32be data/2d/crf/gx809.dat
2952db4c32ebf93b383e6c8b2bd6802a2b887a22997545a4058bd97d876da46f mhe_f3 seismic/sections/f3_f3d178sub2.f32be data/2d/f3d/f3d178Sub2.dat
47840a7cbc8db0f944c8c4327897e1002219893d931129405cf13326247b7c61 osv_f3 seismic/sections/f3_f3d75s.f32be data/2d/f3d/f3d75s.dat
df2e996e33bb75095325ec3323e9c02afef795f74f99c7e7d73a42214c103f61 mhe_teapot seismic/sections/teapot_tp73.f32be data/2d/tpd/tp73.dat
0a67eb280b820bb459362721910283771b511b69b51f928c105336d98b43194d igi seismic/sections/teapot_tpd.f32be data/tpd/seis.dat
75a4bae98a6c82fe6a01e2e66aab747306836c34296a42bf2252b5e074e5af44 segysak seismic/volve_fullstack_twt_arbline.sgy examples/data/volve10r12-full-twt-arb.sgy
80a2fcc668fe03aec127d721e129a5159524cd8fd73965424d2902fde353cb69 segysak seismic/volve_licence.txt examples/data/licence
f2194eaef8ad675f2efe26845ed61e37451472cc23a770d0ec337778b61ae9a5 segysak seismic/volve_migvel_depth_sub3d.sgy examples/data/volve10-migvel-depth-sub3d.sgy
75867b3e75cfc3c2e96da9f753c04c9fbaa6a59468dea13e2859f3109b38bd66 laspy terrain/autzen_trim.laz tests/data/autzen_trim.laz
b6ed6303945b0d85b59c314df8a265c91a85b9768dc70dff3c5df35970e49b6b pysheds terrain/dem_hydrosheds_dfw.tif data/dem.tif
"""

# segyio's test data (equinor/segyio test-data/, 90 files; its README says what each one tests): not in the data
# directory, always downloaded. Same columns as _TABLE.
_DOWNLOAD_ONLY_TABLE = """
7de3f6dd742069bf489626d6ee494d5657f5fae37f89ce43d24f73bed47f8faa segyio_tests seismic/segyio_test_data/1x1.sgy test-data/1x1.sgy
f08308d76c78564667d6ac13f2f315eec826239e8add42dac3cf1e0f293a3fe6 segyio_tests seismic/segyio_test_data/1xN.sgy test-data/1xN.sgy
360b1bb041124d14a62477f2cf61495aa98539b53123590a048fccd24556de3a segyio_tests seismic/segyio_test_data/Mx1.sgy test-data/Mx1.sgy
6269ebe48c82527d3fe20813fc4c97bf7fefbd923d8e62eb7d4797a32e1dcc72 segyio_tests seismic/segyio_test_data/acute-small.sgy test-data/acute-small.sgy
c5e019183b5d07c25fda617e51fad3238be32030591c9e253fa24865bcf7b8cf segyio_tests seismic/segyio_test_data/broken.sgy test-data/broken.sgy
b1531c7173ca2b570dd2c9b7d1b54c825606f9afb1f4aa0cc769cf399af7226b segyio_tests seismic/segyio_test_data/decrement-lsb.sgy test-data/decrement-lsb.sgy
62862a2473e83186b3b51838a9129345cec3b45839a8a6de75017e131b128c91 segyio_tests seismic/segyio_test_data/decrement.sgy test-data/decrement.sgy
b3f9943fb3db56263b446be5f5fc7ba1c51d7facbc7a558b694db91d60f0fa33 segyio_tests seismic/segyio_test_data/delay-scalar.sgy test-data/delay-scalar.sgy
7820e102547c938fcc86236ca928e5e7b2854b8585201b777d7bf980ad04af3e segyio seismic/segyio_test_data/f3-lsb.sgy test-data/f3-lsb.sgy
6008d05547c6b8f6050cea7ca4683f1be3fac260235cad47eb5e61ee05d2ce23 segyio seismic/segyio_test_data/f3.sgy test-data/f3.sgy
d2054569cf3a039a381a7ea30b236a8bcb025a160342b9ea791093a8ff021fe0 segyio_tests seismic/segyio_test_data/increment-lsb.sgy test-data/increment-lsb.sgy
eae59cc02ce50e83cfc395dc4bb50992897850d385eaf9ec49a7459dce1adde2 segyio_tests seismic/segyio_test_data/increment.sgy test-data/increment.sgy
edd425179124542c038fffc12fab68b1b682d901585fefcca391a5a694aa99cf segyio_tests seismic/segyio_test_data/interval-neg-bin-neg-trace.sgy test-data/interval-neg-bin-neg-trace.sgy
d5d941871794605b69fd2ef49ce9fb4f161113df0c29dde21f97be27362caf5d segyio_tests seismic/segyio_test_data/interval-neg-bin-pos-trace.sgy test-data/interval-neg-bin-pos-trace.sgy
84187c00aea13fb4bbd2d2fb1dc8899d8654ca48ff6b73b481387b46a957383b segyio_tests seismic/segyio_test_data/interval-pos-bin-neg-trace.sgy test-data/interval-pos-bin-neg-trace.sgy
af64af5347f00d8c1cbc7babbacfbf1e48a1143d901d5e434177cc9da0e937e3 segyio_tests seismic/segyio_test_data/inv-acute-small.sgy test-data/inv-acute-small.sgy
e43bb9f3ec1d80b84c1864413fdcc94bf828341a3c1621197df2cd930eeed0b2 segyio_tests seismic/segyio_test_data/left-small.sgy test-data/left-small.sgy
514719491d7be4893cf89447e605a85a781e8ec4bd67b21eee2573d96610fbb9 segyio_tests seismic/segyio_test_data/long.sgy test-data/long.sgy
72816b3a78d1bd48bdaeeba02af45fa454c8b8e1ba96eec85a6d2d359cede8ce segyio_tests seismic/segyio_test_data/mapping-all-types-lsb.sgy test-data/mapping-all-types-lsb.sgy
d3a7aac97f0a08f3a0bd1120b4636b6632582ae6d4b2746440ff1187d9cea062 segyio_tests seismic/segyio_test_data/mapping-all-types.sgy test-data/mapping-all-types.sgy
b005a797dfa4a09c12e398ddd317c1c5b38cf782af91c75dd2cea850c6100b06 segyio_tests seismic/segyio_test_data/mapping-default.sgy test-data/mapping-default.sgy
89fd8bfd6c7b2558a82aa47621de46dd509cf5baabc62455c99d41b08a8b3c5c segyio_tests seismic/segyio_test_data/mapping-empty.sgy test-data/mapping-empty.sgy
d14529407ea2289199f9ea515c32a02583f63c37844064b5ddbc6e64e3f55899 segyio_tests seismic/segyio_test_data/mapping-encoding-ext1.sgy test-data/mapping-encoding-ext1.sgy
8dc7b22d32ab5725614f8e84b716edfeac20113bafad722df51987b930a8bf13 segyio_tests seismic/segyio_test_data/mapping-encoding-private.sgy test-data/mapping-encoding-private.sgy
6cb10c6edb251eed1fa2a60da694ec0dc4ebce5e591b0781aebededba6732230 segyio_tests seismic/segyio_test_data/mapping-invalid-attribute.sgy test-data/mapping-invalid-attribute.sgy
98079fb5916b89f717100dcc54ff20ef46b5a40391c1c2e15eb3f7d288803892 segyio_tests seismic/segyio_test_data/mapping-invalid-root.sgy test-data/mapping-invalid-root.sgy
383a454d3e9cc341c39e5690aa564eac3cacacbcf0a74bb2901fbcfd3b87e6a0 segyio_tests seismic/segyio_test_data/mapping-invalid-value.sgy test-data/mapping-invalid-value.sgy
7e059d3f1c8371ecdd83a797baef3be62bba04c7837e94860a7a9f5ca731ed9f segyio_tests seismic/segyio_test_data/mapping-minimal.sgy test-data/mapping-minimal.sgy
739b98b305c5fd9b77152875601269054911be6bfffd258bec0e7841701e905b segyio_tests seismic/segyio_test_data/mapping-mixed-order.sgy test-data/mapping-mixed-order.sgy
17ab9f1a7e16cdecab62bfd81fcadce15f0d6e4af2edf66eece4ab963de03162 segyio_tests seismic/segyio_test_data/mapping-multiple-stanzas.sgy test-data/mapping-multiple-stanzas.sgy
a794907a5dda75feee72bb8383de9ff0e3e93d333a6540d40b451b2207d70509 segyio_tests seismic/segyio_test_data/mapping-no-extension1.sgy test-data/mapping-no-extension1.sgy
f33656cb907f0ee7bdc977bf7642a1ea0a239fe6b06d7408cb8a0f03b02c0cac segyio_tests seismic/segyio_test_data/mapping-shifted.sgy test-data/mapping-shifted.sgy
40925df0058e2fedfc1dedfe488815a4bcded038e5df8943db39884a6a947b58 segyio_tests seismic/segyio_test_data/mapping-unparsable.sgy test-data/mapping-unparsable.sgy
b51214b340de0585655478c6aa0e933a5c4c3b5eb143c65e1f890cdf545d74dd segyio_tests seismic/segyio_test_data/mapping-unsupported-type.sgy test-data/mapping-unsupported-type.sgy
e91fead35dd1ff8860da74ef3085dd9637f75ab7b4481b7fe20d773b3cb9fd24 segyio_tests seismic/segyio_test_data/multi-text.sgy test-data/multi-text.sgy
7db3342a74f6123f913258960886442eeebc1d0a374dd11d60cbb62c3684b510 segyio seismic/segyio_test_data/multiformats/Format10lsb.sgy test-data/multiformats/Format10lsb.sgy
1ea5260d0b3181b9d8f04421021b9d8f2b4711652805f08c8e4fdaad4ffbf5a1 segyio seismic/segyio_test_data/multiformats/Format10msb.sgy test-data/multiformats/Format10msb.sgy
c5a8f66e0d86019d320112408b8f5bc9b13ff620f1795084c128fd9e08f4f141 segyio seismic/segyio_test_data/multiformats/Format11lsb.sgy test-data/multiformats/Format11lsb.sgy
3cfc2000d0093d8fefd82bdbde872ea78e1cfbb2fc815a402c894a206c2839ad segyio seismic/segyio_test_data/multiformats/Format11msb.sgy test-data/multiformats/Format11msb.sgy
d8c659745a26f4fcaf7da38172a73961c41570031296453fe816dd6fa3ab049d segyio seismic/segyio_test_data/multiformats/Format12lsb.sgy test-data/multiformats/Format12lsb.sgy
e7eee88caf03428b8659d333708e7a2f9384f47484b193d7feaad5de3af0078e segyio seismic/segyio_test_data/multiformats/Format12msb.sgy test-data/multiformats/Format12msb.sgy
68c1bad3278aa745e6180264df1013c4a8e0c8700bcafa6f3c10a6c78a786318 segyio seismic/segyio_test_data/multiformats/Format15lsb.sgy test-data/multiformats/Format15lsb.sgy
357e721e5578455482cb92aec21dc9638aab0314d0ea160b32fbdcc9d13a7f16 segyio seismic/segyio_test_data/multiformats/Format15msb.sgy test-data/multiformats/Format15msb.sgy
698fe4cb0d0907426ee11a8b877066335a06518584b1d686b112d3ed2d50a3d2 segyio seismic/segyio_test_data/multiformats/Format16lsb.sgy test-data/multiformats/Format16lsb.sgy
034735c556216b79a858f2051d91537b50e3522d6c74e5634e3beaeebc4e732a segyio seismic/segyio_test_data/multiformats/Format16msb.sgy test-data/multiformats/Format16msb.sgy
c943bcd9492046cec718b4b104309954f225c4062e1145279c1489b19bc83a56 segyio seismic/segyio_test_data/multiformats/Format1lsb.sgy test-data/multiformats/Format1lsb.sgy
57cd19a9807beefafb1729b56faccc71c1ed936a8b80a54aa6113761af000119 segyio seismic/segyio_test_data/multiformats/Format1msb.sgy test-data/multiformats/Format1msb.sgy
ca797e2115a6946d63db3d6c3c8de67f4ef2f5023c1724dea6691c10a92397f0 segyio seismic/segyio_test_data/multiformats/Format2lsb.sgy test-data/multiformats/Format2lsb.sgy
26995d153b8f3873a595806aec9ea01ce1077067ebccaad21c957ee6af619994 segyio seismic/segyio_test_data/multiformats/Format2msb.sgy test-data/multiformats/Format2msb.sgy
323986e72d6ae6afcc1f86a769fd0331480d199af72ad2b3a3a32bdf12f417ed segyio seismic/segyio_test_data/multiformats/Format3lsb.sgy test-data/multiformats/Format3lsb.sgy
6008d05547c6b8f6050cea7ca4683f1be3fac260235cad47eb5e61ee05d2ce23 segyio seismic/segyio_test_data/multiformats/Format3msb.sgy test-data/multiformats/Format3msb.sgy
1d7cdc064fdb11d75273636d3056acf446e346e72d3fc2dcd859b6750319a414 segyio seismic/segyio_test_data/multiformats/Format4lsb.sgy test-data/multiformats/Format4lsb.sgy
9989364711fad1d1ce3e1416615c2ca13ae9186fd4677ea3daade0afe8e8b84b segyio seismic/segyio_test_data/multiformats/Format4msb.sgy test-data/multiformats/Format4msb.sgy
e2bd0c8fdb0af1970ce8e9b152501f144966c5dc44c1de0c5e17b4c2e75b029c segyio seismic/segyio_test_data/multiformats/Format5lsb.sgy test-data/multiformats/Format5lsb.sgy
1be2a5e8a26cb101595c2c322287f2bacf34658d50a55cdd4c55e4b640842dca segyio seismic/segyio_test_data/multiformats/Format5msb.sgy test-data/multiformats/Format5msb.sgy
6ef0dc60b6ef8cee705f90b0d291c2d471f8ff1e0f854b17549060b9b450e876 segyio seismic/segyio_test_data/multiformats/Format6lsb.sgy test-data/multiformats/Format6lsb.sgy
91a1ffdc87f547a2702d9fcf124c30908b19d938115334488b933658d210d01d segyio seismic/segyio_test_data/multiformats/Format6msb.sgy test-data/multiformats/Format6msb.sgy
fa8be692fbd5265459b5d182b5b2a421ed56d2052278f9563e656bb663b438fb segyio seismic/segyio_test_data/multiformats/Format7lsb.sgy test-data/multiformats/Format7lsb.sgy
5574ee44bdbdfb770b45ef80efc0566dc0d71e2eb9626116ac387925e27a43f2 segyio seismic/segyio_test_data/multiformats/Format7msb.sgy test-data/multiformats/Format7msb.sgy
f18a48f3a8e442ed52a635f367964cfdf6468603d5db941cd7411e46cbee2fd7 segyio seismic/segyio_test_data/multiformats/Format8lsb.sgy test-data/multiformats/Format8lsb.sgy
8c0012dfbb2dbed4367ac040f6d85eb0d95367f35d2b25c074da182e28cfa98b segyio seismic/segyio_test_data/multiformats/Format8msb.sgy test-data/multiformats/Format8msb.sgy
0bc6fba1c326fb8a41d5b17aaed0b781741e2c0e94c0806b83fac77b55c0827a segyio seismic/segyio_test_data/multiformats/Format9lsb.sgy test-data/multiformats/Format9lsb.sgy
63b92a783481e2cbcf1fb139185ea9ecb02f84905dacc1b86cf7916e7524e42c segyio seismic/segyio_test_data/multiformats/Format9msb.sgy test-data/multiformats/Format9msb.sgy
9e6757524bbf37dce9fb5ec2a31f9e0f33b17a9f2bac48537bd4ef0e8dbe0f2d segyio_tests seismic/segyio_test_data/normal-small.sgy test-data/normal-small.sgy
57b18ec24e1b4454f2a185fe4d79554eb6390b7e150e7445a7fbeb995077890e segyio_tests seismic/segyio_test_data/obtuse-small.sgy test-data/obtuse-small.sgy
2a78cbec5edd94fa969673c777737a74cd3587bc9156106f6d5c9882fe447d0b segyio_tests seismic/segyio_test_data/reflex-small.sgy test-data/reflex-small.sgy
a53d98ff0166485c90a640c077547b031324eb5e9219b029324daa8437b43c32 segyio_tests seismic/segyio_test_data/right-small.sgy test-data/right-small.sgy
e30ed9722ff38b72cf422dc36c86ed2075cf6d82bac51da067866b8d33b0640b segyio_tests seismic/segyio_test_data/rotated-small-rev2.sgy test-data/rotated-small-rev2.sgy
588eb04460677fdfaba8dd2318c7317153aa6ef08afb8693cff1a14f44d07886 segyio_tests seismic/segyio_test_data/shot-gather.sgy test-data/shot-gather.sgy
f93a0b5102b1891039badf432e92f53df2f30218340617453c5dc23024521973 segyio_tests seismic/segyio_test_data/small-lsb.sgy test-data/small-lsb.sgy
ad8f11f9b2b4ff1178b2318f375eae9f642bf1ba3f36ae215d1c50a114e5d664 segyio_tests seismic/segyio_test_data/small-lsb.su test-data/small-lsb.su
dc68c7aa66524b5efade581b0308a288c9ca50ffc9f744b0821dd8e75b348f43 segyio_tests seismic/segyio_test_data/small-ps-dec-il-inc-xl-off.sgy test-data/small-ps-dec-il-inc-xl-off.sgy
0a59de448a37dc5f5ee3ed818a019e8f2078e3efa6bf8fca09fe036f592e66a7 segyio_tests seismic/segyio_test_data/small-ps-dec-il-off-inc-xl.sgy test-data/small-ps-dec-il-off-inc-xl.sgy
7282ab37c32989758a2b28951ab9208f5124f78ce33c6a8917ec4c4fcd6315ff segyio_tests seismic/segyio_test_data/small-ps-dec-il-xl-inc-off.sgy test-data/small-ps-dec-il-xl-inc-off.sgy
f68ada833e8ec6a32d844bb437db896ad0fd60c7a8a8862e7c6c964f478fb690 segyio_tests seismic/segyio_test_data/small-ps-dec-il-xl-off.sgy test-data/small-ps-dec-il-xl-off.sgy
360c7a50a2bc4533f8d1f4ce620c7020d971632473720855615c2e4be6cc704a segyio_tests seismic/segyio_test_data/small-ps-dec-off-inc-il-xl.sgy test-data/small-ps-dec-off-inc-il-xl.sgy
3429eeae7c8acde05e33f490d5ebbb9a8b9cd77dedfcd69da5ab425964011ee6 segyio_tests seismic/segyio_test_data/small-ps-dec-xl-inc-il-off.sgy test-data/small-ps-dec-xl-inc-il-off.sgy
d3685e565dc3caba4effcaa97eb28cdfc12e8ca088e87e1ff6c05179cb7ad175 segyio_tests seismic/segyio_test_data/small-ps-dec-xl-off-inc-il.sgy test-data/small-ps-dec-xl-off-inc-il.sgy
75cac00cdefe1f3506e69a64d818e00626e67d90f562721f66707e148ba03759 segyio_tests seismic/segyio_test_data/small-ps.sgy test-data/small-ps.sgy
e939ed45a8258f1fbaf3c21ca83f54369c4c4def79384b4cb0fc069a4eb1a191 segyio_tests seismic/segyio_test_data/small.sgy test-data/small.sgy
0b7dcf06812c9b6b40049cc1e5c3cea9baed3e5c9a4c0690c0b15df40e4e7ad5 segyio_tests seismic/segyio_test_data/small.su test-data/small.su
00f2af2326bc609055f17eb2571d3cd7aba67e4c6341b9b22ed8d541160de63a segyio_tests seismic/segyio_test_data/stanzas-known-count.sgy test-data/stanzas-known-count.sgy
c21592a04f2f7633b1005bad32283a3ab5a47796ee392b7802878b47ea25cc28 segyio_tests seismic/segyio_test_data/stanzas-unknown-count.sgy test-data/stanzas-unknown-count.sgy
ff2581f03bfe7200dbbbf997292c0a2323ae49aa9855f861b3ce999ee320a55e segyio_tests seismic/segyio_test_data/straight-small.sgy test-data/straight-small.sgy
6001184a8424d4558d3cbc7da84fed16a7d344182eb9035cb428d43a20da0c70 segyio_tests seismic/segyio_test_data/text-embed-null.sgy test-data/text-embed-null.sgy
9244560788a82c19cd2b54f57d52032e79a159c1bde45d24e0704e7daa04aefa segyio_tests seismic/segyio_test_data/text.sgy test-data/text.sgy
b23509c4644f938c8f7c3d82abf09e2f012a2ce79ade391e9912a158c8eb5d0e segyio_tests seismic/segyio_test_data/tiny.sgy test-data/tiny.sgy
397ed2ef878033fdd3177e279bfbd4767749ade955a2c0b3630559936b987ec2 segyio_tests seismic/segyio_test_data/trace-header-extension1.sgy test-data/trace-header-extension1.sgy
931a731fc9baf80a3f926379f1c2d5c4a5f0f0a342d09ab665f18d8eb04f7cc9 segyio_tests seismic/segyio_test_data/trace-header-extensions.sgy test-data/trace-header-extensions.sgy
e939ed45a8258f1fbaf3c21ca83f54369c4c4def79384b4cb0fc069a4eb1a191 segyio_tests seismic/segyio_test_data/小文件.sgy test-data/小文件.sgy
"""

REGISTRY: tuple[DataFile, ...] = tuple(sorted(_parse_table(_TABLE) + _parse_table(_DOWNLOAD_ONLY_TABLE,
                                                                                  in_data_directory=False),
                                              key=lambda entry: entry.name))
"""Every registered data file, sorted by name."""

_ENTRIES = types.MappingProxyType({entry.name: entry for entry in REGISTRY})
