"""MkDocs hooks of seismo3d's documentation: the command reference generated from the CLI itself, and the
docstrings' Sphinx roles shown as code, and the method's equations as MathML.

``docs/cli.md`` holds the marker ``<!-- cli-reference -->``; at build time it is replaced by the ``--help`` of the
``seismo3d`` command and of each of its sub-commands, as click renders them from the typer app
(:mod:`seismo3d.cli`), so that the reference cannot drift from the command.
"""

from __future__ import annotations

import html as html_module
import re

MARKER = "<!-- cli-reference -->"


def _cell(text) -> str:
    """Text for a Markdown table cell: one line, pipes escaped."""
    return " ".join(str(text).split()).replace("|", "\\|")


def _value(param, ctx) -> str:
    """What a parameter takes: its choices or a type name (typer's own display), nothing for a flag."""
    if getattr(param, "is_flag", False):
        return ""
    shown = param.display_type(ctx)
    return "" if shown == "<bool>" else "`" + shown.replace("|", " / ") + "`"


def _default(param) -> str:
    default = param.default
    if default is None or default is False or default == () or getattr(param, "required", False):
        return ""
    if hasattr(default, "value"):  # an enum member
        default = default.value
    return f"`{default}`"


def _command(command, name: str, parent) -> list:
    """Markdown lines of one command: usage, its help and a table of its arguments and options."""
    ctx = command.context_class(command, info_name=name, parent=parent)
    usage = " ".join(command.collect_usage_pieces(ctx))
    lines = [f"## {ctx.command_path}", "", f"```text\n{ctx.command_path} {usage}\n```", ""]
    lines += [(command.help or "").strip().replace("\b\n", ""), ""]
    rows = []
    for param in command.params:
        if param.param_type_name == "argument":
            label = f"`{param.name.upper()}`" + (" (required)" if param.required else "")
        else:
            names = ", ".join(f"`{o}`" for o in [*param.opts, *param.secondary_opts])
            label = names + (" (required)" if param.required else "")
        rows.append(f"| {label} | {_value(param, ctx)} | {_default(param)} | {_cell(getattr(param, 'help', '') or '')} |")
    if rows:
        lines += ["| argument / option | value | default | what it does |", "|---|---|---|---|", *rows, ""]
    return lines


def cli_reference() -> str:
    """Markdown of the ``seismo3d`` command and of each sub-command (usage, help, arguments and options), in the
    app's order, generated from the typer app."""
    import typer.main

    from seismo3d.cli import app

    group = typer.main.get_command(app)
    root = group.context_class(group, info_name="seismo3d")
    parts = _command(group, "seismo3d", None)
    for name in group.list_commands(root):
        parts += _command(group.get_command(root, name), name, root)
    return "\n".join(parts)


_ROLE = re.compile(r":(?:func|class|meth|mod|attr|data|exc|obj):<code>(~?)([^<]+)</code>")


def _role(match) -> str:
    """A Sphinx role left in a docstring (``:func:`~seismo3d.x.f```) as the code it names (``f``)."""
    short, target = match.group(1), match.group(2)
    return f"<code>{target.rsplit('.', 1)[-1] if short else target}</code>"


def on_page_content(html, page, config, files):  # noqa: ARG001 - MkDocs' hook signature
    """The docstrings are numpydoc, written for Sphinx too: show their cross-reference roles as plain code."""
    return _ROLE.sub(_role, html)


_MATH = re.compile(r'<(span|div) class="arithmatex">\s*(?:\\\(|\\\[)(.*?)(?:\\\)|\\\])\s*</\1>', re.S)


def _mathml(match) -> str:
    """One formula of pymdownx.arithmatex (generic output) as MathML, which browsers draw without JavaScript."""
    from latex2mathml.converter import convert

    tag, tex = match.group(1), html_module.unescape(match.group(2))
    return convert(tex.strip(), display="block" if tag == "div" else "inline")


def on_post_page(output, page, config):  # noqa: ARG001 - MkDocs' hook signature
    """The method's equations as MathML, made at build time (no JavaScript, no network)."""
    return _MATH.sub(_mathml, output) if "arithmatex" in output else output


def on_page_markdown(markdown, page, config, files):  # noqa: ARG001 - MkDocs' hook signature
    """Put the generated command reference where ``cli.md`` has the marker."""
    if MARKER in markdown:
        return markdown.replace(MARKER, cli_reference())
    return markdown
