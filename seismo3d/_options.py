"""Options objects: how a function takes its tuning values from a frozen dataclass and keyword overrides.

Every function with tuning values takes ``options=`` (a frozen, documented dataclass whose defaults are the
function's defaults) and, for convenience and for the callers written before the options objects, the same values as
keyword arguments, which replace the fields of ``options``: ``icp(src, dst, max_iterations=20)`` is
``icp(src, dst, options=ICPOptions(max_iterations=20))``. The dataclasses check their fields when they are made.
"""

from __future__ import annotations

import dataclasses

from .errors import InputError

__all__ = ["resolve_options"]


def resolve_options(cls, options, overrides: dict, caller: str):
    """``options`` (an instance of the dataclass ``cls``, or None for its defaults) with the fields named in
    ``overrides`` replaced.

    Parameters
    ----------
    cls : type
        A frozen dataclass type (e.g. :class:`seismo3d.registration.ICPOptions`).
    options : cls or None
        The caller's options object.
    overrides : dict
        Keyword arguments naming fields of ``cls``.
    caller : str
        The public function's name, for messages.

    Returns
    -------
    cls
        A new options object (``options`` itself when there is nothing to replace).

    Raises
    ------
    InputError
        ``options`` is not a ``cls``, a keyword names no field of ``cls``, or a replaced field is invalid.
    """
    if options is None:
        options = cls()
    elif not isinstance(options, cls):
        raise InputError(f"{caller}(options=...) must be an instance of {cls.__name__}; got {type(options).__name__}")
    if not overrides:
        return options
    names = [f.name for f in dataclasses.fields(cls)]
    unknown = sorted(set(overrides) - set(names))
    if unknown:
        raise InputError(f"{caller}() got unknown keyword argument(s) {', '.join(unknown)}; the options of "
                         f"{cls.__name__} are {', '.join(names)}")
    return dataclasses.replace(options, **overrides)
