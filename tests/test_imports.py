"""Every module of the seismo3d package imports (the package's import graph, its cycles and layers:
``tests/test_layout.py``)."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import seismo3d

MODULES = ["seismo3d"] + [info.name for info in pkgutil.walk_packages(seismo3d.__path__, "seismo3d.")]

# modules that need an optional extra, and the extra's import name
OPTIONAL = {"seismo3d.training.fault_unet": "torch", "seismo3d.training.adapt": "torch"}  # the `train` extra


# the training modules import torch (2.4 s, 12.7 s at load 12): in the slow lane, the fast lane's target being 60 s
@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in OPTIONAL else n
                                  for n in sorted(MODULES)])
def test_every_module_imports(name):
    if name in OPTIONAL:
        pytest.importorskip(OPTIONAL[name])
    importlib.import_module(name)
