"""Progress of long runs: a tqdm bar on a terminal or in a notebook, and one log line per step everywhere else.

A bar redrawn with carriage returns is unreadable in a log file or a CI console, so when standard error is not a
terminal the steps are written as lines to the ``seismo3d`` logger (level INFO) instead; the ``seismo3d`` command
sends that logger to standard error. Loops over many items (inlines, scanned planes) log at most about twenty lines.

A step of a run computed on one block reports the loop within that block (the network's sections, the voting's
seeds) with :func:`progress_within`, under the step's name, when its executor asks for it with
:func:`reporting_within` (the run in memory, one block per step); a run by blocks reports its blocks, not within them.
"""

from __future__ import annotations

import logging
import sys
import time
from contextlib import contextmanager
from contextvars import ContextVar

__all__ = ["LOGGER", "progress_steps", "progress_within", "reporting_within"]

LOGGER = logging.getLogger("seismo3d")
_MAX_LINES = 20  # log lines of a loop over items (every 5 %)
# The name under which the loops of the block step under way report (reporting_within), None: they do not. A context
# variable: the threads of a run by blocks start without it.
_WITHIN: ContextVar = ContextVar("seismo3d_progress_within", default=None)


def _interactive() -> bool:
    """Standard error is a terminal, or this runs in a Jupyter kernel (where tqdm draws a widget)."""
    try:
        if sys.stderr.isatty():
            return True
    except (AttributeError, ValueError):  # a closed or replaced stderr
        pass
    # a kernel, not a process that merely imported ipykernel (nbclient, a test running notebooks)
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None and hasattr(ipython, "get_ipython") else None
    return shell is not None and "IPKernelApp" in getattr(shell, "config", {})


class _Steps:
    """What :func:`progress_steps` yields: ``start(label)`` names the step that begins, ``advance(n)`` counts done;
    ``seconds`` holds the wall time of each named step (from its ``start`` to the next one's or the end)."""

    def __init__(self, total: int, desc: str, unit: str, bar):
        self.total, self.desc, self.unit, self.bar = int(total), desc, unit, bar
        self.done = 0
        self._named = False
        self._next_line = 0
        self.seconds: dict = {}
        self._running: tuple | None = None  # (label, start time) of the named step under way

    def stop(self) -> None:
        """The named step under way, if any, ends (its time is added to ``seconds``)."""
        if self._running is not None:
            label, t0 = self._running
            self.seconds[label] = self.seconds.get(label, 0.0) + time.perf_counter() - t0
            self._running = None

    def start(self, label: str) -> None:
        """A named step begins (the bar's postfix; one log line); the one before it ends."""
        self.stop()
        self._running = (label, time.perf_counter())
        self._named = True
        if self.bar is not None:
            self.bar.set_postfix_str(label)
        elif self.enabled:
            LOGGER.info("%s: %s (%d/%d)", self.desc, label, min(self.done + 1, self.total), self.total)

    def advance(self, n: int = 1, status: str | None = None) -> None:
        """``n`` more steps or items are done (a log line every 5 % of a loop over unnamed items); ``status``, when
        given, is shown beside the count (the bar's postfix, the end of the log line), e.g. a rate."""
        self.done += n
        if self.bar is not None:
            if status is not None:
                self.bar.set_postfix_str(status, refresh=False)
            self.bar.update(n)
        elif self.enabled and not self._named and (self.done >= self._next_line or self.done >= self.total):
            if status is None:
                LOGGER.info("%s: %d/%d %s", self.desc, min(self.done, self.total), self.total, self.unit)
            else:
                LOGGER.info("%s: %d/%d %s, %s", self.desc, min(self.done, self.total), self.total, self.unit, status)
            self._next_line = self.done + max(1, self.total // _MAX_LINES)

    enabled = True


class _Silent(_Steps):
    enabled = False

    def __init__(self):
        super().__init__(0, "", "", None)


def no_progress() -> _Steps:
    """What :func:`progress_steps` yields when disabled, outside a ``with`` block: ``start`` and ``advance`` that
    report nothing (for a caller whose progress is reported elsewhere)."""
    return _Silent()


@contextmanager
def progress_steps(total: int, desc: str, *, unit: str = "step", enabled: bool = True):
    """Report the progress of ``total`` steps: a tqdm bar on a terminal, log lines otherwise, nothing when disabled.

    Parameters
    ----------
    total : int
        Number of steps (or items).
    desc : str
        What runs, e.g. ``'faults'``.
    unit : str
        What a step is, e.g. ``'inline'``.
    enabled : bool
        False: report nothing.

    Yields
    ------
    object
        With ``start(label)`` (a named step begins) and ``advance(n=1, status=None)`` (steps done; ``status`` an
        optional short text such as a rate), and ``seconds``: the wall time of each named step, complete when the
        ``with`` block ends (reported or not).
    """
    if not enabled:
        steps = no_progress()
    elif _interactive():
        from tqdm.auto import tqdm

        with tqdm(total=total, desc=desc, unit=unit, leave=False, file=sys.stderr) as bar:
            steps = _Steps(total, desc, unit, bar)
            try:
                yield steps
            finally:
                steps.stop()
        return
    else:
        steps = _Steps(total, desc, unit, None)
    try:
        yield steps
    finally:
        steps.stop()


@contextmanager
def reporting_within(desc: str | None):
    """Within this ``with`` block, the loops of the step under way (:func:`progress_within`) report under ``desc``.

    Parameters
    ----------
    desc : str or None
        The step's name, e.g. ``'fault voting'``; None: they report nothing (the default).
    """
    token = _WITHIN.set(desc)
    try:
        yield
    finally:
        _WITHIN.reset(token)


@contextmanager
def progress_within(total: int, *, unit: str):
    """The progress of a loop inside a block step (:func:`progress_steps`, under the step's name), reported when the
    step's executor asks for it (:func:`reporting_within`: a run in memory), silent otherwise (a run by blocks, whose
    executor reports per block).

    Parameters
    ----------
    total : int
        Items of the loop.
    unit : str
        What an item is, e.g. ``'section'``, ``'seed'``.

    Yields
    ------
    object
        As :func:`progress_steps`: ``advance(n)`` counts items done.
    """
    desc = _WITHIN.get()
    with progress_steps(total, desc or "", unit=unit, enabled=desc is not None) as bar:
        yield bar
