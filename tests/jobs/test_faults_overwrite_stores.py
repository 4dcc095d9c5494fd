"""--overwrite on a faults folder holding the block-by-block stores of another input (issue 32): without it they are
refused (and a run of the same input resumes or reuses them); with it they are replaced, kept until the new run has
written its own, and moved back when the run fails. The block run is forced on a small cube by reporting that the
in-memory run does not fit (the one memory decision, seismo3d.seismic.blocks.memory.fits_in_memory, as
BlockRunOptions.in_memory_for asks it), as a large cube under --memory-limit would."""

import hashlib
import logging
import shutil

import numpy as np
import pytest
import zarr

import seismo3d.seismic.blocks.options as block_options
import seismo3d.jobs.faults as job
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.jobs.faults import run_faults_job

STORES = ("fault_likelihood.zarr", "fault_surfaces.zarr")


@pytest.fixture
def blocks(monkeypatch):
    monkeypatch.setattr(block_options, "fits_in_memory", lambda *args, **kwargs: False)  # the run by blocks


@pytest.fixture(scope="module")
def cubes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cubes")
    for name, seed in (("a", 2), ("b", 3)):
        np.save(folder / f"{name}.npy", synthetic_cube((32, 32, 48), n_faults=2, seed=seed).cube.astype(np.float32))
    return folder


def _digest(folder):
    """sha256 of every file under the folder's stores, by relative path."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for name in STORES for p in sorted((folder / name).rglob("*")) if p.is_file()}


def _source(folder, store="fault_likelihood.zarr"):
    return zarr.open_group(str(folder / store), mode="r").attrs["source"]


def _results(folder):
    """The bytes of every file of a run's results (:data:`RESULTS`, the TSurf folder's files among them), by relative
    path."""
    paths = [folder / n for n in job.RESULTS]
    files = [q for p in paths if p.is_dir() for q in sorted(p.rglob("*")) if q.is_file()]
    return {str(q.relative_to(folder)): q.read_bytes() for q in files + [p for p in paths if p.is_file()]}


def _leftovers(folder):
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".") or p.name.endswith((".work", ".partial")))


@pytest.mark.slow  # 2.8 s in the fast lane, whose budget is 60 s
def test_stores_of_another_input_are_refused_without_overwrite(blocks, cubes, tmp_path):
    out = tmp_path / "out"
    run_faults_job(cubes / "a.npy", out, progress=False)
    assert _source(out) == "a" and _source(out, "fault_surfaces.zarr") == "a"
    for name in job.RESULTS:  # the earlier run's files gone: only its stores are left in the way
        if (out / name).is_dir():
            shutil.rmtree(out / name)
        (out / name).unlink(missing_ok=True)
    before = _digest(out)
    with pytest.raises(InputError, match=r"holds fault_likelihood.zarr of another input .*--overwrite"):
        run_faults_job(cubes / "b.npy", out, progress=False)
    assert _digest(out) == before and _leftovers(out) == []


@pytest.mark.slow  # 7.5 s in the fast lane, whose budget is 60 s
def test_overwrite_replaces_the_stores_and_a_failed_run_puts_them_back(blocks, cubes, tmp_path, monkeypatch):
    out = tmp_path / "out"
    first = run_faults_job(cubes / "a.npy", out, progress=False)
    before, files = _digest(out), _results(out)
    assert "fault_surfaces_gocad/fault_1.ts" in files

    def fail(*args, **kwargs):  # the new stores are written, the run fails on writing its files
        assert _source(out) == "b" and _source(out, "fault_surfaces.zarr") == "b"
        raise OSError("No space left on device")

    with monkeypatch.context() as patch:
        patch.setattr(job, "_write_steps", fail)
        with pytest.raises(OSError, match="No space"):
            run_faults_job(cubes / "b.npy", out, overwrite=True, progress=False)
    assert _digest(out) == before and _leftovers(out) == []  # the earlier stores as they were, nothing else
    assert _results(out) == files

    second = run_faults_job(cubes / "b.npy", out, overwrite=True, progress=False)
    assert _source(out) == "b" and _source(out, "fault_surfaces.zarr") == "b" and _leftovers(out) == []
    assert (out / "fault_summary.csv").read_text() != files["fault_summary.csv"].decode()
    # the TSurf folder replaced whole: a file per fault of this run, none of the earlier run's left
    assert sorted(p.name for p in (out / "fault_surfaces_gocad").iterdir()) == sorted(
        f"fault_{r['id']}.ts" for r in second.faults)
    assert first.written["likelihood"] == second.written["likelihood"] == out / "fault_likelihood.zarr"


@pytest.mark.slow  # 2.5 s in the fast lane, whose budget is 60 s
def test_a_rerun_of_the_same_input_resumes_without_overwrite(blocks, cubes, tmp_path, monkeypatch, caplog):
    out = tmp_path / "out"
    with monkeypatch.context() as patch:  # interrupted once the stores are finished, before its files are in
        patch.setattr(job, "_write_steps", lambda *a, **k: (_ for _ in ()).throw(KeyboardInterrupt()))
        with pytest.raises(KeyboardInterrupt):
            run_faults_job(cubes / "a.npy", out, progress=False)
    before = _digest(out)
    assert before and not (out / "faults.vtp").exists()
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        result = run_faults_job(cubes / "a.npy", out, progress=False)
    assert "reusing the finished fault likelihood" in caplog.text and "aside" not in caplog.text
    assert _digest(out) == before and (out / "faults.vtp").exists() and result.faults
