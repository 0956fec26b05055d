"""The largest excursion of a settled cycle, compiled: max |x1|/x_st over a stretch of the run.

The reference's :func:`impactdamper.core.excursion.max_excursion` on the describing run's
segments: |x1| sampled ``EXCURSION_SAMPLES_PER_PERIOD`` times a period, then the largest sample (and an
end of the stretch where the largest lies there) refined on its segment by golden-section search
where the reference uses scipy's bounded Brent search; both stop at 1e-12 T.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactdamper.core.compiled.flow import mode_size
from impactdamper.core.compiled.layout import S_OMEGA, S_T, S_XST
from impactdamper.core.excursion import EXCURSION_SAMPLES_PER_PERIOD

# Golden-section iterations of the x1_max refinement: 0.618^80 ~ 2e-17 of a bracket of 2/256 T,
# below the reference's xatol of 1e-12 T.
GOLDEN_ITERATIONS = 80
_GOLD = 0.5 * (3.0 - math.sqrt(5.0))


@njit(cache=True)
def segment_index(seg_f, ns, t):
    """The reference's Trajectory._segment_index for one time."""
    lo, hi = 0, ns
    while lo < hi:  # searchsorted(starts, t, side="right")
        mid = (lo + hi) // 2
        if seg_f[mid, 0] <= t:
            lo = mid + 1
        else:
            hi = mid
    return min(max(lo - 1, 0), ns - 1)


@njit(cache=True)
def _abs_x1(cm, s, seg_m, seg_f, seg_a, k, t, y):
    """|x1(t)| on segment k: the first row of eq. (18) alone, one root of each conjugate pair
    (as the event search's evaluator), the excursion search's hot path. It differs from the
    full state's x1 by rounding only, which moves the maximum's value by rounding only."""
    mode = seg_m[k]
    n = mode_size(mode)
    tau = t - seg_f[k, 0]
    acc = 0.0
    for j in range(n):
        lam = cm[mode, 0, j]
        if lam.imag < 0.0:
            continue
        term = (cm[mode, 2, j] * seg_a[k, j] * np.exp(lam * tau)).real
        acc += 2.0 * term if lam.imag > 0.0 else term
    return abs(acc + (cm[mode, 1, 0] * np.exp(1j * s[S_OMEGA] * t)).imag)


@njit(cache=True)
def _golden_max(cm, s, seg_m, seg_f, seg_a, k, lo, hi):
    """max |x1| on [lo, hi] of segment k by golden-section search."""
    y = np.empty(4)
    a, b = lo, hi
    c = a + _GOLD * (b - a)
    d = b - _GOLD * (b - a)
    fc_ = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, c, y)
    fd_ = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, d, y)
    for _ in range(GOLDEN_ITERATIONS):
        if fc_ >= fd_:
            b, d, fd_ = d, c, fc_
            c = a + _GOLD * (b - a)
            fc_ = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, c, y)
        else:
            a, c, fc_ = c, d, fd_
            d = b - _GOLD * (b - a)
            fd_ = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, d, y)
    return max(fc_, fd_)


@njit(cache=True)
def max_excursion(cm, s, seg_m, seg_f, seg_a, ns, a, b):
    """max |x1|/x_st on [a, b] of the recorded run (segments' modes, starts and alphas, ``ns``
    of them): the samples' largest, refined on its segment (and at an end of [a, b] where the
    largest sample lies there)."""
    T = s[S_T]
    n = max(int(EXCURSION_SAMPLES_PER_PERIOD * (b - a) / T), 16)
    ts = np.linspace(a, b, n + 1)
    x1 = np.empty(n + 1)
    y = np.empty(4)
    k = segment_index(seg_f, ns, ts[0])
    for j in range(n + 1):
        # The samples increase: the segment index only moves forward (the same index as
        # segment_index gives, without a search per sample).
        while k + 1 < ns and seg_f[k + 1, 0] <= ts[j]:
            k += 1
        x1[j] = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, ts[j], y)
    i = int(np.argmax(x1))
    best = x1[i]
    for end in range(2):
        if end == 1:
            if i != 0 and i != n:
                break
            j = n if i == 0 else 0
            lo, hi = ts[max(j - 1, 0)], ts[min(j + 1, n)]
            k = segment_index(seg_f, ns, 0.5 * (lo + hi))
        else:
            lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, n)]
            k = segment_index(seg_f, ns, ts[i])
        seg_end = seg_f[k + 1, 0] if k + 1 < ns else math.inf
        lo, hi = max(lo, seg_f[k, 0]), min(hi, seg_end)
        if hi > lo:
            best = max(best, _golden_max(cm, s, seg_m, seg_f, seg_a, k, lo, hi))
    return best / s[S_XST]
