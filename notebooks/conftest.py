"""The notebooks run as tests through nbmake: ``python -m pytest notebooks`` collects ``notebooks/*.ipynb`` (one of
the checks of ``benchmarks/checks.py``; the suite, ``python -m pytest``, collects ``tests/`` only: together the six
take about 3 minutes of its 10). Each takes a minute or two, so they are marked ``slow``; like the real-data tests they
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
