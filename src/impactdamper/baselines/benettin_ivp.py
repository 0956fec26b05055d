"""An independent largest Lyapunov exponent: Benettin's two-trajectory estimate on solve_ivp.

The check of :mod:`impactdamper.analysis.lyapunov` (the tangent walk: exact transition
matrices, saltation matrices, QR) that shares no flow, event or model code with it, nor with
any other part of the library: nothing of :mod:`impactdamper` is imported here. The equations
are written out again from Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100, from
the paper's relative parameters (this module converts them itself):

* between impacts, eqs. (2) and (9), state y = (x1, x2, x1', x2')::

      m1 x1'' + k1 x1' + k2 (x1' - x2') + c1 x1 + c2 (x1 - x2) = P0 sin(omega t)
      m2 x2'' + k2 (x2' - x1') + c2 (x2 - x1) = 0

  integrated by :func:`scipy.integrate.solve_ivp` (DOP853, ``RTOL``, ``ATOL``);
* an impact where the gap Delta0 - (x2 - x1), eq. (20), falls through zero (located by
  solve_ivp's event root finder), the pulse of eqs. (21)-(22): with the closing velocity
  v = x2' - x1', S = m1 m2 / (m1 + m2) (1 + R) v, x1' += S / m1, x2' -= S / m2;
* the start: a state given by the caller (4 numbers, e.g. a section of the motion the tangent
  walk followed: Algorithm No. 2's step 1 itself chatters into persistent contact at negative
  gaps, which this module does not model), then a transient of its own.

Persistent contact is not modelled: a run whose impacts accumulate (more than ``MAX_IMPACTS``
in a period, or a closing velocity under ``MIN_CLOSING`` x_st omega) stops with an error, so
the estimate is made only at a point whose motion does not capture (gap -16: none in the
tangent walk's 2000 periods).

Benettin et al. (1980): a second trajectory starts ``SEPARATION`` (relative to x_st and
x_st omega) from the first; both run one forcing period; the log of their distance's growth
is that period's sample; the second is put back at ``SEPARATION`` along the new direction.
The exponent is the plain mean of the samples, per forcing period; its error the standard
error of the means of ``blocks`` blocks.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["ATOL", "RTOL", "SEPARATION", "physical", "benettin_ivp"]

# solve_ivp's tolerances, on the state in x_st and x_st omega (its atol scaled per component):
# the motion's own error per period is ~1e-12 x_st, 1e-5 of SEPARATION.
RTOL = 1e-12
ATOL = 1e-12
# The two trajectories' distance, relative: the map's curvature adds ~SEPARATION to each
# period's log, the integration error ~1e-12 / SEPARATION = 1e-5 (both far below the error).
SEPARATION = 1e-7
MAX_IMPACTS = 1000
MIN_CLOSING = 1e-9
FIRST_STEP = 1e-6


def physical(theta, mu, N, delta1, delta2, R, gap, omega=10.0, x_st=1.0, m1=1.0) -> dict:
    """The dimensional constants of the relative parameters (the paper's "relative values"):
    omega1 = omega / theta, c1 = m1 omega1^2, P0 = c1 x_st, m2 = mu m1, c2 = m2 (N omega1)^2,
    k1 = 2 m1 omega1 delta1, k2 = 2 m2 omega1 delta2, Delta0 = gap x_st."""
    w1 = omega / theta
    m2 = mu * m1
    c1 = m1 * w1 * w1
    return {
        "m1": m1,
        "m2": m2,
        "c1": c1,
        "c2": m2 * (N * w1) ** 2,
        "k1": 2.0 * m1 * w1 * delta1,
        "k2": 2.0 * m2 * w1 * delta2,
        "P0": c1 * x_st,
        "omega": omega,
        "R": R,
        "Delta0": gap * x_st,
        "x_st": x_st,
    }


class _ImpactOscillator:
    """The two bodies and the stop of one parameter set (:func:`physical`'s constants)."""

    def __init__(self, c: dict):
        self.c = c
        self.T = 2.0 * math.pi / c["omega"]
        self.scale = np.array([c["x_st"], c["x_st"], c["x_st"] * c["omega"], c["x_st"] * c["omega"]])
        self.impacts = 0

        def gap(t, y):
            return c["Delta0"] - (y[1] - y[0])

        gap.terminal, gap.direction = True, -1.0
        self._gap = gap

    def rhs(self, t, y):
        """The accelerations of eqs. (2) + (9) with the bodies apart."""
        c = self.c
        x1, x2, v1, v2 = y
        spring, damper = c["c2"] * (x1 - x2), c["k2"] * (v1 - v2)
        force = c["P0"] * math.sin(c["omega"] * t)
        a1 = (force - c["k1"] * v1 - c["c1"] * x1 - spring - damper) / c["m1"]
        a2 = (spring + damper) / c["m2"]
        return [v1, v2, a1, a2]

    def strike(self, y) -> np.ndarray:
        """The state just after an impact, eqs. (21)-(22), the suppressor put on the stop."""
        c = self.c
        closing = y[3] - y[2]
        if closing < MIN_CLOSING * self.scale[2]:
            raise RuntimeError(f"closing velocity {closing:.3g} at an impact: a capture, not modelled here")
        S = c["m1"] * c["m2"] / (c["m1"] + c["m2"]) * (1.0 + c["R"]) * closing
        return np.array([y[0], y[0] + c["Delta0"], y[2] + S / c["m1"], y[3] - S / c["m2"]])

    def advance(self, t0: float, y0: np.ndarray, t1: float) -> np.ndarray:
        """The state at t1 from y0 at t0, through every impact on the way."""
        t, y, count = t0, np.asarray(y0, float), 0
        atol = ATOL * self.scale
        while t < t1:
            # A small first step, so that a short rebound's flight is not stepped over (its
            # landing would be found at the start of the step, the impact's own time).
            sol = solve_ivp(
                self.rhs,
                (t, t1),
                y,
                method="DOP853",
                rtol=RTOL,
                atol=atol,
                events=self._gap,
                first_step=FIRST_STEP * self.T,
            )
            if sol.status < 0:
                raise RuntimeError(f"solve_ivp failed at t = {t:.6g}: {sol.message}")
            if sol.status == 0:
                return sol.y[:, -1]
            if not sol.t_events[0][0] > t:
                raise RuntimeError(f"an impact at its predecessor's time t = {t:.6g}: chatter, not modelled here")
            t, y = float(sol.t_events[0][0]), self.strike(sol.y_events[0][0])
            count += 1
            self.impacts += 1
            if count > MAX_IMPACTS:
                raise RuntimeError(f"more than {MAX_IMPACTS} impacts between t = {t0:.6g} and {t1:.6g}")
        return y


def benettin_ivp(
    theta, mu, N, delta1, delta2, R, gap, start, *, transient: int, periods: int, blocks: int = 10, omega=10.0
) -> dict:
    """Benettin's largest exponent per forcing period at one parameter set (relative values):
    from ``start`` (x1/x_st, x2/x_st, x1'/(x_st omega), x2'/(x_st omega)) at the forcing's
    phase 0, ``transient`` periods, then ``periods`` periods of the two trajectories.

    Returns a dict: exponent, error (block standard error), blocks, periods, transient,
    separation, impacts_per_period, rtol, atol, method."""
    if periods % blocks or blocks < 2:
        raise ValueError(f"`periods` = {periods!r} is not allowed: must be a multiple of `blocks` = {blocks!r} >= 2")
    osc = _ImpactOscillator(physical(theta, mu, N, delta1, delta2, R, gap, omega=omega))
    c, T = osc.c, osc.T
    y = osc.advance(0.0, np.asarray(start, float) * osc.scale, transient * T)
    direction = np.ones(4) / 2.0
    logs = np.empty(periods)
    osc.impacts = 0
    for n in range(periods):
        t = (transient + n) * T
        twin = y + SEPARATION * direction * osc.scale
        if c["Delta0"] - (twin[1] - twin[0]) < 0.0:  # (the twin inside the stop: mirror it)
            twin = y - SEPARATION * direction * osc.scale
        y_next = osc.advance(t, y, t + T)
        apart = (osc.advance(t, twin, t + T) - y_next) / osc.scale
        distance = float(np.linalg.norm(apart))
        logs[n] = math.log(distance / SEPARATION)
        direction, y = apart / distance, y_next
    means = logs.reshape(blocks, -1).mean(axis=1)
    return {
        "exponent": float(logs.mean()),
        "error": float(means.std(ddof=1) / math.sqrt(blocks)),
        "blocks": blocks,
        "periods": periods,
        "transient": transient,
        "separation": SEPARATION,
        "impacts_per_period": osc.impacts / (2 * periods),
        "rtol": RTOL,
        "atol": ATOL,
        "method": "Benettin two-trajectory estimate, scipy solve_ivp DOP853 with event location (no library code)",
    }
