"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design table. Both
devices on the reference object (mu, delta1 of the design stage) over the band: the impact
suppressor optimised in gap, N, delta2 and R, the linear TMD in N and delta2, by one optimiser
and criterion (peak located, and band average), beside the bare object, the absorber without a
stop and the paper's suppressor at the design chart's best gap; each device's worst case with
the object's natural frequency detuned, its stroke and (impact) loads; the robust optima and
the sensitivity of the peak optima (impactdamper.studies.design.optimum.design_study).

Outputs ``figures/design_optimum.json`` (the record) and ``figures/design_optimum.csv`` (one row
per device of the design table).
"""

import logging

from impactdamper.reporting.records import Timer, machine, read_json, run_stage, write_csv, write_json
from impactdamper.studies.config import sweep_settings
from impactdamper.studies.design.design import design_band, design_parameters
from impactdamper.studies.design.optimum import Budget, design_study


COLUMNS = [
    "device",
    "gap",
    "N",
    "delta2",
    "R",
    "peak",
    "peak_theta",
    "band_average",
    "worst_case_5",
    "worst_case_10",
    "stroke",
    "impulse_per_impact",
    "impacts_per_second",
    "mean_force",
]


def table_rows(record: dict) -> list[dict]:
    """The design table's rows (CSV): parameters absent for a device are empty."""
    out = []
    for d in record["devices"]:
        w = d["worst_case"]
        keys = sorted(w, key=float)
        out.append(
            {
                "device": d["device"],
                **{k: d["parameters"].get(k, "") for k in ("gap", "N", "delta2", "R")},
                "peak": d["peak"],
                "peak_theta": d["peak_theta"],
                "band_average": d["band_average"],
                "worst_case_5": w[keys[0]],
                "worst_case_10": w[keys[-1]],
                "stroke": d["stroke"],
                **{k: d.get(k, "") for k in ("impulse_per_impact", "impacts_per_second", "mean_force")},
            }
        )
    return out


def main(reference: dict, solver: dict, sweep: dict, design: dict, chart_json, out_json, out_csv, log=None) -> None:
    log = log if log is not None else logging.getLogger("design_optimum")
    p = design_parameters(reference, design)
    paper = p.replace(gap=float(read_json(chart_json)["best"]["peak"]["gap"]))
    budget = Budget(
        starts=int(design["optimum_starts"]),
        keep=int(design["optimum_keep"]),
        local_evaluations=int(design["optimum_evaluations"]),
        polish_evaluations=int(design["polish_evaluations"]),
    )
    with Timer() as t:
        record = design_study(
            design_band(design),
            p.mu,
            p.delta1,
            paper,
            [float(d) for d in design["detunings"]],
            budget=budget,
            step=float(design["band_step"]),
            coarse_step=float(design["coarse_step"]),
            robust_evaluations=int(design["robust_evaluations"]),
            settings=sweep_settings(sweep, solver),
            progress=log.info,
        )
    write_json(out_json, record)
    write_csv(out_csv, COLUMNS, table_rows(record))
    log.info("timing: %.1f s wall, %.1f s processor, machine %s", t.wall, t.cpu, machine())


JOB = "params.reference params.solver params.sweep params.design input.chart output.json output.csv log=log"
STAGE = {"logger": "design_optimum", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
