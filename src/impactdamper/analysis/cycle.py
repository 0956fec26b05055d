"""A periodic cycle solved by shooting, checked: admissibility and saltation-matrix stability.

A solution of the shooting equations of :mod:`impactdamper.analysis.shooting` (impact times
and the states after them; the exact flow of eq. 18 of Timofeev et al. 2019 between impacts,
the impact law of eqs. 21-22 at them) becomes a :class:`PeriodicOrbit` here
(:func:`orbit_from_solution`): its impacts ordered as :func:`~impactdamper.core.steady.steady_state`
orders a settled cycle's, its admissibility checked and its Floquet multipliers computed. The
cycles without impacts (``no_contact``, ``stuck``) are solved in closed form
(:func:`closed_form_orbit`). :mod:`impactdamper.analysis.orbits` seeds and solves a cycle,
:mod:`impactdamper.analysis.continuation` follows one along a parameter.

Admissibility (what shooting alone does not check)
----------------------------------------------------
A solution of these equations is a motion of the suppressor only if every impact closes the
gap (closing velocity x2' - x1' > 0) and the gap stays positive between impacts. The latter is
checked with the certified root search :func:`impactdamper.core.events.march` on every flight
(:func:`flight_scan`), which never misses a crossing; an orbit that fails gets the reason (e.g.
"gap negative on (0.2467, 0.6319) T after impact 1", Algorithm No. 1's orbit at Delta0/x_st =
-10, the paper's Fig. 2a; the intervals are read from samples refined by root finding). Each
flight's interior gap minima are also located, for grazing detection.

Stability
---------
The Floquet multipliers are the eigenvalues of the monodromy matrix of exact flows and
saltation matrices (:mod:`impactdamper.analysis.shooting` tells how, and its independent
check); the orbit is stable when every multiplier has modulus < 1. The motions without impacts
are the forced responses of one linear mode: their multipliers are the eigenvalues of e^{M T}
(for ``stuck`` those of the joined bodies, the relative motion being pressed back into contact).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.analysis.shooting import OrbitError, monodromy_matrix
from impactdamper.core.impact_law import impact_matrix, impact_pulse
from impactdamper.core.events import SearchLimitError, Segment, march
from impactdamper.core.model import FREE, STUCK, Model
from impactdamper.core.parameters import Parameters, ScaleMap, state_scale
from impactdamper.core.excursion import max_excursion
from impactdamper.core.settled_cycle import CycleImpact, SteadyState, rescale_steady
from impactdamper.core.trajectory import Event, Trajectory
from impactdamper.core.validation import work_limit_message

__all__ = [
    "PeriodicOrbit",
    "orbit_from_solution",
    "closed_form_orbit",
    "forced_response",
    "rescale_orbit",
    "flight_scan",
    "least_period",
    "impact_states",
]

# Samples of the gap per forcing period when locating its interior minima (then refined).
GAP_SAMPLES_PER_PERIOD = 256


@dataclass(frozen=True)
class PeriodicOrbit(SteadyState):
    """A directly solved cycle: the fields of :class:`SteadyState` plus its checks.

    The regime, impacts, ``cycle_start`` (the impact that ends the longest free flight, as in
    ``steady_state``), ``x1_max`` etc. describe the solved cycle; ``periods`` is the number of
    forcing periods simulated to seed it (0 for Algorithm No. 1), ``residual`` Newton's final
    residual. ``trajectory`` holds two cycles of the exact motion (``sample`` wraps any time
    onto the cycle).

    Attributes
    ----------
    solved : bool
        The cycle was solved directly. False for cycles with persistent contact phases
        (``chatter``) or a seed that never settled: the rest of the fields are then the
        simulated cycle's and ``reason`` says why.
    admissible : bool
        Every impact closes the gap and the gap stays positive between impacts.
    stable : bool or None
        All Floquet multipliers inside the unit circle (None if not solved).
    multipliers : ndarray of complex, shape (m,)
        Floquet multipliers, largest modulus first (m = 4 for impacting and no-contact
        cycles, 2 for ``stuck``; empty if not solved).
    reason : str
        Why the orbit is not admissible or not solved ("" otherwise).
    seed : str
        ``"alg1"``, ``"simulate"``, ``"closed_form"`` or ``"orbit"`` (from another orbit).
    newton_iterations : int
    min_gap : float
        Smallest interior local minimum of Delta/x_st over the cycle's flights (how close the
        orbit comes to the stop between impacts; inf if the gap has no interior minimum).
    min_velocity : float
        Smallest closing velocity over x_st omega (inf without impacts).
    times : ndarray, shape (z,)
        Absolute impact times, s (t_1 in [0, T)).
    states_after, states_before : ndarray, shape (z, 4)
        (x1, x2, x1', x2') just after / before each impact.
    """

    solved: bool = True
    admissible: bool = False
    stable: bool | None = None
    multipliers: np.ndarray = field(default_factory=lambda: np.zeros(0, complex), repr=False, compare=False)
    reason: str = ""
    seed: str = ""
    newton_iterations: int = 0
    min_gap: float = math.inf
    min_velocity: float = math.inf
    times: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False, compare=False)
    states_after: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)), repr=False, compare=False)
    states_before: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)), repr=False, compare=False)

    @property
    def spectral_radius(self) -> float:
        """Largest multiplier modulus (nan if not solved)."""
        return float(abs(self.multipliers[0])) if len(self.multipliers) else math.nan

    def _wrap(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if self.solved:
            t = self.cycle_start + np.mod(t - self.cycle_start, self.cycle_duration)
        return t

    def sample(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Relative coordinates (x1_bar, x2_bar) at any absolute times t (the cycle repeats)."""
        return super().sample(self._wrap(t))

    def state(self, t: np.ndarray | float) -> np.ndarray:
        """Full states (x1, x2, x1', x2') at any absolute times t, shape t.shape + (4,) (just
        after an impact at impact times). A start for the simulation on the cycle."""
        return self.trajectory.sample(self._wrap(t))[0]

    def monodromy(self, t_section: float | None = None) -> np.ndarray:
        """Monodromy matrix of the cycle, shape (4, 4) (or (2, 2) for ``stuck``).

        Parameters
        ----------
        t_section : float, optional
            Absolute time (s) of the section y(t_s) -> y(t_s + k T); it must not be an impact
            time. Default: just after the cycle's first impact.
        """
        if not self.solved:
            raise OrbitError(f"the cycle was not solved directly ({self.reason})")
        model = Model(self.p)
        Tc = self.cycle_duration
        if self.regime in ("no_contact", "stuck"):
            return model.mode(STUCK if self.regime == "stuck" else FREE).propagator(Tc)
        return monodromy_matrix(model, self.times, self.states_before, Tc, t_section)

    def to_dict(self) -> dict:
        """The JSON object of ``python -m impactdamper orbit --json``: the keys of
        ``steady --json`` plus ``solved``, ``admissible``, ``stable``, ``multipliers`` (moduli,
        largest first), ``multipliers_complex`` ([re, im] pairs), ``reason``, ``seed``,
        ``newton_iterations``, ``min_gap`` and ``min_velocity_rel``."""
        d = super().to_dict()
        d.update(
            solved=self.solved,
            admissible=self.admissible,
            stable=self.stable,
            multipliers=[float(abs(m)) for m in self.multipliers],
            multipliers_complex=[[float(m.real), float(m.imag)] for m in self.multipliers],
            reason=self.reason,
            seed=self.seed,
            newton_iterations=self.newton_iterations,
            min_gap=self.min_gap,
            min_velocity_rel=self.min_velocity,
        )
        return d


# ----------------------------------------------------------------------------------------
# Admissibility: the gap between impacts
# ----------------------------------------------------------------------------------------
def flight_scan(model: Model, t_a: float, y_a: np.ndarray, t_b: float, v_end: float, gap_tol: float):
    """Check one flight (t_a, t_b) between impacts: where the gap first reaches the stop, where it
    is negative, and its interior minima.

    The first contact is certified (:func:`~impactdamper.core.events.march` never skips a root). The negative-gap
    intervals and the minima describe it, from samples refined by root finding and bounded
    minimisation. (The certified search is not alternated between the gap and its negative, as
    a touch of the stop to rounding level would then make no progress.)

    Returns
    -------
    contact : float or None
        First time (since t_a, over T) the gap reaches ``gap_tol * x_st`` while closing, before
        the impact at t_b; None if the flight stays clear of the stop.
    intervals : list of (float, float)
        Where the sampled gap is negative, in units of T since t_a.
    minima : list of (float, float)
        Interior local minima (time since t_a over T, Delta/x_st).
    opens : bool
        The gap opens after the impact at t_a (positive rebound, or for a plastic or grazing
        impact, a positive second or higher derivative).
    """
    p = model.p
    tol = gap_tol * p.x_st
    seg = Segment(model.free, t_a, y_a)
    opens, departure = _departure(model, t_a, y_a)
    contact = _first_contact(model, seg, t_a, t_b, tol, v_end, departure) if opens else 0.0
    intervals, minima = _sampled_gap(model, seg, t_a, t_b)
    return contact, intervals, minima, opens


def _departure(model: Model, t_a: float, y_a: np.ndarray) -> tuple[bool, tuple[int, float] | None]:
    """Whether the gap opens after the impact at t_a, and how (``march``'s ``departure``): by a
    positive rebound, else by its first derivative of order 2-4 that is not at rounding level."""
    p = model.p
    rebound = float(y_a[2] - y_a[3])
    opens = True
    if rebound > 1e-14 * p.x_st * p.omega:
        departure = (1, rebound)
    else:
        departure = None
        derivs = model.gap_derivatives(t_a, y_a, orders=5)
        for order in (2, 3, 4):
            if abs(derivs[order]) > 1e-12 * p.x_st * p.omega**order:
                opens = derivs[order] > 0
                departure = (order, float(derivs[order])) if opens else None
                break
    return opens, departure


def _first_contact(model: Model, seg: Segment, t_a: float, t_b: float, tol: float, v_end: float, departure):
    """The certified first time (since t_a, over T) the gap reaches ``tol`` while closing before
    the impact at t_b (closing at ``v_end``), or None."""
    p, T = model.p, model.p.T
    # The impact ending the flight: a root within this of t_b is that impact.
    end_margin = max(1e-9 * T, 10.0 * tol / v_end) if v_end > 0 else 1e-9 * T
    try:
        root, _ = march(seg, model.gap, t_a, t_b, tol, departure)
    except SearchLimitError as err:
        raise SearchLimitError(work_limit_message(p, str(err))) from None
    if root is not None and root[0] < t_b - end_margin:
        return float((root[0] - t_a) / T)
    return None


def _sampled_gap(model: Model, seg: Segment, t_a: float, t_b: float):
    """The flight's negative-gap intervals and interior minima (:func:`flight_scan`), from
    ``GAP_SAMPLES_PER_PERIOD`` samples per period refined by root finding and bounded
    minimisation."""
    import scipy.optimize  # (loaded on first use: the package import stays light)

    p, T = model.p, model.p.T

    def gap_at(s: float) -> float:
        return float(model.gap_of(seg.state(s)))

    n = max(int(GAP_SAMPLES_PER_PERIOD * (t_b - t_a) / T), 32)
    ts = np.linspace(t_a, t_b, n + 1)
    g = model.gap_of(seg.state(ts))
    g[0] = 0.0  # the impacts, rounding aside
    g[-1] = 0.0
    # Negative-gap intervals: runs of negative samples, their ends refined.
    intervals = []
    negative = g < 0.0
    i = 1
    while i < n:
        if negative[i]:
            j = i
            while j + 1 < n and negative[j + 1]:
                j += 1
            # (A run touching an impact starts or ends there: the gap is zero at impacts.)
            start = t_a if i == 1 else scipy.optimize.brentq(gap_at, ts[i - 1], ts[i], xtol=1e-14 * T)
            end = t_b if j + 1 == n else scipy.optimize.brentq(gap_at, ts[j], ts[j + 1], xtol=1e-14 * T)
            intervals.append((float((start - t_a) / T), float((end - t_a) / T)))
            i = j + 1
        else:
            i += 1
    # Interior local minima: samples, refined on their brackets.
    minima = []
    for i in np.flatnonzero((g[1:-1] <= g[:-2]) & (g[1:-1] <= g[2:])) + 1:
        res = scipy.optimize.minimize_scalar(
            gap_at, bounds=(ts[i - 1], ts[i + 1]), method="bounded", options={"xatol": 1e-14 * T}
        )
        minima.append((float((res.x - t_a) / T), float(res.fun) / p.x_st))
    return intervals, minima


def orbit_from_solution(
    p: Parameters,
    model: Model,
    k: int,
    times: np.ndarray,
    after: np.ndarray,
    seed: str,
    iterations: int,
    residual: float,
    periods: int,
    gap_tol: float,
) -> PeriodicOrbit:
    """The checked cycle of a solution of the shooting equations.

    Orders the impacts from the one ending the longest flight (as :func:`steady_state`),
    checks admissibility (closing velocities > 0 and, with the certified search of
    :func:`flight_scan`, a positive gap between impacts), and computes the Floquet
    multipliers from the monodromy matrix of saltation matrices and exact flows.

    Parameters
    ----------
    p : Parameters
    model : Model
        ``Model(p)``.
    k : int
        Period multiple.
    times : ndarray, shape (z,)
        Impact times, s, increasing within one cycle.
    after : ndarray, shape (z, 4)
        States just after them.
    seed : str
        Recorded in :attr:`PeriodicOrbit.seed`.
    iterations, residual, periods :
        Recorded (Newton's iterations and final residual, forcing periods simulated).
    gap_tol : float
        Relative gap tolerance of the certified search.
    """
    T, Tc = p.T, k * p.T
    times, after, before = _from_longest_flight(model, times, after, Tc)
    velocities = before[:, 3] - before[:, 2]
    reasons, min_gap = _admissibility(model, times, after, velocities, Tc, gap_tol)
    mult = _floquet_multipliers(monodromy_matrix(model, times, before, Tc))
    traj = _two_cycles(model, times, after, before, velocities, Tc)
    impacts = tuple(
        CycleImpact(float(t), float((t - times[0]) / T), float((t / T) % 1.0), float(v), float(impact_pulse(p, v)))
        for t, v in zip(times, velocities)
    )
    return PeriodicOrbit(
        p=p,
        regime="single_impact" if (k == 1 and len(times) == 1) else "multi_impact",
        period_multiple=k,
        impacts=impacts,
        cycle_start=float(times[0]),
        contact_fraction=0.0,
        contact_phases=(),
        x1_max=max_excursion(p, traj, times[0], times[0] + Tc),
        periods=periods,
        residual=residual,
        trajectory=traj,
        solved=True,
        admissible=not reasons,
        stable=bool(np.max(np.abs(mult)) < 1.0),
        multipliers=mult,
        reason="; ".join(reasons),
        seed=seed,
        newton_iterations=iterations,
        min_gap=min_gap,
        min_velocity=float(np.min(velocities) / (p.x_st * p.omega)),
        times=times,
        states_after=after.copy(),
        states_before=before.copy(),
    )


def _from_longest_flight(model: Model, times: np.ndarray, after: np.ndarray, Tc: float):
    """The cycle's impact times (the first in [0, T): the forcing is T-periodic), states after
    and states before each impact, in order from the impact that ends the longest flight (as
    :func:`~impactdamper.core.steady.steady_state` reports a cycle)."""
    T, z = model.p.T, len(times)
    times = np.asarray(times, float) - math.floor(times[0] / T) * T
    t_next = np.append(times[1:], times[0] + Tc)
    # Flight i ends in the state before impact i + 1: rolled, before[j] is impact j's.
    before = np.roll(np.array([model.free.state(t_next[i], times[i], after[i]) for i in range(z)]), 1, axis=0)
    first = int(np.argmax(np.roll(t_next - times, 1)))
    order = [(first + m) % z for m in range(z)]
    times = np.array([times[i] + (Tc if i < first else 0.0) for i in order])
    return times - math.floor(times[0] / T) * T, after[order], before[order]


def _admissibility(model: Model, times, after, velocities, Tc: float, gap_tol: float) -> tuple[list[str], float]:
    """Why the cycle is not a motion of the suppressor (no reason: admissible), and its least
    interior gap minimum over x_st: each impact must close the gap, and each flight keep it
    positive (:func:`flight_scan`)."""
    p, z = model.p, len(times)
    t_next = np.append(times[1:], times[0] + Tc)
    reasons = []
    if np.any(velocities <= 0.0):
        i = int(np.argmin(velocities))
        reasons.append(f"impact {i + 1} has closing velocity {velocities[i] / (p.x_st * p.omega):.6g} x_st omega <= 0")
    min_gap = math.inf
    for i in range(z):
        contact, intervals, minima, opens = flight_scan(
            model, times[i], after[i], t_next[i], float(velocities[(i + 1) % z]), gap_tol
        )
        if not opens:
            reasons.append(f"the gap does not open after impact {i + 1}")
        elif intervals:
            ivs = ", ".join(f"({a:.4f}, {b:.4f})" for a, b in intervals)
            reasons.append(f"gap negative on {ivs} T after impact {i + 1}")
        elif contact is not None:
            reasons.append(f"the gap reaches the stop {contact:.4f} T after impact {i + 1} (a grazing touch)")
        min_gap = min([min_gap] + [m[1] for m in minima])
    return reasons, min_gap


def _two_cycles(model: Model, times, after, before, velocities, Tc: float) -> Trajectory:
    """Two cycles of the exact motion: a free flight from each impact, the impacts as events."""
    traj = Trajectory(model)
    R_of = impact_matrix(model.p)
    for c in range(2):
        for i in range(len(times)):
            t_i = times[i] + c * Tc
            v = float(velocities[i])
            impulse = float(impact_pulse(model.p, velocities[i]))
            traj.events.append(Event(t_i, "impact", v, impulse, before[i].copy(), (R_of @ before[i]).copy(), t_i))
            traj.segments.append((FREE, Segment(model.free, t_i, after[i])))
    return traj


def _floquet_multipliers(monodromy: np.ndarray) -> np.ndarray:
    """The eigenvalues of a monodromy matrix, largest modulus first."""
    mult = np.linalg.eigvals(monodromy)
    return mult[np.argsort(-np.abs(mult), kind="stable")]


def forced_response(model: Model, regime: str):
    """The linear mode of a cycle without impacts (``no_contact``: the free mode, ``stuck``: the
    joined bodies), the functional that must stay positive on its forced response (the gap, the
    contact force) and its scale. On the forced response the functional is g0 + Im(G e^{i w t}):
    its least value is g0 - |G|."""
    if regime == "no_contact":
        return model.free, model.gap, model.p.x_st
    return model.stuck, model.contact_force, model.force_scale


def closed_form_orbit(p: Parameters, regime: str, periods: int = 0) -> PeriodicOrbit:
    """The no-contact or persistent-contact cycle: the forced response of one mode."""
    model = Model(p)
    T = p.T
    mode, fn, scale = forced_response(model, regime)
    what = "gap" if regime == "no_contact" else "contact force"
    least = (fn.g0 - abs(fn.G)) / scale
    # (Im(G e^{iwt}) = |G| sin(wt + arg G) is least where wt + arg G = -pi/2.)
    t_least = ((-0.5 * math.pi - math.atan2(fn.G.imag, fn.G.real)) / p.omega) % T
    admissible = least > 0.0
    reason = (
        ""
        if admissible
        else (
            f"the {what} of the forced response reaches {least:.6g} (relative) at phase {t_least / T:.6f}: "
            + ("the bodies would overlap" if regime == "no_contact" else "the stop would have to pull")
        )
    )
    mult = _floquet_multipliers(mode.propagator(T))
    traj = Trajectory(model)
    traj.segments.append((STUCK if regime == "stuck" else FREE, Segment(mode, 0.0, mode.forced(0.0))))
    min_gap = least if regime == "no_contact" else 0.0
    return PeriodicOrbit(
        p=p,
        regime=regime,
        period_multiple=1,
        impacts=(),
        cycle_start=0.0,
        contact_fraction=1.0 if regime == "stuck" else 0.0,
        contact_phases=((0.0, 1.0),) if regime == "stuck" else (),
        x1_max=float(abs(mode.Yhat[0])) / p.x_st,
        periods=periods,
        residual=0.0,
        trajectory=traj,
        solved=True,
        admissible=admissible,
        stable=bool(np.max(np.abs(mult)) < 1.0),
        multipliers=mult,
        reason=reason,
        seed="closed_form",
        min_gap=min_gap,
    )


def rescale_orbit(o: PeriodicOrbit, scales: ScaleMap) -> PeriodicOrbit:
    """The same orbit in ``scales.target``'s units (relative fields and multipliers unchanged)."""
    base = rescale_steady(o, scales)
    return dataclasses.replace(
        base,
        times=scales.apply(o.times, "time"),
        states_after=scales.full(o.states_after),
        states_before=scales.full(o.states_before),
    )


def least_period(p: Parameters, k: int, times: np.ndarray, after: np.ndarray, tol: float) -> int:
    """The least d | k such that the cycle of period k T with impacts at ``times`` (s) and states
    just after them ``after`` is a cycle of period d T repeated: its impacts recur after d T to
    ``tol`` (in units of T, and of x_st and x_st omega)."""
    T, z = p.T, len(times)
    for d in range(1, k):
        m = z * d // k
        if k % d or (z * d) % k or m == 0:
            continue
        dt = times[m:] - times[:-m] - d * T
        dy = (after[m:] - after[:-m]) / state_scale(p)
        if np.all(np.abs(dt) < tol * T) and np.all(np.abs(dy) < tol):
            return d
    return k


def impact_states(s: SteadyState) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and states (x1, x2, x1', x2') just after the impacts of a settled cycle, read
    from its trajectory: a seed of the Newton shooting."""
    T = s.p.T
    events = s.trajectory.impacts(s.cycle_start - 1e-9 * T, s.cycle_start + max(s.period_multiple, 1) * T)
    nearest = [min(events, key=lambda e: abs(e.t - imp.t)) for imp in s.impacts]
    return np.array([e.t for e in nearest]), np.array([e.after for e in nearest])
