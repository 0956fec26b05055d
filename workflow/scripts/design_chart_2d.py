"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design chart against
a second parameter (config ``design.second``: N or R). At each of its values the gap chart of
``design_chart.py`` (the worst branch located at each gap) on a coarser gap grid.

Outputs ``figures/design_chart_2d.csv`` (one row per value and gap) and
``figures/design_chart_2d.json`` (the best gap of the grid for each value and criterion).
"""

import logging

from impactdamper.reporting.records import run_stage, write_csv, write_json
from impactdamper.studies.design.design import (
    CHART_COLUMNS,
    CRITERIA,
    design_band,
    design_chart_2d,
    design_gaps,
    design_parameters,
)
from impactdamper.studies.design.devices import DESIGN_SETTINGS


COLUMNS = ["value", *CHART_COLUMNS]


def main(reference: dict, design: dict, out_csv, out_json, log=None, workers: int = 1) -> None:
    log = log if log is not None else logging.getLogger("design_chart_2d")
    p = design_parameters(reference, design)
    name = design["second"]
    charts = design_chart_2d(
        p,
        name,
        [float(v) for v in design["second_values"]],
        design_gaps(design, second=True),
        design_band(design),
        float(design["band_step"]),
        settings=DESIGN_SETTINGS,
        workers=workers,
        progress=log.info,
    )
    rows, best = [], []
    for value, chart in charts.items():
        rows.extend({"value": value, **r} for r in chart.rows())
        for c in CRITERIA:
            b = chart.best(c, float(design["tolerance"]))
            b["peak_theta"] = float(chart.branches[b["index"]].peak_theta)
            best.append({"second": value, **b})
            log.info("%s = %g, best gap (%s): %g, %.4g", name, value, c, b["gap"], b["value"])
    write_csv(out_csv, COLUMNS, rows)
    write_json(out_json, {"parameter": name, "best": best, "parameters": p.to_dict()})


JOB = "params.reference params.design output.csv output.json log=log workers=threads"
STAGE = {"logger": "design_chart_2d", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
