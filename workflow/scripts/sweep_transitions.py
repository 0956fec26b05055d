"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: where the motion
changes along the gap sweep, located by bisection and checked against analytic values.

1. Every change of Peterka's label z/k between neighbouring sweep points is bisected
   (:func:`impactdamper.analysis.sweeps.locate_transition`; each midpoint starts from the motion on
   the first label's side, as a finer sweep would) to ``transition_xtol``, each transition on its
   own in the job's threads (:func:`impactdamper.analysis.sweeps.find_transitions`).
2. The three transitions with analytic values (lift-off of the persistent contact, first
   contact, Algorithm No. 1's grazing), each computed numerically a second way and located
   again by the sweep (:func:`impactdamper.studies.sweeps.transitions.checks`, whose module docstring
   says how).

Outputs: ``figures/sweep_transitions.csv`` (every bisected transition) and
``figures/sweep_checks.json`` (the three checks).
"""

from impactdamper.analysis.sweeps import find_transitions
from impactdamper.reporting.records import Timer, clean, run_stage, write_csv, write_json
from impactdamper.studies.sweeps import gapsweep as gs
from impactdamper.studies.sweeps import transitions as tr
from impactdamper.studies.config import parameters, sweep_settings


TRANSITION_COLUMNS = ["direction", "value", "lower", "upper", "before", "after", "evaluations", "stopped", "one_sided"]


def main(
    points_npz, reference: dict, solver: dict, sweep: dict, out_csv, out_json, processes: int = 1, log=None
) -> dict:
    """Bisect the sweep's transitions (the points of ``points_npz``, written by sweep_gap.py with
    the same ``reference``, ``solver`` and ``sweep`` config) and check the three analytic ones."""
    data = gs.read_points(points_npz)
    base, parameter, settings = parameters(reference), gs.SWEEP_PARAMETER, sweep_settings(sweep, solver)
    xtol = float(sweep["transition_xtol"])
    with Timer() as timer:
        found = find_transitions(base, parameter, data, settings=settings, xtol=xtol, workers=processes)
    rows = [t.row() for d in ("up", "down") for t in found[d]]
    write_csv(out_csv, TRANSITION_COLUMNS, rows, booleans="digits")
    if log is not None:
        log.info("%d transitions bisected to %g in %.1f s", len(rows), xtol, timer.wall)
    result = {
        "parameter": parameter,
        "base": base.to_dict(),
        "transition_xtol": xtol,
        "check_xtol": float(sweep["check_xtol"]),
        "checks": tr.checks(base, parameter, data["up"], data["down"], settings, float(sweep["check_xtol"]), log),
    }
    write_json(out_json, clean(result), indent=2)
    return result


JOB = "input.points params.reference params.solver params.sweep output.csv output.json log=log processes=threads"
STAGE = {"logger": "sweep_transitions", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
