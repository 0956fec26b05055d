"""The workflow's own cost: every job's Snakemake benchmark gathered into the rules' cost.

Each job of the workflow writes a Snakemake benchmark file (``benchmark:``, one per job:
``<rule>[-<wildcard value>...].tsv``, :func:`impactdamper.reporting.records.job_name`) with its
wall time (``s``) and the CPU time of its processes (``cpu_time``, user and system, sampled by
Snakemake once a second while the job runs: a worker process that starts and ends between two
samples is never seen, a job shorter than the first sample has none). The file is written when
the job ends, so its modification time is the job's end and the end less its wall time its
start. A Python job also writes its exact CPU time when it ends (itself and its waited-for
children: :data:`impactdamper.reporting.records.JOB_COST_DIR`); where it did, in this run, that
is the job's CPU time (``cpu_source`` ``exact``), else Snakemake's sample (``sampled``: the
shell jobs, the report and the notebooks).

:func:`run_jobs` keeps the jobs of the latest run: those that ended after the latest start of
the run's first job (the compiled kernels' warm-up, which every job that runs compiled code
waits for); :func:`summarize` sums them by rule and takes the run's wall time from its first
job's start to its last job's end. The jobs that run after the gathering (the report and the
README summary, which read it) cannot be in it.
"""

from __future__ import annotations

import csv
import json
import math
import os
from collections.abc import Sequence
from pathlib import Path

__all__ = ["FIRST_RULE", "run_jobs", "summarize"]

# The run's first job: every job that runs compiled code waits for it (workflow/rules/common.smk).
FIRST_RULE = "compiled_warm_up"
# A job's own record ends before Snakemake writes its benchmark; this much later is still the job's
# (file times' resolution and the shell's exit), s.
EXACT_SLACK_S = 5.0


def _number(text: str) -> float:
    """A benchmark cell as a float (``NA``, ``-``: nan)."""
    try:
        return float(text)
    except ValueError:
        return math.nan


def _read_benchmark(path, exact_dir=None) -> dict:
    """One job's benchmark file: ``rule``, ``wildcards`` (the name's parts after the rule's),
    ``wall_s``, ``cpu_s`` (nan where Snakemake sampled none), ``cpu_source``, ``start``, ``end``
    (epoch s); with ``exact_dir``, the CPU time the job recorded there itself if it ended in this
    job (after the job's start)."""
    path = Path(path)
    with path.open(newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    if not rows or "s" not in rows[0]:
        raise ValueError(f"`path` = {str(path)!r} is not allowed: not a Snakemake benchmark file")
    rule, *wildcards = path.stem.split("-")
    wall = sum(_number(r["s"]) for r in rows)  # (one row per repeat; the workflow runs one)
    cpu = sum(_number(r.get("cpu_time", "NA")) for r in rows)
    end = os.stat(path).st_mtime
    out = {"rule": rule, "wildcards": wildcards, "wall_s": wall, "cpu_s": cpu, "cpu_source": "sampled"}
    out.update(start=end - wall, end=end)
    exact = Path(exact_dir) / f"{path.stem}.json" if exact_dir is not None else None
    if exact is not None and exact.is_file():
        record = json.loads(exact.read_text())
        if out["start"] <= float(record["end"]) <= end + EXACT_SLACK_S:
            out.update(cpu_s=float(record["cpu_s"]), cpu_source="exact")
    return out


def run_jobs(paths: Sequence, exclude: Sequence[str] = (), exact_dir=None) -> list[dict]:
    """The benchmarks of the latest run among ``paths`` (each with its exact CPU time from
    ``exact_dir`` where recorded, :func:`read_benchmark`): every job that ended after the start
    of the latest :data:`FIRST_RULE` job (all of them where there is none), but the rules
    ``exclude``."""
    jobs = [_read_benchmark(p, exact_dir) for p in paths]
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
        "exact_jobs": sum(j.get("cpu_source") == "exact" for j in jobs),
        "cores": cores,
        "busy": cpu / (wall * cores) if cores and wall > 0 else None,
        "start": min((j["start"] for j in jobs), default=None),
        "end": max((j["end"] for j in jobs), default=None),
    }
