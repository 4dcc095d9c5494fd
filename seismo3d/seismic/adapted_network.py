"""A fault network adapted to a survey by ``seismo3d adapt``: the MODEL folder it writes, read back for tracing.

A MODEL folder holds two files:

* ``fault_unet.onnx``: the network, the architecture of :mod:`~seismo3d.seismic.faults.likelihood.network` with the
  weights fine-tuned on an interpreter's faults (or the shipped float network itself when adapting did not help on
  the held-back picks: the record says so), run by ONNX Runtime like the shipped one;
* ``adapt.json``: the record, a ``run.json`` of the ``adapt`` command (:mod:`seismo3d.jobs.runinfo`: the inputs with
  their sha256, the options) whose ``results`` hold the lines and picks, the training steps and loss, the held-back
  validation before and after, the decision (``kept``: ``'adapted'`` or ``'default'``), ``sensitivity`` (the
  tracing's sensitivity MODEL traces with unless one is given: :func:`model_sensitivity`) and ``network_sha256``,
  the sha256 of ``fault_unet.onnx``.

Reading one needs ONNX Runtime only (no training framework); the sha256 of the network is checked against the
record when it is loaded (:func:`seismo3d.seismic.faults.likelihood.learned.load_network`). Writing one is
:mod:`seismo3d.jobs.adapt`'s.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from ..errors import DataNotFoundError, InputError

__all__ = ["MODEL_NETWORK", "MODEL_RECORD", "read_adapted_model", "check_adapted_model", "is_model_path",
           "model_sensitivity"]

MODEL_NETWORK = "fault_unet.onnx"
MODEL_RECORD = "adapt.json"


def check_adapted_model(path) -> dict:
    """The record of a MODEL folder written by ``seismo3d adapt``, checked: both files present, the network's
    sha256 the recorded one.

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
        ``path`` is not a MODEL folder of ``seismo3d adapt``, or its network is not the one its record names.
    """
    folder = _folder(path)
    record = _record(folder)
    digest, recorded = hashlib.sha256((folder / MODEL_NETWORK).read_bytes()).hexdigest(), \
        record["results"]["network_sha256"]
    if digest != recorded:
        raise InputError(f"{folder / MODEL_NETWORK} has sha256 {digest}, not the {recorded} its {MODEL_RECORD} "
                         "records: the model was changed after 'seismo3d adapt' wrote it; adapt again")
    return record


def model_sensitivity(path) -> float | None:
    """The sensitivity a MODEL folder traces with when none is given (``seismo3d faults --model MODEL`` without
    ``--sensitivity``): the record's ``sensitivity`` (``seismo3d adapt`` stores it with the network it keeps), None
    when the record holds none (the tracing's default then).

    Parameters
    ----------
    path : str or os.PathLike
        The MODEL folder (or its ``fault_unet.onnx``).

    Returns
    -------
    float or None
        In [0, 1].

    Raises
    ------
    DataNotFoundError, InputError
        As :func:`check_adapted_model`; a recorded sensitivity outside [0, 1].
    """
    value = check_adapted_model(path)["results"].get("sensitivity")
    if value is None:
        return None
    if not 0.0 <= float(value) <= 1.0:
        raise InputError(f"{_folder(path) / MODEL_RECORD} records a sensitivity of {value!r}, outside [0, 1]; adapt "
                         "again")
    return float(value)


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
