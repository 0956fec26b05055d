"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: one chunk of a
two-parameter regime map (Peterka-style).

A map has Delta0/x_st on one axis and a second parameter (theta = omega/omega1, or the damping
ratio delta = delta1 = delta2) on the other. For each value of the second parameter the gap is
swept one way (``maps.direction``), each point from its neighbour's settled motion, by the
compiled batch (:func:`impactdamper.analysis.batch.regime_map_batch`): every point is simulated
until it settles (Algorithm No. 2 with the stroboscopic period test, ``solve_point`` without
its accelerators), the Newton rescue of points that do not settle only with ``maps.rescue``.
Points the kernels cannot take go to the Python reference one by one; their count by reason is
the chunk's ``fallbacks``. The values of the second parameter are split into ``maps.chunks``
contiguous blocks, one Snakemake job each, so the map runs in parallel locally or as separate
cluster jobs (profiles/slurm); the job logs its progress per map row.

Outputs: ``results/maps/{map}/chunk_{chunk}.csv`` (one row per cell) and
``results/maps/{map}/chunk_{chunk}.json`` (the chunk's fallback counts, wall and processor
time, with start and end times so that the gather can compute the whole map's wall time).
"""

from impactdamper.studies.sweeps import gapsweep as gs
from impactdamper.studies.config import chunk_indices, parameters, sweep_settings
from impactdamper.reporting.records import Timer, machine, run_stage, write_csv, write_json
from impactdamper.analysis.batch import regime_map_batch


COLUMNS = ["i", "j", "slow", "gap", "label", "regime", "k", "z", "x1_max", "method", "periods", "fallback"]


def main(reference: dict, solver: dict, maps: dict, name: str, chunk: int, out_csv, out_json, log=None) -> dict:
    base = parameters(reference)
    settings = sweep_settings(maps, solver, continuation=False, rescue=bool(maps["rescue"]))
    slow, slow_values, gaps = gs.map_axes(maps, name)
    rows_idx = chunk_indices(len(slow_values), int(maps["chunks"]), chunk)
    out, fallbacks = [], {}
    with Timer() as timer:
        for n, i in enumerate(rows_idx):
            row = regime_map_batch(
                base, "gap", gaps, slow, [slow_values[i]], direction=maps["direction"], settings=settings
            )[0]
            for reason, count in row.fallbacks.items():
                fallbacks[reason] = fallbacks.get(reason, 0) + count
            for j, (value, label, regime, k, z, x1_max, method, periods, fallback) in enumerate(
                zip(
                    row.values[:, 0],
                    row.label,
                    row.regime,
                    row.period_multiple,
                    row.impacts_per_cycle,
                    row.x1_max,
                    row.method,
                    row.periods,
                    row.fallback,
                )
            ):
                out.append(
                    {
                        "i": int(i),
                        "j": j,
                        "slow": float(slow_values[i]),
                        "gap": float(value),
                        "label": label,
                        "regime": regime,
                        "k": int(k),
                        "z": int(z),
                        "x1_max": float(x1_max),
                        "method": method,
                        "periods": int(periods),
                        "fallback": fallback,
                    }
                )
            if log is not None:
                log.info(
                    "map %s chunk %d: row %d/%d (%s = %.6g) done in %.2f s",
                    name,
                    chunk,
                    n + 1,
                    len(rows_idx),
                    slow,
                    slow_values[i],
                    row.elapsed,
                )
    write_csv(out_csv, COLUMNS, out, booleans="digits")
    timing = {
        "map": name,
        "chunk": chunk,
        "rows": len(rows_idx),
        "cells": len(out),
        "rescue": settings.rescue,
        "fallbacks": dict(sorted(fallbacks.items())),
        "wall_s": timer.wall,
        "cpu_s": timer.cpu,
        "start_epoch": timer.epoch0,
        "end_epoch": timer.epoch1,
        "machine": machine(),
    }
    write_json(out_json, timing, indent=2)
    if log is not None:
        log.info(
            "map %s chunk %d: %d cells, fallbacks %s, wall %.1f s, cpu %.1f s",
            name,
            chunk,
            len(out),
            timing["fallbacks"],
            timer.wall,
            timer.cpu,
        )
    return timing


JOB = "params.reference params.solver params.maps wildcards.map wildcards.chunk:int output.csv output.json log=log"
STAGE = {"logger": "map_chunk", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
