"""The README and the documentation site (docs/, mkdocs.yml): the README opens with the two commands that set
everything up, every Python block of the README and of docs/ (the generated API pages aside) runs as written and prints
what its page shows, the command reference lists every command and option of the CLI, and the site builds with
warnings as errors (mkdocs build --strict)."""

import doctest
import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
# Every page a user reads, but the API pages (generated from the docstrings, which hold no runnable blocks).
PAGES = [ROOT / "README.md"] + sorted(p for p in (ROOT / "docs").rglob("*.md") if "api" not in p.parts)
_FENCE = re.compile(r"^```([\w-]*)[^\n]*\n(.*?)^```[ \t]*$", flags=re.S | re.M)
# Pages whose examples fail today, and who fixes them: a strict xfail, so that the fix turns it into a failure that
# says "remove the entry".
KNOWN_BROKEN: dict = {}  # page stem -> why its examples fail today (a strict xfail: mended pages turn it red)


def _fenced_blocks(path: Path) -> list:
    """The fenced blocks of a Markdown file, in order: (info string's language, text, whether only blank lines
    separate it from the block before)."""
    text = path.read_text(encoding="utf-8")
    blocks, end = [], None
    for match in _FENCE.finditer(text):
        adjacent = end is not None and not text[end:match.start()].strip()
        blocks.append((match.group(1), match.group(2), adjacent))
        end = match.end()
    return blocks


def page_examples(path: Path) -> list:
    """The ```python blocks of a Markdown page and what the page shows each one printing: a list of (code, shown
    output or None). A block's output is the ```text block right after it (nothing but blank lines between);
    ``...`` in it stands for any text (a number that varies from machine to machine), as in a doctest."""
    blocks = _fenced_blocks(path)
    examples = []
    for i, (language, code, _) in enumerate(blocks):
        if language != "python":
            continue
        after = blocks[i + 1] if i + 1 < len(blocks) else None
        shown = after[1] if after is not None and after[0] == "text" and after[2] else None
        examples.append((code, shown))
    return examples


def _same_output(shown: str, printed: str) -> bool:
    """``printed`` is what the page shows (trailing spaces and blank lines aside; ``...`` matches any text)."""
    def tidy(text):
        return "\n".join(line.rstrip() for line in text.strip("\n").splitlines()) + "\n"

    return doctest.OutputChecker().check_output(tidy(shown), tidy(printed), doctest.ELLIPSIS)


def run_page(path: Path, folder: Path, monkeypatch, capsys) -> dict:
    """Run a page's Python blocks one after the other in one namespace, in ``folder`` (they write their outputs
    there), each block's printed output checked against the page; returns the namespace.

    Raises
    ------
    AssertionError
        A block printed something other than its page shows, or printed with no output shown on the page.
    """
    monkeypatch.chdir(folder)
    namespace = {"__name__": "__docs__"}
    capsys.readouterr()
    for n, (code, shown) in enumerate(page_examples(path), start=1):
        where = f"{path.relative_to(ROOT)}, Python block {n}"
        exec(compile(code, where, "exec"), namespace)  # noqa: S102 - the docs' own code
        printed = capsys.readouterr().out
        if shown is None:
            assert not printed.strip(), (f"{where} prints\n{printed}but the page shows no output: put it in a "
                                         "```text block right after the code")
        else:
            assert _same_output(shown, printed), f"{where} prints\n{printed}where the page shows\n{shown}"
    return namespace


def _hooks():
    spec = importlib.util.spec_from_file_location("docs_hooks", ROOT / "docs" / "hooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _quick_start() -> list:
    """The commands of the README's first code block (its non-blank, non-comment lines)."""
    language, code, _ = _fenced_blocks(ROOT / "README.md")[0]
    assert language in ("bash", "console", "sh"), language
    return [line for line in code.splitlines() if line.strip() and not line.lstrip().startswith("#")]


def test_readme_opens_with_two_commands_that_set_everything_up():
    """The README's first code block is two commands: the first installs seismo3d and runs the demo, the second
    installs the test extra and runs the suite; CI (.ci/run) runs that second command as written."""
    first, second = _quick_start()  # exactly two
    assert "pip install -e ." in first and re.search(r"&& seismo3d faults --demo -o \S+$", first), first
    assert first.index("venv") < first.index("pip install") < first.index("seismo3d faults"), first
    assert second == 'pip install -e ".[test]" && python -m pytest', second
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert second in ci, "the README's test command is what .ci/run runs"
    assert ci[-1] == second, "and .ci/run ends with it (its exit code is CI's)"
    guide = (ROOT / "docs" / "getting-started.md").read_text(encoding="utf-8")
    assert f"\n{first}\n" in guide and f"\n{second}\n" in guide, "getting started gives the same two commands"


def test_readme_is_short():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.encode("utf-8")) <= 9000
    assert max(len(line) for line in text.splitlines()) < 200  # no development log crammed into a table cell


@pytest.mark.parametrize(("path", "limit"), [("CONTRIBUTING.md", 8 * 1024), ("docs/model-card.md", 12 * 1024)])
def test_guides_for_users_stay_short(path, limit):
    """CONTRIBUTING is a guide to the code and the model card a model card, not logs of the work (issue 77)."""
    size = len((ROOT / path).read_bytes())
    assert size <= limit, f"{path}: {size} bytes, over {limit}"


@pytest.mark.parametrize("page", PAGES + [ROOT / "CONTRIBUTING.md"], ids=lambda p: p.stem)
def test_no_development_log_in_the_docs(page):
    """History belongs in commit messages (and a short CHANGELOG.md): no rounds of work in what users read."""
    text = page.read_text(encoding="utf-8")
    for pattern in (r"\bstop \d+", r"\bissue \d+", r"\bmodules? counts?\b", r"\b\d+ modules\b"):
        assert not re.search(pattern, text, flags=re.I), (page.name, pattern)


def test_shown_output_is_compared():
    """The machinery fails a wrong printed output and a print the page does not show, and takes ``...`` for any
    text."""
    assert _same_output("8 8 2216\n", "8 8 2216  \n\n")
    assert not _same_output("8 8 2216\n", "3 3 887\n")
    assert _same_output("True ... mm\n", "True 0.31 mm\n")
    assert not _same_output("True ... mm\n", "False 0.31 mm\n")


def test_page_examples_pair_each_block_with_its_output(tmp_path, monkeypatch, capsys):
    page = tmp_path / "page.md"
    page.write_text("```python\nprint(1 + 1)\n```\n\n```text\n2\n```\n\nprose\n\n```python\nx = 3\n```\n\n"
                    "then\n\n```text\nnot its output\n```\n", encoding="utf-8")
    assert page_examples(page) == [("print(1 + 1)\n", "2\n"), ("x = 3\n", None)]
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    assert run_page(page, tmp_path, monkeypatch, capsys)["x"] == 3
    page.write_text("```python\nprint(3, 3, 887)\n```\n\n```text\n8 8 2216\n```\n", encoding="utf-8")
    with pytest.raises(AssertionError, match="where the page shows"):
        run_page(page, tmp_path, monkeypatch, capsys)
    page.write_text("```python\nprint(3)\n```\n", encoding="utf-8")
    with pytest.raises(AssertionError, match="shows no output"):
        run_page(page, tmp_path, monkeypatch, capsys)


EXAMPLE_PAGES = [p for p in PAGES if page_examples(p)]


@pytest.mark.slow  # each page runs a job on real data: 2-20 s a page
@pytest.mark.parametrize("page", [pytest.param(p, marks=pytest.mark.xfail(reason=KNOWN_BROKEN[p.stem], strict=True))
                                  if p.stem in KNOWN_BROKEN else p for p in EXAMPLE_PAGES], ids=lambda p: p.stem)
def test_page_examples_run_and_print_what_the_page_shows(page, data_dir, tmp_path, monkeypatch, capsys):
    namespace = run_page(page, tmp_path, monkeypatch, capsys)
    from seismo3d.geometry import rotation_error_deg

    checks = {  # what each page's example claims beyond its printed lines, checked on its results
        "README": lambda ns: ns["result"].converged and ns["result"].inlier_rmse < 1e-3  # metres
        and rotation_error_deg(ns["result"].transform, ns["pair"].transform) < 0.5,  # the scans are 34 deg apart
        "faults": lambda ns: (len(ns["job"].faults) >= 3 and "summary" in ns["job"].written
                              and _parihaka_example_is_true(ns)),
        "horizons": lambda ns: ns["job"].horizon.coverage > 0.8 and ns["job"].n_rows > 300,
        "volumes": lambda ns: ns["result"].converged and abs(ns["result"].transform_index
                                                             - np.linalg.inv(ns["stretch"])).max() < 0.05,
        "mapping": lambda ns: ns["result"].converged and len(ns["trajectory"].poses) == 5,
        "terrain": lambda ns: len(ns["found"]) > 0,
        "rendering": lambda ns: (tmp_path / "xl1155.png").stat().st_size > 10_000 and "inline" in ns["caption"],
    }
    assert checks.get(page.stem, lambda ns: True)(namespace)


def _parihaka_example_is_true(ns) -> bool:
    """The faults page's real cube: the crop it says (128 x 128 x 128 samples, all but 41 of people's fault samples
    in the window), its traced samples those of the run's faults, its counts within their bounds."""
    parihaka, window = ns["parihaka"], ns["window"]
    assert ns["cube"].shape == (128, 128, 128) and window.stop - window.start == 128
    assert int(parihaka.faults[:, :, window].sum()) - int(ns["people"].sum()) == 41
    assert ns["traced"].any() == (ns["run"].n_faults > 0)
    assert np.count_nonzero(ns["touched"]) <= ns["n_outlines"] and ns["n_outlines"] > 100
    assert (Path("parihaka_faults") / "faults.png").stat().st_size > 10_000  # in the page's folder (the cwd)
    return True


def test_cli_reference_lists_every_command_and_option():
    """The command reference is generated from the typer app: every command and every flag is on the page."""
    import typer.main

    from seismo3d.cli import app

    text = _hooks().cli_reference()
    group = typer.main.get_command(app)
    root = group.context_class(group, info_name="seismo3d")
    for name in group.list_commands(root):
        assert f"## seismo3d {name}\n" in text
        for param in group.get_command(root, name).params:
            for flag in param.opts:
                assert f"`{flag}`" in text or f"`{flag.upper()}`" in text, (name, flag)


def test_docstring_roles_are_shown_as_code():
    hooks = _hooks()
    html = "see :func:<code>~seismo3d.seismic.open_segy</code> and :class:<code>seismo3d.errors.InputError</code>"
    assert hooks.on_page_content(html, None, None, None) == (
        "see <code>open_segy</code> and <code>seismo3d.errors.InputError</code>")


def test_equations_become_mathml():
    """The method's equations are MathML in the built page: browsers draw them with no JavaScript or network."""
    pytest.importorskip("latex2mathml", reason='the documentation tools: pip install -e ".[docs]"')
    page = ('<p><span class="arithmatex">\\(d = 2\\)</span></p>'
            '<div class="arithmatex">\\[E = \\frac{1}{N} \\sum_i r_i^2\\]</div>')
    out = _hooks().on_post_page(page, None, None)
    assert "arithmatex" not in out and out.count("<math") == 2 and 'display="block"' in out and "<mfrac>" in out


@pytest.mark.slow  # about 10 s
def test_site_builds_with_warnings_as_errors(tmp_path):
    pytest.importorskip("mkdocs", reason='the documentation tools: pip install -e ".[docs]"')
    pytest.importorskip("mkdocstrings_handlers.python", reason='pip install -e ".[docs]"')
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
           "NO_MKDOCS_2_WARNING": "1"}
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    for page in ("index.html", "cli/index.html", "guide/faults/index.html", "api/registration/index.html"):
        assert (tmp_path / "site" / page).is_file(), page
    cli = (tmp_path / "site" / "cli" / "index.html").read_text(encoding="utf-8")
    assert "--n-samples" in cli and "seismo3d faults" in cli
    api = (tmp_path / "site" / "api" / "registration" / "index.html").read_text(encoding="utf-8")
    assert 'id="seismo3d.registration.icp.icp"' in api and 'id="seismo3d.registration.fused_icp"' in api
    method = (tmp_path / "site" / "method" / "index.html").read_text(encoding="utf-8")
    assert method.count("<math") >= 20 and "arithmatex" not in method
