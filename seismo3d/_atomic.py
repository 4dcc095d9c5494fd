"""Atomic output: write to a temporary file beside the destination, then rename over it."""

from __future__ import annotations

import json
import os
import pathlib
import shutil
import signal
import socket
import tempfile
import threading
from contextlib import contextmanager

from .errors import InputError

__all__ = ["atomic_path", "atomic_directory", "deferred_interrupt", "existing_folder", "remove_stale_staging",
           "SetAside", "STAGING_RECORD", "StagedFolder"]


@contextmanager
def atomic_path(path, *, suffix: str = ".tmp"):
    """Yield a temporary path in the destination's folder; on success rename it to ``path``, on any error remove it.

    A reader never sees a half-written file, and an interrupted run (exception, Ctrl-C) leaves any earlier file at
    ``path`` untouched.

    Parameters
    ----------
    path : str or os.PathLike
        The final destination.
    suffix : str, optional
        End of the temporary file's name: ``.tmp``, or for a writer that insists on its own extension (VTK's PLY
        writer appends ``.ply`` to any other name) e.g. ``.tmp.ply``.

    Yields
    ------
    pathlib.Path
        Where to write.

    Raises
    ------
    InputError
        If the destination's folder does not exist.
    """
    path = pathlib.Path(path)
    folder = existing_folder(path)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=suffix)
    os.close(fd)
    tmp = pathlib.Path(tmp)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; a finished output gets the usual permissions
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


@contextmanager
def atomic_directory(path):
    """Yield a temporary directory beside ``path``; on success rename it to ``path``, on any error remove it.

    For outputs that are directories (a Zarr store): a reader never sees a half-written ``path``, and an interrupted
    run (exception, Ctrl-C) leaves only what was at ``path`` before. An existing ``path`` is replaced on success (the
    caller decides whether that is allowed): it is first renamed aside, then removed once the new one is in place.

    Parameters
    ----------
    path : str or os.PathLike
        The final destination directory.

    Yields
    ------
    pathlib.Path
        An empty directory to write into.

    Raises
    ------
    InputError
        If the folder that is to hold ``path`` does not exist.
    """
    path = pathlib.Path(path)
    folder = existing_folder(path)
    tmp = pathlib.Path(tempfile.mkdtemp(dir=folder, prefix=f".{path.name}.", suffix=".tmp"))
    old = None
    try:
        yield tmp
        os.chmod(tmp, 0o777 & ~_umask())  # mkdtemp makes 0700; a finished output gets the usual permissions
        if path.exists() or path.is_symlink():
            old = pathlib.Path(tempfile.mkdtemp(dir=folder, prefix=f".{path.name}.", suffix=".old"))
            os.replace(path, old / "replaced")
        try:
            os.replace(tmp, path)
        except BaseException:
            if old is not None:  # put the earlier output back
                os.replace(old / "replaced", path)
            raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


# The record of the run that made a staging folder, inside it (StagedFolder's owner)
STAGING_RECORD = ".staging-run.json"


def _this_process(owner: str) -> dict:
    """The record of a staging folder: its owner, and this process (host, id, start time: an id the system has
    given to a later process is told apart by its start time)."""
    import psutil

    return {"owner": owner, "host": socket.gethostname(), "pid": os.getpid(),
            "started": psutil.Process().create_time()}


def remove_stale_staging(folder, owner: str) -> list:
    """Remove the staging folders (``.staged-*.tmp``) of ``owner`` in ``folder`` whose run's process is no longer
    running on this host (a run killed outright), as :class:`StagedFolder` with ``owner`` does on entering.

    Parameters
    ----------
    folder : str or os.PathLike
        An output folder.
    owner : str
        What writes it (:class:`StagedFolder`'s ``owner``).

    Returns
    -------
    list of pathlib.Path
        The staging folders removed: only those whose record (:data:`STAGING_RECORD`) names ``owner`` and this host,
        and a process that has ended.
    """
    import psutil

    removed = []
    for path in sorted(pathlib.Path(folder).glob(".staged-*.tmp")):
        try:
            record = json.loads((path / STAGING_RECORD).read_text())
            if record.get("owner") != owner or record.get("host") != socket.gethostname():
                continue
            pid, started = int(record["pid"]), float(record["started"])
        except (OSError, ValueError, TypeError, KeyError, AttributeError):
            continue  # not a staging folder of this owner's: left alone
        try:
            if abs(psutil.Process(pid).create_time() - started) < 0.01:  # its clock ticks
                continue  # its run is still going
        except psutil.NoSuchProcess:
            pass
        shutil.rmtree(path, ignore_errors=True)
        removed.append(path)
    return removed


class StagedFolder:
    """The files of an output folder written into a hidden staging folder inside it, and moved in together when the
    block ends without an error (each by a rename over any earlier file; a staged folder replaces an earlier folder of
    its name whole); on an error, nothing of them is kept.

    A run that fails while writing its files (a full disk, a renderer that cannot start) leaves the earlier files of
    the folder as they were, not a mix of old and new ones. The folder is created (with its parents) on entering,
    and removed again on an error when it was created here and is still empty, so a refused run leaves nothing
    behind. Files the block writes into the folder itself (e.g. the resumable stores of a chunked run) are not
    touched.

    A process killed outright (``kill -9``, a crash, a power cut) cannot remove its staging folder. With ``owner``,
    the staging folder holds a record of its run (:data:`STAGING_RECORD`: the owner, the host, the process id and
    its start time), and entering removes the staging folders of the same ``owner`` in ``folder`` whose process is
    no longer running on this host (:func:`remove_stale_staging`): only those; a folder without that record, of
    another owner or host, or whose process still runs is left alone.

    Parameters
    ----------
    folder : str or os.PathLike
        The output folder.
    owner : str, optional
        What writes the folder (e.g. ``'seismo3d faults'``): its staging folders left by a killed run are removed
        on entering.

    Examples
    --------
    >>> with StagedFolder(out_dir) as stage:                  # doctest: +SKIP
    ...     (stage.path / "result.csv").write_text("...")
    >>> stage.final(stage.path / "result.csv")                # doctest: +SKIP
    PosixPath('out_dir/result.csv')
    """

    def __init__(self, folder, *, owner: str | None = None):
        self.folder = pathlib.Path(folder)
        self.owner = owner
        self.path = None
        self._created = False

    def __enter__(self) -> "StagedFolder":
        self._created = not self.folder.exists()
        self.folder.mkdir(parents=True, exist_ok=True)
        if self.owner is not None:
            remove_stale_staging(self.folder, self.owner)
        self.path = pathlib.Path(tempfile.mkdtemp(dir=self.folder, prefix=".staged-", suffix=".tmp"))
        if self.owner is not None:
            (self.path / STAGING_RECORD).write_text(json.dumps(_this_process(self.owner)))
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None:
                for item in sorted(p for p in self.path.iterdir() if p.name != STAGING_RECORD):
                    final, earlier = self.folder / item.name, None
                    if item.is_dir() and final.is_dir() and not final.is_symlink():
                        # a folder of files (a TSurf per fault): rename() cannot replace a folder that is not empty,
                        # so the earlier one goes into the staging folder first, removed with it
                        earlier = self.path / f".earlier-{item.name}"
                        os.replace(final, earlier)
                    try:
                        os.replace(item, final)
                    except BaseException:
                        if earlier is not None:  # put the earlier folder back
                            os.replace(earlier, final)
                        raise
        finally:
            shutil.rmtree(self.path, ignore_errors=True)
            if exc_type is not None and self._created and not any(self.folder.iterdir()):
                self.folder.rmdir()

    def final(self, path) -> pathlib.Path:
        """Where a file written into the staging folder is once the block has ended.

        Parameters
        ----------
        path : str or os.PathLike
            A path inside :attr:`path` (other paths are returned unchanged).

        Returns
        -------
        pathlib.Path
        """
        path = pathlib.Path(path)
        return self.folder / path.relative_to(self.path) if path.is_relative_to(self.path) else path


class SetAside:
    """Entries of a folder that a run replaces, moved into a hidden folder inside it while the run writes its own:
    deleted when the block ends without an error, moved back when it ends with one (after removing whatever the run
    left at their names), so a failed or interrupted run leaves the earlier entries as they were.

    Parameters
    ----------
    folder : str or os.PathLike
        The folder holding the entries (an output folder).

    Examples
    --------
    >>> with SetAside(out_dir) as aside:                      # doctest: +SKIP
    ...     aside.move(["fault_likelihood.zarr", "fault_likelihood.zarr.work"])
    ...     write_new_stores(out_dir)
    """

    def __init__(self, folder):
        self.folder = pathlib.Path(folder)
        self.path = None  # the hidden folder, made by the first move
        self.names: list = []  # every name handed over: the run's own entries there are removed on an error
        self.moved: list = []  # the names whose earlier entries are in the hidden folder

    def __enter__(self) -> "SetAside":
        return self

    def move(self, names) -> None:
        """Move the entries ``names`` (of :attr:`folder`; missing ones are only remembered) aside.

        Parameters
        ----------
        names : iterable of str
        """
        for name in names:
            if name in self.names:
                continue
            self.names.append(name)
            if os.path.lexists(self.folder / name):
                if self.path is None:
                    self.path = pathlib.Path(tempfile.mkdtemp(dir=self.folder, prefix=".earlier-", suffix=".tmp"))
                os.replace(self.folder / name, self.path / name)
                self.moved.append(name)

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is not None:
            for name in self.names:
                _remove(self.folder / name)
            for name in self.moved:
                os.replace(self.path / name, self.folder / name)
        if self.path is not None:
            shutil.rmtree(self.path, ignore_errors=True)


def _remove(path: pathlib.Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    elif os.path.lexists(path):
        path.unlink()


@contextmanager
def deferred_interrupt():
    """A Ctrl-C (SIGINT) that arrives within the block is held until it ends, then raised (KeyboardInterrupt).

    For a block that must not be interrupted midway: the import of VTK's extension modules (pyvista) crashes the
    process (a segmentation fault) when a KeyboardInterrupt is raised inside it, and a crashed process cleans up
    nothing (a :class:`StagedFolder` left behind in the output folder). Outside the main thread, or when SIGINT is
    not Python's default handler (ignored, or the caller's own), the block runs as it is.

    Raises
    ------
    KeyboardInterrupt
        On leaving the block, when a SIGINT arrived within it.
    """
    if threading.current_thread() is not threading.main_thread() or \
            signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        yield
        return
    arrived = []
    signal.signal(signal.SIGINT, lambda signum, frame: arrived.append(signum))  # Python runs it between bytecodes
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if arrived:
        raise KeyboardInterrupt


def existing_folder(path: pathlib.Path) -> pathlib.Path:
    """The folder of ``path``; InputError when it does not exist (checked before a long run, and again on writing).

    Parameters
    ----------
    path : pathlib.Path
        An output file.

    Returns
    -------
    pathlib.Path
        Its folder (``.`` for a bare file name).

    Raises
    ------
    InputError
        The folder does not exist.
    """
    folder = path.parent if str(path.parent) else pathlib.Path(".")
    if not folder.is_dir():
        raise InputError(f"cannot write {path}: folder {folder} does not exist; create it first")
    return folder


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
