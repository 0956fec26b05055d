"""Closed-form transition thresholds and amplitudes of the two-mass suppressor.

Where a sweep of the gap Delta0/x_st (Timofeev et al. 2019, Fig. 2) must change regime, some
band edges are known in closed form from the linear theory (eqs. 10-16): the lift-off of the
joined bodies (persistent contact ends), the onset of contact of the free forced response
(eq. 12's U1), the existence range of Algorithm No. 1's one-impact orbit (eq. 16), and, by
bisection on Algorithm No. 1 alone, the gap where that orbit first crosses the stop. The
amplitude with the suppressor rigidly attached is a reference (the object alone is
:meth:`impactdamper.analysis.linear_device.LinearDevice.bare`)
for the suppression figures. A sweep (:mod:`impactdamper.analysis.sweeps`) must bracket these
values; the workflow compares them.
"""

from __future__ import annotations

import math

from impactdamper.core.algorithm1 import algorithm1
from impactdamper.core.linear import forced_amplitudes
from impactdamper.core.parameters import Parameters

__all__ = [
    "stuck_liftoff_gap",
    "no_contact_gap",
    "algorithm1_existence_gap",
    "algorithm1_grazing_gap",
    "rigid_amplitude",
    "liftoff_resolution_offset",
]


def stuck_liftoff_gap(p: Parameters) -> float:
    """Largest Delta0/x_st at which the persistent-contact motion exists (lift-off threshold).

    With the bodies joined (mass m1 + m2 on c1, k1) the periodic response is
    x1(t) = Im(X e^{i w t}), X = P0/(c1 - (m1 + m2) w^2 + i w k1). The suppressor's equation
    m2 x2'' = -c2 (x2 - x1) - k2 (x2' - x1') - F with x2 - x1 = Delta0, x2' = x1' (the damper
    k2 carries no force: the relative velocity is zero) gives the stop's force

        F(t) = -m2 x1''(t) - c2 Delta0 = m2 w^2 Im(X e^{i w t}) - c2 Delta0,

    which stays >= 0 for all t iff Delta0 <= -m2 w^2 |X|/c2. In relative terms, with
    m2/c2 = 1/omega2^2 = 1/(N omega1)^2 and |X|/x_st = 1/|1 - (1 + mu) theta^2 + 2 i delta1 theta|:

        Delta0/x_st <= -(theta/N)^2 / |1 - (1 + mu) theta^2 + 2 i delta1 theta|.

    (k1 enters through x1'' of the joined bodies; delta2 does not enter.)
    """
    return -((p.theta / p.N) ** 2) * rigid_amplitude(p)


def no_contact_gap(p: Parameters) -> float:
    """Delta0/x_st above which the motion without contact exists: U1/x_st.

    Apart, the bodies' forced response has the relative displacement
    x2p - x1p = Im((x2p_hat - x1p_hat) e^{i w t}) (eq. 10), whose maximum is
    U1 = |x2p_hat - x1p_hat| (eq. 12); the gap Delta0 - (x2p - x1p) stays positive iff
    Delta0 > U1.
    """
    x1p, x2p = forced_amplitudes(p)
    return abs(x2p - x1p) / p.x_st


def algorithm1_existence_gap(p: Parameters) -> float:
    """sqrt(U1^2 + U2^2)/x_st: eq. (16) has a solution iff |Delta0| is at most this."""
    a = algorithm1(p.replace(gap=0.0))
    return math.hypot(a.U1, a.U2) / p.x_st


def algorithm1_grazing_gap(p: Parameters, bracket: tuple[float, float], xtol: float = 1e-10) -> float:
    """The gap where Algorithm No. 1's orbit starts to cross the stop between impacts.

    Bisection on "the orbit has a negative-gap interval" (Algorithm1Result.admissible)
    between ``bracket[0]`` (one side) and ``bracket[1]`` (the other), to ``xtol``.

    Raises
    ------
    ValueError
        If admissibility does not change over the bracket.
    """
    a, b = float(bracket[0]), float(bracket[1])

    def ok(g: float) -> bool:
        r = algorithm1(p.replace(gap=g))
        return bool(r.exists and not r.negative_gap_intervals)

    fa, fb = ok(a), ok(b)
    if fa == fb:
        raise ValueError(
            f"`bracket` = {bracket!r} is not allowed: Algorithm No. 1's admissibility is {fa} at both ends"
        )
    while abs(b - a) > xtol:
        m = 0.5 * (a + b)
        if ok(m) == fa:
            a = m
        else:
            b = m
    return 0.5 * (a + b)


def rigid_amplitude(p: Parameters) -> float:
    """max |x1|/x_st with the suppressor rigidly attached (m1 + m2 on c1, k1):
    1/|1 - (1 + mu) theta^2 + 2 i delta1 theta|."""
    return 1.0 / abs(1.0 - (1.0 + p.mu) * p.theta**2 + 2j * p.delta1 * p.theta)


def liftoff_resolution_offset(p: Parameters, gap_tol: float) -> float:
    """How far past the analytic lift-off threshold (:func:`stuck_liftoff_gap`) a simulation
    with grazing resolution ``gap_tol`` keeps the bodies in contact, in Delta0/x_st.

    Past the threshold by eps = (Delta0 - Delta_lift)/x_st, the joined bodies' contact force
    F(t) = m2 w^2 |X| sin(...) - c2 Delta0 dips below zero by c2 eps x_st for a time 2 tau,
    tau^2 = 2 omega2^2 eps/(omega^4 |X|/x_st) (|X|: the joined bodies' forced amplitude,
    eqs. 10-11). Let go, the gap would open with the relative acceleration
    -F (1/m1 + 1/m2) = (1 + mu) omega2^2 eps x_st (1 - t^2/tau^2) and reach, when F is
    positive again, (4/3) (1 + mu) omega2^2 eps tau^2 x_st = C eps^2 x_st with

        C = (8/3) (1 + mu) (N/theta)^4 |1 - (1 + mu) theta^2 + 2 i delta1 theta|

    (leading order in eps). The event solver keeps contact through a dip whose gap stays at
    or below its grazing resolution gap_tol x_st (``EventDrivenSolver._dip_unresolved``), so
    the label stays "stuck" up to eps = sqrt(gap_tol/C).

    Parameters
    ----------
    p : Parameters
        The case (theta, mu, N, delta1 are used).
    gap_tol : float
        The solver's grazing resolution, units of x_st.

    Returns
    -------
    float
        eps = sqrt(gap_tol/C), units of x_st.
    """
    mu, n, theta, delta1 = float(p.mu), float(p.N), float(p.theta), float(p.delta1)
    d = abs(1.0 - (1.0 + mu) * theta**2 + 2j * delta1 * theta)
    c = 8.0 / 3.0 * (1.0 + mu) * (n / theta) ** 4 * d
    return math.sqrt(gap_tol / c)
