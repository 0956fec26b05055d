"""Speed of the reference case: the exact solver against the solve_ivp cross-check.

The reference-speed benchmark. In one run, on the paper's reference case (Timofeev et al. 2019,
DOI 10.18698/0236-3941-2019-1-90-100, Fig. 2: theta = 1, mu = 0.08, N = 0.5,
delta1 = delta2 = 0.05, R = 0.7, Delta0/x_st = -5.8, omega = 10 rad/s):

* times (CPU time of the process) ``steady_state(p)`` (Algorithm No. 2 with the exact flow, from the paper's step 1
  until the motion repeats, period detection included), median of ``--repeats`` runs, and the
  bare event-driven ``simulate(p, t_span)`` over the same span;
* times the independent cross-check ``simulate_ivp`` (solve_ivp with event location, DOP853 and
  RK45, rtol = atol = 1e-10, no dense output) over the same simulated span, from the same start;
* measures the impact phases of each against Algorithm No. 1's closed form (eqs. 13-17), whose
  orbit is admissible at this gap: the settled cycle's phase, the largest phase error over the
  impacts of the last ``--tail`` periods of the run (which still holds the transient's last
  ~1e-11 of convergence), and, for the solver error alone, the largest phase error over 20
  periods followed from Algorithm No. 1's exact post-impact state.

Targets: the exact steady state at least 20 times faster than the cross-check and
within 50 ms, with impact phases as accurate or better. The script reports whether they are
met; ``--check`` makes it exit with status 1 when they are not.

Usage: ``python benchmarks/reference_speed.py results/benchmarks/reference_speed.json``
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import scipy

import impactdamper as idp
from impactdamper.baselines.ivp import simulate_ivp

# The benchmark's targets.
SPEEDUP_TARGET = 20.0
EXACT_TIME_TARGET = 0.050  # s
RTOL = ATOL = 1e-10  # the cross-check's tolerances the targets name
# Periods followed on Algorithm No. 1's orbit to measure each solver's own phase error.
ORBIT_PERIODS = 20


def _phase_error(phase: float, reference: float) -> float:
    return abs((phase - reference + 0.5) % 1.0 - 0.5)


def _timed(fn, repeats: int) -> tuple[float, list[float], list[float], object]:
    """Median CPU time of ``repeats`` runs (after a warm-up), the CPU and wall times, the result.

    CPU time (this process only) is what the targets are judged on: on a shared machine the
    wall time also counts the other processes' turns."""
    fn()  # warm-up (imports, caches)
    cpu, wall, result = [], [], None
    for _ in range(repeats):
        c, w = time.process_time(), time.perf_counter()
        result = fn()
        cpu.append(time.process_time() - c)
        wall.append(time.perf_counter() - w)
    return statistics.median(cpu), cpu, wall, result


def _tail_phase_error(impacts, t_from: float, T: float, reference: float) -> tuple[float, int]:
    tail = [e for e in impacts if e.t >= t_from]
    if not tail:
        return math.nan, 0
    return max(_phase_error((e.t / T) % 1.0, reference) for e in tail), len(tail)


def run(repeats: int, ivp_repeats: int, tail: int) -> dict:
    p = idp.Parameters()
    T = p.T
    alg1 = idp.algorithm1(p)
    if not alg1.admissible:
        raise SystemExit("Algorithm No. 1's orbit is not admissible at the reference case: no tight reference")
    reference = alg1.impact_phase

    exact_median, exact_times, exact_wall, steady = _timed(lambda: idp.steady_state(p, backend="python"), repeats)
    k = max(steady.period_multiple, 1)
    # steady_state runs n periods until settled and then one cycle plus one period more.
    t_span = (steady.periods + k + 1) * T
    sim_median, sim_times, sim_wall, traj = _timed(lambda: idp.simulate(p, t_span, backend="python"), repeats)
    t_tail = t_span - tail * T

    out = {
        "case": p.to_dict(),
        "reference_phase_alg1": reference,
        "simulated_span_periods": t_span / T,
        "exact": {
            "steady_state_median_s": exact_median,
            "steady_state_cpu_times_s": exact_times,
            "steady_state_wall_times_s": exact_wall,
            "steady_state_wall_median_s": statistics.median(exact_wall),
            "simulate_median_s": sim_median,
            "simulate_cpu_times_s": sim_times,
            "simulate_wall_times_s": sim_wall,
            "regime": steady.regime,
            "periods_to_settle": steady.periods,
            "events": len(traj.events),
            "phase": steady.impacts[0].phase if steady.impacts else None,
            "phase_error": _phase_error(steady.impacts[0].phase, reference) if steady.impacts else None,
        },
        "crosscheck": {},
    }
    err, n = _tail_phase_error(traj.impacts(), t_tail, T, reference)
    out["exact"]["tail_max_phase_error"], out["exact"]["tail_impacts"] = err, n

    # Solver error alone: start on Algorithm No. 1's orbit (its exact post-impact state) and
    # follow it for ORBIT_PERIODS periods; every impact should fall on the closed-form phase.
    t_imp, after = alg1.t_impact, alg1.state_after
    t_orbit = t_imp + (ORBIT_PERIODS + 0.5) * T
    orbit = idp.simulate(p, t_orbit, t0=t_imp, state=after, backend="python")
    err, n = _tail_phase_error(orbit.impacts(), t_imp + 0.5 * T, T, reference)
    out["exact"]["orbit_max_phase_error"], out["exact"]["orbit_impacts"] = err, n

    for method in ("DOP853", "RK45"):
        median, times, wall, ivp = _timed(
            lambda: simulate_ivp(p, t_span, method=method, rtol=RTOL, atol=ATOL), ivp_repeats
        )
        err, n = _tail_phase_error(ivp.impacts(), t_tail, T, reference)
        last = ivp.impacts()[-1]
        orbit = simulate_ivp(p, t_orbit, t0=t_imp, state=after, method=method, rtol=RTOL, atol=ATOL)
        orbit_err, orbit_n = _tail_phase_error(orbit.impacts(), t_imp + 0.5 * T, T, reference)
        out["crosscheck"][method] = {
            "median_s": median,
            "cpu_times_s": times,
            "wall_times_s": wall,
            "wall_median_s": statistics.median(wall),
            "rtol": RTOL,
            "atol": ATOL,
            "nfev": ivp.nfev,
            "legs": len(ivp.legs),
            "events": len(ivp.events),
            "last_phase": (last.t / T) % 1.0,
            "last_phase_error": _phase_error((last.t / T) % 1.0, reference),
            "tail_max_phase_error": err,
            "tail_impacts": n,
            "orbit_max_phase_error": orbit_err,
            "orbit_impacts": orbit_n,
            "speedup_of_steady_state": median / exact_median,
            "speedup_of_simulate": median / sim_median,
        }

    best = min(out["crosscheck"].values(), key=lambda d: d["median_s"])
    out["targets"] = {
        "speedup_target": SPEEDUP_TARGET,
        "exact_time_target_s": EXACT_TIME_TARGET,
        "speedup_vs_fastest_crosscheck": best["median_s"] / exact_median,
        "speedup_met": best["median_s"] / exact_median >= SPEEDUP_TARGET,
        "exact_time_met": exact_median < EXACT_TIME_TARGET,
        "phase_accuracy_met": all(
            out["exact"]["tail_max_phase_error"] <= d["tail_max_phase_error"]
            and out["exact"]["orbit_max_phase_error"] <= d["orbit_max_phase_error"]
            for d in out["crosscheck"].values()
        ),
    }
    out["machine"] = {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "impactdamper": idp.__version__,
        "platform": platform.platform(),
        "cpu_count": os.cpu_count(),
        "load_average_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        "repeats": repeats,
        "crosscheck_repeats": ivp_repeats,
    }
    return out


def summary(out: dict) -> str:
    e, t = out["exact"], out["targets"]
    lines = [
        f"reference case, {out['simulated_span_periods']:.0f} periods simulated "
        f"(load average {out['machine']['load_average_1min']:.2f} on {out['machine']['cpu_count']} CPUs)",
        "  (CPU time of this process, median of repeats; wall-clock medians in the JSON)",
        f"  exact steady_state  {1e3 * e['steady_state_median_s']:8.2f} ms "
        f"(wall {1e3 * e['steady_state_wall_median_s']:.2f} ms); "
        f"bare simulate {1e3 * e['simulate_median_s']:.2f} ms; {e['regime']}, phase error vs Alg. 1 "
        f"{e['phase_error']:.2e}, last {e['tail_impacts']} impacts max {e['tail_max_phase_error']:.2e}; "
        f"on Alg. 1's orbit ({e['orbit_impacts']} impacts) max {e['orbit_max_phase_error']:.2e}",
    ]
    for method, d in out["crosscheck"].items():
        lines.append(
            f"  solve_ivp {method:6s}    {1e3 * d['median_s']:8.2f} ms (wall {1e3 * d['wall_median_s']:.2f} ms; "
            f"{d['nfev']} f-evals, {d['legs']} legs); "
            f"{d['speedup_of_steady_state']:.1f}x the steady state, {d['speedup_of_simulate']:.1f}x bare simulate; "
            f"phase error: last {d['tail_impacts']} impacts max {d['tail_max_phase_error']:.2e}, "
            f"on Alg. 1's orbit max {d['orbit_max_phase_error']:.2e}"
        )
    lines.append(
        f"  targets: speed-up {t['speedup_vs_fastest_crosscheck']:.1f}x >= {t['speedup_target']:.0f}x: "
        f"{'met' if t['speedup_met'] else 'NOT met'}; exact < {1e3 * t['exact_time_target_s']:.0f} ms: "
        f"{'met' if t['exact_time_met'] else 'NOT met'}; phases as accurate or better: "
        f"{'met' if t['phase_accuracy_met'] else 'NOT met'}"
    )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", type=Path, help="JSON file to write (e.g. results/benchmarks/reference_speed.json)")
    parser.add_argument("--repeats", type=int, default=15, help="timed runs of the exact solver (median)")
    parser.add_argument("--ivp-repeats", type=int, default=5, help="timed runs of each solve_ivp method (median)")
    parser.add_argument("--tail", type=int, default=10, help="final periods whose impacts are checked")
    parser.add_argument("--check", action="store_true", help="exit with status 1 if a target is missed")
    args = parser.parse_args(argv)
    for name in ("repeats", "ivp_repeats", "tail"):
        if getattr(args, name) < 1:
            parser.error(f"argument --{name.replace('_', '-')}: must be >= 1")
    out = run(args.repeats, args.ivp_repeats, args.tail)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(out, indent=2, sort_keys=True) + "\n")
    print(summary(out))
    t = out["targets"]
    return 1 if args.check and not (t["speedup_met"] and t["exact_time_met"] and t["phase_accuracy_met"]) else 0


if __name__ == "__main__":
    sys.exit(main())
