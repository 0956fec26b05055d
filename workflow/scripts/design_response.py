"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the frequency response
(upward and downward theta sweeps, each point from its neighbour's settled motion) of the
optimal impact suppressor of the design table (optimal for the peak, its stop within reach), of
the paper's suppressor at the design chart's located best gap and at the gaps the config names
(the paper's -5.8), with the exact linear response without a stop beside each, and each one's
worst branch located.

Outputs ``figures/design_response.csv`` (per device, theta and direction: regime, max|x1|,
max|x2|, impacts per period, pulses, energies, hysteresis) and ``figures/design_response.json``
(per device: its parameters, located peak, band average, loads, hysteresis count, the energy
balance's largest mismatch).
"""

import logging

import numpy as np

from impactdamper.analysis.response import frequency_response
from impactdamper.reporting.records import read_json, run_stage, write_csv, write_json
from impactdamper.studies.design.design import design_band, design_parameters, response_gaps
from impactdamper.studies.design.devices import DESIGN_SETTINGS, IMPACT_NAMES
from impactdamper.studies.design.verdict import device


COLUMNS = [
    "role",
    "gap",
    "N",
    "delta2",
    "R",
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


def devices(p, chart: dict, optimum: dict, gaps) -> list[tuple[str, object]]:
    """(role, suppressor): the optimal one, the paper's at the chart's located best gap, and the
    paper's at each further gap of the config."""
    x = device(optimum, "impact_peak_reach")["parameters"]
    best = chart["located"]["peak"]["gap"]
    out = [("optimal", p.replace(**x)), ("best", p.replace(gap=best))]
    out += [("paper", p.replace(gap=g)) for g in response_gaps(best, gaps)[1:]]
    return out


def main(reference: dict, design: dict, chart_json, optimum_json, out_csv, out_json, log=None) -> None:
    log = log if log is not None else logging.getLogger("design_response")
    p = design_parameters(reference, design)
    band = design_band(design)
    rows, summary = [], []
    for role, q in devices(p, read_json(chart_json), read_json(optimum_json), design["response_gaps"]):
        log.info("frequency response of %s (%s)", role, q)
        r = frequency_response(q, *band, int(design["response_points"]), settings=DESIGN_SETTINGS, progress=log.info)
        extra = {"role": role, **{k: getattr(q, k) for k in IMPACT_NAMES}}
        rows.extend({**extra, **row} for row in r.rows())
        ms = [m for pt in r.points for m in (pt.up, pt.down)]
        theta, branch = r.peak_where()
        summary.append(
            {
                **extra,
                "peak": r.peak(),
                "peak_theta": theta,
                "peak_branch": branch,
                "grid_peak": r.grid_peak(),
                "band_average": r.band_average(),
                **r.loads(),
                "hysteresis_points": int(sum(pt.hysteresis for pt in r.points)),
                "largest_balance": float(np.nanmax([m.balance for m in ms])),
                "largest_drift_settled": float(
                    np.nanmax([abs(m.drift) for m in ms if m.regime not in ("nonperiodic", "failed")])
                ),
            }
        )
    write_csv(out_csv, COLUMNS, rows, booleans="digits")
    write_json(out_json, {"responses": summary, "band": list(band), "points": int(design["response_points"])})


JOB = "params.reference params.design input.chart input.optimum output.csv output.json log=log"
STAGE = {"logger": "design_response", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
