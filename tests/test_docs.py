"""The README and the documentation site (docs/, mkdocs.yml): the README stays short, every Python example of the
README and of the user guide runs as written on the real data, the command reference lists every command and option
of the CLI, and the site builds with warnings as errors (mkdocs build --strict)."""

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
GUIDE = sorted((ROOT / "docs" / "guide").glob("*.md"))


def _python_blocks(path: Path) -> list:
    """The ```python blocks of a Markdown file, in order."""
    return re.findall(r"^```python\n(.*?)^```", path.read_text(encoding="utf-8"), flags=re.S | re.M)


def _run_blocks(path: Path, folder: Path, monkeypatch) -> dict:
    """Run a page's Python blocks one after the other in one namespace, in ``folder`` (they write their outputs
    there); returns the namespace."""
    monkeypatch.chdir(folder)
    namespace = {"__name__": "__docs__"}
    for n, code in enumerate(_python_blocks(path)):
        exec(compile(code, f"{path.name}[python block {n + 1}]", "exec"), namespace)  # noqa: S102 - the docs' own code
    return namespace


def _hooks():
    spec = importlib.util.spec_from_file_location("docs_hooks", ROOT / "docs" / "hooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_readme_is_short_and_says_how_to_run_the_tests():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.encode("utf-8")) <= 9000
    for command in ("python -m pytest", 'python -m pytest -m "not slow"', "seismo3d faults --demo",
                    'pip install -e ".[test]"', "cd seismo3d"):
        assert command in text, command
    assert max(len(line) for line in text.splitlines()) < 200  # no development log crammed into a table cell


@pytest.mark.slow  # the bunny scans' ICP: about 5 s
def test_readme_library_example_runs_as_written(data_dir, tmp_path, monkeypatch, capsys):
    """The README's library example on the real bunny scans: it converges, and what it prints is true."""
    assert len(_python_blocks(ROOT / "README.md")) == 1  # the one library example
    namespace = _run_blocks(ROOT / "README.md", tmp_path, monkeypatch)
    result, pair = namespace["result"], namespace["pair"]
    from seismo3d.geometry import rotation_error_deg

    assert result.converged and result.inlier_rmse < 1e-3  # metres
    assert rotation_error_deg(result.transform, pair.transform) < 0.5  # the scans are 34 deg apart
    printed = capsys.readouterr().out
    assert printed.startswith("True ") and "deg from the true rotation" in printed


@pytest.mark.slow  # each page runs a job on real data: 2-20 s a page
@pytest.mark.parametrize("page", GUIDE, ids=lambda p: p.stem)
def test_guide_examples_run_as_written(page, data_dir, tmp_path, monkeypatch, capsys):
    blocks = _python_blocks(page)
    if not blocks:
        pytest.skip(f"{page.name} has no Python example")
    namespace = _run_blocks(page, tmp_path, monkeypatch)
    assert capsys.readouterr().out.strip()  # every example prints what it found
    checks = {  # what each page's example claims, checked on its results
        "faults": lambda ns: (len(ns["job"].faults) >= 3 and "summary" in ns["job"].written
                              and _parihaka_example_is_true(ns)),
        "horizons": lambda ns: ns["job"].horizon.coverage > 0.8 and ns["job"].n_rows > 300,
        "volumes": lambda ns: ns["result"].converged and abs(ns["result"].transform_index
                                                             - np.linalg.inv(ns["stretch"])).max() < 0.05,
        "mapping": lambda ns: ns["result"].converged and len(ns["trajectory"].poses) == 5,
        "terrain": lambda ns: len(ns["found"]) > 0,
        "rendering": lambda ns: (tmp_path / "xl1155.png").stat().st_size > 10_000 and "inline" in ns["caption"],
    }
    assert checks[page.stem](namespace)


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
