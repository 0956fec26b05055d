"""The settled one-impact cycle in arbitrary precision (mpmath), by two independent routes.

The paper's Algorithm No. 1 (eqs. 4-8, 10-17) written from its modal form
(:func:`algorithm1_mp`), and the fixed point of Algorithm No. 2's impact-to-impact map solved by
Newton's method and certified to have no impact inside the period (:func:`settled_cycle`), which
must agree; and the closed-form amplitudes of the motions without impacts
(:func:`forced_amplitudes_mp`). See :mod:`impactdamper.baselines.highprecision`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mpmath
from mpmath import mp

from impactdamper.baselines.highprecision.model import (
    BRACKET_HALF_WIDTH,
    DIGITS,
    HighPrecisionError,
    MPModel,
    exact_mpf,
)
from impactdamper.core.parameters import Parameters

__all__ = ["MPAlgorithm1", "MPCycle", "algorithm1_mp", "settled_cycle", "forced_amplitudes_mp"]


@dataclass(frozen=True)
class MPAlgorithm1:
    """Algorithm No. 1 in mpmath (see :func:`impactdamper.core.algorithm1.algorithm1`)."""

    exists: bool
    eps: object = None
    S: object = None
    candidates: tuple = ()
    U1: object = None
    U2: object = None
    zeta: object = None
    eps21: object = None
    roots: tuple = ()
    t_impact: object = None
    impact_phase: object = None
    state_after: object = field(default=None, repr=False)
    reason: str = ""


def algorithm1_mp(p: Parameters, dps: int = DIGITS) -> MPAlgorithm1:
    """Algorithm No. 1 (eqs. 4-8, 10-17) in mpmath, written from the paper's modal form.

    The roots of eq. (4) come from ``mpmath.polyroots`` (not from the state matrix), A_j from
    eq. (5), alpha_j from eq. (8), the forced amplitudes from eq. (10) (the 2x2 complex
    system), U1, U2, eps21 and zeta from eqs. (12)-(16), and both roots of eq. (17); the one
    with S > 0 is chosen. Needs simple roots of eq. (4).
    """
    m = MPModel(p, dps)
    with mp.workdps(dps):
        lam = _characteristic_roots(m, dps)
        T = m.T
        z0, x21s_T, dx21s_T = _unit_pulse_response(m, lam)
        w = m.omega
        x1p, x2p = m.forced_amplitudes()
        U1 = abs(x2p - x1p)
        eps21 = mp.atan2(mp.im(x2p - x1p), mp.re(x2p - x1p))
        D = m.reduced_mass * (1 + m.R)
        denom = 1 - D * dx21s_T
        U2 = D * x21s_T / denom * U1 * w
        zeta = mp.atan2(U2, U1)
        rho = m.Delta0 / mp.hypot(U1, U2)
        common = dict(U1=U1, U2=U2, zeta=zeta, eps21=eps21, roots=tuple(lam))
        if abs(rho) > 1:
            return MPAlgorithm1(exists=False, reason="|Delta0|/sqrt(U1^2+U2^2) > 1", **common)
        candidates = _pulse_candidates(rho, zeta, eps21, D * U1 * w, denom)
        positive = [c for c in candidates if c[1] > 0]
        if not positive:
            return MPAlgorithm1(exists=False, candidates=tuple(candidates), reason="no positive pulse", **common)
        eps, S = positive[0]
        phase = eps / (2 * mp.pi)
        t_imp = phase * T
        after = m.forced(t_imp) + S * z0
        return MPAlgorithm1(
            exists=True,
            eps=eps,
            S=S,
            candidates=tuple(candidates),
            t_impact=t_imp,
            impact_phase=phase,
            state_after=after,
            **common,
        )


def _characteristic_roots(m: MPModel, dps: int) -> list:
    """The four roots of eq. (4) by ``mpmath.polyroots``; HighPrecisionError if two (nearly)
    coincide (the modal form needs simple roots). Called at ``dps`` digits."""
    w1, w2 = m.omega1, m.omega2
    h1, h2 = m.k1 / (2 * m.m1), m.k2 / (2 * m.m2)
    m1, m2 = m.m1, m.m2
    d1 = m1 * w1**2 * w2**2
    d2 = 2 * m1 * (w2**2 * h1 + w1**2 * h2)
    d3 = m1 * (w1**2 + 4 * h1 * h2) + w2**2 * (m1 + m2)
    d4 = 2 * (m1 * h1 + h2 * (m1 + m2))
    d5 = m1
    lam = mp.polyroots([d5, d4, d3, d2, d1], maxsteps=200, extraprec=4 * dps)
    for i in range(4):
        for j in range(i):
            if abs(lam[i] - lam[j]) < mp.mpf(10) ** (-dps / 3) * max(abs(lam[i]), 1):
                raise HighPrecisionError(
                    "eq. (4) has (nearly) repeated roots: the modal form of Algorithm No. 1 breaks"
                )
    return lam


def _unit_pulse_response(m: MPModel, lam: list):
    """The T-periodic response to the unit pulse pair (eqs. 5-8): the state just after it
    (eq. 6 at t = 0+) and the relative displacement x2 - x1 and its rate at t = T-."""
    w2, h2 = m.omega2, m.k2 / (2 * m.m2)
    m1, m2 = m.m1, m.m2
    A = [(2 * h2 * l + w2**2) / (l**2 + 2 * h2 * l + w2**2) for l in lam]
    T = m.T
    E = [mp.exp(l * T) - 1 for l in lam]
    lhs = mp.matrix(4, 4)
    for j in range(4):
        lhs[0, j] = E[j]
        lhs[1, j] = m1 * lam[j] * E[j]
        lhs[2, j] = A[j] * E[j]
        lhs[3, j] = m2 * lam[j] * A[j] * E[j]
    alpha = mp.lu_solve(lhs, mp.matrix([0, -1, 0, 1]))
    # Eq. (6) at t = 0+ (state just after the unit pulse pair).
    z0 = mp.matrix(
        [
            mp.re(mp.fsum(alpha[j] for j in range(4))),
            mp.re(mp.fsum(alpha[j] * A[j] for j in range(4))),
            mp.re(mp.fsum(alpha[j] * lam[j] for j in range(4))),
            mp.re(mp.fsum(alpha[j] * A[j] * lam[j] for j in range(4))),
        ]
    )
    eT = [mp.exp(l * T) for l in lam]
    x21s_T = mp.re(mp.fsum(alpha[j] * (A[j] - 1) * eT[j] for j in range(4)))
    dx21s_T = mp.re(mp.fsum(alpha[j] * (A[j] - 1) * lam[j] * eT[j] for j in range(4)))
    return z0, x21s_T, dx21s_T


def _pulse_candidates(rho, zeta, eps21, DU1w, denom) -> list:
    """Both roots of eq. (17): (eps in [0, 2 pi), S) for phi = asin(rho) - zeta and
    pi - asin(rho) - zeta, where S = D U1 omega cos(phi) / denom (``DU1w`` = D U1 omega)."""
    candidates = []
    for phi in (mp.asin(rho) - zeta, mp.pi - mp.asin(rho) - zeta):
        eps = mp.fmod(phi - eps21, 2 * mp.pi)
        if eps < 0:
            eps += 2 * mp.pi
        S = DU1w * mp.cos(phi) / denom
        candidates.append((eps, S))
    return candidates


@dataclass(frozen=True)
class MPCycle:
    """The settled one-impact cycle in mpmath.

    Attributes
    ----------
    t_impact : mpf
        Impact time in [0, T), s; impacts at t_impact + k T.
    impact_phase : mpf
        t_impact / T.
    state_after, state_before : mpmath.matrix, shape (4,)
        States just after and just before the impact.
    velocity, impulse : mpf
    alg1_difference : mpf
        Largest difference (relative to x_st, x_st omega and T) between the Newton fixed point
        and Algorithm No. 1's closed form.
    newton_residual : mpf
        Residual of the fixed-point equations.
    """

    model: MPModel = field(repr=False)
    t_impact: object
    impact_phase: object
    state_after: object = field(repr=False)
    state_before: object = field(repr=False)
    velocity: object
    impulse: object
    alg1_difference: object
    newton_residual: object

    def state(self, t) -> mpmath.matrix:
        """State at absolute time t (s) on the periodic orbit (right-continuous at impacts)."""
        m = self.model
        with mp.workdps(m.dps):
            t = exact_mpf(t) if isinstance(t, float) else mp.mpf(t)
            k = mp.floor((t - self.t_impact) / m.T)
            return m.segment(self.t_impact + k * m.T, self.state_after).state(t)

    def impact_times(self, t_from: float, t_to: float) -> list:
        """Impact times in [t_from, t_to), s (mpf)."""
        m = self.model
        with mp.workdps(m.dps):
            k = mp.ceil((exact_mpf(t_from) - self.t_impact) / m.T)
            out = []
            while self.t_impact + k * m.T < exact_mpf(t_to):
                out.append(self.t_impact + k * m.T)
                k += 1
            return out


def settled_cycle(p: Parameters, dps: int = DIGITS) -> MPCycle:
    """The settled one-impact-per-period cycle in mpmath, by two independent routes.

    Algorithm No. 1 in mpmath gives the orbit; Newton's method on the impact-to-impact map of
    Algorithm No. 2 (exact flow over one period, then the impact law; unknowns: impact time
    and the state after it) then solves for the fixed point from there, and the certified
    scan proves the gap positive inside the period.

    Raises
    ------
    HighPrecisionError
        If Algorithm No. 1 has no orbit, the orbit crosses the stop inside the period, or the
        two routes disagree.
    """
    a1 = algorithm1_mp(p, dps)
    if not a1.exists:
        raise HighPrecisionError(f"Algorithm No. 1 has no orbit: {a1.reason}")
    m = MPModel(p, dps)
    with mp.workdps(dps):
        T = m.T

        def residual(t, x1, v1, v2):
            start = mp.matrix([x1, x1 + m.Delta0, v1, v2])
            before = m.segment(t, start).state(t + T)
            after, _, _ = m.impact(before)
            return [
                (after[0] - start[0]) / m.x_st,
                (after[1] - start[1]) / m.x_st,
                (after[2] - start[2]) / (m.x_st * m.omega),
                (after[3] - start[3]) / (m.x_st * m.omega),
            ]

        guess = (a1.t_impact, a1.state_after[0], a1.state_after[2], a1.state_after[3])
        sol = mp.findroot(residual, guess, tol=mp.mpf(10) ** (-2 * dps + 10))
        t_imp, x1, v1, v2 = (sol[i] for i in range(4))
        res = max(abs(r) for r in residual(t_imp, x1, v1, v2))
        after = mp.matrix([x1, x1 + m.Delta0, v1, v2])
        diff = max(
            abs(t_imp - a1.t_impact) / T,
            *(abs(after[i] - a1.state_after[i]) / m.x_st for i in (0, 1)),
            *(abs(after[i] - a1.state_after[i]) / (m.x_st * m.omega) for i in (2, 3)),
        )
        if diff > mp.mpf(10) ** (-(dps - 8)):
            raise HighPrecisionError(f"Algorithm No. 1 and the fixed point differ by {mpmath.nstr(diff, 5)}")
        seg = m.segment(t_imp, after)
        root, _ = seg.certified_first_root(
            t_imp, t_imp + T * (1 - BRACKET_HALF_WIDTH), departure_rate=after[2] - after[3]
        )
        if root is not None:
            raise HighPrecisionError(f"the orbit meets the stop inside the period, at {mpmath.nstr(root / T, 12)} T")
        before = seg.state(t_imp + T)
        _, v, S = m.impact(before)
        return MPCycle(m, t_imp, t_imp / T, after, before, v, S, diff, res)


def forced_amplitudes_mp(p: Parameters, dps: int = DIGITS) -> dict:
    """Amplitudes of the two closed-form periodic motions without impacts, relative to x_st.

    ``free``: the forced response of eq. (10) with the bodies apart: |x1p|/x_st and the
    relative amplitude |x2p - x1p|/x_st (the gap's swing: the no-contact threshold of
    Delta0/x_st). ``stuck``: the bodies moving as one mass m1 + m2 on (c1, k1):
    |P0 / (c1 - (m1 + m2) omega^2 + i omega k1)| / x_st. Returned as floats.
    """
    m = MPModel(p, dps)
    with mp.workdps(dps):
        w = m.omega
        x1p, x2p = m.forced_amplitudes()
        stuck = m.P0 / (m.c1 - (m.m1 + m.m2) * w**2 + 1j * w * m.k1)
        return {
            "free_x1": float(abs(x1p) / m.x_st),
            "free_relative": float(abs(x2p - x1p) / m.x_st),
            "stuck_x1": float(abs(stuck) / m.x_st),
        }
