"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in
the paper): how the exact solver's cost grows with the simulated time and with the number of
impacts, data only (the figure is drawn by fig_cost_growth.py).

For each gap of ``performance.growth_gaps`` (the reference case's -5.8: one impact per
period once settled; -10: three impacts per two periods; -13: chatter, ~10 impacts and a
contact phase per period) Algorithm No. 2 runs from its default start over each span of
``performance.growth_periods``; CPU time (median of repeats), impacts and events are
recorded. If the cost per impact is flat, the cost is linear in the number of impacts: the
fitted exponent of cost against impacts (log-log least squares) says how close to 1 it is.

Outputs: ``results/benchmarks/cost_growth.json`` and ``figures/cost_growth.csv``. Timings
are CPU time and not deterministic.
"""

import numpy as np

from impactdamper.studies.config import parameters
from impactdamper.reporting.records import run_stage, write_csv, write_json
from impactdamper.studies.performance import workprecision as wp


CSV_COLUMNS = ["gap", "periods", "impacts", "events", "cpu_seconds", "per_impact", "per_period"]


def fit_exponent(rows: list[dict]) -> float:
    """Least-squares slope of log(cpu) against log(impacts)."""
    x = np.log([r["impacts"] for r in rows if r["impacts"] > 0])
    y = np.log([r["cpu_seconds"] for r in rows if r["impacts"] > 0])
    return float(np.polyfit(x, y, 1)[0]) if len(x) >= 2 else float("nan")


def main(reference: dict, performance: dict, out_json, out_csv, log=print) -> dict:
    base = parameters(reference)
    rows = []
    for gap in performance["growth_gaps"]:
        rows += wp.cost_growth(
            base.replace(gap=float(gap)),
            performance["growth_periods"],
            repeats=performance["repeats"],
            min_time=performance["min_time"],
            log=log,
        )
    per_impact = [r["per_impact"] for r in rows if r["impacts"] > 0]
    summary = {
        "exponent_cost_vs_impacts": fit_exponent(rows),
        "per_impact_median": float(np.median(per_impact)),
        "per_impact_min": float(np.min(per_impact)),
        "per_impact_max": float(np.max(per_impact)),
        "per_impact_spread": float(np.max(per_impact) / np.min(per_impact)),
        "per_gap": {
            str(g): {
                "exponent_cost_vs_impacts": fit_exponent([r for r in rows if r["gap"] == g]),
                "per_impact_median": float(np.median([r["per_impact"] for r in rows if r["gap"] == g])),
            }
            for g in sorted({r["gap"] for r in rows})
        },
        "note": "CPU time (time.process_time), medians; not deterministic",
    }
    write_json(out_json, {"rows": rows, "summary": summary, "parameters": base.to_dict()})
    write_csv(out_csv, CSV_COLUMNS, rows, booleans="python", float_format=None)
    log(
        f"per-impact cost {summary['per_impact_min'] * 1e6:.0f}-{summary['per_impact_max'] * 1e6:.0f} us, "
        f"exponent {summary['exponent_cost_vs_impacts']:.3f}"
    )
    return summary


JOB = "params.reference params.performance output.json output.csv log=log.info"
STAGE = {"logger": "cost_growth"}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
