"""Algorithm No. 2 of Timofeev et al. (2019), event after event with the exact flow,
extended with persistent contact (stick), lift-off and grazing.

The loop (eqs. 18-22): from the state after an event, the motion is the exact flow of the
current mode (eq. 18 with alpha_j from eq. 19, see :mod:`impactdamper.core.linear`); the next event
is the first root of the gap (eq. 20) or, in contact, of the contact force, found by
:func:`impactdamper.core.events.march`, which never skips a root; at an impact the pulse of
eq. (21) updates the velocities, eq. (22), and the flow restarts. What a run records, its
events and the stitched trajectory, is :mod:`impactdamper.core.trajectory`.

What the paper leaves out, decided here:

* **Chatter into contact.** With R < 1 and the bodies pressed together (the contact force F
  of the stuck mode positive), the impacts accumulate: closing velocities fall by R each
  bounce and infinitely many impacts happen before the accumulation time
  t_inf ~ t_k + 2 R v_k / ((1 - R) a), a = F/m_red (Budd & Dux 1994). Once the rebound's
  height h = (R v_k)^2 / (2 a) is below ``chatter_tol * x_st`` while F > 0, the rest of the
  sequence is replaced by its limit: a plastic capture into the stuck mode. The bounces left
  out move the bodies apart by at most h for a time O(sqrt(h/a)); the centre of mass is
  untouched (impacts conserve momentum), so the state error is far below h.
  ``chatter_tol`` sits well above ``gap_tol`` so that every bounce kept is resolved.
* **Plastic impacts (R = 0)** stick if F > 0 and separate otherwise.
* **Lift-off**: the stuck mode ends where F falls through zero; the gap then opens like
  s^3 (Delta = Delta' = Delta'' = 0 there), which the event search's departure order handles.
* **Grazing**: a gap minimum at or below ``gap_tol * x_st`` counts as a touch (an impact with
  near-zero velocity); one above it is a near miss and is not counted.
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper.core.constants import CURVATURE_FLOOR, DEPARTURE_FLOOR, DEPARTURE_ULPS, REBOUND_FLOOR, SAME_TIME_ULPS
from impactdamper.core.constants import STEPS_AT_START, STEPS_PER_PERIOD  # (the work bound)
from impactdamper.core import impact_law
from impactdamper.core.events import LinearFunctional, SearchLimitError, Segment, StepBudget, march
from impactdamper.core.model import FREE, STUCK, model_of
from impactdamper.core.parameters import NATIVE_SCALES, Parameters, ScaleMap, require_parameters
from impactdamper.core.trajectory import Event, Trajectory, rescale_trajectory

from impactdamper.core.validation import (
    Tolerances,
    check_run_call,
    check_start_time,
    check_state,
    check_tolerances,
    work_bound_message,
)

__all__ = [
    "EventDrivenSolver",
    "simulate",
    "simulate_checked",
    "default_initial_state",
    "Tolerances",
    "Event",  # (the run's result types, from core/trajectory.py)
    "Trajectory",
    "budget_exceeded",
    "degenerate_contact",
]

# The paper's step 1 example pulse, 1 N s with m1 = 1 kg in the reference case
# (m1 omega1 x_st = 10 N s there), written relative to m1 omega1 x_st so that relative
# results do not depend on the free mass scale m1.
DEFAULT_KICK = 0.1
# Consecutive events at one instant beyond which the model is degenerate (a guard).
MAX_EVENTS_AT_ONE_TIME = 50
# Samples of the gap over a contact-force dip when judging whether the bodies part by a
# resolvable amount (the gap there is a smooth bump).
DIP_SAMPLES = 33
# Default bound on a simulation's length in forcing periods (simulate's max_periods): the
# pure-Python solver advances ~6000 periods a second at the reference case, so a default call
# ends within ~20 s (6e5 periods took 100 s); a longer run must ask for it with max_periods.
MAX_SIMULATE_PERIODS = 100_000


def budget_exceeded(used: float, periods: float) -> str:
    """What a run that spent its step budget says (both backends): the bound, the steps used and
    how far into the run (in forcing periods)."""
    return (
        f"the event search reached its work bound, {STEPS_AT_START} + {STEPS_PER_PERIOD} certified steps per "
        f"forcing period ({int(used)} steps {periods:.3g} periods into the run)"
    )


def degenerate_contact(t: float) -> str:
    """What a run with more than MAX_EVENTS_AT_ONE_TIME events at one instant says."""
    return f"more than {MAX_EVENTS_AT_ONE_TIME} events at t = {t!r}: degenerate contact"


def default_initial_state(p: Parameters) -> np.ndarray:
    """Algorithm No. 2, step 1: x1 = 0, x2 = Delta0 (gap zero), and equal and opposite
    momenta that open the gap (see NOTES: x2' < 0 so that x2 - x1 decreases)."""
    S0 = DEFAULT_KICK * p.m1 * p.omega1 * p.x_st
    return np.array([0.0, p.Delta0, S0 / p.m1, -S0 / p.m2])


class EventDrivenSolver:
    """Advances the suppressor's motion event by event (Algorithm No. 2 with contact modes).

    Parameters
    ----------
    p : Parameters
    t0 : float
        Start time, s (the forcing is P0 sin(omega t) in this absolute time).
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0; default :func:`default_initial_state`. Must have a
        non-negative gap. At zero gap it may close (an impact comes first), open, or rest
        with the bodies pressed together (persistent contact).
    tolerances : Tolerances, optional
    """

    def __init__(
        self, p: Parameters, t0: float = 0.0, state: np.ndarray | None = None, tolerances: Tolerances | None = None
    ):
        p = require_parameters(p)
        t0 = check_start_time(t0, p)
        if not p.native_scales():
            name = next(n for n, (lo, hi) in NATIVE_SCALES.items() if not lo <= getattr(p, n) <= hi)
            lo, hi = NATIVE_SCALES[name]
            raise ValueError(
                f"`{name}` = {getattr(p, name)!r} is not allowed here: the event-driven solver works in the "
                f"given units, where {name} must be in [{lo:g}, {hi:g}]; simulate, steady_state and "
                "solve_orbit rescale such cases (relative results do not depend on x_st, m1, omega)"
            )
        self.p = p
        self.tol = check_tolerances(tolerances)
        full = check_state(state, p)
        self.model = model_of(p)
        self.trajectory = Trajectory(self.model)
        self.budget = StepBudget(STEPS_AT_START, self._budget_message)
        self._t_start = t0
        full = default_initial_state(p) if full is None else full
        gap = float(self.model.gap_of(full))
        gap_tol = self.tol.gap_tol * self.model.length_scale
        if gap < -gap_tol:
            raise ValueError(f"`state` has gap Delta0 - (x2 - x1) = {gap:.6g} m < 0: the bodies would overlap")
        self._same_time_events = 0
        if gap <= gap_tol:
            full = full.copy()
            full[1] = full[0] + p.Delta0  # exactly on the stop
            if full[3] - full[2] > 0.0:
                self._impact(float(t0), full)
            else:
                self._leave_contact(float(t0), full, rebound=float(full[2] - full[3]))
        else:
            self._start(FREE, float(t0), full, departure=None)

    # --- bookkeeping ------------------------------------------------------------------
    def _budget_message(self, t: float) -> str:
        return work_bound_message(
            self.p,
            self.tol,
            budget_exceeded(self.budget.used, (t - self._t_start) / self.p.T),
            self._impacts_in_a_row(),
        )

    def _impacts_in_a_row(self) -> int:
        """Impacts among the last events since the last other event (a chatter sequence)."""
        n = 0
        for e in reversed(self.trajectory.events):
            if e.kind != "impact":
                break
            n += 1
        return n

    def _start(self, mode: str, t: float, y: np.ndarray, departure: tuple[int, float] | None) -> None:
        if mode == STUCK and self.model.stuck_resonant:
            raise ValueError(self.model.resonance_message(STUCK))
        self.mode = mode
        self.segment = Segment(self.model.mode(mode), t, y)
        self.trajectory.segments.append((mode, self.segment))
        self.search_from = t
        self.departure = departure

    def _record(self, event: Event) -> None:
        events = self.trajectory.events
        if events and event.t - events[-1].t <= SAME_TIME_ULPS * math.ulp(max(abs(event.t), 1.0)):
            self._same_time_events += 1
            if self._same_time_events > MAX_EVENTS_AT_ONE_TIME:
                raise SearchLimitError(
                    work_bound_message(self.p, self.tol, degenerate_contact(event.t), self._impacts_in_a_row())
                )
        else:
            self._same_time_events = 0
        events.append(event)

    @property
    def t(self) -> float:
        """Time up to which the motion is known to hold no further event, s."""
        return self.search_from

    def state_at(self, t: float) -> np.ndarray:
        """Full state at t >= the current segment's start, shape (4,)."""
        return self.model.full_state(self.mode, self.segment.state(t))

    # --- the loop -----------------------------------------------------------------------
    def advance(self, t_target: float) -> None:
        """Process every event up to ``t_target``; the motion then continues past it.

        Raises
        ------
        SearchLimitError
            The run exceeded its work bound (``STEPS_AT_START`` plus ``STEPS_PER_PERIOD``
            certified search steps per forcing period since the start).
        """
        t_target = check_start_time(t_target, self.p, "t_target")
        model, tol = self.model, self.tol
        self.budget.limit = STEPS_AT_START + int(STEPS_PER_PERIOD * max(t_target - self._t_start, 0.0) / self.p.T)
        while True:
            if self.mode == FREE:
                fn: LinearFunctional = model.gap
                eps = tol.gap_tol * model.length_scale
            else:
                fn = model.contact_force
                eps = tol.force_tol * model.force_scale
            if self.search_from >= t_target:
                return  # an earlier march already certified the motion past t_target
            try:
                root, reached = march(self.segment, fn, self.search_from, t_target, eps, self.departure, self.budget)
            except SearchLimitError as err:
                if str(err).startswith("`"):  # the budget's message names a parameter already
                    raise
                raise SearchLimitError(
                    work_bound_message(self.p, self.tol, str(err), self._impacts_in_a_row())
                ) from None
            if root is None:
                # Resume later from where the march got (it may have stepped past t_target),
                # not from t_target: restarting there would repeat the march's first steps.
                self.search_from, self.departure = reached, None
                return
            t_event, _ = root
            if self.mode == FREE:
                full = self.segment.state(t_event)
                full[1] = full[0] + self.p.Delta0  # on the stop exactly (removes the <= gap_tol residue)
                self._impact(t_event, full)
            else:
                self._liftoff(t_event)

    def _impact(self, t: float, full: np.ndarray) -> None:
        after, v, S = self.model.impact(full)
        self._record(Event(t, "impact", v, S, full, after, t))
        self._leave_contact(t, after, rebound=impact_law.rebound(self.p, v))

    def _leave_contact(self, t: float, full: np.ndarray, rebound: float) -> None:
        """After an impact (or at a start on the stop): rebound, separate, or stick."""
        model, p = self.model, self.p
        F = model.force_in_contact(t, full)
        a = F / p.reduced_mass  # relative acceleration pressing the bodies together
        if a > 0.0 and rebound * rebound <= 2.0 * a * self.tol.chatter_tol * model.length_scale:
            self._stick(t, full, impact_law.accumulation_time(p, t, rebound, a))
            return
        departure = self._gap_departure(t, full, rebound)
        if departure is None:  # nothing pulls the bodies apart: they stay together
            self._stick(t, full, t)
        else:
            self._start(FREE, t, full, departure)

    def _stick(self, t: float, full: np.ndarray, t_accumulation: float) -> None:
        """Capture into persistent contact (the plastic pulse of :meth:`Model.stick`)."""
        stuck, S = self.model.stick(full)
        self._record(Event(t, "stick", 0.0, S, full, self.model.full_state(STUCK, stuck), t_accumulation))
        self._start(STUCK, t, stuck, departure=self._force_departure(t, stuck))

    def _gap_departure(self, t: float, full: np.ndarray, rebound: float) -> tuple[int, float] | None:
        """Order and value of the gap's first non-zero derivative when leaving the stop."""
        scale = self.model.length_scale
        w = max(self.p.omega, self.p.omega1)
        if rebound > REBOUND_FLOOR * scale * w:
            return 1, rebound
        derivs = self.model.gap_derivatives(t, full, orders=5)
        for order in (2, 3, 4):
            threshold = DEPARTURE_FLOOR * scale * w**order
            # An event time is only known to ~ulp(t), and
            # one ulp of t moves g^(m) by g^(m+1) ulp(t). Below that, g^(m) is rounding noise,
            # not a departure: at t ~ 382 s (gap -19, step 608) a lift-off left g'' = 1.4e-10
            # (F = -1e-11 N) with g''' = 5.8e3; order 2 gave a first step below ulp(t), the
            # search re-found the stop at once and 50 zero-velocity impacts raised
            # "degenerate contact". Order 3 decides there.
            if order < 4:
                threshold = max(threshold, DEPARTURE_ULPS * math.ulp(max(abs(t), 1.0)) * abs(float(derivs[order + 1])))
            if derivs[order] > threshold:
                return order, float(derivs[order])
            if derivs[order] < -threshold:
                return None
        return None

    def _force_departure(self, t: float, stuck: np.ndarray) -> tuple[int, float] | None:
        """At the start of contact F may be ~0 (plastic capture at the edge of lift-off)."""
        fn = self.model.contact_force
        F = float(fn.of_state(t, stuck))
        scale = self.tol.force_tol * self.model.force_scale
        if F > scale:
            return None
        w = max(self.p.omega, self.p.omega1)
        for order in (1, 2, 3):
            d = float(fn.of_state(t, stuck, order))
            if d > scale * w**order:
                return order, d
            if d < -scale * w**order:
                return None  # F falls at once: the search finds lift-off at t
        return None

    def _liftoff(self, t: float) -> None:
        stuck = self.segment.state(t)
        full = self.model.full_state(STUCK, stuck)
        departure = self._gap_departure(t, full, rebound=0.0)
        if departure is None:
            # F touched zero without changing sign: contact goes on; step past the touch.
            F2 = float(self.model.contact_force.of_state(t, stuck, 2))
            self.search_from, self.departure = t, (2, max(F2, CURVATURE_FLOOR))
            return
        if self._dip_unresolved(t, full):
            return
        self._record(Event(t, "liftoff", 0.0, 0.0, full, full, t))
        self._start(FREE, t, full, departure)

    def _dip_unresolved(self, t: float, full: np.ndarray) -> bool:
        """Whether the contact force's dip below zero is too brief to part the bodies by more
        than the grazing resolution; if so, contact goes on through it.

        Near the lift-off threshold F dips below zero only just: the gap would open by less
        than gap_tol x_st (it grows like s^3) and close again before F recovers. Free motion
        there sits at rounding level, where no certified step can be taken (the search stalled
        at gap -31.2347523777 + 1e-6). Such a separation is below the model's resolution, so
        the bodies stay in contact; the contact-force search resumes where F is positive again.
        """
        model, fn = self.model, self.model.contact_force
        neg = LinearFunctional(fn.mode, -fn.c, -fn.g0, -fn.d_s)  # -F >= 0 during the dip
        slope = float(fn.of_state(t, self.segment.state(t), 1))
        eps = self.tol.force_tol * model.force_scale
        root, _ = march(self.segment, neg, t, t + self.p.T, eps, (1, -slope) if slope < 0.0 else None, self.budget)
        if root is None or root[0] <= t:
            return False  # F stays negative for a whole period: a real lift-off
        t_up = root[0]
        gap = model.gap_of(Segment(model.free, t, full).state(np.linspace(t, t_up, DIP_SAMPLES)))
        if float(gap.max()) > self.tol.gap_tol * model.length_scale:
            return False
        slope_up = float(fn.of_state(t_up, self.segment.state(t_up), 1))
        self.search_from, self.departure = t_up, ((1, slope_up) if slope_up > 0.0 else None)
        return True


def simulate(
    p: Parameters,
    t_end: float,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    *,
    max_periods: int = MAX_SIMULATE_PERIODS,
) -> Trajectory:
    """Run Algorithm No. 2 (with contact modes) from ``t0`` to ``t_end``.

    Parameters
    ----------
    p : Parameters
    t_end, t0 : float
        End and start, s (within ``MAX_CLOCK_PERIODS`` forcing periods of 0).
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0; default :func:`default_initial_state`.
    tolerances : Tolerances, optional
    max_periods : int
        Bound on the run's length, (t_end - t0)/T (a bound on the work).

    Returns
    -------
    Trajectory
        Segments and events; ``sample(t)`` gives the exact state at any t in [t0, t_end].

    Raises
    ------
    SearchLimitError
        The run exceeded its work bound (see :meth:`EventDrivenSolver.advance`).
    """
    return simulate_checked(*check_run_call(p, t_end, t0, state, tolerances, max_periods))


def simulate_checked(p: Parameters, t_end: float, t0: float, full, tolerances: Tolerances) -> Trajectory:
    """:func:`simulate` on arguments already checked (``check_run_call`` of
    :mod:`impactdamper.core.validation`): the reference backend's ``run``."""
    if not p.native_scales():
        # Solve the same relative problem in the reference case's units, and convert back.
        q = p.canonical()
        to_q, to_p = ScaleMap(p, q), ScaleMap(q, p)
        traj = simulate_checked(
            q, to_q.apply(t_end, "time"), to_q.apply(t0, "time"), None if full is None else to_q.full(full), tolerances
        )
        return rescale_trajectory(traj, to_p)
    solver = EventDrivenSolver(p, t0=t0, state=full, tolerances=tolerances)
    solver.advance(t_end)
    return solver.trajectory
