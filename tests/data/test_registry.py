"""Tests of seismo3d.data.registry: the table matches the shared data; fetch resolves, verifies and fails clearly."""

from __future__ import annotations

import hashlib
import os
import pathlib
import shutil

import pooch
import pytest

from seismo3d.data import registry
from seismo3d.data.registry import REGISTRY, data_dir, fetch, file_info, list_files
from seismo3d.errors import DataIntegrityError, DataNotFoundError, InputError

# Files rebuilt from their origin (see the data README): no download URL.
EXPECTED_DERIVED = {
    "rgbd/7scenes_redkitchen_0000_0495/associations.txt",
    "rgbd/7scenes_redkitchen_0000_0495/depth.txt",
    "rgbd/7scenes_redkitchen_0000_0495/groundtruth.txt",
    "rgbd/7scenes_redkitchen_0000_0495/rgb.txt",
    "scans/bunny/bun.conf.reference.txt",
    "scans/bunny/bun000_clean.ply",
    "scans/bunny/bun045_clean.ply",
    "seismic/penobscot_sections/penobscot_sections_1075_1092.npz",
}
SMALL_FILE = "rgbd/tum_fr1xyz_pair/kinect_params.txt"  # not derived, 29 bytes
SMALL_DERIVED = "rgbd/7scenes_redkitchen_0000_0495/associations.txt"  # derived, 5 kB
DATA_DIR_ONLY = "seismic/penobscot_sections/penobscot_sections_1075_1092.npz"  # derived, not made again


@pytest.fixture(scope="module")
def shared_dir() -> pathlib.Path:
    value = os.environ.get("SEISMO3D_DATA_DIR")
    if not value:
        pytest.skip("SEISMO3D_DATA_DIR is not set")
    return pathlib.Path(value)


@pytest.fixture
def empty_data_dir(tmp_path, monkeypatch) -> pathlib.Path:
    """Point the data directory at an empty folder and the cache at another; forbid real downloads."""
    root = tmp_path / "data"
    root.mkdir()
    monkeypatch.setenv("SEISMO3D_DATA_DIR", str(root))
    monkeypatch.setenv("SEISMO3D_CACHE_DIR", str(tmp_path / "cache"))

    def no_network(*args, **kwargs):
        raise AssertionError("the test tried to download")

    monkeypatch.setattr(pooch, "retrieve", no_network)
    return root


def _sha256(path: pathlib.Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_registry_matches_sha256sums(shared_dir):
    listed = {}
    for line in (shared_dir / "SHA256SUMS").read_text().splitlines():
        sha, name = line.split()
        listed[name.removeprefix("./")] = sha
    listed.pop("README.md", None)
    listed.pop("SHA256SUMS", None)
    assert {entry.name: entry.sha256 for entry in REGISTRY if entry.in_data_directory} == listed


def test_every_file_in_data_dir_is_registered_and_hashes_match(shared_dir):
    on_disk = {p.relative_to(shared_dir).as_posix() for p in shared_dir.rglob("*") if p.is_file()}
    on_disk -= {"README.md", "SHA256SUMS"}
    assert on_disk == {entry.name for entry in REGISTRY if entry.in_data_directory}
    for entry in (e for e in REGISTRY if e.in_data_directory):  # about 40 MB in total: hash each file once
        assert _sha256(shared_dir / entry.name) == entry.sha256, entry.name


def test_fetch_resolves_every_file_from_data_dir(shared_dir):
    for name in (e.name for e in REGISTRY if e.in_data_directory):
        path = fetch(name)
        assert path == (shared_dir / name).resolve()


def test_entries_are_consistent():
    names = [entry.name for entry in REGISTRY]
    assert names == sorted(set(names)), "names must be unique and sorted"
    assert {entry.name for entry in REGISTRY if entry.derived} == EXPECTED_DERIVED
    for entry in REGISTRY:
        assert len(entry.sha256) == 64 and int(entry.sha256, 16) >= 0
        assert entry.licence
        assert len(entry.commit) == 40
        assert entry.in_data_directory or not entry.derived  # a download-only file must be downloadable
        if entry.derived:
            assert entry.url is None
        else:
            assert entry.url == (f"https://raw.githubusercontent.com/{entry.repo}/{entry.commit}/"
                                 f"{entry.origin_path}")
    info = file_info("rgbd/7scenes_redkitchen_0000_0495/depth/frame-000495.depth.png")
    assert info.url == ("https://raw.githubusercontent.com/andyzeng/tsdf-fusion-python/"
                        "3f22a940d90f684145b1f29b1feaa92e09eb1db6/data/frame-000495.depth.png")
    with pytest.raises(Exception):
        info.sha256 = "0" * 64  # frozen


def test_list_files_prefix():
    bunny = list_files("scans/bunny/")
    assert bunny == ["scans/bunny/bun.conf.reference.txt", "scans/bunny/bun000_clean.ply",
                     "scans/bunny/bun045_clean.ply"]
    assert len(list_files("rgbd/7scenes_redkitchen_0000_0495/depth/")) == 100
    assert list_files("no/such/prefix") == []
    assert len(list_files()) == len(REGISTRY) == 347 + 90
    segyio_tests = list_files("seismic/segyio_test_data/")
    assert len(segyio_tests) == 90 and len(list_files("seismic/segyio_test_data/multiformats/")) == 28
    assert {e.name for e in REGISTRY if not e.in_data_directory} == set(segyio_tests)


def test_unknown_name_lists_close_names():
    with pytest.raises(InputError, match="bun000_clean.ply"):
        fetch("scans/bunny/bun000.ply")
    with pytest.raises(InputError, match="f3_crop.sgy"):
        fetch("seismic/f3_crop.segy")
    with pytest.raises(InputError, match="list_files"):
        fetch("rgbd/tum_fr1xyz_pair")  # a folder, not a file
    with pytest.raises(InputError):
        fetch(42)


def test_data_dir_from_env(monkeypatch, tmp_path):
    monkeypatch.delenv("SEISMO3D_DATA_DIR", raising=False)
    assert data_dir() is None
    monkeypatch.setenv("SEISMO3D_DATA_DIR", str(tmp_path))
    assert data_dir() == tmp_path


def test_derived_file_missing_raises_without_network(empty_data_dir):
    with pytest.raises(DataNotFoundError, match="SEISMO3D_DATA_DIR") as info:
        fetch(DATA_DIR_ONLY)
    assert "export SEISMO3D_DATA_DIR=" in str(info.value)
    assert isinstance(info.value, FileNotFoundError)


def test_derived_file_missing_and_env_unset(monkeypatch):
    monkeypatch.delenv("SEISMO3D_DATA_DIR", raising=False)
    monkeypatch.setattr(pooch, "retrieve", lambda *a, **k: pytest.fail("must not download a derived file"))
    with pytest.raises(DataNotFoundError, match="SEISMO3D_DATA_DIR is not set"):
        fetch(DATA_DIR_ONLY)


def test_download_failure_raises_data_not_found(empty_data_dir, monkeypatch):
    def offline(*args, **kwargs):
        raise ConnectionError("no network")  # requests' ConnectionError is also an OSError

    monkeypatch.setattr(pooch, "retrieve", offline)
    with pytest.raises(DataNotFoundError, match="SEISMO3D_DATA_DIR") as info:
        fetch(SMALL_FILE)
    assert "raw.githubusercontent.com" in str(info.value)


def test_download_hash_mismatch_raises_integrity_error(empty_data_dir, monkeypatch):
    def bad_hash(*args, **kwargs):
        raise ValueError("SHA256 hash of downloaded file does not match the known hash")

    monkeypatch.setattr(pooch, "retrieve", bad_hash)
    with pytest.raises(DataIntegrityError, match="does not match"):
        fetch(SMALL_FILE)


def test_download_goes_to_cache_dir_with_known_hash(empty_data_dir, shared_dir, monkeypatch, tmp_path):
    calls = []

    def fake_retrieve(url, known_hash, fname, path, progressbar):
        calls.append((url, known_hash, fname, pathlib.Path(path)))
        target = pathlib.Path(path) / fname
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(shared_dir / SMALL_FILE, target)
        return str(target)

    monkeypatch.setattr(pooch, "retrieve", fake_retrieve)
    path = fetch(SMALL_FILE)
    entry = file_info(SMALL_FILE)
    assert calls == [(entry.url, f"sha256:{entry.sha256}", "kinect_params.txt",
                      tmp_path / "cache" / "rgbd" / "tum_fr1xyz_pair")]
    assert path == (tmp_path / "cache" / SMALL_FILE).resolve()
    assert _sha256(path) == entry.sha256


def test_hash_mismatch_in_data_dir(empty_data_dir, shared_dir):
    target = empty_data_dir / SMALL_DERIVED
    target.parent.mkdir(parents=True)
    shutil.copyfile(shared_dir / SMALL_DERIVED, target)
    assert fetch(SMALL_DERIVED) == target.resolve()  # verified and cached
    target.write_text("0 frame-000000\n")  # changed size and mtime: verified again
    with pytest.raises(DataIntegrityError, match="SHA-256"):
        fetch(SMALL_DERIVED)
    assert fetch(SMALL_DERIVED, verify=False) == target.resolve()


def test_verification_is_cached(shared_dir, monkeypatch):
    calls = []
    real = registry._sha256
    monkeypatch.setattr(registry, "_sha256", lambda path: calls.append(path) or real(path))
    registry._verified.cache_clear()
    for _ in range(3):
        fetch(SMALL_FILE)
    assert len(calls) == 1


@pytest.mark.parametrize("name", ["scans/bunny/bun000_clean.ply", "scans/bunny/bun045_clean.ply"])
def test_bunny_scan_is_made_again_from_its_origin(empty_data_dir, shared_dir, monkeypatch, tmp_path, name):
    """Without the data directory's copy, the origin (headerless 'x y z ' rows, then junk rows) is downloaded and
    cleaned into a file byte-identical to the data directory's (the registry's hash is checked)."""
    from seismo3d.data.derived import DERIVATIONS

    # the origin's layout, rebuilt from the cleaned file: rows with a trailing blank, then one-number rows
    rows = (shared_dir / name).read_text().split("end_header\n", 1)[1].splitlines()
    origin = tmp_path / "origin.ply"
    origin.write_text("".join(f"{r} \n" for r in rows) + "0 \n" * 50)
    calls = []

    def fake_retrieve(url, known_hash, fname, path, progressbar):
        calls.append((url, known_hash))
        return str(origin)

    monkeypatch.setattr(pooch, "retrieve", fake_retrieve)
    path = fetch(name)
    entry, derivation = file_info(name), DERIVATIONS[name]
    assert calls == [(f"https://raw.githubusercontent.com/{entry.repo}/{entry.commit}/{derivation.origin_path}",
                      f"sha256:{derivation.origin_sha256}")]
    assert path == (tmp_path / "cache" / name).resolve()
    assert path.read_bytes() == (shared_dir / name).read_bytes()
    assert fetch(name) == path and len(calls) == 1  # the cached copy is used (and checked) next time


def test_bunny_poses_need_no_download(empty_data_dir, shared_dir):
    path = fetch("scans/bunny/bun.conf.reference.txt")  # pooch.retrieve would raise: nothing is downloaded
    assert path.read_bytes() == (shared_dir / "scans/bunny/bun.conf.reference.txt").read_bytes()


def test_derivation_from_another_origin_is_refused(empty_data_dir, monkeypatch, tmp_path):
    origin = tmp_path / "origin.ply"
    origin.write_text("0.1 0.2 0.3 \n0 \n")
    monkeypatch.setattr(pooch, "retrieve", lambda *a, **k: str(origin))
    with pytest.raises(DataIntegrityError, match="made again"):
        fetch("scans/bunny/bun000_clean.ply")
    assert not (tmp_path / "cache" / "scans/bunny/bun000_clean.ply").exists()


@pytest.mark.parametrize("kind", ["groundtruth.txt", "rgb.txt", "depth.txt", "associations.txt"])
def test_7scenes_index_files_are_made_again(empty_data_dir, shared_dir, monkeypatch, tmp_path, kind):
    """The TUM-style index files of the 7-Scenes subset, made from the registered frames and their fetched pose
    files (downloads served here from the shared folder), are byte-identical to the data directory's."""
    cache = tmp_path / "cache"

    def from_shared(url, known_hash, fname, path, progressbar):
        relative = pathlib.Path(path).relative_to(cache) / fname
        assert known_hash == f"sha256:{file_info(relative.as_posix()).sha256}"
        return str(shared_dir / relative)

    monkeypatch.setattr(pooch, "retrieve", from_shared)
    name = f"rgbd/7scenes_redkitchen_0000_0495/{kind}"
    assert fetch(name).read_bytes() == (shared_dir / name).read_bytes()
