"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in
the paper): the reference-speed benchmark, the exact solver against the solve_ivp cross-check.

On the reference case (Fig. 2), CPU time (medians of repeats) of ``steady_state`` (Algorithm
No. 2 with the exact flow from the paper's step 1 until the motion repeats) and of the bare
``simulate`` over the same span, against ``simulate_ivp`` (DOP853, RK45; rtol = atol = 1e-10)
over that span from the same start, each cross-check run between two exact runs (the speed-up:
the median of these pairs' ratios, ``records.paired_cpu_ratios``); the impact phases of each
against Algorithm No. 1's closed form (eqs. 13-17): the settled cycle's, the largest over the
last ``TAIL_PERIODS`` periods, and (the solver error alone) over ``ORBIT_PERIODS`` periods from
Algorithm No. 1's exact post-impact state. Targets: config ``performance.reference_speed_targets``
(``speedup`` over the fastest cross-check, ``steady_s``), with phases as accurate or better.

Output: ``results/benchmarks/reference_speed.json``. Timings are CPU time and not deterministic.
"""

import functools
import math
import os
import platform
import statistics
import time

import numpy as np
import scipy

import impactdamper as idp
from impactdamper.baselines.ivp import simulate_ivp
from impactdamper.reporting.records import paired_cpu_ratios, start_stage, write_json

RTOL = ATOL = 1e-10  # the cross-check's tolerances the targets name
TAIL_PERIODS = 10  # final periods of the run whose impacts are checked
ORBIT_PERIODS = 20  # periods followed on Algorithm No. 1's orbit to measure each solver's own phase error


def phase_error(phase: float, reference: float) -> float:
    return abs((phase - reference + 0.5) % 1.0 - 0.5)


def timed(fn, repeats: int, prefix: str = "") -> tuple[dict, object]:
    """CPU (this process's only) and wall times of ``repeats`` runs after a warm-up, medians, the result."""
    fn()
    cpu, wall, result = [], [], None
    for _ in range(repeats):
        c, w = time.process_time(), time.perf_counter()
        result = fn()
        cpu.append(time.process_time() - c)
        wall.append(time.perf_counter() - w)
    keys = ("median_s", "cpu_times_s", "wall_times_s", "wall_median_s")
    values = (statistics.median(cpu), cpu, wall, statistics.median(wall))
    return {prefix + k: v for k, v in zip(keys, values)}, result


def max_phase_error(impacts, t_from: float, T: float, reference: float) -> tuple[float, int]:
    """The largest phase error of the impacts from ``t_from`` on, and their number."""
    tail = [e for e in impacts if e.t >= t_from]
    return (max(phase_error((e.t / T) % 1.0, reference) for e in tail), len(tail)) if tail else (math.nan, 0)


def machine(repeats: int, ivp_repeats: int) -> dict:
    """What the timings ran on (the machine is shared: its load beside them) and how often."""
    out = {"python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__}
    out |= {"impactdamper": idp.__version__, "platform": platform.platform(), "cpu_count": os.cpu_count()}
    out["load_average_1min"] = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    return out | {"repeats": repeats, "crosscheck_repeats": ivp_repeats}


def run(repeats: int, ivp_repeats: int, targets: dict) -> dict:
    p = idp.Parameters()
    T, alg1 = p.T, idp.algorithm1(p)
    if not alg1.admissible:
        raise ValueError("Algorithm No. 1's orbit is not admissible at the reference case: no tight reference")
    reference = alg1.impact_phase
    exact_run = functools.partial(idp.steady_state, p, backend="python")
    steady_times, steady = timed(exact_run, repeats, "steady_state_")
    # steady_state runs n periods until settled and then one cycle plus one period more.
    t_span = (steady.periods + max(steady.period_multiple, 1) + 1) * T
    sim_times, traj = timed(lambda: idp.simulate(p, t_span, backend="python"), repeats, "simulate_")
    del sim_times["simulate_wall_median_s"]
    # Each solver's phase errors: over the run's last periods, and (the solver error alone) from
    # Algorithm No. 1's exact post-impact state, where every impact falls on the closed-form phase.
    t_imp, after = alg1.t_impact, alg1.state_after
    t_orbit = t_imp + (ORBIT_PERIODS + 0.5) * T

    def phase_errors(motion, orbit) -> dict:
        tail, n = max_phase_error(motion.impacts(), t_span - TAIL_PERIODS * T, T, reference)
        on_orbit, m = max_phase_error(orbit.impacts(), t_imp + 0.5 * T, T, reference)
        return {"tail_max_phase_error": tail, "tail_impacts": n, "orbit_max_phase_error": on_orbit, "orbit_impacts": m}

    phase = steady.impacts[0].phase
    exact = {**steady_times, **sim_times, "regime": steady.regime, "periods_to_settle": steady.periods}
    exact |= {"events": len(traj.events), "phase": phase, "phase_error": phase_error(phase, reference)}
    exact |= phase_errors(traj, idp.simulate(p, t_orbit, t0=t_imp, state=after, backend="python"))
    crosscheck = {}
    for method in ("DOP853", "RK45"):
        ivp_run = functools.partial(simulate_ivp, p, t_span, method=method, rtol=RTOL, atol=ATOL)
        pairs = paired_cpu_ratios(exact_run, ivp_run, ivp_repeats)
        ivp, median = pairs["result"], statistics.median(pairs["other_cpu_s"])
        orbit = simulate_ivp(p, t_orbit, t0=t_imp, state=after, method=method, rtol=RTOL, atol=ATOL)
        last = (ivp.impacts()[-1].t / T) % 1.0
        crosscheck[method] = {
            "median_s": median,
            "cpu_times_s": pairs["other_cpu_s"],
            "rtol": RTOL,
            "atol": ATOL,
            "nfev": ivp.nfev,
            "legs": len(ivp.legs),
            "events": len(ivp.events),
            "last_phase": last,
            "last_phase_error": phase_error(last, reference),
            **phase_errors(ivp, orbit),
            "speedup_of_steady_state": median / steady_times["steady_state_median_s"],
            "paired_speedups": pairs["ratios"],
            "paired_speedup": pairs["median"],
            "paired_exact_cpu_times_s": pairs["base_cpu_s"],
            "speedup_of_simulate": median / sim_times["simulate_median_s"],
        }
    speedup = min(d["paired_speedup"] for d in crosscheck.values())
    errors = ("tail_max_phase_error", "orbit_max_phase_error")
    return {
        "case": p.to_dict(),
        "reference_phase_alg1": reference,
        "simulated_span_periods": t_span / T,
        "exact": exact,
        "crosscheck": crosscheck,
        "targets": {
            "speedup_target": float(targets["speedup"]),
            "exact_time_target_s": float(targets["steady_s"]),
            "speedup_vs_fastest_crosscheck": speedup,
            "speedup_how": "median over pairs: a cross-check run's CPU time over its two neighbouring exact runs'",
            "speedup_met": speedup >= float(targets["speedup"]),
            "exact_time_met": steady_times["steady_state_median_s"] < float(targets["steady_s"]),
            "phase_accuracy_met": all(exact[k] <= d[k] for d in crosscheck.values() for k in errors),
        },
        "machine": machine(repeats, ivp_repeats),
    }


def main(repeats: int, ivp_repeats: int, targets: dict, output, log=print) -> dict:
    out = run(repeats, ivp_repeats, targets)
    write_json(output, out, indent=2)
    medians = {m: d["median_s"] for m, d in out["crosscheck"].items()}
    log(f"CPU medians (s): exact {out['exact']['steady_state_median_s']:.4g}, solve_ivp {medians}; {out['targets']}")
    return out


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    cfg, lg = start_stage(sm, "reference_speed")
    main(cfg["repeats"], cfg["ivp_repeats"], cfg["targets"], sm.output[0], log=lg.info)
