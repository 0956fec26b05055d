"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper, which shows no map): every boundary of a regime map as a curve.

The special points of the branches of periodic cycles found on ``boundaries.seed_rows`` rows of
the map (Algorithm No. 1's orbit and the settled cycles at ``boundaries.seed_gaps`` gaps per
row, followed in the gap, and the settled cycles at the seeds of the one-parameter branches
of ``orbits.branches`` on the reference row, and at ``boundaries.extra_seeds`` of the map: a
boundary no row reaches) seed two-parameter continuations of folds, period doublings,
Neimark-Sacker points and both kinds of grazing across the plane
(:func:`impactdamper.analysis.boundaries.plane_boundaries`); the first-contact and lift-off
closed forms are sampled along the second parameter.

Writes ``figures/boundaries_{map}.csv`` (curve, cycle, kind, gap, the second parameter by its
name, stable_side, end_reason on the last row of each curve: each continued curve as its two
legs from its seed, ids ``NNa``/``NNb``), ``results/boundaries/{map}.pkl`` (the curves, for
the checks) and ``results/boundaries/{map}_timing.json`` (this job's processor time).

Deviations: none from the paper (it has no such computation).
"""

import pickle
import time

from impactdamper.analysis.boundaries import COLUMNS, BoundarySettings, plane_boundaries
from impactdamper.reporting.records import run_stage, write_csv, write_json
from impactdamper.studies.config import parameters
from impactdamper.studies.sweeps import gapsweep as gs


def main(
    reference: dict, maps: dict, boundaries: dict, orbits: dict, name: str, out_csv, out_curves, out_timing, log=None
):
    start = time.process_time()
    slow, slow_values, gaps = gs.map_axes(maps, name)
    base = parameters(reference)
    # The one-parameter branches' seeds (config orbits.branches) on the reference row seed too.
    value = getattr(base, "delta1" if slow == "delta" else slow)
    settings = BoundarySettings(
        seed_rows=int(boundaries["seed_rows"]),
        seed_gaps=int(boundaries["seed_gaps"]),
        closed_form_points=int(boundaries["closed_form_points"]),
        extra_seeds=tuple((float(b["gap"]), value) for b in orbits["branches"])
        + tuple((float(g), float(v)) for g, v in boundaries.get("extra_seeds", {}).get(name, [])),
    )
    b = plane_boundaries(base, slow, (gaps[0], gaps[-1]), (slow_values[0], slow_values[-1]), settings, log)
    write_csv(out_csv, [slow if c == "value" else c for c in COLUMNS], b.rows)
    with open(out_curves, "wb") as f:
        pickle.dump(b, f)
    write_json(
        out_timing,
        {
            "cpu_s": time.process_time() - start,
            "curves": len(b.curves),
            "seeds": b.seeds,
            "duplicates": b.duplicates,
            "failures": b.failures,
        },
    )
    return b


JOB = "params.reference params.maps params.boundaries params.orbits wildcards.map output.csv output.curves output.timing log=log"

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, logger="boundaries")  # noqa: F821 (injected by Snakemake's script: directive)
