"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in
the paper): the work-precision study, data only (the figure is drawn by
fig_work_precision.py).

On the reference case, the first impacts from Algorithm No. 2's default start and the
settled cycle, against the mpmath reference (src/impactdamper/baselines/highprecision/): the exact
event-driven solver across its gap tolerance, Algorithm No. 1, solve_ivp with events (RK45,
DOP853, Radau, LSODA) across rtol, fixed-step RK4 with bisection across the step, and
Siconos's Moreau-Jean time-stepping when its Python module is present (see
src/impactdamper/studies/performance/workprecision.py for the definitions of error and cost).

Outputs: ``results/benchmarks/work_precision.json`` (everything, with the per-method summary
and the speed-ups) and ``figures/work_precision.csv`` (one row per measured run). Timings are
CPU time and not deterministic.
"""

from impactdamper.studies.config import parameters
from impactdamper.reporting.records import run_stage, write_csv, write_json
from impactdamper.studies.performance import workprecision as wp


def main(reference: dict, performance: dict, out_json, out_csv, log=print) -> dict:
    p = parameters(reference)
    study = wp.run_study(p, performance, log=log)
    study["summary"] = wp.summarize(study, tuple(performance["targets"]))
    write_json(out_json, study)
    write_csv(out_csv, wp.RUN_COLUMNS, study["runs"], booleans="python", float_format=None)
    log(f"siconos: {study['siconos']['detail']}")
    return study


JOB = "params.reference params.performance output.json output.csv log=log.info"
STAGE = {"logger": "work_precision"}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
