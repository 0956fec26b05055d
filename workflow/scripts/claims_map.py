"""Both claims of the paper's Fig. 2 (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100)
over a grid of two parameters (config ``claims_search.map``, R against Delta0/x_st, or one of
``claims_search.pair_maps``), where one parameter alone does not explain where the behaviour
occurs: Algorithm No. 1 and Algorithm No. 2 from the paper's step 1 on the compiled batch, the
grid computed where its cells change (:func:`impactdamper.studies.claims.maps.adaptive_claims_map`:
every ``coarse_step``-th point first, blocks whose corners differ or do not settle split down to
the grid, the rest filled; every ``check_every``-th row computed in full as a check), then
refined beyond the grid where the claims' labels change or a cell does not settle
(:func:`impactdamper.studies.claims.maps.refine_claims_map`, the map's ``refine_levels``). A cell
that needs more than the map's ``max_periods`` to settle is nonperiodic. The batch calls run in
the job's threads.

Outputs: ``figures/claims_map.csv`` (or ``figures/claims_map_{name}.csv``: the grid, every
cell; ``periods`` empty where a cell was filled), ``..._refined.csv`` (the points the refinement
added, with their level) and ``..._settings.json`` (the settings, the grid's computed share
and its check, the refinement's counts).
"""

from impactdamper.reporting.records import run_stage, write_csv, write_json
from impactdamper.studies.claims.maps import MAP_COLUMNS, REFINED_COLUMNS, adaptive_claims_map, refine_claims_map
from impactdamper.studies.config import parameters, sweep_settings
from impactdamper.studies.replication import cases as rep


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
    reference: dict,
    solver: dict,
    search: dict,
    out_csv,
    out_json,
    out_refined,
    name: str | None = None,
    workers: int = 1,
    log=print,
) -> dict:
    m = search["map"] if name is None else search["pair_maps"][name]
    p, settings, gap_tol = parameters(reference), map_settings(m, solver), float(solver["gap_tol"])
    x_axis = (float(m["x_start"]), float(m["x_stop"]), int(m["x_points"]))
    y_axis = (float(m["y_start"]), float(m["y_stop"]), int(m["y_points"]))
    # Both calls read the same grid (x, its axis, y, its axis) with the same settings.
    grid_args = (p, m["x"], x_axis, m["y"], y_axis)
    common = {"gap_tol": gap_tol, "settings": settings, "workers": workers}
    rows, grid = adaptive_claims_map(
        *grid_args, coarse_step=int(m["coarse_step"]), check_every=int(m["check_every"]), **common
    )
    write_csv(out_csv, MAP_COLUMNS, rows)
    check = grid["check"]
    log(
        f"{name or 'R_gap'}: {grid['computed']} of {grid['grid_points']} grid cells computed "
        f"({100 * grid['computed_share']:.1f} %); check on {check['rows']} rows: {check['differences']} of "
        f"{check['filled']} filled cells differ; both claims at {sum(r['both'] for r in rows)}"
    )
    refined, stats = refine_claims_map(*grid_args, levels=int(m["refine_levels"]), base=rows, **common)
    log(f"{name or 'R_gap'}: {stats['refined_points']} points refined (per level {stats['points_per_level']})")
    write_csv(out_refined, REFINED_COLUMNS, refined)
    settings_record = {
        "paper": rep.PAPER,
        "what": "claims (a), (b) and both over two parameters, the "
        "others as stated; Algorithm No. 2 from the paper's step 1 at every computed cell (compiled "
        "batch; a cell not settled within max_periods is nonperiodic); the grid computed where its cells "
        "change (every coarse_step-th point first, a block whose corners differ in claim (a), the orbit's "
        "existence, regime, k or z, or do not settle, split down to the grid; the other cells filled from "
        "their block's corners, without periods; every check_every-th row computed in full as a check); "
        "then refined where the labels of a cell's corners differ or one does not settle (edge "
        "midpoints and centre, refine_levels halvings, floor = step / 2^refine_levels)",
        "name": name or "R_gap",
        "map": m,
        "grid": grid,
        "refinement": stats,
        "reference": reference,
        "solver": solver,
    }
    write_json(out_json, settings_record, sort_keys=False)
    return settings_record


JOB = "params.reference params.solver params.search output.csv output.json output.refined"

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, name="wildcards.name?", workers="threads", log="say")  # noqa: F821 (injected by Snakemake's script: directive)
