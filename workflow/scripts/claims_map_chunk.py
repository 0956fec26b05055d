"""Both claims of the paper's Fig. 2 (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100)
over a grid of two parameters (config ``claims_search.map``, default R against Delta0/x_st),
where one parameter alone does not explain where the behaviour occurs: Algorithm No. 1 and
Algorithm No. 2 from the paper's step 1 at every cell (:func:`impactdamper.studies.claims.claims_at`).
One chunk of rows (contiguous y values) per Snakemake job.

Output: ``results/claims/map_{chunk}.csv``.
"""


import numpy as np

from impactdamper.studies import replication as rep
from impactdamper.studies.config import parameters
from impactdamper.reporting.records import start_stage, write_csv
from impactdamper.studies.claims import claims_at

COLUMNS = ["x", "y", "claim_a", "claim_b", "both", "alg1_exists", "regime", "period_multiple", "impacts_per_cycle",
           "periods"]


def axes(m: dict) -> tuple[np.ndarray, np.ndarray]:
    return (np.linspace(float(m["x_start"]), float(m["x_stop"]), int(m["x_points"])),
            np.linspace(float(m["y_start"]), float(m["y_stop"]), int(m["y_points"])))


def main(chunk: int, reference: dict, solver: dict, search: dict, out_csv, log=print) -> list[dict]:
    m = search["map"]
    xs, ys = axes(m)
    rows_y = np.array_split(np.arange(len(ys)), int(m["chunks"]))[chunk]
    base = parameters(reference)
    out = []
    for j in rows_y:
        for x in xs:
            p = base.replace(**{m["x"]: float(x), m["y"]: float(ys[j])})
            c = claims_at(p, gap_tol=float(solver["gap_tol"]), steady_kwargs=rep.solver_options(solver))
            out.append({"x": float(x), "y": float(ys[j]), **c, "both": c["claim_a"] and c["claim_b"]})
        log(f"row {j}: {m['y']} = {ys[j]:.6g} done")
    write_csv(out_csv, COLUMNS, out)
    return out


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    import sys

    cfg, _ = start_stage(sm)
    main(int(sm.wildcards.chunk), cfg["reference"], cfg["solver"],
         cfg["search"], sm.output.csv, log=lambda msg: print(msg, file=sys.stderr, flush=True))
