"""Computes one case of the paper's Fig. 2 (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100): Algorithm No. 1's orbit and Algorithm No. 2's settled
motion, the data behind Fig. 2a, Fig. 2b and the impact-time table.

Outputs (``case`` is ``stated`` or ``located``):

* ``figures/reference_{case}.json``: the parameters, Algorithm No. 1 (impact phase, pulse,
  negative-gap intervals in units of T since the impact, claim (a)) and the settled motion
  (regime, T_c/T, impacts of the cycle plus the next cycle's first, claim (b));
* ``figures/fig2a_{case}.csv``: t/T since the impact, x1_bar, x2_bar, gap/x_st over one
  forcing period of Algorithm No. 1's orbit;
* ``figures/fig2b_{case}.csv``: (t - t1)/T, x1_bar, x2_bar, gap/x_st over the settled cycle
  plus the next impact (and a margin of ``FIG2B_MARGIN`` T).
"""

import numpy as np

from impactdamper.studies.replication import cases as rep
from impactdamper.reporting.records import read_json, run_stage, say, write_csv, write_json


# How far past the next cycle's first impact Fig. 2b runs, and how far before t1, in T.
FIG2B_MARGIN = 0.12
FIG2B_LEAD = 0.05
CURVE_COLUMNS = ["t_over_T", "x1_bar", "x2_bar", "gap"]


def _alg1_curve(a) -> list[dict]:
    p = a.p
    n = rep.SAMPLES_PER_PERIOD
    tau = np.linspace(0.0, 1.0, n + 1)
    marks = [x for iv in a.negative_gap_intervals for x in iv]
    tau = np.unique(np.concatenate([tau, np.asarray(marks, dtype=float)]))
    full = a.sample(tau * p.T)
    x1b, x2b = full[:, 0] / p.x_st, (full[:, 1] - p.Delta0) / p.x_st
    return [
        {"t_over_T": float(t), "x1_bar": float(u), "x2_bar": float(v), "gap": float(u - v)}
        for t, u, v in zip(tau, x1b, x2b)
    ]


def _alg2_curve(s, table: list[dict]) -> list[dict]:
    p = s.p
    span_end = (table[-1]["t_over_T"] if table else s.cycle_duration / p.T) + FIG2B_MARGIN
    n = int(round((span_end + FIG2B_LEAD) * rep.SAMPLES_PER_PERIOD))
    tau = np.linspace(-FIG2B_LEAD, span_end, n + 1)
    tau = np.unique(np.concatenate([tau, [row["t_over_T"] for row in table]]))
    x1b, x2b = s.sample(s.cycle_start + tau * p.T)
    return [
        {"t_over_T": float(t), "x1_bar": float(u), "x2_bar": float(v), "gap": float(u - v)}
        for t, u, v in zip(tau, x1b, x2b)
    ]


def main(case: str, parameters: dict, solver: dict, out_json, out_fig2a, out_fig2b, origin: str = "") -> dict:
    """Compute the case and write its three files. Returns the JSON object written."""
    if case not in rep.CASES:
        raise ValueError(f"`case` = {case!r} is not allowed: must be one of {', '.join(rep.CASES)}")
    p = rep.parameters(parameters)
    a = rep.run_alg1(p, solver)
    s = rep.run_steady(p, solver)
    steady = rep.steady_summary(s)
    result = {
        "paper": rep.PAPER,
        "case": case,
        "origin": origin,
        "parameters": p.to_dict(),
        "T": p.T,
        "algorithm1": rep.alg1_summary(a),
        "algorithm2": steady,
    }
    write_json(out_json, result, sort_keys=False)
    write_csv(out_fig2a, CURVE_COLUMNS, _alg1_curve(a) if a.exists else [])
    write_csv(out_fig2b, CURVE_COLUMNS, _alg2_curve(s, steady["impact_table"]))
    return result


def case_of(job) -> tuple[dict, str]:
    """The case's parameters and where they come from: the config's stated case, or the gap
    scan's located one."""
    if job.params.case == "stated":
        return job.params.reference, "the paper's stated reference case (config: reference)"
    located = read_json(job.input.located)["located"]
    return located["parameters"], located["rule"]


JOB = (
    "params.case",
    lambda j: case_of(j)[0],
    "params.solver output.json output.fig2a output.fig2b",
    lambda j: case_of(j)[1],
)

if __name__ == "__main__":
    out = run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
    say(
        f"{out['case']}: gap {out['parameters']['gap']}, claim (a) {out['algorithm1']['claim_a']}, "
        f"regime {out['algorithm2']['regime']}, T_c = {out['algorithm2']['T_c_over_T']} T, "
        f"claim (b) {out['algorithm2']['claim_b']}"
    )
