"""Every design optimum checked against its box's sub-regions (the design table's sub-region
record, ``figures/design_subregions.json``).

A search's passed 2 % check certifies a local minimum only (a search restricted differently found
a lower force-robust optimum in an earlier version). Here every row of the design table
(:data:`impactdamper.studies.design.optimum.ROWS`, both devices) is checked by
:func:`impactdamper.studies.design.search.subregions`: its search box split at the midpoint
along each design variable, every half that does not hold the row's optimum (d halves for d
variables) searched with :data:`SUBREGION_BUDGET`, by the row's own criterion (the travel limit's
penalty included) and its final fidelity, and the best value there compared with the row's
optimum. The box of a row is the one its global search was given: the impact suppressor's
search box as its record states it, and the TMD's box of the global stage (the TMD's refinement
then widens delta2 up to a locked absorber near its answer only,
:mod:`~impactdamper.studies.design.tmd`). Before the halves, the row's criterion is evaluated
again at its optimum (``reproduced``: the relative difference from the search's value, so that
the halves are judged by the criterion the row was). Where a half is lower by more than the
search's tolerance (CHECK_RTOL), the design search adopts it (:func:`vouched`, called by
:func:`~impactdamper.studies.design.optimum.design_optima`): a local search of the row's box from
the half's answer, never worse than it, and the check again; the record keeps the finding.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactdamper.studies.design.devices import (
    DESIGN_SETTINGS,
    IMPACT_NAMES,
    TMD_NAMES,
    ImpactCriterion,
    TmdCriterion,
    Uncertainty,
)
from impactdamper.studies.design.search import CHECK_RTOL, Budget, SearchResult, search, subregions

__all__ = ["SUBREGION_BUDGET", "ADOPTIONS", "subregion_budget", "vouched", "summary"]

# The halves' budget: the design table's (search_setup.BUDGET) with a smaller global stage (64
# designs of the whole box, 32 in each half, against 128 for the row's own search), one local
# search from the best of them, 8 polls instead of 10, no polish and one round of the 2 % check
# (instead of 6): the 40 halves of the 12 rows in about two and a half minutes of processor
# time. A half's answer is an upper bound of its minimum: a half it misses is not lower for it.
SUBREGION_BUDGET = Budget(
    samples=64, starts=1, polls=8, first_step=1 / 8, last_step=1 / 128, coarse_above=1 / 32, polish=0, checks=1
)


def subregion_budget(design: dict) -> Budget:
    """The sub-region check's budget from the config's ``design`` section: ``subregion_samples``
    (the Sobol sample over the whole box, a power of 2; each half holds about half of it) and
    ``subregion_polls`` (the one start's compass polls); the rest, and any key left out, as
    :data:`SUBREGION_BUDGET` (the shipped config's values are its own)."""
    return dataclasses.replace(
        SUBREGION_BUDGET,
        samples=int(design.get("subregion_samples", SUBREGION_BUDGET.samples)),
        polls=int(design.get("subregion_polls", SUBREGION_BUDGET.polls)),
    )


# A row whose half is lower adopts it at most this many times (each adoption checked again).
ADOPTIONS = 2


def _criterion_of(kind: str, criterion: str, mu, delta1, band, uncertainty: Uncertainty, max_stroke, workers=1):
    """A row's criterion as its search evaluated it: (evaluate, the parameters' names); the
    travel-limited rows (``stroke``) are the peak with the limit's penalty."""
    limit = max_stroke if criterion == "stroke" else None
    c = "peak" if criterion == "stroke" else criterion
    if kind == "tmd":
        return TmdCriterion(mu, delta1, tuple(band), c, uncertainty, max_stroke=limit), list(TMD_NAMES)
    crit = ImpactCriterion(
        mu, delta1, tuple(band), c, uncertainty, max_stroke=limit, settings=DESIGN_SETTINGS, workers=workers
    )
    return crit, list(IMPACT_NAMES)


def _check(evaluate, names: list, box: dict, result: SearchResult, budget: Budget, seed: int, say) -> dict:
    """One sub-region check of ``result`` over ``box`` (its value evaluated again first)."""
    bounds = {n: tuple(box[n]) for n in names}
    x = {n: float(result.x[n]) for n in names}
    again = float(evaluate(np.array([[x[n] for n in names]]), "final")[0])
    out = subregions(evaluate, bounds, x, float(result.value), budget=budget, seed=seed, progress=say)
    return {"reproduced": again / result.value - 1.0, **out}


def vouched(key, kind, criterion, result, box, context: dict, budgets: tuple, seed: int = 0, say=None):
    """The row ``key``'s search ``result`` over ``box`` checked against the box's halves (module
    docstring) with ``budgets[0]``; where a half is lower, its answer adopted: a local search of
    the box (``budgets[1]`` without its global stage) from it, never worse than it, checked
    again, at most ADOPTIONS times. ``context``: mu, delta1, band, uncertainty, max_stroke.

    Returns
    -------
    (SearchResult, dict)
        The answer (``source`` ``subregion`` where adopted), and the record: the row's first
        check's fields, ``adopted`` (each adoption: the half, its value and parameters, the
        local search's value), ``rechecks`` (the checks after them) and ``final`` (the last
        check's ``value``, ``parameters``, ``smallest_margin``, ``passed``).
    """
    say = say or (lambda m: None)
    evaluate, names = _criterion_of(kind, criterion, **context)
    tell = lambda m: say(f"{key}, {m}")  # noqa: E731
    checks = [_check(evaluate, names, box, result, budgets[0], seed, tell)]
    adopted = []
    while not checks[-1]["passed"] and len(adopted) < ADOPTIONS:
        half = min(checks[-1]["halves"], key=lambda h: h["value"])
        local = dataclasses.replace(budgets[1], samples=0)
        bounds = {n: tuple(box[n]) for n in names}
        r = search(
            evaluate,
            bounds,
            budget=local,
            seeds=[half["parameters"]],
            incumbents=[(half["parameters"], half["value"])],
            seed=seed,
            progress=lambda m: tell(f"adopting: {m}"),
        )
        result = dataclasses.replace(r, source="subregion", starts=result.starts)
        adopted.append(
            {
                "half": f"{half['parameter']} {half['half']}",
                "value": half["value"],
                "parameters": half["parameters"],
                "searched": r.value,
                "searched_parameters": dict(r.x),
            }
        )
        tell(f"adopted the {half['parameter']} {half['half']} half's answer: {r.value:.8g}")
        checks.append(_check(evaluate, names, box, result, budgets[0], seed, tell))
    last = checks[-1]
    final = {k: last[k] for k in ("value", "parameters", "smallest_margin", "passed")}
    record = {
        "device": key,
        "kind": kind,
        "criterion": criterion,
        **checks[0],
        "adopted": adopted,
        "rechecks": checks[1:],
        "final": final,
    }
    return result, record


def summary(rows: list, budget: Budget, seed: int) -> dict:
    """The sub-region record of the design table from its rows' :func:`vouched` records:
    ``rows``, ``budget``, ``rtol`` (CHECK_RTOL), ``rows_count``, ``halves_count`` (of the first
    checks), ``halves_searched`` (the rechecks' included); ``lower`` (every half of a first check
    lower than its row's search answer by more than CHECK_RTOL: row, half, both values and
    parameters: the findings), ``adopted`` (the rows that adopted one); of the final checks (the
    table's answers): ``smallest_margin`` and where (``smallest_row``, ``smallest_half``),
    ``passed``; ``largest_reproduced`` (the largest ``reproduced`` in size)."""
    final = [(r, (r["rechecks"] or [r])[-1]) for r in rows]
    halves = [(r, h) for r, c in final for h in c["halves"]]
    worst_row, worst = min(halves, key=lambda rh: rh[1]["margin"])
    lower = [
        {
            "device": r["device"],
            "half": f"{h['parameter']} {h['half']}",
            "value": h["value"],
            "optimum": r["value"],
            "parameters": h["parameters"],
            "optimum_parameters": r["parameters"],
            "margin": h["margin"],
        }
        for r in rows
        for h in r["halves"]
        if h["margin"] < -CHECK_RTOL
    ]
    return {
        "budget": budget.to_dict(),
        "rtol": CHECK_RTOL,
        "seed": seed,
        "adoptions": ADOPTIONS,
        "rows_count": len(rows),
        "halves_count": sum(len(r["halves"]) for r in rows),
        "halves_searched": sum(len(c["halves"]) for r in rows for c in [r, *r["rechecks"]]),
        "lower": lower,
        "adopted": [r["device"] for r in rows if r["adopted"]],
        "smallest_margin": worst["margin"],
        "smallest_row": worst_row["device"],
        "smallest_half": f"{worst['parameter']} {worst['half']}",
        "largest_reproduced": max(abs(c["reproduced"]) for r in rows for c in [r, *r["rechecks"]]),
        "passed": all(r["final"]["passed"] for r in rows),
        "rows": rows,
    }
