"""Both claims of the paper's Fig. 2 (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100)
over a grid of two parameters (config ``claims_search.map``, R against Delta0/x_st, or one of
``claims_search.pair_maps``), where one parameter alone does not explain where the behaviour
occurs: Algorithm No. 1 and Algorithm No. 2 from the paper's step 1 at every cell, on the
compiled batch (:func:`impactdamper.studies.claims.maps.claims_map`; a cell that needs more than the
map's ``max_periods`` to settle is nonperiodic). One chunk of rows (contiguous y values) per
Snakemake job.

Output: ``results/claims/map_{chunk}.csv`` or ``results/claims/map_{name}_{chunk}.csv``.
"""

import numpy as np

from impactdamper.reporting.records import run_stage, write_csv
from impactdamper.studies.claims.maps import MAP_COLUMNS, claims_map
from impactdamper.studies.config import parameters, sweep_settings


COLUMNS = MAP_COLUMNS


def axes(m: dict) -> tuple[np.ndarray, np.ndarray]:
    return (
        np.linspace(float(m["x_start"]), float(m["x_stop"]), int(m["x_points"])),
        np.linspace(float(m["y_start"]), float(m["y_stop"]), int(m["y_points"])),
    )


def map_settings(m: dict, solver: dict):
    """The batch's settings of a map: the solver's, with the map's period cap."""
    cap = int(m["max_periods"])
    return sweep_settings(
        {
            "settle_tol": solver["settle_tol"],
            "max_periods": cap,
            "max_periods_after_nonperiodic": cap,
            "max_period_multiple": solver["max_period_multiple"],
        },
        solver,
        continuation=False,
        rescue=False,
    )


def main(
    chunk: int, reference: dict, solver: dict, search: dict, out_csv, log=print, name: str | None = None
) -> list[dict]:
    m = search["map"] if name is None else search["pair_maps"][name]
    xs, ys = axes(m)
    rows_y = np.array_split(np.arange(len(ys)), int(m["chunks"]))[chunk]
    out = claims_map(
        parameters(reference),
        m["x"],
        xs,
        m["y"],
        ys[rows_y],
        gap_tol=float(solver["gap_tol"]),
        settings=map_settings(m, solver),
    )
    log(
        f"rows {rows_y[0] if len(rows_y) else '-'}..{rows_y[-1] if len(rows_y) else '-'} of {m['y']}: {len(out)} cells, "
        f"both claims at {sum(r['both'] for r in out)}"
    )
    write_csv(out_csv, COLUMNS, out)
    return out


JOB = "wildcards.chunk:int params.reference params.solver params.search output.csv log=say name=wildcards.name?"

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
