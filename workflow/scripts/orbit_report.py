"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in
the paper): the numbers of the orbits stage for the report.

Reads figures/orbit_branches.csv, figures/orbit_special_points.csv and
figures/orbit_summary.json and writes

* ``results/report/orbits.json``: the stage's record (:class:`impactdamper.reporting.latex.MacroFile`),
  from which the macros below and the README summary's numbers are rendered;
* ``paper/generated/orbit_macros.tex``: one ``\\newcommand`` per number the report quotes.
  Names are ``\\Orbit`` + what + branch (+ ``Low``/``High`` when a kind occurs twice on a
  branch, in order of the gap; ``A``, ``B``, ... beyond two), letters only:

  - special points: ``\\OrbitPDSingle``, ``\\OrbitNSDouble``, ``\\OrbitFoldTriple``,
    ``\\OrbitGrazingTouchDouble`` (the gap's interior minimum reaches the stop: a new impact),
    ``\\OrbitGrazingVanishSingleHigh`` (an impact's closing velocity reaches zero);
  - stretches: ``\\OrbitStableDoubleLow``/``High``/``Width`` (stable and admissible),
    ``\\OrbitAdmissibleDoubleLow``/``High`` (a motion, stable or not);
  - branches: ``\\OrbitLabelDouble`` (z/k), ``\\OrbitSeedGapDouble``;
  - the cases: ``\\OrbitStatedGap``, ``\\OrbitStatedLabel``, ``\\OrbitStatedStable``,
    ``\\OrbitStatedAdmissible``, ``\\OrbitStatedMultA``...``D`` (multiplier moduli, largest
    first), ``\\OrbitStatedRadius``, ``\\OrbitStatedXmax``; the same with ``Located`` and
    each of the config's ``orbits.cases`` (``\\OrbitExampleMultA``: Delta0/x_st = -10).

* ``paper/generated/orbit_special_points_table.tex``: the special points (booktabs).

Numbers are bare (for math mode): gaps to 6 decimals, multipliers to 6 decimals.
"""

from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import read_csv, read_json, run_stage, write_json
from impactdamper.studies.sweeps.orbit_record import macros, table


# What the stage's record holds (results/report/orbits.json).
RECORD_WHAT = "the orbits stage's numbers for the report (paper/generated/orbit_macros.tex) and the README"


def main(branches_csv, special_csv, summary_json, out_record, out_macros, out_table) -> None:
    """Write the stage's record (``out_record``, JSON) and from it the macros (``out_macros``),
    and the special points' table."""
    from pathlib import Path

    branches = read_csv(branches_csv)
    special = read_csv(special_csv)
    summary = read_json(summary_json)
    write_json(out_record, macros(special, summary).record(RECORD_WHAT), sort_keys=False)
    for path, text in (
        (out_macros, render_macros(read_json(out_record))),
        (out_table, table(special, branches, summary)),
    ):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        Path(path).write_text(text)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.branches input.special input.summary output.record output.macros output.table")  # noqa: F821 (injected by Snakemake's script: directive)
