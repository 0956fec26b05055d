"""The impact suppressor's searches of one design table (what
:func:`impactdamper.studies.design.optimum.design_optima` asks of them): one shared global
sample of the whole box, evaluated once under every scenario the searches need, then the
searches (:func:`impactdamper.studies.design.search.search`) that start from it: the nominal
criteria with the stop within reach and over the whole box, the robust ones from the nominal
optimum, the travel-limited one with the gap at most the limit.
"""

from __future__ import annotations

import functools

import numpy as np
import scipy.stats

from impactdamper.studies.design.devices import DESIGN_SETTINGS, IMPACT_NAMES, ImpactCriterion, Scenario
from impactdamper.studies.design.search import search
from impactdamper.studies.design.tasks import in_parallel

__all__ = ["ROBUST_SEARCHED", "impact_searches"]

# Designs of the shared sample per batch (a progress line after each).
SAMPLE_BATCH = 32
# The nominal criteria, and the robust criteria searched (the others are evaluated for every
# design: the table's columns).
CRITERIA_NOMINAL = ("peak", "band_average")
ROBUST_SEARCHED = ("detuning", "force", "restitution")


def impact_searches(mu, delta1, band, unc, bounds, max_stroke, tmd, stroke_tmd, budgets, seed, workers, say, robust):
    """The impact suppressor's searches (module docstring): one shared global sample over the
    whole box (one batch on ``workers`` processes); then, ``workers`` searches at a time (each in
    its own process: a search's answer does not depend on where it runs), the nominal criteria
    with the stop within reach; the nominal criteria over the whole box from the TMD limit and
    the best samples outside the first box, never worse than the first; the robust ones from the
    nominal peak's optimum; the travel-limited one with the gap at most the limit."""
    names = list(IMPACT_NAMES)
    lo = np.array([bounds["impact"][n][0] for n in names])
    hi = np.array([bounds["impact"][n][1] for n in names])
    budget, robust_budget = budgets
    X = lo + scipy.stats.qmc.Sobol(len(names), scramble=True, seed=seed).random(int(budget.samples)) * (hi - lo)
    values = _shared_sample(mu, delta1, band, unc, X, workers, ROBUST_SEARCHED if robust else (), say)
    say(f"global stage: {len(X)} designs, {len(values)} criteria, best peak {np.min(values['peak']):.5g}")
    task = functools.partial(_search, mu, delta1, band, seed=seed, workers=1, say=say)
    reach = bounds["impact_reach"]
    first = {f"{c}_reach": functools.partial(task, c, unc, reach, budget, (X, values[c])) for c in CRITERIA_NOMINAL}
    out = in_parallel(first, workers)
    limit = {"gap": bounds["impact"]["gap"][1], **tmd.x, "R": 0.5}
    second = {}
    for c in CRITERIA_NOMINAL:
        r = out[f"{c}_reach"]
        # The whole box from its TMD limit, the sub-box's answer where it stops at the sub-box's
        # gap bound (it may go on beyond it), and the best samples outside the sub-box.
        seeds = [limit] + ([r.x] if "gap" in r.at_bound else [])
        second[c] = functools.partial(
            task,
            c,
            unc,
            bounds["impact"],
            budget,
            (X, values[c]),
            seeds=seeds,
            incumbents=[(r.x, r.value)],
            searched=reach,
        )
    for c in ROBUST_SEARCHED if robust else ():
        second[c] = functools.partial(task, c, unc, reach, robust_budget, (X, values[c]), seeds=[out["peak_reach"].x])
    # The travel limit: the gap at most the limit (an impacting device travels the gap towards
    # its stop); a local search from the travel-limited TMD with its stop at the limit (it never
    # reaches it: a feasible start) and from the best sample inside the box (its stroke is read
    # at the search's finer fidelities only: each evaluation runs the band's cycles again).
    box = {**reach, "gap": (reach["gap"][0], min(max_stroke, reach["gap"][1]))}
    inside = np.flatnonzero(X[:, 0] <= box["gap"][1])
    seeds = [{"gap": box["gap"][1], **stroke_tmd.x, "R": 0.5}]
    if len(inside):
        seeds.append(dict(zip(names, X[inside[int(np.argmin(values["peak"][inside]))]])))
    second["stroke"] = functools.partial(
        task, "peak", unc, box, budget, (X, values["peak"]), seeds=seeds, max_stroke=max_stroke
    )
    return {**out, **in_parallel(second, workers)}


def _shared_sample(mu, delta1, band, unc, X: np.ndarray, workers: int, robust, say) -> dict:
    """The global stage every impact search shares: the designs ``X`` (rows in IMPACT_NAMES'
    order) at the ``coarse`` fidelity under the nominal scenario and each robust criterion's
    scenarios, in batches of SAMPLE_BATCH designs (a progress line after each). Returns each
    criterion's coarse values."""
    names = list(IMPACT_NAMES)
    crit = ImpactCriterion(mu, delta1, band, "peak", unc, settings=DESIGN_SETTINGS, workers=workers)
    scen = list(dict.fromkeys(s for c in ("peak", *robust) for s in unc.scenarios(c)))
    out = []
    for k in range(0, len(X), SAMPLE_BATCH):
        out += crit.branches([dict(zip(names, x)) for x in X[k : k + SAMPLE_BATCH]], scen, "coarse")
        say(f"global stage: {min(k + SAMPLE_BATCH, len(X))} of {len(X)} designs under {len(scen)} scenarios")
    m = len(scen)
    mine = [dict(zip(scen, out[i * m : (i + 1) * m])) for i in range(len(X))]
    values = {
        "peak": np.array([d[Scenario()][0].peak for d in mine]),
        "band_average": np.array([d[Scenario()][0].band_average for d in mine]),
    }
    for c in robust:
        cs = unc.scenarios(c)
        values[c] = np.array([max(d[s][1] * d[s][0].peak for s in cs) for d in mine])
    return values


def _search(
    mu,
    delta1,
    band,
    criterion,
    unc,
    box,
    budget,
    sample,
    *,
    seeds=(),
    incumbents=(),
    searched=None,
    max_stroke=None,
    seed=0,
    workers=1,
    say=None,
):
    """One search of the impact suppressor (:func:`~impactdamper.studies.design.search.search`)."""
    crit = ImpactCriterion(
        mu, delta1, band, criterion, unc, max_stroke=max_stroke, settings=DESIGN_SETTINGS, workers=workers
    )
    tag = criterion if max_stroke is None else f"stroke <= {max_stroke:.3g}"
    r = search(
        crit,
        box,
        budget=budget,
        sample=sample,
        seeds=seeds,
        incumbents=incumbents,
        searched=searched,
        seed=seed,
        progress=lambda m: say(f"impact, {tag}: {m}"),
    )
    say(f"impact, {tag}: {', '.join(f'{k} = {v:.4g}' for k, v in r.x.items())}: {r.value:.6g}")
    return r
