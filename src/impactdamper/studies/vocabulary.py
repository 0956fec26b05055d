"""How the studies' records, tables and figures name a parameter: its row of the one parameter
table (:data:`impactdamper.core.parameters.PARAMETER_TABLE`: symbol, macro-name part, plain
name, axis label), looked up by name, and its plain name with the Greek letters written out
(the README's ``θ``, ``Δ0/x_st``).

The parameters are those of Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI
10.18698/0236-3941-2019-1-90-100, in relative form (theta, mu, N, delta1, delta2, R,
Delta0/x_st) and the free scales; no symbol or name is spelled out anywhere else.
"""

from __future__ import annotations

import re
import unicodedata

from impactdamper.core.parameters import PARAMETER_TABLE

__all__ = ["SPEC", "UNICODE", "GAP_AXIS_LABEL", "tex"]

# Each parameter's row of the table, by name.
SPEC = {s.name: s for s in PARAMETER_TABLE}


def _greek(plain: str) -> str:
    """``plain`` with each word that names a Greek letter written as the letter (``Delta0/x_st``
    -> ``Δ0/x_st``, ``delta1`` -> ``δ1``); other words as they are."""

    def letter(word: re.Match) -> str:
        case = "CAPITAL" if word[0][0].isupper() else "SMALL"
        try:
            return unicodedata.lookup(f"GREEK {case} LETTER {word[0].upper()}")
        except KeyError:
            return word[0]

    return re.sub(r"[A-Za-z]{2,}", letter, plain)


# The gap's axis label where a figure has room to name it (the table's long label).
GAP_AXIS_LABEL = SPEC["gap"].long_label
# Each parameter's plain name in Unicode (the README's tables), by name.
UNICODE = {s.name: _greek(s.plain) for s in PARAMETER_TABLE}


def tex(name: str) -> str:
    """The parameter's symbol (its row's ``symbol``) in inline math, between dollars."""
    return f"${SPEC[name].symbol}$"
