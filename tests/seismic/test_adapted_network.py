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
from seismo3d.seismic.adapted_network import model_sensitivity
from seismo3d.seismic.faults import trace_faults
from seismo3d.seismic.faults.result import fault_labels


def _model(folder, **results):
    network = resources.files("seismo3d.seismic.faults.likelihood").joinpath("fault_unet.onnx").read_bytes()
    return write_model(folder, network, RunRecord("adapt", {}), {}, {"kept": "adapted", **results})


def test_the_recorded_sensitivity_is_read_and_a_bad_one_refused(tmp_path):
    assert model_sensitivity(_model(tmp_path / "a", sensitivity=0.35)) == 0.35
    assert model_sensitivity(_model(tmp_path / "b")) is None  # a record without one: the tracing's default
    with pytest.raises(InputError, match="outside"):
        model_sensitivity(_model(tmp_path / "c", sensitivity=1.5))


def test_tracing_with_a_model_uses_its_sensitivity_unless_given_another(tmp_path):
    section = synthetic_fault_section((160, 128), seed=4).section
    model = _model(tmp_path / "model", sensitivity=0.9)

    def traced(**kw):
        return fault_labels(trace_faults(section, progress=False, **kw).faults, section.shape) > 0

    high, default = traced(sensitivity=0.9), traced()
    assert high.sum() > default.sum() > 0  # measured: 750 fault samples at sensitivity 0.9, 585 at 0.5
    np.testing.assert_array_equal(traced(model=model), high)  # the shipped network's bits at the recorded 0.9
    np.testing.assert_array_equal(traced(model=model, sensitivity=0.5), default)
