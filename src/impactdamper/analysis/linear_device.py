"""The linear two-mass system in closed form: amplitude, stroke, their peaks over a band, and
the no-contact floor of an impact suppressor.

In relative form (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100, eq. 10; time in
1/omega1, lengths in x_st, B = N^2 + 2 i delta2 theta) the forced motion without contact has

    x1_hat/x_st = (B - theta^2)/D(theta),   (x2_hat - x1_hat)/x_st = theta^2/D(theta),
    D(theta) = (1 - theta^2 + 2 i delta1 theta)(B - theta^2) - mu B theta^2,

polynomials in theta with complex coefficients. Their moduli are smooth, and every stationary
point over a band is a real root of one real polynomial (:func:`linear_maxima`): the peaks of a
linear device are exact, not sampled.

**The no-contact floor.** An impact suppressor whose stop is at Delta0/x_st = gap > 0 moves
without contact wherever the linear motion's relative amplitude |x2_hat - x1_hat|/x_st (eq. 12's
U1) is below the gap: the linear motion then never reaches the stop, and, being the motion of a
damped linear system, attracts every start near it. So wherever U1(theta) < gap it is a stable
steady state, a branch that a slow sweep follows, and the largest |x1_hat|/x_st over that set
(its ends are where the motion first touches the stop) is a lower bound of the worst branch of
the impact suppressor over the band, exact (:func:`no_contact_floor`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from collections.abc import Sequence

import numpy as np

from impactdamper.core.parameters import Parameters, require_parameters
from impactdamper.core.validation import finite_argument

__all__ = [
    "LinearDevice",
    "den_hartog",
    "linear_maxima",
    "linear_peak",
    "NoContactFloor",
    "no_contact_floor",
    "check_band",
]

P = np.polynomial.polynomial


def check_band(band: object) -> tuple[float, float]:
    """``band`` as (theta_start, theta_stop): two finite numbers, 0 < start < stop; else a
    one-line error naming ``band``."""
    try:
        a, b = band  # type: ignore[misc]
    except (TypeError, ValueError):
        raise ValueError(f"`band` = {band!r} is not allowed: must be two numbers (theta_start, theta_stop)") from None
    a, b = finite_argument("theta_start", a), finite_argument("theta_stop", b)
    if not a > 0:
        raise ValueError(f"`theta_start` = {a!r} is not allowed: must be > 0")
    if not b > a:
        raise ValueError(f"`theta_stop` = {b!r} is not allowed: must be > theta_start = {a!r}")
    return float(a), float(b)


@dataclass(frozen=True)
class LinearDevice:
    """A linear device on the object: the bare object (``mu`` = 0), the absorber without a stop
    or a TMD, as polynomials in theta (the module docstring).

    Attributes
    ----------
    mu, N, delta1, delta2 : float
        The relative parameters (N and delta2 unused when mu = 0).
    """

    mu: float
    N: float
    delta1: float
    delta2: float

    @classmethod
    def of(cls, p: Parameters) -> LinearDevice:
        """The linear part of a suppressor's parameters (its stop removed)."""
        p = require_parameters(p)
        return cls(p.mu, p.N, p.delta1, p.delta2)

    @classmethod
    def bare(cls, delta1: float) -> LinearDevice:
        """The object alone: |x1|/x_st = 1/|1 - theta^2 + 2 i delta1 theta|."""
        return cls(0.0, 1.0, delta1, 0.0)

    def polynomials(self) -> tuple:
        """(x1 numerator, denominator D, stroke numerator), ascending complex coefficients."""
        obj = np.array([1.0, 2j * self.delta1, -1.0])
        if self.mu == 0.0:
            return np.array([1.0 + 0j]), obj, np.array([0.0j])
        b = np.array([self.N**2, 2j * self.delta2, -1.0])
        den = P.polysub(P.polymul(obj, b), self.mu * np.array([0.0, 0.0, self.N**2, 2j * self.delta2]))
        return b, den, np.array([0.0, 0.0, 1.0 + 0j])

    def amplitude(self, thetas: Sequence[float]) -> np.ndarray:
        """|x1|/x_st. Shape (len(thetas),)."""
        num, den, _ = self.polynomials()
        th = np.asarray(thetas, float)
        return np.abs(P.polyval(th, num) / P.polyval(th, den))

    def absorber(self, thetas: Sequence[float]) -> np.ndarray:
        """|x2|/x_st = |x1 + (x2 - x1)|/x_st = |B|/|D| (|x1|/x_st for the bare object, whose
        stroke is 0). Shape (len(thetas),)."""
        num, den, st = self.polynomials()
        th = np.asarray(thetas, float)
        return np.abs(P.polyval(th, P.polyadd(num, st)) / P.polyval(th, den))

    def stroke(self, thetas: Sequence[float]) -> np.ndarray:
        """|x2 - x1|/x_st (0 for the bare object). Shape (len(thetas),)."""
        _, den, st = self.polynomials()
        th = np.asarray(thetas, float)
        return np.abs(P.polyval(th, st) / P.polyval(th, den))

    def band_average(self, thetas: Sequence[float]) -> float:
        """The mean of |x1|/x_st over the band that ``thetas`` (increasing, ends included)
        spans, by the trapezoidal rule on them."""
        th = np.asarray(thetas, float)
        return float(np.trapezoid(self.amplitude(th), th) / (th[-1] - th[0]))

    def peak(self, band: tuple[float, float]) -> tuple[float, float]:
        """(theta, value) of the largest |x1|/x_st over the band, in closed form."""
        num, den, _ = self.polynomials()
        return linear_peak(num, den, band)

    def stroke_peak(self, band: tuple[float, float]) -> tuple[float, float]:
        """(theta, value) of the largest |x2 - x1|/x_st over the band, in closed form."""
        _, den, st = self.polynomials()
        if self.mu == 0.0:
            return float(band[0]), 0.0
        return linear_peak(st, den, band)


def den_hartog(mu: float) -> dict:
    """Den Hartog's optimal TMD on an undamped object: tuning N, damping delta2 and the peak of
    |x1|/x_st, N = 1/(1 + mu), delta2 = sqrt(3 mu/(8 (1 + mu)^3)), peak sqrt(1 + 2/mu) (the
    height of the fixed points, the exact minimax value on an unbounded band).

    Den Hartog (Mechanical Vibrations, 1956, sec. 3.3) gives the damping ratio on the
    absorber's own critical damping, zeta2 = k2/(2 m2 omega2) = sqrt(3 mu/(8 (1 + mu))); this
    project's delta2 = k2/(2 m2 omega1) = N zeta2 (the same number as his c/c_c with
    c_c = 2 m2 Omega_n on the main system's frequency). An earlier version multiplied it by N
    once more, 1/(1 + mu) too small (8 % at mu = 0.08); the numerical minimax optimum of an
    undamped object sits within 1 % of this delta2 (tests).
    """
    return {
        "N": 1.0 / (1.0 + mu),
        "delta2": math.sqrt(3.0 * mu / (8.0 * (1.0 + mu) ** 3)),
        "peak": math.sqrt(1.0 + 2.0 / mu),
    }


def _real_roots(poly: np.ndarray, a: float, b: float) -> list[float]:
    """The real roots of a real polynomial in [a, b] (ascending coefficients), Newton-polished."""
    poly = np.trim_zeros(np.asarray(poly, float), "b")
    if len(poly) < 2:
        return []
    d = P.polyder(poly)
    out = []
    for r in P.polyroots(poly):
        if abs(r.imag) <= 1e-6 * max(1.0, abs(r.real)) and a - 1e-9 <= r.real <= b + 1e-9:
            t = float(r.real)
            for _ in range(3):  # Newton polish of the real root
                slope = P.polyval(t, d)
                if slope == 0:
                    break
                t -= P.polyval(t, poly) / slope
            out.append(min(max(t, a), b))
    return sorted(out)


def linear_maxima(num: np.ndarray, den: np.ndarray, band: tuple[float, float]) -> list[tuple[float, float]]:
    """Every local maximum over ``band`` of |num(theta)/den(theta)|, num and den polynomials in
    theta with complex coefficients (ascending order), in closed form: the stationary points
    are the real roots of f' = 0 with f = |num|^2/|den|^2, i.e. of the real polynomial
    (|num|^2)' |den|^2 - |num|^2 (|den|^2)', polished by Newton's method; the band's ends count
    where the function falls away from them.

    Returns
    -------
    list of (theta, value), largest first.
    """
    a, b = check_band(band)
    n2 = np.real(P.polymul(num, np.conj(num)))
    d2 = np.real(P.polymul(den, np.conj(den)))
    g = P.polysub(P.polymul(P.polyder(n2), d2), P.polymul(n2, P.polyder(d2)))
    value = lambda t: float(np.sqrt(P.polyval(t, n2) / P.polyval(t, d2)))  # noqa: E731
    candidates = _real_roots(g, a, b) + [a, b]
    out = []
    # Neighbours 1e-5 of the band away: on a resonance of half-width >= 1e-3 of the band the
    # function changes there by >= ~1e-4 relative, far above the rounding that 1e-12 allows.
    h = 1e-5 * (b - a)
    values = {t: value(t) for t in sorted(set(candidates))}
    for t, v in values.items():
        left = value(t - h) if t - h >= a else -math.inf
        right = value(t + h) if t + h <= b else -math.inf
        # A flat maximum's neighbours may exceed it by rounding: 1e-12 relative is allowed.
        if v >= (1.0 - 1e-12) * left and v >= (1.0 - 1e-12) * right:
            out.append((t, v))
    top = max(values.items(), key=lambda x: x[1])  # the largest stationary point or end: always a maximum
    if top not in out:
        out.append(top)
    return sorted(out, key=lambda x: -x[1])


def linear_peak(num: np.ndarray, den: np.ndarray, band: tuple[float, float]) -> tuple[float, float]:
    """(theta, value) of the largest |num/den| over ``band`` (see :func:`linear_maxima`)."""
    return linear_maxima(num, den, band)[0]


@dataclass(frozen=True)
class NoContactFloor:
    """The no-contact floor of an impact suppressor over a band (module docstring).

    Attributes
    ----------
    theta, value : float
        Where the largest |x1|/x_st of the motion without contact is, over the part of the band
        where that motion exists (U1 < gap), and its value; (nan, 0.0) where it exists nowhere.
    first_contact : bool
        The largest value is at an end of that part inside the band: where the motion first
        touches the stop (a supremum, reached as the sweep approaches it).
    intervals : tuple of (float, float)
        The parts of the band where the motion without contact exists.
    """

    theta: float
    value: float
    first_contact: bool
    intervals: tuple

    def admissible(self, thetas: Sequence[float]) -> np.ndarray:
        """Whether the motion without contact exists at each theta (inside an interval)."""
        th = np.asarray(thetas, float)
        out = np.zeros(th.shape, bool)
        for a, b in self.intervals:
            out |= (th >= a) & (th <= b)
        return out


def no_contact_floor(p: Parameters, band: tuple[float, float]) -> NoContactFloor:
    """The largest |x1|/x_st of the motion without contact over the part of ``band`` where it
    exists (module docstring), in closed form: the ends of that part are the real roots of
    |theta^2|^2 - gap^2 |D(theta)|^2 (where U1 = gap), the maxima inside it those of
    :func:`linear_maxima`.

    Parameters
    ----------
    p : Parameters
        The suppressor (its theta is not used); gap <= 0 (a stop touched at rest) has no
        motion without contact.
    band : (float, float)
    """
    p = require_parameters(p)
    a, b = check_band(band)
    if not p.gap > 0:
        return NoContactFloor(math.nan, 0.0, False, ())
    dev = LinearDevice.of(p)
    num, den, st = dev.polynomials()
    s2 = np.real(P.polymul(st, np.conj(st)))
    d2 = np.real(P.polymul(den, np.conj(den)))
    f = P.polysub(s2, p.gap**2 * d2)  # < 0 where the motion without contact exists
    edges = [a] + [t for t in _real_roots(f, a, b) if a < t < b] + [b]
    intervals = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        if hi > lo and P.polyval(0.5 * (lo + hi), f) < 0:
            if intervals and intervals[-1][1] == lo:  # (a double root: the two parts join)
                lo = intervals.pop()[0]
            intervals.append((float(lo), float(hi)))
    best = (math.nan, 0.0, False)
    for lo, hi in intervals:
        t, v = linear_peak(num, den, (lo, hi)) if hi - lo > 1e-12 * hi else (lo, float(dev.amplitude([lo])[0]))
        if v > best[1]:
            contact = (t == lo and lo > a) or (t == hi and hi < b)
            best = (float(t), float(v), bool(contact))
    return NoContactFloor(best[0], best[1], best[2], tuple(intervals))
