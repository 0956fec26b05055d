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
* ``paper/generated/compiled_speed_table.tex``: the compiled solver's speed beside the
  pure-Python solver's and DOP853's on the same runs (booktabs; its targets and their words stay
  in the record, for the repository's benchmark page, docs/BENCHMARKS.md);
* ``results/benchmarks/performance_summary.json``: the same numbers, machine-readable.

All timings are CPU time on the machine that ran the workflow: not deterministic.
"""

from pathlib import Path

from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import read_json, run_stage, write_json
from impactdamper.studies.performance.record import compiled_table, macros, table
from impactdamper.studies.performance.summary import (  # noqa: F401 (the tests import them from here)
    compiled_speed,
    met,
    summarize,
)


# What the stage's record holds (results/report/performance.json).
RECORD_WHAT = "the performance stage's numbers for the report (paper/generated/performance_macros.tex) and the README"


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
    in_warm_up=None,
) -> dict:
    """Write the summary, the stage's record (``out_record``, JSON) and from it the macros
    (``out_macros``), the work-precision table and the compiled solver's table. The JIT compile
    times come from ``in_compile_time`` (the set-up's record, or rule performance_compile_time's
    in the run: its ``measured`` says which) where the benchmark's record has none; the run's own
    warm-up (loading the kernels from numba's cache, or compiling them where it was stale) from
    ``in_warm_up`` (rule compiled_warm_up's record)."""
    wp = read_json(in_wp)
    compiled = read_json(in_compiled)
    if compiled.get("compile") is None:
        if in_compile_time is None:
            raise ValueError("the compiled benchmark's record has no compile times: give `in_compile_time`")
        record = read_json(in_compile_time)
        compiled["compile"] = dict(record["compile"], measured=record.get("measured", "workflow"))
    if in_warm_up is not None:
        compiled["compile"] = dict(compiled["compile"], run_warm_up_s=read_json(in_warm_up)["seconds"])
    s = summarize(wp, read_json(in_growth), read_json(in_hard), read_json(in_ref), performance, compiled)
    write_json(out_summary, s)
    write_json(out_record, macros(s, performance, wp).record(RECORD_WHAT), sort_keys=False)
    Path(out_macros).parent.mkdir(parents=True, exist_ok=True)
    Path(out_macros).write_text(render_macros(read_json(out_record)))
    Path(out_table).write_text(table(wp, performance))
    Path(out_compiled_table).write_text(compiled_table(s["compiled_speed"]))
    return s


JOB = (
    "params.performance input.work_precision input.cost_growth input.hardcases "
    "input.reference_speed input.compiled_speed output.record output.macros output.table "
    "output.compiled_table output.summary in_compile_time=input.compile_time in_warm_up=input.warm_up"
)
STAGE = {"logger": "performance_report"}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
