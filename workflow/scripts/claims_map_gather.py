"""Gathers a two-parameter map of the paper's Fig. 2 claims (claims_map_chunk.py) into
``figures/claims_map.csv`` (or ``figures/claims_map_{name}.csv`` for
``claims_search.pair_maps``; chunks in order, so the table does not depend on the number of
jobs) and writes its settings beside it (``..._settings.json``)."""

import gather_csv
from impactdamper.studies import replication as rep
from impactdamper.reporting.records import start_stage, write_json


def main(chunks, reference: dict, solver: dict, search: dict, out_csv, out_json, name: str | None = None) -> None:
    m = search["map"] if name is None else search["pair_maps"][name]
    gather_csv.main(chunks, out_csv)
    write_json(
        out_json,
        {
            "paper": rep.PAPER,
            "what": "claims (a), (b) and both over two parameters, the "
            "others as stated; Algorithm No. 2 from the paper's step 1 at every cell (compiled "
            "batch; a cell not settled within max_periods is nonperiodic)",
            "name": name or "R_gap",
            "map": m,
            "reference": reference,
            "solver": solver,
        },
        sort_keys=False,
    )


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    cfg, _ = start_stage(sm)
    main(
        list(sm.input.chunks),
        cfg["reference"],
        cfg["solver"],
        cfg["search"],
        sm.output.csv,
        sm.output.json,
        name=getattr(sm.wildcards, "name", None),
    )
