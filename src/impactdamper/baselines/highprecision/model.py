"""The suppressor in arbitrary precision (mpmath) and its impacts, certified.

The free mode and the impact law of Timofeev et al. (2019) at ``DIGITS`` digits
(:class:`MPModel`), the exact free motion with the gap and its certified first root
(:class:`MPSegment`), and Algorithm No. 2's impacts from a start (:func:`first_impacts`); see
:mod:`impactdamper.baselines.highprecision` for the method and its certificate.
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
    "exact_mpf",
    "first_impacts",
    "default_initial_state_mp",
    "gap_minimum",
    "to_float",
]

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


def exact_mpf(x: float) -> mpmath.mpf:
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
            theta, mu, N, d1, d2, R, gap, omega, x_st, m1 = (exact_mpf(getattr(p, n)) for n in Parameters.names())
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

    def forced_amplitudes(self) -> tuple:
        """The complex amplitudes (x1p_hat, x2p_hat) of the forced response with the bodies apart,
        from eq. (10) as the paper writes it (the 2x2 complex system; ``Yhat`` solves the same
        response in state form)."""
        with mp.workdps(self.dps):
            w = self.omega
            Z = mp.matrix(
                [
                    [-self.m1 * w**2 + 1j * w * (self.k1 + self.k2) + (self.c1 + self.c2), -1j * w * self.k2 - self.c2],
                    [-1j * w * self.k2 - self.c2, -self.m2 * w**2 + 1j * w * self.k2 + self.c2],
                ]
            )
            x1p, x2p = mp.lu_solve(Z, mp.matrix([self.P0, 0]))
            return x1p, x2p

    def segment(self, t0, y0) -> _MPSegment:
        return _MPSegment(self, t0, y0)

    def gap_of(self, y) -> mpmath.mpf:
        return self.Delta0 - (y[1] - y[0])

    def impact(self, y) -> tuple[mpmath.matrix, mpmath.mpf, mpmath.mpf]:
        """Eqs. (21)-(22): state after, closing velocity v = x2' - x1' and pulse S."""
        with mp.workdps(self.dps):
            v = y[3] - y[2]
            S = self.reduced_mass * (1 + self.R) * v
            after = mp.matrix([y[0], y[1], y[2] + S / self.m1, y[3] - S / self.m2])
            return after, v, S


class _MPSegment:
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
                lo, hi = exact_mpf(estimate) - half, exact_mpf(estimate) + half
                glo, ghi = self.gap(lo), self.gap(hi)
                if lo > a and glo > 0 and ghi <= 0 and abs(self.gap_rate(exact_mpf(estimate))) > self.K * 2 * half:
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
        S0 = exact_mpf(DEFAULT_KICK) * model.m1 * model.omega1 * model.x_st
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
        y = default_initial_state_mp(model) if state is None else mp.matrix([exact_mpf(v) for v in state])
        t = exact_mpf(t0)
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


def gap_minimum(p: Parameters, t0: float, state, lo: float, hi: float, dps: int = DIGITS):
    """The free motion's gap minimum inside (lo, hi), from ``state`` at ``t0``, in mpmath.

    The gap rate must change sign from negative to positive on [lo, hi] (a bracket from a
    double-precision estimate). Returns (t_min, gap_min) as mpf, s and m."""
    m = MPModel(p, dps)
    seg = m.segment(exact_mpf(t0), [exact_mpf(v) for v in state])
    with mp.workdps(dps):
        a, b = exact_mpf(lo), exact_mpf(hi)
        if not (seg.gap_rate(a) < 0 < seg.gap_rate(b)):
            raise HighPrecisionError("the gap rate does not change sign from - to + on the bracket")
        t = mp.findroot(seg.gap_rate, (a, b), solver="anderson")
        return t, seg.gap(t)


def to_float(x) -> np.ndarray | float:
    """mpf or mpmath matrix to float / ndarray."""
    if isinstance(x, mpmath.matrix):
        return np.array([float(x[i]) for i in range(x.rows)])
    return float(x)
