"""Numbers and text for the report: ``\\newcommand`` macros and number formats.

Every number in the report reaches LaTeX through a macro file a workflow stage writes with
these helpers; nothing in ``paper/`` is typed by hand.
"""

from __future__ import annotations

import math
import re

__all__ = ["MISSING", "macro", "camel", "fixed", "sci", "tex_sci", "tex_time", "tex_escape"]

# A value that does not exist, in a macro (works in math and text mode).
MISSING = "\\mbox{--}"

_MACRO_NAME = re.compile(r"^[A-Za-z]+$")


def macro(name: str, value) -> str:
    """One ``\\newcommand`` line, without a newline (TeX macro names are letters only)."""
    if not _MACRO_NAME.match(name):
        raise ValueError(f"`name` = {name!r} is not allowed: a TeX macro name has letters only")
    return f"\\newcommand{{\\{name}}}{{{value}}}"


def camel(name: str) -> str:
    """A config name as a macro-name part: ``double`` -> ``Double``."""
    return name[:1].upper() + name[1:]


def fixed(x, digits: int) -> str:
    """A number with fixed decimals (math mode); :data:`MISSING` when missing; never ``-0.00``."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return MISSING
    s = f"{x:.{digits}f}"
    return s[1:] if s.startswith("-") and float(s) == 0.0 else s


def sci(x, digits: int = 1) -> str:
    """A number as ``m \\times 10^{e}`` with ``digits`` decimals in m (math mode)."""
    if x is None or not math.isfinite(x):
        return MISSING
    if x == 0:
        return "0"
    e = int(math.floor(math.log10(abs(x))))
    m = x / 10**e
    if round(abs(m), digits) >= 10:
        m, e = m / 10, e + 1
    return f"{m:.{digits}f} \\times 10^{{{e}}}"


def tex_sci(x, digits: int = 2) -> str:
    """x with ``digits`` significant digits, e.g. ``3.1\\times10^{-14}``; ``\\text{---}`` when not
    reached (the performance tables' form)."""
    if x is None or not math.isfinite(x):
        return r"\text{---}"
    if x == 0:
        return "0"
    e = math.floor(math.log10(abs(x)))
    m = x / 10**e
    if round(m, digits - 1) >= 10:
        m, e = m / 10, e + 1
    return rf"{m:.{digits - 1}f}\times10^{{{e}}}"


def tex_time(seconds) -> str:
    """A CPU time with a unit suited to its size (text mode), ``---`` when not reached."""
    if seconds is None or not math.isfinite(seconds):
        return "---"
    if seconds < 1e-3:
        return rf"{seconds * 1e6:.0f}\,\textmu s"
    if seconds < 1.0:
        return rf"{seconds * 1e3:.3g}\,ms"
    return rf"{seconds:.3g}\,s"


def tex_escape(text: str) -> str:
    """Escape LaTeX specials outside ``$...$`` (math passes through)."""
    out, math_mode = [], False
    for ch in text:
        if ch == "$":
            math_mode = not math_mode
            out.append(ch)
        elif not math_mode and ch in "&%#_":
            out.append("\\" + ch)
        elif not math_mode and ch == "^":
            out.append(r"\textasciicircum{}")
        else:
            out.append(ch)
    return "".join(out)
