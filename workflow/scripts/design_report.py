"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design stage's numbers
for the report's section "Choosing a suppressor", as LaTeX macros and booktabs tables (no
number is typed by hand).

Outputs ``results/report/design.json`` (the stage's record, from which the macros and the
README's lines are rendered), ``paper/generated/design_macros.tex``, and the tables
``paper/generated/design_table.tex`` (one row per device), ``design_loads_table.tex`` (the impact
suppressors' loads), ``design_second_table.tex`` (best gap against the second parameter) and
``design_benchmark_table.tex`` (the design command's times).
"""

from pathlib import Path

from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import read_json, run_stage, write_json
from impactdamper.studies.design.record import RECORD_WHAT, design_macros
from impactdamper.studies.design.record_tables import benchmark_table, design_table, loads_table, second_table


def main(
    baselines_json,
    chart_json,
    chart2d_json,
    response_json,
    optimum_json,
    checks_json,
    subregions_json,
    benchmark_json,
    out_record,
    out_macros,
    out_table,
    out_design_table,
    out_loads_table,
    out_benchmark_table,
) -> None:
    """Write the stage's record (``out_record``, JSON), from it the macros (``out_macros``), and
    the tables."""
    stage = (baselines_json, chart_json, chart2d_json, response_json, optimum_json, checks_json)
    base, chart, chart2, resp, opt, checks, sub, bench = (
        read_json(x) for x in (*stage, subregions_json, benchmark_json)
    )
    m = design_macros(base, chart, chart2, resp, opt, checks, sub, bench)
    write_json(out_record, m.record(RECORD_WHAT), sort_keys=False)
    Path(out_macros).parent.mkdir(parents=True, exist_ok=True)
    Path(out_macros).write_text(render_macros(read_json(out_record)))
    Path(out_table).write_text(second_table(chart2))
    Path(out_design_table).write_text(design_table(opt))
    Path(out_loads_table).write_text(loads_table(opt))
    Path(out_benchmark_table).write_text(benchmark_table(bench))


JOB = (
    "input.baselines input.chart input.chart2d input.response input.optimum input.checks input.subregions "
    "input.benchmark output.record output.macros output.table output.design_table output.loads_table "
    "output.benchmark_table"
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
