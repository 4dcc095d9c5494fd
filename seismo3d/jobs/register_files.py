"""The results and files of ``seismo3d register`` shared by its branches (:mod:`seismo3d.jobs.register`,
:mod:`seismo3d.jobs.register_terrain`): the job's result, the transform JSON written and read.
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
from dataclasses import dataclass

import numpy as np

from .._atomic import atomic_path
from ..errors import InputError
from ..geometry.transforms import as_transform
from .outputs import output_file
from .runinfo import RunRecord, run_json_path

__all__ = ["RegisterJob", "finish_register_job", "write_json", "read_transform"]


@dataclass(frozen=True, eq=False)
class RegisterJob:
    """What :func:`~seismo3d.jobs.register.run_register_job` did.

    Attributes
    ----------
    kind : {'point_clouds', 'volumes', 'terrain'}
        What was registered.
    result : RegistrationResult, VolumeRegistration or TerrainRegistration
        The registration.
    payload : dict
        What was written to the JSON file.
    converged : bool
        Whether the registration converged (``payload['converged']``).
    output : pathlib.Path
        The transform JSON.
    run_json : pathlib.Path
        The record of the run (:mod:`seismo3d.jobs.runinfo`).
    stage_seconds : dict
        Wall time of each stage (``read``, ``register``, ``write``).
    """

    kind: str
    result: object
    payload: dict
    converged: bool
    output: pathlib.Path | None = None
    run_json: pathlib.Path | None = None
    stage_seconds: dict | None = None


def write_json(path, payload: dict) -> None:
    """Write ``payload`` as indented JSON, atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(payload, indent=2) + "\n")


def read_transform(path, dim: int) -> np.ndarray:
    """The (dim+1, dim+1) transform of a JSON file (``{"transform": [[...], ...]}`` or a bare matrix).

    Raises
    ------
    InputError
        A missing file, not JSON, or not a (dim+1, dim+1) transform (the message names ``--init``).
    """
    try:
        payload = json.loads(pathlib.Path(path).read_text())
    except FileNotFoundError as exc:
        raise InputError(f"--init file {path} does not exist") from exc
    except json.JSONDecodeError as exc:
        raise InputError(f"--init file {path} is not JSON ({exc}); write {{\"transform\": [[...], ...]}}") from exc
    matrix = payload.get("transform") if isinstance(payload, dict) else payload
    return as_transform(matrix, f"the transform in {path}", dims=(dim,))


def finish_register_job(job: RegisterJob, record: RunRecord, output: pathlib.Path, inputs: dict) -> RegisterJob:
    """Write the transform JSON and the run's record beside it; ``job`` with both paths and the stage times.

    Parameters
    ----------
    job : RegisterJob
    record : RunRecord
    output : pathlib.Path
        The transform JSON.
    inputs : dict
        Input paths by role (None entries left out).

    Returns
    -------
    RegisterJob
    """
    with record.stage("write"):
        write_json(output, job.payload)
    run_json = record.write(run_json_path(output_file(output)), inputs=inputs, outputs={"transform": output},
                            results={k: job.payload.get(k) for k in ("converged", "fitness", "inlier_rmse",
                                                                      "n_iterations", "correlation", "overlap")
                                     if k in job.payload} | {"kind": job.kind})
    return dataclasses.replace(job, output=output, run_json=run_json, stage_seconds=dict(record.stage_seconds))
