"""The paper's claims about its Fig. 2, the aligned comparison of two settled cycles, and where
the claims hold along one parameter.

Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100, say of
the reference case (Delta0/x_st = -5.8, the prose around the paper's Fig. 2):

* **(a)** Algorithm No. 1 (eqs. 7-17) gives an orbit whose gap is negative on an interval
  (t1, t2) (the paper's Fig. 2a);
* **(b)** Algorithm No. 2, run from its step 1 until the motion settles, gives T_c = 2T with
  three impacts t1, t2, t3 per cycle (the paper's Fig. 2b).

:func:`compare_cycles` compares two settled cycles of the same motion computed by different
methods (the exact solver and an independent integrator): the cycles are aligned by forcing
phase (the same period multiple k, impacts matched by t/T modulo k, over the k shifts by a
whole period), and "agree" means the measured time and velocity differences are below stated
tolerances. :func:`claim_intervals` finds, along one parameter with the others fixed, the
intervals where each claim holds: a grid, then every end of a run bisected to a relative
tolerance.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from collections.abc import Callable, Sequence

from impactdamper.core.algorithm1 import algorithm1
from impactdamper.analysis.solve import steady_state

__all__ = [
    "CLAIM_B_PERIOD_MULTIPLE",
    "CLAIM_B_IMPACTS",
    "claim_a",
    "claim_b",
    "CycleComparison",
    "compare_cycles",
    "Interval",
    "true_runs",
    "true_intervals",
    "intersect",
    "claim_intervals",
    "distance_to",
    "SEARCH_PARAMETERS",
    "SEARCH_SYMBOLS",
    "nearest_both",
    "reference_check",
    "check_rows",
    "refine_grid",
    "batch_rows",
    "search_parameter",
    "MAP_COLUMNS",
    "claims_map",
    "count_end_checks",
]

# Claim (b): the paper's Fig. 2b motion, T_c = 2T with three impacts per cycle.
CLAIM_B_PERIOD_MULTIPLE = 2
CLAIM_B_IMPACTS = 3


def claim_a(alg1) -> bool:
    """Claim (a) for an :class:`~impactdamper.Algorithm1Result`: the orbit exists (eq. 17 has
    a root) and its gap is negative somewhere between impacts."""
    return bool(alg1.exists and alg1.negative_gap_intervals)


def claim_b(steady) -> bool:
    """Claim (b) for a :class:`~impactdamper.SteadyState`: T_c = 2T, three impacts, no
    persistent contact in the cycle."""
    return bool(
        steady.regime == "multi_impact"
        and steady.period_multiple == CLAIM_B_PERIOD_MULTIPLE
        and steady.impacts_per_cycle == CLAIM_B_IMPACTS
    )


# --- the aligned cross-check of two settled cycles ------------------------------------------
@dataclass(frozen=True)
class CycleComparison:
    """Two settled cycles compared impact by impact, aligned by forcing phase.

    Attributes
    ----------
    period_multiple : (int, int)
        k of each cycle (T_c = k T; 0 when a motion did not settle).
    impacts : (int, int)
        Impacts per cycle of each.
    matched : int
        Impacts paired one to one (all of them when the cycles agree).
    shift_periods : int
        Whole periods added to the first cycle's times to align it with the second.
    max_time_difference_over_T : float
        Largest |t_a - t_b|/T over the pairs (inf when the cycles cannot be paired).
    max_velocity_difference_rel : float
        Largest |v_a - v_b|/(x_st omega) of the closing velocities (inf when not paired).
    time_tol, velocity_tol : float
        The tolerances "agree" is measured against.
    agree : bool
        Same k, same number of impacts, every impact paired, both differences within tolerance.
    reason : str
        Why they do not agree ("" when they do).
    """

    period_multiple: tuple
    impacts: tuple
    matched: int
    shift_periods: int
    max_time_difference_over_T: float
    max_velocity_difference_rel: float
    time_tol: float
    velocity_tol: float
    agree: bool
    reason: str
    pairs: list = field(default_factory=list)

    def to_dict(self) -> dict:
        return asdict(self)


def _circular(d: float, k: int) -> float:
    """d modulo k folded into [-k/2, k/2)."""
    return (d + 0.5 * k) % k - 0.5 * k


def compare_cycles(
    a: Sequence, k_a: int, b: Sequence, k_b: int, T: float, velocity_scale: float, time_tol: float, velocity_tol: float
) -> CycleComparison:
    """Compare settled cycle ``a`` (impacts with ``.t`` in s and ``.velocity`` in m/s, or
    ``(t, velocity)`` pairs) with cycle ``b``.

    The two runs may use different clocks that differ by whole forcing periods (the exact
    solver rebases its clock, and describes the cycle on a fresh run), so an impact is placed
    by u = t/T modulo k, its forcing phase within the cycle. For each shift j = 0..k-1 the
    impacts of ``a`` at u + j are paired with the nearest impacts of ``b``; the shift with the
    smallest largest difference is kept. A pairing that is not one to one, a different k or a
    different number of impacts is a disagreement, never compared by counts alone.

    Parameters
    ----------
    a, b : sequence of impacts, each ``.t``/``.velocity`` or ``(t, velocity)``
    k_a, k_b : int
        Period multiples (T_c = k T) of the two cycles.
    T : float
        Forcing period, s.
    velocity_scale : float
        x_st omega, m/s: velocity differences are relative to it.
    time_tol : float
        Largest time difference that agrees, units of T.
    velocity_tol : float
        Largest velocity difference that agrees, relative to ``velocity_scale``.
    """
    for name, v in (
        ("T", T),
        ("velocity_scale", velocity_scale),
        ("time_tol", time_tol),
        ("velocity_tol", velocity_tol),
    ):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"`{name}` = {v!r} is not allowed: must be a positive finite number")
    ta = [(float(i[0]), float(i[1])) if isinstance(i, (tuple, list)) else (float(i.t), float(i.velocity)) for i in a]
    tb = [(float(i[0]), float(i[1])) if isinstance(i, (tuple, list)) else (float(i.t), float(i.velocity)) for i in b]
    counts, ks = (len(ta), len(tb)), (int(k_a), int(k_b))

    def fail(reason: str) -> CycleComparison:
        return CycleComparison(ks, counts, 0, 0, math.inf, math.inf, time_tol, velocity_tol, False, reason)

    if k_a < 1 or k_b < 1:
        return fail("a motion did not settle (k = 0)")
    if k_a != k_b:
        return fail(f"different period multiples: k = {k_a} and {k_b}")
    if not ta and not tb:
        return CycleComparison(ks, counts, 0, 0, 0.0, 0.0, time_tol, velocity_tol, True, "", [])
    k = k_a
    ua = [((t / T) % k, v) for t, v in ta]
    ub = [((t / T) % k, v) for t, v in tb]
    best = None
    for j in range(k):
        pairs, used = [], set()
        for u, v in ua:
            m = min(range(len(ub)), key=lambda i: abs(_circular(ub[i][0] - (u + j), k))) if ub else None
            if m is None or m in used:
                pairs = None
                break
            used.add(m)
            pairs.append((abs(_circular(ub[m][0] - (u + j), k)), abs(ub[m][1] - v) / velocity_scale))
        if pairs is None:
            continue
        worst = max(p[0] for p in pairs)
        if best is None or worst < best[0]:
            best = (worst, j, pairs)
    if counts[0] != counts[1]:
        # Report how far apart the paired ones are, but a missing impact never agrees.
        extra = f"; the {min(counts)} paired differ by up to {best[0]:.1e} T" if best else ""
        return fail(f"different impact counts: {counts[0]} and {counts[1]} per cycle{extra}")
    if best is None:
        return fail("the impacts cannot be paired one to one")
    worst_t, j, pairs = best
    worst_v = max(p[1] for p in pairs)
    ok = worst_t <= time_tol and worst_v <= velocity_tol
    reason = (
        ""
        if ok
        else (
            f"time difference {worst_t:.1e} T > {time_tol:.0e}"
            if worst_t > time_tol
            else f"velocity difference {worst_v:.1e} > {velocity_tol:.0e}"
        )
    )
    return CycleComparison(
        ks, counts, len(pairs), j, worst_t, worst_v, time_tol, velocity_tol, ok, reason, [list(p) for p in pairs]
    )


# --- where a claim holds along one parameter ------------------------------------------------
@dataclass(frozen=True)
class Interval:
    """A run of parameter values where a predicate holds.

    ``lo``/``hi`` are the ends (the midpoint of the final bracket, or the window's edge when
    ``lo_open``/``hi_open``: the run reaches the searched range's end); ``lo_bracket`` and
    ``hi_bracket`` are (inside, outside) values from the bisection (None at an open end).
    """

    lo: float
    hi: float
    lo_open: bool
    hi_open: bool
    lo_bracket: tuple | None
    hi_bracket: tuple | None

    @property
    def width(self) -> float:
        return self.hi - self.lo

    def to_dict(self) -> dict:
        return asdict(self)


def _resolution(x: float, rel_tol: float, floor: float, abs_tol: float | None = None) -> float:
    """Bisection stops at a bracket this wide: ``abs_tol`` when given, else ``rel_tol``
    relative to the value, with an absolute floor ``rel_tol * floor`` for ends near zero
    (damping, R)."""
    return abs_tol if abs_tol is not None else rel_tol * max(abs(x), floor)


def bisect(
    pred: Callable[[float], bool], x_in: float, x_out: float, rel_tol: float, floor: float, abs_tol: float | None = None
) -> tuple:
    """Shrink [x_in, x_out] (pred True at x_in, False at x_out) until its width is within
    ``rel_tol`` of the end's value, or ``abs_tol`` (see :func:`_resolution`)."""
    while abs(x_out - x_in) > _resolution(0.5 * (x_in + x_out), rel_tol, floor, abs_tol):
        mid = 0.5 * (x_in + x_out)
        if pred(mid):
            x_in = mid
        else:
            x_out = mid
    return x_in, x_out


def true_runs(flags: Sequence[bool]) -> list[tuple[int, int]]:
    """The maximal runs of True in ``flags``, as (first, last) indices, in order."""
    out, i, n = [], 0, len(flags)
    while i < n:
        if not flags[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and flags[j + 1]:
            j += 1
        out.append((i, j))
        i = j + 1
    return out


def true_intervals(
    xs: Sequence[float],
    flags: Sequence[bool],
    pred: Callable[[float], bool],
    rel_tol: float,
    floor: float,
    abs_tol: float | None = None,
) -> list[Interval]:
    """Maximal runs of True on the grid ``xs`` (increasing), each inner end bisected with
    ``pred`` to ``rel_tol`` (or ``abs_tol``); a run reaching the grid's end is open there. A
    run narrower than the grid step between two False grid points is not seen: the grid sets
    the search's resolution."""
    out, n = [], len(xs)
    for i, j in true_runs(flags):
        ends = {}
        for side, k_in, k_out in (("lo", i, i - 1), ("hi", j, j + 1)):
            if 0 <= k_out < n:
                x_in, x_out = bisect(pred, float(xs[k_in]), float(xs[k_out]), rel_tol, floor, abs_tol)
                ends[side] = (0.5 * (x_in + x_out), False, (x_in, x_out))
            else:
                ends[side] = (float(xs[k_in]), True, None)
        out.append(Interval(ends["lo"][0], ends["hi"][0], ends["lo"][1], ends["hi"][1], ends["lo"][2], ends["hi"][2]))
    return out


def intersect(ra: Sequence[Interval], rb: Sequence[Interval]) -> list[Interval]:
    """Intersections of two lists of intervals (each end taken from the interval bounding it)."""
    out = []
    for a in ra:
        for b in rb:
            lo_src = a if a.lo >= b.lo else b
            hi_src = a if a.hi <= b.hi else b
            if lo_src.lo < hi_src.hi:
                out.append(
                    Interval(lo_src.lo, hi_src.hi, lo_src.lo_open, hi_src.hi_open, lo_src.lo_bracket, hi_src.hi_bracket)
                )
    return out


def claim_intervals(
    xs: Sequence[float],
    claim_a_at: Callable[[float], bool],
    claim_b_at: Callable[[float], bool],
    rel_tol: float,
    floor: float,
    flags_a: Sequence[bool] | None = None,
    flags_b: Sequence[bool] | None = None,
) -> dict:
    """Intervals of ``xs`` (an increasing grid of one parameter) where claim (a), claim (b)
    and both hold; ``claim_*_at(x)`` evaluates a claim at one value (the grid's flags may be
    passed in when already computed). Returns ``{"a": [...], "b": [...], "both": [...]}``."""
    fa = list(flags_a) if flags_a is not None else [claim_a_at(float(x)) for x in xs]
    fb = list(flags_b) if flags_b is not None else [claim_b_at(float(x)) for x in xs]
    ia = true_intervals(xs, fa, claim_a_at, rel_tol, floor)
    ib = true_intervals(xs, fb, claim_b_at, rel_tol, floor)
    return {"a": ia, "b": ib, "both": intersect(ia, ib)}


def distance_to(intervals: Sequence[Interval], x: float) -> tuple[float, float | None]:
    """Distance from ``x`` to the nearest interval, and that interval's nearest point
    (0 and ``x`` itself when ``x`` lies inside one; inf and None when there is none)."""
    best = (math.inf, None)
    for r in intervals:
        nearest = min(max(x, r.lo), r.hi)
        d = abs(nearest - x)
        if d < best[0]:
            best = (d, nearest)
    return best


# --- the claims at one point, and along one parameter ---------------------------------------
def claims_at(p, *, gap_tol: float, steady_kwargs: dict) -> dict:
    """Both claims at parameters ``p``: Algorithm No. 1 (closed form, ``gap_tol``) and
    Algorithm No. 2 from the paper's step 1 run until settled (the compiled
    :func:`impactdamper.steady_state` with its default backend, with ``steady_kwargs``)."""
    a = algorithm1(p, gap_tol=gap_tol)
    s = steady_state(p, **steady_kwargs)
    return {
        "claim_a": claim_a(a),
        "claim_b": claim_b(s),
        "alg1_exists": bool(a.exists),
        "alg1_min_gap": float(a.min_gap) if a.exists else None,
        "regime": s.regime,
        "period_multiple": int(s.period_multiple),
        "impacts_per_cycle": int(s.impacts_per_cycle),
        "periods": int(s.periods),
    }


def refine_grid(
    xs: Sequence[float], rows_at: Callable[[list], list], min_step: float, max_rounds: int = 64
) -> tuple[list[dict], int]:
    """Adaptive refinement of a labelled grid: wherever two neighbours have different labels, or
    either did not settle (``label`` "np"), the midpoint is added, until every such pair is
    ``min_step`` (the floor) apart or less, or ``max_rounds`` rounds were made (halving a
    step reaches the floor when the step is the floor times a power of two). A window (a run of
    one label) wider than ``min_step`` between two neighbours of another label is then seen
    wherever its label differs from theirs or a neighbour does not settle; a window inside a
    run of one settled label, narrower than the initial step, is not (nothing there asks for
    refinement).

    Parameters
    ----------
    xs : sequence of float
        The initial grid, increasing.
    rows_at : callable
        ``rows_at(list_of_x)`` -> list of dict, each with ``value`` and ``label`` (one call per
        round, all the round's new points at once).
    min_step : float
        The floor: pairs closer than this are not split.

    Returns
    -------
    rows : list of dict
        Every point evaluated, in increasing value, each with ``level`` (0: the initial grid,
        n: added in round n).
    rounds : int
        Refinement rounds made.
    """
    if not (isinstance(min_step, (int, float)) and math.isfinite(min_step) and min_step > 0):
        raise ValueError(f"`min_step` = {min_step!r} is not allowed: must be a positive finite number")
    rows = [dict(r, level=0) for r in rows_at([float(x) for x in xs])]
    rounds = 0
    while rounds < max_rounds:
        rows.sort(key=lambda r: r["value"])
        # Midpoints rounded to 12 decimals: the same value as a grid written lo + i h (the motion
        # next to a bifurcation changes with the last bit of a parameter).
        new = [
            round(0.5 * (a["value"] + b["value"]), 12)
            for a, b in zip(rows, rows[1:])
            if (a["label"] != b["label"] or "np" in (a["label"], b["label"]))
            and b["value"] - a["value"] > 1.5 * min_step
        ]  # (1.5: halving reaches min_step despite rounding)
        if not new:
            break
        rounds += 1
        rows += [dict(r, level=rounds) for r in rows_at(new)]
    rows.sort(key=lambda r: r["value"])
    return rows, rounds


def batch_rows(p, name: str, xs: list, settings, longer_periods: int | None = None) -> list[dict]:
    """Algorithm No. 2 from the paper's step 1 at each value of ``name`` (the others as in
    ``p``), on the compiled batch (:func:`impactdamper.steady_states`, each point
    alone, ``settings``: its ``rescue`` tries the Newton rescue on a point that did not
    settle). A point still nonperiodic is run again with ``longer_periods`` (if given).

    Returns
    -------
    list of dict
        ``value``, ``claim_b``, ``regime``, ``period_multiple``, ``impacts_per_cycle``,
        ``periods``, ``label`` (Peterka's z/k, "np" when nonperiodic), ``method``
        (``simulation``, ``rescue`` or ``longer``).
    """
    import dataclasses

    import numpy as np

    from impactdamper import steady_states

    if not xs:
        return []

    def run(values, st):
        r = steady_states(p, (name,), np.array(values, float)[:, None], settings=st, chain=False)
        return [
            {
                "value": float(v),
                "regime": str(rg),
                "period_multiple": int(k),
                "impacts_per_cycle": int(z),
                "periods": int(n),
                "label": str(lb),
                "method": str(m),
                "claim_b": bool(rg == "multi_impact" and k == CLAIM_B_PERIOD_MULTIPLE and z == CLAIM_B_IMPACTS),
            }
            for v, rg, k, z, n, lb, m in zip(
                values, r.regime, r.period_multiple, r.impacts_per_cycle, r.periods, r.label, r.method
            )
        ]

    rows = run(list(xs), settings)
    again = [i for i, r in enumerate(rows) if r["period_multiple"] == 0 and r["regime"] == "nonperiodic"]
    if again and longer_periods:
        st = dataclasses.replace(
            settings, max_periods=int(longer_periods), max_periods_after_nonperiodic=int(longer_periods)
        )
        for i, r in zip(again, run([rows[i]["value"] for i in again], st)):
            if r["period_multiple"] > 0:
                rows[i] = dict(r, method="longer")
            else:
                rows[i]["periods"] = r["periods"]
    return rows


def search_parameter(
    p,
    name: str,
    values: Sequence[float],
    alg1_values: Sequence[float],
    *,
    gap_tol: float,
    steady_kwargs: dict,
    rel_tol: float,
    floor: float,
    log: Callable[[str], None] | None = None,
    refine_floor: float | None = None,
    rescue: bool = True,
    longer_periods: int | None = None,
) -> dict:
    """Where the claims hold along parameter ``name`` (a field of
    :class:`~impactdamper.Parameters`), the others as in ``p``.

    Claim (a) (closed form, cheap) is evaluated on the fine grid ``alg1_values``, claim (b)
    (a settled simulation per point, compiled) on ``values``; every end of a run where a claim holds is
    bisected until its bracket is within ``rel_tol`` relative (absolute ``rel_tol * floor``
    near zero); "both" is the intersection. Returns the grids, their flags and the intervals.

    With ``refine_floor``, claim (b)'s grid runs on the compiled batch
    (:func:`batch_rows`: a nonperiodic point is rescued (``rescue``) or run again with
    ``longer_periods``) and is refined adaptively (:func:`refine_grid`) wherever the settled
    motion's label changes between neighbours or a point does not settle, down to
    ``refine_floor``; the ends are then bisected as above between the refined neighbours.
    """
    if name not in p.names():
        raise ValueError(f"`name` = {name!r} is not allowed: must be one of {', '.join(p.names())}")
    say = log or (lambda msg: None)
    if refine_floor is not None:
        return _search_refined(
            p,
            name,
            values,
            alg1_values,
            gap_tol=gap_tol,
            steady_kwargs=steady_kwargs,
            rel_tol=rel_tol,
            floor=floor,
            say=say,
            refine_floor=refine_floor,
            rescue=rescue,
            longer_periods=longer_periods,
        )

    def pred_a(x: float) -> bool:
        return claim_a(algorithm1(p.replace(**{name: float(x)}), gap_tol=gap_tol))

    rows: dict[float, dict] = {}

    def point_b(x: float) -> dict:
        s = steady_state(p.replace(**{name: float(x)}), **steady_kwargs)
        row = {
            "value": float(x),
            "claim_b": claim_b(s),
            "regime": s.regime,
            "period_multiple": int(s.period_multiple),
            "impacts_per_cycle": int(s.impacts_per_cycle),
            "periods": int(s.periods),
        }
        rows[float(x)] = row
        return row

    def pred_b(x: float) -> bool:
        return point_b(x)["claim_b"]

    flags_a = [pred_a(x) for x in alg1_values]
    say(f"{name}: claim (a) on {len(alg1_values)} values, holds at {sum(flags_a)}")
    grid_b = [point_b(x) for x in values]
    flags_b = [r["claim_b"] for r in grid_b]
    say(f"{name}: claim (b) on {len(values)} values, holds at {sum(flags_b)}")
    ia = true_intervals(alg1_values, flags_a, pred_a, rel_tol, floor)
    ib = true_intervals(values, flags_b, pred_b, rel_tol, floor)
    say(f"{name}: {len(ia)} interval(s) of (a), {len(ib)} of (b) after bisection")
    return {
        "parameter": name,
        "stated": float(getattr(p, name)),
        "alg1_values": [float(x) for x in alg1_values],
        "claim_a_flags": flags_a,
        "grid_b": grid_b,
        "intervals": {"a": ia, "b": ib, "both": intersect(ia, ib)},
        "bisection_points": sorted(
            (r for x, r in rows.items() if x not in set(map(float, values))), key=lambda r: r["value"]
        ),
    }


def _search_refined(
    p, name, values, alg1_values, *, gap_tol, steady_kwargs, rel_tol, floor, say, refine_floor, rescue, longer_periods
) -> dict:
    """:func:`search_parameter` with claim (b)'s grid refined (see there)."""
    from impactdamper.analysis.point import SweepSettings

    mp = int(steady_kwargs.get("max_periods", 4000))
    settings = SweepSettings(
        settle_tol=float(steady_kwargs.get("settle_tol", 1e-10)),
        max_periods=mp,
        max_periods_after_nonperiodic=mp,
        max_period_multiple=int(steady_kwargs.get("max_period_multiple", 8)),
        continuation=False,
        rescue=bool(rescue),
        **({"tolerances": steady_kwargs["tolerances"]} if "tolerances" in steady_kwargs else {}),
    )

    def pred_a(x: float) -> bool:
        return claim_a(algorithm1(p.replace(**{name: float(x)}), gap_tol=gap_tol))

    bisected: dict[float, dict] = {}

    def pred_b(x: float) -> bool:
        row = batch_rows(p, name, [float(x)], settings, longer_periods)[0]
        bisected[float(x)] = dict(row, level=-1)
        return row["claim_b"]

    flags_a = [pred_a(x) for x in alg1_values]
    say(f"{name}: claim (a) on {len(alg1_values)} values, holds at {sum(flags_a)}")
    grid_b, rounds = refine_grid(values, lambda xs: batch_rows(p, name, xs, settings, longer_periods), refine_floor)
    xs = [r["value"] for r in grid_b]
    flags_b = [r["claim_b"] for r in grid_b]
    say(
        f"{name}: claim (b) on {len(values)} values refined to {len(grid_b)} in {rounds} rounds "
        f"(floor {refine_floor:g}), holds at {sum(flags_b)}; "
        f"{sum(r['label'] == 'np' for r in grid_b)} still nonperiodic"
    )
    ia = true_intervals(alg1_values, flags_a, pred_a, rel_tol, floor)
    ib = true_intervals(xs, flags_b, pred_b, rel_tol, floor)
    say(f"{name}: {len(ia)} interval(s) of (a), {len(ib)} of (b) after bisection")
    step = (float(values[-1]) - float(values[0])) / (len(values) - 1) if len(values) > 1 else 0.0
    return {
        "parameter": name,
        "stated": float(getattr(p, name)),
        "alg1_values": [float(x) for x in alg1_values],
        "claim_a_flags": flags_a,
        "grid_b": grid_b,
        "intervals": {"a": ia, "b": ib, "both": intersect(ia, ib)},
        "bisection_points": sorted(bisected.values(), key=lambda r: r["value"]),
        "refinement": {
            "step": step,
            "alg1_step": (float(alg1_values[-1]) - float(alg1_values[0])) / (len(alg1_values) - 1)
            if len(alg1_values) > 1
            else 0.0,
            "floor": float(refine_floor),
            "rounds": rounds,
            "points": len(grid_b),
            "added": len(grid_b) - len(values),
            "rescue": bool(rescue),
            "longer_periods": int(longer_periods) if longer_periods else None,
            "rescued": sum(r["method"] == "rescue" for r in grid_b),
            "settled_longer": sum(r["method"] == "longer" for r in grid_b),
            "nonperiodic": sum(r["label"] == "np" for r in grid_b),
        },
    }


def reference_check(p, name: str, rows: Sequence[dict], steady_kwargs: dict) -> dict:
    """Algorithm No. 2 at each row's value again, by the pure-Python reference
    :func:`impactdamper.steady_state` (the compiled solver's independent check): the settled
    regime, k, z (z not for a nonperiodic motion, whose final window is chaotic) and claim (b)
    must be the same.

    Parameters
    ----------
    rows : sequence of dict
        Rows of :func:`search_parameter` (``value``, ``regime``, ``period_multiple``,
        ``impacts_per_cycle``, ``claim_b``).

    Returns
    -------
    dict
        ``points`` checked, ``agree`` (how many gave the same regime, k, z and claim),
        ``mismatches``: per disagreeing value, both results; ``settling`` of them, where one
        solver's run settled within ``max_periods`` and the other's did not (next to a
        bifurcation the motion settles slowly, and whether it gets below ``settle_tol`` within
        the cap follows the rounding of the arithmetic), and ``cycles``, where both settled, on
        different cycles (an error of one of them: none is expected).
    """
    mismatches = []
    for row in rows:
        s = steady_state(p.replace(**{name: float(row["value"])}), **steady_kwargs, backend="python")
        ref = {
            "regime": s.regime,
            "period_multiple": int(s.period_multiple),
            "impacts_per_cycle": int(s.impacts_per_cycle),
            "claim_b": claim_b(s),
        }
        mine = {key: row[key] for key in ref}
        if ref["period_multiple"] == 0 and mine["period_multiple"] == 0:
            # A motion that does not settle is chaotic: rounding differences between the two
            # solvers grow over the thousands of periods run, so the impacts counted in its final
            # window differ; only "nonperiodic" itself is compared.
            ref.pop("impacts_per_cycle"), mine.pop("impacts_per_cycle")
        if ref != mine:
            mismatches.append({"value": float(row["value"]), "compiled": mine, "reference": ref})
    settling = sum(1 for m in mismatches if 0 in (m["compiled"]["period_multiple"], m["reference"]["period_multiple"]))
    return {
        "points": len(rows),
        "agree": len(rows) - len(mismatches),
        "settling": settling,
        "cycles": len(mismatches) - settling,
        "mismatches": mismatches,
    }


def check_rows(result: dict, every: int) -> list[dict]:
    """The rows of a :func:`search_parameter` result that :func:`reference_check` repeats: every
    ``every``-th value of the initial grid (not of the points the refinement added), and both values of the final bracket of every bisected end of
    claim (b) (where the claim changes, the motion is most sensitive to the solver)."""
    ends = set()
    for iv in result["intervals"]["b"]:
        for bracket in (iv.lo_bracket, iv.hi_bracket):
            ends.update(float(x) for x in (bracket or ()))
    initial = [r for r in result["grid_b"] if r.get("level", 0) == 0]  # not the refinement's points
    rows = {float(r["value"]): r for r in initial[::every]}
    for r in list(result["grid_b"]) + list(result["bisection_points"]):
        if float(r["value"]) in ends:
            rows[float(r["value"])] = r
    return [rows[x] for x in sorted(rows)]


# The parameters the claims are searched along beyond the gap, each varied alone at the stated
# Delta0/x_st (config claims_search), in the order of the report's table, and their symbols there.
SEARCH_PARAMETERS = ("theta", "mu", "N", "delta1", "delta2", "R")
SEARCH_SYMBOLS = {
    "theta": "$\\theta$",
    "mu": "$\\mu$",
    "N": "$N$",
    "delta1": "$\\delta_1$",
    "delta2": "$\\delta_2$",
    "R": "$R$",
}


def nearest_both(result: dict) -> dict:
    """The nearest value to the stated one where both claims hold, and how far it is, from one
    parameter's search record (``stated`` and ``intervals["both"]`` as dicts of
    :class:`Interval`'s fields).

    Returns
    -------
    dict
        ``stated``, ``nearest`` (None: nowhere), ``distance`` (absolute, None: nowhere),
        ``relative_distance`` (over |stated|; None when nowhere or stated is 0), ``intervals``
        (how many intervals where both hold).
    """
    stated = result["stated"]
    ivs = [Interval(**{**iv, "lo_bracket": None, "hi_bracket": None}) for iv in result["intervals"]["both"]]
    d, x = distance_to(ivs, stated)
    return {
        "stated": stated,
        "nearest": x,
        "distance": d if math.isfinite(d) else None,
        "relative_distance": (d / abs(stated)) if (math.isfinite(d) and stated) else None,
        "intervals": len(ivs),
    }


# --- both claims over two parameters ---------------------------------------------------------
MAP_COLUMNS = [
    "x",
    "y",
    "claim_a",
    "claim_b",
    "both",
    "alg1_exists",
    "regime",
    "period_multiple",
    "impacts_per_cycle",
    "periods",
    "label",
]


def claims_map(p, x: str, xs: Sequence[float], y: str, ys: Sequence[float], *, gap_tol: float, settings) -> list[dict]:
    """Both claims at every cell of the grid ``xs`` x ``ys`` of parameters ``x`` and ``y`` (the
    others as in ``p``): Algorithm No. 1 (closed form, ``gap_tol``) and Algorithm No. 2 from the
    paper's step 1 on the compiled batch (:func:`impactdamper.steady_states`, each
    cell alone, ``settings``), in one call for all cells.

    Returns
    -------
    list of dict
        One per cell, rows of y outer, x inner, with :data:`MAP_COLUMNS`.
    """
    if x == y:
        raise ValueError(f"`y` = {y!r} is not allowed: must differ from `x`")
    return claims_cells(p, x, y, [(float(a), float(b)) for b in ys for a in xs], gap_tol=gap_tol, settings=settings)


def claims_cells(p, x: str, y: str, points: Sequence[tuple[float, float]], *, gap_tol: float, settings) -> list[dict]:
    """Both claims at each point ``(x value, y value)`` of ``points`` (any set, in the given
    order), as :func:`claims_map` computes them at its cells (one batch call for all points).

    Returns
    -------
    list of dict
        One per point, with :data:`MAP_COLUMNS`.
    """
    import numpy as np

    from impactdamper import steady_states

    if x == y:
        raise ValueError(f"`y` = {y!r} is not allowed: must differ from `x`")
    if not len(points):
        return []
    cells = np.array(points, float).reshape(-1, 2)
    res = steady_states(p, (x, y), cells, settings=settings, chain=False)
    out = []
    for i, (a, b) in enumerate(cells):
        alg1 = algorithm1(p.replace(**{x: float(a), y: float(b)}), gap_tol=gap_tol)
        ca = claim_a(alg1)
        rg, k, z = str(res.regime[i]), int(res.period_multiple[i]), int(res.impacts_per_cycle[i])
        cb = rg == "multi_impact" and k == CLAIM_B_PERIOD_MULTIPLE and z == CLAIM_B_IMPACTS
        out.append(
            {
                "x": float(a),
                "y": float(b),
                "claim_a": ca,
                "claim_b": cb,
                "both": ca and cb,
                "alg1_exists": bool(alg1.exists),
                "regime": rg,
                "period_multiple": k,
                "impacts_per_cycle": z,
                "periods": int(res.periods[i]),
                "label": str(res.label[i]),
            }
        )
    return out


def count_end_checks(checks: Sequence[dict]) -> dict:
    """The located range's end checks (:func:`impactdamper.studies.gapscan.end_checks`) counted
    by what they rest on.

    Returns
    -------
    dict
        ``checks``; ``compared_within``: both methods gave a motion to compare and every
        measured difference is within its tolerance; ``nothing_to_compare``: the same verdict
        but nothing to compare (claim a: no orbit by either method; claim b: neither settles);
        ``outside_tolerance``: compared, a difference above its tolerance (whatever the
        verdicts); ``different_verdict``: the two methods give different verdicts on the claim.
    """
    out = {
        "checks": len(checks),
        "compared_within": 0,
        "nothing_to_compare": 0,
        "outside_tolerance": 0,
        "different_verdict": 0,
    }
    for c in checks:
        if c["exact"] != c["independent"]:
            out["different_verdict"] += 1
        if c["claim"] == "a":
            nothing = c["comparison"]["periodicity_residual"] is None
            within = bool(c["comparison"]["agree"])
        else:
            nothing = c["exact_period_multiple"] == 0 and c["independent_period_multiple"] == 0
            within = bool(c["details"].get("agree", False))
        if nothing:
            out["nothing_to_compare"] += c["exact"] == c["independent"]
        elif within:
            out["compared_within"] += 1
        else:
            out["outside_tolerance"] += 1
    return out
