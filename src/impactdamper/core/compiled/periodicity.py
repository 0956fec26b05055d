"""When a run has settled, compiled: the period test on the stroboscopic sections, on arrays.

The reference's :mod:`impactdamper.core.periodicity` with its constants, step for step: the
screen of the last section against the ones up to ``kmax`` periods back, the whole cycle's
mismatch (:func:`_period`), the least divisor that may still be converging
(:func:`_least_period`) and the decay of the section differences (:func:`_converged`).
:func:`settled_period` is the test after ``n`` sections, as the settled-motion kernel
(:mod:`~impactdamper.core.compiled.settle`) runs it after every period.
"""

from __future__ import annotations

import math

from numba import njit

from impactdamper.core.periodicity import (
    CONVERGENCE_NOISE,
    CONVERGENCE_WINDOW,
    DIVISOR_DECAY,
    DIVISOR_FLOOR_FACTOR,
    DIVISOR_SUSPECT,
    ROUNDING_FLOOR,
    STALL_WINDOW,
)


@njit(cache=True)
def _mismatch(sections, modes, n, k):
    if n < 2 * k + 1:
        return math.inf
    for j in range(k):
        if modes[n - k + j] != modes[n - 2 * k + j]:
            return math.inf
    worst = 0.0
    for j in range(k):
        for c in range(4):
            worst = max(worst, abs(sections[n - k + j, c] - sections[n - 2 * k + j, c]))
    return worst


@njit(cache=True)
def _period(sections, modes, n, kmax, tol):
    best = math.inf
    for k in range(1, kmax + 1):
        worst = _mismatch(sections, modes, n, k)
        best = min(best, worst)
        if worst < tol:
            return k, worst
    return 0, best


@njit(cache=True)
def _lag_windows(sections, n, lag, window):
    """The largest change over ``lag`` periods in each of the two last windows of ``window``
    sections before n: (the older window's, the recent one's). Whether it decays from one to
    the next tells a transient from a settled motion (the divisor rule, the convergence test)."""
    older = 0.0
    recent = 0.0
    for r in range(2 * window):
        row = n - 2 * window + r
        worst = 0.0
        for c in range(4):
            worst = max(worst, abs(sections[row, c] - sections[row - lag, c]))
        if r < window:
            older = max(older, worst)
        else:
            recent = max(recent, worst)
    return older, recent


@njit(cache=True)
def _least_period(sections, modes, n, k, settle_tol):
    window = max(STALL_WINDOW, 2 * k)
    for d in range(1, k):
        m = _mismatch(sections, modes, n, d) if k % d == 0 else math.inf
        if m >= max(DIVISOR_SUSPECT, DIVISOR_FLOOR_FACTOR * settle_tol):
            continue
        if n < 2 * window + d:
            return 0, m
        first, second = _lag_windows(sections, n, d, window)
        if second < DIVISOR_DECAY * first:
            return 0, m
        if m < min(DIVISOR_FLOOR_FACTOR * settle_tol, DIVISOR_SUSPECT):
            return d, m
    return k, _mismatch(sections, modes, n, k)


@njit(cache=True)
def _converged(sections, n, k, settle_tol):
    """The reference's _converged on the first n sections."""
    w = -(-max(CONVERGENCE_WINDOW, 2 * k) // k) * k
    if n < 2 * w + k:
        return False
    spread = 0.0
    for i in range(w):
        for c in range(4):
            spread = max(spread, abs(sections[n - 1 - i, c] - sections[n - 1 - i % k, c]))
    older, recent = _lag_windows(sections, n, k, w)
    if recent < max(CONVERGENCE_NOISE * settle_tol, ROUNDING_FLOOR):
        tail = 0.0
    elif recent < older:
        g = (recent / older) ** (k / w)
        tail = recent * g / (1.0 - g)
    else:
        tail = math.inf
    return max(spread, tail) < settle_tol


@njit(cache=True)
def settled_period(sections, modes, n, kmax, settle_tol):
    """The reference's settling test after ``n`` sections: (k, residual), k the cycle's least
    period in forcing periods once the motion has settled (0 before), residual the sections'
    mismatch (inf before two sections can be compared). A quick look first: the smallest
    mismatch of the last section with one up to ``kmax`` periods back; only below
    ``settle_tol`` are the period, its least divisor and the convergence checked."""
    lags = min(kmax, (n - 1) // 2)
    if lags == 0:
        return 0, math.inf
    residual = math.inf
    for j in range(1, lags + 1):
        worst = 0.0
        for c in range(4):
            worst = max(worst, abs(sections[n - 1 - j, c] - sections[n - 1, c]))
        residual = min(residual, worst)
    if residual >= settle_tol:
        return 0, residual
    k, residual = _period(sections, modes, n, kmax, settle_tol)
    if k:
        k, residual = _least_period(sections, modes, n, k, settle_tol)
    if k and residual < settle_tol and not _converged(sections, n, k, settle_tol):
        k = 0
    return k, residual
