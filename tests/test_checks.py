"""The checks of claims too long for the suite (benchmarks/checks.py): each names a benchmark that exists with the
section it runs and a ``--check`` flag (or the notebooks' check), and ``checks.py --list`` names them all, the list
CONTRIBUTING.md points to (one list, run by one command)."""

import importlib.util
import re
import subprocess
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
        if argv[0] == "notebooks/build.py":  # the notebooks against a fresh run
            assert argv[1:] == ["--check"] and list((REPO / "notebooks" / "src").glob("*.py")), check
            continue
        script = REPO / argv[0]
        assert script.is_file(), check
        assert "--check" in argv, f"{check.name}: without --check a missed target exits 0"
        source = script.read_text()
        assert '"--check"' in source, f"{script.name} has no --check flag"
        if "--only" in argv:
            section = argv[argv.index("--only") + 1]
            assert re.search(rf'"{section}"\s*:', source), f"{script.name} has no section {section!r}"


def test_contributing_points_to_the_list_that_names_every_check():
    assert "python benchmarks/checks.py --list" in (REPO / "CONTRIBUTING.md").read_text()
    done = subprocess.run([sys.executable, str(REPO / "benchmarks" / "checks.py"), "--list"], capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    for check in _checks():
        assert f"{check.name}: python {' '.join(check.argv)}\n" in done.stdout, check.name


def test_fault_speed_names_the_written_files_apart_from_the_steps_by_blocks(capsys):
    # by blocks the executor's steps "surfaces" and "votes" are rows of the table; the files written in memory under
    # "write outputs" are "write surfaces", "write votes"
    spec = importlib.util.spec_from_file_location("seismo3d_fault_speed", REPO / "benchmarks" / "fault_speed.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    runs = {"in memory": {"steps": {"throw": 9.0, "write outputs": 6.0},
                          "cpu_steps": {"throw": 9.1, "write outputs": 0.0, "surfaces": 2.0, "votes": 1.5}},
            "by blocks (900MB)": {"steps": {"surfaces": 30.0, "votes": 4.0, "write outputs": 7.0}, "cpu_steps": {}}}
    module._print_files(runs, 0.067)
    rows = [line.split("|")[0].rstrip() for line in capsys.readouterr().out.splitlines()]
    assert rows == ["  write surfaces", "  write votes"]
