"""Siconos Moreau-Jean time-stepping as a baseline, run in a subprocess.

Siconos (https://nonsmooth.gricad-pages.univ-grenoble-alpes.fr/siconos/) is the reference
open-source platform for nonsmooth mechanics; its Moreau-Jean scheme is the standard
time-stepping method for impacts. Debian packages its Python module as ``python3-siconos``
for Debian's own ``/usr/bin/python3``, which is not the interpreter this project runs in, so
the simulation runs in a subprocess (:mod:`impactdamper.baselines._siconos_driver`) with JSON in and
out. Where that interpreter or module is missing, :func:`siconos_status` says so and the
work-precision study states that Siconos was not available.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import default_initial_state

__all__ = [
    "SICONOS_PYTHON",
    "siconos_status",
    "simulate_siconos",
]

SICONOS_PYTHON = os.environ.get("IMPACTDAMPER_SICONOS_PYTHON", "/usr/bin/python3")
"""The interpreter that has Siconos (Debian's python3; override with IMPACTDAMPER_SICONOS_PYTHON)."""
# The driver runs as a script from this folder, so no module here may be called siconos.py:
# it would hide the real package.
DRIVER = Path(__file__).with_name("_siconos_driver.py")
# A run longer than this (s, wall clock) is a hang, not a measurement.
SUBPROCESS_TIMEOUT = 3600


@dataclass(frozen=True)
class _SiconosResult:
    """One Moreau-Jean run.

    Attributes
    ----------
    impacts : ndarray, shape (n,)
        Times of the steps that start a contact episode (impulse > 0), s.
    final_state : ndarray, shape (4,)
        (x1, x2, x1', x2') at t_end.
    cpu_seconds : float
        Median CPU time of one run inside the subprocess (set-up and time loop).
    steps : int
        Time steps taken.
    version : str
        Siconos's version.
    """

    impacts: np.ndarray
    final_state: np.ndarray
    cpu_seconds: float
    steps: int
    version: str


def siconos_status(python: str = SICONOS_PYTHON) -> tuple[bool, str]:
    """Whether Siconos's Python module can be used, and a one-line explanation."""
    if not Path(python).exists():
        return False, f"{python} not found"
    try:
        res = subprocess.run(
            [python, "-c", "import numpy, siconos.kernel"], capture_output=True, text=True, timeout=120
        )
    except (OSError, subprocess.TimeoutExpired) as exc:
        return False, f"{python} could not run: {exc}"
    if res.returncode != 0:
        last = (res.stderr.strip().splitlines() or ["import failed"])[-1]
        return False, f"`import siconos.kernel` fails in {python}: {last}"
    return True, f"siconos.kernel imports in {python}"


def simulate_siconos(
    p: Parameters,
    t_end: float,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    steps_per_period: int = 1000,
    repeats: int = 1,
    theta: float = 0.5,
    python: str = SICONOS_PYTHON,
) -> _SiconosResult:
    """Integrate the suppressor with Siconos's Moreau-Jean scheme from t0 to t_end.

    Parameters
    ----------
    p : Parameters
    t_end, t0 : float
        Interval, s.
    state : ndarray, shape (4,), optional
        Initial (x1, x2, x1', x2'); default Algorithm No. 2's step 1.
    steps_per_period : int
        h ~ T / steps_per_period (the step divides [t0, t_end] exactly).
    repeats : int
        Runs inside the subprocess; the median CPU time is reported.
    theta : float
        Moreau-Jean's theta (1/2: the trapezoidal rule for the smooth part).
    """
    if not (isinstance(steps_per_period, int) and steps_per_period >= 1):
        raise ValueError(f"`steps_per_period` = {steps_per_period!r} is not allowed: must be an integer >= 1")
    if not (math.isfinite(t_end) and t_end > t0):
        raise ValueError(f"`t_end` = {t_end!r} is not allowed: must be finite and > t0 = {t0!r}")
    full = default_initial_state(p) if state is None else np.asarray(state, dtype=float)
    steps = max(int(round((t_end - t0) / p.T * steps_per_period)), 1)
    cfg = {name: float(getattr(p, name)) for name in ("m1", "m2", "c1", "c2", "k1", "k2", "P0", "omega", "Delta0", "R")}
    cfg.update(
        t0=float(t0),
        t_end=float(t_end),
        state=[float(v) for v in full],
        steps=steps,
        theta=float(theta),
        repeats=int(repeats),
    )
    res = subprocess.run(
        [python, str(DRIVER)], input=json.dumps(cfg), capture_output=True, text=True, timeout=SUBPROCESS_TIMEOUT
    )
    if res.returncode != 0:
        last = (res.stderr.strip().splitlines() or ["no message"])[-1]
        raise RuntimeError(f"Siconos driver failed: {last}")
    out = json.loads(res.stdout)
    return _SiconosResult(
        np.array(out["impacts"], dtype=float),
        np.array(out["final_state"], dtype=float),
        float(out["cpu_seconds"]),
        int(out["steps"]),
        str(out["siconos_version"]),
    )
