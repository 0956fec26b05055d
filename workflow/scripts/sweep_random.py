"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: random initial states
along the gap sweep (one chunk of them).

Where motions coexist, the neighbour-started sweeps show only the one each direction follows;
several random initial states per sweep point show the others: the compiled batch
:func:`impactdamper.analysis.batch.random_starts_batch` (the states of
:func:`impactdamper.analysis.sweeps.random_start_states`, fixed seed; the generator of point i, start
j is seeded with (seed, i, j), so chunks do not change the result; a start the kernels do not
settle goes to the pure-Python reference, with its Newton rescue). Every ``random_every``-th sweep point gets
``random_starts`` states.

Output: ``results/sweeps/random_{chunk}.csv`` (gathered into ``figures/sweep_random.csv``).
"""

from impactdamper.studies.sweeps import gapsweep as gs
from impactdamper.studies.config import chunk_indices, parameters, sweep_settings
from impactdamper.reporting.records import Timer, joined, run_stage, write_csv
from impactdamper.analysis.batch import random_starts_batch


def points_of(sweep: dict):
    """(indices, values) of the sweep points that get random starts."""
    values = gs.grid(sweep["start"], sweep["stop"], sweep["points"])
    idx = list(range(0, len(values), int(sweep["random_every"])))
    return idx, values[idx]


def main(reference: dict, solver: dict, sweep: dict, chunk: int, out_csv, log=None) -> list[dict]:
    base = parameters(reference)
    settings = sweep_settings(sweep, solver)
    idx, values = points_of(sweep)
    mine = chunk_indices(len(idx), int(sweep["random_chunks"]), chunk)
    indices = [idx[i] for i in mine]
    with Timer() as timer:

        def progress(i, n, pt):
            if log is not None and ((i + 1) % max(n // 10, 1) == 0 or i + 1 == n):
                log.info("random starts: %d/%d values (%s = %.6g)", i + 1, n, gs.SWEEP_PARAMETER, pt.value)

        res = random_starts_batch(
            base,
            gs.SWEEP_PARAMETER,
            values[mine],
            int(sweep["random_starts"]),
            int(sweep["seed"]),
            indices=indices,
            settings=settings,
        )
        for i, starts in enumerate(res):
            progress(i, len(res), starts[-1])
    rows = []
    for i, starts in zip(indices, res):
        for j, pt in enumerate(starts):
            rows.append(
                {
                    "index": i,
                    "start_index": j,
                    "value": pt.value,
                    "label": pt.label,
                    "regime": pt.regime,
                    "k": pt.period_multiple,
                    "z": pt.impacts_per_cycle,
                    "x1_max": pt.x1_max,
                    "method": pt.method,
                    "periods": pt.periods,
                    "velocities": joined(pt.velocities),
                }
            )
    write_csv(out_csv, gs.RANDOM_COLUMNS, rows, booleans="digits")
    if log is not None:
        log.info("chunk %d: %d runs, wall %.1f s, cpu %.1f s", chunk, len(rows), timer.wall, timer.cpu)
    return rows


JOB = "params.reference params.solver params.sweep wildcards.chunk:int output.csv log=log"
STAGE = {"logger": "sweep_random", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
