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
again at its optimum (``reproduced``: the relative difference from the record's value, so that
the halves are judged by the criterion the row was).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from impactdamper.studies.design.devices import (
    DESIGN_SETTINGS,
    IMPACT_NAMES,
    TMD_NAMES,
    ImpactCriterion,
    TmdCriterion,
    Uncertainty,
)
from impactdamper.studies.design.optimum import ROWS
from impactdamper.studies.design.search import CHECK_RTOL, Budget, subregions
from impactdamper.studies.design.tasks import in_parallel, processor_time
from impactdamper.studies.design.verdict import device

__all__ = ["SUBREGION_BUDGET", "design_subregions", "row_check"]

# The halves' budget: the design table's (search_setup.BUDGET) with a smaller global stage (64
# designs of the whole box, 32 in each half, against 128 for the row's own search), one local
# search from the best of them, 8 polls instead of 10, no polish and one round of the 2 % check
# (instead of 6): the 40 halves of the 12 rows in about two and a half minutes of processor
# time. A half's answer is an upper bound of its minimum: a half it misses is not lower for it.
SUBREGION_BUDGET = Budget(
    samples=64, starts=1, polls=8, first_step=1 / 8, last_step=1 / 128, coarse_above=1 / 32, polish=0, checks=1
)


def _uncertainty(record: dict) -> Uncertainty:
    u = record["uncertainty"]
    return Uncertainty(u["detuning"], tuple(u["force"]), u["restitution"], u["stiffness"], u["damping"])


def _criterion(record: dict, kind: str, criterion: str, workers: int = 1):
    """The row's criterion as its search evaluated it: (evaluate, the parameters' names)."""
    band, unc = tuple(record["band"]), _uncertainty(record)
    limit = record["max_stroke"] if criterion == "stroke" else None
    c = "peak" if criterion == "stroke" else criterion
    if kind == "tmd":
        return TmdCriterion(record["mu"], record["delta1"], band, c, unc, max_stroke=limit), list(TMD_NAMES)
    crit = ImpactCriterion(
        record["mu"], record["delta1"], band, c, unc, max_stroke=limit, settings=DESIGN_SETTINGS, workers=workers
    )
    return crit, list(IMPACT_NAMES)


def row_check(record: dict, key: str, budget: Budget = SUBREGION_BUDGET, seed: int = 0, say=None) -> dict:
    """The sub-region check of the design table's row ``key`` (module docstring) in the design
    record ``record`` (:func:`~impactdamper.studies.design.optimum.design_optima`'s)."""
    say = say or (lambda m: None)
    kind, criterion = next((k, c) for r, k, c, _ in ROWS if r == key)
    row = device(record, key)
    evaluate, names = _criterion(record, kind, criterion)
    box = record["bounds"]["tmd"] if kind == "tmd" else row["search"]["bounds"]
    bounds = {n: tuple(box[n]) for n in names}
    x = {n: float(row["search"]["parameters"][n]) for n in names}
    value = float(row["search"]["value"])
    again = float(evaluate(np.array([[x[n] for n in names]]), "final")[0])
    out = subregions(evaluate, bounds, x, value, budget=budget, seed=seed, progress=lambda m: say(f"{key}, {m}"))
    return {"device": key, "kind": kind, "criterion": criterion, "reproduced": again / value - 1.0, **out}


def design_subregions(
    record: dict,
    *,
    budget: Budget = SUBREGION_BUDGET,
    workers: int = 1,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Every row of the design table ``record`` checked against its box's halves (module
    docstring), ``workers`` rows at a time (each in its own process: the answer does not depend
    on where it runs).

    Returns
    -------
    dict
        ``rows`` (per row of :data:`ROWS`: :func:`row_check`'s record), ``budget``, ``rtol``
        (CHECK_RTOL), ``rows_count``, ``halves_count``, ``smallest_margin`` (over every half)
        and where (``smallest_row``, ``smallest_half``), ``largest_reproduced`` (the largest
        ``reproduced`` in size), ``lower`` (every half lower than its row's optimum by more than
        CHECK_RTOL: row, half, both values and parameters), ``passed`` (none is).
    """
    t0, c0 = time.perf_counter(), processor_time()
    say = progress or (lambda m: None)
    tasks = {key: _task(record, key, budget, seed, say) for key, *_ in ROWS}
    rows = list(in_parallel(tasks, workers).values())
    halves = [(r, h) for r in rows for h in r["halves"]]
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
        for r, h in halves
        if h["margin"] < -CHECK_RTOL
    ]
    return {
        "budget": budget.to_dict(),
        "rtol": CHECK_RTOL,
        "seed": seed,
        "rows_count": len(rows),
        "halves_count": len(halves),
        "smallest_margin": worst["margin"],
        "smallest_row": worst_row["device"],
        "smallest_half": f"{worst['parameter']} {worst['half']}",
        "largest_reproduced": max(abs(r["reproduced"]) for r in rows),
        "lower": lower,
        "passed": not lower,
        "rows": rows,
        "elapsed": time.perf_counter() - t0,
        "cpu": processor_time() - c0,
    }


def _task(record: dict, key: str, budget: Budget, seed: int, say) -> Callable[[], dict]:
    return lambda: row_check(record, key, budget, seed, say)
