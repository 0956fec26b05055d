"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the Lyapunov stage's
numbers for the report's section on Lyapunov exponents, as LaTeX macros and a booktabs table
(no number is typed by hand).

Outputs ``results/report/lyapunov.json`` (the stage's record, from which the macros and the
README's lines are rendered), ``paper/generated/lyapunov_macros.tex`` (thresholds, run lengths,
the labels of the former np points of the sweep and the map, the checks, the independent
check, the quasi-periodic points against the Neimark-Sacker points),
``paper/generated/lyapunov_benettin_table.tex`` (Benettin's checks) and
``paper/generated/lyapunov_timing.tex`` (the benchmark's CPU times: not deterministic).
"""

from pathlib import Path

from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import read_csv, read_json, run_stage, write_json
from impactdamper.studies.lyapunov.record import RECORD_WHAT, benettin_table, lyapunov_macros, timing


def main(
    lyapunov: dict,
    sweep_csv,
    map_csv,
    checks_json,
    independent_json,
    independent_cpu_json,
    special_csv,
    sweep_table_csv,
    speed_json,
    sweep_timings,
    map_timings,
    out_record,
    out_macros,
    out_table,
    out_timing,
) -> None:
    checks = read_json(checks_json)
    m = lyapunov_macros(
        read_csv(sweep_csv), read_csv(map_csv), checks, lyapunov, read_json(independent_json), read_csv(special_csv),
        read_csv(sweep_table_csv),
    )  # fmt: skip
    write_json(out_record, m.record(RECORD_WHAT), sort_keys=False)
    Path(out_macros).parent.mkdir(parents=True, exist_ok=True)
    Path(out_macros).write_text(render_macros(read_json(out_record)))
    Path(out_table).write_text(benettin_table(checks))
    bench = read_json(speed_json)
    bench["sweep_cpu_s"] = sum(read_json(f)["cpu_s"] for f in sweep_timings)
    bench["map_cpu_s"] = sum(read_json(f)["cpu_s"] for f in map_timings)
    bench["independent_cpu_s"] = read_json(independent_cpu_json)["cpu_s"]
    Path(out_timing).write_text(timing(bench))


JOB = (
    "params.lyapunov input.sweep input.map input.checks input.independent input.independent_cpu input.special input.sweep_table "
    "input.speed input.sweep_timings:list "
    "input.map_timings:list output.record output.macros output.table output.timing"
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
