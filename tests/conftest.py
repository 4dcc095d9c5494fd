"""Shared fixtures: the real-data directory and small generated point sets."""

import collections
import os
import pickle
import signal
import sys

import numpy as np
import pytest
from filelock import FileLock

# pytest keeps the assertion-rewritten test modules in __pycache__, unless Python is told not to write bytecode
# (PYTHONDONTWRITEBYTECODE, set in some CI images and sandboxes, this machine's among them): then every worker rewrites
# every test module on every run, 4-5 s of each worker's collection here. The modules imported after this line (the
# test modules and seismo3d) are written again.
sys.dont_write_bytecode = False


def pytest_collection_modifyitems(config, items):
    """The test files in the order pytest-xdist hands them to its workers (``--dist loadfile``, one file at a time to
    the first worker free, ``--no-loadscope-reorder`` in ``pyproject.toml``): the files with the most slow tests first,
    then those with the most tests, each file's tests in their order. A file of a few long tests handed out last
    kept one worker busy alone at the end of the suite."""
    def file_of(item):
        return item.nodeid.split("::")[0]

    slow = collections.Counter(file_of(item) for item in items if item.get_closest_marker("slow"))
    count = collections.Counter(file_of(item) for item in items)
    items.sort(key=lambda item: (-slow[file_of(item)], -count[file_of(item)], file_of(item)))


def computed_once(tmp_path_factory, key, compute):
    """``compute()`` once per test session, shared by the pytest-xdist workers: the first worker to ask computes it
    under a file lock and pickles it into the session's temporary folder (which the workers share); the others wait
    for it and load the same value. Without xdist it is computed in the process. Only for results the tests read and
    never modify."""
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent  # pytest-of-<user>/pytest-<n>/: one folder per session, shared by its workers
    path = root / f"computed-once-{key}.pickle"
    with FileLock(f"{path}.lock"):
        if path.is_file():
            return pickle.loads(path.read_bytes())
        value = compute()
        path.write_bytes(pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL))
        return value


@pytest.fixture
def default_sigint_handler():
    """Python's default Ctrl-C handler (SIGINT raises KeyboardInterrupt), as a user's command has it, for the tests
    of what a Ctrl-C does. A suite started in the background by a non-interactive shell (a script's ``&``, nohup)
    starts with SIGINT ignored, and a process that ignores it holds and raises nothing
    (:func:`seismo3d._atomic.deferred_interrupt`). The handler found is put back after the test."""
    found = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, found)


@pytest.fixture(scope="session")
def data_dir():
    """The real-data directory (env SEISMO3D_DATA_DIR); tests needing it skip when it is unset."""
    path = os.environ.get("SEISMO3D_DATA_DIR")
    if not path:
        pytest.skip("SEISMO3D_DATA_DIR is not set")
    return path


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.fixture(scope="session")
def penobscot(data_dir):
    """The 18 real Penobscot inlines with people's horizons (seismo3d.data.load_penobscot_sections)."""
    from seismo3d.data import load_penobscot_sections

    return load_penobscot_sections()


@pytest.fixture(scope="session")
def autzen(data_dir):
    """The real Autzen LiDAR tile (110,000 points, feet; seismo3d.terrain.read_las)."""
    from seismo3d.data import fetch
    from seismo3d.terrain import read_las

    return read_las(fetch("terrain/autzen_trim.laz"))


@pytest.fixture(scope="session")
def dfw(data_dir):
    """The real HydroSHEDS DEM near Dallas-Fort Worth (359 x 367, 3 arc-seconds, EPSG:4326)."""
    from seismo3d.data import fetch
    from seismo3d.terrain import read_dem

    return read_dem(fetch("terrain/dem_hydrosheds_dfw.tif"))


@pytest.fixture(scope="session")
def map_folder(tmp_path_factory):
    """A `seismo3d map`-like output folder of the generated room (seismo3d.data.terrain.synthetic_room): mesh.ply
    written as the map job writes it (:func:`seismo3d.jobs.map.write_ply`: binary PLY, float32 vertices and normals,
    the normals from the faces) and trajectory.txt (TUM: timestamp tx ty tz qx qy qz qw). (ASCII PLY is read by the
    point-cloud tests; plyfile reads it a line at a time, 4.5 s for this mesh.)"""
    from scipy.spatial.transform import Rotation

    from seismo3d.data.terrain import synthetic_room
    from seismo3d.jobs.map import write_ply
    from seismo3d.mapping.tsdf import TriangleMesh

    room = synthetic_room()
    folder = tmp_path_factory.mktemp("map")
    tri = room.vertices[room.faces]
    normals = np.zeros_like(room.vertices)
    np.add.at(normals, room.faces.ravel(), np.repeat(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), 3, 0))
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    write_ply(folder / "mesh.ply", TriangleMesh(room.vertices, room.faces, normals))
    rows = [[0.1 * k, *pose[:3, 3], *Rotation.from_matrix(pose[:3, :3]).as_quat()]
            for k, pose in enumerate(room.camera_poses)]
    np.savetxt(folder / "trajectory.txt", rows, fmt="%.6f")
    return folder


@pytest.fixture(scope="session")
def traced_cube(tmp_path_factory):
    """``traced_cube(seed)``: a 128^3 synthetic cube (3 faults, noise 0.1) traced by :func:`trace_faults` (fault
    likelihood, voting, skins, throws) with its reflector orientation, computed once per seed and session, also
    across pytest-xdist workers (:func:`computed_once`; about 15 s per cube on 2 cores).

    Shared by the fault-surface and fault-throw tests, which read the same five cubes and may run on different
    workers; nothing may modify them."""
    import functools
    from types import SimpleNamespace

    from seismo3d.data.synthetic import synthetic_cube
    from seismo3d.seismic import FaultLikelihood, structure_tensor_orientation, trace_faults

    def compute(seed):
        syn = synthetic_cube((128, 128, 128), seed=seed, noise=0.1)
        res = trace_faults(syn.cube, progress=False)
        return SimpleNamespace(syn=syn, likelihood=FaultLikelihood(res.likelihood, res.strike_deg, res.dip_deg),
                               votes=res.votes, thin=res.thin, faults=res.faults, throws=res.throws,
                               orientation=structure_tensor_orientation(syn.cube))

    @functools.lru_cache(maxsize=None)
    def trace(seed):
        return computed_once(tmp_path_factory, f"traced_cube-{seed}", lambda: compute(seed))

    return trace


@pytest.fixture(scope="session")
def faulted_cube():
    """``faulted_cube(seed)``: a 64 x 64 x 96 synthetic cube (3 faults) and its trace_faults interpretation, once per
    seed and session (read by the horizon-tracking and fault-crossing tests)."""
    import functools
    import warnings

    from seismo3d.data.synthetic import synthetic_cube
    from seismo3d.seismic import trace_faults

    @functools.lru_cache(maxsize=None)
    def trace(seed):
        syn = synthetic_cube((64, 64, 96), n_faults=3, seed=seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return syn, trace_faults(syn.cube, progress=False)

    return trace


@pytest.fixture(scope="session")
def write_segy_cube():
    """:func:`seismo3d.data.synthetic.write_segy_cube`: a (n_il, n_xl, ns) array as a 3D SEG-Y (inlines from 101,
    crosslines from 20 every 2nd, 4 ms, CDP X / Y in centimetres with scalar -100)."""
    from seismo3d.data.synthetic import write_segy_cube

    return write_segy_cube


@pytest.fixture
def check_run_json():
    """``check_run_json(path, command, inputs, outputs, options, since)``: the ``run.json`` of a run
    (seismo3d.jobs.runinfo) parses and holds the version, the command line and the command's arguments, every
    option named in ``options``, each input file's size and sha256 (computed here again), a start time no earlier
    than ``since`` (time.time() before the run; one second of margin for the record's whole seconds), stage times
    that add up to no more than the run's, and the outputs, which exist; no temporary file is left beside it.
    Returns the record."""
    import datetime
    import hashlib
    import json
    import time
    from pathlib import Path

    import seismo3d

    def check(path, command, inputs, outputs, options, since, cli=True):
        path = Path(path)
        record = json.loads(path.read_text())
        assert record["seismo3d_version"] == seismo3d.__version__
        assert record["command"] == command and isinstance(record["argv"], list) and record["argv"]
        assert set(options) <= set(record["options"]), set(options) - set(record["options"])
        if cli:
            assert record["cli"]["command"] == command
            assert record["cli"]["arguments"], "the command's arguments"
        for role, file in inputs.items():
            entry, file = record["inputs"][role], Path(file)
            assert entry["path"] == os.path.abspath(file)
            if file.is_file():
                assert entry["identity"] == "sha256" and entry["bytes"] == file.stat().st_size
                assert entry["sha256"] == hashlib.sha256(file.read_bytes()).hexdigest()
            else:
                assert entry["kind"] == "folder" and entry["identity"] == "size+mtime" and entry["files"] > 0
        started = datetime.datetime.fromisoformat(record["started"]).timestamp()
        assert since - 1.0 <= started <= time.time()
        stages = record["stage_seconds"]
        assert stages and all(v >= 0 for v in stages.values())
        assert sum(stages.values()) <= record["seconds"] + 1e-5  # stages do not overlap; rounding to 1 us each
        for key in outputs:
            assert Path(record["outputs"][key]).exists(), key
        assert not list(path.parent.glob(".*.tmp")) and not list(path.parent.glob(".staged-*"))
        return record

    return check
