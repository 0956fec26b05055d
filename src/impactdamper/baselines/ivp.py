"""An independent cross-check: the same model integrated numerically with ``solve_ivp``.

This module shares nothing with the exact solver (:mod:`impactdamper.core.linear`,
:mod:`impactdamper.core.events`, :mod:`impactdamper.core.model`, :mod:`impactdamper.core.simulate`) but the
parameter set and the result types: the equations of motion are written out again here from
Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100, and integrated by
:func:`scipy.integrate.solve_ivp` with event location. The tests use it to confirm the exact
solver in every regime; the benchmark compares its cost and accuracy with the exact flow.

The model
---------
* **Free** (the bodies apart, gap Delta = Delta0 - (x2 - x1) > 0), eqs. (2) and (9), state
  y = (x1, x2, x1', x2')::

      m1 x1'' = P0 sin(omega t) - k1 x1' - k2 (x1' - x2') - c1 x1 - c2 (x1 - x2)
      m2 x2'' = -k2 (x2' - x1') - c2 (x2 - x1)

* **Stuck** (persistent contact, x2 = x1 + Delta0), state y = (x1, x1')::

      (m1 + m2) x1'' + k1 x1' + c1 x1 = P0 sin(omega t),
      F = -m2 x1'' - c2 Delta0   (the stop's force on the bodies, >= 0 while stuck).

* **Impact** (the gap reaches zero while closing), eqs. (21)-(22): with the closing velocity
  v = x2' - x1' and S = m1 m2/(m1 + m2) (1 + R) v, x1' += S/m1 and x2' -= S/m2.
* **Chatter capture** (the same physical rule as the exact solver): after an impact, let F be
  the stuck-mode contact force at the centre-of-mass velocity and a = F/m_red the relative
  acceleration it means. If F > 0 and the rebound's apex (R v)^2/(2 a) is at most
  ``chatter_tol * x_st``, the bodies are captured into the stuck mode (both take the
  centre-of-mass velocity, a "stick" event). R = 0 impacts therefore stick if F > 0 and
  separate otherwise.
* **Lift-off**: the stuck mode ends where F falls through zero.

How the integration is restarted
--------------------------------
The motion is integrated in legs, one mode each; every leg is a fresh ``solve_ivp`` call
from the state after the last event, and ends at the first terminal event or at ``t_end``.

* Free legs stop at the event g(t, y) = Delta(t) + ``gap_tol * x_st`` = 0 with
  ``direction = -1``. A leg that leaves the stop starts with Delta = 0 exactly (the state is
  projected onto the stop), so g = ``gap_tol * x_st`` > 0 there: the impact just handled (or
  the lift-off point, where the gap opens only like s^3) is *not* a root of the new leg's
  event function, however the first step's rounding falls. The next impact is located where
  the gap falls ``gap_tol * x_st`` below zero (a shift of that size, far below what the
  integrator resolves at rtol = 1e-10), and the state is projected back onto the stop.
* Stuck legs stop at F = 0 with ``direction = -1``; they start with F > 0 (the capture rule
  demands it), so the start is not a root either.
* ``solve_ivp`` only sees sign changes at step ends, so a dip of the event function below zero
  and back inside one step would be lost (a grazing impact). Each leg therefore also records,
  as a non-terminal event, every minimum of its event function (the roots of its derivative
  Delta' = x1' - x2', or F'); if a recorded minimum lies below zero, the leg is integrated
  again up to that minimum with dense output and the missed crossing is found by ``brentq``
  in the step that holds it.

This gives a cross-check, not a certificate: a minimum and a maximum of the gap both inside
one step would still go unseen, and the event times carry the integrator's error. The grazing
resolution differs slightly from the exact solver's by design (it counts a touch when the gap's
minimum is at most +gap_tol x_st, this module when it is below -gap_tol x_st): the two can
disagree only about minima within gap_tol x_st (1e-12 x_st by default) of the stop.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.integrate
import scipy.optimize

from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import Tolerances, default_initial_state
from impactdamper.core.trajectory import Event

__all__ = ["simulate_ivp", "METHODS", "methods"]

METHODS = ("RK45", "DOP853", "Radau", "LSODA")
"""The ``solve_ivp`` methods the cross-check supports (all tested)."""
methods = METHODS

FREE = "free"
STUCK = "stuck"
# Events at one instant beyond which the contact is degenerate (a guard against loops).
MAX_EVENTS_AT_ONE_TIME = 50
# solve_ivp warns (and the strict test suite fails) below rtol = 100 eps.
MIN_RTOL = 100 * np.finfo(float).eps


@dataclass
class _IvpLeg:
    """One ``solve_ivp`` call: a mode from (t0, y0) to t1.

    Attributes
    ----------
    mode : str
        ``"free"`` (y = x1, x2, x1', x2') or ``"stuck"`` (y = x1, x1').
    t0, t1 : float
        Start and end, s.
    y0 : ndarray, shape (4,) or (2,)
        State at t0.
    nfev : int
        Right-hand-side evaluations of this leg.
    sol : OdeSolution or None
        Dense output, computed on demand by :meth:`IvpTrajectory.sample`.
    """

    mode: str
    t0: float
    y0: np.ndarray
    t1: float
    nfev: int
    sol: object = None


class Equations:
    """The two modes' right-hand sides, Jacobians and event functions (written from eqs. 2, 9)."""

    def __init__(self, p: Parameters):
        self.p = p
        m1, m2, c1, c2, k1, k2 = p.m1, p.m2, p.c1, p.c2, p.k1, p.k2
        self.m = m1 + m2
        self.m_red = m1 * m2 / (m1 + m2)
        self.J_free = np.array(
            [
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
                [-(c1 + c2) / m1, c2 / m1, -(k1 + k2) / m1, k2 / m1],
                [c2 / m2, -c2 / m2, k2 / m2, -k2 / m2],
            ]
        )
        self.J_stuck = np.array([[0.0, 1.0], [-c1 / self.m, -k1 / self.m]])

    # --- free mode: eqs. (2) + (9) -----------------------------------------------------
    def free_rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        p = self.p
        x1, x2, v1, v2 = y
        a1 = (p.P0 * math.sin(p.omega * t) - p.k1 * v1 - p.k2 * (v1 - v2) - p.c1 * x1 - p.c2 * (x1 - x2)) / p.m1
        a2 = (-p.k2 * (v2 - v1) - p.c2 * (x2 - x1)) / p.m2
        return np.array([v1, v2, a1, a2])

    def free_jac(self, t: float, y: np.ndarray) -> np.ndarray:
        return self.J_free

    def gap(self, y: np.ndarray) -> float:
        return self.p.Delta0 - (y[1] - y[0])

    # --- stuck mode: the joined bodies on c1, k1 ----------------------------------------
    def stuck_acc(self, t: float, x1: float, v1: float) -> float:
        p = self.p
        return (p.P0 * math.sin(p.omega * t) - p.k1 * v1 - p.c1 * x1) / self.m

    def stuck_rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        return np.array([y[1], self.stuck_acc(t, y[0], y[1])])

    def stuck_jac(self, t: float, y: np.ndarray) -> np.ndarray:
        return self.J_stuck

    def force(self, t: float, x1: float, v1: float) -> float:
        """Contact force F = -m2 x1'' - c2 Delta0 of the joined bodies, N."""
        return -self.p.m2 * self.stuck_acc(t, x1, v1) - self.p.c2 * self.p.Delta0

    def force_rate(self, t: float, x1: float, v1: float) -> float:
        """dF/dt = -m2 x1''' with (m1 + m2) x1''' = P0 omega cos(omega t) - k1 x1'' - c1 x1'."""
        p = self.p
        a = self.stuck_acc(t, x1, v1)
        return -p.m2 * (p.P0 * p.omega * math.cos(p.omega * t) - p.k1 * a - p.c1 * v1) / self.m

    def full(self, mode: str, y: np.ndarray) -> np.ndarray:
        """(x1, x2, x1', x2') from a state of either mode, shape (..., 4): ``Model.full_state``
        written again, as the whole model is here (the cross-check uses nothing of the exact
        solver's model)."""
        y = np.asarray(y, dtype=float)
        if mode == FREE:
            return y
        x1, v1 = y[..., 0], y[..., 1]
        return np.stack([x1, x1 + self.p.Delta0, v1, v1], axis=-1)


def _event(fn, terminal: bool, direction: float):
    fn.terminal = terminal
    fn.direction = direction
    return fn


class _IvpTrajectory:
    """The motion integrated by ``solve_ivp``: legs of one mode each, and the events.

    Attributes
    ----------
    p : Parameters
    legs : list of IvpLeg
    events : list of impactdamper.core.trajectory.Event
        Same kinds and meaning as the exact solver's (impact, stick, liftoff).
    nfev : int
        Right-hand-side evaluations over all legs (dense output for :meth:`sample` excluded).
    method : str
    rtol, atol : float

    sample_times, samples, sample_modes : ndarray
        The states (x1, x2, x1', x2') and mode names at the ``sample_times`` given to
        :func:`simulate_ivp` (empty if none), read from each step's interpolant while the legs
        were integrated; at an event time, the state after the event.

    Notes
    -----
    The legs are integrated without dense output (the cheapest form, the one the benchmark
    times). :meth:`sample` integrates a leg again with dense output the first time it needs it:
    same method and tolerances, hence the same steps, the last one clipped at the leg's end.
    Times known before the run are cheaper as ``sample_times`` (no second integration).
    """

    def __init__(self, p: Parameters, eq: Equations, method: str, rtol: float, atol: float):
        self.p = p
        self._eq = eq
        self.method = method
        self.rtol = rtol
        self.atol = atol
        self.legs: list[_IvpLeg] = []
        self.events: list[Event] = []
        self.sample_times = np.empty(0)
        self.samples = np.empty((0, 4))
        self.sample_modes = np.empty(0, dtype=object)

    @property
    def nfev(self) -> int:
        return sum(leg.nfev for leg in self.legs)

    def impacts(self, t_from: float = -math.inf, t_to: float = math.inf) -> list[Event]:
        return [e for e in self.events if e.kind == "impact" and t_from <= e.t < t_to]

    def _dense(self, leg: _IvpLeg):
        if leg.sol is None:
            if leg.t1 > leg.t0:
                # Same method and tolerances as the leg: the same steps (the last one clipped
                # at the leg's end), now with their interpolants.
                res = _solve(
                    self._eq,
                    leg.mode,
                    leg.t0,
                    leg.t1,
                    leg.y0,
                    self.method,
                    self.rtol,
                    self.atol,
                    events=None,
                    dense_output=True,
                )
                leg.sol = res.sol
            else:
                y0 = leg.y0
                leg.sol = lambda t, y0=y0: np.repeat(y0[:, None], np.size(t), axis=1)
        return leg.sol

    def sample(self, t: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """Full states (x1, x2, x1', x2') at times t, shape t.shape + (4,), and the mode
        names, shape t.shape. At an event time the state after the event is returned."""
        t = np.asarray(t, dtype=float)
        flat = t.reshape(-1)
        if flat.size and (flat.min() < self.legs[0].t0 or flat.max() > self.legs[-1].t1):
            raise ValueError(f"`t` must lie in [{self.legs[0].t0!r}, {self.legs[-1].t1!r}]")
        starts = np.array([leg.t0 for leg in self.legs])
        idx = np.clip(np.searchsorted(starts, flat, side="right") - 1, 0, len(self.legs) - 1)
        out = np.empty((flat.size, 4))
        modes = np.empty(flat.size, dtype=object)
        for k in np.unique(idx):
            sel = idx == k
            leg = self.legs[k]
            y = np.asarray(self._dense(leg)(flat[sel]))  # shape (n, m)
            out[sel] = self._eq.full(leg.mode, y.T)
            modes[sel] = leg.mode
        return out.reshape(t.shape + (4,)), modes.reshape(t.shape)


def _solve(
    eq: Equations,
    mode: str,
    t0: float,
    t1: float,
    y0: np.ndarray,
    method: str,
    rtol: float,
    atol: float,
    events,
    dense_output: bool,
    t_eval: np.ndarray | None = None,
):
    fun, jac = (eq.free_rhs, eq.free_jac) if mode == FREE else (eq.stuck_rhs, eq.stuck_jac)
    options = {"jac": jac} if method in ("Radau", "LSODA") else {}
    if t_eval is not None:  # (read off each step's interpolant; the steps are the same without)
        options["t_eval"] = t_eval
    res = scipy.integrate.solve_ivp(
        fun, (t0, t1), y0, method=method, rtol=rtol, atol=atol, events=events, dense_output=dense_output, **options
    )
    if res.status < 0:
        raise RuntimeError(f"solve_ivp ({method}) failed on [{t0!r}, {t1!r}]: {res.message}")
    return res


class _Driver:
    """The event loop: leg -> event -> impact law / capture / lift-off -> next leg."""

    def __init__(self, p, t0, state, method, rtol, atol, tol: Tolerances, max_events, sample_times=None):
        self.p = p
        self.eq = Equations(p)
        self.method, self.rtol, self.atol = method, rtol, atol
        self.tol = tol
        self.max_events = max_events
        self.traj = _IvpTrajectory(p, self.eq, method, rtol, atol)
        times = np.empty(0) if sample_times is None else np.asarray(sample_times, dtype=float)
        self.traj.sample_times = times
        self.traj.samples = np.full((times.size, 4), np.nan)
        self.traj.sample_modes = np.empty(times.size, dtype=object)
        self.gap_offset = tol.gap_tol * p.x_st
        self._same_time = 0
        self.pending: tuple[str, float, np.ndarray] | None = None
        eq = self.eq
        gap = eq.gap(state)
        if gap < -self.gap_offset:
            raise ValueError(f"`state` has gap Delta0 - (x2 - x1) = {gap:.6g} m < 0: the bodies would overlap")
        if gap <= self.gap_offset:
            full = np.array(state, dtype=float)
            full[1] = full[0] + p.Delta0
            if full[3] - full[2] > 0.0:
                self._impact(t0, full)
            else:
                self._leave_contact(t0, full, rebound=float(full[2] - full[3]))
        else:
            self.pending = (FREE, t0, np.array(state, dtype=float))

    # --- events ---------------------------------------------------------------------------
    def _record(self, event: Event) -> None:
        events = self.traj.events
        if events and event.t - events[-1].t <= 4 * math.ulp(max(abs(event.t), 1.0)):
            self._same_time += 1
            if self._same_time > MAX_EVENTS_AT_ONE_TIME:
                raise RuntimeError(f"more than {MAX_EVENTS_AT_ONE_TIME} events at t = {event.t!r}: degenerate contact")
        else:
            self._same_time = 0
        if len(events) >= self.max_events:
            raise RuntimeError(f"more than `max_events` = {self.max_events} events before t = {event.t!r}")
        events.append(event)

    def _impact(self, t: float, full: np.ndarray) -> None:
        p = self.p
        v = max(float(full[3] - full[2]), 0.0)  # closing velocity, eq. (21)
        S = self.eq.m_red * (1.0 + p.R) * v
        after = full.copy()
        after[2] += S / p.m1  # eq. (22)
        after[3] -= S / p.m2
        self._record(Event(t, "impact", v, S, full, after, t))
        self._leave_contact(t, after, rebound=p.R * v)

    def _leave_contact(self, t: float, full: np.ndarray, rebound: float) -> None:
        p, eq = self.p, self.eq
        v_cm = (p.m1 * full[2] + p.m2 * full[3]) / (p.m1 + p.m2)
        F = eq.force(t, full[0], v_cm)
        a = F / eq.m_red
        if F > 0.0 and rebound * rebound <= 2.0 * a * self.tol.chatter_tol * p.x_st:
            stuck = np.array([full[0], v_cm])
            t_inf = t + (2.0 * rebound / ((1.0 - p.R) * a) if p.R < 1.0 else 0.0)
            self._record(Event(t, "stick", 0.0, p.m1 * (v_cm - full[2]), full, eq.full(STUCK, stuck), t_inf))
            self.pending = (STUCK, t, stuck)
        else:
            self.pending = (FREE, t, full)

    # --- legs -----------------------------------------------------------------------------
    def _guards(self, mode: str):
        eq = self.eq
        if mode == FREE:
            off = self.gap_offset
            guard = _event(lambda t, y: eq.p.Delta0 - (y[1] - y[0]) + off, True, -1.0)
            rate = _event(lambda t, y: y[2] - y[3], False, 1.0)  # Delta' = x1' - x2'
        else:
            guard = _event(lambda t, y: eq.force(t, y[0], y[1]), True, -1.0)
            rate = _event(lambda t, y: eq.force_rate(t, y[0], y[1]), False, 1.0)
        return guard, rate

    def run(self, t_end: float) -> _IvpTrajectory:
        while self.pending is not None:
            mode, t0, y0 = self.pending
            self.pending = None
            if t0 >= t_end:
                self.traj.legs.append(_IvpLeg(mode, t0, y0, t0, 0))
                break
            guard, rate = self._guards(mode)
            times = self.traj.sample_times
            lo, hi = np.searchsorted(times, t0, side="left"), np.searchsorted(times, t_end, side="right")
            res = _solve(
                self.eq,
                mode,
                t0,
                t_end,
                y0,
                self.method,
                self.rtol,
                self.atol,
                events=[guard, rate],
                dense_output=False,
                t_eval=times[lo:hi] if hi > lo else None,
            )
            # (the leg ends at its terminal event or at t_end; with t_eval, res.t holds the samples)
            t1 = float(res.t_events[0][0]) if res.status == 1 else t_end
            leg = _IvpLeg(mode, t0, y0, t1, int(res.nfev))
            self.traj.legs.append(leg)
            t_hit, y_hit = None, None
            if res.status == 1:
                t_hit, y_hit = float(res.t_events[0][0]), res.y_events[0][0]
            # A minimum of the event function below zero means a crossing inside one step.
            for tm, ym in zip(res.t_events[1], res.y_events[1]):
                if (t_hit is None or tm < t_hit) and guard(tm, ym) < 0.0:
                    t_hit, y_hit, extra = self._missed_crossing(mode, t0, y0, float(tm), guard)
                    leg.nfev += extra
                    break
            if hi > lo:  # samples up to the leg's end; a later leg's overwrite one at its start
                ts = np.asarray(res.t, dtype=float).reshape(-1)  # (a list when none was reached)
                ys = np.asarray(res.y, dtype=float).reshape(len(y0), ts.size)
                keep = ts <= (t_hit if t_hit is not None else t_end)
                at = lo + np.searchsorted(times[lo:hi], ts[keep])
                self.traj.samples[at] = self.eq.full(mode, ys[:, keep].T)
                self.traj.sample_modes[at] = mode
            if t_hit is None:
                break
            leg.t1 = t_hit
            leg.sol = None
            if mode == FREE:
                full = np.array(y_hit, dtype=float)
                full[1] = full[0] + self.p.Delta0  # onto the stop (removes the gap_tol shift)
                self._impact(t_hit, full)
            else:
                full = self.eq.full(STUCK, np.asarray(y_hit, dtype=float))
                self._record(Event(t_hit, "liftoff", 0.0, 0.0, full, full.copy(), t_hit))
                self.pending = (FREE, t_hit, full.copy())
        return self.traj

    def _missed_crossing(self, mode, t0, y0, t_min, guard):
        """Integrate again to the minimum t_min with dense output; the crossing lies in the
        last step (every earlier step end had guard >= 0, or the event would have fired)."""
        res = _solve(self.eq, mode, t0, t_min, y0, self.method, self.rtol, self.atol, events=None, dense_output=True)
        ts = res.t
        g = np.array([guard(t, res.y[:, i]) for i, t in enumerate(ts)])
        k = int(np.flatnonzero(g < 0.0)[0])
        lo = ts[max(k - 1, 0)]
        t_root = scipy.optimize.brentq(
            lambda t: guard(t, res.sol(t)), lo, ts[k], xtol=4 * np.finfo(float).eps, rtol=4 * np.finfo(float).eps
        )
        return float(t_root), res.sol(t_root), int(res.nfev)


def _positive(name: str, value, upper: float | None = None, lower: float = 0.0) -> float:
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > lower
    if ok and upper is not None:
        ok = value < upper
    if not ok:
        allowed = f"a finite number > {lower:.3g}" + (f" and < {upper:g}" if upper is not None else "")
        raise ValueError(f"`{name}` = {value!r} is not allowed: must be {allowed}")
    return float(value)


def simulate_ivp(
    p: Parameters,
    t_end: float,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float = 1e-10,
    tolerances: Tolerances | None = None,
    max_events: int = 1_000_000,
    sample_times: np.ndarray | None = None,
) -> _IvpTrajectory:
    """Integrate the suppressor with ``solve_ivp`` and event location from ``t0`` to ``t_end``.

    Parameters
    ----------
    p : Parameters
    t_end : float
        End time, s (> t0).
    t0 : float
        Start time, s (the forcing is P0 sin(omega t) in absolute time).
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0 in m, m/s; default the paper's step 1
        (:func:`impactdamper.core.simulate.default_initial_state`). Gap must be >= -gap_tol x_st;
        on the stop it closes (impact first), opens, or is captured into contact.
    method : {"RK45", "DOP853", "Radau", "LSODA"}
        ``solve_ivp`` method (Radau and LSODA get the constant Jacobian).
    rtol, atol : float
        ``solve_ivp`` tolerances (atol in the state's units, m and m/s).
    tolerances : Tolerances, optional
        ``gap_tol`` (event shift, relative to x_st) and ``chatter_tol`` (capture rule), as in
        the exact solver.
    max_events : int
        Guard: more events than this raise RuntimeError.
    sample_times : array of float, optional
        Increasing times in [t0, t_end] whose states the run records as it goes
        (``IvpTrajectory.samples``), from the steps' interpolants.

    Returns
    -------
    IvpTrajectory
    """
    if not isinstance(p, Parameters):
        raise ValueError(f"`p` = {p!r} is not allowed: must be an impactdamper.Parameters")
    t0 = float(t0) if isinstance(t0, (int, float)) and not isinstance(t0, bool) else t0
    if not (isinstance(t0, float) and math.isfinite(t0)):
        raise ValueError(f"`t0` = {t0!r} is not allowed: must be a finite number")
    if not (isinstance(t_end, (int, float)) and not isinstance(t_end, bool) and math.isfinite(t_end) and t_end > t0):
        raise ValueError(f"`t_end` = {t_end!r} is not allowed: must be finite and > t0 = {t0!r}")
    if method not in METHODS:
        raise ValueError(f"`method` = {method!r} is not allowed: must be one of {', '.join(METHODS)}")
    rtol = _positive("rtol", rtol, lower=MIN_RTOL, upper=1.0)
    atol = _positive("atol", atol)
    if tolerances is None:
        tolerances = Tolerances()
    elif not isinstance(tolerances, Tolerances):
        raise ValueError(f"`tolerances` = {tolerances!r} is not allowed: must be an impactdamper.Tolerances")
    if not (isinstance(max_events, int) and not isinstance(max_events, bool) and max_events >= 1):
        raise ValueError(f"`max_events` = {max_events!r} is not allowed: must be an integer >= 1")
    if state is None:
        full = default_initial_state(p)
    else:
        try:
            full = np.asarray(state, dtype=float)
        except (TypeError, ValueError):
            full = None
        if full is None or full.shape != (4,) or not np.all(np.isfinite(full)):
            raise ValueError(f"`state` = {state!r} is not allowed: must be 4 finite numbers (x1, x2, x1', x2')")
    if sample_times is not None:
        sample_times = np.asarray(sample_times, dtype=float).reshape(-1)
        if not (
            np.all(np.isfinite(sample_times))
            and np.all(np.diff(sample_times) > 0.0)
            and (sample_times.size == 0 or (sample_times[0] >= t0 and sample_times[-1] <= t_end))
        ):
            raise ValueError(
                f"`sample_times` is not allowed: must be increasing finite times in [t0, t_end] = [{t0!r}, {t_end!r}]"
            )
    driver = _Driver(p, t0, np.array(full, dtype=float), method, rtol, atol, tolerances, max_events, sample_times)
    return driver.run(float(t_end))
