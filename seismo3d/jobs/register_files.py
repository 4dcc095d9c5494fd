"""The results and files of ``seismo3d register`` shared by its branches (:mod:`seismo3d.jobs.register`,
:mod:`seismo3d.jobs.register_terrain`): the job's result, the transform JSON written and read.
"""

from __future__ import annotations

import json
import pathlib
from dataclasses import dataclass

import numpy as np

from .._atomic import atomic_path
from ..errors import InputError
from ..geometry.transforms import as_transform

__all__ = ["RegisterJob", "write_json", "read_transform"]


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
    """

    kind: str
    result: object
    payload: dict
    converged: bool


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
