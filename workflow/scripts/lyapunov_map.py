"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the largest Lyapunov
exponent over the theta map's plane, one chunk of its rows.

The paper has no Lyapunov exponents. On the grid of ``lyapunov.map`` (Delta0/x_st against
theta), each row sweeps the gap upward, every cell settled from its neighbour's section by the
many-point call with the Newton rescue; a cell left nonperiodic after the rescue is labelled
by its spectrum from its own section (the labelling run), every other cell gets its largest
exponent from the short run (:func:`impactdamper.studies.lyapunov.exponent_map.map_rows`). The
rows are split into ``lyapunov.map.chunks`` contiguous blocks, one Snakemake job each.

Outputs: ``results/lyapunov/map_{chunk}.csv`` (one row per cell) and
``results/benchmarks/lyapunov_map_{chunk}.json`` (the chunk's wall and processor time).
"""

from impactdamper.reporting.records import Timer, run_stage, write_chunk
from impactdamper.studies.config import chunk_indices, parameters, sweep_settings
from impactdamper.studies.lyapunov.exponent_map import COLUMNS, map_axes, map_rows
from impactdamper.studies.lyapunov.sweep import RunLengths


def main(reference: dict, solver: dict, lyapunov: dict, chunk: int, out_csv, out_json, log=None) -> dict:
    section = lyapunov["map"]
    settings = sweep_settings(section, solver, continuation=False, rescue=bool(section["rescue"]))
    slow, slow_values, gaps = map_axes(section)
    rows = chunk_indices(len(slow_values), int(section["chunks"]), chunk)
    p, lengths = parameters(reference), RunLengths.from_config(lyapunov)
    with Timer() as timer:
        out = map_rows(p, slow, slow_values, gaps, rows, settings, lengths, say=None if log is None else log.info)
    return write_chunk(out_csv, COLUMNS, out, out_json, timer, chunk=chunk, cells=len(out))


JOB = "params.reference params.solver params.lyapunov wildcards.chunk:int output.csv output.json log=log"
STAGE = {"logger": "lyapunov_map", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
