"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the largest Lyapunov
exponent along the gap sweep, one chunk of the sweep table's rows.

The paper has no Lyapunov exponents. Each point of the sweeps stage's table
(``figures/sweep_gap.csv``, both directions) is run again from its own start state (the state
the sweep's run for it started from) and its spectrum computed by the exact tangent map after a
transient (:func:`impactdamper.studies.lyapunov.sweep.sweep_exponents`): every point with the
short run, a point the sweep calls ``np`` with the labelling run (config: lyapunov). The rows
are split into ``lyapunov.sweep_chunks`` contiguous blocks, one Snakemake job each.

Outputs: ``results/lyapunov/sweep_{chunk}.csv`` (one row per sweep row) and
``results/benchmarks/lyapunov_sweep_{chunk}.json`` (the chunk's wall and processor time).
"""

from impactdamper.reporting.records import Timer, read_csv, run_stage, write_chunk
from impactdamper.studies.config import chunk_indices, parameters, tolerances
from impactdamper.studies.lyapunov.sweep import COLUMNS, RunLengths, sweep_exponents


def main(reference: dict, solver: dict, lyapunov: dict, sweep_csv, chunk: int, out_csv, out_json, log=None) -> dict:
    rows = read_csv(sweep_csv)
    chosen = [rows[i] for i in chunk_indices(len(rows), int(lyapunov["sweep_chunks"]), chunk)]
    with Timer() as timer:
        out = sweep_exponents(
            parameters(reference),
            chosen,
            RunLengths.from_config(lyapunov),
            tolerances(solver),
            say=None if log is None else log.info,
        )
    return write_chunk(out_csv, COLUMNS, out, out_json, timer, chunk=chunk, rows=len(out))


JOB = "params.reference params.solver params.lyapunov input.sweep wildcards.chunk:int output.csv output.json log=log"
STAGE = {"logger": "lyapunov_sweep", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
