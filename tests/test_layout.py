"""The package's layout stays navigable: no module imports another's private name, no import cycle between modules,
the engine imports no application, and no library package imports the renderers, the jobs or the command line.

Modules are cut by concept; their sizes are not capped (a size is a hint to split by concept, never a limit to pack
code against)."""

from __future__ import annotations

import ast
import functools
import pathlib

import pytest

import seismo3d

ROOT = pathlib.Path(seismo3d.__file__).parent


def _name(path: pathlib.Path) -> str:
    return ".".join(("seismo3d",) + path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")


MODULES = {_name(p): p for p in ROOT.rglob("*.py")}


@functools.cache  # each module parsed once for the tests of this file
def _tree(name: str) -> ast.Module:
    """A module's syntax tree without its ``if TYPE_CHECKING:`` blocks' bodies."""
    tree = ast.parse(MODULES[name].read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", "") == "TYPE_CHECKING":
            node.body = []
    return tree


@functools.cache
def _imports(name: str, *, top_level: bool = False) -> tuple[tuple[str, str], ...]:
    """(module, imported name) of every import of a module, outside ``if TYPE_CHECKING:`` blocks; with
    ``top_level``, only the imports run when the module is imported (not those inside functions)."""
    path = MODULES[name]
    tree = _tree(name)
    here = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    nodes = list(_module_level(tree)) if top_level else list(ast.walk(tree))
    out = []
    for node in nodes:
        if isinstance(node, ast.ImportFrom):
            base = here[:len(here) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else [])) if node.level else node.module or ""
            out += [(module, alias.name) for alias in node.names]
        elif isinstance(node, ast.Import):
            out += [(alias.name, "") for alias in node.names]
    return tuple(out)


def _module_level(tree: ast.AST):
    """The statements run at import: the module's body and the bodies of its top-level if / try blocks."""
    stack = list(tree.body)
    while stack:
        node = stack.pop()
        yield node
        if isinstance(node, (ast.If, ast.Try)):
            stack += node.body + node.orelse + getattr(node, "finalbody", [])
            stack += [s for h in getattr(node, "handlers", []) for s in h.body]


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


def test_no_import_cycle_between_modules():
    edges = {name: {t for m, i in _imports(name, top_level=True) if (t := _target(m, i)) and t != name}
             for name in MODULES}
    # a package's __init__ importing its own modules is how a package shows its face, not a cycle
    for name in edges:
        edges[name] = {t for t in edges[name] if not t.startswith(name + ".")}
    state: dict[str, int] = {}
    cycles = []

    def visit(node: str, path: list[str]) -> None:
        state[node] = 1
        for nxt in sorted(edges[node]):
            if state.get(nxt) == 1:
                cycles.append(path[path.index(nxt):] + [nxt] if nxt in path else [node, nxt])
            elif nxt not in state:
                visit(nxt, path + [nxt])
        state[node] = 2

    for name in sorted(MODULES):
        if name not in state:
            visit(name, [name])
    assert cycles == []


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
