"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the gap sweep.

The paper's introduction: with a negative initial gap "the object and the suppressor move
together" at small forcing, work "with one impact per period" at large forcing, and pass
through several impacts per period in between. Here Delta0/x_st is swept upward and downward
over a range covering every regime of the reference case (persistent contact to no
contact), each point starting from its neighbour's settled motion
(:func:`impactdamper.analysis.sweeps.two_way_sweep`; the accelerators and what "nonperiodic" means are
in that module's docstring).

Outputs: ``figures/sweep_gap_settings.json`` (the configuration it ran with, for the record
test), ``figures/sweep_gap.csv`` (one row per point and direction: label z/k, regime,
stability, max |x1|/x_st, impact velocities over x_st omega, and the state the point started
from, so that any row can be recomputed on its own), ``results/sweeps/sweep_points.npz``
(the points themselves as arrays, :func:`impactdamper.studies.sweeps.gapsweep.write_points`, for the
transition bisection) and
``results/benchmarks/sweep_timing.json`` (wall and processor time of the two-way sweep, timed
inside this job, beside the config's target ``performance.sweep_target_wall_s``).
"""

from impactdamper.studies.sweeps import gapsweep as gs
from impactdamper.studies.config import parameters, sweep_settings
from impactdamper.reporting.records import Timer, machine, run_stage, write_csv, write_json
from impactdamper.analysis.sweeps import two_way_sweep


def main(
    reference: dict,
    solver: dict,
    sweep: dict,
    out_csv,
    out_settings,
    out_points,
    out_timing,
    processes: int = 1,
    log=None,
    *,
    target_wall_s: float,
) -> dict:
    base = parameters(reference)
    settings = sweep_settings(sweep, solver)
    values = gs.grid(sweep["start"], sweep["stop"], sweep["points"])
    if log is not None:
        log.info(
            "two-way sweep of %s over [%g, %g], %d points, %d process(es)",
            gs.SWEEP_PARAMETER,
            values[0],
            values[-1],
            len(values),
            processes,
        )
    before = machine()
    with Timer() as timer:
        res = two_way_sweep(base, gs.SWEEP_PARAMETER, values, settings=settings, processes=processes)
    rows = [gs.point_row(d, i, pt) for d in ("up", "down") for i, pt in enumerate(res[d])]
    write_csv(out_csv, gs.POINT_COLUMNS, rows, booleans="digits")
    write_json(
        out_settings,
        {"reference": reference, "solver": solver, "sweep": sweep, "parameter": gs.SWEEP_PARAMETER},
        indent=2,
    )
    gs.write_points(out_points, {"up": res["up"], "down": res["down"]})
    timing = {
        "what": f"two-way sweep of {gs.SWEEP_PARAMETER}, {len(values)} points each way",
        "points": len(values),
        "processes": processes,
        "wall_s": timer.wall,
        "cpu_s": res["cpu"],
        "wall_per_direction_s": res["wall"],
        "target_wall_s": float(target_wall_s),
        "machine_before": before,
        "machine_after": machine(),
        "methods": {d: _count(res[d], "method") for d in ("up", "down")},
        "periods_simulated": {d: int(sum(p.periods for p in res[d])) for d in ("up", "down")},
    }
    write_json(out_timing, timing, indent=2)
    if log is not None:
        log.info("done: wall %.1f s, cpu up %.1f s, down %.1f s", timer.wall, res["cpu"]["up"], res["cpu"]["down"])
    return timing


def _count(points, attr: str) -> dict:
    out: dict = {}
    for p in points:
        key = getattr(p, attr)
        out[key] = out.get(key, 0) + 1
    return dict(sorted(out.items()))


JOB = (
    "params.reference params.solver params.sweep output.csv output.settings output.points "
    "output.timing log=log target_wall_s=params.target_wall_s:float"
)
STAGE = {"logger": "sweep_gap", "timestamps": True, "library": True}
# The two sweep directions, one process each (at most the job's threads).
TWO_DIRECTIONS = lambda j: min(int(j.threads), 2)  # noqa: E731

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, processes=TWO_DIRECTIONS, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
