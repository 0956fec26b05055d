"""Gathers a two-parameter map of the paper's Fig. 2 claims (claims_map_chunk.py) into
``figures/claims_map.csv`` (or ``figures/claims_map_{name}.csv`` for
``claims_search.pair_maps``; chunks in order, so the table does not depend on the number of
jobs), refines it where the labels change or a cell does not settle
(:func:`impactdamper.studies.claims.maps.refine_claims_map`, the map's ``refine_levels``) into
``..._refined.csv`` (the added points only, with their level) and writes the settings and the
refinement's counts beside it (``..._settings.json``)."""

import sys

import gather_csv
from claims_map_chunk import map_settings
from impactdamper.studies.replication import cases as rep
from impactdamper.studies.claims.maps import REFINED_COLUMNS, refine_claims_map
from impactdamper.studies.config import parameters
from impactdamper.reporting.records import read_csv, run_stage, write_csv, write_json


def main(
    chunks, reference: dict, solver: dict, search: dict, out_csv, out_json, out_refined, name: str | None = None
) -> None:
    m = search["map"] if name is None else search["pair_maps"][name]
    gather_csv.main(chunks, out_csv)
    refined, stats = refine_claims_map(
        parameters(reference),
        m["x"],
        (float(m["x_start"]), float(m["x_stop"]), int(m["x_points"])),
        m["y"],
        (float(m["y_start"]), float(m["y_stop"]), int(m["y_points"])),
        levels=int(m["refine_levels"]),
        gap_tol=float(solver["gap_tol"]),
        settings=map_settings(m, solver),
        base=read_csv(out_csv),
    )
    print(
        f"{name or 'R_gap'}: {stats['grid_points']} grid points, {stats['refined_points']} refined "
        f"(per level {stats['points_per_level']})",
        file=sys.stderr,
        flush=True,
    )
    write_csv(out_refined, REFINED_COLUMNS, refined)
    write_json(
        out_json,
        {
            "paper": rep.PAPER,
            "what": "claims (a), (b) and both over two parameters, the "
            "others as stated; Algorithm No. 2 from the paper's step 1 at every cell (compiled "
            "batch; a cell not settled within max_periods is nonperiodic); the uniform grid "
            "refined where the labels of a cell's corners differ or one does not settle (edge "
            "midpoints and centre, refine_levels halvings, floor = step / 2^refine_levels)",
            "name": name or "R_gap",
            "map": m,
            "refinement": stats,
            "reference": reference,
            "solver": solver,
        },
        sort_keys=False,
    )


JOB = (
    "input.chunks:list params.reference params.solver params.search output.csv output.json "
    "output.refined name=wildcards.name?"
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
