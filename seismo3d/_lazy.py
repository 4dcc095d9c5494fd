"""A package's public names imported on first use (PEP 562), so that importing one module of a package does not
import all of its siblings.

A package ``__init__`` keeps its re-exports as ordinary ``from .module import name`` statements, inside an
``if TYPE_CHECKING:`` block (read by type checkers, editors and the documentation, never run), and ends with::

    __getattr__, __dir__ = lazy_exports(__name__, __file__)

Then ``from seismo3d.seismic import trace_faults`` and ``seismo3d.seismic.trace_faults`` import
``seismo3d.seismic.faults`` when first asked for, and ``import seismo3d.seismic.io.segy`` no longer runs the fault,
horizon and attribute modules (scipy, numba). The ``TYPE_CHECKING`` block is the one list: :func:`lazy_exports`
reads it from the package's source (as ``lazy_loader.attach_stub`` reads a ``.pyi`` stub, scikit-image's lazy
packages) and hands it to ``lazy_loader.attach``, which imports each name on first use. The package's sub-packages
and modules are also attributes on first use (``seismo3d.seismic.faults``).

References
----------
PEP 562, "Module __getattr__ and __dir__". SPEC 1, "Lazy Loading of Submodules and Functions" (Scientific Python).
"""

from __future__ import annotations

import ast
import pkgutil
import sys
from pathlib import Path

__all__ = ["lazy_exports", "reexports"]


def _is_type_checking(test: ast.expr) -> bool:
    """Whether an ``if`` tests ``TYPE_CHECKING`` (or ``typing.TYPE_CHECKING``)."""
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or \
        (isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def reexports(source: str) -> dict[str, str]:
    """The names a package ``__init__`` re-exports in its ``if TYPE_CHECKING:`` block, and the module of each.

    Parameters
    ----------
    source : str
        The text of the ``__init__.py``.

    Returns
    -------
    dict
        Public name -> relative module (``'.faults.throw'``), in the order of the source.

    Raises
    ------
    ValueError
        The block imports with ``as`` or ``*``, or not relatively (a re-export is a name of the package's own
        modules, under its own name).
    """
    homes = {}
    for node in ast.parse(source).body:
        if not (isinstance(node, ast.If) and _is_type_checking(node.test)):
            continue
        for statement in node.body:
            if not (isinstance(statement, ast.ImportFrom) and statement.level == 1):
                raise ValueError(f"line {statement.lineno}: a lazy re-export is 'from .module import name'")
            for alias in statement.names:
                if alias.asname is not None or alias.name == "*":
                    raise ValueError(f"line {statement.lineno}: a lazy re-export keeps its name (no 'as', no '*')")
                homes[alias.name] = "." + (statement.module or "")
    return homes


def lazy_exports(package: str, init_file: str):
    """The module ``__getattr__`` and ``__dir__`` of a package whose re-exports are imported on first use.

    Parameters
    ----------
    package : str
        The package's name (its ``__name__``).
    init_file : str
        Its ``__init__.py`` (its ``__file__``), whose ``if TYPE_CHECKING:`` block lists the re-exports
        (:func:`reexports`).

    Returns
    -------
    getattr : callable
        ``getattr(name)``: the re-exported object (imported once, then kept in the package's namespace), or the
        package's sub-module ``name``; AttributeError for anything else (``lazy_loader.attach``'s).
    dir : callable
        ``dir()``: the package's namespace and its re-exports.
    """
    import lazy_loader

    homes = reexports(Path(init_file).read_text(encoding="utf-8"))
    modules = {}
    for name, module in homes.items():
        modules.setdefault(module[1:], []).append(name)
    submodules = {m.name for m in pkgutil.iter_modules([str(Path(init_file).parent)])}
    getattr_, _, _ = lazy_loader.attach(package, submodules=submodules, submod_attrs=modules)

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(homes))

    return getattr_, __dir__
