"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in
the paper, which simulates and never solves a cycle directly): the branches of periodic
orbits of the reference case in Delta0/x_st, with their stability and admissibility.

The paper's prose around Fig. 2: Algorithm No. 1's one-impact orbit crosses the stop ("the
gap Delta takes on negative values when t in (t1, t2)") and Algorithm No. 2 settles to
"T_c = 2T and during this period T_c there are three collisions". Here the one-impact orbit
(seeded by Algorithm No. 1), the 2T cycle with three impacts and the 3T cycle with four
impacts (seeded by Algorithm No. 2's settled motion) are followed by pseudo-arclength
continuation (:func:`impactdamper.continue_orbit`, Floquet multipliers from saltation
matrices), with folds, period doublings, Neimark-Sacker points and grazings located on them
(see :mod:`impactdamper.studies.sweeps.branches` for where a branch ends).

Writes

* ``figures/orbit_branches.csv``: one row per orbit along each branch (gap, z/k label,
  max |x1|/x_st, least interior gap, largest multiplier modulus, stable, admissible, the
  impacts' closing velocities over x_st omega and phases);
* ``figures/orbit_special_points.csv``: kind, branch, gap, what happens;
* ``figures/orbit_summary.json``: each branch's ends and its stable and admissible stretches
  (bounded by the located special points), and the directly solved orbits of the stated case,
  of the located case (figures/located_case.json) and of the config's ``orbits.cases`` with
  their multipliers.

Deviations: none from the paper (it has no such computation); ranges and steps come from the
config's ``orbits`` section.
"""

from impactdamper.studies.sweeps import branches as br
from impactdamper.studies.config import located_gap, parameters, steady_options
from impactdamper.reporting.records import run_stage, write_csv, write_json
from impactdamper import solve_orbit


def case_summary(p, solver: dict) -> dict:
    """The directly solved steady orbit at p (Algorithm No. 1's if admissible and stable,
    else the settled cycle's: :func:`impactdamper.solve_orbit` with ``seed="auto"``)."""
    opts = steady_options(solver)
    o = solve_orbit(p, "auto", **opts)
    return {
        "gap": p.gap,
        "regime": o.regime,
        "label": br.label(o.period_multiple, o.impacts_per_cycle),
        "k": o.period_multiple,
        "z": o.impacts_per_cycle,
        "solved": o.solved,
        "seed": o.seed,
        "stable": o.stable,
        "admissible": o.admissible,
        "x1_max": o.x1_max,
        "multipliers": [abs(m) for m in o.multipliers],
        "multipliers_complex": [[m.real, m.imag] for m in o.multipliers],
        "phases": [i.phase for i in o.impacts],
        "velocities": [i.velocity / (p.x_st * p.omega) for i in o.impacts],
    }


def compute(reference: dict, solver: dict, orbits: dict, located: float, log=None) -> dict:
    """Every branch of ``orbits.branches`` and the two cases; the CSV rows and the summary."""
    p = parameters(reference)
    cont = orbits["continuation"]
    branch_rows, special_rows = [], []
    summary = {
        "paper": br.PAPER,
        "parameter": br.PARAMETER,
        "order": [b["name"] for b in orbits["branches"]],
        "branches": {},
    }
    for spec in orbits["branches"]:
        b = br.follow(p, spec, cont, solver, log)
        branch_rows += br.branch_rows(b)
        special_rows += br.special_rows(b)
        summary["branches"][b["name"]] = {
            "label": b["label"],
            "k": b["k"],
            "z": b["z"],
            "seed": spec["seed"],
            "seed_gap": float(spec["gap"]),
            "bounds": [float(spec["gap_min"]), float(spec["gap_max"])],
            "points": len(b["points"]),
            "seed_index": b["seed_index"],
            "ends": b["ends"],
            "stable": br.stretches(b, "stable"),
            "admissible": br.stretches(b, "admissible"),
        }
    summary["cases"] = {"stated": case_summary(p, solver), "located": case_summary(p.replace(gap=located), solver)}
    for case in orbits.get("cases", []):
        summary["cases"][case["name"]] = case_summary(p.replace(gap=float(case["gap"])), solver)
    summary["case_order"] = ["stated", "located"] + [c["name"] for c in orbits.get("cases", [])]
    return {"branches": branch_rows, "special": special_rows, "summary": summary}


def main(
    reference: dict, solver: dict, orbits: dict, located_json, out_branches, out_special, out_summary, log=None
) -> dict:
    res = compute(reference, solver, orbits, located_gap(located_json), log)
    write_csv(out_branches, br.BRANCH_COLUMNS, res["branches"], booleans="digits")
    write_csv(out_special, br.SPECIAL_COLUMNS, res["special"], booleans="digits")
    write_json(out_summary, res["summary"])
    return res


JOB = "params.reference params.solver params.orbits input.located output.branches output.special output.summary log=log"
STAGE = {"logger": "orbit_branches"}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
