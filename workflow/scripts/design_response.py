"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the frequency response of
the impact suppressor (upward and downward theta sweeps) at the best gap of the design chart
and at the gaps the config names (the paper's -5.8 among them), with the exact linear response
without a stop beside it.

Outputs ``figures/design_response.csv`` (per gap, theta and direction: regime, max|x1|, max|x2|,
impacts per period, pulses, energies, hysteresis) and ``figures/design_response.json`` (per gap:
peak, band average, loads, hysteresis count, the energy balance's largest mismatch).
"""

import logging

import numpy as np

from impactdamper.analysis.response import frequency_response
from impactdamper.analysis.sweeps import with_value
from impactdamper.reporting.records import read_json, run_stage, write_csv, write_json
from impactdamper.studies.config import sweep_settings
from impactdamper.studies.design.design import design_band, design_parameters, response_gaps


COLUMNS = [
    "gap",
    "theta",
    "direction",
    "regime",
    "label",
    "period_multiple",
    "max_abs_x1",
    "max_abs_x2",
    "impacts_per_period",
    "mean_impulse",
    "peak_impulse",
    "energy_input",
    "energy_impacts",
    "energy_dampers",
    "balance",
    "drift",
    "hysteresis",
    "linear_max_abs_x1",
    "linear_max_abs_x2",
]


def main(reference: dict, solver: dict, sweep: dict, design: dict, chart_json, out_csv, out_json, log=None) -> None:
    log = log if log is not None else logging.getLogger("design_response")
    p = design_parameters(reference, design)
    band = design_band(design)
    # The best gap (peak criterion) of the design chart first, then the config's.
    gaps = response_gaps(read_json(chart_json)["best"]["peak"]["gap"], design["response_gaps"])
    rows, summary = [], []
    for role, g in zip(["best"] + ["config"] * (len(gaps) - 1), gaps):
        log.info("frequency response at Delta0/x_st = %g (%s)", g, role)
        r = frequency_response(
            with_value(p, "gap", g),
            *band,
            int(design["response_points"]),
            settings=sweep_settings(sweep, solver),
            progress=log.info,
        )
        rows.extend({"gap": g, **row} for row in r.rows())
        ms = [m for q in r.points for m in (q.up, q.down)]
        summary.append(
            {
                "gap": g,
                "role": role,
                "peak": r.peak(),
                "band_average": r.band_average(),
                **r.loads(),
                "hysteresis_points": int(sum(q.hysteresis for q in r.points)),
                "hysteresis_thetas": [q.theta for q in r.points if q.hysteresis],
                "largest_balance": float(np.nanmax([m.balance for m in ms])),
                "largest_drift_settled": float(
                    np.nanmax([abs(m.drift) for m in ms if m.regime not in ("nonperiodic", "failed")])
                ),
            }
        )
    write_csv(out_csv, COLUMNS, rows, booleans="digits")
    write_json(out_json, {"responses": summary, "band": list(band), "points": int(design["response_points"])})


JOB = "params.reference params.solver params.sweep params.design input.chart output.csv output.json log=log"
STAGE = {"logger": "design_response", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
