"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: gathers a regime
map's chunks into the committed label matrix and its benchmark.

Outputs: ``figures/map_{map}_settings.json`` (the configuration, for the record test, with
the method that computed the cells, the share of cells it computed (``computed``, the rest
filled, see :mod:`impactdamper.analysis.adaptive`), its check against the brute force on the
chunks' check rows (``check``: cells compared, differences and their distances to the nearest
change of the brute force's labels) and the points the compiled kernels handed to the Python
reference, by reason, summed over the chunks: ``fallbacks``, see
:mod:`impactdamper.analysis.batch`),
``figures/map_{map}.csv`` -- the label matrix (first column the second parameter's
value, then one column per Delta0/x_st value, header ``slow,<gap values>``; cells are
Peterka's labels, see :func:`impactdamper.analysis.point.label_of`) -- and
``results/benchmarks/map_{map}_timing.json``: the total processor time, the sum of the jobs'
wall times, and the map's wall time (first job start to last job end, the figure that
answers "how long with ``--cores N``" when nothing else runs) with the machine's load.
"""

from pathlib import Path

from impactdamper.reporting.records import read_csv, read_json, run_stage, write_json


# How every cell was computed (map_chunk.py), for the record and the report.
METHOD = "adaptive_regime_map"


def fallback_counts(timings: list[dict]) -> dict:
    """The chunks' fallback counts (points settled by the Python reference), summed by reason."""
    out: dict = {}
    for t in timings:
        for reason, count in t.get("fallbacks", {}).items():
            out[reason] = out.get(reason, 0) + int(count)
    return dict(sorted(out.items()))


def computed_counts(timings: list[dict]) -> dict:
    """The chunks' cells computed and their check against the brute force, summed."""
    cells, computed = sum(int(t["cells"]) for t in timings), sum(int(t["computed"]) for t in timings)
    checks = [t["check"] for t in timings]
    distances = sorted(d for c in checks for d in c["distances"])
    compared = sum(int(c["cells"]) for c in checks)
    return {
        "cells": cells,
        "computed": computed,
        "computed_share": computed / cells if cells else 0.0,
        "settlings": sum(int(t["settlings"]) for t in timings),
        "coarse_step": timings[0]["coarse_step"] if timings else None,
        "check": {
            "rows": sorted(r for c in checks for r in c["rows"]),
            "cells": compared,
            "differences": len(distances),
            "share": len(distances) / compared if compared else 0.0,
            "next_to_change": sum(d == 1 for d in distances),
            "max_distance": max(distances, default=0),
            # the differences at filled cells and at computed ones (history), where the chunks split them
            "filled_differences": sum(int(c.get("filled_differences", 0)) for c in checks),
            "computed_differences": sum(int(c.get("computed_differences", 0)) for c in checks),
            "distances": distances,
        },
    }


def main(
    chunk_csvs, chunk_jsons, name: str, out_csv, out_timing, out_settings=None, config: dict | None = None
) -> dict:
    cells = [r for path in chunk_csvs for r in read_csv(path)]
    slow_of = {int(r["i"]): r["slow"] for r in cells}
    gaps = {int(r["j"]): r["gap"] for r in cells}
    label = {(int(r["i"]), int(r["j"])): r["label"] for r in cells}
    ni, nj = max(slow_of) + 1, max(gaps) + 1
    if len(label) != ni * nj:
        raise ValueError(f"map `{name}`: {len(label)} cells gathered, expected {ni} x {nj}")
    lines = ["slow," + ",".join(gaps[j] for j in range(nj))]
    for i in range(ni):
        lines.append(slow_of[i] + "," + ",".join(label[i, j] for j in range(nj)))
    Path(out_csv).parent.mkdir(parents=True, exist_ok=True)
    Path(out_csv).write_text("\n".join(lines) + "\n")
    timings = [read_json(p) for p in chunk_jsons]
    fallbacks = fallback_counts(timings)
    counts = computed_counts(timings)
    if out_settings is not None:
        write_json(out_settings, dict(config or {}, map=name, method=METHOD, fallbacks=fallbacks, **counts), indent=2)
    methods: dict = {}
    for r in cells:
        methods[r["method"]] = methods.get(r["method"], 0) + 1
    out = {
        "map": name,
        "cells": ni * nj,
        "shape": [ni, nj],
        "chunks": len(timings),
        "cpu_s": sum(t["cpu_s"] for t in timings),
        "sum_wall_s": sum(t["wall_s"] for t in timings),
        "wall_s": max(t["end_epoch"] for t in timings) - min(t["start_epoch"] for t in timings),
        "max_chunk_wall_s": max(t["wall_s"] for t in timings),
        "target_wall_s": 600.0,
        "load_average": [t["machine"]["load_average"] for t in timings],
        "methods": dict(sorted(methods.items())),
        "periods_simulated": sum(int(r["periods"]) for r in cells),
        "method": METHOD,
        "fallbacks": fallbacks,
        "computed_share": counts["computed_share"],
        "check_cpu_s": sum(t["check"]["cpu_s"] for t in timings),
    }
    write_json(out_timing, out, indent=2)
    return out


JOB = (
    "input.csvs:list input.jsons:list wildcards.map output.csv output.timing output.settings",
    lambda j: {k: getattr(j.params, k) for k in ("reference", "solver", "maps")},
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
