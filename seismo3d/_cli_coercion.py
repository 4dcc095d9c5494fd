"""The ``seismo3d`` command's values converted without pydantic when typer's result is certain.

typer (0.29, installed here) converts every command-line value through a pydantic ``TypeAdapter`` built per parameter
when the value is processed (``typer._coercion.build_runtime_param``): even ``--help`` and a parameter left at its
default build one, so every command imported pydantic and pydantic_core and built its adapters, about 0.1 s of each
process (0.07-0.1 s of imports, 3-10 ms per adapter). No parameter declaration avoids it: only file annotations
(``typer.FileText``, ...) are converted without an adapter.

:class:`FastCoercionGroup`, the ``seismo3d`` app's group class, gives each parameter of the command being run a
converter that returns typer's own result for the plain cases (a default value already of the parameter's type,
None, a path, an Enum choice through typer's own ``coerce_cli_choice``, a plain decimal integer or float inside the
parameter's ``min`` / ``max``) and hands every other value to typer's converter, built then as before (so typer's
messages for bad values, its clamping, lists, tuples and custom parsers are unchanged). tests/test_cli_coercion.py
checks, parameter by parameter of every command, that a value converted here equals typer's result in value and
type. With a typer whose parameters do not convert this way (no ``type_descriptor``), nothing is changed.
"""

from __future__ import annotations

import re
from enum import Enum
from pathlib import Path

from typer.core import TyperGroup

__all__ = ["FastCoercionGroup", "fast_value", "DECLINED"]

DECLINED = object()  # fast_value's answer for a value typer converts itself
_INT = re.compile(r"-?(?:0|[1-9][0-9]{0,17})")
_FLOAT = re.compile(r"-?(?:0|[1-9][0-9]{0,15})(?:\.[0-9]{1,15})?")


def _in_range(value, info) -> bool:
    """Whether ``value`` is inside the parameter's ``min`` / ``max`` (where typer's adapter accepts it unchanged)."""
    if getattr(info, "clamp", False):
        return False  # typer clamps: its own result
    low, high = getattr(info, "min", None), getattr(info, "max", None)
    return (low is None or value >= low) and (high is None or value <= high)


def fast_value(descriptor, value, *, multiple: bool = False, ctx=None):
    """typer's conversion of ``value`` for a parameter when it is certain without pydantic, else :data:`DECLINED`.

    Parameters
    ----------
    descriptor : typer._coercion.TypeDescriptor
        The parameter's annotation and options (``param.type_descriptor``).
    value : object
        The value typer's parser gives: a string from the command line, the default, or None.
    multiple : bool
        Whether the parameter takes several values (a list or repeated option).
    ctx : click context, optional
        For typer's ``coerce_cli_choice`` (its case normalisation).

    Returns
    -------
    object
        The converted value, or :data:`DECLINED`.
    """
    annotation, info = descriptor.annotation, descriptor.parameter_info
    if value is None:
        return () if multiple else None  # as typer's RuntimeParam.coerce, before any adapter
    if multiple or getattr(info, "parser", None) is not None or descriptor.file_annotation is not None:
        return DECLINED
    if annotation is bool:
        return value if isinstance(value, bool) else DECLINED
    if annotation is str:
        return value if isinstance(value, str) else DECLINED
    if annotation is int:
        if isinstance(value, str) and _INT.fullmatch(value):
            value = int(value)
        return value if type(value) is int and _in_range(value, info) else DECLINED
    if annotation is float:
        if isinstance(value, str) and _FLOAT.fullmatch(value):
            value = float(value)
        return value if type(value) is float and _in_range(value, info) else DECLINED
    if isinstance(annotation, type) and issubclass(annotation, Enum):
        return _choice(annotation, value, info, ctx)
    if isinstance(annotation, type) and issubclass(annotation, Path) and getattr(info, "path_type", None) is None:
        return _path(annotation, value, info)
    return DECLINED


def _choice(annotation, value, info, ctx):
    """An Enum choice through typer's own ``coerce_cli_choice`` (the function its adapter calls)."""
    try:
        from typer._param_types import coerce_cli_choice
    except ImportError:  # another typer: its own converter
        return DECLINED
    try:
        return coerce_cli_choice(value, choices=list(annotation), case_sensitive=info.case_sensitive, ctx=ctx)
    except Exception:  # noqa: BLE001 - typer says what is wrong
        return DECLINED


def _path(annotation, value, info):
    """A path as typer's path adapter gives it (pydantic's ``Path(value)``, then typer's checks: existence, file or
    folder, ...), for a string or a path; a check that fails is left to typer, which says so."""
    try:
        from typer._param_types import coerce_cli_path
    except ImportError:  # another typer: its own converter
        return DECLINED
    if isinstance(value, str) and value:
        value = annotation(value)
    if not isinstance(value, annotation):
        return DECLINED
    try:
        return coerce_cli_path(value, info, path_type=annotation)
    except Exception:  # noqa: BLE001 - typer says what is wrong
        return DECLINED


class _FastRuntimeParam:
    """typer's runtime converter of one parameter, built only for the values :func:`fast_value` declines."""

    def __init__(self, param):
        self._param, self._typer = param, None

    def coerce(self, value, param, ctx):
        multiple = bool(param.multiple or param.nargs == -1)
        converted = fast_value(param.type_descriptor, value, multiple=multiple, ctx=ctx)
        if converted is not DECLINED:
            return converted
        if self._typer is None:
            from typer._coercion import build_runtime_param

            self._typer = build_runtime_param(param.type_descriptor)
        return self._typer.coerce(value, param=param, ctx=ctx)


def _prime(params) -> None:
    """Give each typer parameter not yet converted the fast converter (parameters of other kinds are left alone)."""
    for param in params:
        if hasattr(param, "type_descriptor") and getattr(param, "_runtime_param", False) is None:
            param._runtime_param = _FastRuntimeParam(param)


class FastCoercionGroup(TyperGroup):
    """typer's group, whose parameters and the parameters of the command it runs convert their values through
    :func:`fast_value` first (see the module docstring)."""

    def parse_args(self, ctx, args):
        _prime(self.get_params(ctx))
        return super().parse_args(ctx, args)

    def resolve_command(self, ctx, args):
        name, command, rest = super().resolve_command(ctx, args)
        if command is not None:
            _prime(command.get_params(ctx))
        return name, command, rest
