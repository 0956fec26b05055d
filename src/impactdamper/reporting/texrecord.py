"""A stage's records rendered into TeX from a declaration: which value each macro shows and in
what format, and the columns of each table.

Every report stage of the workflow declares, in its room's ``record`` module
(``impactdamper.studies.<room>.record``), its macros as :class:`Macro` rows (a name, where the
value is in the stage's records, a number format) and its booktabs tables as :class:`Table`
(the column spec, the header, a :class:`Column` per cell); :func:`macro_lines` reads the
values and formats them into the lines of the stage's
:class:`~impactdamper.reporting.latex.MacroFile` (its one JSON record, from which the TeX macro
file and the README's numbers are rendered), and :meth:`Table.render` writes a table. A value
that does not exist (``None``, not finite, or a macro's ``when`` false) shows the format's
``missing`` text, never a number.

Formats are callables ``value -> TeX``: :func:`fixed`, :func:`sci`, :func:`tex_sci`,
:func:`percent`, :func:`bound` (rounded up), :func:`general` (a Python format string), :func:`time`, and the words
:data:`YES_NO`, :data:`COUNT`, :data:`TEXT`, :data:`WORDS`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

from impactdamper.reporting import latex

__all__ = [
    "pick",
    "Format",
    "fixed",
    "percent",
    "sci",
    "tex_sci",
    "bound",
    "general",
    "time",
    "YES_NO",
    "COUNT",
    "TEXT",
    "WORDS",
    "Macro",
    "macros_named_by_path",
    "macro_lines",
    "Column",
    "fixed_columns",
    "Table",
    "MIDRULE",
]

# Where a value is: a dotted path into the source ("algorithm1.impact_phase", "rows.0.lo"; a
# part ending in "?" may be absent, giving None), or a function of the source.
Getter = str | Callable[[Any], Any]


def pick(source, where: Getter):
    """The value ``where`` (a :data:`Getter`) of ``source``: a missing dict key or list index is
    an error unless its part of the path ends in ``?`` (then None); a part of a None is None."""
    if callable(where):
        return where(source)
    value = source
    for part in where.split("."):
        optional = part.endswith("?")
        part = part.rstrip("?")
        if value is None:
            return None
        try:
            value = value[int(part)] if isinstance(value, (list, tuple)) else value[part]
        except (KeyError, IndexError):
            if not optional:
                raise
            return None
    return value


def _absent(x) -> bool:
    return x is None or (isinstance(x, float) and not math.isfinite(x))


@dataclass(frozen=True)
class Format:
    """A number format: ``render(value)`` for a value that exists, ``missing`` for one that does
    not (None or not finite)."""

    render: Callable[[Any], str]
    missing: str = latex.MISSING

    def __call__(self, value) -> str:
        return self.missing if _absent(value) else self.render(value)


def fixed(digits: int, missing: str = latex.MISSING) -> Format:
    """Fixed decimals (:func:`impactdamper.reporting.latex.fixed`: never ``-0.00``)."""
    return Format(lambda x: latex.fixed(x, digits), missing)


def percent(digits: int, missing: str = latex.MISSING) -> Format:
    """A share as a percentage with fixed decimals (0.123 -> ``12.3``)."""
    return Format(lambda x: latex.fixed(100 * x, digits), missing)


def sci(digits: int = 1, missing: str = latex.MISSING) -> Format:
    """``m \\times 10^{e}`` with ``digits`` decimals in m (:func:`impactdamper.reporting.latex.sci`)."""
    return Format(lambda x: latex.sci(x, digits), missing)


def tex_sci(
    digits: int = 2, missing: str = r"\text{---}", *, powers_of_ten: bool = False, math_mode: bool = False
) -> Format:
    """``digits`` significant digits as ``3.1\\times10^{-14}``
    (:func:`impactdamper.reporting.latex.tex_sci`); ``math_mode`` wraps it in ``\\ensuremath``
    for a macro used in text and math."""

    def render(x) -> str:
        return latex.tex_sci(x, digits, powers_of_ten=powers_of_ten)

    if math_mode:
        return Format(lambda x: rf"\ensuremath{{{render(x)}}}", rf"\ensuremath{{{missing}}}")
    return Format(render, missing)


def bound(digits: int = 2, missing: str = r"\text{---}") -> Format:
    """An upper bound: ``digits`` significant digits as ``1.3\\times10^{-10}``, the magnitude
    rounded up, so that "at most" the value holds for every number it bounds
    (:func:`impactdamper.reporting.latex.tex_sci` with ``round_up``)."""
    return Format(lambda x: latex.tex_sci(x, digits, round_up=True), missing)


def general(spec: str, missing: str = latex.MISSING) -> Format:
    """A Python format string, ``"{:g}"``, ``"{:.4f}"``."""
    return Format(spec.format, missing)


def time(missing: str = "---") -> Format:
    """A CPU time with a unit suited to its size (:func:`impactdamper.reporting.latex.tex_time`)."""
    return Format(latex.tex_time, missing)


# Words: a flag as yes/no, a count as an integer, text as it is, a code name (multi_impact) as
# words.
YES_NO = Format(lambda b: "yes" if b else "no", "no")
COUNT = Format(lambda n: str(int(n)))
TEXT = Format(str)
WORDS = Format(lambda s: str(s).replace("_", " "))


@dataclass(frozen=True)
class Macro:
    """One macro of a stage's record.

    Attributes
    ----------
    name : str
        The macro's name (letters only), after the prefix :func:`macro_lines` is given.
    value : Getter
        Where its value is in the source (:func:`pick`).
    format : callable
        Value to TeX (:class:`Format`, or any callable).
    when : Getter, optional
        The value exists only where this is true (else the format's ``missing``).
    text : Getter, optional
        Its README text, where the plain form of the TeX (:func:`impactdamper.reporting.latex.plain_text`)
        would not read (a list of TeX symbols).
    """

    name: str
    value: Getter
    format: Callable[[Any], str] = TEXT
    when: Getter | None = None
    text: Getter | None = None


def macros_named_by_path(prefix: str, paths: Iterable[str], format: Callable[[Any], str] = TEXT, root: str = ""):
    """A :class:`Macro` per path of ``paths``, all in ``format``: its value at ``root`` + the path
    (:func:`pick`), its name ``prefix`` + the path in CamelCase (``check.next_to_change?`` ->
    ``CheckNextToChange``), for the runs of macros named after where their values are."""
    return tuple(Macro(prefix + _camel_case(path), root + path, format) for path in paths)


def _camel_case(path: str) -> str:
    """``check.next_to_change?`` -> ``CheckNextToChange``: a record path as part of a macro name."""
    return "".join(word.capitalize() for word in path.rstrip("?").replace(".", "_").split("_"))


def macro_lines(spec: Iterable[Macro | str], source, prefix: str = "", **parts: str) -> list:
    """The lines of a :class:`~impactdamper.reporting.latex.MacroFile` for ``spec`` read from
    ``source``: ``(name, tex)`` per :class:`Macro` (``(name, tex, text)`` where it has its own
    text), a comment line per str. Each name is ``prefix`` + the macro's name with its ``{}``
    fields filled from ``parts`` (``"Orbit{case}Gap"``, ``case="Stated"``)."""
    out = []
    for m in spec:
        if isinstance(m, str):
            out.append(m)
            continue
        name = prefix + m.name.format(**parts)
        if m.when is not None and not pick(source, m.when):
            tex = m.format.missing if isinstance(m.format, Format) else latex.MISSING
        else:
            tex = m.format(pick(source, m.value))
        out.append((name, tex) if m.text is None else (name, tex, pick(source, m.text)))
    return out


@dataclass(frozen=True)
class Column:
    """A table's cell in each row: where its value is in the row (:func:`pick`) and its format."""

    value: Getter
    format: Callable[[Any], str] = TEXT


def fixed_columns(digits: dict[str, int]) -> list[Column]:
    """A :class:`Column` per key of ``digits`` (where its value is in the row, :func:`pick`),
    its number in :func:`fixed` point with the key's digits."""
    return [Column(key, fixed(d)) for key, d in digits.items()]


# A rule between rows of a table's body.
MIDRULE = r"\midrule"


@dataclass(frozen=True)
class Table:
    """A booktabs table.

    Attributes
    ----------
    colspec : str
        The tabular's column spec, ``"lrllllr"``.
    header : str
        The header row, without its ``\\\\``.
    columns : sequence of Column
        The cells of a row given as a dict (rows may also be lists of cells, or lines as they are).
    comments : sequence of str
        The file's first lines, each a TeX comment without its ``%``.
    header_rule : bool
        A ``\\midrule`` under the header (False where the body starts with its own).
    """

    colspec: str
    header: str
    columns: Sequence[Column] = ()
    comments: Sequence[str] = ()
    header_rule: bool = True

    def cells(self, row: dict, count: int | None = None) -> list[str]:
        """The cells of a row given as a dict, through the first ``count`` columns (all)."""
        return [c.format(pick(row, c.value)) for c in self.columns[:count]]

    def row(self, row) -> str:
        """One body line: a dict through the columns, a list of cells joined, a str as it is."""
        if isinstance(row, str):
            return row
        return " & ".join(self.cells(row) if isinstance(row, dict) else list(row)) + r" \\"

    def render(self, rows: Iterable, after: Sequence[str] = ()) -> str:
        """The table's TeX file: comments, ``\\begin{tabular}``, the header, the rows, the end,
        and the lines ``after`` it (notes)."""
        lines = ["% " + c if c else "%" for c in self.comments]
        lines += [rf"\begin{{tabular}}{{{self.colspec}}}", r"\toprule", self.header + r" \\"]
        lines += [MIDRULE] if self.header_rule else []
        lines += [self.row(r) for r in rows]
        lines += [r"\bottomrule", r"\end{tabular}", *after]
        return "\n".join(lines) + "\n"
