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
from, so that any row can be recomputed on its own), ``results/sweeps/sweep_points.pkl``
(the points themselves, for the transition bisection) and
``results/benchmarks/sweep_timing.json`` (wall and processor time of the two-way sweep, timed
inside this job).
"""

import pickle
from pathlib import Path

import sweepstage as st
from impactdamper.analysis.sweeps import two_way_sweep


def main(reference: dict, solver: dict, sweep: dict, out_csv, out_settings, out_pkl, out_timing,
         processes: int = 1, log=None) -> dict:
    base = st.parameters(reference)
    settings = st.settings(sweep, solver)
    values = st.grid(sweep["start"], sweep["stop"], sweep["points"])
    if log is not None:
        log.info("two-way sweep of %s over [%g, %g], %d points, %d process(es)", st.SWEEP_PARAMETER,
                 values[0], values[-1], len(values), processes)
    before = st.machine()
    with st.Timer() as timer:
        res = two_way_sweep(base, st.SWEEP_PARAMETER, values, settings=settings, processes=processes)
    rows = [st.point_row(d, i, pt) for d in ("up", "down") for i, pt in enumerate(res[d])]
    st.write_csv(out_csv, rows, st.POINT_COLUMNS)
    st.write_json(out_settings, {"reference": reference, "solver": solver, "sweep": sweep,
                                 "parameter": st.SWEEP_PARAMETER})
    Path(out_pkl).parent.mkdir(parents=True, exist_ok=True)
    with open(out_pkl, "wb") as f:
        pickle.dump({"base": base, "parameter": st.SWEEP_PARAMETER, "settings": settings,
                     "up": res["up"], "down": res["down"]}, f)
    timing = {
        "what": f"two-way sweep of {st.SWEEP_PARAMETER}, {len(values)} points each way",
        "points": len(values),
        "processes": processes,
        "wall_s": timer.wall,
        "cpu_s": res["cpu"],
        "wall_per_direction_s": res["wall"],
        "target_wall_s": 60.0,
        "machine_before": before,
        "machine_after": st.machine(),
        "methods": {d: _count(res[d], "method") for d in ("up", "down")},
        "periods_simulated": {d: int(sum(p.periods for p in res[d])) for d in ("up", "down")},
    }
    st.write_json(out_timing, timing)
    if log is not None:
        log.info("done: wall %.1f s, cpu up %.1f s, down %.1f s", timer.wall, res["cpu"]["up"], res["cpu"]["down"])
    return timing


def _count(points, attr: str) -> dict:
    out: dict = {}
    for p in points:
        key = getattr(p, attr)
        out[key] = out.get(key, 0) + 1
    return dict(sorted(out.items()))


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    import json

    log = st.logger(sm.log[0], "sweep_gap")
    main(json.loads(sm.params.reference), json.loads(sm.params.solver), json.loads(sm.params.sweep),
         sm.output.csv, sm.output.settings, sm.output.pkl, sm.output.timing, processes=min(int(sm.threads), 2), log=log)
