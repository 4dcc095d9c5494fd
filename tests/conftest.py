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
