"""seismo3d._cli_coercion: every value it converts without pydantic is typer's own result, in value and type, for
every parameter of every command; the values it is not certain of are left to typer (its messages unchanged)."""

from __future__ import annotations

import enum
import pathlib

import pytest
import typer.main

from seismo3d._cli_coercion import DECLINED, FastCoercionGroup, fast_value
from seismo3d.cli import app

typer_coercion = pytest.importorskip("typer._coercion")

# strings a user may type, and values typer's parser passes (defaults, flags)
SAMPLES = ["189", "0", "-3", "+5", "007", " 12", "12 ", "1_000", "1e3", "12.5", "0.0005", "0.001", "64", "64.0",
           "-0", "-0.0", ".5", "5.", "abc", "", "inf", "nan", "big", "BIG", "lz4", "none", "ms", "scan", "fused",
           "/tmp", "x.zarr", ".", "-", "true", "1", None, True, False, 3, 3.5, 0.0005, -1]


def _parameters():
    group = typer.main.get_command(app)
    ctx = group.context_class(group)
    for name, command in group.commands.items():
        for param in command.get_params(ctx):
            if hasattr(param, "type_descriptor"):
                yield pytest.param(command, param, id=f"{name}-{param.name}")


def _typer(param, value, ctx):
    """typer's own conversion (pydantic), or the exception it raises."""
    try:
        return typer_coercion.build_runtime_param(param.type_descriptor).coerce(value, param=param, ctx=ctx)
    except Exception as exc:  # noqa: BLE001 - compared below
        return exc


def test_the_app_uses_the_group():
    assert isinstance(typer.main.get_command(app), FastCoercionGroup)


@pytest.mark.parametrize("command, param", list(_parameters()))
def test_a_fast_value_is_typers(command, param):
    ctx = command.context_class(command)
    multiple = bool(param.multiple or param.nargs == -1)
    for value in [*SAMPLES, param.default]:
        fast = fast_value(param.type_descriptor, value, multiple=multiple, ctx=ctx)
        if fast is DECLINED:
            continue
        expected = _typer(param, value, ctx)
        assert not isinstance(expected, Exception), f"{value!r}: typer refuses it ({expected}), fast gave {fast!r}"
        assert fast == expected and type(fast) is type(expected), f"{value!r}: {fast!r} against typer's {expected!r}"


def test_plain_values_are_converted_and_the_rest_declined():
    """The cases a convert meets are certain; a value typer would refuse, or convert in its own way, is declined."""
    group = typer.main.get_command(app)
    convert = group.commands["convert"]
    ctx = convert.context_class(convert)
    params = {p.name: p for p in convert.get_params(ctx)}

    def fast(name, value):
        return fast_value(params[name].type_descriptor, value, ctx=ctx)

    assert fast("input", "a.sgy") == pathlib.Path("a.sgy") and fast("iline", "9") == 9 and fast("iline", 189) == 189
    assert fast("chunk_mb", "32") == 32.0 and type(fast("chunk_mb", "32")) is float
    assert fast("compression", "lz4").value == "lz4" and fast("endian", None) is None
    assert fast("overwrite", False) is False
    for name, value in [("iline", "abc"), ("iline", "1e3"), ("iline", True), ("chunk_mb", "0.0001"),
                        ("chunk_mb", "inf"), ("compression", "gzip"), ("input", ""), ("overwrite", "yes")]:
        assert fast(name, value) is DECLINED, (name, value)


@pytest.mark.slow
@pytest.mark.parametrize("args", [["--chunk-mb", "0"], ["--iline", "x"], ["--chunk-mb", "1e-9"], ["--endian", "mid"],
                                  ["--compression", "gzip"]])
def test_a_declined_value_gets_typers_message(args, tmp_path, monkeypatch):
    """A bad value is refused as typer alone refuses it: the same message and exit code."""
    import seismo3d._cli_coercion as coercion
    from typer.testing import CliRunner

    argv = ["convert", str(tmp_path / "in.sgy"), str(tmp_path / "o.zarr"), *args]
    ours = CliRunner().invoke(app, argv)
    monkeypatch.setattr(coercion, "_prime", lambda params: None)  # typer's converters only
    typers = CliRunner().invoke(app, argv)
    assert ours.exit_code == typers.exit_code == 2 and ours.output == typers.output


class _Colour(str, enum.Enum):
    red = "red"


def test_annotations_it_does_not_know_are_declined():
    """Lists, tuples and other types go to typer."""
    descriptor = typer_coercion.resolve_type_descriptor(list[float], typer.models.OptionInfo())
    assert fast_value(descriptor, ["1"], multiple=True) is DECLINED
    descriptor = typer_coercion.resolve_type_descriptor(complex, typer.models.OptionInfo())
    assert fast_value(descriptor, "1") is DECLINED
    descriptor = typer_coercion.resolve_type_descriptor(_Colour, typer.models.OptionInfo())
    assert fast_value(descriptor, "red") is _Colour.red
