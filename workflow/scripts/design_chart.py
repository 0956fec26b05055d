"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design chart over the
gap. At each Delta0/x_st the frequency response over the band (upward and downward theta
sweeps) gives the peak and the band average of max|x1|/x_st (the worse direction at each theta),
and the loads (largest pulse per impact, impacts per period); also max|x1|/x_st at the
reference case's theta alone, the reading of the sweeps stage's gap sweep.

Outputs ``figures/design_chart.csv`` (one row per gap) and ``figures/design_chart.json`` (the best
gap for each criterion, its band of good gaps, its loads, and the run's timing).
"""

import logging

import numpy as np

from impactdamper.reporting.records import Timer, machine, run_stage, write_csv, write_json
from impactdamper.studies.config import sweep_settings
from impactdamper.studies.design.design import CRITERIA, design_band, design_gaps, design_parameters, gap_chart
from impactdamper.analysis.response import theta_grid


COLUMNS = [
    "gap",
    "peak_max_abs_x1",
    "band_average_max_abs_x1",
    "peak_impulse",
    "impacts_per_period",
    "hysteresis_points",
    "max_abs_x1_at_theta",
]


def main(reference: dict, solver: dict, sweep: dict, design: dict, out_csv, out_json, log=None) -> None:
    log = log if log is not None else logging.getLogger("design_chart")
    p = design_parameters(reference, design)
    gaps, band = design_gaps(design), design_band(design)
    # The chart also reads each gap at the reference case's theta: it must be a grid point. Checked
    # here, before the sweeps, so that a config without it fails at once and not minutes later.
    thetas = theta_grid(band[0], band[1], int(design["theta_points"]))
    if not np.any(np.abs(thetas - float(reference["theta"])) <= 1e-9 * max(abs(float(reference["theta"])), 1.0)):
        raise ValueError(
            f"`design.theta_points` = {int(design['theta_points'])} is not allowed: the grid from "
            f"{band[0]:g} to {band[1]:g} must contain the reference theta = {float(reference['theta']):g}"
        )
    log.info(
        "design chart: %d gaps from %g to %g, theta band %s with %d points",
        len(gaps),
        gaps[0],
        gaps[-1],
        band,
        int(design["theta_points"]),
    )
    with Timer() as t:
        chart = gap_chart(
            p, gaps, band, int(design["theta_points"]), settings=sweep_settings(sweep, solver), progress=log.info
        )
    # The gap sweep (sweeps stage) reads the gap at the reference case's forcing frequency alone.
    theta = float(reference["theta"])
    write_csv(out_csv, COLUMNS, chart.rows(theta))
    at = chart.at_theta(theta)
    i = int(np.nanargmin(at))
    best = {c: chart.best(c, float(design["tolerance"])) for c in CRITERIA}
    for c, b in best.items():
        log.info("best gap (%s): %g, %.4g; good from %g to %g", c, b["gap"], b["value"], b["good_from"], b["good_to"])
    log.info("at theta = %g alone: best gap %g, max|x1|/x_st %.4g", theta, chart.gaps[i], at[i])
    write_json(
        out_json,
        {
            "at_reference_theta": {"theta": theta, "gap": float(chart.gaps[i]), "value": float(at[i])},
            "best": best,
            "parameters": p.to_dict(),
            "band": list(band),
            "theta_points": int(design["theta_points"]),
            "gap_step": float(gaps[1] - gaps[0]) if len(gaps) > 1 else 0.0,
        },
    )
    log.info("timing: %.1f s wall, %.1f s processor, machine %s", t.wall, t.cpu, machine())


JOB = "params.reference params.solver params.sweep params.design output.csv output.json log=log"
STAGE = {"logger": "design_chart", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
