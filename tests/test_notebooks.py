"""The notebooks (notebooks/): each saved notebook is its source's cells, its outputs hold no warning, error or
absolute path, and a fresh run prints what it shows. The suite runs the cheapest notebook again; ``python
benchmarks/checks.py notebooks`` (``python notebooks/build.py --check``) runs all six."""

import importlib.util
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SOURCES = sorted((REPO / "notebooks" / "src").glob("*.py"))
CHEAP = ["06_terrain"]  # under ~20 s on 2 cores; the others take a minute or more: the check runs them


@pytest.fixture(scope="module")
def build():
    pytest.importorskip("nbclient", reason='the test tools: pip install -e ".[test]"')
    spec = importlib.util.spec_from_file_location("notebooks_build", REPO / "notebooks" / "build.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
@pytest.mark.parametrize("source", SOURCES, ids=lambda p: p.stem)
def test_saved_notebook_is_its_source_with_clean_outputs(build, source):
    import nbformat

    saved = nbformat.read(REPO / "notebooks" / f"{source.stem}.ipynb", as_version=4)
    assert build.stale_cells(saved, source) == [], f"python notebooks/build.py {source.stem}"
    assert build.problems(saved) == []
    assert any(text.strip() for text in build.printed(saved)), "a notebook prints what it found"


def test_problems_finds_warnings_errors_and_machine_paths(build):
    import nbformat

    cell = nbformat.v4.new_code_cell("x")
    cell.outputs = [nbformat.v4.new_output("stream", name="stdout", text="read /home/me/data/f3.sgy\n"),
                    nbformat.v4.new_output("stream", name="stderr", text="UserWarning: clipped\n"),
                    nbformat.v4.new_output("error", ename="ValueError", evalue="bad", traceback=[])]
    found = build.problems(nbformat.v4.new_notebook(cells=[cell]))
    assert len(found) == 3 and "absolute path" in found[2] and "standard error" in found[0]
    cell.outputs = [nbformat.v4.new_output("stream", name="stdout", text="0.5 m/s; DEM 367 x 359\n")]
    assert build.problems(nbformat.v4.new_notebook(cells=[cell])) == []


@pytest.mark.slow  # a Jupyter kernel and the notebook's real data: about 20-40 s
@pytest.mark.parametrize("name", CHEAP)
def test_cheap_notebook_prints_what_it_shows_when_run_again(build, name, data_dir):
    assert build.check(REPO / "notebooks" / "src" / f"{name}.py") == []
