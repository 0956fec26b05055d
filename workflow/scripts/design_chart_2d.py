"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design chart against
a second parameter (config ``design.second``: N or R). At each of its values the gap chart of
``design_chart.py`` on a coarser gap grid.

Outputs ``figures/design_chart_2d.csv`` (one row per value and gap) and
``figures/design_chart_2d.json`` (the best gap for each value and criterion).
"""

import design_common as dc
from impactdamper.studies.design import CRITERIA, design_chart_2d
from impactdamper.reporting.records import write_csv, write_json

COLUMNS = ["value", "gap", "peak_max_abs_x1", "band_average_max_abs_x1", "peak_impulse", "impacts_per_period",
           "hysteresis_points"]


def main(reference: dict, solver: dict, sweep: dict, design: dict, out_csv, out_json, log_path) -> None:
    log = dc.logger(log_path, "design_chart_2d")
    p = dc.parameters(reference, design)
    name = design["second"]
    charts = design_chart_2d(p, name, [float(v) for v in design["second_values"]], dc.gaps(design, "second_gap"),
                             dc.band(design), int(design["theta_points"]), settings=dc.settings(sweep, solver),
                             progress=log.info)
    rows, best = [], []
    for value, chart in charts.items():
        rows.extend({"value": value, **r} for r in chart.rows())
        for c in CRITERIA:
            b = chart.best(c, float(design["tolerance"]))
            best.append({"second": value, **b})
            log.info("%s = %g, best gap (%s): %g, %.4g", name, value, c, b["gap"], b["value"])
    write_csv(out_csv, COLUMNS, rows)
    write_json(out_json, {"parameter": name, "best": best, "parameters": p.to_dict()})


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    import json

    main(json.loads(sm.params.reference), json.loads(sm.params.solver), json.loads(sm.params.sweep),
         json.loads(sm.params.design), sm.output.csv, sm.output.json, sm.log[0])
