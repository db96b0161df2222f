"""Checks of input values: a clear error that names the value and the limit."""

from __future__ import annotations

import math


class SceneError(ValueError):
    """An invalid scene value: the message names the field, the value and the limit."""


def check_real(name: str, value, *, lower=None, upper=None, lower_open=False, upper_open=False,
               unit: str = "") -> float:
    """Return ``value`` as float after checking it is finite and within bounds, else raise SceneError.

    The message names the field, the value (with ``unit`` when given) and the violated limit.
    """
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise SceneError(f"{name} must be a real number{' in ' + unit if unit else ''}, got {value!r}") from None
    if not math.isfinite(x):
        raise SceneError(f"{name} = {x!r}{' ' + unit if unit else ''} is not finite")
    if lower is not None and (x < lower or (lower_open and x == lower)):
        op = ">" if lower_open else ">="
        raise SceneError(f"{name} = {x!r}{' ' + unit if unit else ''} is out of range: it must be {op} {lower!r}")
    if upper is not None and (x > upper or (upper_open and x == upper)):
        op = "<" if upper_open else "<="
        raise SceneError(f"{name} = {x!r}{' ' + unit if unit else ''} is out of range: it must be {op} {upper!r}")
    return x


def positive(name, value, *, allow_zero=False):
    return check_real(name, value, lower=0.0, lower_open=not allow_zero)


def error_text(exc: BaseException) -> str:
    """``"TypeName: message"`` of an exception, in words: an OSError-style ``(errno, text)`` pair (math's
    OverflowError carries ``(34, 'Numerical result out of range')``) gives its text."""
    args = exc.args
    if len(args) == 2 and type(args[0]) is int and isinstance(args[1], str):
        return f"{type(exc).__name__}: {args[1]}"
    return f"{type(exc).__name__}: {exc}"
