"""Fixed-step RK4 with bisection on the gap: the integrator many impact papers use.

A baseline for the work-precision study, not a production solver. The free mode
(eqs. 2 and 9 of Timofeev et al. 2019, written out here again) is advanced by the classical
fourth-order Runge-Kutta method with a fixed step h. When a step ends with a negative gap
Delta = Delta0 - (x2 - x1), the impact time inside the step is found by bisection on the
length of an RK4 step from the step's start (each trial step is a fresh RK4 step of that
length), to ``bisect_tol`` T; the state is put on the stop, the impact law of eqs. (21)-(22)
applied, and stepping restarts from the impact with step h.

What it does not do, on purpose (this is the method as usually published): it cannot see a
gap that dips below zero and back inside one step (a grazing impact is missed), and it has
no persistent-contact mode (accumulating impacts end in ``max_events``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import default_initial_state
from impactdamper.core.trajectory import Event

__all__ = [
    "simulate_rk4",
]

# Bisection stops when the bracket is below this many periods (a few ulps of t ~ T).
BISECT_TOL = 1e-15
# Halvings of the step in the bisection (2^-60 of h is far below BISECT_TOL T for any h used).
MAX_BISECTIONS = 60


@dataclass
class _Rk4Trajectory:
    """Result of :func:`simulate_rk4`.

    Attributes
    ----------
    events : list of Event
        The impacts (kind ``"impact"``), with states before and after.
    t_end : float
        Final time, s.
    state : ndarray, shape (4,)
        (x1, x2, x1', x2') at t_end.
    nfev : int
        Right-hand-side evaluations (4 per RK4 step, bisection included).
    steps : int
        RK4 steps taken (bisection trials included).
    """

    events: list = field(default_factory=list)
    t_end: float = math.nan
    state: np.ndarray = None
    nfev: int = 0
    steps: int = 0

    def impacts(self, t_from: float = -math.inf, t_to: float = math.inf) -> list:
        return [e for e in self.events if e.kind == "impact" and t_from <= e.t < t_to]


def simulate_rk4(
    p: Parameters,
    t_end: float,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    steps_per_period: int = 1000,
    bisect_tol: float = BISECT_TOL,
    max_events: int = 100_000,
) -> _Rk4Trajectory:
    """Integrate the suppressor with fixed-step RK4 and bisection on the gap.

    Parameters
    ----------
    p : Parameters
    t_end : float
        End time, s (> t0); the last step is shortened to land on it.
    t0 : float
        Start time, s.
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0; default Algorithm No. 2's step 1. If the gap is zero the
        bodies must be separating.
    steps_per_period : int
        h = T / steps_per_period.
    bisect_tol : float
        Width of the final bisection bracket, in units of T.
    max_events : int
        Guard against accumulating impacts: more raise RuntimeError.

    Returns
    -------
    Rk4Trajectory
    """
    if not (isinstance(steps_per_period, int) and steps_per_period >= 1):
        raise ValueError(f"`steps_per_period` = {steps_per_period!r} is not allowed: must be an integer >= 1")
    if not (math.isfinite(t_end) and t_end > t0):
        raise ValueError(f"`t_end` = {t_end!r} is not allowed: must be finite and > t0 = {t0!r}")
    if not (math.isfinite(bisect_tol) and 0 < bisect_tol < 1):
        raise ValueError(f"`bisect_tol` = {bisect_tol!r} is not allowed: must be in (0, 1)")
    rk4, Delta0 = _rk4_step(p), p.Delta0

    def gap(y: tuple) -> float:
        return Delta0 - (y[1] - y[0])

    out = _Rk4Trajectory()
    y = _start(p, state, gap)
    h = p.T / steps_per_period
    t = float(t0)
    steps = 0
    while t < t_end:
        last = t_end - t <= h
        step = t_end - t if last else h
        y_new = rk4(t, y, step)
        steps += 1
        if gap(y_new) >= 0.0:
            t, y = (t_end if last else t + h), y_new
            continue
        hi, y_hi, trials = _bisect_impact(rk4, gap, t, y, step, y_new, bisect_tol * p.T)
        steps += trials
        t_hit = t + hi
        event = _impact(p, t_hit, y_hi)
        out.events.append(event)
        if len(out.events) > max_events:
            raise RuntimeError(f"more than `max_events` = {max_events} impacts before t = {t_hit!r}")
        t, y = t_hit, tuple(float(v) for v in event.after)
    out.t_end = t
    out.state = np.array(y)
    out.steps = steps
    out.nfev = 4 * steps
    return out


def _start(p: Parameters, state: np.ndarray | None, gap) -> tuple:
    """The start (x1, x2, x1', x2') as a tuple of floats, checked finite and not overlapping."""
    full = default_initial_state(p) if state is None else np.asarray(state, dtype=float)
    if full.shape != (4,) or not np.all(np.isfinite(full)):
        raise ValueError(f"`state` = {state!r} is not allowed: must be 4 finite numbers (x1, x2, x1', x2')")
    y = tuple(float(v) for v in full)
    if gap(y) < -1e-12 * p.x_st:
        raise ValueError("`state` has a negative gap: the bodies would overlap")
    return y


def _bisect_impact(rk4, gap, t: float, y: tuple, step: float, y_new: tuple, width: float):
    """The impact inside a step whose gap changed sign, by bisection on the length of a fresh
    RK4 step from (t, y) down to a bracket of ``width`` s.

    Returns the bracket's upper end (the step length to the impact), the state there (gap < 0)
    and the RK4 trial steps taken."""
    lo, hi = 0.0, step
    y_hi = y_new
    trials = 0
    for _ in range(MAX_BISECTIONS):
        if hi - lo <= width:
            break
        mid = 0.5 * (lo + hi)
        y_mid = rk4(t, y, mid)
        trials += 1
        if gap(y_mid) >= 0.0:
            lo = mid
        else:
            hi, y_hi = mid, y_mid
    return hi, y_hi, trials


def _rk4_step(p: Parameters):
    """One classical RK4 step of the free mode, ``rk4(t, y, h)`` -> y(t + h), y = (x1, x2, x1', x2')."""
    m1, m2, c1, c2, k1, k2 = p.m1, p.m2, p.c1, p.c2, p.k1, p.k2
    P0, w = p.P0, p.omega
    sin = math.sin

    # eqs. (2), (9): m1 x1'' = P0 sin wt - k1 x1' - k2 (x1' - x2') - c1 x1 - c2 (x1 - x2)
    #                m2 x2'' = -k2 (x2' - x1') - c2 (x2 - x1)
    def f(t, x1, x2, v1, v2):
        a1 = (P0 * sin(w * t) - k1 * v1 - k2 * (v1 - v2) - c1 * x1 - c2 * (x1 - x2)) / m1
        a2 = (-k2 * (v2 - v1) - c2 * (x2 - x1)) / m2
        return v1, v2, a1, a2

    def rk4(t: float, y: tuple, h: float) -> tuple:
        x1, x2, v1, v2 = y
        a = f(t, x1, x2, v1, v2)
        hh = 0.5 * h
        b = f(t + hh, x1 + hh * a[0], x2 + hh * a[1], v1 + hh * a[2], v2 + hh * a[3])
        c = f(t + hh, x1 + hh * b[0], x2 + hh * b[1], v1 + hh * b[2], v2 + hh * b[3])
        d = f(t + h, x1 + h * c[0], x2 + h * c[1], v1 + h * c[2], v2 + h * c[3])
        s = h / 6.0
        return (
            x1 + s * (a[0] + 2 * b[0] + 2 * c[0] + d[0]),
            x2 + s * (a[1] + 2 * b[1] + 2 * c[1] + d[1]),
            v1 + s * (a[2] + 2 * b[2] + 2 * c[2] + d[2]),
            v2 + s * (a[3] + 2 * b[3] + 2 * c[3] + d[3]),
        )

    return rk4


def _impact(p: Parameters, t: float, y: tuple) -> Event:
    """The impact law of eqs. (21)-(22) on the state y found at the stop (put on it exactly)."""
    x1, x2, v1, v2 = y
    x2 = x1 + p.Delta0  # onto the stop
    v = max(v2 - v1, 0.0)
    S = p.reduced_mass * (1.0 + p.R) * v
    before = np.array([x1, x2, v1, v2])
    after = np.array([x1, x2, v1 + S / p.m1, v2 - S / p.m2])
    return Event(t, "impact", v, S, before, after, t)
