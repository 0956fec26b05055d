"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design stage's numbers
for the report's section "Choosing a suppressor", as LaTeX macros and a booktabs table (no
number is typed by hand).

Outputs ``results/report/design.json`` (the stage's record, from which the macros and the
README's lines are rendered), ``paper/generated/design_macros.tex`` (the design table's optima,
located peaks, worst cases, strokes, loads and the recommendation; the chart's best gap, good
band, loads, checks), ``paper/generated/design_table.tex`` (the design table: one row per
device) and ``paper/generated/design_second_table.tex`` (best gap against the second parameter).
"""

from pathlib import Path

from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import read_json, run_stage, write_json
from impactdamper.studies.design.record import RECORD_WHAT, design_macros, design_table, second_table


def main(
    baselines_json,
    chart_json,
    chart2d_json,
    response_json,
    response_csv,
    optimum_json,
    out_record,
    out_macros,
    out_table,
    out_design_table,
) -> None:
    """Write the stage's record (``out_record``, JSON), from it the macros (``out_macros``), the
    second-parameter table (``out_table``) and the design table (``out_design_table``)."""
    base, chart, chart2, resp = (read_json(x) for x in (baselines_json, chart_json, chart2d_json, response_json))
    optimum = read_json(optimum_json)
    m = design_macros(base, chart, chart2, resp, optimum, response_csv)
    write_json(out_record, m.record(RECORD_WHAT), sort_keys=False)
    Path(out_macros).parent.mkdir(parents=True, exist_ok=True)
    Path(out_macros).write_text(render_macros(read_json(out_record)))
    Path(out_table).write_text(second_table(chart2))
    Path(out_design_table).write_text(design_table(optimum))


JOB = (
    "input.baselines input.chart input.chart2d input.response input.response_csv input.optimum "
    "output.record output.macros output.table output.design_table"
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
