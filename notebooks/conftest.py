"""The notebooks run as tests through nbmake (``python -m pytest`` collects ``notebooks/*.ipynb``). Each takes a minute
or two, so they are marked ``slow`` and left out of the fast lane (``-m "not slow"``); like the real-data tests they
are skipped when ``SEISMO3D_DATA_DIR`` is unset (without it they would download their data: hundreds of files)."""

import os

import pytest


def pytest_collection_modifyitems(config, items):
    no_data = not os.environ.get("SEISMO3D_DATA_DIR")
    for item in items:
        if str(item.path).endswith(".ipynb"):
            item.add_marker(pytest.mark.slow)
            if no_data:
                item.add_marker(pytest.mark.skip(reason="SEISMO3D_DATA_DIR is not set"))
