"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the sweep stage's
numbers for the report, as LaTeX macros and a booktabs table (no number is typed by hand).

Outputs:

* ``results/report/sweeps.json`` -- the stage's record
  (:class:`impactdamper.reporting.latex.MacroFile`), from which the macros below and the
  README summary's numbers are rendered;
* ``paper/generated/sweep_macros.tex`` -- the sweep's extent and settling cap, the regime
  sequence of each direction, the three closed-form checks, the overlaps of the two sweep
  directions (hysteresis), and the bistable rows of each regime map
  (:func:`impactdamper.studies.sweeps.record.macros`);
* ``paper/generated/sweep_transitions.tex`` -- the main transitions, each identified where
  possible (:func:`impactdamper.studies.sweeps.record.table`; changes inside the chaotic bands
  are in ``figures/sweep_transitions.csv``);
* ``paper/generated/sweep_timing.tex`` -- the benchmarks (wall and processor times measured
  inside the jobs). The only output of the stage that changes from run to run.
"""

from pathlib import Path

from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import read_csv, read_json, run_stage, write_json
from impactdamper.studies.sweeps import record as sweep_record


# What the stage's record holds (results/report/sweeps.json).
RECORD_WHAT = "the sweeps stage's numbers for the report (paper/generated/sweep_macros.tex) and the README"


def report(
    sweep_csv, transitions_csv, checks_json, settings_json, special_csv, maps: dict, out_record, out_macros, out_table
) -> None:
    """The deterministic outputs (the stage's record, JSON; from it the macros; the table), from
    the committed figures/ files. ``maps``: map name -> (map CSV, curves CSV, settings JSON)."""
    rows = read_csv(sweep_csv)
    trans = read_csv(transitions_csv)
    checks_doc = read_json(checks_json)
    record = sweep_record.macros(rows, trans, checks_doc, read_json(settings_json), maps).record(RECORD_WHAT)
    write_json(out_record, record, sort_keys=False)
    Path(out_macros).parent.mkdir(parents=True, exist_ok=True)
    Path(out_macros).write_text(render_macros(read_json(out_record)))
    Path(out_table).write_text(sweep_record.table(rows, trans, checks_doc, read_csv(special_csv)))


def main(
    sweep_csv,
    transitions_csv,
    checks_json,
    sweep_timing,
    map_timings,
    out_record,
    out_macros,
    out_table,
    out_timing,
    *,
    settings_json,
    special_csv,
    map_csvs,
    map_curves,
    map_settings,
) -> None:
    maps = {read_json(s)["map"]: (c, k, s) for c, k, s in zip(map_csvs, map_curves, map_settings)}
    report(sweep_csv, transitions_csv, checks_json, settings_json, special_csv, maps, out_record, out_macros, out_table)
    Path(out_timing).write_text(sweep_record.timing(sweep_timing, map_timings))


JOB = (
    "input.sweep input.transitions input.checks input.sweep_timing input.map_timings:list "
    "output.record output.macros output.table output.timing settings_json=input.settings "
    "special_csv=input.special map_csvs=input.maps:list map_curves=input.map_curves:list "
    "map_settings=input.map_settings:list"
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
