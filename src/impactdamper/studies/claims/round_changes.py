"""The stated set with one parameter (or, if no single one reproduces, two) at a round value:
the values that differ from the stated one in one significant digit, both of the paper's Fig. 2
claims at each, and which of them keep the paper's tuning.

Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100 state the
reference case to one or two significant digits: a slip of one digit is the nearest change a
reader would suspect. :func:`round_candidates` lists, per parameter, the values that differ
from the stated one in one significant digit (a digit replaced, or one unit of the last stated
digit up or down: 1 -> 0.9); :func:`round_values` evaluates them alone, then pairs only if no
single change reproduces (:class:`~impactdamper.studies.claims.claims_evaluator.ClaimsEvaluator`).
"""

from __future__ import annotations

from decimal import Decimal

import numpy as np

from impactdamper.studies.claims.claims_evaluator import NEAREST_NAMES, ClaimsEvaluator, norm, robust

__all__ = [
    "round_values",
]


# --- round values -------------------------------------------------------------------------
def _round_candidates(name: str, stated: float, lo: float, hi: float) -> list[float]:
    """Values of ``name`` that differ from ``stated`` (as the paper writes it, e.g. 0.08, -5.8)
    in one significant digit, within [lo, hi]: one digit replaced by another (a leading digit
    by a non-zero one), or one unit of the last stated digit up or down (a lone 1 read as 1.0:
    0.9 and 1.1)."""
    d = Decimal(repr(float(stated))).normalize()
    sign, digits, exp = d.as_tuple()
    out = set()
    for i in range(len(digits)):
        for r in range(10):
            if r == digits[i] or (i == 0 and r == 0):
                continue
            new = list(digits)
            new[i] = r
            out.add(float(Decimal((sign, tuple(new), exp))))
    unit = float(Decimal((0, (1,), exp)))
    # One unit of the last digit up and down; a lone 1 is also read as written 1.0 (the
    # paper's theta), whose neighbours are 0.9 and 1.1.
    steps = (unit, -unit) + ((unit / 10.0, -unit / 10.0) if digits == (1,) else ())
    for v in (float(d) + st for st in steps):
        if v != 0:
            out.add(float(Decimal(repr(round(v, 12))).normalize()))
    return sorted(v for v in out if lo <= v <= hi and v != float(stated))


def round_values(ev: ClaimsEvaluator, ranges: dict, margin: float) -> dict:
    """The stated set with one parameter at a round value (:func:`round_candidates`, within
    ``ranges[name] = (lo, hi)``), both claims evaluated at each; pairs of changes only if no
    single one reproduces. Each reproducing candidate also gets the robustness test
    (:func:`robust`, ``margin``).

    Returns
    -------
    dict
        ``candidates`` (count), ``changed`` (how many parameters changed in the answer),
        ``reproducing``: list of {``changes``, ``u``, ``distance`` (both norms), ``robust``},
        nearest (max-norm) first.
    """
    stated = ev.stated
    singles = []
    for j, n in enumerate(NEAREST_NAMES):
        lo, hi = ranges[n]
        for v in _round_candidates(n, stated[j], lo, hi):
            u = np.zeros(len(NEAREST_NAMES))
            u[j] = v / stated[j] - 1.0
            singles.append(({n: v}, u))
    sets, changed = singles, 1
    flags = ev.both(np.array([u for _, u in sets]))
    if not flags.any():
        pairs = []
        for a in range(len(singles)):
            for b in range(a + 1, len(singles)):
                (ca, ua), (cb, ub) = singles[a], singles[b]
                if set(ca) & set(cb):
                    continue
                pairs.append(({**ca, **cb}, ua + ub))
        sets, changed = pairs, 2
        flags = ev.both(np.array([u for _, u in sets])) if sets else np.zeros(0, bool)
    rep = [(c, u) for (c, u), f in zip(sets, flags) if f]
    rob = robust(ev, np.array([u for _, u in rep]), margin) if rep else np.zeros(0, bool)
    rows = [
        {
            "changes": c,
            "u": dict(zip(NEAREST_NAMES, map(float, u))),
            "distance": {"max": float(norm(u, "max")), "euclidean": float(norm(u, "euclidean"))},
            "robust": bool(r),
            "keeps_tuning_condition": _tuning_condition(c),
        }
        for (c, u), r in zip(rep, rob)
    ]
    rows.sort(key=lambda r: (r["distance"]["max"], sorted(r["changes"])))
    return {"candidates": len(sets), "changed": changed if rows else None, "reproducing": rows}


def _tuning_condition(changes: dict) -> bool:
    """Whether a change keeps the paper's tuning 2 sqrt(c2/m2) = sqrt(c1/m1) = omega, i.e.
    N = omega2/omega1 = 1/2 and theta = omega/omega1 = 1 (the paper's choice of the reference
    case): true when neither theta nor N is changed."""
    return not ({"theta", "N"} & set(changes))
