"""A fault network adapted to a survey by ``seismo3d adapt``: the MODEL folder it writes, read back for tracing.

A MODEL folder holds two files:

* ``fault_unet.onnx``: the network, the architecture of :mod:`~seismo3d.seismic.faults.likelihood.network` with the
  weights fine-tuned on an interpreter's faults (or the shipped float network itself when adapting did not win
  clearly on the held-back picks: the record says so), run by ONNX Runtime like the shipped one;
* ``adapt.json``: the record, a ``run.json`` of the ``adapt`` command (:mod:`seismo3d.jobs.runinfo`: the inputs with
  their sha256, the options) whose ``results`` hold the lines and picks, the training steps and loss, the held-back
  validation before and after, the decision (``kept``: ``'adapted'`` or ``'default'``), how MODEL traces
  (:func:`model_tracing`): ``sensitivity`` (the tracing's sensitivity unless one is given) and ``unbroken_veto``
  (whether the tracing's evidence drops the faults across which the reflectors continue unbroken,
  :attr:`~seismo3d.seismic.faults.EvidenceOptions.unbroken_veto`), and ``network_sha256``, the sha256 of
  ``fault_unet.onnx``. A record without ``sensitivity`` or ``unbroken_veto`` (or with None) leaves the tracing's own.

Reading one needs ONNX Runtime only (no training framework); the sha256 of the network is checked against the
record when it is loaded (:func:`seismo3d.seismic.faults.likelihood.learned.load_network`). Writing one is
:mod:`seismo3d.jobs.adapt`'s.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

from ..errors import DataNotFoundError, InputError

__all__ = ["MODEL_NETWORK", "MODEL_RECORD", "ModelTracing", "read_adapted_model", "check_adapted_model",
           "is_model_path", "model_tracing"]

MODEL_NETWORK = "fault_unet.onnx"
MODEL_RECORD = "adapt.json"


def check_adapted_model(path) -> dict:
    """The record of a MODEL folder written by ``seismo3d adapt``, checked: both files present, the network's
    sha256 the recorded one, the tracing it records valid (``sensitivity`` None or in [0, 1], ``unbroken_veto`` None
    or a boolean). The network file is read and hashed once.

    Parameters
    ----------
    path : str or os.PathLike
        The MODEL folder (or its ``fault_unet.onnx``).

    Returns
    -------
    dict
        The record (``adapt.json``).

    Raises
    ------
    DataNotFoundError
        No folder or file at ``path``.
    InputError
        ``path`` is not a MODEL folder of ``seismo3d adapt``, its network is not the one its record names, or the
        record's sensitivity or unbroken veto is not a valid value.
    """
    folder = _folder(path)
    record = _record(folder)
    results = record["results"]
    digest, recorded = hashlib.sha256((folder / MODEL_NETWORK).read_bytes()).hexdigest(), results["network_sha256"]
    if digest != recorded:
        raise InputError(f"{folder / MODEL_NETWORK} has sha256 {digest}, not the {recorded} its {MODEL_RECORD} "
                         "records: the model was changed after 'seismo3d adapt' wrote it; adapt again")
    value = results.get("sensitivity")
    if value is not None and not (isinstance(value, (int, float)) and 0.0 <= float(value) <= 1.0):
        raise InputError(f"{folder / MODEL_RECORD} records a sensitivity of {value!r}, outside [0, 1]; adapt again")
    veto = results.get("unbroken_veto")
    if veto is not None and not isinstance(veto, bool):
        raise InputError(f"{folder / MODEL_RECORD} records an unbroken_veto of {veto!r}, not true or false; adapt "
                         "again")
    return record


@dataclass(frozen=True)
class ModelTracing:
    """How a MODEL folder traces, from its checked record (:func:`model_tracing`).

    Attributes
    ----------
    record : dict
        The record (``adapt.json``), checked by :func:`check_adapted_model`.
    sensitivity : float or None
        The sensitivity in [0, 1] MODEL traces with unless one is given (``seismo3d faults --model MODEL`` without
        ``--sensitivity``); None: the tracing's own.
    unbroken_veto : bool or None
        Whether the tracing's evidence drops the faults across which the reflectors continue unbroken
        (:attr:`~seismo3d.seismic.faults.EvidenceOptions.unbroken_veto`), as ``seismo3d adapt`` chose on the
        held-back picks; None: the tracing's own (on).
    """

    record: dict
    sensitivity: float | None
    unbroken_veto: bool | None


def model_tracing(path) -> ModelTracing:
    """How a MODEL folder traces: its record checked once (:func:`check_adapted_model`: one read of the record, one
    hash of the network), and the sensitivity and unbroken veto it records.

    Parameters
    ----------
    path : str or os.PathLike
        The MODEL folder (or its ``fault_unet.onnx``).

    Returns
    -------
    ModelTracing

    Raises
    ------
    DataNotFoundError, InputError
        As :func:`check_adapted_model`.
    """
    record = check_adapted_model(path)
    results = record["results"]
    sensitivity, veto = results.get("sensitivity"), results.get("unbroken_veto")
    return ModelTracing(record, None if sensitivity is None else float(sensitivity), veto)


def is_model_path(network) -> bool:
    """Whether ``network`` (``LearnedOptions.model``'s answer) names a MODEL folder rather than a shipped network
    ('int8', 'float'): a path with a folder separator, or one that exists."""
    text = str(network)
    return any(c in text for c in "/\\") or Path(text).exists()


def read_adapted_model(path) -> tuple[bytes, dict]:
    """The ONNX network of a MODEL folder and its record, the sha256 checked (:func:`check_adapted_model`).

    Parameters
    ----------
    path : str or os.PathLike
        The MODEL folder (or its ``fault_unet.onnx``).

    Returns
    -------
    (bytes, dict)
        The serialised ONNX model (input ``sections`` (n, 1, H, W) float32, output ``probability``) and the record.

    Raises
    ------
    DataNotFoundError, InputError
        As :func:`check_adapted_model`.
    """
    record = check_adapted_model(path)
    return (_folder(path) / MODEL_NETWORK).read_bytes(), record


def _folder(path) -> Path:
    p = Path(path)
    if p.is_file() and p.name == MODEL_NETWORK:
        p = p.parent
    if not p.exists():
        raise DataNotFoundError(f"no adapted model at {p}; pass the MODEL folder 'seismo3d adapt -o MODEL' wrote")
    if not (p.is_dir() and (p / MODEL_NETWORK).is_file() and (p / MODEL_RECORD).is_file()):
        raise InputError(f"{p} is not a model written by 'seismo3d adapt' (a folder holding {MODEL_NETWORK} and "
                         f"{MODEL_RECORD}); pass the MODEL folder of 'seismo3d adapt -o MODEL'")
    return p


def _record(folder: Path) -> dict:
    try:
        record = json.loads((folder / MODEL_RECORD).read_text())
    except (OSError, ValueError) as exc:
        raise InputError(f"{folder / MODEL_RECORD} is not a readable record ({exc}); adapt again") from None
    if not isinstance(record, dict) or "network_sha256" not in (record.get("results") or {}):
        raise InputError(f"{folder / MODEL_RECORD} is not the record of 'seismo3d adapt'; adapt again")
    return record
