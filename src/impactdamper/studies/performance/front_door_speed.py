"""What a user's calls cost: the compiled solver's benchmark at the front door.

Part of ``workflow/scripts/compiled_speed.py``'s record (``front_door`` of
``figures/compiled_speed.json``), on the paper's reference case (Timofeev et al. 2019, Fig. 2):
``impactdamper.steady_state`` on the auto and python backends, a batch through
``impactdamper.steady_states`` against the steady kernel's own time on the same points, and the
command line in fresh processes (its import time too).
"""

from __future__ import annotations

import math
import statistics
import subprocess
import sys
import time

import numpy as np

import impactdamper as idp
from impactdamper.analysis.point import SweepSettings
from impactdamper.core.compiled.layout import N_DIAG
from impactdamper.core.compiled.pack import pack_parameters
from impactdamper.core.compiled.settle import steady_kernel
from impactdamper.studies.performance.timing import load, strip, timed

__all__ = ["front_door", "BATCH_GAPS", "BATCH_THETAS", "CLI_RUNS"]

# Batch points: gap x theta around the reference case (every cell a settled motion within the cap).
BATCH_GAPS = (-9.0, -3.0)
BATCH_THETAS = (0.8, 1.2)

# Fresh processes timed for the command line's wall time (median taken).
CLI_RUNS = 3


def front_door(p, repeats: int, batch_points: int, targets: dict, map_settings: dict) -> dict:
    """What a user's calls cost: impactdamper.steady_state (auto and python backends), a batch
    through impactdamper.steady_states against the kernels' own time, and the command line."""
    out = {"steady_state": _public_steady(p, repeats, targets)}
    out["batch"] = _batch_against_kernels(p, batch_points, targets, map_settings)
    out["cli"] = _command_line(targets)
    return out


def _public_steady(p, repeats: int, targets: dict) -> dict:
    """``impactdamper.steady_state`` timed on the auto backend and (a tenth as often) on python."""
    public = timed(lambda: idp.steady_state(p), repeats)
    python = timed(lambda: idp.steady_state(p, backend="python"), max(1, repeats // 10))
    s = public["result"]
    return {
        "auto": strip(public),
        "python": strip(python),
        "backend": s.backend,
        "method": s.method,
        "fallback": s.fallback,
        "speedup_vs_python": python["wall_median_s"] / public["wall_median_s"],
        "target_s": targets["public_steady_s"],
        "met": public["wall_median_s"] <= targets["public_steady_s"],
    }


def _batch_against_kernels(p, batch_points: int, targets: dict, map_settings: dict) -> dict:
    """A batch through ``impactdamper.steady_states`` against the steady kernel's own time on the
    same points (pre-packed parameters), with the maps' settle settings."""
    # The batch: an n x n grid of (gap, theta), each point from Algorithm No. 2's step 1.
    n = max(2, int(round(math.sqrt(batch_points))))
    gg, tt = np.meshgrid(np.linspace(*BATCH_GAPS, n), np.linspace(*BATCH_THETAS, n))
    values = np.column_stack([gg.ravel(), tt.ravel()])
    settings = SweepSettings(**map_settings)  # the maps' caps (a map row's cells, here each from step 1)
    c, w = time.process_time(), time.perf_counter()
    res = idp.steady_states(p, ("gap", "theta"), values, settings=settings, chain=False)
    batch_cpu, batch_wall = time.process_time() - c, time.perf_counter() - w
    kernel_cpu, kernel_wall, kernel_points = _kernels_alone(p, values, settings)
    return {
        "points": len(values),
        "grid": [n, n],
        "gaps": list(BATCH_GAPS),
        "thetas": list(BATCH_THETAS),
        "public_cpu_s": batch_cpu,
        "public_wall_s": batch_wall,
        "kernel_cpu_s": kernel_cpu,
        "kernel_wall_s": kernel_wall,
        "us_per_point_public": 1e6 * batch_cpu / len(values),
        "us_per_point_kernel": 1e6 * kernel_cpu / len(values),
        "ratio": batch_cpu / kernel_cpu,
        "kernel_points": kernel_points,
        "fallbacks": res.fallbacks,
        "nonperiodic": int(np.sum(res.regime == "nonperiodic")),
        "target_ratio": targets["batch_ratio"],
        "met": batch_cpu / kernel_cpu <= targets["batch_ratio"],
        "load_1min": load(),
    }


def _kernels_alone(p, values: np.ndarray, settings: SweepSettings) -> tuple[float, float, int]:
    """The kernels' own time on the same points: the steady kernel on pre-packed parameters
    (CPU s, wall s, and the points it ran: those the packing does not refer to the reference)."""
    points = [p.replace(gap=float(g), theta=float(t)) for g, t in values]
    packed = [(pack_parameters(q), idp.default_initial_state(q)) for q in points]
    packed = [(pk, full) for pk, full in packed if not pk.fallback]
    diag = np.zeros(N_DIAG)
    c, w = time.process_time(), time.perf_counter()
    for pk, full in packed:
        steady_kernel(
            pk.cm,
            pk.fm,
            pk.fc,
            pk.fk,
            pk.fg,
            pk.s,
            0.0,
            full,
            True,
            settings.settle_tol,
            settings.max_periods,
            settings.max_period_multiple,
            diag,
        )
    kernel_cpu, kernel_wall = time.process_time() - c, time.perf_counter() - w
    return kernel_cpu, kernel_wall, len(packed)


def _command_line(targets: dict) -> dict:
    """``python -m impactdamper steady --json`` timed in fresh processes, and the package's import
    time there (and whether it loads numba)."""
    # The command line, a fresh process each (the kernels from numba's warm cache).
    walls = []
    for _ in range(CLI_RUNS):
        w = time.perf_counter()
        subprocess.run([sys.executable, "-m", "impactdamper", "steady", "--json"], check=True, capture_output=True)
        walls.append(time.perf_counter() - w)
    probe = (
        "import sys, time; t = time.perf_counter(); import impactdamper; "
        "print(time.perf_counter() - t, 'numba' in sys.modules)"
    )
    imports = [
        subprocess.run([sys.executable, "-c", probe], check=True, capture_output=True, text=True).stdout.split()
        for _ in range(CLI_RUNS)
    ]
    return {
        "command": "python -m impactdamper steady --json",
        "runs": CLI_RUNS,
        "wall_min_s": min(walls),
        "wall_median_s": statistics.median(walls),
        "import_median_s": statistics.median(float(i[0]) for i in imports),
        "import_loads_numba": any(i[1] == "True" for i in imports),
        "target_s": targets["cli_wall_s"],
        "met": statistics.median(walls) <= targets["cli_wall_s"],
        "load_1min": load(),
    }
