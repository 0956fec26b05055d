"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: one chunk of a
two-parameter regime map (Peterka-style), Delta0/x_st against theta or the damping ratio,
computed where its labels change and checked against the brute force on some of its rows
(:func:`impactdamper.studies.sweeps.mapchunk.regime_map_chunk`, whose docstring says how). The
rows are dealt to ``maps.chunks`` chunks in turn, one Snakemake job each, so the map runs in
parallel locally or as separate cluster jobs (profiles/slurm).

Outputs: ``results/maps/{map}/chunk_{chunk}.csv`` (one row per cell, ``computed`` false where
filled) and ``results/maps/{map}/chunk_{chunk}.json`` (the chunk's cells computed, its check
against the brute force, fallback counts, wall and processor time, with start and end times so
that the gather can compute the whole map's wall time).
"""

from impactdamper.reporting.records import run_stage, write_chunk
from impactdamper.studies.sweeps.mapchunk import CHUNK_COLUMNS, regime_map_chunk


def main(reference: dict, solver: dict, maps: dict, name: str, chunk: int, out_csv, out_json, log=None) -> dict:
    rows, counts, timer = regime_map_chunk(reference, solver, maps, name, chunk, log)
    return write_chunk(out_csv, CHUNK_COLUMNS, rows, out_json, timer, epochs=True, booleans="digits", **counts)


JOB = "params.reference params.solver params.maps wildcards.map wildcards.chunk:int output.csv output.json log=log"
STAGE = {"logger": "map_chunk", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
