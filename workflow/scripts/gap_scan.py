"""Locates where the behaviour of the paper's Fig. 2 occurs (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100), scanning Delta0/x_st with the other parameters as stated.

The paper claims, at Delta0/x_st = -5.8: (a) Algorithm No. 1 gives a gap below zero on
(t1, t2) (Fig. 2a); (b) Algorithm No. 2 gives T_c = 2T with three impacts per cycle (Fig. 2b).
This script runs :func:`impactdamper.studies.replication.gapscan.locate` (whose module docstring says
how) over the config's ``verdict`` window and writes the records.

Outputs: ``figures/gap_scan.csv`` (the Algorithm No. 2 grid with both claims) and
``figures/located_case.json`` (the ranges, their ends with brackets, the overlap, the
located case, the directly solved orbit's range and the cross-checks).
"""

from impactdamper.reporting.records import run_stage, say, write_csv, write_json
from impactdamper.studies.replication import gapscan


SCAN_COLUMNS = [
    "gap",
    "alg1_exists",
    "alg1_min_gap",
    "alg1_t1",
    "alg1_t2",
    "claim_a",
    "alg2_regime",
    "alg2_period_multiple",
    "alg2_impacts_per_cycle",
    "alg2_periods",
    "claim_b",
    "both",
]


def main(reference: dict, solver: dict, verdict: dict, out_csv, out_json, workers: int = 1) -> dict:
    """Locate the case (:func:`impactdamper.studies.replication.gapscan.locate`) and write the grid
    (``out_csv``) and the result (``out_json``)."""
    rows, result = gapscan.locate(reference, solver, verdict, workers)
    write_csv(out_csv, SCAN_COLUMNS, rows)
    write_json(out_json, result, sort_keys=False)
    return result


JOB = "params.reference params.solver params.verdict output.csv output.json workers=threads"

if __name__ == "__main__":
    out = run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
    say(f"claim (a) ranges {[(r['lo'], r['hi']) for r in out['claim_a_ranges']]}")
    say(f"claim (b) ranges {[(r['lo'], r['hi']) for r in out['claim_b_ranges']]}")
    say(f"both {[(r['lo'], r['hi']) for r in out['both_ranges']]}; located {out['located']['gap']}")
