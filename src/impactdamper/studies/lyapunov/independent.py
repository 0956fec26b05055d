"""The independent check of the compiled Lyapunov spectrum, for the stage's record.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100. At one chaotic point the
tangent walk's largest exponent (:func:`impactdamper.analysis.lyapunov.lyapunov_spectrum`, the
compiled walk) against Benettin's two-trajectory estimate on scipy's solve_ivp
(:mod:`impactdamper.baselines.benettin_ivp`: its own equations, parameter conversion and
impact law, DOP853 with event location; it imports nothing of the library). What the two
share is data: the relative parameters' values and the start, the walk's last section (4
numbers), after which the estimate runs a transient of its own. Agreement: within
SIGNIFICANCE combined standard errors.
"""

from __future__ import annotations

import math
import time

from impactdamper.analysis.lyapunov import SIGNIFICANCE, lyapunov_spectrum
from impactdamper.baselines.benettin_ivp import benettin_ivp
from impactdamper.core.parameters import Parameters, state_scale

__all__ = ["independent_check"]


def independent_check(p: Parameters, run: dict, independent: dict) -> tuple[dict, float]:
    """The walk's largest exponent at ``p`` (``run``: its lengths) against Benettin's estimate on
    solve_ivp (:func:`impactdamper.baselines.benettin_ivp.benettin_ivp`, the relative parameters
    handed over as numbers, ``independent``: its transient and periods), started from the walk's
    last section. Returns (the record, the estimate's CPU time in s)."""
    s = lyapunov_spectrum(p, backend="compiled", **run)
    start = s.sections[-1] / state_scale(p)
    t = time.process_time()
    ivp = benettin_ivp(
        p.theta, p.mu, p.N, p.delta1, p.delta2, p.R, p.gap, start,
        transient=int(independent["transient"]), periods=int(independent["periods"]), omega=p.omega,
    )  # fmt: skip
    cpu = time.process_time() - t
    lam, err = float(s.exponents[0]), float(s.errors[0])
    combined = math.hypot(err, ivp["error"])
    difference = abs(ivp["exponent"] - lam)
    return {
        "gap": p.gap,
        "tangent": {"exponent": lam, "error": err, "label": s.label, "periods": s.periods,
                    "transient": s.transient, "warmup": s.warmup, "captures": s.captures},
        "ivp": ivp,
        "difference": difference,
        "combined_error": combined,
        "in_combined_errors": difference / combined,
        "agrees": difference <= SIGNIFICANCE * combined,
        "significance": SIGNIFICANCE,
        "shares": "the start state (the walk's last section, 4 numbers) and the relative parameters' values; "
        "no flow, event, model or parameter-conversion code",
    }, cpu  # fmt: skip
