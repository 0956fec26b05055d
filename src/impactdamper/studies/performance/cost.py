"""The workflow's own cost: every job's Snakemake benchmark gathered into the rules' cost.

Each job of the workflow writes a Snakemake benchmark file (``benchmark:``, one per job:
``<rule>[-<wildcard value>...].tsv``) with its wall time (``s``) and the CPU time of its
processes (``cpu_time``, user and system, sampled by Snakemake while the job runs: a job's last
second of CPU time can be missing, and a job shorter than the first sample has none). The file
is written when the job ends, so its modification time is the job's end and the end less its
wall time its start.

:func:`run_jobs` keeps the jobs of the latest run: those that ended after the latest start of
the run's first job (the compiled kernels' warm-up, which every job that runs compiled code
waits for); :func:`summarize` sums them by rule and takes the run's wall time from its first
job's start to its last job's end. The jobs that run after the gathering (the report and the
README summary, which read it) cannot be in it.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Sequence
from pathlib import Path

__all__ = ["FIRST_RULE", "read_benchmark", "run_jobs", "summarize"]

# The run's first job: every job that runs compiled code waits for it (workflow/rules/common.smk).
FIRST_RULE = "compiled_warm_up"


def _number(text: str) -> float:
    """A benchmark cell as a float (``NA``, ``-``: nan)."""
    try:
        return float(text)
    except ValueError:
        return math.nan


def read_benchmark(path) -> dict:
    """One job's benchmark file: ``rule``, ``wildcards`` (the name's parts after the rule's),
    ``wall_s``, ``cpu_s`` (nan where Snakemake sampled none), ``start``, ``end`` (epoch s)."""
    path = Path(path)
    with path.open(newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    if not rows or "s" not in rows[0]:
        raise ValueError(f"`path` = {str(path)!r} is not allowed: not a Snakemake benchmark file")
    rule, *wildcards = path.stem.split("-")
    wall = sum(_number(r["s"]) for r in rows)  # (one row per repeat; the workflow runs one)
    cpu = sum(_number(r.get("cpu_time", "NA")) for r in rows)
    end = os.stat(path).st_mtime
    return {"rule": rule, "wildcards": wildcards, "wall_s": wall, "cpu_s": cpu, "start": end - wall, "end": end}


def run_jobs(paths: Sequence, exclude: Sequence[str] = ()) -> list[dict]:
    """The benchmarks of the latest run among ``paths``: every job that ended after the start of
    the latest :data:`FIRST_RULE` job (all of them where there is none), but the rules
    ``exclude``."""
    jobs = [read_benchmark(p) for p in paths]
    first = [j["start"] for j in jobs if j["rule"] == FIRST_RULE]
    since = max(first) if first else -math.inf
    return sorted(
        (j for j in jobs if j["end"] >= since and j["rule"] not in exclude), key=lambda j: (j["start"], j["rule"])
    )


def summarize(jobs: Sequence[dict], top: int = 10, cores: int | None = None) -> dict:
    """The run's cost: per rule (``rules``, the costliest first by CPU time: jobs, wall and CPU
    seconds summed over its jobs, its longest job's wall), the ``top`` costliest, and the run's
    ``wall_s`` (first start to last end), ``cpu_s`` (every job's), ``jobs``, ``cores`` given, and
    ``busy`` (CPU time over wall time times cores: the share of the cores the jobs kept busy)."""
    rules: dict[str, dict] = {}
    for j in jobs:
        r = rules.setdefault(j["rule"], {"rule": j["rule"], "jobs": 0, "wall_s": 0.0, "cpu_s": 0.0, "longest_s": 0.0})
        r["jobs"] += 1
        r["wall_s"] += j["wall_s"]
        r["cpu_s"] += 0.0 if math.isnan(j["cpu_s"]) else j["cpu_s"]
        r["longest_s"] = max(r["longest_s"], j["wall_s"])
    ordered = sorted(rules.values(), key=lambda r: (-r["cpu_s"], -r["wall_s"], r["rule"]))
    wall = max(j["end"] for j in jobs) - min(j["start"] for j in jobs) if jobs else 0.0
    cpu = sum(r["cpu_s"] for r in ordered)
    return {
        "jobs": len(jobs),
        "rules": ordered,
        "top": ordered[:top],
        "wall_s": wall,
        "cpu_s": cpu,
        "job_wall_s": sum(j["wall_s"] for j in jobs),
        "unsampled_jobs": sum(math.isnan(j["cpu_s"]) for j in jobs),
        "cores": cores,
        "busy": cpu / (wall * cores) if cores and wall > 0 else None,
        "start": min((j["start"] for j in jobs), default=None),
        "end": max((j["end"] for j in jobs), default=None),
    }
