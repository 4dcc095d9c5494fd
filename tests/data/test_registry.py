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
    "seismic/gsb_fault_sticks/gsb_crl_2600.sgy",
    "seismic/gsb_fault_sticks/gsb_crl_2800.sgy",
    "seismic/gsb_fault_sticks/gsb_crl_2800_second_mask.png",
    "seismic/parihaka_timeslices/parihaka_timeslices_cols174_302.npz",
    "seismic/penobscot_sections/penobscot_sections_1075_1092.npz",
}
SMALL_FILE = "rgbd/tum_fr1xyz_pair/kinect_params.txt"  # not derived, 29 bytes
SMALL_DERIVED = "rgbd/7scenes_redkitchen_0000_0495/associations.txt"  # derived, 5 kB
PENOBSCOT = "seismic/penobscot_sections/penobscot_sections_1075_1092.npz"  # derived from 36 PNGs
SEQUENCE = "rgbd/7scenes_redkitchen_0000_0495"


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
    assert {entry.name: entry.sha256 for entry in REGISTRY} == listed


def test_every_file_in_data_dir_is_registered_and_hashes_match(shared_dir):
    on_disk = {p.relative_to(shared_dir).as_posix() for p in shared_dir.rglob("*") if p.is_file()}
    on_disk -= {"README.md", "SHA256SUMS"}
    assert on_disk == {entry.name for entry in REGISTRY}
    for entry in REGISTRY:  # about 60 MB in total: hash each file once
        assert _sha256(shared_dir / entry.name) == entry.sha256, entry.name


def test_fetch_resolves_every_file_from_data_dir(shared_dir):
    for name in (e.name for e in REGISTRY):
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
    assert len(list_files()) == len(REGISTRY) == 347 + 91 + 10 + 5 + 2
    segyio_tests = list_files("seismic/segyio_test_data/")
    assert len(segyio_tests) == 91 and len(list_files("seismic/segyio_test_data/multiformats/")) == 28
    assert list_files("seismic/f3_fault_masks/") == sorted(
        f"seismic/f3_fault_masks/{kind}_inline_{n}.png" for kind in ("mask", "seismic") for n in range(100, 501, 100))


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


def _offline(*args, **kwargs):
    raise ConnectionError("no network")  # requests' ConnectionError is also an OSError


def test_derived_file_missing_raises_without_network(empty_data_dir, monkeypatch):
    monkeypatch.setattr(pooch, "retrieve", _offline)
    with pytest.raises(DataNotFoundError, match="SEISMO3D_DATA_DIR") as info:
        fetch(PENOBSCOT)
    assert "export SEISMO3D_DATA_DIR=" in str(info.value)
    assert "mini_test/images/1075.png" in str(info.value)  # the origin it tried to download
    assert isinstance(info.value, FileNotFoundError)
    assert not (empty_data_dir.parent / "cache" / PENOBSCOT).exists()


def test_derived_file_missing_and_env_unset(monkeypatch, tmp_path):
    monkeypatch.delenv("SEISMO3D_DATA_DIR", raising=False)
    monkeypatch.setenv("SEISMO3D_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(pooch, "retrieve", _offline)
    with pytest.raises(DataNotFoundError, match="SEISMO3D_DATA_DIR is not set"):
        fetch(PENOBSCOT)


def test_download_failure_raises_data_not_found(empty_data_dir, monkeypatch):
    monkeypatch.setattr(pooch, "retrieve", _offline)
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
    ((origin_path, origin_sha256),) = derivation.origins
    assert calls == [(f"https://raw.githubusercontent.com/{entry.repo}/{entry.commit}/{origin_path}",
                      f"sha256:{origin_sha256}")]
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


def _penobscot_origin(shared_dir, folder: pathlib.Path) -> dict:
    """The origin's 18 images and 18 masks rebuilt from the data directory's stack (grey PNG = the 8-bit section,
    RGB PNG = each interval in its class colour, with one anti-aliased pixel between two classes per column): the
    PNGs of atlan-antillia's repository hold the same pixels (checked byte for byte against the real origin when
    this derivation was written; the real files are not in the data directory)."""
    import cv2
    import numpy as np

    from seismo3d.data.derived import PENOBSCOT_CLASS_COLOURS

    colours = np.asarray(PENOBSCOT_CLASS_COLOURS, np.int32)
    files = {}
    with np.load(shared_dir / PENOBSCOT) as z:
        for section, image, labels in zip(z["section_ids"], z["seismic"], z["labels"]):
            mask = colours[labels]
            edge = np.nonzero(np.diff(labels[:, 100].astype(int)))[0]
            if len(edge):  # a blend 40 % of the way to the class below: still snaps to the class above
                r = edge[0]
                mask[r, 100] = (0.6 * colours[labels[r, 100]] + 0.4 * colours[labels[r + 1, 100]]).round()
            for kind, array in (("images", image), ("masks", mask[:, :, ::-1].astype(np.uint8))):
                path = folder / kind / f"{section}.png"
                path.parent.mkdir(parents=True, exist_ok=True)
                assert cv2.imwrite(str(path), array)
                files[f"{kind}/{section}.png"] = path
    return files


@pytest.mark.slow  # 6.6 s in the fast lane, whose budget is 60 s
def test_penobscot_stack_is_made_again_from_its_origin(empty_data_dir, shared_dir, monkeypatch, tmp_path):
    """Without the data directory's copy, the 36 origin PNGs are downloaded (pooch checks each registered hash) and
    stacked into an npz byte-identical to the data directory's, then checked against the registry's hash."""
    from seismo3d.data import load_penobscot_sections
    from seismo3d.data.derived import DERIVATIONS

    files = _penobscot_origin(shared_dir, tmp_path / "origin")
    entry, derivation = file_info(PENOBSCOT), DERIVATIONS[PENOBSCOT]
    prefix = (f"https://raw.githubusercontent.com/{entry.repo}/{entry.commit}/"
              "projects/TensorFlowFlexUNet/Penobscot/mini_test/")
    calls = []

    def fake_retrieve(url, known_hash, fname, path, progressbar):
        calls.append((url, known_hash))
        return str(files[url.removeprefix(prefix)])

    monkeypatch.setattr(pooch, "retrieve", fake_retrieve)
    path = fetch(PENOBSCOT)
    assert [url for url, _ in calls] == [prefix + f"{kind}/{k}.png" for kind in ("images", "masks")
                                         for k in range(1075, 1093)]
    assert [h for _, h in calls] == [f"sha256:{sha}" for _, sha in derivation.origins]
    assert len(set(calls)) == 36
    assert path == (tmp_path / "cache" / PENOBSCOT).resolve()
    assert path.read_bytes() == (shared_dir / PENOBSCOT).read_bytes()
    assert load_penobscot_sections().cube.shape == (18, 512, 1536)  # the loader reads the cache's copy
    assert len(calls) == 36


def test_penobscot_stack_snaps_masks_and_finds_horizon_tops(tmp_path):
    """Anti-aliased mask pixels go to the nearest class colour (a tie to the lower class); horizon k on a trace is
    the first row of a class above k, so a horizon whose interval is missing there takes the next one's top."""
    import cv2
    import numpy as np

    from seismo3d.data.derived import PENOBSCOT_CLASS_COLOURS, stack_penobscot_sections

    colours = np.asarray(PENOBSCOT_CLASS_COLOURS, np.int32)
    labels = np.zeros((12, 3), np.uint8)
    labels[3:, 0], labels[6:, 0] = 1, 7  # trace 0: classes 0, 1, 7 (horizons 1-6 at the top of class 7)
    labels[5:, 1] = 2  # trace 1: class 2 from row 5 (horizon 0 there too); no class above 2
    mask = colours[labels].astype(np.float64)
    mask[4, 2] = (colours[3] + colours[4]) / 2  # trace 2, all class 0 but a tie between classes 3 and 4
    mask[8, 2] = 0.7 * colours[5] + 0.3 * colours[6]
    image = np.arange(36, dtype=np.uint8).reshape(12, 3)
    origins = []
    for kind, array in (("images", image), ("masks", mask.round().astype(np.uint8)[:, :, ::-1])):
        origins.append(tmp_path / kind / "1200.png")
        origins[-1].parent.mkdir()
        cv2.imwrite(str(origins[-1]), array)
    stack_penobscot_sections(tuple(origins), tmp_path / "out.npz", PENOBSCOT)
    with np.load(tmp_path / "out.npz") as z:
        assert z["section_ids"].tolist() == [1200]
        assert np.array_equal(z["seismic"][0], image)
        expected = labels.copy()
        expected[4, 2], expected[8, 2] = 3, 5
        assert np.array_equal(z["labels"][0], expected)
        assert z["horizons"][0, :, 0].tolist() == [3, 6, 6, 6, 6, 6, 6]
        assert z["horizons"][0, :, 1].tolist() == [5, 5, -1, -1, -1, -1, -1]
        assert z["horizons"][0, :, 2].tolist() == [4, 4, 4, 8, 8, -1, -1]


def test_penobscot_stack_refuses_a_mismatched_mask(tmp_path):
    import cv2
    import numpy as np

    from seismo3d.data.derived import stack_penobscot_sections

    image, mask = tmp_path / "images" / "1.png", tmp_path / "masks" / "1.png"
    for path, array in ((image, np.zeros((8, 4), np.uint8)), (mask, np.zeros((8, 5, 3), np.uint8))):
        path.parent.mkdir()
        cv2.imwrite(str(path), array)
    with pytest.raises(DataIntegrityError, match="not the origin registered"):
        stack_penobscot_sections((image, mask), tmp_path / "out.npz", PENOBSCOT)
    assert not (tmp_path / "out.npz").exists()


def test_fetch_folder_from_data_dir(shared_dir):
    from seismo3d.data import fetch_folder

    assert fetch_folder(SEQUENCE + "/") == (shared_dir / SEQUENCE).resolve()
    with pytest.raises(InputError, match="list_files"):
        fetch_folder("rgbd/no_such_sequence")


@pytest.mark.slow
def test_fetch_folder_gathers_a_partial_folder_in_the_cache(empty_data_dir, shared_dir, monkeypatch, tmp_path):
    """A data directory holding part of a sequence: the missing files are downloaded (served here from the shared
    folder), the index files made again, and the present ones copied, so the cache holds the whole folder."""
    from seismo3d.data import fetch_folder
    from seismo3d.mapping import open_sequence

    for name in list_files(SEQUENCE + "/pose/"):  # the data directory holds the poses only
        (empty_data_dir / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(shared_dir / name, empty_data_dir / name)
    cache = tmp_path / "cache"
    downloads = []

    def from_shared(url, known_hash, fname, path, progressbar):
        relative = (pathlib.Path(path).relative_to(cache) / fname).as_posix()
        downloads.append(relative)
        pathlib.Path(path).mkdir(parents=True, exist_ok=True)
        shutil.copyfile(shared_dir / relative, pathlib.Path(path) / fname)  # as pooch does
        return str(pathlib.Path(path) / fname)

    monkeypatch.setattr(pooch, "retrieve", from_shared)
    folder = fetch_folder(SEQUENCE)
    assert folder == (cache / SEQUENCE).resolve()
    names = list_files(SEQUENCE + "/")
    assert {p.relative_to(cache).as_posix() for p in folder.rglob("*") if p.is_file()} == set(names)
    for name in names:
        assert (cache / name).read_bytes() == (shared_dir / name).read_bytes(), name
    assert not any("/pose/" in name for name in downloads)  # the data directory's poses were copied
    assert len(open_sequence(folder)) == 100
