"""Established oscillations: run Algorithm No. 2 until the motion repeats, then read the cycle.

The run is settled with period T_c = k T when its stroboscopic sections (the state once per
forcing period, t_n = t0 + n T) repeat after k periods and have converged to that cycle: the
period test of :mod:`impactdamper.core.periodicity`, after every period.

The settled cycle's events are those from its start impact to half its longest flight before
the same impact one cycle later (:func:`_cycle_events`), never a window with a fixed margin: a
loose settle_tol gives a less refined cycle, never a different one.

The regime of the settled cycle:

* ``no_contact``: no impact and no contact in the cycle;
* ``stuck``: the bodies in contact all the time (the paper's "move together");
* ``chatter``: the cycle holds a phase of persistent contact (reached through an accumulation
  of impacts or a plastic impact) and a lift-off;
* ``single_impact``: k = 1 with one impact (the motion Algorithm No. 1 describes);
* ``multi_impact``: any other periodic impacting motion (k > 1 or several impacts);
* ``nonperiodic``: no period up to ``max_period_multiple`` within ``max_periods``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.core.model import STUCK
from impactdamper.core.parameters import Parameters, ScaleMap, state_scale
from impactdamper.core.periodicity import settled_period
from impactdamper.core.simulate import EventDrivenSolver, Tolerances, Trajectory, rescale_trajectory
from impactdamper.core.validation import SettleOptions, check_settle_call

__all__ = [
    "SteadyState",
    "CycleImpact",
    "steady_state",
    "REGIMES",
    "describe_cycle",
    "max_excursion",
    "rescale_steady",
    "section_of",
    "start_in_first_period",
    "describe_run",
    "settle",
]

REGIMES = ("no_contact", "stuck", "chatter", "single_impact", "multi_impact", "nonperiodic")


@dataclass(frozen=True)
class CycleImpact:
    """One impact of the settled cycle.

    Attributes
    ----------
    t : float
        Absolute time, s.
    t_over_T : float
        Time since the cycle's first impact, in forcing periods.
    phase : float
        t/T modulo 1 (phase of the forcing P0 sin(omega t)).
    velocity : float
        Closing relative velocity x2' - x1' before the impact, m/s.
    impulse : float
        Pulse S of eq. (21), N s.
    """

    t: float
    t_over_T: float
    phase: float
    velocity: float
    impulse: float


@dataclass(frozen=True)
class SteadyState:
    """The settled motion (or the last stretch of a motion that did not settle).

    Attributes
    ----------
    regime : str
        One of :data:`REGIMES`.
    period_multiple : int
        k in T_c = k T (0 when nonperiodic).
    impacts : list of CycleImpact
        The cycle's impacts in order, the first one ending the cycle's longest free flight.
    cycle_start : float
        Time in ``trajectory`` where the reported cycle starts, s (on the run's clock, which
        starts at t0 reduced modulo T into [0, T): t/T modulo 1 is the forcing's phase).
    contact_fraction : float
        Share of the cycle spent in persistent contact.
    contact_phases : list of (float, float)
        Contact intervals (stick to lift-off) in units of T since ``cycle_start``.
    x1_max : float
        max |x1|/x_st over the cycle.
    periods : int
        Forcing periods simulated until settled (or the limit).
    residual : float
        Largest relative section mismatch over the final cycle.
    trajectory : Trajectory
        The motion over the reported cycle, with at least one cycle (and 4 periods) before
        and one cycle after it (re-simulated from a section of the run, so its clock is
        the run's start plus a few periods: times in it differ from t0 + n T by a multiple of
        T).
    section_times : ndarray, shape (periods,)
        Times t_s + n T of the stroboscopic sections on the run's clock, s (t_s: t0 reduced
        modulo T into [0, T)).
    sections : ndarray, shape (periods, 4)
        States (x1, x2, x1', x2') there (the transient's record).
    method : str
        How it was found: ``simulation`` (Algorithm No. 2 until the motion repeats) or
        ``algorithm1`` (Algorithm No. 1's closed-form orbit, a stable attractor; no transient).
    backend : str
        What computed it: ``python`` (this reference) or ``compiled`` (the numba kernels).
    fallback : str
        "" unless another backend was asked for: then why the Python reference ran instead
        (``matrix_exponential``, ``scales``, ``error``, ``numba_unavailable``).
    """

    p: Parameters = field(repr=False)
    regime: str
    period_multiple: int
    impacts: tuple
    cycle_start: float
    contact_fraction: float
    contact_phases: tuple
    x1_max: float
    periods: int
    residual: float
    trajectory: Trajectory = field(repr=False)
    section_times: np.ndarray = field(default=None, repr=False)
    sections: np.ndarray = field(default=None, repr=False)
    method: str = "simulation"
    backend: str = "python"
    fallback: str = ""

    @property
    def impacts_per_cycle(self) -> int:
        return len(self.impacts)

    @property
    def settled(self) -> bool:
        return self.regime != "nonperiodic"

    @property
    def cycle_duration(self) -> float:
        """T_c in s (the reported stretch, k T or the last periods when nonperiodic)."""
        if self.settled:
            return max(self.period_multiple, 1) * self.p.T
        return min(NONPERIODIC_WINDOW, max(self.periods, 1)) * self.p.T  # (a run shorter than the window)

    def sample(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Relative coordinates (x1_bar, x2_bar) at absolute times t (within the simulation)."""
        full, _ = self.trajectory.sample(t)
        return self.trajectory.model.relative(full)

    def to_dict(self) -> dict:
        """The JSON object of ``python -m impactdamper steady --json``."""
        vscale = self.p.x_st * self.p.omega
        sscale = self.p.m1 * self.p.x_st * self.p.omega
        return {
            "regime": self.regime,
            "period_multiple": self.period_multiple,
            "impacts_per_cycle": self.impacts_per_cycle,
            "impacts": [
                {
                    "t_over_T": i.t_over_T,
                    "phase": i.phase,
                    "velocity": i.velocity,
                    "impulse": i.impulse,
                    "velocity_rel": i.velocity / vscale,
                    "impulse_rel": i.impulse / sscale,
                }
                for i in self.impacts
            ],
            "contact_fraction": self.contact_fraction,
            "contact_phases": [list(c) for c in self.contact_phases],
            "x1_max": self.x1_max,
            "cycle_start_phase": (self.cycle_start / self.p.T) % 1.0,
            "periods_simulated": self.periods,
            "residual": self.residual,
            "parameters": self.p.to_dict(),
        }


# How many final periods describe a motion that never settled.
NONPERIODIC_WINDOW = 8


def start_in_first_period(p: Parameters, t0: float) -> float:
    """The time in [0, T) with the forcing's phase at ``t0``: omega t0 modulo 2 pi, exactly.

    The forcing P0 sin(omega t) is T-periodic, so a run from there is the run from t0 shifted
    by a whole number of periods. In floating point omega t0 would lose the phase for large t0
    (at t0 = 1e5 s the rounding noise broke the settle test, at 1e20 s the phase was lost);
    the remainder is taken in multiple precision: omega t0 is exact as a product of two
    doubles, and 2 pi is carried to the bits that the remainder needs.
    """
    if 0.0 <= t0 < p.T:
        return t0
    bits = max(math.frexp(p.omega)[1] + math.frexp(t0)[1], 0) + 96
    import mpmath  # (only for a t0 outside the first period: loaded then)

    with mpmath.workprec(bits):
        cycles = mpmath.mpf(p.omega) * mpmath.mpf(t0) / (2 * mpmath.pi)
        fraction = float(cycles - mpmath.floor(cycles))
    start = fraction * p.T
    return start if start < p.T else 0.0  # (a fraction that rounds to 1 is the phase 0)


def steady_state(
    p: Parameters,
    *,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    **options,
) -> SteadyState:
    """Run Algorithm No. 2 from Algorithm No. 2's step 1 (or ``state`` at ``t0``) until the
    motion repeats, and describe the settled cycle.

    Parameters
    ----------
    p : Parameters
    t0 : float
        Start time, s.
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0; default the paper's step 1 (see ``default_initial_state``).
    tolerances : Tolerances, optional
        Event-solver tolerances.
    **options
        The search's :class:`~impactdamper.core.validation.SettleOptions` by name (defaults
        there):

    settle_tol : float
        Section mismatch (relative) below which the motion counts as repeating, in
        [:data:`~impactdamper.core.validation.SETTLE_TOL_FLOOR`, 1): the
        last sections' distance to the cycle they approach is below it, and x1_max is within
        :data:`~impactdamper.core.periodicity.X1_MAX_FACTOR` settle_tol of the exactly settled
        motion's (:mod:`impactdamper.core.periodicity`). The regime, k and the cycle's impacts do not depend on it.
    max_periods : int
        Forcing periods after which an unsettled motion is called ``nonperiodic`` (at most
        :data:`~impactdamper.core.validation.MAX_PERIODS_LIMIT`; a motion needs at least
        2 :data:`~impactdamper.core.periodicity.CONVERGENCE_WINDOW` + k periods to settle).
    max_period_multiple : int
        Largest k tried for T_c = k T.

    The result does not depend on t0 beyond its forcing phase (the run starts at t0 reduced
    modulo T, see :func:`start_in_first_period`), nor on the free scales x_st, m1 and omega in
    relative units (outside :data:`impactdamper.core.parameters.NATIVE_SCALES` the same relative
    problem is solved in the reference case's units and converted back).

    Raises
    ------
    TypeError, ValueError
        A bad argument, named (``ArgumentTypeError`` is both).
    SearchLimitError
        The motion needs more work than the event-driven solver's bound (see
        :meth:`impactdamper.EventDrivenSolver.advance`).
    """
    return settle(*check_settle_call(p, t0, state, tolerances, **options))


def settle(p: Parameters, t0: float, state, tolerances: Tolerances, options: SettleOptions) -> SteadyState:
    """:func:`steady_state` on arguments already checked (``check_settle_call`` of
    :mod:`impactdamper.core.validation`): the reference backend's ``settle``."""
    start = start_in_first_period(p, t0)
    if not p.native_scales():
        q = p.canonical()
        to_q = ScaleMap(p, q)
        s = _steady_state(
            q, to_q.apply(start, "time"), None if state is None else to_q.full(state), tolerances, options
        )
        return rescale_steady(s, ScaleMap(q, p))
    return _steady_state(p, start, state, tolerances, options)


def rescale_steady(s: SteadyState, scales: ScaleMap) -> SteadyState:
    """The same settled motion in ``scales.target``'s units (relative fields unchanged)."""
    return dataclasses.replace(
        s,
        p=scales.target,
        impacts=tuple(
            dataclasses.replace(
                i,
                t=scales.apply(i.t, "time"),
                velocity=scales.apply(i.velocity, "velocity"),
                impulse=scales.apply(i.impulse, "impulse"),
            )
            for i in s.impacts
        ),
        cycle_start=scales.apply(s.cycle_start, "time"),
        trajectory=rescale_trajectory(s.trajectory, scales),
        section_times=None if s.section_times is None else scales.apply(s.section_times, "time"),
        sections=None if s.sections is None else scales.full(s.sections),
    )


def section_of(s: SteadyState) -> tuple[np.ndarray, str]:
    """State and mode at a stroboscopic section of the reported cycle.

    The section is the first time t = n T (forcing phase zero) at or after the cycle's start,
    inside the stored trajectory (which :func:`steady_state` keeps around the reported cycle;
    its clock differs from the run's by a multiple of T, so the phase is the same). A sweep
    carries this state to its next point.

    Parameters
    ----------
    s : SteadyState
        A settled motion, with its trajectory.

    Returns
    -------
    state : ndarray, shape (4,)
        (x1, x2, x1', x2') at the section, in m and m/s.
    mode : str
        The contact mode there, ``free`` or ``stuck``.
    """
    T = s.p.T
    t = math.ceil(s.cycle_start / T - 1e-9) * T
    full, modes = s.trajectory.sample(np.array([t]))
    return full[0], str(modes[0])


def _steady_state(
    p: Parameters, t0: float, state: np.ndarray | None, tolerances: Tolerances, options: SettleOptions
) -> SteadyState:
    """steady_state on validated arguments, t0 in [0, T), in native scales."""
    settle_tol, max_periods, max_period_multiple = options.settle_tol, options.max_periods, options.max_period_multiple
    T = p.T
    scale = state_scale(p)
    solver = EventDrivenSolver(p, t0=t0, state=state, tolerances=tolerances)
    start_state = solver.state_at(t0) if state is None else np.asarray(state, dtype=float)
    states = np.empty((max_periods, 4))  # the section states, (x1, x2, x1', x2')
    sections = np.empty((max_periods, 4))  # the same, scaled by x_st and x_st omega
    modes: list[str] = []
    found_k, n, residual = 0, 0, math.inf
    base = 0  # the section the current solver started from (at time t0: same forcing phase)
    for n in range(1, max_periods + 1):
        if n - 1 - base >= REBASE_PERIODS:
            solver = EventDrivenSolver(p, t0=t0, state=states[n - 2], tolerances=tolerances)
            base = n - 1
        t_n = t0 + (n - base) * T
        solver.advance(t_n)
        states[n - 1] = solver.state_at(t_n)
        sections[n - 1] = states[n - 1] / scale
        modes.append(solver.mode)
        found_k, residual = settled_period(sections[:n], modes, max_period_multiple, settle_tol)
        if found_k:
            break
    return describe_run(p, t0, states[:n], found_k, residual, start_state, tolerances)


def describe_run(
    p: Parameters,
    t0: float,
    states: np.ndarray,
    found_k: int,
    residual: float,
    start_state: np.ndarray,
    tolerances: Tolerances,
    trajectory: Trajectory | None = None,
) -> SteadyState:
    """The :class:`SteadyState` of a run of :func:`steady_state`'s period loop, from its section
    states (x1, x2, x1', x2') at t0 + T, ..., t0 + n T, the period it found (0: none) and its
    last residual; the cycle is described on a fresh run (below). The compiled backend ends here
    too for a cycle with contact phases, with ``trajectory``: that fresh run, made by its
    kernels (None: the pure-Python solver makes it)."""
    T = p.T
    n = len(states)
    # (A run shorter than the window reports what it has: with max_periods = 2 the window began
    # before the run, found by the hardened-input property tests.)
    k = found_k if found_k else min(NONPERIODIC_WINDOW, n)
    # Describe the cycle on a fresh run from a section at least one cycle (and 4 periods)
    # before the reported one, so that its first impact's free flight is known and plots can
    # show what led into it, to one cycle after it (for "cycle + next impact"), with the clock
    # again near t0.
    first = max(n - k - max(k, PERIODS_BEFORE_CYCLE), 0)
    state, t_end = states[first - 1] if first else start_state, t0 + (n - first + k + 1) * T
    if trajectory is None:
        describer = EventDrivenSolver(p, t0=t0, state=state, tolerances=tolerances)
        describer.advance(t_end)
        trajectory = describer.trajectory
    result = describe_cycle(p, trajectory, t0 + (n - first - k) * T, k, bool(found_k), n, residual)
    return dataclasses.replace(result, section_times=t0 + T * np.arange(1, n + 1), sections=np.array(states, float))


# The solver restarts from its section state every REBASE_PERIODS forcing periods, with its
# clock back at t0 (the forcing's phase is the same there). A long run's absolute time
# would otherwise put ulp(t) ~ 1e-12 s of rounding into every event: near a bifurcation, where
# a multiplier is close to 1 in modulus and amplifies it, that noise floor (~1e-9 after
# 3000 periods at gap -9.49) exceeds settle_tol, and a period-2 motion passed for period 4.
REBASE_PERIODS = 100
# Forcing periods (at least) that the reported trajectory holds before the cycle.
PERIODS_BEFORE_CYCLE = 4


def describe_cycle(
    p: Parameters, traj: Trajectory, window_start: float, k: int, settled: bool, periods: int, residual: float
) -> SteadyState:
    """Describe the cycle of period k T that a trajectory repeats from ``window_start``.

    This is how :func:`steady_state` reads a settled motion, and how any other route to a
    settled cycle (the sweeps' stroboscopic Newton) must read it so that the two agree: the
    cycle starts at the impact ending its longest free flight (the paper's Fig. 2 phase
    convention: one impact per cycle starts it), its impacts carry their phase t/T mod 1,
    closing velocity and impulse (eqs. (21)-(22)), and the regime follows from its impacts
    and contact phases (see the module docstring).

    Parameters
    ----------
    p : Parameters
    traj : Trajectory
        The exact motion, covering [window_start - one flight, window_start + 2 k T] (the
        longest flight into the window and the next cycle are read).
    window_start : float
        A section time t = t0 + n T, s, where the cycle is taken to begin.
    k : int
        Period multiple (for an unsettled motion: the window's length in periods).
    settled : bool
        The motion repeats with period k T (False: regime ``nonperiodic``).
    periods : int
        Forcing periods simulated to get here (recorded).
    residual : float
        The relative section mismatch that decided ``settled`` (recorded).

    Returns
    -------
    SteadyState
        Without ``section_times`` and ``sections`` (the caller's run has them).
    """
    T = p.T
    Tc = k * T
    window_end = window_start + Tc
    impacts = traj.impacts(window_start, window_end)
    # The cycle starts at the impact that ends its longest free flight (for one impact per
    # cycle: that impact); without impacts, at the section.
    start = window_start
    if impacts:
        position = {id(e): i for i, e in enumerate(traj.events)}
        t_begin = traj.segments[0][1].t0
        flights = []
        for e in impacts:
            i = position[id(e)]
            flights.append(e.t - (traj.events[i - 1].t if i else t_begin))
        longest = int(np.argmax(flights))
        start = impacts[longest].t
    if settled and impacts:
        cycle_events = _cycle_events(traj, start, Tc, flights[longest])
    else:  # no impact (the events between the sections), or no cycle (the window's stretch)
        cycle_events = [e for e in traj.events if start <= e.t < start + Tc]
    cycle_impacts = tuple(
        CycleImpact(e.t, (e.t - start) / T, (e.t / T) % 1.0, e.velocity, e.impulse)
        for e in cycle_events
        if e.kind == "impact"
    )
    contact = _contact_phases(traj, start, start + Tc)
    contact_time = sum(b - a for a, b in contact)
    contact_fraction = min(contact_time / Tc, 1.0)
    has_contact_events = any(e.kind in ("stick", "liftoff") for e in cycle_events)
    if not settled:
        regime = "nonperiodic"
    elif contact_fraction >= 1.0 - 1e-12 and not cycle_impacts:
        regime = "stuck"
    elif not cycle_impacts and contact_fraction == 0.0:
        regime = "no_contact"
    elif has_contact_events or contact_fraction > 0.0:
        regime = "chatter"
    elif k == 1 and len(cycle_impacts) == 1:
        regime = "single_impact"
    else:
        regime = "multi_impact"
    return SteadyState(
        p=p,
        regime=regime,
        period_multiple=k if settled else 0,
        impacts=cycle_impacts,
        cycle_start=start,
        contact_fraction=contact_fraction,
        contact_phases=tuple(((a - start) / T, (b - start) / T) for a, b in contact),
        x1_max=max_excursion(p, traj, start, start + Tc),
        periods=periods,
        residual=residual,
        trajectory=traj,
    )


def _cycle_events(traj: Trajectory, start: float, Tc: float, flight: float) -> list:
    """The events of one cycle of period T_c from ``start``, the impact that ends the cycle's
    longest free flight (of duration ``flight``).

    The cycle is [start, start + T_c - flight / 2): the same impact one cycle later comes at
    start + T_c up to the motion's drift per cycle, and the cycle's last event at least a
    longest flight before that, so half a flight separates the two whatever ``settle_tol``.
    A window with a fixed margin does not: at settle_tol = 1e-5 the reference case drifts by
    2e-8 T per period, and [start - 1e-9 T, start + T_c - 1e-9 T) counted the same impact
    twice. (Counting the events between two sections instead fails in chatter: a section inside
    a sequence of bounces splits it, and the count of its last, tiny bounces varies.)
    """
    end = start + Tc - 0.5 * flight
    return [e for e in traj.events if start <= e.t < end]


def _contact_phases(traj: Trajectory, a: float, b: float) -> list[tuple[float, float]]:
    """Intervals of [a, b) spent in the stuck mode."""
    out = []
    segs = traj.segments
    for i, (mode, seg) in enumerate(segs):
        if mode != STUCK:
            continue
        s0 = seg.t0
        s1 = segs[i + 1][1].t0 if i + 1 < len(segs) else math.inf
        lo, hi = max(s0, a), min(s1, b)
        if hi > lo:
            out.append((lo, hi))
    return out


# Samples per forcing period when searching the object's largest excursion (then refined).
EXCURSION_SAMPLES_PER_PERIOD = 256


def max_excursion(p: Parameters, traj: Trajectory, a: float, b: float) -> float:
    """max |x1|/x_st on [a, b] of a trajectory: the object's amplitude, the quantity of the
    paper's Fig. 2 (x1_max) and of the suppression measure.

    Dense samples (``EXCURSION_SAMPLES_PER_PERIOD`` per forcing period), the largest refined
    by bounded minimisation on its segment (both ends for a repeating window).

    Parameters
    ----------
    p : Parameters
    traj : Trajectory
        Covering [a, b].
    a, b : float
        The window, s (a < b).

    Returns
    -------
    float
        max |x1(t)|/x_st over [a, b].
    """
    n = max(int(EXCURSION_SAMPLES_PER_PERIOD * (b - a) / p.T), 16)
    ts = np.linspace(a, b, n + 1)
    x1 = np.abs(traj.sample(ts)[0][:, 0])
    i = int(np.argmax(x1))
    seg, lo, hi = _segment_bracket(traj, ts[max(i - 1, 0)], ts[min(i + 1, n)], ts[i])
    best = max(float(x1[i]), _segment_peak(p, seg, lo, hi))
    if i in (0, n):
        # The motion repeats: a peak just before the window's start shows as the largest sample
        # at its start and its end alike, and argmax takes the start, whose bracket does not
        # hold the peak (x1_max then came out up to 1e-4 low, depending on the start's phase:
        # found by the start-time invariance test). Refine the other end's bracket too.
        j = n if i == 0 else 0
        lo, hi = ts[max(j - 1, 0)], ts[min(j + 1, n)]
        seg, lo, hi = _segment_bracket(traj, lo, hi, 0.5 * (lo + hi))
        if hi > lo:
            best = max(best, _segment_peak(p, seg, lo, hi))
    return best / p.x_st


def _segment_bracket(traj: Trajectory, lo: float, hi: float, t: float):
    """The segment that holds time t, and the bracket [lo, hi] cut to it."""
    k = int(traj.segment_index(np.array([t]))[0])
    seg = traj.segments[k][1]
    seg_end = traj.segments[k + 1][1].t0 if k + 1 < len(traj.segments) else math.inf
    return seg, max(lo, seg.t0), min(hi, seg_end)


def _segment_peak(p: Parameters, seg, lo: float, hi: float) -> float:
    """max |x1| on [lo, hi] of one segment (x1 is the first state entry in both modes), by
    bounded minimisation to 1e-12 T."""
    import scipy.optimize  # (loaded on first use: the package import stays light)

    res = scipy.optimize.minimize_scalar(
        lambda t: -abs(float(seg.state(float(t))[0])), bounds=(lo, hi), method="bounded", options={"xatol": 1e-12 * p.T}
    )
    return -float(res.fun)
