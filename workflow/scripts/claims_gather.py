"""Gathers the search beyond the gap (claims_parameter.py, one job per parameter) for the
paper's Fig. 2 claims (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100).

Outputs:

* ``figures/claims_by_parameter.csv``: columns ``parameter, claim, lo, hi``, one row per
  interval where claim ``a``, ``b`` or ``both`` holds (each parameter varied alone at the
  stated Delta0/x_st, the others as stated);
* ``figures/claims_by_parameter_settings.json``: the settings (stated point, ranges, grids,
  tolerances, solver), every interval with its open ends and bisection brackets, and for each
  parameter the nearest value where both claims hold and its distance from the stated value
  (absolute and relative);
* ``figures/claims_by_parameter_grid.csv``: the grid behind the figure (Algorithm No. 2's
  settled motion at every value);
* ``paper/generated/claims_table.tex``: the report's table of the nearest interval where both
  claims hold, per parameter.
"""

from pathlib import Path

from impactdamper.studies.replication import cases as rep
from impactdamper.reporting.records import read_json, run_stage, say, write_csv, write_json
from impactdamper.studies.claims.record import table
from impactdamper.studies.claims.search import SEARCH_PARAMETERS, nearest_both, solver_dependent


PARAMETERS = SEARCH_PARAMETERS
CLAIMS = ("a", "b", "both")
GRID_COLUMNS = [
    "parameter",
    "value",
    "claim_b",
    "regime",
    "period_multiple",
    "impacts_per_cycle",
    "periods",
    "label",
    "method",
    "level",
]


def main(inputs: dict, reference: dict, solver: dict, search: dict, out_csv, out_json, out_grid, out_tex) -> dict:
    rows, grid, per = [], [], {}
    for name in PARAMETERS:
        r = read_json(inputs[name])
        for claim in CLAIMS:
            for iv in r["intervals"][claim]:
                rows.append({"parameter": name, "claim": claim, "lo": iv["lo"], "hi": iv["hi"]})
        for g in r["grid_b"] + r["bisection_points"]:
            grid.append({"parameter": name, **g})
        per[name] = {
            "range": r["range"],
            "refinement": r.get("refinement"),
            "intervals": r["intervals"],
            "nearest_both": nearest_both(r),
            "claim_a_grid_true": sum(r["claim_a_flags"]),
            "claim_b_grid_true": sum(g["claim_b"] for g in r["grid_b"]),
            "reference_check": r["reference_check"],
        }
        per[name]["solver_dependent_ends"] = solver_dependent(per[name])
    grid.sort(key=lambda g: (PARAMETERS.index(g["parameter"]), g["value"]))
    settings = {
        "paper": rep.PAPER,
        "what": "each parameter varied alone at the stated Delta0/x_st, the others as stated; claim (a): Algorithm No. 1's "
        "gap goes negative between impacts; claim (b): Algorithm No. 2 from the paper's step 1 settles to "
        "T_c = 2T with three impacts; both: the intersection",
        "reference": reference,
        "solver": solver,
        "rel_tol": float(search["rel_tol"]),
        "floor": float(search["floor"]),
        "refine_levels": int(search["refine_levels"]),
        "resolution_note": "claim (b)'s grid (step per parameter in 'refinement') is halved, up to refine_levels times "
        "(down to its 'floor'), wherever the settled motion's label (z/k, np) changes between "
        "neighbours or a value does not settle (nonperiodic values rescued by Newton's method "
        "first); a window narrower than the floor, or one inside a run of a single settled label "
        "narrower than the step, is not seen; claim (a) on its own grid (alg1_step); ends are "
        "bisected to rel_tol * max(|x|, floor)",
        "reference_check": {
            "what": "Algorithm No. 2 runs compiled; the pure-Python solver repeats it at every "
            "reference_check_every-th grid value and both ends of every final bisection bracket of claim "
            "(b): the same regime, "
            "k, z and claim (b) agree; 'settling': disagreements where one run settled within max_periods and "
            "the other did not; 'cycles': where both settled on different cycles",
            "every": int(search["reference_check_every"]),
            "points": sum(per[n]["reference_check"]["points"] for n in PARAMETERS),
            "agree": sum(per[n]["reference_check"]["agree"] for n in PARAMETERS),
            "settling": sum(per[n]["reference_check"]["settling"] for n in PARAMETERS),
            "cycles": sum(per[n]["reference_check"]["cycles"] for n in PARAMETERS),
        },
        "parameters": per,
    }
    write_csv(out_csv, ["parameter", "claim", "lo", "hi"], rows)
    write_csv(out_grid, GRID_COLUMNS, grid)
    write_json(out_json, settings, sort_keys=False)
    Path(out_tex).parent.mkdir(parents=True, exist_ok=True)
    Path(out_tex).write_text(table(per))
    return settings


JOB = (
    lambda j: dict(zip(PARAMETERS, j.input.results)),
    "params.reference params.solver params.search output.csv output.json output.grid output.tex",
)

if __name__ == "__main__":
    out = run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
    for name, d in out["parameters"].items():
        say(f"{name}: nearest both {d['nearest_both']}")
