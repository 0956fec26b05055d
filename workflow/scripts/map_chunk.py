"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: one chunk of a
two-parameter regime map (Peterka-style).

A map has Delta0/x_st on one axis and a second parameter (theta = omega/omega1, or the damping
ratio delta = delta1 = delta2) on the other. For each value of the second parameter the gap is
swept one way (``maps.direction``), each cell from its left neighbour's settled motion, as the
compiled batch's :func:`impactdamper.analysis.batch.regime_map_batch` sweeps it (Algorithm No. 2
with the stroboscopic period test, ``solve_point`` without its accelerators; the Newton rescue of
cells that do not settle only with ``maps.rescue``), but computed where the labels change
(:func:`impactdamper.analysis.adaptive.adaptive_regime_map`): every ``maps.coarse_step``-th cell
of a row first, then the cells between two of different labels or an unsettled one, each from
its nearest computed left neighbour, the rest filled. About every ``maps.check_every``-th row
(each chunk's every ``check_every / chunks``-th) is swept cell by cell as well, the brute force,
and the two compared
(:func:`impactdamper.analysis.adaptive.label_differences`). Cells the kernels cannot take go to
the Python reference one by one; their count by reason is the chunk's ``fallbacks``. The rows
are dealt to ``maps.chunks`` chunks in turn (chunk c takes rows c, c + chunks, ...: the costly
rows near resonance lie together), one Snakemake job each, so the map runs in parallel locally
or as separate cluster jobs (profiles/slurm).

Outputs: ``results/maps/{map}/chunk_{chunk}.csv`` (one row per cell, ``computed`` false where
filled) and ``results/maps/{map}/chunk_{chunk}.json`` (the chunk's cells computed, its check
against the brute force, fallback counts, wall and processor time, with start and end times so
that the gather can compute the whole map's wall time).
"""

import numpy as np

from impactdamper.analysis.adaptive import adaptive_regime_map, label_differences
from impactdamper.analysis.batch import regime_map_batch
from impactdamper.reporting.records import Timer, run_stage, write_chunk
from impactdamper.studies.config import parameters, sweep_settings
from impactdamper.studies.sweeps import gapsweep as gs

COLUMNS = [
    "i",
    "j",
    "slow",
    "gap",
    "label",
    "regime",
    "k",
    "z",
    "x1_max",
    "method",
    "periods",
    "fallback",
    "computed",
]


def chunk_rows(rows: int, chunks: int, chunk: int) -> np.ndarray:
    """The rows of chunk ``chunk``: ``chunk``, ``chunk + chunks``, ... (dealt in turn)."""
    if not (0 <= chunk < chunks):
        raise ValueError(f"`chunk` = {chunk!r} is not allowed: must be in [0, {chunks})")
    return np.arange(chunk, rows, chunks)


def main(reference: dict, solver: dict, maps: dict, name: str, chunk: int, out_csv, out_json, log=None) -> dict:
    base = parameters(reference)
    settings = sweep_settings(maps, solver, continuation=False, rescue=bool(maps["rescue"]))
    slow, slow_values, gaps = gs.map_axes(maps, name)
    rows_idx = chunk_rows(len(slow_values), int(maps["chunks"]), chunk)
    # The brute force's rows, every check_every-th row of the map spread over the chunks (chunk c's
    # every (check_every / chunks)-th row: rows c, c + check_every, ... when it divides).
    every = int(maps["check_every"])
    check_idx = list(range(0, len(rows_idx), max(1, every // int(maps["chunks"])))) if every else []
    with Timer() as timer:
        m = adaptive_regime_map(
            base,
            "gap",
            gaps,
            slow,
            slow_values[rows_idx],
            direction=maps["direction"],
            settings=settings,
            coarse_step=int(maps["coarse_step"]),
        )
    labels = m.label
    if log is not None:
        log.info(
            "map %s chunk %d: %d rows, %d of %d cells computed (%d settlings in %d rounds), %.1f s",
            name,
            chunk,
            len(rows_idx),
            int(m.computed.sum()),
            m.computed.size,
            m.settlings,
            len(m.points_per_round),
            timer.wall,
        )
    with Timer() as check_timer:
        brute = regime_map_batch(
            base, "gap", gaps, slow, slow_values[rows_idx[check_idx]], direction=maps["direction"], settings=settings
        )
    reference_labels = labels.copy()
    for n, row in zip(check_idx, brute):
        reference_labels[n] = row.label
    check = label_differences(labels, reference_labels, rows=check_idx)
    check.update(rows=[int(rows_idx[n]) for n in check_idx], cpu_s=check_timer.cpu)
    if log is not None:
        log.info(
            "map %s chunk %d: brute force on rows %s: %d of %d cells differ (distances to a change %s), %.1f s",
            name,
            chunk,
            check["rows"],
            check["differences"],
            check["cells"],
            check["distances"],
            check_timer.wall,
        )
    out = []
    for n, i in enumerate(rows_idx):
        for j, gap in enumerate(m.fast_values):
            out.append(
                {
                    "i": int(i),
                    "j": j,
                    "slow": float(slow_values[i]),
                    "gap": float(gap),
                    "label": labels[n, j],
                    "regime": gs.regime_of_label(labels[n, j]),
                    "k": int(m.period_multiple[n, j]),
                    "z": int(m.impacts_per_cycle[n, j]),
                    "x1_max": float(m.x1_max[n, j]),
                    "method": m.method[n, j],
                    "periods": int(m.periods[n, j]),
                    "fallback": m.fallback[n, j],
                    "computed": bool(m.computed[n, j]),
                }
            )
    return write_chunk(
        out_csv,
        COLUMNS,
        out,
        out_json,
        timer,
        epochs=True,
        booleans="digits",
        map=name,
        chunk=chunk,
        rows=len(rows_idx),
        cells=int(m.computed.size),
        computed=int(m.computed.sum()),
        settlings=m.settlings,
        points_per_round=m.points_per_round,
        coarse_step=m.coarse_step,
        rescue=settings.rescue,
        fallbacks=m.fallbacks,
        check=check,
        periods_simulated=int(m.periods.sum()),
    )


JOB = "params.reference params.solver params.maps wildcards.map wildcards.chunk:int output.csv output.json log=log"
STAGE = {"logger": "map_chunk", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
