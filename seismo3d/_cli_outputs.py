"""The output checks the ``seismo3d`` command makes before it imports a job.

A job module imports the applications (numpy, scipy, numba, pyvista, ...: 1-2 s in a fresh process), so each command
of :mod:`seismo3d.cli` first checks its main output here, with the light output policy alone
(:mod:`seismo3d.jobs.outputs`): a destination the user cannot write, an output that is (or, for a folder or store,
holds) an input, and an existing output file or store without ``--overwrite`` are refused in one line before any heavy
import. The job checks again, with everything it writes (``run.json``, an output folder's earlier results, the files
it reads of an input folder): these checks are a first pass, not the policy.
"""

from __future__ import annotations

from .jobs.outputs import Output, check_outputs, output_file, output_folder, output_store

__all__ = ["check_before_import"]

_OUTPUTS = {"file": output_file, "store": output_store, "folder": lambda path: output_folder(path, ())}


def check_before_import(kind: str, output, inputs, *, overwrite: bool, also: Output | None = None) -> None:
    """Refuse a command's main output before the job (and its heavy imports) is loaded.

    Parameters
    ----------
    kind : {'file', 'store', 'folder'}
        What the command writes (:class:`~seismo3d.jobs.outputs.Output`); for a folder, the earlier run's files
        are the job's to check (its results are named there).
    output : str or os.PathLike
        The output as the user gave it (``-o``).
    inputs : iterable of str or os.PathLike or None
        The command's input paths (None entries skipped).
    overwrite : bool
        ``--overwrite``.
    also : Output, optional
        A second output to check the same way (``horizon --surface``).

    Raises
    ------
    InputError
        As :func:`~seismo3d.jobs.outputs.check_outputs`, one line naming the path and what to do.
    """
    check_outputs([_OUTPUTS[kind](output), also], inputs, overwrite=overwrite)
