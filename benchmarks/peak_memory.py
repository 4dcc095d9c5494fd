"""The peak memory of a process, as the benchmarks report it (Linux).

:class:`PeakRSS` reads the process's own high-water mark of resident memory (``VmHWM`` of ``/proc/PID/status``),
which the kernel keeps exactly, so a peak between two samples is not missed and a child the process forks (a tool
run by ``subprocess``: a copy of the whole process until it execs) is not counted again; and, for runs whose work
is in child processes (a ``dask.distributed`` cluster of worker processes), the summed proportional set size (PSS)
of the process and its children, shared pages split between the processes that share them.
"""

from __future__ import annotations

import os
import threading
import time


def _hwm(pid: int) -> int | None:
    """``VmHWM`` of a process, bytes; None once it has exited."""
    try:
        with open(f"/proc/{pid}/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        return None
    return None  # a zombie: its status has no memory lines


def reset_peak(pid: int | None = None) -> bool:
    """Reset a process's ``VmHWM`` to its resident memory now (writing 5 to ``/proc/PID/clear_refs``, Linux 4.0+);
    False when the kernel does not allow it (the peak is then the one since the process started)."""
    try:
        with open(f"/proc/{pid or os.getpid()}/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


class PeakRSS:
    """The peak memory of a process from now on (this process by default).

    ``peak`` (and :meth:`stop`'s value) is the process's own peak resident memory: its ``VmHWM``, reset when the
    sampler starts (:func:`reset_peak`) and read every 0.2 s while the process lives and once more at :meth:`stop`.
    The kernel keeps it exactly, so it misses no peak between samples, and only the last 0.2 s of a process that
    exits before :meth:`stop` can be missed. Its children are not in it: a fork of the process (e.g. ctypes' library
    search running ``/sbin/ldconfig``, which once made a summed RSS count a 0.7 GiB process twice) is a copy of pages
    the process already counts. ``peak_pss`` is the largest summed proportional set size (PSS) of the process and its
    children, sampled every 1 s: the memory the machine gives a run whose work is in child processes (a
    ``dask.distributed`` cluster's workers), pages shared between them counted once.

    Parameters
    ----------
    pid : int, optional
        The process (default this one).
    """

    def __init__(self, pid: int | None = None):
        import psutil

        self.pid = int(pid or os.getpid())
        self.proc = psutil.Process(self.pid)
        reset_peak(self.pid)
        self.peak, self.peak_pss, self._stop = _hwm(self.pid) or 0, 0, threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        import psutil

        tick = 0
        while not self._stop.is_set():
            self.peak = max(self.peak, _hwm(self.pid) or 0)
            if tick % 5 == 0:
                pss = 0
                try:
                    for p in [self.proc] + self.proc.children(recursive=True):
                        try:
                            pss += getattr(p.memory_full_info(), "pss", 0)
                        except psutil.Error:
                            pass
                except psutil.Error:
                    pass
                self.peak_pss = max(self.peak_pss, pss)
            tick += 1
            time.sleep(0.2)

    def stop(self) -> int:
        """Stop sampling; the process's own peak resident memory, bytes."""
        self._stop.set()
        self._thread.join()
        self.peak = max(self.peak, _hwm(self.pid) or 0)
        return self.peak
