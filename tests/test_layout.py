"""The package's layout stays navigable (issue 53): no module imports another's private name, no module over 600
lines, the fault package's public face and its modules' sizes, and the fault package's size and depth as reached
(its targets: 22 modules and import chains of at most 6: CONTRIBUTING.md)."""

from __future__ import annotations

import ast
import functools
import pathlib

import seismo3d

ROOT = pathlib.Path(seismo3d.__file__).parent
FAULTS = ROOT / "seismic" / "faults"


def _name(path: pathlib.Path) -> str:
    return ".".join(("seismo3d",) + path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")


MODULES = {_name(p): p for p in ROOT.rglob("*.py")}


def _imports(name: str) -> list[tuple[str, str]]:
    """(module, imported name) of every ``from ... import`` of a module, outside ``if TYPE_CHECKING:`` blocks."""
    path = MODULES[name]
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", "") == "TYPE_CHECKING":
            node.body = []
    here = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = here[:len(here) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else [])) if node.level else node.module or ""
            out += [(module, alias.name) for alias in node.names]
    return out


def test_no_module_imports_another_modules_private_name():
    private = [(name, module, imported) for name in MODULES for module, imported in _imports(name)
               if module.startswith("seismo3d") and imported.startswith("_") and not imported.startswith("__")
               and f"{module}.{imported}" not in MODULES]  # a private module (seismic._kernels) is imported whole
    assert private == []


def test_no_module_over_600_lines_and_none_of_the_fault_package_over_500():
    lines = {name: len(path.read_text().splitlines()) for name, path in MODULES.items()}
    assert {n: k for n, k in lines.items() if k > 600} == {}
    assert {n: k for n, k in lines.items() if k > 500 and n.startswith("seismo3d.seismic.faults")} == {}


def test_the_fault_package_shows_what_users_call():
    import seismo3d.seismic.faults as faults

    assert len(faults.__all__) <= 20
    assert {"trace_faults", "FaultTracingOptions", "FaultInterpretation", "Fault"} <= set(faults.__all__)
    assert all(hasattr(faults, name) for name in faults.__all__)


def test_the_fault_package_is_no_larger_or_deeper_than_reached():
    inside = {n for n, p in MODULES.items() if FAULTS == p.parent or FAULTS in p.parents}
    edges = {n: {m if m in MODULES else f"{m}.{i}" for m, i in _imports(n)} & inside for n in inside}

    @functools.lru_cache(maxsize=None)
    def chain(name: str, seen: frozenset = frozenset()) -> int:
        return 1 + max([chain(m, seen | {name}) for m in edges[name] if m not in seen and m != name] or [0])

    assert len(inside) <= 23  # 33 before issue 53, 31 on main 628e870, 28 with the block runs regrouped, 29 with the
    # 2D throw profile (throw_profile, issue 54), 27 with one block executor (faults/blocks/ dissolved into likelihood/,
    # surfaces/, checks and pipeline), 25 with the executor's read-compute-write layer (seismic/blocks/apply.py:
    # surfaces/block_steps dissolved, the thresholds' statistics in seismic/blocks/statistics), 23 with the preflight
    # out of faults/ (checks dissolved: the sampled blocks and the size check in seismic/blocks/preflight, the dead
    # samples and the amplitude checks in seismic/amplitudes, the fault refusals on a sample in steps); the target is 22
    assert chain("seismo3d.seismic.faults") <= 6  # 12 before issue 53, 9 on main 628e870; 6 is the target
