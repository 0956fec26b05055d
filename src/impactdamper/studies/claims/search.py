"""Where the paper's Fig. 2 claims hold beyond the stated gap: each other parameter varied alone
(claim (b)'s grid refined where the settled motion changes, the ends bisected), checked
point by point against the pure-Python reference, and the nearest value where both hold.

Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100: the claims
(:mod:`impactdamper.studies.replication.claims`) are stated at one point; this search, which
the paper does not have, finds where they hold around it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from impactdamper.analysis.parallel import map_blocks
from impactdamper.analysis.solve import steady_state
from impactdamper.core.algorithm1 import algorithm1
from impactdamper.core.parameters import RELATIVE_PARAMETERS
from impactdamper.studies.intervals import Interval, distance_to, intersect, true_intervals
from impactdamper.studies.replication.claims import CLAIM_B_IMPACTS, CLAIM_B_PERIOD_MULTIPLE, claim_a, claim_b

__all__ = [
    "SEARCH_PARAMETERS",
    "refine_grid",
    "search_parameter",
    "reference_check",
    "check_rows",
    "nearest_both",
    "solver_dependent",
]


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


def _batch_rows(p, name: str, xs: list, settings, longer_periods: int | None = None, workers: int = 1) -> list[dict]:
    """Algorithm No. 2 from the paper's step 1 at each value of ``name`` (the others as in
    ``p``), on the compiled batch (:func:`impactdamper.steady_states`, each point
    alone, ``settings``: its ``rescue`` tries the Newton rescue on a point that did not
    settle; in ``workers`` processes). A point still nonperiodic is run again with
    ``longer_periods`` (if given).

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
        r = steady_states(p, (name,), np.array(values, float)[:, None], settings=st, chain=False, workers=workers)
        regimes, labels = r.regime, r.label  # (each property builds its array)
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
                values, regimes, r.period_multiple, r.impacts_per_cycle, r.periods, labels, r.method
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
    workers: int = 1,
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
    Algorithm No. 1's grid and each round of the refinement run in ``workers`` processes
    (:func:`impactdamper.analysis.parallel.map_blocks`, the batch's own workers: the same result).
    """
    if name not in p.names():
        raise ValueError(f"`name` = {name!r} is not allowed: must be one of {', '.join(p.names())}")
    say = log or (lambda msg: None)
    both = {"gap_tol": gap_tol, "steady_kwargs": steady_kwargs, "rel_tol": rel_tol, "floor": floor, "say": say}
    if refine_floor is not None:
        return _search_refined(
            p,
            name,
            values,
            alg1_values,
            **both,
            refine_floor=refine_floor,
            rescue=rescue,
            longer_periods=longer_periods,
            workers=workers,
        )
    return _search_pointwise(p, name, values, alg1_values, **both)


def _claim_b_row(x: float, s) -> dict:
    """Claim (b)'s record of the settled motion ``s`` at value ``x``."""
    return {
        "value": float(x),
        "claim_b": claim_b(s),
        "regime": s.regime,
        "period_multiple": int(s.period_multiple),
        "impacts_per_cycle": int(s.impacts_per_cycle),
        "periods": int(s.periods),
    }


def _search_pointwise(p, name, values, alg1_values, *, gap_tol, steady_kwargs, rel_tol, floor, say) -> dict:
    """:func:`search_parameter` without ``refine_floor``: claim (b) by :func:`steady_state` one
    point at a time on the grid ``values``, each end bisected."""

    def pred_a(x: float) -> bool:
        return claim_a(algorithm1(p.replace(**{name: float(x)}), gap_tol=gap_tol))

    rows: dict[float, dict] = {}

    def point_b(x: float) -> dict:
        row = _claim_b_row(x, steady_state(p.replace(**{name: float(x)}), **steady_kwargs))
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
    bisected = [r for x, r in rows.items() if x not in set(map(float, values))]
    return _searched(p, name, alg1_values, flags_a, grid_b, ia, ib, bisected)


def _searched(p, name: str, alg1_values, flags_a: list, grid_b: list, ia: list, ib: list, bisected) -> dict:
    """The record of :func:`search_parameter`: the grids, their flags, the intervals of claims
    (a), (b) and both, and the points the bisection added (in increasing value)."""
    return {
        "parameter": name,
        "stated": float(getattr(p, name)),
        "alg1_values": [float(x) for x in alg1_values],
        "claim_a_flags": flags_a,
        "grid_b": grid_b,
        "intervals": {"a": ia, "b": ib, "both": intersect(ia, ib)},
        "bisection_points": sorted(bisected, key=lambda r: r["value"]),
    }


def _search_refined(
    p,
    name,
    values,
    alg1_values,
    *,
    gap_tol,
    steady_kwargs,
    rel_tol,
    floor,
    say,
    refine_floor,
    rescue,
    longer_periods,
    workers=1,
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
        row = _batch_rows(p, name, [float(x)], settings, longer_periods)[0]
        bisected[float(x)] = dict(row, level=-1)
        return row["claim_b"]

    flags_a = map_blocks(lambda xs: [pred_a(x) for x in xs], list(alg1_values), workers, MIN_BLOCK)
    say(f"{name}: claim (a) on {len(alg1_values)} values, holds at {sum(flags_a)}")
    grid_b, rounds = refine_grid(
        values, lambda xs: _batch_rows(p, name, xs, settings, longer_periods, workers), refine_floor
    )
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
        **_searched(p, name, alg1_values, flags_a, grid_b, ia, ib, bisected.values()),
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


def reference_check(p, name: str, rows: Sequence[dict], steady_kwargs: dict, workers: int = 1) -> dict:
    """Algorithm No. 2 at each row's value again, by the pure-Python reference
    :func:`impactdamper.steady_state` (the compiled solver's independent check): the settled
    regime, k, z (z not for a nonperiodic motion, whose final window is chaotic) and claim (b)
    must be the same. The rows run in ``workers`` processes.

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

    def reference(rows: list) -> list[dict]:
        out = []
        for row in rows:
            s = steady_state(p.replace(**{name: float(row["value"])}), **steady_kwargs, backend="python")
            out.append(
                {
                    "regime": s.regime,
                    "period_multiple": int(s.period_multiple),
                    "impacts_per_cycle": int(s.impacts_per_cycle),
                    "claim_b": claim_b(s),
                }
            )
        return out

    mismatches = []
    for row, ref in zip(rows, map_blocks(reference, list(rows), workers)):
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


# Fewest values of Algorithm No. 1's grid a worker process is given (each costs about a millisecond).
MIN_BLOCK = 200
# The parameters the claims are searched along beyond the gap, each varied alone at the stated
# Delta0/x_st (config claims_search), in the order of the report's table: every relative
# parameter but the gap (the gap scan's, replication/gapscan.py).
SEARCH_PARAMETERS = tuple(n for n in RELATIVE_PARAMETERS if n != "gap")


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


def solver_dependent(d: dict) -> list[float]:
    """Ends of the intervals where both claims hold whose final bisection bracket holds a value
    where the pure-Python reference gives another motion than the compiled solver (the end is
    known to the bisection's tolerance only for the compiled solver), from one parameter's
    gathered record (``intervals["both"]`` as dicts, ``reference_check``)."""
    off = {float(m["value"]) for m in d["reference_check"]["mismatches"]}
    out = []
    for iv in d["intervals"]["both"]:
        for side in ("lo", "hi"):
            bracket = iv[side + "_bracket"]
            if bracket is not None and off & {float(x) for x in bracket}:
                out.append(iv[side])
    return out
