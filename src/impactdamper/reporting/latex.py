"""Numbers and text for the report: ``\\newcommand`` macros and number formats.

Every number in the report reaches LaTeX through a macro file a workflow stage writes with
these helpers; nothing in ``paper/`` is typed by hand.
"""

from __future__ import annotations

import math
import re

__all__ = [
    "MISSING",
    "macro",
    "camel",
    "fixed",
    "sci",
    "tex_sci",
    "tex_time",
    "tex_escape",
    "plain_text",
    "MacroFile",
    "render_macros",
    "macro_texts",
]

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


def tex_sci(
    x, digits: int = 2, *, missing: str = r"\text{---}", powers_of_ten: bool = False, round_up: bool = False
) -> str:
    """x with ``digits`` significant digits, e.g. ``3.1\\times10^{-14}`` (math mode);
    ``missing`` when None or not finite (not reached, in the performance tables); with
    ``powers_of_ten`` an exact power of ten as ``10^{-9}`` (a tolerance, in the sweep's macros);
    with ``round_up`` the magnitude rounded up, never down (a bound the data must not exceed:
    1.25e-10 as 1.3e-10, never 1.2e-10)."""
    if x is None or not math.isfinite(x):
        return missing
    if x == 0:
        return "0"
    e = math.floor(math.log10(abs(x)))
    m = abs(x) / 10**e
    if round_up:
        scale = 10 ** (digits - 1)
        # The smallest m' >= m with digits - 1 decimals (a relative 1e-12 absorbs the division's rounding).
        m = math.ceil(m * scale * (1 - 1e-12)) / scale
    if round(m, digits - 1) >= 10:
        m, e = m / 10, e + 1
    sign = "-" if x < 0 else ""
    if powers_of_ten and abs(m - 1.0) < 1e-12:
        return f"{sign}10^{{{e}}}"
    return rf"{sign}{m:.{digits - 1}f}\times10^{{{e}}}"


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


def plain_text(tex: str) -> str:
    """A macro's value as plain text for the README (Markdown): the math markup our formatters
    write (``\\times 10^{e}``, ``\\,``, ``\\textmu``, ``$\\to$``, :data:`MISSING`) as text.
    Applied once, when a stage records its macros (:class:`MacroFile`), never to a TeX file."""
    text = tex.replace(r"\ensuremath", "").replace(r"\,", " ").replace(r"\textmu ", "µ").replace(r"\textmu", "µ")
    text = re.sub(r"\s*\\times\s*10\^\{([-0-9]+)\}", r"e\1", text)
    text = (
        text.replace(r"$\to$", "->")
        .replace(r"$\times$", "x")
        .replace(MISSING, "–")
        .replace("--", "–")
        .replace("{", "")
        .replace("}", "")
        .replace("\\", "")
    )
    return re.sub(r"\s+", " ", text).strip()


class MacroFile:
    """The macros of one report stage, in order, with its comment lines.

    A stage adds its numbers here (:meth:`add`, :meth:`append` for a comment line) and writes
    :meth:`record` as its one JSON record; the TeX macro file (:func:`render_macros`) and the
    README summary (:func:`macro_texts`) are both rendered from that record, so that nothing
    reads a number back out of TeX.
    """

    def __init__(self, lines=()):
        """``lines``: the first lines, each a comment line (str) or a macro ((name, value))."""
        self.entries: list[dict] = []
        self.extend(lines)

    def extend(self, lines) -> None:
        """Lines in order, each a comment line (str) or a macro ((name, value), or (name, value,
        text) with its README text)."""
        for line in lines:
            if isinstance(line, tuple):
                self.add(*line)
            else:
                self.append(line)

    def append(self, line: str) -> None:
        """A line of the file that is not a macro (a comment), without its newline."""
        self.entries.append({"line": line[:-1] if line.endswith("\n") else line})

    def add(self, name: str, value, text: str | None = None) -> None:
        """One macro: ``value`` as TeX (checked by :func:`macro`) and as plain text (``text``, or
        :func:`plain_text` of the TeX where not given)."""
        macro(name, value)
        self.entries.append({"name": name, "tex": str(value), "text": plain_text(str(value)) if text is None else text})

    def record(self, what: str) -> dict:
        """The JSON record: what the macros are (``what``) and the entries in file order."""
        return {"what": what, "entries": list(self.entries)}

    def tex(self) -> str:
        """The TeX macro file (as :func:`render_macros` renders the record)."""
        return render_macros(self.record(""))


def render_macros(record: dict) -> str:
    """The TeX macro file of a record written from a :class:`MacroFile`."""
    return "".join((macro(e["name"], e["tex"]) if "name" in e else e["line"]) + "\n" for e in record["entries"])


def macro_texts(*records: dict) -> dict[str, str]:
    """The macros of the records by name, as plain text (for the README summary)."""
    return {e["name"]: e["text"] for record in records for e in record["entries"] if "name" in e}
