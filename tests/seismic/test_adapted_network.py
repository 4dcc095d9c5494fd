"""A MODEL folder of ``seismo3d adapt`` read back (seismo3d.seismic.adapted_network): the sensitivity its record holds
is the one ``trace_faults(model=...)`` and ``seismo3d faults --model`` trace with, unless another is given."""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

from seismo3d.data.synthetic_sections import synthetic_fault_section
from seismo3d.errors import InputError
from seismo3d.jobs.adapt import write_model
from seismo3d.jobs.runinfo import RunRecord
from seismo3d.seismic.adapted_network import model_tracing
from seismo3d.seismic.faults import FaultTracingOptions, trace_faults
from seismo3d.seismic.faults.result import fault_labels


def _model(folder, **results):
    network = resources.files("seismo3d.seismic.faults.likelihood").joinpath("fault_unet.onnx").read_bytes()
    return write_model(folder, network, RunRecord("adapt", {}), {}, {"kept": "adapted", **results})


def test_the_recorded_tracing_is_read_and_a_bad_one_refused(tmp_path):
    tracing = model_tracing(_model(tmp_path / "a", sensitivity=0.35, unbroken_veto=False))
    assert (tracing.sensitivity, tracing.unbroken_veto) == (0.35, False)
    assert tracing.record["results"]["kept"] == "adapted"
    tracing = model_tracing(_model(tmp_path / "b"))  # a record without them: the tracing's own
    assert (tracing.sensitivity, tracing.unbroken_veto) == (None, None)
    with pytest.raises(InputError, match="records a sensitivity of 1.5, outside"):
        model_tracing(_model(tmp_path / "c", sensitivity=1.5))
    with pytest.raises(InputError, match="records an unbroken_veto of 'no', not true or false"):
        model_tracing(_model(tmp_path / "d", unbroken_veto="no"))


def test_model_tracing_reads_the_record_and_hashes_the_network_once(tmp_path, monkeypatch):
    import hashlib

    import seismo3d.seismic.adapted_network as adapted

    model = _model(tmp_path / "model", sensitivity=0.35, unbroken_veto=False)
    calls, sha256 = [], hashlib.sha256
    monkeypatch.setattr(adapted.hashlib, "sha256", lambda data: calls.append(len(data)) or sha256(data))
    options = FaultTracingOptions().with_model(model)
    assert len(calls) == 1  # one hash of the network (the loading of the network hashes it again, when it runs)
    assert (options.sensitivity, options.evidence.unbroken_veto, options.learned.adapted) == (0.35, False, str(model))
    assert FaultTracingOptions().with_model(model, sensitivity=0.6).sensitivity == 0.6  # the one asked for wins


@pytest.mark.slow
def test_tracing_with_a_model_uses_its_sensitivity_unless_given_another(tmp_path):
    section = synthetic_fault_section((160, 128), seed=4).section
    model = _model(tmp_path / "model", sensitivity=0.9)

    def traced(**kw):
        return fault_labels(trace_faults(section, progress=False, **kw).faults, section.shape) > 0

    high, default = traced(sensitivity=0.9), traced()
    assert high.sum() > default.sum() > 0  # measured: 750 fault samples at sensitivity 0.9, 585 at 0.5
    np.testing.assert_array_equal(traced(model=model), high)  # the shipped network's bits at the recorded 0.9
    np.testing.assert_array_equal(traced(model=model, sensitivity=0.5), default)
