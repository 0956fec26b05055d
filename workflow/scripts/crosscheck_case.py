"""Cross-checks one case of the paper's Fig. 2 (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100) with the independent ``solve_ivp`` integrators.

* Algorithm No. 1: the orbit's state just after the impact is integrated by ``solve_ivp``
  over one period T with eqs. (2) + (9) written out again (no stop); the impact law applied
  at T must return the start (periodicity residual), and the gap's sign over the period is
  read from the dense output (negative intervals, claim (a)).
* Algorithm No. 2: :func:`impactdamper.crosscheck.simulate_ivp` runs from the paper's step 1
  for as many periods as the exact solver needed plus ``max_period_multiple``; the period
  T_c and the impacts per cycle are read off its own stroboscopic sections (claim (b)), and
  its impacts in the exact solver's reported cycle are compared with the exact ones.

Output: ``figures/crosscheck_{case}.json``.
"""

import replication as rep


def main(case_json, solver: dict, verdict: dict, out_json) -> dict:
    data = rep.read_json(case_json)
    p = rep.parameters(data["parameters"])
    kw = dict(method=verdict["ivp_method"], rtol=float(verdict["ivp_rtol"]), atol=float(verdict["ivp_atol"]))
    a = rep.run_alg1(p, solver)
    s = rep.run_steady(p, solver)
    kmax = int(solver["max_period_multiple"])
    alg1 = rep.alg1_ivp(a, **kw) if a.exists else {"claim_a": False, "reason": "no orbit"}
    alg2 = rep.alg2_ivp(p, s.periods + kmax, kmax, section_tol=float(verdict["ivp_section_tol"]), exact=s,
                        tolerances=rep.solver_options(solver)["tolerances"], **kw)
    exact_a, exact_b = data["algorithm1"]["claim_a"], data["algorithm2"]["claim_b"]
    out = {
        "paper": rep.PAPER,
        "case": data["case"],
        "parameters": data["parameters"],
        "algorithm1": alg1,
        "algorithm2": alg2,
        "agree_a": alg1["claim_a"] == exact_a,
        "agree_b": alg2["claim_b"] == exact_b and alg2["period_multiple"] == data["algorithm2"]["period_multiple"],
    }
    rep.write_json(out_json, out)
    return out


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    import sys

    sys.stderr = open(sm.log[0], "w")
    out = main(sm.input.json, rep.json.loads(sm.params.solver), rep.json.loads(sm.params.verdict), sm.output.json)
    print(f"agree (a) {out['agree_a']}, agree (b) {out['agree_b']}", file=sys.stderr)
