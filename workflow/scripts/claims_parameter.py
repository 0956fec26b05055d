"""Searches beyond the gap for the behaviour of the paper's Fig. 2 (Timofeev et al. 2019,
DOI 10.18698/0236-3941-2019-1-90-100): at the stated Delta0/x_st, one parameter (theta, mu,
N, delta1, delta2 or R) is varied alone over a wide range, the others as stated, and the
intervals where claim (a) (Algorithm No. 1: the gap goes negative between impacts), claim (b)
(Algorithm No. 2 from the paper's step 1: T_c = 2T with three impacts) and both hold are
located, each end bisected to ``claims_search.rel_tol`` relative
(:func:`impactdamper.studies.claims.search.search_parameter`). Claim (b)'s grid (the compiled batch,
each value from the paper's step 1, a nonperiodic value rescued by Newton's method from the
run's last sections where it can be) is refined adaptively wherever the settled motion's label
changes between neighbours or a value does not settle, halving the step
``claims_search.refine_levels`` times at most (the floor: step / 2^levels).

Why: "not reproduced" at the stated point could come from a transcription slip or another
normalisation of any parameter, not only of the gap.

Algorithm No. 1's grid, each round of the refinement and the pure-Python check run in the
job's threads. Algorithm No. 2 runs compiled; the pure-Python reference repeats it at every
``claims_search.reference_check_every``-th grid value and at both ends of every final
bisection bracket, and the
record says where the two agree.

Output: ``results/claims/{parameter}.json`` (gathered by claims_gather.py).
"""

import time

import numpy as np

from impactdamper.studies.replication import cases as rep
from impactdamper.studies.config import parameters
from impactdamper.reporting.records import run_stage, write_json
from impactdamper.studies.claims.search import check_rows, reference_check, search_parameter


def main(parameter: str, reference: dict, solver: dict, search: dict, out_json, log=print, workers: int = 1) -> dict:
    rng = search["parameters"][parameter]
    lo, hi = float(rng["start"]), float(rng["stop"])
    values = np.linspace(lo, hi, int(rng["points"]))
    alg1_values = np.linspace(lo, hi, int(rng["alg1_points"]))
    p = parameters(reference)
    t = time.perf_counter()
    result = search_parameter(
        p,
        parameter,
        values,
        alg1_values,
        gap_tol=float(solver["gap_tol"]),
        steady_kwargs=rep.solver_options(solver),
        rel_tol=float(search["rel_tol"]),
        floor=float(search["floor"]),
        log=log,
        refine_floor=(hi - lo) / (int(rng["points"]) - 1) / 2 ** int(search["refine_levels"]),
        rescue=True,
        workers=workers,
    )
    log(f"{parameter}: searched in {time.perf_counter() - t:.1f} s")
    t = time.perf_counter()
    every = int(search["reference_check_every"])
    check = reference_check(p, parameter, check_rows(result, every), rep.solver_options(solver), workers)
    log(
        f"{parameter}: the pure-Python solver agrees at {check['agree']} of {check['points']} values "
        f"(every {every}th grid value and both ends of every final bracket), {time.perf_counter() - t:.1f} s"
    )
    result["reference_check"] = {"every": every, **check}
    result["intervals"] = {k: [iv.to_dict() for iv in v] for k, v in result["intervals"].items()}
    result["range"] = {"start": lo, "stop": hi, "points": int(rng["points"]), "alg1_points": int(rng["alg1_points"])}
    write_json(out_json, result, sort_keys=False)
    return result


if __name__ == "__main__":
    run_stage(
        snakemake,  # noqa: F821 (injected by Snakemake's script: directive)
        main,
        "wildcards.parameter params.reference params.solver params.search output.json log=say workers=threads",
    )
