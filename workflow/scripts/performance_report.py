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

from impactdamper.reporting.latex import MacroFile, render_macros, tex_escape, tex_sci, tex_time
from impactdamper.reporting.records import json_float, read_json, start_stage, write_json

CASE_MACRO = {"first_impacts": "First", "settled_cycle": "Settled"}
CASE_TITLE = {"first_impacts": "First {n} impacts from Algorithm No.~2's start (error: impact times, units of $T$)",
              "settled_cycle": "{m} periods on the settled cycle (error: impact times and final state)"}
FAMILY_LABEL = {"exact": "exact, Alg.~2 (this work)", "alg1": "Alg.~1, closed form (this work)",
                "RK45": r"\texttt{solve\_ivp} RK45", "DOP853": r"\texttt{solve\_ivp} DOP853",
                "Radau": r"\texttt{solve\_ivp} Radau", "LSODA": r"\texttt{solve\_ivp} LSODA",
                "RK4": "RK4, fixed step + bisection", "Moreau-Jean": "Moreau--Jean (Siconos)"}
IVP = ("RK45", "DOP853", "Radau", "LSODA")
LEVEL = ("Low", "High")  # the two targets, in config order
# The compiled solver's map whose wall time has a target (the benchmark's MAP_TIME_TARGET_S).
COMPILED_MAP_TARGET_SIZE = "200x200"


def _m(x) -> str:
    return rf"\ensuremath{{{tex_sci(x)}}}"


def _yes(b: bool) -> str:
    return "yes" if b else "no"


def _speedup(x: float) -> str:
    return "---" if not math.isfinite(x) else f"{x:.1f}"


def met(value: float, target: float, at_most: bool) -> str:
    """ "met" or "not met": ``value`` against ``target`` (an upper bound if ``at_most``, else
    a lower one); "---" when either is missing."""
    if value is None or target is None or not (math.isfinite(value) and math.isfinite(target)):
        return "---"
    return "met" if (value <= target if at_most else value >= target) else "not met"


def compiled_speed(cs: dict) -> dict:
    """The compiled solver's benchmark (figures/compiled_speed.json): each number with its
    target and whether it is met (judged here, from the two)."""
    pi, st, f10, c = cs["per_impact"], cs["steady_state"], cs["first_10_impacts"], cs["compile"]
    tg = st["targets"]
    phase = max(json_float(st["phase_error_vs_alg1"]), json_float(st["phase_error_vs_python"]))
    out = {
        "us_per_impact": {"value": json_float(pi["compiled"]["us_per_impact_min"]), "target": json_float(pi["target_us"]),
                          "at_most": True},
        "steady_seconds": {"value": json_float(st["compiled"]["cpu_min_s"]), "target": json_float(tg["time_s"]),
                           "at_most": True},
        "steady_speedup": {"value": json_float(st["speedup_vs_dop853"]), "target": json_float(tg["speedup"]),
                           "at_most": False},
        "steady_phase_error": {"value": phase, "target": json_float(tg["phase"]), "at_most": True},
        "first_speedup": {"value": json_float(f10["speedup_vs_dop853"]), "target": json_float(f10["target_speedup"]),
                          "at_most": False},
    }
    name = COMPILED_MAP_TARGET_SIZE if COMPILED_MAP_TARGET_SIZE in cs["maps"] else next(iter(cs["maps"]))
    m = cs["maps"][name]
    target = m.get("target_s")
    out["map_wall"] = {"value": json_float(m["wall_min_s"]), "target": json_float(target) if target else math.inf,
                       "at_most": True}
    # Where users are: the public calls (impactdamper.steady_state, steady_states) and the CLI.
    fd = cs["front_door"]
    out["public_steady"] = {"value": json_float(fd["steady_state"]["auto"]["wall_median_s"]),
                            "target": json_float(fd["steady_state"]["target_s"]), "at_most": True}
    out["batch_ratio"] = {"value": json_float(fd["batch"]["ratio"]), "target": json_float(fd["batch"]["target_ratio"]),
                          "at_most": True}
    out["cli_wall"] = {"value": json_float(fd["cli"]["wall_median_s"]), "target": json_float(fd["cli"]["target_s"]),
                       "at_most": True}
    for v in out.values():
        v["met"] = met(v["value"], v["target"], v["at_most"])
    out["map"] = {"grid": m["grid"], "workers": m["workers"], "rescue": m["rescue"], "cpu_s": json_float(m["cpu_total_min_s"]),
                  "nonperiodic_share": json_float(m["nonperiodic_share"]),
                  "nonperiodic_share_rescued": json_float(m["nonperiodic_share_rescued"]),
                  "rescue_cpu_s": json_float(m["rescue_run"]["cpu_s"])}
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
    targets = [float(t) for t in perf["targets"]]
    out = {"targets": targets, "siconos": wp["siconos"], "cases": {}}
    for case, s in wp["summary"].items():
        methods = s["methods"]
        exact = methods["exact"]
        ivp_best = {m: json_float(methods[m]["best_error"]) for m in IVP if m in methods}
        best_ivp_method = min(ivp_best, key=ivp_best.get) if ivp_best else None
        c = {
            "exact_best_error": json_float(exact["best_error"]),
            "exact_cost": json_float(exact["min_cost"]),
            "exact_phase_target_met": json_float(exact["best_error"]) <= float(perf["phase_target"]),
            "best_ivp_error": ivp_best.get(best_ivp_method, math.inf) if best_ivp_method else math.inf,
            "best_ivp_error_method": best_ivp_method,
            "levels": {},
        }
        for key in ("alg1", "RK4", "Moreau-Jean"):
            if key in methods:
                c[f"{key}_best_error"] = json_float(methods[key]["best_error"])
                c[f"{key}_min_cost"] = json_float(methods[key]["min_cost"])
        for t in targets:
            sp = s["speedup_vs_best_ivp"][f"{t:g}"]
            speedup = json_float(sp["speedup"])
            rk4 = json_float(methods["RK4"]["cost_to_reach"][f"{t:g}"]) if "RK4" in methods else math.inf
            exact_t = json_float(exact["cost_to_reach"][f"{t:g}"])
            c["levels"][f"{t:g}"] = {
                "speedup": speedup, "best_ivp_method": sp["best_ivp_method"], "best_ivp_cost": json_float(sp["best_ivp_cost"]),
                "exact_cost": exact_t, "speedup_met": math.isfinite(speedup) and speedup >= float(perf["speedup_target"]),
                "speedup_vs_rk4": rk4 / exact_t if math.isfinite(rk4) and math.isfinite(exact_t) else math.inf,
            }
        out["cases"][case] = c
    out["cost_growth"] = growth["summary"]
    out["hardcases"] = {"passed": hard["passed"], "total": hard["total"],
                        "slowest": max(hard["cases"], key=lambda r: json_float(r["cpu_seconds"]))["case"],
                        "slowest_seconds": max(json_float(r["cpu_seconds"]) for r in hard["cases"]),
                        "total_seconds": sum(json_float(r["cpu_seconds"]) for r in hard["cases"]),
                        "failed": [r["case"] for r in hard["cases"] if not r["passed"]]}
    ex, tg, cross = ref.get("exact", {}), ref.get("targets", {}), ref.get("crosscheck", {})
    fastest = min(cross, key=lambda m: cross[m]["median_s"]) if cross else None
    out["reference_speed"] = {"steady_state_seconds": json_float(ex.get("steady_state_median_s")),
                              "speedup_vs_fastest_crosscheck": json_float(tg.get("speedup_vs_fastest_crosscheck")),
                              "speedup_target": json_float(tg.get("speedup_target")),
                              "exact_time_target_s": json_float(tg.get("exact_time_target_s")),
                              "speedup_met": bool(tg.get("speedup_met", False)),
                              "exact_time_met": bool(tg.get("exact_time_met", False)),
                              "fastest_crosscheck": fastest,
                              "crosscheck_rtol": json_float(cross[fastest]["rtol"]) if fastest else math.inf,
                              "phase_error": json_float(ex.get("phase_error"))}
    out["compiled_speed"] = compiled_speed(cs)
    return out


# What the stage's record holds (results/report/performance.json).
RECORD_WHAT = "the performance stage's numbers for the report (paper/generated/performance_macros.tex) and the README"


def macros(s: dict, perf: dict, wp: dict) -> MacroFile:
    lines = MacroFile(["% Numbers of the performance study, Timofeev et al. (2019) extension.",
             "% Generated by workflow/scripts/performance_report.py (Snakemake rule performance_report); do not edit.",
             "% Timings are CPU time on the machine that ran the workflow: not deterministic."])
    add = lines.add
    add("PerfDigits", perf["digits"])
    add("PerfNImpacts", perf["n_impacts"])
    add("PerfSettledPeriods", perf["settled_periods"])
    for lev, t in zip(LEVEL, s["targets"]):
        add(f"PerfTarget{lev}", _m(t))
    add("PerfSpeedupTarget", f"{float(perf['speedup_target']):g}")
    add("PerfPhaseTarget", _m(float(perf["phase_target"])))
    rtols = [float(r) for r in perf.get("ivp_rtols", [])]
    add("PerfIvpRtolMax", _m(max(rtols)) if rtols else "---")
    add("PerfIvpRtolMin", _m(min(rtols)) if rtols else "---")
    add("PerfSiconosAvailable", _yes(s["siconos"]["available"]))
    sic = [r for r in wp["runs"] if r["family"] == "Moreau-Jean"]
    add("PerfSiconosDetail", tex_escape(s["siconos"]["detail"]).replace("/", "/\\allowbreak "))
    add("PerfSiconosRuns", len(sic))
    for case, c in s["cases"].items():
        C = CASE_MACRO[case]
        add(f"Perf{C}ExactError", _m(c["exact_best_error"]))
        add(f"Perf{C}ExactCost", tex_time(c["exact_cost"]))
        add(f"Perf{C}BestIvpError", _m(c["best_ivp_error"]))
        add(f"Perf{C}BestIvpErrorMethod", c["best_ivp_error_method"] or "---")
        for key, name in (("alg1", "AlgOne"), ("RK4", "RkFour"), ("Moreau-Jean", "MoreauJean")):
            if f"{key}_best_error" in c:
                add(f"Perf{C}{name}Error", _m(c[f"{key}_best_error"]))
                add(f"Perf{C}{name}Cost", tex_time(c[f"{key}_min_cost"]))
        for lev, t in zip(LEVEL, s["targets"]):
            L = c["levels"][f"{t:g}"]
            add(f"Perf{C}Speedup{lev}", _speedup(L["speedup"]))
            add(f"Perf{C}BestIvp{lev}", L["best_ivp_method"] or "none")
            add(f"Perf{C}BestIvpCost{lev}", tex_time(L["best_ivp_cost"]))
            add(f"Perf{C}ExactCost{lev}", tex_time(L["exact_cost"]))
            add(f"Perf{C}SpeedupRkFour{lev}", _speedup(L["speedup_vs_rk4"]))
    g = s["cost_growth"]
    add("PerfCostPerImpact", tex_time(g["per_impact_median"]))
    add("PerfCostPerImpactMin", tex_time(g["per_impact_min"]))
    add("PerfCostPerImpactMax", tex_time(g["per_impact_max"]))
    add("PerfCostPerImpactSpread", f"{g['per_impact_spread']:.2f}")
    add("PerfCostExponent", f"{g['exponent_cost_vs_impacts']:.3f}")
    h = s["hardcases"]
    add("PerfHardCasesTotal", h["total"])
    add("PerfHardCasesPassed", h["passed"])
    add("PerfHardCasesSlowest", tex_escape(h["slowest"]))
    add("PerfHardCasesSlowestTime", tex_time(h["slowest_seconds"]))
    add("PerfHardCasesTotalTime", tex_time(h["total_seconds"]))
    r = s["reference_speed"]
    add("PerfRefSteadyTime", tex_time(r["steady_state_seconds"]))
    add("PerfRefSpeedup", _speedup(r["speedup_vs_fastest_crosscheck"]))
    add("PerfRefSpeedupTarget", f"{r['speedup_target']:g}" if math.isfinite(r["speedup_target"]) else "---")
    add("PerfRefTimeTarget", tex_time(r["exact_time_target_s"]))
    add("PerfRefCrosscheckMethod", r["fastest_crosscheck"] or "---")
    add("PerfRefCrosscheckRtol", _m(r["crosscheck_rtol"]))
    add("PerfRefPhaseError", _m(r["phase_error"]))
    c = s["compiled_speed"]
    for key, name, fmt in (("us_per_impact", "UsPerImpact", lambda x: rf"{x:.2g}\,\textmu s"),
                           ("steady_seconds", "SteadyTime", tex_time),
                           ("steady_speedup", "SteadySpeedup", lambda x: f"{x:.0f}"),
                           ("steady_phase_error", "PhaseError", _m),
                           ("first_speedup", "FirstSpeedup", lambda x: f"{x:.0f}"),
                           ("map_wall", "MapWall", tex_time),
                           ("public_steady", "PublicSteady", tex_time),
                           ("batch_ratio", "BatchRatio", lambda x: f"{x:.2f}"),
                           ("cli_wall", "CliWall", tex_time)):
        add(f"PerfCompiled{name}", fmt(c[key]["value"]))
        add(f"PerfCompiled{name}Target", fmt(c[key]["target"]) if math.isfinite(c[key]["target"]) else "---")
        add(f"PerfCompiled{name}Met", c[key]["met"])
    add("PerfCompiledFirstSpeedupPacked", f"{c['first_speedup_packed_once']:.0f}")
    add("PerfCompiledPublicSteadyPython", tex_time(c["public_steady_python"]))
    add("PerfCompiledBatchPoints", f"{c['batch_points']:,}".replace(",", "{,}"))
    add("PerfCompiledBatchUsPerPoint", tex_time(1e-6 * c["batch_us_per_point"]))
    add("PerfCompiledImportTime", tex_time(c["import_seconds"]))
    add("PerfCompiledImportNumba", "loads" if c["import_loads_numba"] else "does not load")
    add("PerfCompiledSteadyPeriods", c["steady_periods"])
    add("PerfCompiledFirstImpacts", c["first_impacts"])
    add("PerfCompiledImpacts", c["per_impact_impacts"])
    add("PerfCompiledPythonUsPerImpact", tex_time(1e-6 * c["python_us_per_impact"]))
    add("PerfCompiledDopUsPerImpact", tex_time(1e-6 * c["dop853_us_per_impact"]))
    add("PerfCompiledDopRatioPerImpact", f"{c['dop853_us_per_impact'] / c['us_per_impact']['value']:.0f}")
    add("PerfCompiledMapCells", rf"{c['map']['grid'][0]}~$\times$~{c['map']['grid'][1]}")
    add("PerfCompiledMapWorkers", c["map"]["workers"])
    add("PerfCompiledMapCpu", tex_time(c["map"]["cpu_s"]))
    add("PerfCompiledMapNonperiodic", f"{100 * c['map']['nonperiodic_share']:.1f}\\,\\%")
    add("PerfCompiledMapNonperiodicRescued", f"{100 * c['map']['nonperiodic_share_rescued']:.1f}\\,\\%")
    add("PerfCompiledMapRescueCpu", tex_time(c["map"]["rescue_cpu_s"]))
    add("PerfCompiledCompileTime", tex_time(c["compile_seconds"]))
    add("PerfCompiledCacheLoad", tex_time(c["cache_load_seconds"]))
    return lines


def table(wp: dict, perf: dict) -> str:
    targets = [float(t) for t in perf["targets"]]
    head = " & ".join([r"Method"] + [rf"to ${tex_sci(t, 1)}$" for t in targets] + ["Best error", "its cost"])
    lines = ["% CPU time per run to reach each error, best error reached (work-precision study).",
             "% Generated by workflow/scripts/performance_report.py (Snakemake rule performance_report); do not edit.",
             "% Timings are CPU time on the machine that ran the workflow: not deterministic.",
             r"\begin{tabular}{l" + "r" * (len(targets) + 2) + "}", r"\toprule", head + r" \\"]
    ncol = len(targets) + 3
    for case, s in wp["summary"].items():
        title = CASE_TITLE[case].format(n=perf["n_impacts"], m=perf["settled_periods"])
        lines += [r"\midrule", rf"\multicolumn{{{ncol}}}{{l}}{{\emph{{{title}}}}} \\", r"\midrule"]
        for fam, label in FAMILY_LABEL.items():
            if fam not in s["methods"]:
                if fam == "Moreau-Jean" and not wp["siconos"]["available"]:
                    lines.append(rf"{label} & \multicolumn{{{ncol - 1}}}{{l}}{{not available: {tex_escape(wp['siconos']['detail'])}}} \\")
                continue
            m = s["methods"][fam]
            cells = [tex_time(json_float(m["cost_to_reach"][f"{t:g}"])) for t in targets]
            best = json_float(m["best_error"])
            cells += [rf"${tex_sci(best)}$" if math.isfinite(best) else "---", tex_time(json_float(m["cost_at_best"]))]
            lines.append(" & ".join([label] + cells) + r" \\")
    lines += [r"\bottomrule", r"\end{tabular}", ""]
    return "\n".join(lines)


# The compiled solver's table: (row title, macro name part, the target's bound), in order.
COMPILED_ROWS = (
    (r"cost per impact (\PerfCompiledImpacts{} impacts)", "UsPerImpact", r"$\le$ "),
    (r"reference case's steady state (\PerfCompiledSteadyPeriods{} periods)", "SteadyTime", r"$\le$ "),
    (r"\quad speed-up over DOP853", "SteadySpeedup", r"$\ge$ "),
    (r"\quad phase error, units of $T$", "PhaseError", r"$\le$ "),
    (r"first \PerfCompiledFirstImpacts{} impacts, speed-up over DOP853", "FirstSpeedup", r"$\ge$ "),
    (r"regime map \PerfCompiledMapCells{}, wall time on \PerfCompiledMapWorkers{} processes", "MapWall", r"$\le$ "),
    (r"\texttt{impactdamper.steady\_state(Parameters())}, median wall", "PublicSteady", r"$\le$ "),
    (r"\texttt{steady\_states}, \PerfCompiledBatchPoints{} points, time over the kernels'", "BatchRatio", r"$\le$ "),
    (r"\texttt{python -m impactdamper steady --json}, wall (warm cache)", "CliWall", r"$\le$ "),
)


def compiled_table(c: dict) -> str:
    """The compiled solver's numbers beside their targets (``c``: the summary's compiled_speed,
    read for which targets exist): every number a macro of the record."""
    def cell(name: str) -> str:
        return rf"\Perf{name}{{}}"

    lines = ["% The compiled solver against its targets (workflow/scripts/compiled_speed.py); every number a macro of",
             "% performance_macros.tex. Generated by workflow/scripts/performance_report.py (Snakemake rule",
             "% performance_report); do not edit. Timings are not deterministic.",
             r"\begin{tabular}{lrrl}", r"\toprule", r"Measure & this run & target & \\", r"\midrule"]
    keys = {"UsPerImpact": "us_per_impact", "SteadyTime": "steady_seconds", "SteadySpeedup": "steady_speedup",
            "PhaseError": "steady_phase_error", "FirstSpeedup": "first_speedup", "MapWall": "map_wall",
            "PublicSteady": "public_steady", "BatchRatio": "batch_ratio", "CliWall": "cli_wall"}
    for title, name, bound in COMPILED_ROWS:
        target = cell(f"Compiled{name}Target")
        if not math.isfinite(c[keys[name]]["target"]):
            bound = ""  # no target at this size: the macro says ---
        lines.append(rf"{title} & {cell(f'Compiled{name}')} & {bound}{target} & \PerfCompiled{name}Met{{}} \\")
    lines += [r"JIT compile from scratch (from the cache) & \PerfCompiledCompileTime{} (\PerfCompiledCacheLoad{}) & --- & \\",
              r"\bottomrule", r"\end{tabular}", ""]
    return "\n".join(lines)


def main(performance: dict, in_wp, in_growth, in_hard, in_ref, in_compiled, out_record, out_macros, out_table,
         out_compiled_table, out_summary, in_compile_time=None) -> dict:
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
    main(cfg["performance"], sm.input.work_precision, sm.input.cost_growth, sm.input.hardcases,
         sm.input.reference_speed, sm.input.compiled_speed, sm.output.record, sm.output.macros, sm.output.table,
         sm.output.compiled_table, sm.output.summary, in_compile_time=sm.input.compile_time)
