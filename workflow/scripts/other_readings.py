"""Tests other readings of the paper's definitions at the stated Delta0/x_st (Timofeev et al.
2019, DOI 10.18698/0236-3941-2019-1-90-100): does any plausible reading reproduce Fig. 2's
behaviour, (a) a negative gap in Algorithm No. 1's orbit and (b) T_c = 2T with three impacts
from Algorithm No. 2, where the stated parameters give neither?

The readings and how each is evaluated: :mod:`impactdamper.studies.replication.readings`.

Outputs: ``figures/other_readings.csv`` (one row per reading) and
``figures/other_readings.json`` (the rows, the random states' motions, the R ranges).
"""

from impactdamper.reporting.records import run_stage, say, write_csv, write_json
from impactdamper.studies.replication import readings as rd


COLUMNS = [
    "id",
    "reading",
    "gap",
    "R",
    "delta1",
    "delta2",
    "mu",
    "alg1_exists",
    "alg1_t1",
    "alg1_t2",
    "alg1_min_gap",
    "claim_a",
    "alg2_regime",
    "alg2_period_multiple",
    "alg2_impacts_per_cycle",
    "claim_b",
    "ivp_claim_a",
    "ivp_claim_b",
    "ivp_cycle_time_diff",
    "ivp_cycle_velocity_diff",
    "ivp_cycle_agree",
    "reproduces",
]


def main(reference: dict, solver: dict, verdict: dict, out_csv, out_json) -> dict:
    """Test every reading (:func:`impactdamper.studies.replication.readings.evaluate_readings`) and write the
    table (``out_csv``) and the result (``out_json``)."""
    rows, result = rd.evaluate_readings(reference, solver, verdict)
    write_csv(out_csv, COLUMNS, rows)
    write_json(out_json, result, sort_keys=False)
    return result


if __name__ == "__main__":
    out = run_stage(snakemake, main, "params.reference params.solver params.verdict output.csv output.json")  # noqa: F821 (injected by Snakemake's script: directive)
    for row in out["readings"]:
        say(f"{row['id']}: claim (a) {row['claim_a']}, claim (b) {row['claim_b']}")
