"""When a run has settled: the period test on its stroboscopic sections.

The paper's step 6 says "calculations continue until established oscillations occur" without
saying how that is recognised. Here: the state is sampled once per forcing period
(stroboscopic section t_n = t0 + n T, the forcing's phase is then the same), and the motion is
settled with period T_c = k T when, for the smallest k <= ``max_period_multiple``, the last k
sections each match the section k periods earlier to ``settle_tol`` (relative to x_st and
x_st omega) in the same mode (:func:`settled_period`). Matching a whole cycle of sections, not
one, keeps a slow transient from passing for a period-k motion; a divisor of the matched k
that may still be converging is waited for (:func:`_least_period`); and the section
differences must have decayed over the last few periods (:func:`_converged`): a slowly
decaying mode's difference from one period to the next is far smaller than its distance to the
cycle, and without this check the test stopped at theta = 50 with x1_max 430 settle_tol off
the settled motion's. A settled motion's x1_max is within ``X1_MAX_FACTOR`` settle_tol (in
x_st) of the exactly settled one's.

:func:`impactdamper.core.steady.steady_state` runs this test after every period; the compiled
kernels (:mod:`impactdamper.core.compiled.periodicity`) repeat it on arrays, with these constants.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "settled_period",
    "CONVERGENCE_WINDOW",
    "CONVERGENCE_NOISE",
    "ROUNDING_FLOOR",
    "DIVISOR_SUSPECT",
    "DIVISOR_DECAY",
    "DIVISOR_FLOOR_FACTOR",
    "STALL_WINDOW",
    "X1_MAX_FACTOR",
]


def settled_period(sections: np.ndarray, modes: list, max_period_multiple: int, settle_tol: float) -> tuple[int, float]:
    """The period of a run whose sections so far are ``sections`` (relative states, shape
    (n, 4)) in ``modes``: (k, its mismatch) once the run has settled with T_c = k T, else
    (0, the mismatch so far; inf before a section can repeat).

    A screen first: a period k is possible only if the latest section repeats the one k periods
    back (:func:`_period` checks the whole cycle); then the least period (:func:`_least_period`)
    and the convergence to the cycle (:func:`_converged`).
    """
    n = len(sections)
    lags = min(max_period_multiple, (n - 1) // 2)
    if lags == 0:
        return 0, math.inf
    # (the ufuncs' reductions themselves, without ndarray.max's Python wrapper: once a period)
    residual = float(
        np.minimum.reduce(np.maximum.reduce(np.abs(sections[n - 1 - lags : n - 1] - sections[n - 1]), axis=1))
    )
    if residual >= settle_tol:
        return 0, residual
    found_k, residual = _period(sections, modes, max_period_multiple, settle_tol)
    if found_k:
        found_k, residual = _least_period(sections, modes, found_k, settle_tol)
    if found_k and residual < settle_tol and not _converged(sections, found_k, settle_tol):
        found_k = 0  # a slow transient still on its way (see _converged)
    return found_k, residual


def _mismatch(sections: np.ndarray, modes: list, k: int) -> float:
    """Largest difference between each of the last k sections and the one k periods earlier."""
    n = len(sections)
    if n < 2 * k + 1:
        return math.inf
    if modes[n - k :] != modes[n - 2 * k : n - k]:
        return math.inf
    return float(np.abs(sections[n - k :] - sections[n - 2 * k : n - k]).max())


def _period(sections: np.ndarray, modes: list, kmax: int, tol: float) -> tuple[int, float]:
    """Smallest k whose last k sections repeat those k periods earlier, with the mismatch."""
    best = math.inf
    for k in range(1, kmax + 1):
        worst = _mismatch(sections, modes, k)
        best = min(best, worst)
        if worst < tol:
            return k, worst
    return 0, best


# A divisor d of a matched k whose mismatch is below this may be the true period still
# converging (a transient with a Floquet multiplier near -1 repeats after 2 periods sooner
# than after 1). Then the run goes on while that divisor's mismatch keeps falling: its
# largest value over the last STALL_WINDOW periods (at least 2k) must stay below
# DIVISOR_DECAY times its largest value over the window before. A genuine period-k motion
# keeps the divisor's mismatch constant (its own transient is already below settle_tol);
# a transient shrinks it by |multiplier| per cycle. Windowed maxima, not cycle-to-cycle
# values, because two transient components beat (at gap -9.49 the divisor's mismatch
# rises now and then while falling by 0.87 per window, and a cycle-to-cycle test gave the
# 2T motion as T_c = 4T).
# With a loose settle_tol the matched k's own mismatch may be near DIVISOR_SUSPECT while the
# divisor's is still above it (a multiplier of -0.99 leaves the lag-1 difference 100 times the
# lag-2 one): a divisor is then suspect below DIVISOR_FLOOR_FACTOR settle_tol too (settle_tol
# 9e-4 settled a transient of a 1T cycle as T_c = 2T; tests/unit/test_settle_tolerance.py).
DIVISOR_SUSPECT = 1e-3
DIVISOR_DECAY = 0.95
STALL_WINDOW = 20
# A divisor whose mismatch stalls below this multiple of settle_tol is the period, stopped by
# the run's noise floor (a genuine period-k motion has a divisor mismatch this small only at
# its bifurcation point itself: the doubled orbit's offset grows like the square root of the
# distance to it). Never above DIVISOR_SUSPECT: with a loose settle_tol a genuine period-k
# motion's divisor mismatch can be below DIVISOR_FLOOR_FACTOR settle_tol.
DIVISOR_FLOOR_FACTOR = 1e3


# The period test compares each section with the one k periods earlier, and a slowly decaying
# transient passes it while still far from the cycle: its lag-k difference is (lambda^k - 1)
# times its distance, small when a Floquet multiplier lambda is close to 1 (at theta = 50 the
# stuck mode turns by 0.12 rad per period and decays by 0.6 %: the period test stopped with
# x1 still 3.7e-8 x_st, 430 settle_tol, off the settled motion). So a period is accepted only
# when, besides, over the last CONVERGENCE_WINDOW periods (at least 2k, a whole number of
# cycles) every section stays within settle_tol of the latest cycle's section of the same
# phase (the spread: a rotating slow mode shows its distance there) and the geometric tail
# sum of the lag-k differences still to come, extrapolated from their decay between this
# window and the one before, is below settle_tol too (a slow monotone decay shows its
# distance there).
CONVERGENCE_WINDOW = 12
# Lag-k differences below CONVERGENCE_NOISE settle_tol (or below ROUNDING_FLOOR) have no tail
# estimate: rounding noise does not decay, and a ratio of noise is no decay rate. The distance
# is then below settle_tol for every multiplier with |lambda^k - 1| >= CONVERGENCE_NOISE.
CONVERGENCE_NOISE = 0.05
# The run's rounding noise in the relative sections: their lag-k differences level off at
# 5e-13 to 2e-12 after the transient (reference case, gap -2, gap -10; re-based clock).
ROUNDING_FLOOR = 5e-12
# The stated accuracy of a settled motion's x1_max: within X1_MAX_FACTOR settle_tol (in x_st)
# of the exactly settled motion's. Measured against the closed-form forced amplitudes, theta 5
# to 50 stuck and 5 to 100 without contact, settle_tol 1e-4 to 1e-10, both backends: at most
# 1.0 settle_tol (stuck) and 0.48 settle_tol (no contact); against the default tolerance's
# answer over random parameters: tests/unit/test_settle_tolerance.py.
X1_MAX_FACTOR = 10.0


def _converged(sections: np.ndarray, k: int, settle_tol: float) -> bool:
    """Whether the run's last sections are within settle_tol of the period-k cycle they
    approach: the spread over the last window and the extrapolated tail both below settle_tol
    (see CONVERGENCE_WINDOW). False while the run is shorter than two windows and a cycle."""
    n = len(sections)
    w = -(-max(CONVERGENCE_WINDOW, 2 * k) // k) * k
    if n < 2 * w + k:
        return False
    spread = 0.0
    for i in range(w):
        spread = max(spread, float(np.abs(sections[n - 1 - i] - sections[n - 1 - i % k]).max()))
    lag = np.abs(sections[n - 2 * w :] - sections[n - 2 * w - k : n - k]).max(axis=1)
    older, recent = float(lag[:w].max()), float(lag[w:].max())
    if recent < max(CONVERGENCE_NOISE * settle_tol, ROUNDING_FLOOR):
        tail = 0.0
    elif recent < older:
        g = (recent / older) ** (k / w)  # the per-cycle decay
        tail = recent * g / (1.0 - g)
    else:
        tail = math.inf
    return max(spread, tail) < settle_tol


def _least_period(sections: np.ndarray, modes: list, k: int, settle_tol: float) -> tuple[int, float]:
    """The period to accept for a matched k: (k or a divisor of it, its mismatch), or (0, .)
    while a divisor may still be converging."""
    n = len(sections)
    window = max(STALL_WINDOW, 2 * k)
    for d in range(1, k):
        m = _mismatch(sections, modes, d) if k % d == 0 else math.inf
        if m >= max(DIVISOR_SUSPECT, DIVISOR_FLOOR_FACTOR * settle_tol):
            continue
        if n < 2 * window + d:
            return 0, m  # not enough history yet to tell
        lagged = np.abs(sections[n - 2 * window :] - sections[n - 2 * window - d : n - d]).max(axis=1)
        if lagged[window:].max() < DIVISOR_DECAY * lagged[:window].max():
            return 0, m
        if m < min(DIVISOR_FLOOR_FACTOR * settle_tol, DIVISOR_SUSPECT):
            return d, m
    return k, _mismatch(sections, modes, k)
