"""Consistency checks of a Lyapunov spectrum that do not use its tangent walk's saltation matrices
and QR (impactdamper.core.tangent, core/compiled/tangent.py) but share its flow or its event
solver (the independent check: unit/test_benettin_ivp.py), for the reference's tests (unit/test_lyapunov.py) and the compiled
path's (unit/test_lyapunov_compiled.py):

* at a stable periodic orbit, log|Floquet multiplier| / k from the orbit solver (Newton
  shooting and the eigenvalues of one monodromy matrix);
* the sum rule: per period, the trace of the free flow's matrix times T plus 2 log R per
  impact (det of an impact's saltation matrix = R^2), the impacts counted by re-simulating the
  period from its section with the reference solver;
* Benettin's two-trajectory estimate of the largest exponent: a nearby start renormalised
  every period, the solver alone (no saltation matrices; the study's own estimate,
  impactdamper.studies.lyapunov.checks.benettin, which shares the event solver with the walk).
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper.analysis.orbits import solve_orbit
from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import EventDrivenSolver, simulate
from impactdamper.studies.lyapunov.checks import BENETTIN_EPS
from impactdamper.studies.lyapunov.checks import benettin as library_benettin

# Tolerances, each with its reason:
# - exponents against Floquet multipliers, absolute per forcing period (the brief's 1e-6; the
#   weighted averages reach ~1e-10 at these orbits);
FLOQUET_TOL = 1e-6
# - the sum rule, relative (rounding of ~1e4 logarithms of 4 x 4 products is ~1e-13);
SUM_RULE_TOL = 1e-8
# - Benettin against the tangent along the same motion: the finite separation EPS (relative)
#   adds a nonlinear term ~EPS times the map's second derivative per period (measured 1.3e-6
#   to 8e-6 at the chaotic points; 1e-4 bounds it).
EPS = 1e-7
SAME_MOTION_TOL = 1e-4
# - Benettin's estimate has a floor besides its statistical error: each period's separation is
#   the difference of two solver states, each rounded to ~1e-15 (relative), so its log carries
#   ~1e-15/EPS = 1e-8 (measured at gap -12.7: bias 3e-8 at EPS = 1e-7, 6e-7 at 1e-8, 5e-6 at
#   1e-9, growing as 1/EPS); 1e-6 bounds it.
BENETTIN_FLOOR = 1e-6


def scale(p: Parameters, n: int = 4) -> np.ndarray:
    """Relative units of a state: (x_st, x_st, x_st omega, x_st omega), or (x_st, x_st omega)."""
    full = np.array([p.x_st, p.x_st, p.x_st * p.omega, p.x_st * p.omega])
    return full if n == 4 else full[[0, 2]]


def run_state(p: Parameters, t0: float, y: np.ndarray, t1: float) -> np.ndarray:
    """(x1, x2, x1', x2') at t1 of the solver's motion from (t0, y): the solver alone."""
    s = EventDrivenSolver(p, t0=t0, state=y)
    s.advance(t1)
    return s.state_at(t1)


def weighted_average(x: np.ndarray) -> np.ndarray:
    """exp(-1/(s(1-s))) weighted average over the first axis (written here again, on purpose)."""
    s = (np.arange(len(x)) + 0.5) / len(x)
    w = np.exp(-1.0 / (s * (1.0 - s)))
    return (w / w.sum()) @ x


def floquet_exponents(p: Parameters) -> np.ndarray:
    """log|mu| / k per forcing period from the orbit solver, largest first."""
    o = solve_orbit(p)
    assert o.solved and o.stable, (o.regime, o.reason)
    return np.sort(np.log(np.abs(o.multipliers)) / o.period_multiple)[::-1]


def free_trace_per_period(p: Parameters) -> float:
    """Trace of the free mode's matrix times T: -(k1 + k2)/m1 - k2/m2 (eqs. 2, 9), closed form."""
    return -((p.k1 + p.k2) / p.m1 + p.k2 / p.m2) * p.T


def check_sum_rule(s) -> tuple[float, float]:
    """Per period, the sum of a spectrum's increments against tr(M) T + 2 log R x (impacts in
    the period, counted by re-simulating it from its section with the reference solver).
    Returns (largest per-period and total relative residual)."""
    p = s.p
    assert s.dimension == 4 and s.captures == 0
    closed = np.empty(s.periods)
    for n, y in enumerate(s.sections):
        events = simulate(p, s.t_section + p.T, s.t_section, y).events
        assert all(e.kind == "impact" for e in events)
        closed[n] = free_trace_per_period(p) + 2.0 * math.log(p.R) * len(events)
    sums = s.increments.sum(axis=1)
    per_period = np.max(np.abs(sums - closed) / np.abs(closed))
    total = abs(sums.sum() - closed.sum()) / abs(closed.sum())
    # The reported exponents are weighted averages of the increments: their sum is the same
    # weighted average of the closed form.
    assert abs(s.exponents.sum() - weighted_average(closed)) <= SUM_RULE_TOL * abs(weighted_average(closed))
    return per_period, total


def benettin(p: Parameters, t0: float, y0: np.ndarray, periods: int, along: np.ndarray | None = None, step=None):
    """Per-period log growth of a separation EPS (relative units) renormalised every period
    (:func:`impactdamper.studies.lyapunov.checks.benettin`: the solver alone, no tangent).

    The reference motion is the solver's from (t0, y0), or, with ``along``, the given section
    states (then y0 = along[0]). ``step(y)``: the state one period on from y at t0 (default
    the reference solver, :func:`run_state`). Returns the growth per period, shape (periods,)."""
    assert EPS == BENETTIN_EPS
    step = step or (lambda y: run_state(p, t0, y, t0 + p.T))
    return library_benettin(p, y0, periods, along=along, step=step)


def block_estimate(x: np.ndarray, blocks: int = 10) -> tuple[float, float]:
    """Weighted average and the standard error of its weighted block averages."""
    b = np.array([weighted_average(c) for c in np.split(x, blocks)])
    return float(weighted_average(x)), float(b.std(ddof=1) / math.sqrt(blocks))
