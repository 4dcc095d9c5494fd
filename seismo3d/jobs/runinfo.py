"""``run.json``: what a run of a ``seismo3d`` command was, written beside its outputs by every job.

Every job starts a :class:`RunRecord` with its arguments, times its stages with :meth:`RunRecord.stage` and ends
with :meth:`RunRecord.write` (which calls :func:`write_run_json`, the one writer). The file holds:

- ``seismo3d_version``, ``command`` (the command's name), ``argv`` (the process's command line, ``sys.argv``) and,
  when the run came from the ``seismo3d`` command, ``cli``: its ``command`` and parsed ``arguments``;
- ``options``: every argument of the job as called (paths as text, option dataclasses as dictionaries);
- ``inputs``: per input, its path, size in bytes, modification time (UTC) and ``sha256``; for a file above
  :data:`HASH_LIMIT` bytes (and for a folder: its file count, total size and newest modification time) the
  ``identity`` says ``'size+mtime'`` instead of ``'sha256'`` and no hash is computed;
- ``started`` (UTC, ISO 8601), ``seconds`` (the whole run) and ``stage_seconds`` (per named stage);
- ``outputs``: the files written, by key; ``results``: the job's counts (faults, rows, ...).

Where it goes (:func:`run_json_path`): ``run.json`` inside an output folder (moved in with the folder's other files),
``<output name>.run.json`` beside an output file or store (``horizon.txt.run.json``, ``cube.zarr.run.json``), so
two runs writing files into one folder keep their own records. It follows the output policy of every command
(:func:`run_json_output` is checked with the other outputs by :func:`~seismo3d.jobs.outputs.check_outputs`: an
earlier record is replaced only with ``overwrite``) and is written atomically.
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import datetime
import enum
import hashlib
import json
import math
import mmap
import os
import sys
import threading
import time
from concurrent.futures import Future
from pathlib import Path

from .. import __version__
from .._atomic import atomic_path
from .outputs import Output

__all__ = ["HASH_LIMIT", "RUN_JSON", "RunRecord", "cli_call", "input_changed", "input_identity", "jsonable",
           "read_run_json", "run_json_output", "run_json_path", "write_run_json"]

RUN_JSON = "run.json"
HASH_LIMIT = 200 * 2**20  # bytes: larger inputs are identified by size and modification time (hashing 200 MiB: ~0.5 s)

_CLI_CALL: contextvars.ContextVar = contextvars.ContextVar("seismo3d_cli_call", default=None)


@contextlib.contextmanager
def cli_call(command: str, arguments: dict):
    """Within the block, runs record that they came from the ``seismo3d`` command ``command`` with ``arguments``
    (used by :mod:`seismo3d.cli`).

    Parameters
    ----------
    command : str
        The command's name, e.g. ``'faults'``.
    arguments : dict
        The command's parsed arguments, by parameter name.
    """
    token = _CLI_CALL.set({"command": command, "arguments": jsonable(arguments)})
    try:
        yield
    finally:
        _CLI_CALL.reset(token)


def run_json_path(output: Output) -> Path:
    """Where the record of a run whose main output is ``output`` goes.

    Parameters
    ----------
    output : Output
        The command's main output (:func:`~seismo3d.jobs.outputs.output_file`, ``output_store``,
        ``output_folder``).

    Returns
    -------
    pathlib.Path
        ``<folder>/run.json`` for an output folder, ``<output>.run.json`` beside an output file or store.
    """
    if output.kind == "folder":
        return output.path / RUN_JSON
    return output.path.with_name(output.path.name + "." + RUN_JSON)


def run_json_output(output: Output) -> Output:
    """The record of a run as an output to check with the others (:func:`~seismo3d.jobs.outputs.check_outputs`).

    Parameters
    ----------
    output : Output
        The command's main output.

    Returns
    -------
    Output
        For an output folder, the folder with ``run.json`` among its results; else the file
        ``<output>.run.json``.
    """
    if output.kind == "folder":
        return Output(output.path, "folder", (RUN_JSON,), output.example)
    return Output(run_json_path(output), "file", (), "")


def jsonable(value):
    """``value`` as plain JSON values: dataclasses as dictionaries, paths as text, enums as their values, numpy
    scalars and arrays as numbers and lists, tuples and sets as lists; anything else as its ``repr``.

    Parameters
    ----------
    value : object

    Returns
    -------
    None, bool, int, float, str, list or dict
    """
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else str(value)
    if isinstance(value, enum.Enum):
        return jsonable(value.value)
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: jsonable(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, set, frozenset)):
        return [jsonable(v) for v in value]
    import numpy as np  # here, not at the top: the commands' --help and refusals import this module, not numpy

    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, np.generic):
        return jsonable(value.item())
    return repr(value)


def _utc(seconds: float) -> str:
    return datetime.datetime.fromtimestamp(seconds, datetime.timezone.utc).isoformat(timespec="seconds")


_HASH_WINDOW = 16 * 2**20  # bytes of the file mapped at a time while hashing (a multiple of mmap's granularity)


def _sha256(path: Path) -> str:
    """The file's sha256, hashed from memory maps of 16 MiB windows (the page cache's pages, not copies of them: 17 %
    less CPU than reading 1 MiB blocks, 0.17 against 0.20 s for 198 MB; the process maps one window at a time)."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        size = os.fstat(fh.fileno()).st_size
        for start in range(0, size, _HASH_WINDOW):
            with mmap.mmap(fh.fileno(), min(_HASH_WINDOW, size - start), offset=start,
                           access=mmap.ACCESS_READ) as window:
                if hasattr(window, "madvise"):  # POSIX: read ahead
                    window.madvise(mmap.MADV_SEQUENTIAL)
                digest.update(window)
    return digest.hexdigest()


def input_identity(path) -> dict:
    """What identifies an input: path, size, modification time and sha256 (size + mtime above :data:`HASH_LIMIT`).

    Parameters
    ----------
    path : str or os.PathLike
        A file or a folder (a sequence folder, a Zarr store, the output folder of another command).

    Returns
    -------
    dict
        ``path`` (absolute), ``kind`` (``'file'``, ``'folder'`` or ``'missing'``), ``bytes``, ``mtime`` (UTC,
        ISO 8601), ``identity`` (``'sha256'`` or ``'size+mtime'``) and ``sha256`` (None when not computed); a
        folder adds ``files`` (how many it holds, at any depth).
    """
    path = Path(path)
    entry = {"path": os.path.abspath(path)}
    if path.is_file():
        stat = path.stat()
        hashed = stat.st_size <= HASH_LIMIT
        entry.update(kind="file", bytes=stat.st_size, mtime=_utc(stat.st_mtime),
                     identity="sha256" if hashed else "size+mtime", sha256=_sha256(path) if hashed else None)
    elif path.is_dir():
        stats = [p.stat() for p in path.rglob("*") if p.is_file()]
        entry.update(kind="folder", files=len(stats), bytes=sum(s.st_size for s in stats),
                     mtime=_utc(max((s.st_mtime for s in stats), default=path.stat().st_mtime)),
                     identity="size+mtime", sha256=None)
    else:
        entry.update(kind="missing", bytes=None, mtime=None, identity=None, sha256=None)
    return entry


def input_changed(entry: dict) -> str | None:
    """Whether an input recorded by :func:`input_identity` is still the file the run read.

    Parameters
    ----------
    entry : dict
        One of ``run.json``'s ``inputs``.

    Returns
    -------
    str or None
        None when the file at ``entry['path']`` has the recorded size and sha256 (for ``identity`` ``'size+mtime'``:
        the recorded size and modification time); otherwise what differs, as a phrase such as ``'no longer
        exists'`` or ``'has changed (3756244 bytes then, 1024 now)'``.
    """
    path = Path(entry.get("path", ""))
    if entry.get("kind") != "file":
        return "was not recorded as a file"
    if not path.is_file():
        return "no longer exists"
    stat = path.stat()
    if stat.st_size != entry.get("bytes"):
        return f"has changed ({entry.get('bytes')} bytes then, {stat.st_size} now)"
    if entry.get("identity") == "sha256":
        return None if _sha256(path) == entry.get("sha256") else "has changed (its sha256 differs)"
    if _utc(stat.st_mtime) != entry.get("mtime"):
        return f"has changed (modified {_utc(stat.st_mtime)}, the run read the version of {entry.get('mtime')})"
    return None


def read_run_json(path) -> dict | None:
    """The record of a run (:func:`write_run_json`), or None when there is none or it cannot be read.

    Parameters
    ----------
    path : str or os.PathLike
        ``run.json`` of an output folder, or ``<output>.run.json`` (:func:`run_json_path`).

    Returns
    -------
    dict or None
        The record; None for a missing file, a file that is not JSON or not a record (no ``command``).
    """
    try:
        record = json.loads(Path(path).read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None
    return record if isinstance(record, dict) and "command" in record else None


def write_run_json(path, *, command: str, options: dict, inputs: dict, started: float, seconds: float,
                   stage_seconds: dict, outputs: dict, results: dict | None = None,
                   identities: dict | None = None) -> Path:
    """Write the record of a run (contents in the module notes), atomically; the one writer every job uses.

    Parameters
    ----------
    path : str or os.PathLike
        Where (:func:`run_json_path`; inside an output folder's staging folder for jobs that stage their files).
    command : str
        The command's name.
    options : dict
        Every argument of the job (made JSON-able by :func:`jsonable`).
    inputs : dict
        Input paths by role (``'input'``, ``'source'``, ...); None entries are left out.
    started : float
        Start time, seconds since the epoch (``time.time()``).
    seconds : float
        Wall time of the run, seconds.
    stage_seconds : dict
        Wall time of each stage, seconds.
    outputs : dict
        Paths written, by key (None entries are left out).
    results : dict, optional
        The job's counts and measures.
    identities : dict, optional
        Identities already made (:func:`input_identity`), by absolute path: these inputs are not identified again.

    Returns
    -------
    pathlib.Path
    """
    known = identities or {}
    record = {
        "seismo3d_version": __version__,
        "command": command,
        "argv": list(sys.argv),
        "cli": None,
        "options": jsonable(options),
        "inputs": {role: known.get(os.path.abspath(p)) or input_identity(p) for role, p in inputs.items()
                   if p is not None},
        "started": _utc(started),
        "seconds": round(float(seconds), 6),
        "stage_seconds": {k: round(float(v), 6) for k, v in stage_seconds.items()},
        "outputs": {k: os.fspath(v) for k, v in outputs.items() if v is not None},
        "results": jsonable(results or {}),
    }
    call = _CLI_CALL.get()
    if call is not None and call["command"] == command:
        record["cli"] = call
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(record, indent=1) + "\n")
    return path


class RunRecord:
    """The record of one run in the making: its start, options and stage times, written by :meth:`write`.

    Parameters
    ----------
    command : str
        The command's name (``'faults'``, ``'register'``, ...).
    options : dict
        Every argument of the job as called (e.g. ``dict(locals())`` first thing in the job).

    Examples
    --------
    >>> record = RunRecord("plan", dict(locals()))            # doctest: +SKIP
    >>> with record.stage("read"):                              # doctest: +SKIP
    ...     grid = load_occupancy(path)
    >>> record.write(run_json_path(out), inputs={"grid": path}, outputs={"path": out})  # doctest: +SKIP
    """

    def __init__(self, command: str, options: dict):
        self.command = command
        self.options = dict(options)
        self.started = time.time()
        self._t0 = time.perf_counter()
        self.stage_seconds: dict = {}
        self._identities: dict = {}  # absolute path -> Future of its input_identity, from identify_early

    @contextlib.contextmanager
    def stage(self, name: str):
        """Time the block as stage ``name`` (a repeated name adds up)."""
        t0 = time.perf_counter()
        try:
            yield
        finally:
            self.stage_seconds[name] = self.stage_seconds.get(name, 0.0) + time.perf_counter() - t0

    def identify_early(self, *paths) -> None:
        """Start identifying inputs (:func:`input_identity`: the sha256 of a file up to :data:`HASH_LIMIT`, about
        0.15 s per 200 MB) on a background thread, so that the hashing, which releases the GIL, overlaps the job's
        imports and reading instead of following them; :meth:`write` then uses these identities.

        The identity is taken when the job starts, before it reads the input, rather than after. The thread is a
        daemon: a job that fails does not wait for it.

        Parameters
        ----------
        *paths : str or os.PathLike or None
            Input files or folders (None is skipped).
        """
        for path in paths:
            if path is not None and os.path.abspath(path) not in self._identities:
                future = Future()
                self._identities[os.path.abspath(path)] = future
                threading.Thread(target=_identify_into, args=(future, path), name="seismo3d-input-identity",
                                 daemon=True).start()

    @property
    def seconds(self) -> float:
        """Wall time since the record was started."""
        return time.perf_counter() - self._t0

    def write(self, path, *, inputs: dict, outputs: dict, results: dict | None = None) -> Path:
        """Write ``run.json`` at ``path`` (:func:`write_run_json`).

        Parameters
        ----------
        path : str or os.PathLike
        inputs : dict
            Input paths by role.
        outputs : dict
            Paths written, by key.
        results : dict, optional
            Counts and measures of the run.

        Returns
        -------
        pathlib.Path
        """
        identities = {p: future.result() for p, future in self._identities.items()}  # raises a failed one's error
        return write_run_json(path, command=self.command, options=self.options, inputs=inputs, started=self.started,
                              seconds=self.seconds, stage_seconds=self.stage_seconds, outputs=outputs,
                              results=results, identities=identities)


def _identify_into(future: Future, path) -> None:
    """On a background thread: ``future`` set to :func:`input_identity` of ``path``, or to its error."""
    try:
        future.set_result(input_identity(path))
    except BaseException as exc:  # handed to RunRecord.write, which raises it
        future.set_exception(exc)
