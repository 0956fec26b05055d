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
record (``best_found`` where they disagree by more than 0.5 %).
The boxes are derived from the object: with s_T the stroke of its optimal TMD,

* the impact suppressor's gap Delta0/x_st in [-s_T, 1.5 s_T] (a stop preloaded by the TMD's
  own travel to one beyond it: there the device is a TMD that never reaches its stop, the
  *TMD limit*), and, *with its stop within reach*, in [-s_T, s_T];
* N in [N_LOW, N_HIGH] times Den Hartog's 1/(1 + mu); delta2 in [0, DELTA2_HIGH times his
  sqrt(3 mu/(8 (1 + mu)^3))] (the TMD's delta2 from DELTA2_LOW of that); R in [0.2, 0.95]
  (a polymer pad to hardened steel);
* under the stroke limit S (default STROKE_FRACTION of the optimal TMD's stroke) the impact
  suppressor's gap at most S (its travel towards the stop is the gap); the TMD's delta2 up to a
  locked absorber (:mod:`~impactdamper.studies.design.tmd`), so that a box bound never decides
  whether a TMD can keep the limit.

The answer over the whole box is seeded with, and never worse than, the one with the stop
within reach. Every row of the table is then evaluated alike: located worst branch, band
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
import scipy.stats

from impactdamper.analysis.linear_device import LinearDevice, check_band, den_hartog
from impactdamper.analysis.parallel import check_workers
from impactdamper.core.validation import finite_argument
from impactdamper.studies.design.devices import (
    ROBUST,
    DESIGN_SETTINGS,
    IMPACT_NAMES,
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
from impactdamper.studies.design.search import Budget, SearchResult, search
from impactdamper.studies.design.tasks import Silences, in_parallel, processor_time
from impactdamper.studies.design.tmd import equal_peaks, refine_tmd
from impactdamper.studies.design.verdict import device, headline, recommendation

__all__ = [
    "RANGES",
    "BUDGET",
    "WORKERS",
    "check_object",
    "design_bounds",
    "optimal_tmd",
    "design_optima",
    "saved_or_searched",
    "SNUBBER_FRACTIONS",
    "SNUBBER_R",
    "STROKE_FRACTION",
    "design_options",
    "ROBUST_BUDGET",
]

# The search's budget, the same for both devices and every criterion (what a minute on two
# cores buys: see the design benchmark).
BUDGET = Budget(
    samples=128, starts=2, polls=10, first_step=1 / 8, last_step=1 / 128, coarse_above=1 / 32, polish=30, checks=6
)
# The robust and travel-limited searches' budget: the nominal one, their global stage one
# shared sample of the whole box evaluated under every robust criterion's scenarios.
ROBUST_BUDGET = BUDGET
# Designs of the shared sample per batch (a progress line after each).
SAMPLE_BATCH = 32
# The nominal criteria, and the robust criteria searched (the others are evaluated for every
# design: the table's columns).
CRITERIA_NOMINAL = ("peak", "band_average")
ROBUST_SEARCHED = ("detuning", "force", "restitution")
# The box's sides relative to Den Hartog's optimum (module docstring).
N_LOW, N_HIGH = 0.2, 1.5
DELTA2_LOW, DELTA2_HIGH = 0.01, 3.0
R_BOX = (0.2, 0.95)
GAP_FULL = 1.5
# The stroke limit of the stroke-limited rows, by default: this fraction of the optimal TMD's.
STROKE_FRACTION = 0.7
# The snubber: a stop put within the optimal TMD's own travel, at these fractions of its stroke,
# with this restitution.
SNUBBER_FRACTIONS = (0.5, 0.75, 0.9)
SNUBBER_R = 0.5


def _in_range(name: str, value: object, unit: str = "") -> float:
    lo, hi = RANGES[name]
    v = finite_argument(name, value)
    if not lo <= v <= hi:
        raise ValueError(f"`{name}` = {v!r} is not allowed: must be in [{lo:g}, {hi:g}]{unit}")
    return v


def check_object(band, mu, delta1, uncertainty: Uncertainty, max_stroke, stop_stiffness, natural_frequency) -> tuple:
    """The command's inputs within :data:`RANGES` (one-line errors naming the input and its
    range). Returns (band, mu, delta1)."""
    try:
        a, b = band
    except (TypeError, ValueError):
        raise ValueError(f"`band` = {band!r} is not allowed: must be (theta_start, theta_stop)") from None
    a, b = _in_range("theta_start", a), _in_range("theta_stop", b)
    if not RANGES["band_width"][0] <= b - a <= RANGES["band_width"][1]:
        lo, hi = RANGES["band_width"]
        raise ValueError(
            f"`theta_stop` = {b!r} is not allowed: the band theta_stop - theta_start must be in [{lo:g}, {hi:g}] "
            f"(theta_start = {a!r})"
        )
    mu, delta1 = _in_range("mu", mu), _in_range("delta1", delta1)
    _in_range("detuning", uncertainty.detuning)
    _in_range("force_low", uncertainty.force[0])
    _in_range("force_high", uncertainty.force[1])
    _in_range("restitution_drift", uncertainty.restitution)
    _in_range("stiffness_drift", uncertainty.stiffness)
    _in_range("damping_drift", uncertainty.damping)
    _in_range("stop_stiffness", stop_stiffness, " (times the object's spring c1)")
    _in_range("natural_frequency", natural_frequency, " Hz")
    if max_stroke is not None:
        s = finite_argument("max_stroke", max_stroke)
        if not s > 0:
            raise ValueError(f"`max_stroke` = {s!r} is not allowed: must be > 0 (x_st)")
    return check_band((a, b)), mu, delta1


def design_bounds(mu: float, tmd_stroke: float) -> dict:
    """The boxes of the search (module docstring): ``tmd``, ``impact`` (the whole box) and
    ``impact_reach`` (the stop within reach), from the object's mass ratio and its optimal TMD's
    stroke."""
    dh = den_hartog(mu)
    n_dh, d_dh = dh["N"], dh["delta2"]
    N = (N_LOW * n_dh, N_HIGH * n_dh)
    impact = dict(zip(IMPACT_NAMES, ((-tmd_stroke, GAP_FULL * tmd_stroke), N, (0.0, DELTA2_HIGH * d_dh), R_BOX)))
    return {
        "tmd": {"N": N, "delta2": (DELTA2_LOW * d_dh, DELTA2_HIGH * d_dh)},
        "impact": impact,
        "impact_reach": {**impact, "gap": (-tmd_stroke, tmd_stroke)},
    }


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


def _impact_searches(mu, delta1, band, unc, bounds, max_stroke, tmd, stroke_tmd, budgets, seed, workers, say, robust):
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
    uncertainty = Uncertainty() if uncertainty is None else uncertainty
    band, mu, delta1 = check_object(band, mu, delta1, uncertainty, max_stroke, stop_stiffness, natural_frequency)
    workers = check_workers(workers)
    choices = ("peak", "band_average", "detuning", "force", "restitution")
    if criterion not in choices:
        raise ValueError(f"`criterion` = {criterion!r} is not allowed: must be one of {', '.join(choices)}")
    say = Silences(progress or (lambda m: None), shared=workers > 1)
    robust = criterion in ROBUST_SEARCHED if robust is None else bool(robust)
    budgets = (budget, robust_budget)
    tmd = _tmd_searches(mu, delta1, band, uncertainty, budgets, seed, say)
    s_T = LinearDevice(mu, tmd["peak"].x["N"], delta1, tmd["peak"].x["delta2"]).stroke_peak(band)[1]
    S = STROKE_FRACTION * s_T if max_stroke is None else float(max_stroke)
    bounds = design_bounds(mu, s_T)
    tmd["stroke"] = optimal_tmd(TmdCriterion(mu, delta1, band, "peak", uncertainty, max_stroke=S), budget, seed)
    say(f"TMD's stroke {s_T:.4g} x_st; the stroke limit {S:.4g}")
    imp = _impact_searches(
        mu, delta1, band, uncertainty, bounds, S, tmd["peak"], tmd["stroke"], budgets, seed, workers, say, robust
    )
    say("the table's impact suppressors under every uncertainty")
    loads = dict(stop_stiffness=stop_stiffness, natural_frequency=natural_frequency)
    evaluated = ROBUST if robust else ("detuning",)
    devices = _devices(mu, delta1, band, uncertainty, {"tmd": tmd, "impact": imp}, S, workers, loads, evaluated)
    say("the snubber")
    snubber = _snubber(mu, delta1, band, tmd["peak"].x, s_T, device({"devices": devices}, "tmd_peak")["peak"], workers)
    out = {
        "band": list(band),
        "mu": mu,
        "delta1": delta1,
        "uncertainty": uncertainty.to_dict(),
        "detuning": uncertainty.detuning,
        "criterion": criterion,
        **_settings(budget, robust_budget, workers, bounds),
        "tmd_stroke": s_T,
        "max_stroke": S,
        **loads,
        "devices": devices,
        "snubber": snubber,
        "tmd_equal_peaks": equal_peaks(mu, delta1, tmd["peak"].x, band),
        "robust": robust,
        "not_evaluated": [name for name in ROBUST if name not in evaluated],
    }
    out.update(headline(out, criterion))
    out["recommendation"] = recommendation(out)
    out["elapsed"] = time.perf_counter() - t0
    out["cpu"] = processor_time() - c0
    out["longest_silence"] = say.longest()
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


def design_options(design: dict) -> dict:
    """:func:`design_optima`'s options from the config's ``design`` section: the uncertainties
    (``detuning``, ``force_band``, ``restitution_drift``) and the budgets (``search_samples``,
    ``search_starts``, ``search_polls``, ``search_polish``, ``robust_polls``,
    ``robust_polish``, ``search_checks``; the steps are :data:`BUDGET`'s). With the shipped config they
    are the command's defaults, so that the design table is what ``design --json`` prints."""
    budget = dataclasses.replace(
        BUDGET,
        samples=int(design["search_samples"]),
        starts=int(design["search_starts"]),
        polls=int(design["search_polls"]),
        polish=int(design["search_polish"]),
        checks=int(design["search_checks"]),
    )
    robust = dataclasses.replace(
        budget,
        polls=int(design["robust_polls"]),
        polish=int(design["robust_polish"]),
        checks=int(design["search_checks"]),
    )
    low, high = (float(x) for x in design["force_band"])
    unc = Uncertainty(
        float(design["detuning"]),
        (low, high),
        float(design["restitution_drift"]),
        float(design.get("stiffness_drift", Uncertainty.stiffness)),
        float(design.get("damping_drift", Uncertainty.damping)),
    )
    return {"uncertainty": unc, "budget": budget, "robust_budget": robust}
