"""Work-precision study: error against CPU time for every way of computing the motion.

Two test problems on the reference case (Fig. 2 of Timofeev et al. 2019), both measured
against the mpmath reference of :mod:`impactdamper.baselines.highprecision` (40 digits):

``first_impacts``
    From Algorithm No. 2's default start (t = 0, gap zero and opening), the first
    ``n_impacts`` impacts (a shrinking sequence: the motion chatters before it settles).
    Error: max_k |t_k - t_k^ref| / T. A method that finds a different number of impacts in
    the window (the reference's n-th impact plus half the gap to the next) fails: error inf.
``settled_cycle``
    From the settled one-impact orbit, half a period after its impact (state from the mpmath
    fixed point), ``settled_periods`` periods. Error: the larger of max_k |t_k - t_k^ref| / T
    and the end state's max |y_i - y_i^ref| / scale_i (scales x_st, x_st, x_st omega,
    x_st omega).

Methods: every entry of :data:`impactdamper.studies.performance.methods.METHODS` (the exact solver,
Algorithm No. 1 on the settled cycle, the ``solve_ivp`` methods, RK4 with bisection, Siconos's
Moreau-Jean scheme when its Python module is present; the study records plainly whether it
was), each across its own setting, read through one result protocol (``impacts()``,
``state_at(t)``).

Cost is the median over ``repeats`` of the process CPU time (``time.process_time``) of one
call that computes the motion over the window, from the parameters to the list of impacts;
reading the final state out afterwards is not timed. Calls shorter than ``min_time`` are
repeated in a batch (as ``timeit`` does, garbage collection off) and the batch divided.
Siconos's CPU time is measured inside its subprocess (model set-up and time loop; the
interpreter's start and imports excluded). Timings depend on the machine and its load: they
are data of a benchmark, never test assertions, and not part of the deterministic record.
"""

from __future__ import annotations

import gc
import math
import platform
import statistics
import time
from dataclasses import asdict, dataclass, field, fields

import numpy as np

from impactdamper.baselines import highprecision as hp
from impactdamper.core.parameters import Parameters, state_scale
from impactdamper.core.simulate import default_initial_state, simulate
from impactdamper.studies.performance.methods import IVP_METHODS, METHODS, selected  # noqa: F401 (METHODS: the study's table)

__all__ = [
    "CASES",
    "Reference",
    "Run",
    "RUN_COLUMNS",
    "cpu_time",
    "measure",
    "run_study",
    "summarize",
    "cost_to_reach",
    "cost_growth",
    "FAMILIES",
]

CASES = ("first_impacts", "settled_cycle")
# The methods' names (the runs' ``family`` column), in table order.
FAMILIES = tuple(METHODS)
# Siconos takes ~25 us per step in its Python loop: runs beyond this many steps are skipped
# (unless the configuration raises it) to keep the study within minutes.
DEFAULT_MAX_STEPS = 2_000_000


@dataclass(frozen=True)
class Reference:
    """One test problem and its mpmath answer (rounded to double).

    Attributes
    ----------
    case : str
    p : Parameters
    t0, t_end : float
        Window, s.
    state : ndarray, shape (4,)
        (x1, x2, x1', x2') at t0.
    impact_times : ndarray, shape (n,)
        Reference impact times in (t0, t_end), s.
    end_state : ndarray, shape (4,) or None
        Reference state at t_end (settled cycle only).
    impact_phase : float
        Settled cycle: the orbit's impact phase t*/T (nan otherwise).
    """

    case: str
    p: Parameters = field(repr=False)
    t0: float
    t_end: float
    state: np.ndarray = field(repr=False)
    impact_times: np.ndarray = field(repr=False)
    end_state: np.ndarray | None = field(default=None, repr=False)
    impact_phase: float = math.nan

    @property
    def scale(self) -> np.ndarray:
        return state_scale(self.p)

    def to_dict(self) -> dict:
        return {
            "case": self.case,
            "t0": self.t0,
            "t_end": self.t_end,
            "state": self.state.tolist(),
            "impact_times_over_T": (self.impact_times / self.p.T).tolist(),
            "end_state": None if self.end_state is None else self.end_state.tolist(),
            "impact_phase": None if math.isnan(self.impact_phase) else self.impact_phase,
        }


def _build_references(
    p: Parameters, n_impacts: int = 10, settled_periods: int = 10, dps: int = hp.DIGITS
) -> dict[str, Reference]:
    """The two test problems with their mpmath answers.

    The first impacts' brackets come from the exact solver's estimates, certified by the
    high-precision scan (see :mod:`impactdamper.baselines.highprecision`).
    """
    T = p.T
    state0 = default_initial_state(p)
    # One impact more than asked, to place the window's end between impact n and n + 1.
    horizon = T
    while True:
        est = [e.t for e in simulate(p, horizon).impacts()]
        if len(est) > n_impacts or horizon > 1000 * T:
            break
        horizon *= 2
    imps = hp.first_impacts(p, n_impacts + 1, estimates=est[: n_impacts + 1], dps=dps)
    times = np.array([float(e.t) for e in imps])
    t_window = 0.5 * (times[n_impacts - 1] + times[n_impacts])
    first = Reference("first_impacts", p, 0.0, float(t_window), state0, times[:n_impacts])

    cyc = hp.settled_cycle(p, dps=dps)
    t_s = float(cyc.t_impact + cyc.model.T / 2)
    t_e = t_s + settled_periods * T
    settled = Reference(
        "settled_cycle",
        p,
        t_s,
        t_e,
        hp.to_float(cyc.state(t_s)),
        np.array([float(t) for t in cyc.impact_times(t_s, t_e)]),
        hp.to_float(cyc.state(t_e)),
        float(cyc.impact_phase),
    )
    return {"first_impacts": first, "settled_cycle": settled}


@dataclass
class Run:
    """One measured point of the diagram."""

    case: str
    family: str
    setting: str
    value: float
    cpu_seconds: float
    error: float
    phase_error: float
    state_error: float
    impacts_found: int
    impacts_expected: int
    nfev: int = 0
    note: str = ""

    @property
    def ok(self) -> bool:
        return math.isfinite(self.error)


# The columns of the study's CSV record, one row per run: the fields of :class:`Run`.
RUN_COLUMNS = tuple(f.name for f in fields(Run))


def cpu_time(fn, repeats: int = 5, min_time: float = 0.05, long_time: float = 1.0):
    """Median process CPU time of one call of ``fn`` and its (last) result.

    A first call sizes the batch: calls shorter than ``min_time`` are repeated until a batch
    lasts that long, and the batch time divided. A first call longer than ``long_time`` is
    the only measurement.
    """
    start = time.process_time()
    result = fn()
    first = time.process_time() - start
    if first >= long_time:
        return first, result
    batch = max(1, math.ceil(min_time / max(first, 1e-7)))
    times = []
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        for _ in range(max(repeats, 1)):
            start = time.process_time()
            for _ in range(batch):
                result = fn()
            times.append((time.process_time() - start) / batch)
    finally:
        if was_enabled:
            gc.enable()
    return statistics.median(times), result


def _errors(ref: Reference, impact_times, end_state) -> tuple[float, float, float, int]:
    """(error, phase error, state error, impacts found) of one run against the reference."""
    times = np.asarray([t for t in impact_times if ref.t0 < t < ref.t_end], dtype=float)
    n = len(ref.impact_times)
    if len(times) != n:
        return math.inf, math.inf, math.inf, len(times)
    phase = float(np.max(np.abs(times - ref.impact_times)) / ref.p.T) if n else 0.0
    state = math.nan
    if ref.end_state is not None:
        state = float(np.max(np.abs(np.asarray(end_state) - ref.end_state) / ref.scale))
    error = phase if math.isnan(state) else max(phase, state)
    return error, phase, state, len(times)


def _run(ref, family, setting, value, cpu, impact_times, end_state, nfev=0, note="") -> Run:
    err, ph, st, found = _errors(ref, impact_times, end_state)
    if not math.isfinite(err) and not note:
        note = f"found {found} impacts, expected {len(ref.impact_times)}"
    return Run(
        ref.case, family, setting, float(value), float(cpu), err, ph, st, found, len(ref.impact_times), nfev, note
    )


def measure(
    ref: Reference,
    name: str,
    values=(math.nan,),
    repeats: int = 5,
    min_time: float = 0.05,
    max_steps: int = DEFAULT_MAX_STEPS,
    long_time: float = 1.0,
) -> list[Run]:
    """Runs of method ``name`` (:data:`impactdamper.studies.performance.methods.METHODS`) on one problem,
    one per setting in ``values``, each timed (median CPU time, :func:`cpu_time`, a first call
    of at least ``long_time`` s timed alone, unless the method times itself) and its impacts and end state compared with the reference.

    A method of the settled cycle only gives no runs on the first impacts; a method whose
    setting is steps per period skips the runs beyond ``max_steps`` steps; a run that ends in
    an error the method declares is a failed run (error inf) with the error's first line.
    """
    m = METHODS[name]
    if m.settled_only and ref.end_state is None:
        return []
    out = []
    span = (ref.t_end - ref.t0) / ref.p.T
    for v in values:
        if m.steps and v * span > max_steps:
            continue
        solve = lambda: m.solve(ref.p, ref.t_end, ref.t0, ref.state, v, repeats)  # noqa: E731
        try:
            cpu, sol = (math.nan, solve()) if m.times_itself else cpu_time(solve, repeats, min_time, long_time)
        except m.catches as exc:  # a method that loops on chatter or fails to step
            out.append(
                Run(
                    ref.case,
                    name,
                    m.setting,
                    v,
                    math.nan,
                    math.inf,
                    math.inf,
                    math.inf,
                    0,
                    len(ref.impact_times),
                    note=str(exc).splitlines()[0][:120],
                )
            )
            continue
        if sol is None:
            out.append(
                Run(
                    ref.case,
                    name,
                    m.setting,
                    v,
                    cpu,
                    math.inf,
                    math.inf,
                    math.inf,
                    0,
                    len(ref.impact_times),
                    note=m.no_solution,
                )
            )
            continue
        cpu = sol.cpu_seconds if m.times_itself else cpu
        end = sol.state_at(ref.t_end) if ref.end_state is not None else None
        out.append(_run(ref, name, m.setting, v, cpu, sol.impacts(), end, sol.nfev))
    return out


def run_study(p: Parameters, cfg: dict, log=print) -> dict:
    """Every method on both problems; returns a JSON-ready dict.

    ``cfg`` keys (the workflow's ``performance`` section): n_impacts, settled_periods, digits,
    exact_gap_tols, ivp_methods, ivp_rtols, rk4_steps_per_period, siconos_steps_per_period,
    repeats, min_time, long_time, max_steps.
    """
    refs = _build_references(p, cfg["n_impacts"], cfg["settled_periods"], cfg["digits"])
    methods = selected(cfg)
    status = {m.name: m.status() for m in methods}
    repeats, min_time = cfg["repeats"], cfg["min_time"]
    max_steps = cfg.get("max_steps", DEFAULT_MAX_STEPS)
    runs: list[Run] = []
    for case, ref in refs.items():
        for m in methods:
            if not status[m.name][0]:
                continue
            log(f"[{case}] {m.plot_label}")
            values = cfg[m.settings_key] if m.settings_key else (math.nan,)
            runs += measure(ref, m.name, values, repeats, min_time, max_steps, float(cfg.get("long_time", 1.0)))
    available, detail = status.get("Moreau-Jean", METHODS["Moreau-Jean"].status())
    import numpy
    import scipy

    return {
        "parameters": p.to_dict(),
        "config": dict(cfg),
        "references": {k: r.to_dict() for k, r in refs.items()},
        "siconos": {"available": available, "detail": detail},
        "runs": [asdict(r) for r in runs],
        "environment": {
            "python": platform.python_version(),
            "numpy": numpy.__version__,
            "scipy": scipy.__version__,
            "machine": platform.machine(),
            "timer": "time.process_time (median)",
            "note": "timings depend on the machine and its load; not deterministic",
        },
    }


def cost_to_reach(runs: list[dict], target: float) -> float:
    """Cheapest measured CPU time among runs with error <= target (inf if none)."""
    costs = [r["cpu_seconds"] for r in runs if r["error"] <= target and math.isfinite(r["cpu_seconds"])]
    return min(costs) if costs else math.inf


def summarize(study: dict, targets=(1e-6, 1e-10)) -> dict:
    """Per case and method: cost to reach each target, best error and its cost; and the
    exact solver's speed-up over the best ``solve_ivp`` method at each target."""
    out = {}
    runs = study["runs"]
    for case in CASES:
        rows = {}
        for fam in FAMILIES:
            rs = [r for r in runs if r["case"] == case and r["family"] == fam]
            if not rs:
                continue
            finite = [r for r in rs if math.isfinite(r["error"])]
            best = min(finite, key=lambda r: (r["error"], r["cpu_seconds"])) if finite else None
            rows[fam] = {
                "runs": len(rs),
                "failed": len(rs) - len(finite),
                "cost_to_reach": {f"{t:g}": cost_to_reach(rs, t) for t in targets},
                "best_error": best["error"] if best else math.inf,
                "cost_at_best": best["cpu_seconds"] if best else math.inf,
                "min_cost": min((r["cpu_seconds"] for r in finite), default=math.inf),
            }
        speedups = {}
        for t in targets:
            key = f"{t:g}"
            exact = rows.get("exact", {}).get("cost_to_reach", {}).get(key, math.inf)
            ivp = {m: rows[m]["cost_to_reach"][key] for m in IVP_METHODS if m in rows}
            best_m = min(ivp, key=ivp.get) if ivp else None
            best_cost = ivp[best_m] if best_m else math.inf
            speedups[key] = {
                "best_ivp_method": best_m if best_m and math.isfinite(best_cost) else None,
                "best_ivp_cost": best_cost,
                "exact_cost": exact,
                "speedup": best_cost / exact if math.isfinite(best_cost) and math.isfinite(exact) else math.inf,
            }
        out[case] = {"methods": rows, "speedup_vs_best_ivp": speedups}
    return out


def cost_growth(p: Parameters, periods, repeats=3, min_time=0.05, log=print) -> list[dict]:
    """CPU time of :func:`simulate` from the default start over growing windows.

    Returns one row per window: periods, impacts, events, cpu_seconds, and the per-impact and
    per-period costs.
    """
    rows = []
    for n in periods:
        log(f"[cost growth] {p.gap=} {n} periods")
        cpu, traj = cpu_time(lambda: simulate(p, n * p.T), repeats, min_time)
        impacts = len(traj.impacts())
        rows.append(
            {
                "gap": p.gap,
                "periods": int(n),
                "impacts": impacts,
                "events": len(traj.events),
                "cpu_seconds": cpu,
                "per_impact": cpu / impacts if impacts else math.nan,
                "per_period": cpu / n,
            }
        )
    return rows
