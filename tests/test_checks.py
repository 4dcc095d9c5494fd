"""The checks of claims too long for the suite (benchmarks/checks.py): each names a benchmark that exists with the
section it runs and a ``--check`` flag, and CONTRIBUTING.md lists every one of them (issue 58: the list complete,
all run by one command)."""

import importlib.util
import re
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def _checks():
    spec = importlib.util.spec_from_file_location("seismo3d_checks", REPO / "benchmarks" / "checks.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks its module up
    try:
        spec.loader.exec_module(module)
    finally:
        del sys.modules[spec.name]
    return module.CHECKS


def test_every_check_runs_an_existing_benchmark_section_with_its_check():
    for check in _checks():
        argv = list(check.argv)
        if argv[:2] == ["-m", "pytest"]:  # the notebooks, through nbmake
            assert (REPO / argv[2]).is_dir() and list((REPO / argv[2]).glob("*.ipynb")), check
            continue
        script = REPO / argv[0]
        assert script.is_file(), check
        assert "--check" in argv, f"{check.name}: without --check a missed target exits 0"
        source = script.read_text()
        assert '"--check"' in source, f"{script.name} has no --check flag"
        if "--only" in argv:
            section = argv[argv.index("--only") + 1]
            assert re.search(rf'"{section}"\s*:', source), f"{script.name} has no section {section!r}"


def test_contributing_lists_every_check():
    text = (REPO / "CONTRIBUTING.md").read_text()
    assert "python benchmarks/checks.py" in text
    for check in _checks():
        assert f"`{check.name}`" in text, f"CONTRIBUTING.md does not list the check {check.name}"
        command = " ".join(check.argv[:4] if check.argv[0] != "-m" else check.argv[:3])
        assert f"python {command}" in text, f"CONTRIBUTING.md does not give the command of {check.name}"
