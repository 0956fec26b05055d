"""Timing a call for the benchmarks: CPU and wall time of repeated calls, with the machine's
1-minute load average beside them (the machine is shared)."""

from __future__ import annotations

import math
import os
import statistics
import time

__all__ = ["load", "timed", "strip"]


def load() -> float:
    """The 1-minute load average (NaN where the platform has none)."""
    return os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan


def timed(fn, repeats: int) -> dict:
    """CPU and wall times of ``repeats`` calls (after one warm-up call), min and median."""
    result = fn()
    cpu, wall = [], []
    for _ in range(repeats):
        c, w = time.process_time(), time.perf_counter()
        result = fn()
        cpu.append(time.process_time() - c)
        wall.append(time.perf_counter() - w)
    return {
        "cpu_min_s": min(cpu),
        "cpu_median_s": statistics.median(cpu),
        "wall_min_s": min(wall),
        "wall_median_s": statistics.median(wall),
        "repeats": repeats,
        "load_1min": load(),
        "result": result,
    }


def strip(d: dict) -> dict:
    """A :func:`timed` record without the call's result."""
    return {k: v for k, v in d.items() if k != "result"}
