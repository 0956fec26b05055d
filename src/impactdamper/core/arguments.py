"""Generic argument checks: a value checked or a one-line error naming the argument.

"`name` = value is not allowed: must be ...": a :class:`ValueError` (or
:class:`ArgumentTypeError`, also a ValueError, for a wrong type), never a traceback from deep
inside a computation or a silent wrong answer. These checks know nothing of the model; this
module imports nothing of the package, so that :mod:`impactdamper.core.parameters` checks its
values with it. The solver's argument checks, and these names too, are in
:mod:`impactdamper.core.validation`, the one module to import an argument check from.
"""

from __future__ import annotations

import math
import numbers

__all__ = ["ArgumentTypeError", "show_value", "check_value", "real_argument", "finite_argument", "integer_argument"]


class ArgumentTypeError(TypeError, ValueError):
    """An argument of the wrong type (``None``, a string, a bool where a number is expected...).

    A :class:`TypeError`, as scipy raises for a wrong type; also a :class:`ValueError`, so that a
    caller that catches bad values (the command line) catches it with them.
    """


def show_value(value: object) -> str:
    """repr of a bad value, short enough for a one-line message (an int can have 400 digits)."""
    if isinstance(value, numbers.Integral) and not isinstance(value, bool) and abs(int(value)) > 10**20:
        return f"an integer of {len(str(abs(int(value))))} digits"
    if getattr(value, "ndim", 0) and hasattr(value, "shape") and hasattr(value, "dtype"):
        # An array by its shape and dtype: its repr spans lines and says little at this length.
        masked = " (masked)" if type(value).__name__ == "MaskedArray" else ""
        return f"an array of shape {tuple(value.shape)} and dtype {value.dtype}{masked}"
    text = " ".join(repr(value).split())  # (one line whatever the repr)
    return text if len(text) <= 60 else text[:40] + "...(truncated)"


def check_value(name: str, value: object, ok: bool, allowed: str) -> None:
    """Nothing if ``ok``, else a ValueError naming ``name``, its value and what is ``allowed``."""
    if not ok:
        raise ValueError(f"`{name}` = {show_value(value)} is not allowed: must be {allowed}")


def real_argument(name: str, value: object) -> float:
    """``value`` as a float if it is a real number, else an error naming ``name``.

    Python and numpy numbers are accepted (``np.float32(1.0)``, ``np.int64(1)``); a bool is not a
    number here, nor is a string.

    Raises
    ------
    ArgumentTypeError
        Not a real number.
    ValueError
        An integer too large for a float.
    """
    if type(value) is float:  # (the solver's own calls: no abstract-class check on its hot path)
        return value
    if isinstance(value, bool) or type(value).__name__ == "bool_" or not isinstance(value, numbers.Real):
        raise ArgumentTypeError(f"`{name}` = {show_value(value)} is not allowed: must be a real number")
    try:
        return float(value)
    except OverflowError:
        raise ValueError(
            f"`{name}` = {show_value(value)} is not allowed: must be a finite number (it overflows a float)"
        ) from None


def finite_argument(name: str, value: object) -> float:
    """``value`` as a finite float, else an error naming ``name`` (see :func:`real_argument`)."""
    x = real_argument(name, value)
    check_value(name, x, math.isfinite(x), "a finite number")
    return x


def integer_argument(name: str, value: object, low: int, high: int | None = None) -> int:
    """``value`` as an int in [low, high], else an error naming ``name`` (numpy integers are
    accepted; a bool or a float is not an integer here)."""
    allowed = f"an integer >= {low}" if high is None else f"an integer in [{low}, {high}]"
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ArgumentTypeError(f"`{name}` = {show_value(value)} is not allowed: must be {allowed}")
    n = int(value)
    check_value(name, n, n >= low and (high is None or n <= high), allowed)
    return n
