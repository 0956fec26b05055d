"""The parameter set nearest to the stated one where both of the paper's Fig. 2 claims hold
(Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100), searched in all seven relative
parameters at once (theta, mu, N, delta1, delta2, R, Delta0/x_st) on the compiled batch (both
claims' evaluations in the job's threads), with a margin, verified by the pure-Python reference and by solve_ivp; and the nearest set among round
values (:mod:`impactdamper.studies.claims.nearest`).

Outputs: ``figures/claims_nearest.json``; its processor times (search, verification) in
``results/benchmarks/claims_nearest_timing.json`` (timings change from run to run and stay out
of the record).
"""

import time

from impactdamper.studies.replication import cases as rep
from impactdamper.reporting.records import run_stage, write_json
from impactdamper.studies.config import parameters, sweep_settings
from impactdamper.studies.claims.answer_check import verify_point
from impactdamper.studies.claims.claims_evaluator import NEAREST_NAMES, ClaimsEvaluator
from impactdamper.studies.claims.nearest import nearest_set
from impactdamper.studies.claims.round_changes import round_values


def main(
    reference: dict, solver: dict, verdict: dict, search: dict, out_json, out_timing=None, log=print, workers: int = 1
) -> dict:
    n = search["nearest"]
    base = parameters(reference)
    gap_tol = float(solver["gap_tol"])
    caps = {"settle_tol": solver["settle_tol"], "max_period_multiple": solver["max_period_multiple"]}
    screen = sweep_settings(
        {**caps, "max_periods": n["max_periods"], "max_periods_after_nonperiodic": n["max_periods"]},
        solver,
        continuation=False,
        rescue=False,
    )
    full = sweep_settings(
        {**caps, "max_periods": solver["max_periods"], "max_periods_after_nonperiodic": solver["max_periods"]},
        solver,
        continuation=False,
        rescue=False,
    )
    ev, check = ClaimsEvaluator(base, gap_tol, screen, workers), ClaimsEvaluator(base, gap_tol, full, workers)
    cpu = time.process_time()
    joint = nearest_set(
        ev,
        check=check,
        rays=int(n["rays"]),
        seed=int(n["seed"]),
        ray_step=float(n["ray_step"]),
        ray_max=float(n["ray_max"]),
        ray_tol=float(n["ray_tol"]),
        margin=float(n["margin"]),
        starts=int(n["starts"]),
        compass_step=float(n["compass_step"]),
        compass_floor=float(n["compass_floor"]),
        ball_points=int(n["ball_points"]),
        log=log,
    )
    search_cpu = time.process_time() - cpu
    ranges = {name: (float(r["start"]), float(r["stop"])) for name, r in search["parameters"].items()}
    ranges["gap"] = (float(verdict["gap_min"]), float(verdict["gap_max"]))
    rounds = round_values(check, ranges, float(n["margin"]))
    log(f"round values: {len(rounds['reproducing'])} of {rounds['candidates']} reproduce")
    cpu = time.process_time()
    for which, ans in joint["answers"].items():
        if ans is not None:
            ans["verification"] = verify_point(base.replace(**ans["values"]), solver, verdict)
            log(f"{which}: verified, every method both claims: {ans['verification']['both_hold_every_method']}")
    for row in rounds["reproducing"]:
        row["verification"] = verify_point(base.replace(**row["changes"]), solver, verdict)
    verify_cpu = time.process_time() - cpu
    out = {
        "paper": rep.PAPER,
        "what": "the parameter set nearest to the stated one where both claims hold with a margin, searched in "
        "all seven relative parameters at once; distance: relative changes u_i = x_i/x_i,stated - 1, "
        "equally weighted (each a dimensionless ratio stated to one or two digits), in the max-norm and "
        "the Euclidean norm; margin: both claims hold at the answer, its 14 axis points and random points "
        "on the Euclidean ball of radius 'margin' around it (full solver settings)",
        "names": list(NEAREST_NAMES),
        "stated": {k: float(getattr(base, k)) for k in NEAREST_NAMES},
        "settings": {**n, "solver_max_periods": int(solver["max_periods"])},
        "joint": joint,
        "round_values": {
            "rule": "one significant digit of one parameter as the paper writes it replaced, or one "
            "unit of its last digit up or down (1 -> 0.9); pairs only if no single change "
            "reproduces; 'keeps_tuning_condition': theta = 1 and N = 0.5 unchanged, the "
            "paper's 2 sqrt(c2/m2) = sqrt(c1/m1) = omega",
            **rounds,
        },
    }
    write_json(out_json, out, sort_keys=False)
    timing = {
        "what": "processor time of the nearest-set search and of its verifications, s",
        "search": round(search_cpu, 1),
        "verification": round(verify_cpu, 1),
        "points": joint.get("points"),
        "batch_points": joint.get("batch_points"),
    }
    log(f"cpu: search {search_cpu:.1f} s, verification {verify_cpu:.1f} s")
    if out_timing is not None:
        write_json(out_timing, timing, sort_keys=False)
    return out


JOB = "params.reference params.solver params.verdict params.search output.json output.timing log=say workers=threads"

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
