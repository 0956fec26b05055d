"""The performance stage's numbers judged against their targets: per problem the exact
solver's best error and cost against every other method's and its speed-up at each target
error; the cost growth, the hard cases and the reference-speed benchmark; and the compiled
solver's benchmark, each number beside its target and whether it is met (judged here, from the
two). The stage's record (:mod:`impactdamper.studies.performance.record`) renders it.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper). All timings are CPU time on the machine that ran the workflow: not deterministic.
"""

from __future__ import annotations

import math

from impactdamper.reporting.records import json_float
from impactdamper.studies.performance.methods import IVP_METHODS, reported_alone

__all__ = ["met", "compiled_speed", "summarize", "COMPILED_MAP_TARGET_SIZE"]


def met(value: float, target: float, at_most: bool) -> str:
    """ "met" or "not met": ``value`` against ``target`` (an upper bound if ``at_most``, else
    a lower one); "---" when either is missing."""
    if value is None or target is None or not (math.isfinite(value) and math.isfinite(target)):
        return "---"
    return "met" if (value <= target if at_most else value >= target) else "not met"


def _meets(value: float, target: float, at_most: bool) -> bool:
    """Whether ``value`` meets ``target`` (:func:`met`); never where either is missing."""
    return met(value, target, at_most) == "met"


def _report_summary(wp: dict, growth: dict, hard: dict, ref: dict, perf: dict) -> dict:
    """The performance stage's numbers for the report: per problem, the exact solver's best
    error and cost, the best ``solve_ivp`` error, each other method's best error and cost,
    and at each target error the speed-up over the best ``solve_ivp`` method (and over RK4)
    judged against ``perf["speedup_target"]``; the cost growth, the hard cases and the
    reference-speed benchmark.

    Parameters
    ----------
    wp : dict
        The study (:func:`run_study`) with its ``summary`` (:func:`summarize`).
    growth, hard, ref : dict
        The cost growth, hard-case and reference-speed benchmarks' records.
    perf : dict
        The ``performance`` config section (targets, speedup_target, phase_target).
    """
    targets = [float(t) for t in perf["targets"]]
    out = {"targets": targets, "siconos": wp["siconos"], "cases": {}}
    for case, s in wp["summary"].items():
        methods = s["methods"]
        exact = methods["exact"]
        ivp_best = {m: json_float(methods[m]["best_error"]) for m in IVP_METHODS if m in methods}
        best_ivp_method = min(ivp_best, key=ivp_best.get) if ivp_best else None
        c = {
            "exact_best_error": json_float(exact["best_error"]),
            "exact_cost": json_float(exact["min_cost"]),
            "exact_phase_target_met": _meets(
                json_float(exact["best_error"]), float(perf["phase_target"]), at_most=True
            ),
            "best_ivp_error": ivp_best.get(best_ivp_method, math.inf) if best_ivp_method else math.inf,
            "best_ivp_error_method": best_ivp_method,
            "levels": {},
        }
        for key in reported_alone():
            if key in methods:
                c[f"{key}_best_error"] = json_float(methods[key]["best_error"])
                c[f"{key}_min_cost"] = json_float(methods[key]["min_cost"])
        for t in targets:
            sp = s["speedup_vs_best_ivp"][f"{t:g}"]
            speedup = json_float(sp["speedup"])
            rk4 = json_float(methods["RK4"]["cost_to_reach"][f"{t:g}"]) if "RK4" in methods else math.inf
            exact_t = json_float(exact["cost_to_reach"][f"{t:g}"])
            c["levels"][f"{t:g}"] = {
                "speedup": speedup,
                "best_ivp_method": sp["best_ivp_method"],
                "best_ivp_cost": json_float(sp["best_ivp_cost"]),
                "exact_cost": exact_t,
                "speedup_met": _meets(speedup, float(perf["speedup_target"]), at_most=False),
                "speedup_vs_rk4": rk4 / exact_t if math.isfinite(rk4) and math.isfinite(exact_t) else math.inf,
            }
        out["cases"][case] = c
    out["cost_growth"] = growth["summary"]
    out["hardcases"] = {
        "passed": hard["passed"],
        "total": hard["total"],
        "slowest": max(hard["cases"], key=lambda r: json_float(r["cpu_seconds"]))["case"],
        "slowest_seconds": max(json_float(r["cpu_seconds"]) for r in hard["cases"]),
        "total_seconds": sum(json_float(r["cpu_seconds"]) for r in hard["cases"]),
        "failed": [r["case"] for r in hard["cases"] if not r["passed"]],
    }
    ex, tg, cross = ref.get("exact", {}), ref.get("targets", {}), ref.get("crosscheck", {})
    fastest = min(cross, key=lambda m: cross[m]["median_s"]) if cross else None
    out["reference_speed"] = {
        "steady_state_seconds": json_float(ex.get("steady_state_median_s")),
        "speedup_vs_fastest_crosscheck": json_float(tg.get("speedup_vs_fastest_crosscheck")),
        "speedup_target": json_float(tg.get("speedup_target")),
        "exact_time_target_s": json_float(tg.get("exact_time_target_s")),
        "speedup_met": bool(tg.get("speedup_met", False)),
        "exact_time_met": bool(tg.get("exact_time_met", False)),
        "fastest_crosscheck": fastest,
        "crosscheck_rtol": json_float(cross[fastest]["rtol"]) if fastest else math.inf,
        "phase_error": json_float(ex.get("phase_error")),
    }
    return out


# The compiled solver's map whose wall time has a target (the benchmark's MAP_TIME_TARGET_S).
COMPILED_MAP_TARGET_SIZE = "200x200"


def compiled_speed(cs: dict) -> dict:
    """The compiled solver's benchmark (figures/compiled_speed.json): each number with its
    target and whether it is met (judged here, from the two)."""
    pi, st, f10, c = cs["per_impact"], cs["steady_state"], cs["first_10_impacts"], cs["compile"]
    name = COMPILED_MAP_TARGET_SIZE if COMPILED_MAP_TARGET_SIZE in cs["maps"] else next(iter(cs["maps"]))
    m = cs["maps"][name]
    target = m.get("target_s")
    fd = cs["front_door"]
    out = {
        **_solver_targets(pi, st, f10),
        "map_wall": _target(m["wall_min_s"], json_float(target) if target else math.inf, True),
        # Where users are: the public calls (impactdamper.steady_state, steady_states) and the CLI.
        "public_steady": _target(fd["steady_state"]["auto"]["wall_median_s"], fd["steady_state"]["target_s"], True),
        "batch_ratio": _target(fd["batch"]["ratio"], fd["batch"]["target_ratio"], True),
        "cli_wall": _target(fd["cli"]["wall_median_s"], fd["cli"]["target_s"], True),
    }
    for v in out.values():
        v["met"] = met(v["value"], v["target"], v["at_most"])
    out["map"] = {
        "grid": m["grid"],
        "workers": m["workers"],
        "rescue": m["rescue"],
        "cpu_s": json_float(m["cpu_total_min_s"]),
        "nonperiodic_share": json_float(m["nonperiodic_share"]),
        "nonperiodic_share_rescued": json_float(m["nonperiodic_share_rescued"]),
        "rescue_cpu_s": json_float(m["rescue_run"]["cpu_s"]),
    }
    out["first_speedup_packed_once"] = json_float(f10["speedup_vs_dop853_packed_once"])
    out["public_steady_python"] = json_float(fd["steady_state"]["python"]["wall_median_s"])
    out["batch_points"] = fd["batch"]["points"]
    out["batch_us_per_point"] = json_float(fd["batch"]["us_per_point_public"])
    out["import_seconds"] = json_float(fd["cli"]["import_median_s"])
    out["import_loads_numba"] = bool(fd["cli"]["import_loads_numba"])
    out["steady_periods"] = st["periods"]
    out["first_impacts"] = f10["impacts"]
    out["per_impact_impacts"] = pi["compiled"]["impacts"]
    # The same run's other solvers per impact: the machine's speed beside the absolute targets.
    out["python_us_per_impact"] = json_float(pi["python"]["us_per_impact_min"])
    out["dop853_us_per_impact"] = json_float(pi["dop853"]["us_per_impact_min"])
    out.update(_compile_times(c))
    return out


def _target(value, target, at_most: bool) -> dict:
    """A benchmark number beside its target: ``at_most`` if it must not exceed it, else reach it."""
    return {"value": json_float(value), "target": json_float(target), "at_most": at_most}


def _solver_targets(pi: dict, st: dict, f10: dict) -> dict:
    """The solver's own targets: time per impact, the settled motion's time, speed-up and phase
    error, the first impacts' speed-up."""
    tg = st["targets"]
    phase = max(json_float(st["phase_error_vs_alg1"]), json_float(st["phase_error_vs_python"]))
    return {
        "us_per_impact": _target(pi["compiled"]["us_per_impact_min"], pi["target_us"], True),
        "steady_seconds": _target(st["compiled"]["cpu_min_s"], tg["time_s"], True),
        "steady_speedup": _target(st["speedup_vs_dop853"], tg["speedup"], False),
        "steady_phase_error": _target(phase, tg["phase"], True),
        "first_speedup": _target(f10["speedup_vs_dop853"], f10["target_speedup"], False),
    }


def _compile_times(c: dict) -> dict:
    """The compile and cache-load times (None where the record holds none: main() adds rule
    performance_compile_time's), where the compile was measured, and the run's own warm-up."""
    return {
        "compile_seconds": json_float(c["cold_compile_s"]) if c else None,
        "cache_load_seconds": json_float(c["cached_load_s"]) if c else None,
        "compile_measured": c.get("measured", "workflow") if c else None,
        "run_warm_up_seconds": json_float(c["run_warm_up_s"]) if c and "run_warm_up_s" in c else None,
    }


def summarize(wp: dict, growth: dict, hard: dict, ref: dict, perf: dict, cs: dict) -> dict:
    """The stage's summary (:func:`report_summary`) and the compiled solver's benchmark judged
    against its targets (:func:`compiled_speed`)."""
    return {**_report_summary(wp, growth, hard, ref, perf), "compiled_speed": compiled_speed(cs)}
