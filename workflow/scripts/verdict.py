"""The replication verdict on the paper's Fig. 2 (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100): claim by claim, what the stated parameters give (exact
solver, confirmed or not by the independent ``solve_ivp`` integrator), where the claimed
behaviour does occur, and which other readings reproduce it.

The claims (the prose around Fig. 2, at Delta0/x_st = -5.8):

* ``a``: "the gap Delta takes on negative values when t in (t1, t2)" (Algorithm No. 1);
* ``b_period``: "the oscillation period of the system is equal to two periods of external
  influence T_c = 2T" (Algorithm No. 2);
* ``b_impacts``: "during this period T_c there are three collisions" (Algorithm No. 2).

Also notes the transcription slip of eq. (13) (x21s' printed as x1s' - x2s'; eq. 12 defines
x21s = x2s - x1s, which the library follows) and what it would change.

Outputs: ``figures/verdict.json``, ``figures/verdict.csv`` (one row per claim),
``results/report/verdict.json`` (the stage's record of its macros,
:class:`impactdamper.reporting.latex.MacroFile`, from which the TeX file and the README
summary's numbers are rendered) and ``paper/generated/verdict_macros.tex`` (a ``\\newcommand`` for every number the report quotes;
numeric macros are bare numbers for math mode).
"""

from pathlib import Path

from impactdamper.studies.replication import verdict as vd
from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import read_csv, read_json, run_stage, say, write_csv, write_json
from impactdamper.studies.replication.record import claims_macros, macros


CSV_COLUMNS = [
    "claim",
    "paper",
    "stated_gap",
    "stated_result",
    "stated_ivp_result",
    "stated_ivp_difference",
    "ivp_confirms",
    "reproduced",
    "located_gap",
    "located_result",
    "located_ivp_result",
    "located_ivp_difference",
    "located_ivp_confirms",
]


# What the stage's record holds (results/report/verdict.json).
RECORD_WHAT = "the verdict's numbers for the report (paper/generated/verdict_macros.tex) and the README"


def main(
    stated_json,
    located_json,
    cc_stated_json,
    cc_located_json,
    scan_json,
    readings_json,
    claims_json,
    claims_map_csv,
    out_json,
    out_csv,
    out_record,
    out_tex,
) -> dict:
    ref_s, ref_l = read_json(stated_json), read_json(located_json)
    cc_s, cc_l = read_json(cc_stated_json), read_json(cc_located_json)
    scan, rd = read_json(scan_json), read_json(readings_json)
    search = read_json(claims_json)
    cmap = read_csv(claims_map_csv)
    rows, result = vd.verdict(ref_s, ref_l, cc_s, cc_l, scan, rd, search, cmap)
    write_json(out_json, result, sort_keys=False)
    write_csv(out_csv, CSV_COLUMNS, rows)
    record = macros(ref_s, ref_l, cc_s, cc_l, scan, rd, rows).record(RECORD_WHAT)
    dependent = {name: d.get("solver_dependent_ends", []) for name, d in search["parameters"].items()}
    record["entries"] += claims_macros(result["beyond_the_gap"], dependent).entries
    write_json(out_record, record, sort_keys=False)
    Path(out_tex).parent.mkdir(parents=True, exist_ok=True)
    Path(out_tex).write_text(render_macros(read_json(out_record)))
    return result


JOB = (
    "input.stated input.located input.cc_stated input.cc_located input.scan input.readings "
    "input.claims input.claims_map output.json output.csv output.record output.tex"
)

if __name__ == "__main__":
    out = run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
    for row in out["claims"]:
        say(f"{row['claim']}: reproduced {row['reproduced']} (ivp confirms {row['ivp_confirms']})")
