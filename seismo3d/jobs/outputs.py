"""The output policy of every ``seismo3d`` command: where a command may write, decided before it reads its inputs.

Every job calls :func:`check_outputs` first, with its inputs and its outputs; the rules are the same for all:

1. **An output is never an input.** An output that is an input (the same path, through symlinks, or the same file
   under another name) and an output folder or store that holds an input are refused, ``overwrite`` or not. A job
   that reads files of an input folder (``mesh.ply`` of a map folder) passes them as inputs too.
2. **Earlier results are never replaced silently.** An output file (or store) that exists, and an output folder
   holding any of the files a run of the command writes there, are refused unless ``overwrite=True``
   (``--overwrite`` on every command). Other files in an output folder are left alone.
3. **An unwritable destination is found before the work.** The folder that is to hold an output (for an output
   folder that does not exist yet: its nearest existing parent) is probed by creating and removing a temporary
   file in it.

The outputs are then written atomically (:mod:`seismo3d._atomic`: a file through a temporary file renamed over it,
an output folder's files staged and moved in when every one is written), so a refused or failed run leaves every
input and every earlier output as it was.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError

__all__ = ["Output", "check_outputs", "output_file", "output_folder", "output_store"]


@dataclass(frozen=True)
class Output:
    """One output of a command, for :func:`check_outputs`.

    Attributes
    ----------
    path : pathlib.Path
        Where the command writes.
    kind : {'file', 'store', 'folder'}
        ``'file'``: one file, replaced whole (its folder must exist); ``'store'``: a directory written whole, such
        as a Zarr store (its folder must exist); ``'folder'``: a folder the command writes ``results`` into
        (created with its parents if missing).
    results : tuple of str
        ``'folder'``: the names of the files a run writes into it (the earlier run's files that need
        ``overwrite``).
    example : str
        A name to suggest in messages (e.g. ``'transform.json'``).
    """

    path: Path
    kind: str
    results: tuple = ()
    example: str = ""


def output_file(path, example: str = "") -> Output:
    """An output file (its folder must exist).

    Parameters
    ----------
    path : str or os.PathLike
    example : str, optional
        A file name to suggest when ``path`` is refused.

    Returns
    -------
    Output
    """
    return Output(Path(path), "file", (), example)


def output_store(path, example: str = "") -> Output:
    """An output directory written whole, such as a Zarr store (its folder must exist).

    Parameters
    ----------
    path : str or os.PathLike
    example : str, optional
        A name to suggest when ``path`` is refused.

    Returns
    -------
    Output
    """
    return Output(Path(path), "store", (), example)


def output_folder(path, results, example: str = "") -> Output:
    """An output folder (created with its parents if missing) and the files a run writes into it.

    Parameters
    ----------
    path : str or os.PathLike
    results : iterable of str
        File names a run writes into the folder.
    example : str, optional
        A folder name to suggest when ``path`` is refused.

    Returns
    -------
    Output
    """
    return Output(Path(path), "folder", tuple(results), example)


def check_outputs(outputs, inputs, *, overwrite: bool = False) -> None:
    """Refuse outputs that would overwrite an input, replace an earlier result without ``overwrite``, or cannot be
    written; called by every job before it reads its inputs (rules in the module notes).

    Parameters
    ----------
    outputs : iterable of Output
        What the command writes (:func:`output_file`, :func:`output_store`, :func:`output_folder`); None entries
        are skipped (an optional output not asked for).
    inputs : iterable of str or os.PathLike
        Every file or folder the command reads; None entries are skipped.
    overwrite : bool, optional
        Allow replacing an earlier result (``--overwrite``).

    Raises
    ------
    InputError
        The first rule an output breaks, in one line naming the path and what to do.
    """
    inputs = [Path(p) for p in inputs if p is not None]
    for output in (o for o in outputs if o is not None):
        for source in inputs:
            _check_apart(output, source)
        _check_kind(output)
        if not overwrite:
            _check_no_earlier_result(output)
        _probe_writable(output)


def _resolved(path: Path) -> Path:
    return Path(os.path.abspath(path)).resolve()


def _same(a: Path, b: Path) -> bool:
    """Whether ``a`` and ``b`` name the same file or folder (symlinks followed; hard links when both exist)."""
    if _resolved(a) == _resolved(b):
        return True
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _suggestion(output: Output, folder: Path) -> str:
    return f", e.g. {folder / output.example}" if output.example else ""


def _check_apart(output: Output, source: Path) -> None:
    """Rule 1: the output is not ``source`` and does not hold it."""
    out = output.path
    what = "output folder" if output.kind == "folder" else "output"
    if _same(out, source):
        raise InputError(f"{what} {out} is the input {source.name} itself; write to another path"
                         f"{_suggestion(output, _resolved(out).parent)}")
    if output.kind != "file" and _resolved(source).is_relative_to(_resolved(out)):
        raise InputError(f"{what} {out} holds the input {source}; write to a folder that holds no input"
                         f"{_suggestion(output, _resolved(out))}")


def _check_kind(output: Output) -> None:
    """A folder where a file is wanted, or the reverse."""
    out = output.path
    if output.kind == "file" and out.is_dir():
        raise InputError(f"output {out} is a folder; name the file to write{_suggestion(output, out)}")
    if output.kind == "folder" and out.exists() and not out.is_dir():
        raise InputError(f"output folder {out} is a file; pass a folder (it is created if missing)")


def _check_no_earlier_result(output: Output) -> None:
    """Rule 2: nothing an earlier run wrote is replaced without ``overwrite``."""
    out = output.path
    if output.kind == "folder":
        earlier = [name for name in output.results if (out / name).exists()] if out.is_dir() else []
        if earlier:
            shown = ", ".join(earlier[:3]) + (f" and {len(earlier) - 3} more" if len(earlier) > 3 else "")
            raise InputError(f"output folder {out} holds the results of an earlier run ({shown}); pass "
                             "overwrite=True (--overwrite) to replace them, or choose another folder")
    elif out.exists() or out.is_symlink():
        raise InputError(f"output {out} exists; pass overwrite=True (--overwrite) to replace it, or choose another "
                         "path")


def _cannot(output: Output) -> str:
    """The start of a rule-3 message: 'cannot write PATH' or 'cannot create output folder PATH'."""
    if output.kind == "folder" and not output.path.is_dir():
        return f"cannot create output folder {output.path}"
    return f"cannot write {output.path}"


def _destination(output: Output) -> Path:
    """The existing folder that will hold the output (rule 3 probes it)."""
    out = output.path
    if output.kind != "folder":
        folder = out.parent if str(out.parent) else Path(".")
        if not folder.is_dir():
            why = "is a file" if folder.exists() else "does not exist"
            raise InputError(f"{_cannot(output)}: folder {folder} {why}; "
                             f"{'create it first' if why == 'does not exist' else 'choose another path'}")
        return folder
    if out.is_dir():
        return out
    parent = Path(os.path.abspath(out)).parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise InputError(f"{_cannot(output)}: {parent} is a file, not a folder; choose another path")
    return parent


def _probe_writable(output: Output) -> None:
    """Rule 3: create and remove a temporary file where the output goes."""
    folder = _destination(output)
    try:
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".seismo3d-probe-")
    except OSError as exc:
        raise InputError(f"{_cannot(output)}: no file can be created in {folder} ({exc.strerror or exc}); choose "
                         "a folder you can write to") from None
    os.close(fd)
    os.unlink(probe)
