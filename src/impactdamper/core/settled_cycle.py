"""The settled cycle: what a settled motion is (:class:`SteadyState`, its impacts and regime)
and how it is read from a run.

:func:`describe_run` re-simulates a stretch around the reported cycle from the run's sections
(:mod:`impactdamper.core.steady` finds the period), and :func:`describe_cycle` reads it: the
cycle starts at the impact that ends its longest free flight, its events are those from that
impact to half its longest flight before the same impact one cycle later
(:func:`_cycle_events`), never a window with a fixed margin: a loose settle_tol gives a less
refined cycle, never a different one.

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

from impactdamper.core.excursion import max_excursion
from impactdamper.core.model import STUCK
from impactdamper.core.parameters import Parameters, ScaleMap
from impactdamper.core.simulate import EventDrivenSolver
from impactdamper.core.trajectory import Trajectory, rescale_trajectory
from impactdamper.core.validation import Tolerances

__all__ = [
    "SteadyState",
    "CycleImpact",
    "REGIMES",
    "NONPERIODIC_WINDOW",
    "PERIODS_BEFORE_CYCLE",
    "describe_run",
    "describe_cycle",
    "rescale_steady",
    "section_of",
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
    inside the stored trajectory (which :func:`~impactdamper.core.steady.steady_state` keeps around the reported cycle;
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


# Forcing periods (at least) that the reported trajectory holds before the cycle.
PERIODS_BEFORE_CYCLE = 4


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
    """The :class:`SteadyState` of a run of :func:`~impactdamper.core.steady.steady_state`'s period loop, from its section
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


def describe_cycle(
    p: Parameters, traj: Trajectory, window_start: float, k: int, settled: bool, periods: int, residual: float
) -> SteadyState:
    """Describe the cycle of period k T that a trajectory repeats from ``window_start``.

    This is how :func:`~impactdamper.core.steady.steady_state` reads a settled motion, and how
    any other route to a settled cycle (the sweeps' stroboscopic Newton) must read it so that
    the two agree: the cycle starts at the impact ending its longest free flight (the paper's
    Fig. 2 phase convention: one impact per cycle starts it), its impacts carry their phase
    t/T mod 1, closing velocity and impulse (eqs. (21)-(22)), and the regime follows from its
    impacts and contact phases (see the module docstring).

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
    start, flight = _cycle_start(traj, window_start, Tc)
    if settled and flight is not None:
        cycle_events = _cycle_events(traj, start, Tc, flight)
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
    return SteadyState(
        p=p,
        regime=_regime(settled, k, len(cycle_impacts), contact_fraction, has_contact_events),
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


def _cycle_start(traj: Trajectory, window_start: float, Tc: float) -> tuple[float, float | None]:
    """Where the cycle of period T_c in the window from ``window_start`` starts: at the impact
    that ends its longest free flight (for one impact per cycle: that impact), and that
    flight's duration; without impacts in the window, at the section (and None)."""
    impacts = traj.impacts(window_start, window_start + Tc)
    if not impacts:
        return window_start, None
    position = {id(e): i for i, e in enumerate(traj.events)}
    t_begin = traj.segments[0][1].t0
    flights = []
    for e in impacts:
        i = position[id(e)]
        flights.append(e.t - (traj.events[i - 1].t if i else t_begin))
    longest = int(np.argmax(flights))
    return impacts[longest].t, flights[longest]


def _regime(settled: bool, k: int, impacts: int, contact_fraction: float, has_contact_events: bool) -> str:
    """The regime (:data:`REGIMES`) of a cycle of period k T with ``impacts`` impacts, the
    share ``contact_fraction`` of it in persistent contact, and stick or lift-off events or
    none (see the module docstring)."""
    if not settled:
        return "nonperiodic"
    if contact_fraction >= 1.0 - 1e-12 and not impacts:
        return "stuck"
    if not impacts and contact_fraction == 0.0:
        return "no_contact"
    if has_contact_events or contact_fraction > 0.0:
        return "chatter"
    if k == 1 and impacts == 1:
        return "single_impact"
    return "multi_impact"


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
