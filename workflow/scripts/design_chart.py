"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design chart over the
gap of the paper's suppressor (its N, delta2, R). At each Delta0/x_st the worst branch over the
band (both sweep directions, peaks located, the no-contact floor) gives the peak and the band
average of max|x1|/x_st, and the loads (largest pulse per impact over P0/omega1, impacts per
period); also the worst motion at the reference case's theta alone, the reading of the sweeps
stage's gap sweep. The chart's best gap of each criterion is then located (Brent's method on
the worst branch located with random starts), not read off the grid.

Outputs ``figures/design_chart.csv`` (one row per gap) and ``figures/design_chart.json`` (the
chart's best gap for each criterion, its band of good gaps and its loads, the located best
gaps, and the run's timing).
"""

import logging

import numpy as np

from impactdamper.analysis.peaks import band_points
from impactdamper.reporting.records import Timer, machine, run_stage, write_csv, write_json
from impactdamper.studies.design.design import (
    AT_THETA_COLUMN,
    CHART_COLUMNS,
    CRITERIA,
    best_gap,
    design_band,
    design_gaps,
    design_parameters,
    gap_chart,
)
from impactdamper.studies.design.devices import DESIGN_SETTINGS


COLUMNS = [*CHART_COLUMNS, AT_THETA_COLUMN]


def main(reference: dict, design: dict, out_csv, out_json, log=None, workers: int = 1) -> None:
    log = log if log is not None else logging.getLogger("design_chart")
    p = design_parameters(reference, design)
    gaps, band, step = design_gaps(design), design_band(design), float(design["band_step"])
    settings = DESIGN_SETTINGS
    # The chart also reads each gap at the reference case's theta: it must be a grid point. Checked
    # here, before the sweeps, so that a config without it fails at once and not minutes later.
    thetas = np.linspace(band[0], band[1], band_points([band], step))
    theta = float(reference["theta"])
    if not np.any(np.abs(thetas - theta) <= 1e-9 * max(abs(theta), 1.0)):
        raise ValueError(
            f"`design.band_step` = {step!r} is not allowed: the grid from {band[0]:g} to {band[1]:g} must contain "
            f"the reference theta = {theta:g}"
        )
    log.info("design chart: %d gaps from %g to %g, theta band %s, step %g", len(gaps), gaps[0], gaps[-1], band, step)
    with Timer() as t:
        chart = gap_chart(p, gaps, band, step, settings=settings, workers=workers, progress=log.info)
        located = {c: best_gap(chart, c, step=step, settings=settings, workers=workers) for c in CRITERIA}
    write_csv(out_csv, COLUMNS, chart.rows(theta))
    at = chart.at_theta(theta)
    i = int(np.nanargmin(at))
    best = {c: chart.best(c, float(design["tolerance"])) for c in CRITERIA}
    for c in CRITERIA:
        log.info(
            "best gap (%s): chart %g, located %.6g (%.6g)", c, best[c]["gap"], located[c]["gap"], located[c]["value"]
        )
    write_json(
        out_json,
        {
            "at_reference_theta": {"theta": theta, "gap": float(chart.gaps[i]), "value": float(at[i])},
            "best": best,
            "located": located,
            "parameters": p.to_dict(),
            "band": list(band),
            "step": step,
            "gaps": [float(g) for g in gaps],
            "gap_step": float(gaps[1] - gaps[0]) if len(gaps) > 1 else 0.0,
        },
    )
    log.info("timing: %.1f s wall, %.1f s processor, machine %s", t.wall, t.cpu, machine())


JOB = "params.reference params.design output.csv output.json log=log workers=threads"
STAGE = {"logger": "design_chart", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
