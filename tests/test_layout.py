"""The package's layout stays navigable, read from its source with ``ast`` (each module parsed once for the file's
tests): no module imports another's private name, no import cycle between modules, the engine imports no
application, and no library package imports the renderers, the jobs or the command line.

The import graph counts every ``from .x import``, ``from seismo3d.x import`` and ``import seismo3d.x`` statement, at
the top of a module and inside its functions alike (an import inside a function hides a cycle from the interpreter
until the function runs; it is still a cycle of the design), ``if TYPE_CHECKING:`` blocks included (a lazy package's, whose attributes import them). An edge
``A -> B`` means that importing ``A`` runs ``B``:

- ``from P import n`` where ``P.n`` is a module: ``A -> P.n`` (the name is the submodule);
- ``from P import n`` where ``n`` is a name defined in ``P``: ``A -> P`` (``P``'s module, or its ``__init__`` when
  ``P`` is a package);
- ``from P.M import n`` or ``import P.M``: ``A -> P.M``, and ``A -> P`` for each package ``P`` above the target
  that is not a package of ``A`` itself: importing a submodule runs its packages' ``__init__`` first. A package
  containing ``A`` has already started to run when ``A`` is imported, so it is no edge: a package ``__init__``
  that re-exports names from its own submodules is not a cycle.

Modules are cut by concept; their sizes are not capped (a size is a hint to split by concept, never a limit to pack
code against)."""

from __future__ import annotations

import ast
import functools
import pathlib

import seismo3d

ROOT = pathlib.Path(seismo3d.__file__).parent


def _name(path: pathlib.Path) -> str:
    return ".".join(("seismo3d",) + path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")


MODULES = {_name(p): p for p in ROOT.rglob("*.py")}


@functools.cache  # each module parsed once for the tests of this file
def _tree(name: str) -> ast.Module:
    return ast.parse(MODULES[name].read_text(encoding="utf-8"), filename=str(MODULES[name]))


def _is_type_checking(node: ast.AST) -> bool:
    return isinstance(node, ast.If) and getattr(node.test, "id", "") == "TYPE_CHECKING"


@functools.cache
def _imports(name: str, *, type_checking: bool = False) -> tuple[tuple[str, str], ...]:
    """(module, imported name) of every import of a module, at its top and inside its functions, outside
    ``if TYPE_CHECKING:`` blocks unless ``type_checking``."""
    return tuple((module, imported) for module, imported, hidden in _every_import(name) if type_checking or not hidden)


@functools.cache
def _every_import(name: str) -> tuple[tuple[str, str, bool], ...]:
    """(module, imported name, within an ``if TYPE_CHECKING:`` block) of every import of a module: one walk of its
    tree."""
    path = MODULES[name]
    here = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    out = []
    stack = [(node, False) for node in _tree(name).body]
    while stack:
        node, hidden = stack.pop()
        if isinstance(node, ast.ImportFrom):
            base = here[:len(here) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else [])) if node.level else node.module or ""
            out += [(module, alias.name, hidden) for alias in node.names]
        elif isinstance(node, ast.Import):
            out += [(alias.name, "", hidden) for alias in node.names]
        elif _is_type_checking(node):
            stack += [(child, True) for child in node.body] + [(child, hidden) for child in node.orelse]
        else:
            stack += [(child, hidden) for child in ast.iter_child_nodes(node)]
    return tuple(out)


def _target(module: str, imported: str) -> str | None:
    """The seismo3d module an import loads: ``from a.b import c`` loads ``a.b.c`` when that is a module."""
    if not module.startswith("seismo3d"):
        return None
    full = f"{module}.{imported}" if imported else module
    return full if full in MODULES else module if module in MODULES else None


# the file's first test: it pays the parse of the package's modules (about 3 s), which the file's tests share
def test_no_module_imports_another_modules_private_name():
    private = [(name, module, imported) for name in MODULES for module, imported in _imports(name)
               if module.startswith("seismo3d") and imported.startswith("_") and not imported.startswith("__")
               and f"{module}.{imported}" not in MODULES]  # a private module (seismic._kernels) is imported whole
    assert private == []


def _packages_of(name: str) -> list[str]:
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(1, len(parts))]


@functools.cache  # made once for the tests of this file; not to be modified
def import_graph() -> dict[str, set[str]]:
    """Module name -> the package modules importing it runs (edges as in the module docstring)."""
    graph = {}
    for name in MODULES:
        mine = set(_packages_of(name)) | {name}
        # the imports under TYPE_CHECKING too: a lazy package's (lazy_loader) are those its attributes run
        targets = {_target(m, i) or m for m, i in _imports(name, type_checking=True) if m.startswith("seismo3d")}
        graph[name] = {p for t in targets for p in (*_packages_of(t), t) if p not in mine and p in MODULES}
    return graph


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


ENGINE = ("seismo3d.geometry", "seismo3d.registration", "seismo3d.features")
APPLICATIONS = ("seismo3d.seismic", "seismo3d.mapping", "seismo3d.terrain")
FRONT = ("seismo3d.viz", "seismo3d.jobs", "seismo3d.cli")


def _imports_under(prefixes: tuple, forbidden: tuple) -> list:
    return sorted((name, m) for name in MODULES if name.startswith(prefixes)
                  for m, i in _imports(name) if (t := _target(m, i)) and t.startswith(forbidden))


def test_the_engine_imports_no_application_and_libraries_no_front_end():
    assert _imports_under(ENGINE, APPLICATIONS + FRONT) == []
    assert _imports_under(APPLICATIONS, FRONT) == []


def test_the_fault_package_shows_what_users_call():
    import seismo3d.seismic.faults as faults

    assert {"trace_faults", "FaultTracingOptions", "FaultInterpretation", "Fault"} <= set(faults.__all__)
    assert all(hasattr(faults, name) for name in faults.__all__)
