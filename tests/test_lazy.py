"""Package re-exports imported on first use (seismo3d._lazy): a package's public names stay importable from it while
importing the package, or one of its modules, runs none of the others."""

from __future__ import annotations

import importlib
import sys

import pytest

from seismo3d._lazy import reexports

INIT = '''\
"""A package with lazy re-exports."""
from typing import TYPE_CHECKING

from seismo3d._lazy import lazy_exports

if TYPE_CHECKING:
    from .heavy import Heavy, heavy_function
    from .light import LIGHT
    from .deep.inner import inner

__all__ = ["Heavy", "heavy_function", "LIGHT", "inner"]

__getattr__, __dir__ = lazy_exports(__name__, __file__)
'''


@pytest.fixture
def package(tmp_path, monkeypatch):
    """A package ``lazypkg`` with modules ``heavy``, ``light`` and ``deep.inner``, importable for the test."""
    root = tmp_path / "lazypkg"
    (root / "deep").mkdir(parents=True)
    (root / "__init__.py").write_text(INIT)
    (root / "heavy.py").write_text("class Heavy:\n    pass\n\n\ndef heavy_function():\n    return 42\n")
    (root / "light.py").write_text("LIGHT = 'light'\n")
    (root / "deep" / "__init__.py").write_text("")
    (root / "deep" / "inner.py").write_text("def inner():\n    return 'inner'\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    yield "lazypkg"
    for name in [n for n in sys.modules if n == "lazypkg" or n.startswith("lazypkg.")]:
        del sys.modules[name]


def test_reexports_reads_the_type_checking_block_in_order():
    assert reexports(INIT) == {"Heavy": ".heavy", "heavy_function": ".heavy", "LIGHT": ".light",
                               "inner": ".deep.inner"}


@pytest.mark.parametrize("statement", ["from .heavy import Heavy as H", "from .heavy import *",
                                       "from seismo3d.errors import InputError", "import numpy"])
def test_a_reexport_that_is_not_a_relative_name_is_refused(statement):
    source = f"from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    {statement}\n"
    with pytest.raises(ValueError, match="line 3"):
        reexports(source)


def test_a_name_is_imported_on_first_use_only(package):
    lazypkg = importlib.import_module(package)
    assert "lazypkg.heavy" not in sys.modules and "lazypkg.light" not in sys.modules
    from lazypkg import LIGHT

    assert LIGHT == "light"
    assert "lazypkg.light" in sys.modules and "lazypkg.heavy" not in sys.modules
    assert lazypkg.heavy_function() == 42
    assert lazypkg.Heavy is importlib.import_module("lazypkg.heavy").Heavy  # the module's own object
    assert lazypkg.inner() == "inner"


def test_star_import_dir_and_sub_modules(package):
    namespace = {}
    exec(f"from {package} import *", namespace)  # noqa: S102 - the star import uses __all__
    assert {"Heavy", "heavy_function", "LIGHT", "inner"} <= set(namespace)
    lazypkg = importlib.import_module(package)
    assert {"Heavy", "heavy_function", "LIGHT", "inner", "__all__"} <= set(dir(lazypkg))
    assert lazypkg.deep.__name__ == "lazypkg.deep"  # a sub-package, imported as an attribute
    from lazypkg import light  # a module, as from any package

    assert light.LIGHT == "light"


def test_an_unknown_name_is_an_attribute_error(package):
    lazypkg = importlib.import_module(package)
    with pytest.raises(AttributeError, match="lazypkg attribute missing"):
        lazypkg.missing  # noqa: B018
    assert not hasattr(lazypkg, "missing")
    with pytest.raises(ImportError, match="missing"):
        exec(f"from {package} import missing", {})  # noqa: S102
