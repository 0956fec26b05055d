"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: every row of the design
table (figures/design_optimum.json, both devices) checked against its box's sub-regions
(impactdamper.studies.design.subregions.design_subregions): its search box split at the midpoint
along each design variable, every half without the row's optimum searched with the check's
stated budget by the row's criterion at its final fidelity, and the best value there compared
with the optimum.

Outputs ``figures/design_subregions.json``.
"""

import logging

from impactdamper.reporting.records import machine, read_json, run_stage, write_json
from impactdamper.studies.design.subregions import design_subregions


def main(optimum_json, out_json, log=None, workers: int = 2) -> None:
    log = log if log is not None else logging.getLogger("design_subregions")
    record = design_subregions(read_json(optimum_json), workers=workers, progress=log.info)
    write_json(out_json, record)
    log.info(
        "%d rows, %d halves: smallest margin %.3e (%s, %s), %d lower; %.1f s wall, %.1f s processor, machine %s",
        record["rows_count"],
        record["halves_count"],
        record["smallest_margin"],
        record["smallest_row"],
        record["smallest_half"],
        len(record["lower"]),
        record["elapsed"],
        record["cpu"],
        machine(),
    )


JOB = "input.optimum output.json log=log workers=threads"
STAGE = {"logger": "design_subregions", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
