"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the analytic
boundaries drawn over a regime map.

For each value of the map's second parameter: the lift-off threshold of the persistent
contact (:func:`impactdamper.analysis.transitions.stuck_liftoff_gap`), the gap above which the free forced
response never reaches the stop (U1/x_st, :func:`~impactdamper.analysis.transitions.no_contact_gap`), and
every gap where Algorithm No. 1's orbit starts or stops crossing the stop between impacts
(its admissibility changes along a scan of ``SCAN_POINTS`` gaps over the map's range, each
change bisected to ``BISECT_XTOL``, :func:`~impactdamper.analysis.transitions.algorithm1_grazing_gaps`).
The grazing scan costs ~200 Algorithm No. 1 runs per row, so it runs on every
``maps.grazing_every``-th row (and the last); the two closed-form thresholds on every row.

Output: ``figures/map_{map}_curves.csv`` (slow, liftoff, first_contact, alg1_scanned (1 where
the grazing scan ran), alg1_grazing with ';'-joined values).
"""

import numpy as np

from impactdamper.studies.sweeps import gapsweep as gs
from impactdamper.studies.config import parameters
from impactdamper.reporting.records import run_stage, write_csv
from impactdamper.analysis.sweeps import with_value
from impactdamper.analysis.transitions import algorithm1_grazing_gaps, no_contact_gap, stuck_liftoff_gap


COLUMNS = ["slow", "liftoff", "first_contact", "alg1_scanned", "alg1_grazing"]
# Algorithm No. 1 costs ~2 ms: a scan of this many gaps per row finds the admissibility
# changes (ranges narrower than the scan step, ~0.3 x_st, are missed), then bisection.
SCAN_POINTS = 200
BISECT_XTOL = 1e-6


def row(base, slow: str, value: float, gaps: np.ndarray, scanned: bool = True) -> dict:
    p = with_value(base, slow, value)
    thresholds = {"slow": float(value), "liftoff": stuck_liftoff_gap(p), "first_contact": no_contact_gap(p)}
    if not scanned:
        return {**thresholds, "alg1_scanned": 0, "alg1_grazing": ""}
    graze = algorithm1_grazing_gaps(p, gaps[0], gaps[-1], SCAN_POINTS, xtol=BISECT_XTOL)
    return {**thresholds, "alg1_scanned": 1, "alg1_grazing": ";".join(repr(float(g)) for g in graze)}


def main(reference: dict, maps: dict, name: str, out_csv) -> list[dict]:
    base = parameters(reference)
    slow, slow_values, gaps = gs.map_axes(maps, name)
    every = int(maps["grazing_every"])
    last = len(slow_values) - 1
    rows = [row(base, slow, v, gaps, scanned=(i % every == 0 or i == last)) for i, v in enumerate(slow_values)]
    write_csv(out_csv, COLUMNS, rows, booleans="digits")
    return rows


if __name__ == "__main__":
    run_stage(snakemake, main, "params.reference params.maps wildcards.map output.csv")  # noqa: F821 (injected by Snakemake's script: directive)
