"""The impact law, stated once for the Python reference: Newton's restitution R (eqs. 14, 21-22).

Timofeev et al. (2019): at an impact (the gap Delta of eq. (20) closes while v = x2' - x1' > 0)
the stop gives the pulse

    S = m_red (1 + R) v,      m_red = m1 m2/(m1 + m2)          (eqs. 14, 21),

which adds S/m1 to x1' and -S/m2 to x2' (eq. 22): momentum is kept and the relative velocity
becomes -R v (the rebound R v). Its Jacobian on (x1, x2, x1', x2') is the jump matrix J_R.
A rebound too slow to part the bodies while the stop presses them together ends a chatter
sequence, whose impacts accumulate at a finite time (the geometric series of rebounds).

Every reference solver reads the law here: the event loop (:mod:`~impactdamper.core.model`,
:mod:`~impactdamper.core.simulate`), Algorithm No. 1 (:mod:`~impactdamper.core.algorithm1`),
the shooting equations (:mod:`impactdamper.analysis.shooting`) and the tangent walk
(:mod:`~impactdamper.core.tangent`). The compiled kernels' twin is
:mod:`impactdamper.core.compiled.impact` (the equivalence tests hold the two together); the
independent baselines state the law on their own, on purpose.
"""

from __future__ import annotations

import numpy as np

from impactdamper.core.parameters import Parameters

__all__ = ["impact_pulse", "apply_impact", "rebound", "accumulation_time", "impact_matrix", "impact_jump"]


def impact_pulse(p: Parameters, v):
    """The pulse S = m_red (1 + R) v of eq. (21), N s, for closing velocities v (m/s); with
    v = 1, the paper's D = m_red (1 + R) of eq. (14)."""
    return p.reduced_mass * (1.0 + p.R) * v


def apply_impact(p: Parameters, full: np.ndarray) -> tuple[np.ndarray, float, float]:
    """Eqs. (21)-(22) applied to a state (x1, x2, x1', x2') on the stop: (the state just after,
    the closing velocity v = x2' - x1' >= 0 (a grazing touch gives ~0), the pulse S in N s)."""
    v = max(float(full[3] - full[2]), 0.0)
    S = impact_pulse(p, v)
    after = np.array(full, dtype=float)
    after[2] += S / p.m1
    after[3] -= S / p.m2
    return after, v, S


def rebound(p: Parameters, v: float) -> float:
    """The opening relative velocity R v after an impact of closing velocity v, m/s."""
    return p.R * v


def accumulation_time(p: Parameters, t: float, rebound: float, a: float) -> float:
    """When the impacts of a chatter sequence accumulate, s: from an impact at t with the
    given rebound and the bodies pressed together at relative acceleration a > 0, the flights
    2 R^k rebound/a sum to t + 2 rebound/((1 - R) a) (Budd & Dux 1994); at once for R = 1."""
    return t + (2.0 * rebound / ((1.0 - p.R) * a) if p.R < 1.0 else 0.0)


def impact_matrix(p: Parameters) -> np.ndarray:
    """J_R of eqs. (21)-(22) from the pulse: x1' += S/m1, x2' -= S/m2 with
    S = m_red (1 + R)(x2' - x1'), i.e. I + D e w^T; shape (4, 4), acting on (x1, x2, x1', x2')
    just before the impact (the shooting equations and a cycle's saltation matrices)."""
    D = impact_pulse(p, 1.0)
    e = np.array([0.0, 0.0, 1.0 / p.m1, -1.0 / p.m2])
    w = np.array([0.0, 0.0, -1.0, 1.0])
    return np.eye(4) + D * np.outer(e, w)


def impact_jump(m1: float, m2: float, R: float) -> np.ndarray:
    """J_R of eqs. (21)-(22) in mass ratios, as the compiled kernels' twin writes it (the
    tangent walk, which they mirror to the last bit), shape (4, 4).

    The pulse S = m1 m2/(m1 + m2) (1 + R) (x2' - x1') adds S/m1 to x1' and -S/m2 to x2': so
    x1'+ = x1' + (1 + R) m2/M (x2' - x1') and x2'+ = x2' - (1 + R) m1/M (x2' - x1'), M = m1 + m2.
    Positions are unchanged. det J_R = -R. (The same matrix as :func:`impact_matrix`, rounded
    otherwise.)
    """
    M = m1 + m2
    a, c = (1.0 + R) * m2 / M, (1.0 + R) * m1 / M
    return np.array(
        [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0 - a, a],
            [0.0, 0.0, c, 1.0 - c],
        ]
    )
