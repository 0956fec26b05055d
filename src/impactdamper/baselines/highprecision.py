"""High-precision reference: the same closed form in arbitrary precision (mpmath).

The double-precision library (Algorithm No. 2 of Timofeev et al. 2019 with the exact flow,
and the closed-form Algorithm No. 1) is accurate to about 1e-14 in impact phase. To measure
errors that small, this module recomputes the reference case's motion at ``DIGITS``
significant digits with the same closed form but independent code:

* the free mode's state matrix (eqs. 2, 9) in mpmath, its free response by eigen-decomposition
  (``mpmath.eig``; the matrix exponential ``mpmath.expm`` where the eigenvectors are
  ill-conditioned), the forced response by complex amplitudes, (i omega I - M) Yhat = b
  (eq. 10 in state form);
* the impact law of eqs. (14), (21)-(22);
* the next impact as the first root of the gap (eq. 20), found by ``mpmath.findroot`` on a
  bracket around the double-precision estimate, and *certified independently* of the
  library's event search: on every interval [u, v] before the bracket the gap g satisfies
  min(g(u), g(v)) > K (v - u)^2 / 8 with K a bound of |g''| (then g > 0 on [u, v], because a
  function with |g''| <= K lies above its chord minus K h^2 / 8); intervals that fail are
  halved. Inside the bracket, |g'(mid)| > K (v - u) / 2 proves g monotone, so the root is
  unique. Without an estimate the same scan finds the bracket itself.

For |g''| the modal form gives K = |G| omega^2 + sum_j |g_j| |lambda_j|^2 (all Re lambda_j
<= 0), with G the forced and g_j the modal amplitudes of the gap; with the matrix exponential
the free response's energy, which never grows, bounds it (as in ``events.py``, but evaluated
here in mpmath).

Two settled-cycle computations check each other: the paper's Algorithm No. 1 (eqs. 4-8,
10-17) in mpmath, with the roots of eq. (4) from ``mpmath.polyroots``, and a Newton solve of
the impact-to-impact map of Algorithm No. 2 (flow over one period, then the impact law) for
its fixed point, started from Algorithm No. 1's orbit and certified to have no impact inside
the period.

Everything is computed from the double-precision values of the relative parameters taken as
exact binary numbers, so the double and the mpmath computations solve the same problem.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mpmath
import numpy as np
from mpmath import mp

from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import DEFAULT_KICK

__all__ = [
    "DIGITS",
    "HighPrecisionError",
    "MPModel",
    "MPImpact",
    "MPCycle",
    "MPAlgorithm1",
    "first_impacts",
    "settled_cycle",
    "algorithm1_mp",
    "default_initial_state_mp",
    "gap_minimum",
    "forced_amplitudes_mp",
    "to_float",
]

# 40 significant digits: double-precision errors (~1e-16) are resolved with ~20 digits to spare.
DIGITS = 40
# First scan intervals, in units of T; they are halved where the certificate fails.
SCAN_STEP = 1.0 / 64.0
# Halvings allowed below SCAN_STEP (2^-60 T ~ 1e-19 T): deeper means a tangency the scan
# cannot separate from a root (a grazing contact), which raises HighPrecisionError.
MAX_DEPTH = 60
# Half-width of the bracket around a double-precision estimate, in units of T: far wider than
# the estimate's error (~1e-14), far narrower than the spacing of impacts.
BRACKET_HALF_WIDTH = 1e-8
# Above this condition number of the eigenvector matrix (relative to 10^dps) the modal form
# would lose more than a third of the digits; mpmath.expm takes over.
MODAL_CONDITION_DIGITS_FRACTION = 1.0 / 3.0


class HighPrecisionError(RuntimeError):
    """The high-precision reference cannot certify a result (a tangency, or a disagreement)."""


def _mpf(x: float) -> mpmath.mpf:
    """The double ``x`` as an exact binary mpf (no decimal rounding)."""
    return mp.mpf(float(x))


class MPModel:
    """The suppressor's free mode and impact law in mpmath at ``dps`` digits.

    Parameters
    ----------
    p : Parameters
    dps : int
        Decimal digits of the working precision.
    """

    def __init__(self, p: Parameters, dps: int = DIGITS):
        if not (isinstance(dps, int) and dps >= 20):
            raise ValueError(f"`dps` = {dps!r} is not allowed: must be an integer >= 20")
        self.p = p
        self.dps = dps
        with mp.workdps(dps):
            theta, mu, N, d1, d2, R, gap, omega, x_st, m1 = (_mpf(getattr(p, n)) for n in Parameters.names())
            omega1 = omega / theta
            omega2 = N * omega1
            m2 = mu * m1
            c1 = m1 * omega1**2
            c2 = m2 * omega2**2
            k1 = 2 * m1 * omega1 * d1
            k2 = 2 * m2 * omega1 * d2
            self.theta, self.mu, self.N, self.R, self.omega, self.x_st = theta, mu, N, R, omega, x_st
            self.m1, self.m2, self.c1, self.c2, self.k1, self.k2 = m1, m2, c1, c2, k1, k2
            self.omega1, self.omega2 = omega1, omega2
            self.P0 = c1 * x_st
            self.Delta0 = gap * x_st
            self.T = 2 * mp.pi / omega
            self.reduced_mass = m1 * m2 / (m1 + m2)
            # y = (x1, x2, x1', x2'):  m1 x1'' = -(c1 + c2) x1 + c2 x2 - (k1 + k2) x1' + k2 x2' + P0 sin wt
            #                          m2 x2'' = c2 x1 - c2 x2 + k2 x1' - k2 x2'
            M = mp.matrix(4, 4)
            M[0, 2] = M[1, 3] = 1
            M[2, 0], M[2, 1], M[2, 2], M[2, 3] = -(c1 + c2) / m1, c2 / m1, -(k1 + k2) / m1, k2 / m1
            M[3, 0], M[3, 1], M[3, 2], M[3, 3] = c2 / m2, -c2 / m2, k2 / m2, -k2 / m2
            self.M = M
            self.b = mp.matrix([0, 0, self.P0 / m1, 0])
            A = mp.matrix(4, 4)
            for i in range(4):
                A[i, i] = 1j * omega
            self.Yhat = mp.lu_solve(A - M, self.b)
            lam, V = mp.eig(M)
            self.roots = list(lam)
            Vinv = None
            try:
                Vinv = mp.inverse(V)
                condition = mp.mnorm(V, 1) * mp.mnorm(Vinv, 1)
            except ZeroDivisionError:
                condition = mp.inf
            self.modal = bool(condition < mp.mpf(10) ** (dps * MODAL_CONDITION_DIGITS_FRACTION))
            self.V, self.Vinv = V, (Vinv if self.modal else None)
            # Energy weight W (z^T W z never grows in free motion) for the expm path's bound.
            self.W = mp.diag([c1 + c2, c2, m1, m2])
            self.W[0, 1] = self.W[1, 0] = -c2
            self.gap_c = mp.matrix([[1, -1, 0, 0]])  # Delta = Delta0 + gap_c . y

    # --- closed-form pieces ---------------------------------------------------------------
    def forced(self, t) -> mpmath.matrix:
        """Forced response Y(t) = Im(Yhat e^{i omega t}), shape (4,)."""
        e = mp.expj(self.omega * t)
        return mp.matrix([mp.im(self.Yhat[i] * e) for i in range(4)])

    def segment(self, t0, y0) -> MPSegment:
        return MPSegment(self, t0, y0)

    def gap_of(self, y) -> mpmath.mpf:
        return self.Delta0 - (y[1] - y[0])

    def impact(self, y) -> tuple[mpmath.matrix, mpmath.mpf, mpmath.mpf]:
        """Eqs. (21)-(22): state after, closing velocity v = x2' - x1' and pulse S."""
        with mp.workdps(self.dps):
            v = y[3] - y[2]
            S = self.reduced_mass * (1 + self.R) * v
            after = mp.matrix([y[0], y[1], y[2] + S / self.m1, y[3] - S / self.m2])
            return after, v, S


class MPSegment:
    """Exact free motion from (t0, y0) in mpmath; the gap and its first derivative."""

    def __init__(self, model: MPModel, t0, y0):
        self.model = m = model
        dps = m.dps
        with mp.workdps(dps):
            self.t0 = mp.mpf(t0)
            self.y0 = mp.matrix([mp.mpf(v) for v in y0])
            self.z0 = self.y0 - m.forced(self.t0)
            self.G = m.Yhat[0] - m.Yhat[1]  # gap's forced amplitude: -(x2 - x1)
            w = m.omega
            if m.modal:
                alpha = m.Vinv * self.z0
                self.alpha = alpha
                self.gcoef = [-(m.V[1, j] - m.V[0, j]) * alpha[j] for j in range(4)]
                # |g''| <= |G| w^2 + sum |g_j| |lambda_j|^2 for tau >= 0 (Re lambda_j <= 0).
                self.K = abs(self.G) * w**2 + mp.fsum(abs(g) * abs(l) ** 2 for g, l in zip(self.gcoef, m.roots))
            else:
                # |c M^2 z| <= |c M^2 L^-T| sqrt(z^T W z), and z^T W z never grows.
                L = mp.cholesky(m.W)
                cM2 = m.gap_c * m.M * m.M
                bound = mp.norm(cM2 * mp.inverse(L.T), 2)
                energy = (self.z0.T * m.W * self.z0)[0]
                self.K = abs(self.G) * w**2 + bound * mp.sqrt(energy)
            # Zero damping puts the roots on the imaginary axis, up to rounding (~10^-dps).
            if any(mp.re(l) > mp.mpf(10) ** (-(dps // 2)) * abs(l) for l in m.roots):
                raise HighPrecisionError("an eigenvalue with positive real part: the |g''| bound does not hold")
            # Safety margin for the rounding of the bound itself (and Re lambda ~ +10^-dps).
            self.K = self.K * (1 + mp.mpf(10) ** (-6))

    def free(self, t) -> mpmath.matrix:
        m = self.model
        tau = t - self.t0
        if m.modal:
            e = [self.alpha[j] * mp.exp(m.roots[j] * tau) for j in range(4)]
            return mp.matrix([mp.re(mp.fsum(m.V[i, j] * e[j] for j in range(4))) for i in range(4)])
        return mp.expm(m.M * tau) * self.z0

    def state(self, t) -> mpmath.matrix:
        with mp.workdps(self.model.dps):
            t = mp.mpf(t)
            return self.model.forced(t) + self.free(t)

    def gap(self, t) -> mpmath.mpf:
        m = self.model
        with mp.workdps(m.dps):
            t = mp.mpf(t)
            forced = mp.im(self.G * mp.expj(m.omega * t))
            if m.modal:
                tau = t - self.t0
                free = mp.re(mp.fsum(g * mp.exp(l * tau) for g, l in zip(self.gcoef, m.roots)))
            else:
                z = self.free(t)
                free = -(z[1] - z[0])
            return m.Delta0 + forced + free

    def gap_rate(self, t) -> mpmath.mpf:
        m = self.model
        with mp.workdps(m.dps):
            t = mp.mpf(t)
            forced = mp.re(self.G * mp.expj(m.omega * t)) * m.omega
            if m.modal:
                tau = t - self.t0
                free = mp.re(mp.fsum(g * l * mp.exp(l * tau) for g, l in zip(self.gcoef, m.roots)))
            else:
                z = m.M * self.free(t)
                free = -(z[1] - z[0])
            return forced + free

    # --- certified search -------------------------------------------------------------------
    def _search(self, u, v, gu, gv, depth: int, counter: list):
        """First sign change of the gap on (u, v], certified (see the module docstring).

        Returns None if g > 0 on [u, v], else (lo, hi, g(lo), g(hi)) with exactly one root."""
        h = v - u
        counter[0] += 1
        if gu > 0 and gv > 0 and min(gu, gv) > self.K * h * h / 8:
            return None
        if gu > 0 and gv <= 0 and abs(self.gap_rate(u + h / 2)) > self.K * h / 2:
            return (u, v, gu, gv)  # g monotone on [u, v]: one root
        if depth >= MAX_DEPTH:
            raise HighPrecisionError(
                f"gap tangency near t = {mpmath.nstr(u, 20)} s: cannot certify a root or its absence (grazing)"
            )
        mid = u + h / 2
        gm = self.gap(mid)
        if gu > 0:
            found = self._search(u, mid, gu, gm, depth + 1, counter)
            if found is not None:
                return found
        return self._search(mid, v, gm, gv, depth + 1, counter)

    def certified_first_root(self, t_from, t_to, departure_rate=None, estimate: float | None = None):
        """The first root of the gap on (t_from, t_to], certified, at full precision.

        Parameters
        ----------
        t_from, t_to : mpf
            Search interval, s.
        departure_rate : mpf, optional
            g'(t_from) > 0 when g(t_from) = 0 (leaving the stop after an impact).
        estimate : float, optional
            Double-precision estimate of the root; the bracket is then
            estimate +- BRACKET_HALF_WIDTH T, and the scan certifies (t_from, bracket].

        Returns
        -------
        (root, info) or (None, info)
            ``info`` holds the number of certified intervals and whether the estimate's
            bracket was confirmed.
        """
        m = self.model
        with mp.workdps(m.dps):
            a = mp.mpf(t_from)
            t_to = mp.mpf(t_to)
            if departure_rate is not None:
                if not departure_rate > 0:
                    raise HighPrecisionError("leaving the stop needs a positive gap rate")
                # g(a + s) >= g' s - K s^2 / 2 > 0 for 0 < s <= g'/K.
                a = a + departure_rate / self.K
            ga = self.gap(a)
            if not ga > 0:
                raise HighPrecisionError(f"gap {mpmath.nstr(ga, 5)} <= 0 at the start of the search")
            counter = [0]
            info = {"intervals": 0, "estimate_confirmed": None}
            end = t_to
            bracket = None
            if estimate is not None:
                half = BRACKET_HALF_WIDTH * m.T
                lo, hi = _mpf(estimate) - half, _mpf(estimate) + half
                glo, ghi = self.gap(lo), self.gap(hi)
                if lo > a and glo > 0 and ghi <= 0 and abs(self.gap_rate(_mpf(estimate))) > self.K * 2 * half:
                    bracket, end = (lo, hi, glo, ghi), lo
            step = SCAN_STEP * m.T
            u, gu = a, ga
            found = None
            while u < end:
                v = min(u + step, end)
                gv = self.gap(v)
                found = self._search(u, v, gu, gv, 0, counter)
                if found is not None:
                    break
                u, gu = v, gv
            info["intervals"] = counter[0]
            if estimate is not None:
                info["estimate_confirmed"] = bracket is not None and found is None
            if found is None:
                found = bracket
            if found is None:
                return None, info
            lo, hi, _, _ = found
            root = mp.findroot(self.gap, (lo, hi), solver="anderson")
            if not (lo <= root <= hi):
                raise HighPrecisionError("findroot left its certified bracket")
            # Newton polish to the last digits (the bracketing solver may stop a few short).
            for _ in range(3):
                rate = self.gap_rate(root)
                root = root - self.gap(root) / rate
            return root, info


@dataclass(frozen=True)
class MPImpact:
    """One impact computed in mpmath.

    Attributes
    ----------
    t : mpf
        Time, s.
    velocity : mpf
        Closing relative velocity before the impact, m/s.
    impulse : mpf
        Pulse S, N s.
    before, after : mpmath.matrix, shape (4,)
        States (x1, x2, x1', x2').
    estimate_confirmed : bool or None
        Whether the double-precision estimate's bracket was certified (None: no estimate).
    """

    t: object
    velocity: object
    impulse: object
    before: object = field(repr=False)
    after: object = field(repr=False)
    estimate_confirmed: object = None

    def t_over_T(self, T) -> float:
        return float(self.t / T)


def default_initial_state_mp(model: MPModel) -> mpmath.matrix:
    """Algorithm No. 2, step 1, in mpmath (same kick as :func:`simulate.default_initial_state`)."""
    with mp.workdps(model.dps):
        S0 = _mpf(DEFAULT_KICK) * model.m1 * model.omega1 * model.x_st
        return mp.matrix([0, model.Delta0, S0 / model.m1, -S0 / model.m2])


def first_impacts(
    p: Parameters, n: int, *, t0: float = 0.0, state=None, estimates=None, dps: int = DIGITS, min_velocity: float = 1e-6
) -> list[MPImpact]:
    """The first ``n`` impacts of Algorithm No. 2 from ``state`` at ``t0``, in mpmath.

    Parameters
    ----------
    p : Parameters
    n : int
        Number of impacts (>= 1).
    t0 : float
        Start time, s.
    state : sequence of 4 numbers, optional
        (x1, x2, x1', x2') at t0; default Algorithm No. 2's step 1 (gap zero, opening).
        With a zero gap the state must be opening (x1' > x2').
    estimates : sequence of float, optional
        Double-precision estimates of the impact times (e.g. from :func:`simulate`); each
        brackets its root, certified by the scan.
    dps : int
        Decimal digits.
    min_velocity : float
        Relative closing velocity (to x_st omega) below which the impacts are accumulating
        into persistent contact, which this reference does not model: HighPrecisionError.

    Returns
    -------
    list of MPImpact
    """
    if not (isinstance(n, int) and n >= 1):
        raise ValueError(f"`n` = {n!r} is not allowed: must be an integer >= 1")
    model = MPModel(p, dps)
    out: list[MPImpact] = []
    with mp.workdps(dps):
        y = default_initial_state_mp(model) if state is None else mp.matrix([_mpf(v) for v in state])
        t = _mpf(t0)
        g = model.gap_of(y)
        rate = y[2] - y[3]
        departure = None
        if abs(g) <= mp.mpf(10) ** (-(dps - 5)) * model.x_st:
            if not rate > 0:
                raise HighPrecisionError("starting on the stop without opening velocity")
            departure = rate
        elif g < 0:
            raise ValueError("`state` has a negative gap")
        horizon = 1000 * model.T  # an impact-free stretch this long ends the search
        for k in range(n):
            seg = model.segment(t, y)
            est = None if estimates is None or k >= len(estimates) else float(estimates[k])
            root, info = seg.certified_first_root(t, t + horizon, departure, est)
            if root is None:
                raise HighPrecisionError(f"no impact {k + 1} within {horizon} s")
            before = seg.state(root)
            after, v, S = model.impact(before)
            out.append(MPImpact(root, v, S, before, after, info["estimate_confirmed"]))
            if v < min_velocity * model.x_st * model.omega:
                raise HighPrecisionError(f"impact {k + 1} closes at {mpmath.nstr(v, 5)} m/s: impacts accumulate")
            t, y, departure = root, after, after[2] - after[3]
    return out


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
        # Eq. (10): the forced complex amplitudes.
        w = m.omega
        Z = mp.matrix(
            [
                [-m1 * w**2 + 1j * w * (m.k1 + m.k2) + (m.c1 + m.c2), -1j * w * m.k2 - m.c2],
                [-1j * w * m.k2 - m.c2, -m2 * w**2 + 1j * w * m.k2 + m.c2],
            ]
        )
        x1p, x2p = mp.lu_solve(Z, mp.matrix([m.P0, 0]))
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
        candidates = []
        for phi in (mp.asin(rho) - zeta, mp.pi - mp.asin(rho) - zeta):
            eps = mp.fmod(phi - eps21, 2 * mp.pi)
            if eps < 0:
                eps += 2 * mp.pi
            S = D * U1 * w * mp.cos(phi) / denom
            candidates.append((eps, S))
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
            t = _mpf(t) if isinstance(t, float) else mp.mpf(t)
            k = mp.floor((t - self.t_impact) / m.T)
            return m.segment(self.t_impact + k * m.T, self.state_after).state(t)

    def impact_times(self, t_from: float, t_to: float) -> list:
        """Impact times in [t_from, t_to), s (mpf)."""
        m = self.model
        with mp.workdps(m.dps):
            k = mp.ceil((_mpf(t_from) - self.t_impact) / m.T)
            out = []
            while self.t_impact + k * m.T < _mpf(t_to):
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


def gap_minimum(p: Parameters, t0: float, state, lo: float, hi: float, dps: int = DIGITS):
    """The free motion's gap minimum inside (lo, hi), from ``state`` at ``t0``, in mpmath.

    The gap rate must change sign from negative to positive on [lo, hi] (a bracket from a
    double-precision estimate). Returns (t_min, gap_min) as mpf, s and m."""
    m = MPModel(p, dps)
    seg = m.segment(_mpf(t0), [_mpf(v) for v in state])
    with mp.workdps(dps):
        a, b = _mpf(lo), _mpf(hi)
        if not (seg.gap_rate(a) < 0 < seg.gap_rate(b)):
            raise HighPrecisionError("the gap rate does not change sign from - to + on the bracket")
        t = mp.findroot(seg.gap_rate, (a, b), solver="anderson")
        return t, seg.gap(t)


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
        Z = mp.matrix(
            [
                [-m.m1 * w**2 + 1j * w * (m.k1 + m.k2) + (m.c1 + m.c2), -1j * w * m.k2 - m.c2],
                [-1j * w * m.k2 - m.c2, -m.m2 * w**2 + 1j * w * m.k2 + m.c2],
            ]
        )
        x1p, x2p = mp.lu_solve(Z, mp.matrix([m.P0, 0]))
        stuck = m.P0 / (m.c1 - (m.m1 + m.m2) * w**2 + 1j * w * m.k1)
        return {
            "free_x1": float(abs(x1p) / m.x_st),
            "free_relative": float(abs(x2p - x1p) / m.x_st),
            "stuck_x1": float(abs(stuck) / m.x_st),
        }


def to_float(x) -> np.ndarray | float:
    """mpf or mpmath matrix to float / ndarray."""
    if isinstance(x, mpmath.matrix):
        return np.array([float(x[i]) for i in range(x.rows)])
    return float(x)
