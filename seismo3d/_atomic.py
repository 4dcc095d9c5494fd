"""Atomic output: write to a temporary file beside the destination, then rename over it."""

from __future__ import annotations

import os
import pathlib
import tempfile
from contextlib import contextmanager

from .errors import InputError

__all__ = ["atomic_path"]


@contextmanager
def atomic_path(path):
    """Yield a temporary path in the destination's folder; on success rename it to ``path``, on any error remove it.

    A reader never sees a half-written file, and an interrupted run (exception, Ctrl-C) leaves any earlier file at
    ``path`` untouched.

    Parameters
    ----------
    path : str or os.PathLike
        The final destination.

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
    folder = path.parent if str(path.parent) else pathlib.Path(".")
    if not folder.is_dir():
        raise InputError(f"cannot write {path}: folder {folder} does not exist; create it first")
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    tmp = pathlib.Path(tmp)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; a finished output gets the usual permissions
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
