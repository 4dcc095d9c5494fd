"""The seismo3d package imports cleanly: no import cycle between its modules, and every module imports on its own.

The module import graph is read from the source with ``ast``: every ``from .x import``, ``from seismo3d.x import``
and ``import seismo3d.x`` statement, at the top of a module and inside its functions alike (an import inside a
function hides a cycle from the interpreter until the function runs; it is still a cycle of the design).

An edge ``A -> B`` means that importing ``A`` runs ``B``:

- ``from P import n`` where ``P.n`` is a module: ``A -> P.n`` (the name is the submodule);
- ``from P import n`` where ``n`` is a name defined in ``P``: ``A -> P`` (``P``'s module, or its ``__init__`` when
  ``P`` is a package);
- ``from P.M import n`` or ``import P.M``: ``A -> P.M``, and ``A -> P`` for each package ``P`` above the target
  that is not a package of ``A`` itself: importing a submodule runs its packages' ``__init__`` first. A package
  containing ``A`` has already started to run when ``A`` is imported, so it is no edge: a package ``__init__``
  that re-exports names from its own submodules is not a cycle, unless one of those submodules imports a name
  from the ``__init__`` back (``from . import name`` of a name defined there), which is an edge ``A -> P``.
"""

from __future__ import annotations

import ast
import functools
import importlib
import importlib.util
import pathlib
import pkgutil

import pytest

import seismo3d

ROOT = "seismo3d"


def _modules() -> dict[str, tuple[pathlib.Path, bool]]:
    """Every module of the package: name -> (source file, is a package)."""
    out = {ROOT: (pathlib.Path(seismo3d.__file__), True)}
    for info in pkgutil.walk_packages(seismo3d.__path__, ROOT + "."):
        spec = importlib.util.find_spec(info.name)
        if spec is None or spec.origin is None or not spec.origin.endswith(".py"):
            continue
        out[info.name] = (pathlib.Path(spec.origin), info.ispkg)
    return out


MODULES = _modules()


def _packages_of(name: str) -> list[str]:
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(1, len(parts))]


def _targets(name: str, path: pathlib.Path, is_package: bool) -> set[str]:
    """The modules of the package that importing ``name`` runs (see the module docstring)."""
    here = name if is_package else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), filename=str(path))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names if alias.name.split(".")[0] == ROOT)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here.split(".")
                base = base[:len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            elif node.module and node.module.split(".")[0] == ROOT:
                target = node.module
            else:
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                found.add(sub if sub in MODULES else target)
    mine = set(_packages_of(name)) | {name}
    edges = set()
    for target in found:
        edges.update(p for p in (*_packages_of(target), target) if p not in mine and p in MODULES)
    return edges


@functools.cache  # parsed once for the tests of this file (every module of the package)
def import_graph() -> dict[str, set[str]]:
    """Module name -> the package modules it imports (edges as in the module docstring); not to be modified."""
    return {name: _targets(name, path, is_package) for name, (path, is_package) in MODULES.items()}


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of ``graph`` as a list of modules (first repeated at the end), or None."""
    state: dict[str, int] = {}  # 1 on the path, 2 done
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                cycle = visit(nxt)
                if cycle:
                    return cycle
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


@pytest.mark.slow
def test_the_graph_sees_imports_inside_functions_and_package_inits():
    graph = import_graph()
    # a re-export from the sub-package's modules, and an import of a sibling sub-package runs its __init__
    assert "seismo3d.seismic.faults.pipeline" in graph["seismo3d.seismic.faults"]
    assert "seismo3d.seismic.io" in graph["seismo3d.seismic.blocks.stores"]
    assert "seismo3d.seismic.blocks.stores" not in graph["seismo3d.seismic.blocks.stores"]
    # `from .. import _kernels` names a module: no edge to the package __init__ that holds it
    assert "seismo3d.seismic" not in graph["seismo3d.seismic.attributes"]
    assert "seismo3d.seismic._kernels" in graph["seismo3d.seismic.attributes"]
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": set()}) is None


def test_no_import_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


# modules that need an optional extra, and the extra's import name
OPTIONAL = {"seismo3d.training.fault_unet": "torch", "seismo3d.training.adapt": "torch"}  # the `train` extra


# the training modules import torch (2.4 s, 12.7 s at load 12): in the slow lane, the fast lane's target being 60 s
@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in OPTIONAL else n
                                  for n in sorted(MODULES)])
def test_every_module_imports(name):
    if name in OPTIONAL:
        pytest.importorskip(OPTIONAL[name])
    importlib.import_module(name)
