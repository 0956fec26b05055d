"""Choosing a suppressor, answered: the design table of one object, what ``python -m
impactdamper design`` prints and what the report's design table shows (one call,
:func:`design_optima`).

Both devices (:mod:`impactdamper.studies.design.devices`) on the object of mass ratio mu and
damping delta1 over a band of forcing frequencies (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100, eqs. 1-2 and 9-10 in relative form) are optimised by a
global search (:func:`impactdamper.studies.design.search.search`, the same budget for both:
a Sobol sample, compass searches from its best distinct points, a polish, the 2 % check) for
each criterion: the nominal peak, the band average, the worst peak with the object detuned,
with the force amplitude off its design value, with the restitution drifting; and under a
stroke limit. The impact suppressor's searches share one sample of the whole box, evaluated
once under every scenario they need; the robust ones (on request: ``robust``) start from it
and from the nominal optimum. The TMD's answers are then converged on its exact peaks
(:func:`impactdamper.studies.design.tmd.refine_tmd`: the equal-peak optimum for the peak). What
a search certifies: a local minimum that no 2 % move along an axis improves (where its check
passed), and the best reached from its global samples; its starts' ends and spread are in its
record (``best_found`` where they disagree by more than 0.5 %). With ``subregion_budget`` (the
workflow's design table) every row's answer is also checked against the halves of its box
without it, and a lower half's answer adopted and checked again
(:mod:`impactdamper.studies.design.subregions`).
The boxes are derived from the object and the budgets are the same for both devices
(:mod:`impactdamper.studies.design.search_setup`); the impact suppressor's searches are
:mod:`impactdamper.studies.design.impact_searches`. The answer over the whole box is seeded
with, and never worse than, the one with the stop within reach. Every row of the table is then evaluated alike: located worst branch, band
average, worst peaks over each uncertainty and over all together, stroke and loads.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import os
import time
from collections.abc import Callable

import numpy as np

from impactdamper.analysis.linear_device import LinearDevice, den_hartog
from impactdamper.analysis.parallel import check_workers
from impactdamper.studies.design.devices import (
    ROBUST,
    DESIGN_SETTINGS,
    NATURAL_FREQUENCY,
    RANGES,
    STOP_STIFFNESS,
    ImpactCriterion,
    Scenario,
    WORKERS,
    TmdCriterion,
    Uncertainty,
    impact_rows,
    tmd_row,
)
from impactdamper.studies.design.impact_searches import ROBUST_SEARCHED, impact_searches
from impactdamper.studies.design.search import Budget, SearchResult, search
from impactdamper.studies.design.search_setup import (
    BUDGET,
    ROBUST_BUDGET,
    STROKE_FRACTION,
    check_object,
    design_bounds,
)
from impactdamper.studies.design.subregions import summary, vouched
from impactdamper.studies.design.tasks import Silences, in_parallel, processor_time
from impactdamper.studies.design.tmd import equal_peaks, refine_tmd
from impactdamper.studies.design.verdict import device, headline, recommendation

__all__ = [
    "RANGES",
    "BUDGET",
    "WORKERS",
    "check_object",
    "optimal_tmd",
    "design_optima",
    "saved_or_searched",
    "SNUBBER_FRACTIONS",
    "SNUBBER_R",
    "ROBUST_BUDGET",
]

# The snubber: a stop put within the optimal TMD's own travel, at these fractions of its stroke,
# with this restitution.
SNUBBER_FRACTIONS = (0.5, 0.75, 0.9)
SNUBBER_R = 0.5


def _record(kind: str, criterion: str, name: str, row: dict, result: SearchResult | None) -> dict:
    out = {"device": name, "criterion": criterion, **row}
    if result is not None:
        out["search"] = result.to_dict()
        out["at_bound"] = list(result.at_bound)
    if kind == "impact" and not row["impacts"]:
        out["tmd_limit"] = True  # never reaches its stop over the band: a TMD
    return out


def _tmd_searches(mu, delta1, band, unc, budgets, seed, say) -> dict:
    """The TMD's searches, each with the impact suppressor's nominal budget (its global stage
    included), then refined to convergence on the exact peaks with delta2 free up to a locked
    absorber (:func:`~impactdamper.studies.design.tmd.refine_tmd`); the force and the restitution
    leave it as it is."""
    out = {}
    for c in ("peak", "band_average", "detuning"):
        out[c] = optimal_tmd(TmdCriterion(mu, delta1, band, c, unc), budgets[0], seed)
        say(f"TMD, {c}: N = {out[c].x['N']:.6f}, delta2 = {out[c].x['delta2']:.6f}, {out[c].value:.8g}")
    return out


def optimal_tmd(crit: TmdCriterion, budget: Budget = BUDGET, seed: int = 0) -> SearchResult:
    """The optimal linear TMD for criterion ``crit`` (its mu, delta1, band, criterion,
    uncertainty and stroke limit): the one TMD optimiser, a global search (Sobol sample, compass,
    polish) over the TMD's box refined to convergence on the exact peaks
    (:func:`~impactdamper.studies.design.tmd.refine_tmd`)."""
    bounds = design_bounds(crit.mu, 1.0)["tmd"]
    d_dh = den_hartog(crit.mu)["delta2"]
    return refine_tmd(crit, search(crit, bounds, budget=budget, seed=seed), bounds, d_dh, budget)


def _snubber(mu, delta1, band, tmd: dict, tmd_stroke: float, tmd_peak: float, workers: int) -> list[dict]:
    """The optimal TMD with a stop put within its own travel (at SNUBBER_FRACTIONS of its
    stroke, restitution SNUBBER_R): its worst branch against the TMD's peak."""
    crit = ImpactCriterion(mu, delta1, band, "peak", Uncertainty(), settings=DESIGN_SETTINGS, workers=workers)
    designs = [{"gap": f * tmd_stroke, **tmd, "R": SNUBBER_R} for f in SNUBBER_FRACTIONS]
    out = []
    for f, x, (w, _) in zip(SNUBBER_FRACTIONS, designs, crit.branches(designs, [Scenario()], "final")):
        out.append(
            {"fraction": f, "parameters": x, "peak": w.peak, "peak_theta": w.peak_theta, "ratio": w.peak / tmd_peak}
        )
    return out


# The design table's rows: (key, device, criterion, the searches' key), in the table's order.
ROWS = (
    ("tmd_peak", "tmd", "peak", "peak"),
    ("impact_peak_reach", "impact", "peak", "peak_reach"),
    ("impact_peak", "impact", "peak", "peak"),
    ("tmd_band_average", "tmd", "band_average", "band_average"),
    ("impact_band_average_reach", "impact", "band_average", "band_average_reach"),
    ("impact_band_average", "impact", "band_average", "band_average"),
    ("tmd_detuning", "tmd", "detuning", "detuning"),
    ("impact_detuning", "impact", "detuning", "detuning"),
    ("impact_force", "impact", "force", "force"),
    ("impact_restitution", "impact", "restitution", "restitution"),
    ("tmd_stroke", "tmd", "stroke", "stroke"),
    ("impact_stroke", "impact", "stroke", "stroke"),
)


def design_optima(
    band: tuple[float, float],
    mu: float,
    delta1: float,
    *,
    uncertainty: Uncertainty | None = None,
    max_stroke: float | None = None,
    criterion: str = "peak",
    stop_stiffness: float = STOP_STIFFNESS,
    natural_frequency: float = NATURAL_FREQUENCY,
    budget: Budget = BUDGET,
    robust_budget: Budget = ROBUST_BUDGET,
    workers: int = WORKERS,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
    robust: bool | None = None,
    subregion_budget: Budget | None = None,
) -> dict:
    """The design table of one object (module docstring): what ``python -m impactdamper
    design --json`` prints and the report's design table shows.

    Parameters
    ----------
    band : (float, float)
        theta = omega/omega1 band (the object's nominal omega1), within :data:`RANGES`.
    mu, delta1 : float
        Mass ratio and the object's damping, within :data:`RANGES`.
    uncertainty : Uncertainty, optional
        Detuning, force band and restitution drift of the robust criteria (default
        :class:`Uncertainty`'s).
    max_stroke : float, optional
        The stroke limit of the stroke-limited rows, over x_st (default STROKE_FRACTION of the
        optimal TMD's stroke).
    criterion : str
        Which rows ``impact`` and ``tmd`` (and ``ratio``) report: ``peak``, ``band_average``,
        ``detuning``, ``force``, ``restitution`` (the others are in ``devices``).
    stop_stiffness, natural_frequency : float
        The contact model's stop stiffness over c1; the object's natural frequency (Hz) at which
        impacts are counted per hour.
    budget, robust_budget : Budget
        The searches' budgets: of the nominal criteria and the stroke limit, and of the robust
        criteria (the same for both devices).
    workers : int
        Processes (>= 1): the answer does not depend on them (its ``workers``, ``elapsed``,
        ``cpu`` and ``longest_silence`` do).
    seed : int
    progress : callable(str), optional
    robust : bool, optional
        Search the robust rows (the impact suppressor optimal for the detuning, the force and
        the restitution; every row's worst peaks under every uncertainty): by default only when
        ``criterion`` is one of them. Without them the nominal answer (peak, band average, travel
        limit, the TMD's detuned optimum) comes in about a minute on two cores; the rows' worst
        peaks then cover the detuning only (the others NaN, named in ``not_evaluated``).
    subregion_budget : Budget, optional
        Every row's answer checked against its box's halves, a lower half's adopted, with this
        budget (:func:`_vouch`; record ``subregions``); none without it (the command's default).

    Returns
    -------
    dict
        ``band``, ``mu``, ``delta1``, ``uncertainty``, ``detuning`` (its part), ``criterion``,
        ``budget``, ``bounds``, ``max_stroke``; ``devices`` (every row: ``device``,
        ``criterion``, ``kind``, ``parameters``, ``peak``, ``peak_theta``, ``peak_branch``,
        ``band_average``, ``worst`` (per uncertainty and ``together``), ``stroke``, the loads,
        ``impacts``, ``tmd_limit``, ``feasible``, ``search`` (the search's record: its check,
        ``at_bound``, evaluations)); ``impact``, ``tmd``, ``tmd_equal_stroke`` (rows); ``ratio``;
        ``snubber``; ``recommendation``; ``elapsed`` (s, wall), ``cpu`` (s, processor time of
        the call and its workers) and ``longest_silence`` (s, wall: the longest wait for a
        ``progress`` message, the call's start and end counting as messages).
    """
    t0, c0 = time.perf_counter(), processor_time()
    unc = Uncertainty() if uncertainty is None else uncertainty
    obj = check_object(band, mu, delta1, unc, max_stroke, stop_stiffness, natural_frequency)
    call = _checked_call(*obj, unc, criterion, workers, robust, progress, stop_stiffness, natural_frequency)
    found = _searches(call, max_stroke, (budget, robust_budget), seed)
    found, sub = _vouch(call, found, (budget, robust_budget), subregion_budget, seed)
    out = {**_table(call, found, (budget, robust_budget)), **({"subregions": sub} if sub else {})}
    out.update(elapsed=time.perf_counter() - t0, cpu=processor_time() - c0, longest_silence=call.say.longest())
    return out


@dataclasses.dataclass(frozen=True)
class _Call:
    """One design call's inputs, checked: the object, its uncertainty, the criterion reported,
    the workers, whether the robust rows are searched, the loads' model, the progress."""

    band: tuple[float, float]
    mu: float
    delta1: float
    uncertainty: Uncertainty
    criterion: str
    workers: int
    robust: bool
    loads: dict
    say: Silences


def _checked_call(
    band, mu, delta1, uncertainty, criterion, workers, robust, progress, stop_stiffness, natural_frequency
) -> _Call:
    """:func:`design_optima`'s arguments past the object's (checked by
    :func:`~impactdamper.studies.design.search_setup.check_object`) checked, one-line errors
    naming the argument; the robust rows by default only for a robust ``criterion``."""
    workers = check_workers(workers)
    choices = ("peak", "band_average", "detuning", "force", "restitution")
    if criterion not in choices:
        raise ValueError(f"`criterion` = {criterion!r} is not allowed: must be one of {', '.join(choices)}")
    return _Call(
        band,
        mu,
        delta1,
        uncertainty,
        criterion,
        workers,
        robust=criterion in ROBUST_SEARCHED if robust is None else bool(robust),
        loads=dict(stop_stiffness=stop_stiffness, natural_frequency=natural_frequency),
        say=Silences(progress or (lambda m: None), shared=workers > 1),
    )


@dataclasses.dataclass(frozen=True)
class _Found:
    """What the searches found: the TMD's and the impact suppressor's results by key, the optimal
    TMD's stroke s_T, the stroke limit S and the boxes."""

    tmd: dict
    impact: dict
    tmd_stroke: float
    max_stroke: float
    bounds: dict


def _searches(call: _Call, max_stroke, budgets: tuple, seed: int) -> _Found:
    """Every search of the table: the TMD's, its stroke setting the boxes and the stroke limit
    (default STROKE_FRACTION of it), the travel-limited TMD, then the impact suppressor's."""
    mu, delta1, band, unc, say = call.mu, call.delta1, call.band, call.uncertainty, call.say
    tmd = _tmd_searches(mu, delta1, band, unc, budgets, seed, say)
    s_T = LinearDevice(mu, tmd["peak"].x["N"], delta1, tmd["peak"].x["delta2"]).stroke_peak(band)[1]
    S = STROKE_FRACTION * s_T if max_stroke is None else float(max_stroke)
    bounds = design_bounds(mu, s_T)
    tmd["stroke"] = optimal_tmd(TmdCriterion(mu, delta1, band, "peak", unc, max_stroke=S), budgets[0], seed)
    say(f"TMD's stroke {s_T:.4g} x_st; the stroke limit {S:.4g}")
    imp = impact_searches(
        mu, delta1, band, unc, bounds, S, tmd["peak"], tmd["stroke"], budgets, seed, call.workers, say, call.robust
    )
    return _Found(tmd, imp, s_T, S, bounds)


def _vouch(call: _Call, found: _Found, budgets: tuple, sub_budget: Budget | None, seed: int) -> tuple:
    """Every row's answer checked against its box's halves and a lower half's adopted
    (:func:`~impactdamper.studies.design.subregions.vouched`, ``call.workers`` rows at a time):
    the searches' results so vouched for, and the check's record (with its times); with no
    ``sub_budget``, ``found`` as it is and None."""
    if sub_budget is None:
        return found, None
    t0, c0 = time.perf_counter(), processor_time()
    call.say("the answers against their boxes' halves")
    results = {"tmd": dict(found.tmd), "impact": dict(found.impact)}
    context = dict(mu=call.mu, delta1=call.delta1, band=call.band, uncertainty=call.uncertainty)
    context["max_stroke"] = found.max_stroke
    tasks = {}
    for key, kind, crit, k in ROWS:
        if k in results[kind]:
            r = results[kind][k]
            box = found.bounds["tmd"] if kind == "tmd" else r.bounds
            local = budgets[1] if crit in ROBUST_SEARCHED else budgets[0]
            tasks[key] = functools.partial(
                vouched, key, kind, crit, r, box, context, (sub_budget, local), seed, call.say
            )
    done = in_parallel(tasks, call.workers)
    for key, kind, _, k in ROWS:
        if key in done:
            results[kind][k] = done[key][0]
    record = summary([v[1] for v in done.values()], sub_budget, seed)
    record.update(elapsed=time.perf_counter() - t0, cpu=processor_time() - c0)
    return dataclasses.replace(found, tmd=results["tmd"], impact=results["impact"]), record


def _table(call: _Call, found: _Found, budgets: tuple) -> dict:
    """The design table from the searches: every row evaluated alike (:func:`_devices`), the
    snubber, the headline rows of ``call.criterion`` and the recommendation."""
    mu, delta1, band, uncertainty = call.mu, call.delta1, call.band, call.uncertainty
    call.say("the table's impact suppressors under every uncertainty")
    evaluated = ROBUST if call.robust else ("detuning",)
    results = {"tmd": found.tmd, "impact": found.impact}
    devices = _devices(mu, delta1, band, uncertainty, results, found.max_stroke, call.workers, call.loads, evaluated)
    call.say("the snubber")
    tmd_peak = device({"devices": devices}, "tmd_peak")["peak"]
    snubber = _snubber(mu, delta1, band, found.tmd["peak"].x, found.tmd_stroke, tmd_peak, call.workers)
    out = {
        "band": list(band),
        "mu": mu,
        "delta1": delta1,
        "uncertainty": uncertainty.to_dict(),
        "detuning": uncertainty.detuning,
        "criterion": call.criterion,
        **_settings(*budgets, call.workers, found.bounds),
        "tmd_stroke": found.tmd_stroke,
        "max_stroke": found.max_stroke,
        **call.loads,
        "devices": devices,
        "snubber": snubber,
        "tmd_equal_peaks": equal_peaks(mu, delta1, found.tmd["peak"].x, band),
        "robust": call.robust,
        "not_evaluated": [name for name in ROBUST if name not in evaluated],
    }
    out.update(headline(out, call.criterion))
    out["recommendation"] = recommendation(out)
    return out


def saved_or_searched(
    saved: str | os.PathLike | None,
    band: tuple[float, float],
    mu: float,
    delta1: float,
    *,
    uncertainty: Uncertainty | None = None,
    progress: Callable[[str], None] | None = None,
    budget: Budget | None = None,
) -> tuple[dict, str]:
    """The design table of one object read from a saved record when it is of this same object,
    band and uncertainty (the workflow saves its own as ``figures/design_optimum.json``: the
    guided notebook shows it instead of searching again), otherwise :func:`design_optima`'s,
    with ``budget`` for every search if given (a smaller one than :data:`BUDGET` answers sooner
    and certifies less: the record states it).

    Returns
    -------
    (dict, str)
        The table, and where it came from (the record's path and budget, or "searched").
    """
    uncertainty = Uncertainty() if uncertainty is None else uncertainty
    if saved is not None and os.path.isfile(saved):
        with open(saved, encoding="utf-8") as f:
            record = json.load(f)
        same = (
            np.allclose(record.get("band", ()), band, rtol=1e-12, atol=0.0)
            and math.isclose(record.get("mu", math.nan), mu, rel_tol=1e-12)
            and math.isclose(record.get("delta1", math.nan), delta1, rel_tol=1e-12)
            and record.get("uncertainty") == json.loads(json.dumps(uncertainty.to_dict()))
        )
        if same:
            return record, f"read from {os.fspath(saved)}"
    budgets = {} if budget is None else {"budget": budget, "robust_budget": budget}
    return design_optima(band, mu, delta1, uncertainty=uncertainty, progress=progress, **budgets), "searched"


def _settings(budget: Budget, robust_budget: Budget, workers: int, bounds: dict) -> dict:
    """How a design record was searched: budgets, workers, boxes, the settled motions' settings."""
    return {
        "budget": budget.to_dict(),
        "robust_budget": robust_budget.to_dict(),
        "workers": workers,
        "bounds": {k: {n: list(v) for n, v in b.items()} for k, b in bounds.items()},
        "settings": {"settle_tol": DESIGN_SETTINGS.settle_tol, "max_periods": DESIGN_SETTINGS.max_periods},
    }


def _devices(mu, delta1, band, uncertainty, results: dict, S: float, workers: int, loads: dict, evaluated) -> list:
    """The design table's rows (:data:`ROWS`, after the bare object) from the searches'
    ``results`` ({"tmd": {key: SearchResult}, "impact": {...}}): the linear ones in closed form,
    the impact suppressors in one batch (:func:`~impactdamper.studies.design.devices.impact_rows`);
    the travel-limited rows with their limit ``S`` and whether they keep it."""
    rows = [r for r in ROWS if r[3] in results[r[1]]]
    impact_keys = [r for r in rows if r[1] == "impact"]
    xs = [results["impact"][k].x for _, _, _, k in impact_keys]
    rows_i = impact_rows(mu, delta1, band, xs, uncertainty, workers=workers, robust=evaluated, **loads)
    rows_i = dict(zip([r[0] for r in impact_keys], rows_i))
    devices = [_record("linear", "reference", "bare object", tmd_row(mu, delta1, band, {}, uncertainty), None)]
    for key, kind, crit_name, k in rows:
        r = results[kind][k]
        row = tmd_row(mu, delta1, band, r.x, uncertainty) if kind == "tmd" else rows_i[key]
        rec = _record(kind, crit_name, key, row, r)
        if crit_name == "stroke":
            rec["max_stroke"] = S
            rec["feasible"] = bool(row["stroke"] <= S * (1.0 + 1e-6))
        devices.append(rec)
    return devices
