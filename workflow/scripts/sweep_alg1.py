"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: Algorithm No. 1's
one-impact orbit along the gap sweep.

For every sweep value, Algorithm No. 1 (eqs. 7-17: the one-impact-per-period orbit in closed
form) gives the orbit if eq. (16) has a solution; whether it is admissible (the gap stays
positive between impacts, the paper's Fig. 2a test) comes with it, and whether it is stable
from its Floquet multipliers (saltation matrices, :func:`impactdamper.analysis.orbits.solve_orbit`).
The bifurcation diagram draws this branch under the simulated motions.

Output: ``figures/sweep_alg1.csv`` (value, exists, admissible, stable, largest multiplier
modulus, closing velocity over x_st omega, impact phase, smallest interior gap over x_st).
"""

import numpy as np

from impactdamper import algorithm1
from impactdamper.analysis.orbits import OrbitError, solve_orbit
from impactdamper.analysis.sweeps import with_value
from impactdamper.reporting.records import run_stage, write_csv
from impactdamper.studies.sweeps import gapsweep as gs
from impactdamper.studies.config import parameters


COLUMNS = ["value", "exists", "admissible", "stable", "multiplier", "velocity", "phase", "min_gap"]


def row(base, parameter: str, value: float, gap_tol: float) -> dict:
    p = with_value(base, parameter, value)
    a = algorithm1(p, gap_tol=gap_tol)
    out = {
        "value": float(value),
        "exists": int(a.exists),
        "admissible": int(a.admissible),
        "stable": "",
        "multiplier": float("nan"),
        "velocity": float("nan"),
        "phase": float("nan"),
        "min_gap": float("nan"),
    }
    if not a.exists:
        return out
    out.update(velocity=a.velocity / (p.x_st * p.omega), phase=a.impact_phase, min_gap=a.min_gap)
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            o = solve_orbit(p, a)
        out.update(stable=int(bool(o.stable)), multiplier=o.spectral_radius)
    except (OrbitError, ValueError, np.linalg.LinAlgError):
        pass  # the stability columns stay empty where the orbit cannot be solved
    return out


def main(reference: dict, solver: dict, sweep: dict, out_csv, log=None) -> list[dict]:
    base = parameters(reference)
    values = gs.grid(sweep["start"], sweep["stop"], sweep["points"])
    rows = [row(base, gs.SWEEP_PARAMETER, v, float(solver["gap_tol"])) for v in values]
    write_csv(out_csv, COLUMNS, rows, booleans="digits")
    if log is not None:
        log.info(
            "%d values, orbit exists at %d, admissible at %d",
            len(rows),
            sum(r["exists"] for r in rows),
            sum(r["admissible"] for r in rows),
        )
    return rows


JOB = "params.reference params.solver params.sweep output.csv log=log"
STAGE = {"logger": "sweep_alg1", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
