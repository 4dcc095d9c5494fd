"""Write the notebooks from their sources and run them, saving the outputs (pictures and numbers) in them.

Each ``notebooks/src/NN_name.py`` holds the cells of ``notebooks/NN_name.ipynb``: ``# %%`` starts a code cell,
``# %% [markdown]`` a markdown cell whose lines start with ``# ``. Edit the source, then run

    SEISMO3D_DATA_DIR=/path/to/data python notebooks/build.py [NAME ...]      (default: every notebook)

(nbformat and nbclient come with the ``test`` extra). CI runs the saved notebooks with nbmake (``python -m pytest``).
"""

from __future__ import annotations

import argparse
import pathlib
import time

import nbformat
from nbclient import NotebookClient

HERE = pathlib.Path(__file__).resolve().parent


def cells_of(source: str) -> list:
    """Notebook cells of a ``# %%`` source."""
    cells, kind, lines = [], None, []

    def close():
        text = "\n".join(lines).strip("\n")
        if kind == "markdown":
            text = "\n".join(line[2:] if line.startswith("# ") else line.lstrip("#") for line in text.splitlines())
            cells.append(nbformat.v4.new_markdown_cell(text))
        elif kind == "code" and text:
            cells.append(nbformat.v4.new_code_cell(text))

    for line in source.splitlines():
        if line.startswith("# %%"):
            close()
            kind, lines = ("markdown" if "[markdown]" in line else "code"), []
        else:
            lines.append(line)
    close()
    return cells


def build(source: pathlib.Path, *, execute: bool = True) -> pathlib.Path:
    """Write ``notebooks/<stem>.ipynb`` from ``source`` and run it in its folder (outputs saved)."""
    meta = {"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"},
            "language_info": {"name": "python"}}
    notebook = nbformat.v4.new_notebook(cells=cells_of(source.read_text()), metadata=meta)
    target = HERE / f"{source.stem}.ipynb"
    if execute:
        NotebookClient(notebook, timeout=900, kernel_name="python3",
                       resources={"metadata": {"path": str(HERE)}}).execute()
    nbformat.write(notebook, target)
    return target


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help="notebook names (e.g. 01_faults); default every source")
    parser.add_argument("--no-execute", action="store_true", help="write the notebooks without running them")
    args = parser.parse_args()
    sources = sorted((HERE / "src").glob("*.py"))
    if args.names:
        sources = [s for s in sources if s.stem in set(args.names)]
    for source in sources:
        start = time.perf_counter()
        target = build(source, execute=not args.no_execute)
        print(f"{target.name}: {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
