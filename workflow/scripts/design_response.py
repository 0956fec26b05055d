"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the frequency response of
the impact suppressor (upward and downward theta sweeps) at the best gap of the design chart
and at the gaps the config names (the paper's -5.8 among them), with the exact linear response
without a stop beside it.

Outputs ``figures/design_response.csv`` (per gap, theta and direction: regime, max|x1|, max|x2|,
impacts per period, pulses, energies, hysteresis) and ``figures/design_response.json`` (per gap:
peak, band average, loads, hysteresis count, the energy balance's largest mismatch).
"""

import numpy as np

import design_common as dc
from impactdamper.analysis.response import frequency_response
from impactdamper.analysis.sweeps import with_value
from impactdamper.reporting.records import read_json, write_csv, write_json

COLUMNS = ["gap", "theta", "direction", "regime", "label", "period_multiple", "max_abs_x1", "max_abs_x2",
           "impacts_per_period", "mean_impulse", "peak_impulse", "energy_input", "energy_impacts", "energy_dampers",
           "balance", "drift", "hysteresis", "linear_max_abs_x1", "linear_max_abs_x2"]


def response_gaps(design: dict, chart_json) -> list:
    """The best gap (peak criterion) of the design chart, then the config's gaps, without repeats."""
    best = read_json(chart_json)["best"]["peak"]["gap"]
    out = [float(best)]
    for g in design["response_gaps"]:
        if all(abs(float(g) - x) > 1e-12 for x in out):
            out.append(float(g))
    return out


def main(reference: dict, solver: dict, sweep: dict, design: dict, chart_json, out_csv, out_json, log_path) -> None:
    log = dc.logger(log_path, "design_response")
    p = dc.parameters(reference, design)
    rows, summary = [], []
    for role, g in zip(["best"] + ["config"] * 99, response_gaps(design, chart_json)):
        log.info("frequency response at Delta0/x_st = %g (%s)", g, role)
        r = frequency_response(with_value(p, "gap", g), *dc.band(design), int(design["response_points"]),
                               settings=dc.settings(sweep, solver), progress=log.info)
        rows.extend({"gap": g, **row} for row in r.rows())
        ms = [m for q in r.points for m in (q.up, q.down)]
        summary.append({"gap": g, "role": role, "peak": r.peak(), "band_average": r.band_average(), **r.loads(),
                        "hysteresis_points": int(sum(q.hysteresis for q in r.points)),
                        "hysteresis_thetas": [q.theta for q in r.points if q.hysteresis],
                        "largest_balance": float(np.nanmax([m.balance for m in ms])),
                        "largest_drift_settled": float(np.nanmax([abs(m.drift) for m in ms
                                                                  if m.regime not in ("nonperiodic", "failed")]))})
    write_csv(out_csv, COLUMNS, rows, booleans="digits")
    write_json(out_json, {"responses": summary, "band": list(dc.band(design)),
                          "points": int(design["response_points"])})


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    import json

    main(json.loads(sm.params.reference), json.loads(sm.params.solver), json.loads(sm.params.sweep),
         json.loads(sm.params.design), sm.input.chart, sm.output.csv, sm.output.json, sm.log[0])
