"""How the ``seismo3d`` command speaks: seismo3d's errors as one line with exit code 2 (library argument names
replaced by the command's flags), warnings as one line each, Ctrl-C as one line with exit code 130, and progress
lines of long steps on standard error. Used by every command of :mod:`seismo3d.cli`.
"""

from __future__ import annotations

import contextlib
import functools
import logging
import re
import sys
import warnings

import typer

from .errors import Seismo3dError

__all__ = ["compile_note", "friendly", "in_flags", "log_progress_to_stderr", "one_line_warnings"]

class _StderrHandler(logging.Handler):
    """Log records as plain lines on the current standard error (progress lines of long steps)."""

    def emit(self, record):
        try:
            sys.stderr.write(self.format(record) + "\n")
            sys.stderr.flush()
        except (ValueError, OSError):  # pragma: no cover - stderr closed
            pass


# said when a kernel is really compiled (not found in numba's cache): the first run of each command, and of a new kind
# of input (a 2D line after 3D cubes), compiles the kernels it needs and no others
COMPILE_NOTE = ("note: compiling the numba kernels this run needs for the first time (seconds; a minute or two for a "
                "first faults run); numba's cache keeps them for later runs")


@contextlib.contextmanager
def compile_note():
    """Say in one line on standard error, the first time within the block that one of seismo3d's cached numba
    kernels is compiled (not in numba's cache yet: a fresh install, or the first run of a command or of a kind of
    input), that numba's cache keeps them.

    Kernels loaded from numba's cache say nothing (numba's ``numba:compile`` event fires only on a cache miss, after
    the cache index was looked up), nor do kernels that are not cached. Call it after the command's job is imported
    (numba is then loaded)."""
    try:
        from numba.core import event
    except ImportError:  # pragma: no cover - numba is a dependency
        yield
        return

    class _Once(event.Listener):
        said = False

        def on_start(self, ev):
            dispatcher = (ev.data or {}).get("dispatcher")
            module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
            cached = type(getattr(dispatcher, "_cache", None)).__name__ not in ("NullCache", "NoneType")
            if not self.said and cached and module.startswith("seismo3d"):
                self.said = True
                typer.echo(COMPILE_NOTE, err=True)

        def on_end(self, ev):
            pass

    with event.install_listener("numba:compile", _Once()):
        yield


def log_progress_to_stderr() -> None:
    logger = logging.getLogger("seismo3d")
    if not any(isinstance(h, _StderrHandler) for h in logger.handlers):
        handler = _StderrHandler()
        handler.setFormatter(logging.Formatter("%(message)s"))
        logger.addHandler(handler)
    logger.setLevel(logging.INFO)


_WORDS = {"init", "endian"}  # argument names that are no common English word: translated wherever they stand alone
# The options of every command that reads SEG-Y (one opening path: seismo3d.seismic.open_segy).
_SEGY_FLAGS = {"iline": "--iline", "xline": "--xline", "endian": "--endian", "ignore_geometry": "--ignore-geometry",
               "sample_unit": "--sample-unit"}
# The options every command has (the output policy of seismo3d.jobs.outputs).
_COMMON_FLAGS = {"overwrite": "--overwrite"}


def in_flags(message: str, flags: dict) -> str:
    """A library message in the command's terms: ``max_distance=0.1`` -> ``--max-distance 0.1``,
    ``endian='little'`` -> ``--endian little``, ``ignore_geometry=True`` -> ``--ignore-geometry``, ``max_distance``
    -> ``--max-distance`` (names without an underscore, such as ``model``, only when followed by ``=``); a library
    form followed by its flag, ``demo=True (--demo)``, becomes the flag."""
    message = re.sub(r"(?<![\w-])\w+=\S+ \((--[\w-]+)\)", r"\1", message)
    for name, flag in flags.items():
        message = re.sub(rf"(?<![\w-]){name}=True\b", flag, message)
        message = re.sub(rf"(?<![\w-]){name}=(['\"])([^'\"]*)\1", rf"{flag} \2", message)
        message = re.sub(rf"(?<![\w-]){name}=", f"{flag} ", message)
        if "_" in name or name in _WORDS:
            message = re.sub(rf"(?<![\w/.-]){name}(?![\w/-]|\.\w)", flag, message)  # not in a file name
    return message


@contextlib.contextmanager
def one_line_warnings(flags: dict | None = None):
    """Warnings as one line each on standard error (``warning: ...``, library argument names replaced by ``flags``),
    not Python's two-line format. Inside a command (where :func:`friendly` set it up) a call without ``flags``
    keeps the command's translation."""
    if flags is None and getattr(warnings.showwarning, "one_line", False):
        yield
        return

    def one_line(message, category, filename, lineno, file=None, line=None):
        typer.echo(f"warning: {in_flags(str(message), flags or {})}", err=True)

    one_line.one_line = True
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = one_line
        yield


def friendly(flags: dict | None = None):
    """Seismo3d's errors as one line with exit code 2 and warnings as one line each (library argument names replaced
    by ``flags`` and the SEG-Y options); Ctrl-C as one line with exit code 130."""
    flags = {**_SEGY_FLAGS, **_COMMON_FLAGS, **(flags or {})}

    def decorate(fn):
        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            from .jobs.runinfo import cli_call  # here: --help needs no run record (hashlib, json: 15 ms)

            try:  # the command's name is its function's (map_ for map)
                with one_line_warnings(flags), cli_call(fn.__name__.rstrip("_"), kwargs):
                    return fn(*args, **kwargs)
            except Seismo3dError as exc:
                typer.echo(f"error: {in_flags(str(exc), flags)}", err=True)
                raise typer.Exit(2) from None
            except KeyboardInterrupt as exc:
                # a job that keeps partial results to resume says so (resume_hint); others leave nothing
                hint = getattr(exc, "resume_hint", None)
                typer.echo(hint or "interrupted: earlier results are as they were and nothing half-written was left "
                           "(an output folder's new files are moved in only when all are written)", err=True)
                raise typer.Exit(130) from None

        return wrapper

    return decorate
