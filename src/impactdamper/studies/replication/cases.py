"""The reference case's replication: the cases solved by both algorithms, their records, and the
scans of one parameter (grids, ranges where a claim holds, their overlaps).

The paper is Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100.
The two claims about the reference case (the prose around Fig. 2):

* **(a)** Algorithm No. 1 gives an orbit whose gap is negative on an interval (t1, t2);
* **(b)** Algorithm No. 2 settles to T_c = 2T with three impacts per cycle (t1, t2, t3; the
  next cycle starts at t4).

The workflow's reference stage (``workflow/scripts/solve_case.py``, ``crosscheck_case.py``,
``gap_scan.py``, ``other_readings.py``, ``verdict.py``) calls these and writes the records; the
claims themselves are :mod:`impactdamper.studies.replication.claims`, the independent
``solve_ivp`` cross-checks :mod:`impactdamper.studies.replication.crosscheck`.
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper import Parameters, algorithm1, steady_state
from impactdamper.studies.config import parameters, steady_options
from impactdamper.studies.intervals import true_intervals
from impactdamper.studies.replication.claims import CLAIM_B_IMPACTS, CLAIM_B_PERIOD_MULTIPLE, claim_a, claim_b

__all__ = [
    "PAPER",
    "CASES",
    "SAMPLES_PER_PERIOD",
    "CLAIM_B_IMPACTS",
    "CLAIM_B_PERIOD_MULTIPLE",
    "claim_a",
    "claim_b",
    "parameters",
    "solver_options",
    "alg1_summary",
    "steady_summary",
    "grid",
    "ranges",
    "overlap",
    "run_steady",
    "run_alg1",
]

PAPER = "Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100"
CASES = ("stated", "located")
# Samples per forcing period of the curves behind Fig. 2a/2b (dense enough that a straight
# line between samples is within ~1e-4 x_st of the exact motion at the plot's scale).
SAMPLES_PER_PERIOD = 400

# The solver options are the config module's; the stage's scripts know them by this name.
solver_options = steady_options


# --- cases ----------------------------------------------------------------------------------
def _next_cycle_impact(s):
    """The first impact of the next repetition of the settled cycle (the paper's t4), or None."""
    T = s.p.T
    t_next = s.cycle_start + s.cycle_duration - 1e-9 * T
    later = s.trajectory.impacts(t_next)
    return later[0] if later else None


def alg1_summary(a) -> dict:
    """Algorithm No. 1 result as a JSON-ready dict, with the claim (a) verdict."""
    d = a.to_dict()
    d["claim_a"] = claim_a(a)
    return d


def steady_summary(s) -> dict:
    """Settled motion as a JSON-ready dict: the cycle's impacts with times since the cycle's
    first impact (s and T), and the next cycle's first impact."""
    p = s.p
    d = s.to_dict()
    start = s.cycle_start
    rows = [
        {
            "label": f"t{i + 1}",
            "t_s": imp.t - start,
            "t_over_T": (imp.t - start) / p.T,
            "phase": imp.phase,
            "velocity": imp.velocity,
            "impulse": imp.impulse,
            "next_cycle": False,
        }
        for i, imp in enumerate(s.impacts)
    ]
    nxt = _next_cycle_impact(s)
    if nxt is not None and s.settled and s.impacts:
        rows.append(
            {
                "label": f"t{len(rows) + 1}",
                "t_s": nxt.t - start,
                "t_over_T": (nxt.t - start) / p.T,
                "phase": (nxt.t / p.T) % 1.0,
                "velocity": nxt.velocity,
                "impulse": nxt.impulse,
                "next_cycle": True,
            }
        )
    d["impact_table"] = rows
    d["cycle_start"] = start
    d["T_c_over_T"] = s.period_multiple
    d["claim_b"] = claim_b(s)
    return d


# --- scans: grids, ranges and their ends ------------------------------------------------
def grid(lo: float, hi: float, step: float) -> np.ndarray:
    """lo, lo + step, ..., up to hi (inclusive within rounding), rounded to 10 decimals."""
    n = int(math.floor((hi - lo) / step + 1e-9))
    return np.round(lo + step * np.arange(n + 1), 10)


def ranges(gaps: np.ndarray, flags: list[bool], pred, tol: float) -> list[dict]:
    """Maximal runs of True on the grid, each end bisected to ``tol`` (absolute) or open at
    the window's edge (:func:`impactdamper.studies.intervals.true_intervals`), as dicts."""
    out = []
    for iv in true_intervals(gaps, flags, pred, 0.0, 0.0, abs_tol=tol):
        # The run's first and last grid values: a bisected end lies between grid values.
        r = {"grid_lo": float(min(g for g in gaps if g >= iv.lo)), "grid_hi": float(max(g for g in gaps if g <= iv.hi))}
        for side, bracket, is_open in (("lo", iv.lo_bracket, iv.lo_open), ("hi", iv.hi_bracket, iv.hi_open)):
            r[side] = getattr(iv, side)
            r[side + "_bracket"] = list(bracket) if bracket is not None else None
            r[side + "_open"] = is_open  # True: the range reaches the window's edge
        out.append(r)
    return out


def overlap(ra: list[dict], rb: list[dict]) -> list[dict]:
    """Intersections of two lists of ranges; each end says which claim bounds it."""
    out = []
    for a in ra:
        for b in rb:
            lo_src = a if a["lo"] >= b["lo"] else b
            hi_src = a if a["hi"] <= b["hi"] else b
            lo, hi = lo_src["lo"], hi_src["hi"]
            if lo < hi:
                out.append(
                    {
                        "lo": lo,
                        "hi": hi,
                        "lo_claim": "a" if lo_src is a else "b",
                        "hi_claim": "a" if hi_src is a else "b",
                        "lo_bracket": lo_src["lo_bracket"],
                        "hi_bracket": hi_src["hi_bracket"],
                        "lo_open": lo_src["lo_open"],
                        "hi_open": hi_src["hi_open"],
                    }
                )
    return out


def run_steady(p: Parameters, solver: dict, **kw):
    """:func:`impactdamper.steady_state` (the front door, its default backend: compiled) with the
    config's solver options."""
    return steady_state(p, **solver_options(solver), **kw)


def run_alg1(p: Parameters, solver: dict):
    return algorithm1(p, gap_tol=float(solver["gap_tol"]))
