"""Cross-checks one case of the paper's Fig. 2 (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100) with the independent ``solve_ivp`` integrators.

* Algorithm No. 1: the orbit's state just after the impact is integrated by ``solve_ivp``
  over one period T with eqs. (2) + (9) written out again (no stop); the impact law applied
  at T must return the start (periodicity residual), and the gap's sign over the period is
  read from the dense output (negative intervals, claim (a)).
* Algorithm No. 2: :func:`impactdamper.baselines.ivp.simulate_ivp` runs from the paper's step 1
  for as many periods as the exact solver needed plus ``max_period_multiple``; the period
  T_c and the impacts per cycle are read off its own stroboscopic sections (claim (b)), and
  its settled cycle is compared with the exact solver's, aligned by forcing phase (the same
  k, impacts paired by t/T modulo k): impact-time differences (units of T) and closing-velocity
  differences (relative to x_st omega), each against a stated tolerance
  (config ``verdict.crosscheck_time_tol``, ``crosscheck_velocity_tol``).

"Agree" is never a comparison of counts or claims alone: ``agree_a`` needs the periodicity
residual and the negative-gap interval ends within tolerance, ``agree_b`` the aligned cycles.

Output: ``figures/crosscheck_{case}.json``.
"""

from impactdamper.studies.replication import cases as rep
from impactdamper.studies.replication import crosscheck as xc
from impactdamper.studies.config import parameters
from impactdamper.reporting.records import read_json, run_stage, say, write_json


def main(case_json, solver: dict, verdict: dict, out_json) -> dict:
    data = read_json(case_json)
    p = parameters(data["parameters"])
    kw = dict(method=verdict["ivp_method"], rtol=float(verdict["ivp_rtol"]), atol=float(verdict["ivp_atol"]))
    a = rep.run_alg1(p, solver)
    s = rep.run_steady(p, solver)
    kmax = int(solver["max_period_multiple"])
    alg1 = xc.alg1_ivp(a, **kw) if a.exists else {"claim_a": False, "reason": "no orbit"}
    time_tol, velocity_tol = float(verdict["crosscheck_time_tol"]), float(verdict["crosscheck_velocity_tol"])
    alg2 = xc.alg2_ivp(
        p,
        s.periods + kmax,
        kmax,
        section_tol=float(verdict["ivp_section_tol"]),
        exact=s,
        tolerances=rep.solver_options(solver)["tolerances"],
        time_tol=time_tol,
        velocity_tol=velocity_tol,
        **kw,
    )
    alg1_cmp = xc.compare_alg1(a, alg1, time_tol, float(verdict["crosscheck_residual_tol"]))
    out = {
        "paper": rep.PAPER,
        "case": data["case"],
        "parameters": data["parameters"],
        "algorithm1": alg1,
        "algorithm2": alg2,
        "algorithm1_comparison": alg1_cmp,
        "agree_a": alg1_cmp["agree"] and alg1["claim_a"] == data["algorithm1"]["claim_a"],
        "agree_b": alg2["agree"] and alg2["claim_b"] == data["algorithm2"]["claim_b"],
    }
    write_json(out_json, out, sort_keys=False)
    return out


if __name__ == "__main__":
    out = run_stage(snakemake, main, "input.json params.solver params.verdict output.json")  # noqa: F821 (injected by Snakemake's script: directive)
    c1, c2 = out["algorithm1_comparison"], out["algorithm2"]["cycle_comparison"]
    say(
        f"agree (a) {out['agree_a']}: interval ends {c1['max_interval_end_difference_over_T']} T, residual "
        f"{c1['periodicity_residual']}; agree (b) {out['agree_b']}: times {c2['max_time_difference_over_T']:.1e} T "
        f"(tol {c2['time_tol']:.0e}), velocities {c2['max_velocity_difference_rel']:.1e} (tol {c2['velocity_tol']:.0e})"
    )
