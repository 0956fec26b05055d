"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design table of the
reference object (mu, delta1 of the design stage) over the band, by the call behind ``python -m
impactdamper design --json`` (impactdamper.studies.design.optimum.design_optima): both devices
optimised by a global search for every criterion (the robust rows included), every row judged on its located worst
branch under every uncertainty, its stroke and loads; every row's answer checked against the
halves of its box without it, a lower half's adopted (impactdamper.studies.design.subregions).

Outputs ``figures/design_optimum.json`` (the record), ``figures/design_optimum.csv`` (one row
per device of the design table) and ``figures/design_subregions.json`` (the sub-region check's
record: every row's halves, the budget, the margins, what was adopted).
"""

import logging

from impactdamper.reporting.records import Timer, machine, run_stage, write_csv, write_json
from impactdamper.studies.design.design import design_band, design_parameters
from impactdamper.studies.design.devices import IMPACT_NAMES
from impactdamper.studies.design.optimum import design_optima
from impactdamper.studies.design.search_setup import design_options
from impactdamper.studies.design.subregions import subregion_budget


COLUMNS = [
    "device",
    "gap",
    "N",
    "delta2",
    "R",
    "peak",
    "peak_theta",
    "band_average",
    "worst_detuning",
    "worst_force",
    "worst_restitution",
    "worst_together",
    "worst_absorber",
    "stroke",
    "impacts",
    "pulse",
    "impacts_per_hour",
    "contact_force",
]


def table_rows(record: dict) -> list[dict]:
    """The design table's rows (CSV): parameters and loads absent for a device are empty."""
    out = []
    for d in record["devices"]:
        out.append(
            {
                "device": d["device"],
                **{k: d["parameters"].get(k, "") for k in IMPACT_NAMES},
                "peak": d["peak"],
                "peak_theta": d["peak_theta"],
                "band_average": d["band_average"],
                **{f"worst_{k}": d["worst"][k] for k in ("detuning", "force", "restitution", "together", "absorber")},
                "stroke": d["stroke"],
                "impacts": int(bool(d["impacts"])),
                **{k: d.get(k, "") for k in ("pulse", "impacts_per_hour", "contact_force")},
            }
        )
    return out


def main(reference: dict, design: dict, out_json, out_csv, out_subregions, log=None, workers: int = 2) -> None:
    log = log if log is not None else logging.getLogger("design_optimum")
    p = design_parameters(reference, design)
    with Timer() as t:
        record = design_optima(
            design_band(design),
            p.mu,
            p.delta1,
            **design_options(design),
            workers=workers,
            progress=log.info,
            robust=True,
            subregion_budget=subregion_budget(design),
        )
    sub = record.pop("subregions")
    write_json(out_json, record)
    write_json(out_subregions, sub)
    write_csv(out_csv, COLUMNS, table_rows(record))
    log.info(
        "sub-region check: %d rows, %d halves, smallest margin %.3e (%s, %s), %d lower, adopted %s; %.1f s, %.1f s processor",
        sub["rows_count"],
        sub["halves_count"],
        sub["smallest_margin"],
        sub["smallest_row"],
        sub["smallest_half"],
        len(sub["lower"]),
        sub["adopted"],
        sub["elapsed"],
        sub["cpu"],
    )
    log.info("timing: %.1f s wall, %.1f s processor, machine %s", t.wall, t.cpu, machine())


JOB = "params.reference params.design output.json output.csv output.subregions log=log workers=threads"
STAGE = {"logger": "design_optimum", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
