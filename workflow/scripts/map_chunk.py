"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: one chunk of a
two-parameter regime map (Peterka-style).

A map has Delta0/x_st on one axis and a second parameter (theta = omega/omega1, or the damping
ratio delta = delta1 = delta2) on the other. For each value of the second parameter the gap is
swept one way (``maps.direction``), each point from its neighbour's settled motion
(:func:`impactdamper.analysis.sweeps.regime_map`). The values of the second parameter are split into
``maps.chunks`` contiguous blocks, one Snakemake job each, so the map runs in parallel locally
or as separate cluster jobs (profiles/slurm); the job logs its progress per map row.

Outputs: ``results/maps/{map}/chunk_{chunk}.csv`` (one row per cell) and
``results/maps/{map}/chunk_{chunk}.json`` (the chunk's wall and processor time, with start
and end times so that the gather can compute the whole map's wall time).
"""


from impactdamper.studies import gapsweep as gs
from impactdamper.studies.config import chunk_indices, parameters, sweep_settings
from impactdamper.reporting.records import Timer, machine, start_stage, write_csv, write_json
from impactdamper.analysis.sweeps import regime_map

COLUMNS = ["i", "j", "slow", "gap", "label", "regime", "k", "z", "x1_max", "method", "periods"]


def main(reference: dict, solver: dict, maps: dict, name: str, chunk: int, out_csv, out_json, log=None) -> dict:
    base = parameters(reference)
    settings = sweep_settings(maps, solver)
    slow, slow_values, gaps = gs.map_axes(maps, name)
    rows_idx = chunk_indices(len(slow_values), int(maps["chunks"]), chunk)

    def progress(i, n, row):
        if log is not None:
            log.info("map %s chunk %d: row %d/%d (%s = %.6g) done", name, chunk, i + 1, n, slow, slow_values[rows_idx[i]])

    with Timer() as timer:
        result = regime_map(base, "gap", gaps, slow, slow_values[rows_idx], direction=maps["direction"],
                            settings=settings, progress=progress)
    out = []
    for i, row in zip(rows_idx, result):
        for j, pt in enumerate(row):
            out.append({"i": int(i), "j": j, "slow": float(slow_values[i]), "gap": pt.value, "label": pt.label,
                        "regime": pt.regime, "k": pt.period_multiple, "z": pt.impacts_per_cycle, "x1_max": pt.x1_max,
                        "method": pt.method, "periods": pt.periods})
    write_csv(out_csv, COLUMNS, out, booleans="digits")
    timing = {"map": name, "chunk": chunk, "rows": len(rows_idx), "cells": len(out), "wall_s": timer.wall,
              "cpu_s": timer.cpu, "start_epoch": timer.epoch0, "end_epoch": timer.epoch1, "machine": machine()}
    write_json(out_json, timing, indent=2)
    if log is not None:
        log.info("map %s chunk %d: %d cells, wall %.1f s, cpu %.1f s", name, chunk, len(out), timer.wall, timer.cpu)
    return timing


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    cfg, log = start_stage(sm, "map_chunk", timestamps=True, library=True)
    main(cfg["reference"], cfg["solver"], cfg["maps"],
         sm.wildcards.map, int(sm.wildcards.chunk), sm.output.csv, sm.output.json, log=log)
