"""Established oscillations: run Algorithm No. 2 until the motion repeats, then read the cycle.

The paper's step 6 says "calculations continue until established oscillations occur" without
saying how that is recognised. Here: the state is sampled once per forcing period
(stroboscopic section t_n = t0 + n T, the forcing's phase is then the same), and the motion is
settled with period T_c = k T when, for the smallest k <= ``max_period_multiple``, the last k
sections each match the section k periods earlier to ``settle_tol`` (relative to x_st and
x_st omega) in the same mode. Matching a whole cycle of sections, not one, keeps a slow
transient from passing for a period-k motion.

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
import scipy.optimize

from .model import STUCK
from .parameters import Parameters
from .simulate import EventDrivenSolver, Tolerances, Trajectory

__all__ = ["SteadyState", "CycleImpact", "steady_state", "REGIMES"]

REGIMES = ("no_contact", "stuck", "chatter", "single_impact", "multi_impact", "nonperiodic")
# Samples per forcing period when searching the object's largest excursion (then refined).
EXCURSION_SAMPLES_PER_PERIOD = 256


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
        Absolute time where the reported cycle starts, s.
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
        The whole simulated motion, one cycle past the reported one included.
    section_times : ndarray, shape (periods,)
        Times t0 + n T of the stroboscopic sections, s.
    sections : ndarray, shape (periods, 4)
        States (x1, x2, x1', x2') there (the transient's record).
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

    @property
    def impacts_per_cycle(self) -> int:
        return len(self.impacts)

    @property
    def settled(self) -> bool:
        return self.regime != "nonperiodic"

    @property
    def cycle_duration(self) -> float:
        """T_c in s (the reported stretch, k T or the last periods when nonperiodic)."""
        return max(self.period_multiple, 1) * self.p.T if self.settled else NONPERIODIC_WINDOW * self.p.T

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


def _scaled(p: Parameters, full: np.ndarray) -> np.ndarray:
    return full / np.array([p.x_st, p.x_st, p.x_st * p.omega, p.x_st * p.omega])


def steady_state(
    p: Parameters,
    *,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    settle_tol: float = 1e-10,
    max_periods: int = 4000,
    max_period_multiple: int = 8,
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
    settle_tol : float
        Section mismatch (relative) below which the motion counts as repeating.
    max_periods : int
        Forcing periods after which an unsettled motion is called ``nonperiodic``.
    max_period_multiple : int
        Largest k tried for T_c = k T.
    """
    if not (math.isfinite(settle_tol) and 0 < settle_tol < 1):
        raise ValueError(f"`settle_tol` = {settle_tol!r} is not allowed: must be in (0, 1)")
    if not (isinstance(max_periods, int) and max_periods >= 2):
        raise ValueError(f"`max_periods` = {max_periods!r} is not allowed: must be an integer >= 2")
    if not (isinstance(max_period_multiple, int) and 1 <= max_period_multiple < max_periods):
        raise ValueError(f"`max_period_multiple` = {max_period_multiple!r} is not allowed: must be an integer in [1, max_periods)")
    solver = EventDrivenSolver(p, t0=t0, state=state, tolerances=tolerances)
    T = p.T
    sections = np.empty((max_periods, 4))
    modes: list[str] = []
    found_k, n, residual = 0, 0, math.inf
    watch: dict[int, float] = {}  # divisor d of a matched k -> its mismatch when last checked
    for n in range(1, max_periods + 1):
        t_n = t0 + n * T
        solver.advance(t_n)
        sections[n - 1] = _scaled(p, solver.state_at(t_n))
        modes.append(solver.mode)
        # Screen: a period k is possible only if this section repeats the one k periods back.
        lags = min(max_period_multiple, (n - 1) // 2)
        if lags == 0:
            continue
        latest = np.abs(sections[n - 1 - lags:n - 1][::-1] - sections[n - 1]).max(axis=1)
        residual = float(latest.min())
        if residual >= settle_tol:
            found_k = 0
            continue
        found_k, residual = _period(sections[:n], modes, max_period_multiple, settle_tol)
        if found_k and _shorter_period_still_converging(sections[:n], modes, found_k, watch):
            found_k = 0
            continue
        if found_k:
            break
    k = found_k if found_k else NONPERIODIC_WINDOW
    window_end = t0 + n * T
    solver.advance(window_end + (k + 1) * T)  # the next cycle too, for plots of "cycle + next impact"
    scale = np.array([p.x_st, p.x_st, p.x_st * p.omega, p.x_st * p.omega])
    result = _describe(p, solver.trajectory, window_end - k * T, k, bool(found_k), n, residual)
    return dataclasses.replace(result, section_times=t0 + T * np.arange(1, n + 1), sections=sections[:n] * scale)


def _mismatch(sections: np.ndarray, modes: list, k: int) -> float:
    """Largest difference between each of the last k sections and the one k periods earlier."""
    n = len(sections)
    if n < 2 * k + 1:
        return math.inf
    if modes[n - k:] != modes[n - 2 * k:n - k]:
        return math.inf
    return float(np.abs(sections[n - k:] - sections[n - 2 * k:n - k]).max())


def _period(sections: np.ndarray, modes: list, kmax: int, tol: float) -> tuple[int, float]:
    """Smallest k whose last k sections repeat those k periods earlier, with the mismatch."""
    best = math.inf
    for k in range(1, kmax + 1):
        worst = _mismatch(sections, modes, k)
        best = min(best, worst)
        if worst < tol:
            return k, worst
    return 0, best


# A divisor d of a matched k whose mismatch is below this may be the true period still
# converging (a transient with a Floquet multiplier near -1 repeats after 2 periods sooner
# than after 1). The run goes on while that mismatch keeps falling, by at least the factor
# DIVISOR_DECAY per cycle of k periods; if it stalls, the motion has period k.
DIVISOR_SUSPECT = 1e-3
DIVISOR_DECAY = 0.9


def _shorter_period_still_converging(sections: np.ndarray, modes: list, k: int, watch: dict) -> bool:
    n = len(sections)
    converging = False
    for d in range(1, k):
        if k % d:
            continue
        m = _mismatch(sections, modes, d)
        if m >= DIVISOR_SUSPECT:
            continue
        n_seen, m_seen = watch.get(d, (n, m))
        if n - n_seen < k:
            watch.setdefault(d, (n, m))
            converging = True
        elif m < DIVISOR_DECAY * m_seen:
            watch[d] = (n, m)
            converging = True
    return converging


def _describe(p: Parameters, traj: Trajectory, window_start: float, k: int, settled: bool,
              periods: int, residual: float) -> SteadyState:
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
        start = impacts[int(np.argmax(flights))].t
    cycle_events = [e for e in traj.events if start - 1e-9 * T <= e.t < start + Tc - 1e-9 * T]
    cycle_impacts = tuple(
        CycleImpact(e.t, (e.t - start) / T, (e.t / T) % 1.0, e.velocity, e.impulse)
        for e in cycle_events if e.kind == "impact"
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
        p=p, regime=regime, period_multiple=k if settled else 0, impacts=cycle_impacts,
        cycle_start=start, contact_fraction=contact_fraction,
        contact_phases=tuple(((a - start) / T, (b - start) / T) for a, b in contact),
        x1_max=_max_excursion(p, traj, start, start + Tc), periods=periods, residual=residual,
        trajectory=traj,
    )


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


def _max_excursion(p: Parameters, traj: Trajectory, a: float, b: float) -> float:
    """max |x1|/x_st on [a, b]: dense samples, refined around the largest one on its segment."""
    n = max(int(EXCURSION_SAMPLES_PER_PERIOD * (b - a) / p.T), 16)
    ts = np.linspace(a, b, n + 1)
    x1 = np.abs(traj.sample(ts)[0][:, 0])
    i = int(np.argmax(x1))
    lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, n)]
    k = int(traj._segment_index(np.array([ts[i]]))[0])
    seg = traj.segments[k][1]
    seg_end = traj.segments[k + 1][1].t0 if k + 1 < len(traj.segments) else math.inf
    lo, hi = max(lo, seg.t0), min(hi, seg_end)  # x1 is the first state entry in both modes
    res = scipy.optimize.minimize_scalar(lambda t: -abs(float(seg.state(float(t))[0])), bounds=(lo, hi),
                                         method="bounded", options={"xatol": 1e-12 * p.T})
    return max(float(x1[i]), -float(res.fun)) / p.x_st
