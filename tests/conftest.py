"""Shared fixtures: the real-data directory and small generated point sets."""

import os

import numpy as np
import pytest


@pytest.fixture(scope="session")
def data_dir():
    """The real-data directory (env SEISMO3D_DATA_DIR); tests needing it skip when it is unset."""
    path = os.environ.get("SEISMO3D_DATA_DIR")
    if not path:
        pytest.skip("SEISMO3D_DATA_DIR is not set")
    return path


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.fixture(scope="session")
def penobscot(data_dir):
    """The 18 real Penobscot inlines with people's horizons (seismo3d.data.load_penobscot_sections)."""
    from seismo3d.data import load_penobscot_sections

    return load_penobscot_sections()


@pytest.fixture(scope="session")
def penobscot_faults(penobscot):
    """trace_faults on the Penobscot cube (about 30 s; traced once per test session)."""
    import warnings

    from seismo3d.errors import Seismo3dWarning
    from seismo3d.seismic import trace_faults

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)  # clipped amplitudes and the muted top are reported
        return trace_faults(penobscot.cube, progress=False)
