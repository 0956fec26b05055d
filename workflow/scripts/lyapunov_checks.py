"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the checks of the
compiled Lyapunov spectrum that do not use its tangent walk.

The paper has no Lyapunov exponents. At the stable periodic orbits of ``lyapunov.checks``
the exponents against the orbit solver's Floquet multipliers; at np points of the gap sweep
(each checked to be np in the sweep's table) the largest exponent against Benettin's
two-trajectory estimate by the solver alone; the sum of the exponents against its closed form
(the free flow's trace and 2 log R per impact); the compiled walk against the reference's at a
periodic and a chaotic point; one point's label over a short and a long window
(:mod:`impactdamper.studies.lyapunov.checks`).

Output: ``figures/lyapunov_checks.json`` (deterministic: no timings).
"""

from impactdamper.reporting.records import read_csv, run_stage, write_json
from impactdamper.studies.config import parameters
from impactdamper.studies.lyapunov import checks as ck


def main(reference: dict, lyapunov: dict, sweep_csv, out_json, log=None) -> dict:
    base = parameters(reference)
    c = lyapunov["checks"]
    run = dict(periods=int(c["periods"]))
    np_values = {(r["direction"], round(float(r["value"]), 9)) for r in read_csv(sweep_csv) if r["label"] == "np"}

    def at(gap):
        return base.replace(gap=float(gap))

    out = {
        "run": {"periods": run["periods"]},
        "benettin_floor": ck.BENETTIN_FLOOR,
        "benettin_eps": ck.BENETTIN_EPS,
        "floquet": [ck.floquet_check(at(g), run) for g in c["floquet_gaps"]],
        "benettin": [],
        "sum_rule": [ck.sum_rule_check(at(g), run) for g in c["sum_rule_gaps"]],
        "backends": [ck.backends_check(at(g), run) for g in c["backends_gaps"]],
        "windows": ck.window_check(at(c["window_gap"]), c["window_runs"]),
        "torus": ck.torus_check(c["torus_orbit_gap"], c["torus_gaps"], c["torus_transient"], base),
    }
    for g in c["benettin_gaps"]:
        row = ck.benettin_check(at(g), run)
        row["sweep_np"] = [d for d in ("up", "down") if (d, round(float(g), 9)) in np_values]
        out["benettin"].append(row)
        if log is not None:
            log.info("Benettin at gap %g: %s", g, row)
    write_json(out_json, out, indent=1)
    return out


JOB = "params.reference params.lyapunov input.sweep output.json log=log"
STAGE = {"logger": "lyapunov_checks", "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
