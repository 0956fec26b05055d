"""How the studies' records, tables and figures name a parameter: its row of the one parameter
table (:data:`impactdamper.core.parameters.PARAMETER_TABLE`: symbol, macro-name part, plain
name, axis label), looked up by name.

The parameters are those of Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI
10.18698/0236-3941-2019-1-90-100, in relative form (theta, mu, N, delta1, delta2, R,
Delta0/x_st) and the free scales; no symbol or name is spelled out anywhere else.
"""

from __future__ import annotations

from impactdamper.core.parameters import PARAMETER_TABLE

__all__ = ["SPEC", "tex"]

# Each parameter's row of the table, by name.
SPEC = {s.name: s for s in PARAMETER_TABLE}


def tex(name: str) -> str:
    """The parameter's symbol in inline math: ``$\\theta$``."""
    return f"${SPEC[name].symbol}$"
