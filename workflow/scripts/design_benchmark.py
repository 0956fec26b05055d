"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: how long the design
command takes. ``python -m impactdamper design --json --quiet`` is run as a user runs it (a fresh
process, two cores) for each object of the config's ``design.benchmark_objects`` (mu, delta1)
but the reference object, whose time is the design table's own run (the same call).

Outputs ``figures/design_benchmark.json``: per object its wall time, the processor time of the
command and its workers, the longest wait for a progress line (the command's
``longest_silence``: its documented cadence is a line at least every 10 s), the search's
evaluations and the recommendation's first words; the machine and its load (the job holds both
cores: threads 2 in workflow/rules/design.smk).
"""

import json
import logging
import os
import resource
import subprocess
import sys
import time

from impactdamper.reporting.records import machine, read_json, run_stage, write_json
from impactdamper.studies.design.design import design_band, design_parameters


def _summary(record: dict, elapsed: float, how: str, cpu: float | None = None) -> dict:
    evaluations = sum(sum(d["search"]["evaluations"].values()) for d in record["devices"] if "search" in d)
    return {
        "mu": record["mu"],
        "delta1": record["delta1"],
        "elapsed": elapsed,
        "cpu": cpu,
        "longest_silence": record["longest_silence"],
        "evaluations": evaluations,
        "first": record["recommendation"].split(":")[0],
        "how": how,
    }


def main(reference: dict, design: dict, optimum_json, out_json, log=None) -> None:
    log = log if log is not None else logging.getLogger("design_benchmark")
    p = design_parameters(reference, design)
    band = design_band(design)
    own = read_json(optimum_json)
    objects = [_summary(own, own["elapsed"], "the design table's run", own.get("cpu"))]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    for mu, delta1 in design["benchmark_objects"]:
        if abs(mu - p.mu) < 1e-12 and abs(delta1 - p.delta1) < 1e-12:
            continue
        argv = [sys.executable, "-m", "impactdamper", "design", "--json", "--quiet", "--mu", repr(float(mu))]
        argv += ["--delta1", repr(float(delta1)), "--theta-start", repr(band[0]), "--theta-stop", repr(band[1])]
        t, c = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
        out = subprocess.run(argv, capture_output=True, text=True, env=env, check=True)
        wall = time.perf_counter() - t
        c2 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (c2.ru_utime + c2.ru_stime) - (c.ru_utime + c.ru_stime)  # (its forked workers too)
        objects.append(_summary(json.loads(out.stdout), wall, "the command, a fresh process", cpu))
        log.info("mu = %g, delta1 = %g: %.1f s wall, %.1f s processor", mu, delta1, wall, cpu)
    write_json(out_json, {"objects": objects, "band": list(band), "machine": machine(), "cores": os.cpu_count()})


JOB = "params.reference params.design input.optimum output.json log=log"
STAGE = {"logger": "design_benchmark", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
