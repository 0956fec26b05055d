"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in
the paper): the numbers of the performance study for the report.

Reads the work-precision study, the cost growth, the hard cases and the reference-speed
benchmark (results/benchmarks/*.json), and the compiled solver's benchmark
(figures/compiled_speed.json, workflow/scripts/compiled_speed.py), and writes

* ``results/report/performance.json``: the stage's record
  (:class:`impactdamper.reporting.latex.MacroFile`), from which the macros below and the
  README summary's numbers are rendered;
* ``paper/generated/performance_macros.tex``: one ``\\newcommand`` per number the report
  quotes (speed-ups against the best solve_ivp method at equal error, costs, best errors,
  error floors, per-impact cost, hard-case counts, and each target as a number, for the
  report to state beside the measured one; the compiled solver's numbers each with its target
  and a word, "met" or "not met", computed here from the two);
* ``paper/generated/workprecision_table.tex``: per method and problem, the CPU time to reach
  each target error, the best error reached and its cost (booktabs);
* ``paper/generated/compiled_speed_table.tex``: the compiled solver's numbers, each beside its
  target and the word (booktabs);
* ``results/benchmarks/performance_summary.json``: the same numbers, machine-readable.

All timings are CPU time on the machine that ran the workflow: not deterministic.
"""

import math
from pathlib import Path

from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import json_float, read_json, start_stage, write_json
from impactdamper.studies.performance_record import compiled_table, macros, table  # noqa: F401 (the tests')
from impactdamper.studies.workprecision import met, report_summary

# The compiled solver's map whose wall time has a target (the benchmark's MAP_TIME_TARGET_S).
COMPILED_MAP_TARGET_SIZE = "200x200"
# What the stage's record holds (results/report/performance.json).
RECORD_WHAT = "the performance stage's numbers for the report (paper/generated/performance_macros.tex) and the README"


def compiled_speed(cs: dict) -> dict:
    """The compiled solver's benchmark (figures/compiled_speed.json): each number with its
    target and whether it is met (judged here, from the two)."""
    pi, st, f10, c = cs["per_impact"], cs["steady_state"], cs["first_10_impacts"], cs["compile"]
    tg = st["targets"]
    phase = max(json_float(st["phase_error_vs_alg1"]), json_float(st["phase_error_vs_python"]))
    out = {
        "us_per_impact": {
            "value": json_float(pi["compiled"]["us_per_impact_min"]),
            "target": json_float(pi["target_us"]),
            "at_most": True,
        },
        "steady_seconds": {
            "value": json_float(st["compiled"]["cpu_min_s"]),
            "target": json_float(tg["time_s"]),
            "at_most": True,
        },
        "steady_speedup": {
            "value": json_float(st["speedup_vs_dop853"]),
            "target": json_float(tg["speedup"]),
            "at_most": False,
        },
        "steady_phase_error": {"value": phase, "target": json_float(tg["phase"]), "at_most": True},
        "first_speedup": {
            "value": json_float(f10["speedup_vs_dop853"]),
            "target": json_float(f10["target_speedup"]),
            "at_most": False,
        },
    }
    name = COMPILED_MAP_TARGET_SIZE if COMPILED_MAP_TARGET_SIZE in cs["maps"] else next(iter(cs["maps"]))
    m = cs["maps"][name]
    target = m.get("target_s")
    out["map_wall"] = {
        "value": json_float(m["wall_min_s"]),
        "target": json_float(target) if target else math.inf,
        "at_most": True,
    }
    # Where users are: the public calls (impactdamper.steady_state, steady_states) and the CLI.
    fd = cs["front_door"]
    out["public_steady"] = {
        "value": json_float(fd["steady_state"]["auto"]["wall_median_s"]),
        "target": json_float(fd["steady_state"]["target_s"]),
        "at_most": True,
    }
    out["batch_ratio"] = {
        "value": json_float(fd["batch"]["ratio"]),
        "target": json_float(fd["batch"]["target_ratio"]),
        "at_most": True,
    }
    out["cli_wall"] = {
        "value": json_float(fd["cli"]["wall_median_s"]),
        "target": json_float(fd["cli"]["target_s"]),
        "at_most": True,
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
    # (None where the record holds no compile times: main() adds rule performance_compile_time's.)
    out["compile_seconds"] = json_float(c["cold_compile_s"]) if c else None
    out["cache_load_seconds"] = json_float(c["cached_load_s"]) if c else None
    return out


def summarize(wp: dict, growth: dict, hard: dict, ref: dict, perf: dict, cs: dict) -> dict:
    """The stage's summary (:func:`impactdamper.studies.workprecision.report_summary`) and the
    compiled solver's benchmark judged against its targets (:func:`compiled_speed`)."""
    return {**report_summary(wp, growth, hard, ref, perf), "compiled_speed": compiled_speed(cs)}


def main(
    performance: dict,
    in_wp,
    in_growth,
    in_hard,
    in_ref,
    in_compiled,
    out_record,
    out_macros,
    out_table,
    out_compiled_table,
    out_summary,
    in_compile_time=None,
) -> dict:
    """Write the summary, the stage's record (``out_record``, JSON) and from it the macros
    (``out_macros``), the work-precision table and the compiled solver's table. The JIT compile
    times come from ``in_compile_time`` (a ``--compile-only`` run of the benchmark) where the
    benchmark's record has none."""
    wp = read_json(in_wp)
    compiled = read_json(in_compiled)
    if compiled.get("compile") is None:
        if in_compile_time is None:
            raise ValueError("the compiled benchmark's record has no compile times: give `in_compile_time`")
        compiled["compile"] = read_json(in_compile_time)["compile"]
    s = summarize(wp, read_json(in_growth), read_json(in_hard), read_json(in_ref), performance, compiled)
    write_json(out_summary, s)
    write_json(out_record, macros(s, performance, wp).record(RECORD_WHAT), sort_keys=False)
    Path(out_macros).parent.mkdir(parents=True, exist_ok=True)
    Path(out_macros).write_text(render_macros(read_json(out_record)))
    Path(out_table).write_text(table(wp, performance))
    Path(out_compiled_table).write_text(compiled_table(s["compiled_speed"]))
    return s


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    cfg, log = start_stage(sm, "performance_report")
    log.info("writing %s", sm.output.macros)
    main(
        cfg["performance"],
        sm.input.work_precision,
        sm.input.cost_growth,
        sm.input.hardcases,
        sm.input.reference_speed,
        sm.input.compiled_speed,
        sm.output.record,
        sm.output.macros,
        sm.output.table,
        sm.output.compiled_table,
        sm.output.summary,
        in_compile_time=sm.input.compile_time,
    )
