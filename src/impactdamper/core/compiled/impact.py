"""The impact law, compiled: the kernels' twin of :mod:`impactdamper.core.impact_law`.

Newton's restitution R of eqs. (14), (21)-(22) on the packed scalars ``s``
(:mod:`~impactdamper.core.compiled.layout`): the pulse S = m_red (1 + R) v and the velocities
after it, the rebound R v, the accumulation time of a chatter sequence and the jump matrix
J_R. The event loop (:mod:`~impactdamper.core.compiled.loop`) and the tangent walk
(:mod:`~impactdamper.core.compiled.tangent`) read the law here. Each line keeps the reference's
operations in their order, so that the two agree to the last bit
(``tests/unit/test_compiled.py``); the hot path is inlined at numba's IR level as the loop's
own steps are.
"""

from __future__ import annotations

from numba import njit

from impactdamper.core.compiled.layout import S_M1, S_M2, S_MRED, S_R


@njit(cache=True, inline="always")
def apply_impact(s, full):
    """Eqs. (21)-(22) on a state (x1, x2, x1', x2') on the stop: (the state just after, the
    closing velocity v >= 0, the pulse S = m_red (1 + R) v)."""
    v = max(full[3] - full[2], 0.0)
    S = s[S_MRED] * (1.0 + s[S_R]) * v
    after = full.copy()
    after[2] += S / s[S_M1]
    after[3] -= S / s[S_M2]
    return after, v, S


@njit(cache=True, inline="always")
def rebound(s, v):
    """The opening relative velocity R v after an impact of closing velocity v."""
    return s[S_R] * v


@njit(cache=True, inline="always")
def accumulation_time(s, t, rebound, a):
    """When a chatter sequence's impacts accumulate: t + 2 rebound/((1 - R) a); t for R = 1."""
    R = s[S_R]
    return t + (2.0 * rebound / ((1.0 - R) * a) if R < 1.0 else 0.0)


@njit(cache=True)
def impact_jump(s, J):
    """J_R of eqs. (21)-(22) in mass ratios into J (4 x 4): the identity but for
    x1'+ = x1' + a (x2' - x1'), x2'+ = x2' - c (x2' - x1'), a = (1 + R) m2/M, c = (1 + R) m1/M."""
    m1, m2, R = s[S_M1], s[S_M2], s[S_R]
    M = m1 + m2
    a, c = (1.0 + R) * m2 / M, (1.0 + R) * m1 / M
    for i in range(4):
        for k in range(4):
            J[i, k] = 1.0 if i == k else 0.0
    J[2, 2], J[2, 3], J[3, 2], J[3, 3] = 1.0 - a, a, c, 1.0 - c
