"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the closed-form
boundaries drawn over a regime map.

For each value of the map's second parameter: the lift-off threshold of the persistent
contact (:func:`impactdamper.analysis.transitions.stuck_liftoff_gap`) and the gap above which
the free forced response never reaches the stop (U1/x_st,
:func:`~impactdamper.analysis.transitions.no_contact_gap`). Every other boundary, the ends of
the range where Algorithm No. 1's orbit is admissible among them, is a continued curve of
``figures/boundaries_{map}.csv`` (rule ``boundaries``); the scan of Algorithm No. 1's
admissibility that this stage once ran on every few rows found the same gaps (within 5e-4 of
the plane's span, tests/unit/test_sweep_results.py) at ~200 runs per row.

Output: ``figures/map_{map}_curves.csv`` (slow, liftoff, first_contact).
"""

from impactdamper.studies.sweeps import gapsweep as gs
from impactdamper.studies.config import parameters
from impactdamper.reporting.records import run_stage, write_csv
from impactdamper.analysis.sweeps import with_value
from impactdamper.analysis.transitions import no_contact_gap, stuck_liftoff_gap


COLUMNS = ["slow", "liftoff", "first_contact"]


def row(base, slow: str, value: float) -> dict:
    p = with_value(base, slow, value)
    return {"slow": float(value), "liftoff": stuck_liftoff_gap(p), "first_contact": no_contact_gap(p)}


def main(reference: dict, maps: dict, name: str, out_csv) -> list[dict]:
    base = parameters(reference)
    slow, slow_values, _ = gs.map_axes(maps, name)
    rows = [row(base, slow, v) for v in slow_values]
    write_csv(out_csv, COLUMNS, rows, booleans="digits")
    return rows


if __name__ == "__main__":
    run_stage(snakemake, main, "params.reference params.maps wildcards.map output.csv")  # noqa: F821 (injected by Snakemake's script: directive)
