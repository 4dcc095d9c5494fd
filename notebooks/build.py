"""Write the notebooks from their sources and run them, saving the outputs (pictures and numbers) in them; or check
the saved notebooks against their sources and a fresh run.

Each ``notebooks/src/NN_name.py`` holds the cells of ``notebooks/NN_name.ipynb``: ``# %%`` starts a code cell,
``# %% [markdown]`` a markdown cell whose lines start with ``# ``. Edit the source, then run

    SEISMO3D_DATA_DIR=/path/to/data python notebooks/build.py [NAME ...]          (default: every notebook)
    SEISMO3D_DATA_DIR=/path/to/data python notebooks/build.py --check [NAME ...]  (what benchmarks/checks.py runs)

``--check`` saves nothing: it exits 1 when a saved notebook's cells differ from its source, or when what a fresh run
prints differs from what the notebook shows. A run whose outputs hold a warning, an error or an absolute path is not
saved (outputs are meant to read the same on every machine; printed timings would not, so the notebooks print none).
nbformat and nbclient come with the ``test`` extra.
"""

from __future__ import annotations

import argparse
import difflib
import pathlib
import re
import sys
import time

import nbformat
from nbclient import NotebookClient

HERE = pathlib.Path(__file__).resolve().parent
# an absolute path of the machine that ran it: a POSIX root folder, a home folder or a Windows drive
_ABSOLUTE_PATH = re.compile(r"(?<![\w.])(/(home|root|Users|tmp|usr|opt|var|work|mnt)/|~/|[A-Za-z]:\\)")


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


def notebook_of(source: pathlib.Path):
    """The notebook of a ``# %%`` source, not run."""
    meta = {"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"},
            "language_info": {"name": "python"}}
    cells = cells_of(source.read_text())
    for n, cell in enumerate(cells):  # ids by position: a notebook written again differs only where its source does
        cell.id = f"cell-{n:02d}"
    return nbformat.v4.new_notebook(cells=cells, metadata=meta)


def execute(notebook) -> None:
    """Run ``notebook`` in place, in this folder (its outputs kept in it; no timing metadata)."""
    NotebookClient(notebook, timeout=900, kernel_name="python3", record_timing=False,
                   resources={"metadata": {"path": str(HERE)}}).execute()


def printed(notebook) -> list:
    """What each code cell printed: its standard output and the text of its result, one string per code cell."""
    texts = []
    for cell in notebook.cells:
        if cell.cell_type != "code":
            continue
        parts = []
        for out in cell.get("outputs", []):
            if out.output_type == "stream" and out.name == "stdout":
                parts.append(out.text)
            elif out.output_type == "execute_result":
                parts.append(out.get("data", {}).get("text/plain", "") + "\n")
        texts.append("".join(parts))
    return texts


def problems(notebook) -> list:
    """What a saved notebook must not show: warnings or other standard error, errors, absolute paths."""
    found = []
    for n, cell in enumerate(c for c in notebook.cells if c.cell_type == "code"):
        for out in cell.get("outputs", []):
            if out.output_type == "stream" and out.name == "stderr":
                found.append(f"code cell {n + 1} writes to standard error: {out.text.strip()[:300]}")
            elif out.output_type == "error":
                found.append(f"code cell {n + 1} raises {out.ename}: {out.evalue}")
        text = "".join(printed(nbformat.v4.new_notebook(cells=[cell])))
        if _ABSOLUTE_PATH.search(text):
            found.append(f"code cell {n + 1} prints an absolute path: {text.strip()[:300]}")
    return found


def stale_cells(notebook, source: pathlib.Path) -> list:
    """The cells of a saved notebook that differ from its source (kind or text), by number."""
    saved = [(c.cell_type, c.source) for c in notebook.cells]
    wanted = [(c.cell_type, c.source) for c in cells_of(source.read_text())]
    if len(saved) != len(wanted):
        return [f"{len(saved)} cells against the source's {len(wanted)}"]
    return [f"cell {n + 1}" for n, (a, b) in enumerate(zip(saved, wanted)) if a != b]


def build(source: pathlib.Path) -> pathlib.Path:
    """Write ``notebooks/<stem>.ipynb`` from ``source`` after running it in its folder (outputs saved).

    Raises
    ------
    SystemExit
        The run's outputs show a warning, an error or an absolute path (nothing is written).
    """
    notebook = notebook_of(source)
    execute(notebook)
    found = problems(notebook)
    if found:
        raise SystemExit(f"{source.name}: not saved, its outputs show\n  " + "\n  ".join(found))
    target = HERE / f"{source.stem}.ipynb"
    nbformat.write(notebook, target)
    return target


def check(source: pathlib.Path) -> list:
    """What is wrong with the saved notebook of ``source``: cells that differ from the source, what its outputs must
    not show, and the printed text that differs from a fresh run's (as a diff); empty when it is right."""
    target = HERE / f"{source.stem}.ipynb"
    if not target.is_file():
        return [f"{target.name} is missing: python notebooks/build.py {source.stem}"]
    saved = nbformat.read(target, as_version=4)
    found = [f"{target.name}: {p}" for p in stale_cells(saved, source) + problems(saved)]
    if found:
        return found + [f"write it again: python notebooks/build.py {source.stem}"]
    fresh = notebook_of(source)
    execute(fresh)
    found = [f"a fresh run of {source.name}: {p}" for p in problems(fresh)]
    for n, (old, new) in enumerate(zip(printed(saved), printed(fresh))):
        if old != new:
            diff = difflib.unified_diff(old.splitlines(), new.splitlines(), "saved", "fresh run", lineterm="")
            found.append(f"{target.name}, code cell {n + 1} prints otherwise now:\n" + "\n".join(diff))
    return found


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help="notebook names (e.g. 01_faults); default every source")
    parser.add_argument("--check", action="store_true", help="save nothing; exit 1 when a saved notebook differs "
                                                             "from its source or from a fresh run")
    args = parser.parse_args()
    sources = sorted((HERE / "src").glob("*.py"))
    unknown = set(args.names) - {s.stem for s in sources}
    if unknown:
        parser.error(f"no source for {', '.join(sorted(unknown))}; the notebooks: "
                     + ", ".join(s.stem for s in sources))
    if args.names:
        sources = [s for s in sources if s.stem in set(args.names)]
    failed = False
    for source in sources:
        start = time.perf_counter()
        if args.check:
            found = check(source)
            failed = failed or bool(found)
            print(f"{source.stem}: {'differs' if found else 'as saved'} ({time.perf_counter() - start:.0f} s)")
            for line in found:
                print("  " + line.replace("\n", "\n  "))
        else:
            target = build(source)
            print(f"{target.name}: {time.perf_counter() - start:.0f} s")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
