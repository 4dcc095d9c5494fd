"""The faults job gives the same faults in memory and under a memory limit that forces blocks (issue 30): a generated
192^3 cube and the 18 Penobscot inlines, fault_points.csv byte for byte, the fault likelihood within 1e-6."""

import numpy as np
import pytest
import zarr

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.jobs.faults import run_faults_job
from seismo3d.seismic.faults import in_memory_bytes, resident_memory

pytestmark = pytest.mark.slow


def _same_faults(npy, tmp_path):
    """Run the job in memory and under a limit below the in-memory need; compare the outputs."""
    shape = np.load(npy, mmap_mode="r").shape
    in_memory = run_faults_job(npy, tmp_path / "memory", memory_limit=64 << 30, progress=False)
    assert in_memory["likelihood"].suffix == ".npy"
    # the limit leaves 60 % of the in-memory need beside the process: blocks, each fitting the limit
    limit = resident_memory() + int(0.6 * in_memory_bytes(shape))
    blocks = run_faults_job(npy, tmp_path / "blocks", memory_limit=limit, progress=False)
    assert blocks["likelihood"].name == "fault_likelihood.zarr"
    points = in_memory["points"].read_bytes()
    assert points.count(b"\n") > 100  # faults were found
    assert blocks["points"].read_bytes() == points
    assert blocks["summary"].read_bytes() == in_memory["summary"].read_bytes()
    traced = zarr.open_group(str(blocks["surfaces_zarr"]), mode="r")
    assert np.abs(traced["likelihood"][:] - np.load(in_memory["likelihood"])).max() <= 1e-6
    assert np.abs(traced["votes"][:] - np.load(in_memory["votes"])).max() <= 1e-6


def test_generated_192_cube(tmp_path):
    npy = tmp_path / "cube.npy"
    np.save(npy, synthetic_cube((192, 192, 192), seed=4).cube.astype(np.float32))
    _same_faults(npy, tmp_path)


def test_penobscot_inlines(tmp_path):
    from seismo3d.data import load_penobscot_sections

    npy = tmp_path / "penobscot.npy"
    try:
        np.save(npy, load_penobscot_sections().cube)
    except Exception as exc:  # noqa: BLE001 - the data is not installed here
        pytest.skip(f"the Penobscot sections cannot be loaded: {exc}")
    with pytest.warns(Warning, match="clipped amplitudes"):  # the 8-bit sections, on both runs
        _same_faults(npy, tmp_path)
