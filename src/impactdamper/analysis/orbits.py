"""Periodic orbits solved directly: shooting, admissibility, saltation-matrix stability.

Simulating until the motion settles (:func:`impactdamper.core.steady.steady_state`) is slow near
bifurcations and never shows an unstable orbit. Here a cycle of period T_c = k T with z
impacts is solved for directly, with the exact flow between impacts (eq. 18 of Timofeev et
al. 2019, :mod:`impactdamper.core.linear`) and the impact law of eqs. (21)-(22).

The cycle is the solution of the shooting equations of :mod:`impactdamper.analysis.shooting`
(unknowns: the impact times and the states after the impacts; equations: the gap of eq. 20
at each flight's end, the impact law between flights), solved by Newton's method.

Admissibility (what shooting alone does not check)
----------------------------------------------------
A solution of these equations is a motion of the suppressor only if every impact closes the
gap (closing velocity x2' - x1' > 0) and the gap stays positive between impacts. The latter is
checked with the certified root search :func:`impactdamper.core.events.first_root` on every flight,
which never misses a crossing; an orbit that fails gets the reason (e.g. "gap negative on
(0.2467, 0.6319) T after impact 1", Algorithm No. 1's orbit at Delta0/x_st = -10, the paper's
Fig. 2a; the intervals are read from samples refined by root finding). Each flight's interior
gap minima are also located, for grazing detection.

Stability
---------
The Floquet multipliers are the eigenvalues of the monodromy matrix of exact flows and
saltation matrices (:func:`impactdamper.analysis.shooting.monodromy_matrix`); the orbit is
stable when every multiplier has modulus < 1.
:func:`impactdamper.analysis.strobe.stroboscopic_jacobian` is the independent check: the
finite-difference Jacobian of the map y(t_s) -> y(t_s + k T) computed with the event-driven
solver.

Scope
-----
Impacting cycles without persistent contact get the full treatment. The motion without
contact and the motion with the bodies in contact all the time (regimes ``no_contact`` and
``stuck``) are the forced responses of one linear mode, solved in closed form (their
multipliers are the eigenvalues of e^{M T}; for ``stuck`` those of the joined bodies, the
relative motion being pressed back into contact). Cycles with a phase of persistent contact
reached through an accumulation of impacts (``chatter``) are not solved: the result then
carries the simulated cycle with ``solved = False`` and the reason.

Branches of these cycles in one parameter (pseudo-arclength continuation, folds, period
doublings, grazings) are followed by :mod:`impactdamper.analysis.continuation`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.analysis.shooting import OrbitError, Shooting, impact_matrix, monodromy_matrix
from impactdamper.core.algorithm1 import Algorithm1Result, algorithm1, rescale_algorithm1
from impactdamper.core.events import SearchLimitError, Segment, first_root
from impactdamper.core.model import FREE, STUCK, Model
from impactdamper.core.parameters import ArgumentTypeError, Parameters, ScaleMap, require_parameters
from impactdamper.core.simulate import Event, Tolerances, Trajectory
from impactdamper.core.validation import (
    check_state,
    check_tolerances,
    finite_argument,
    integer_argument,
    work_limit_message,
)
from impactdamper.core.steady import (
    CycleImpact,
    SteadyState,
    max_excursion,
    rescale_steady,
    start_in_first_period,
    steady_state,
)

__all__ = [
    "PeriodicOrbit",
    "OrbitError",
    "solve_orbit",
    "orbit_from_cycle",
    "orbit_from_algorithm1",
    "stable_algorithm1_orbit",
    "orbit_from_solution",
    "rescale_orbit",
    "flight_scan",
    "SEEDS",
]

# Samples of the gap per forcing period when locating its interior minima (then refined).
GAP_SAMPLES_PER_PERIOD = 256
# Ways to seed the direct solve.
SEEDS = ("auto", "alg1", "simulate")
# Bounds on the work of one direct solve: the largest period multiple k (as the workflow's
# max_period_multiple) and the most impacts per cycle (Newton solves 5 z equations densely).
MAX_ORBIT_PERIOD_MULTIPLE = 64
MAX_ORBIT_IMPACTS = 512


# ----------------------------------------------------------------------------------------
# The result
# ----------------------------------------------------------------------------------------
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
        return monodromy_matrix(model, self.times, self.states_after, self.states_before, Tc, t_section)

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

    The first contact is certified (:func:`first_root` never skips a root). The negative-gap
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
    p, T = model.p, model.p.T
    tol = gap_tol * p.x_st
    seg = Segment(model.free, t_a, y_a)
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
    # The impact ending the flight: a root within this of t_b is that impact.
    end_margin = max(1e-9 * T, 10.0 * tol / v_end) if v_end > 0 else 1e-9 * T
    contact = None
    if opens:
        try:
            root = first_root(seg, model.gap, t_a, t_b, tol, departure)
        except SearchLimitError as err:
            raise SearchLimitError(work_limit_message(p, str(err))) from None
        if root is not None and root[0] < t_b - end_margin:
            contact = float((root[0] - t_a) / T)
    else:
        contact = 0.0

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
            import scipy.optimize  # (loaded on first use: the package import stays light)

            start = t_a if i == 1 else scipy.optimize.brentq(gap_at, ts[i - 1], ts[i], xtol=1e-14 * T)
            end = t_b if j + 1 == n else scipy.optimize.brentq(gap_at, ts[j], ts[j + 1], xtol=1e-14 * T)
            intervals.append((float((start - t_a) / T), float((end - t_a) / T)))
            i = j + 1
        else:
            i += 1
    # Interior local minima: samples, refined on their brackets.
    minima = []
    for i in np.flatnonzero((g[1:-1] <= g[:-2]) & (g[1:-1] <= g[2:])) + 1:
        import scipy.optimize  # (loaded on first use: the package import stays light)

        res = scipy.optimize.minimize_scalar(
            gap_at, bounds=(ts[i - 1], ts[i + 1]), method="bounded", options={"xatol": 1e-14 * T}
        )
        minima.append((float((res.x - t_a) / T), float(res.fun) / p.x_st))
    return contact, intervals, minima, opens


# ----------------------------------------------------------------------------------------
# Building the result
# ----------------------------------------------------------------------------------------
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
    T, z = p.T, len(times)
    Tc = k * T
    # Times into [0, T) for the first impact (the forcing is T-periodic).
    shift = math.floor(times[0] / T) * T
    times = np.asarray(times, float) - shift
    t_next = np.append(times[1:], times[0] + Tc)
    before = np.array([model.free.state(t_next[i], times[i], after[i]) for i in range(z)])
    # before[i] ends flight i, i.e. it is the state before impact i+1. Reorder so that impact
    # j's state before is before_of[j].
    before_of = np.roll(before, 1, axis=0)
    velocities = before_of[:, 3] - before_of[:, 2]
    # The cycle starts at the impact ending the longest flight (as steady_state reports it).
    flights_into = np.roll(t_next - times, 1)
    first = int(np.argmax(flights_into))
    order = [(first + m) % z for m in range(z)]
    times = np.array([times[i] + (Tc if i < first else 0.0) for i in order])
    shift = math.floor(times[0] / T) * T
    times = times - shift
    after, before_of, velocities = after[order], before_of[order], velocities[order]
    t_next = np.append(times[1:], times[0] + Tc)

    # Admissibility.
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
    admissible = not reasons

    # Stability.
    mono = monodromy_matrix(model, times, after, before_of, Tc)
    mult = np.linalg.eigvals(mono)
    mult = mult[np.argsort(-np.abs(mult), kind="stable")]
    stable = bool(np.max(np.abs(mult)) < 1.0)

    traj = Trajectory(model)
    R_of = impact_matrix(p)
    for c in range(2):
        for i in range(z):
            t_i = times[i] + c * Tc
            D = p.reduced_mass * (1.0 + p.R)
            traj.events.append(
                Event(
                    t_i,
                    "impact",
                    float(velocities[i]),
                    float(D * velocities[i]),
                    before_of[i].copy(),
                    (R_of @ before_of[i]).copy(),
                    t_i,
                )
            )
            traj.segments.append((FREE, Segment(model.free, t_i, after[i])))
    impacts = tuple(
        CycleImpact(
            float(t), float((t - times[0]) / T), float((t / T) % 1.0), float(v), float(p.reduced_mass * (1.0 + p.R) * v)
        )
        for t, v in zip(times, velocities)
    )
    regime = "single_impact" if (k == 1 and z == 1) else "multi_impact"
    return PeriodicOrbit(
        p=p,
        regime=regime,
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
        admissible=admissible,
        stable=stable,
        multipliers=mult,
        reason="; ".join(reasons),
        seed=seed,
        newton_iterations=iterations,
        min_gap=min_gap,
        min_velocity=float(np.min(velocities) / (p.x_st * p.omega)),
        times=times,
        states_after=after.copy(),
        states_before=before_of.copy(),
    )


def orbit_from_cycle(
    p: Parameters,
    period_multiple: int,
    times,
    states_after,
    *,
    seed: str = "orbit",
    periods: int = 0,
    tolerances: Tolerances | None = None,
) -> PeriodicOrbit:
    """Solve the cycle of period ``period_multiple`` T seeded by impact times and states.

    Parameters
    ----------
    p : Parameters
    period_multiple : int
        k in T_c = k T.
    times : array_like, shape (z,)
        Approximate absolute impact times, s, increasing, within one cycle.
    states_after : array_like, shape (z, 4)
        Approximate (x1, x2, x1', x2') just after each impact.

    Raises
    ------
    OrbitError
        If Newton does not converge (the message says how far it got).
    """
    p = require_parameters(p)
    period_multiple = integer_argument("period_multiple", period_multiple, 1, MAX_ORBIT_PERIOD_MULTIPLE)
    try:
        times = np.asarray(times, float).reshape(-1)
        states = np.asarray(states_after, float)
    except (TypeError, ValueError):
        raise ArgumentTypeError("`times` and `states_after` are not allowed: must be arrays of numbers") from None
    if len(times) == 0 or not np.all(np.isfinite(times)) or np.any(np.diff(times) <= 0):
        raise ValueError(f"`times` = {times!r} is not allowed: must be at least one finite, increasing impact time")
    if len(times) > MAX_ORBIT_IMPACTS:
        raise ValueError(f"`times` is not allowed: {len(times)} impacts, at most {MAX_ORBIT_IMPACTS} per cycle")
    if states.shape != (len(times), 4) or not np.all(np.isfinite(states)):
        raise ValueError(
            f"`states_after` is not allowed: must be {len(times)} finite rows (x1, x2, x1', x2'), "
            f"got shape {states.shape}"
        )
    tol = check_tolerances(tolerances)
    if not p.native_scales():
        q = p.canonical()
        to_q = ScaleMap(p, q)
        o = orbit_from_cycle(
            q, period_multiple, to_q.apply(times, "time"), to_q.full(states), seed=seed, periods=periods, tolerances=tol
        )
        return rescale_orbit(o, ScaleMap(q, p))
    # The forcing is T-periodic: shift the cycle so the first impact is in [0, T). Large
    # absolute times would cost digits in sin(omega t) (~1e-13 after 500 periods).
    times = times - math.floor(times[0] / p.T) * p.T
    model = Model(p)
    shoot = Shooting(p, period_multiple, len(times), model)
    u, iterations, residual = shoot.newton(shoot.pack(times, states))
    t, y = shoot.times_states(u)
    return orbit_from_solution(p, model, period_multiple, t, y, seed, iterations, residual, periods, tol.gap_tol)


def _closed_form_orbit(p: Parameters, regime: str, periods: int = 0) -> PeriodicOrbit:
    """The no-contact or persistent-contact cycle: the forced response of one mode."""
    model = Model(p)
    T = p.T
    if regime == "no_contact":
        mode, fn, what = model.free, model.gap, "gap"
        scale = p.x_st
    else:
        mode, fn, what = model.stuck, model.contact_force, "contact force"
        scale = model.force_scale
    # On the forced response the functional is g0 + Im(G e^{i w t}): its minimum is g0 - |G|.
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
    mult = np.linalg.eigvals(mode.propagator(T))
    mult = mult[np.argsort(-np.abs(mult), kind="stable")]
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


def _unsolved(steady: SteadyState, reason: str) -> PeriodicOrbit:
    base = {f.name: getattr(steady, f.name) for f in dataclasses.fields(SteadyState)}
    return PeriodicOrbit(**base, solved=False, admissible=False, stable=None, reason=reason, seed="simulate")


def _from_steady(steady: SteadyState, period_multiple: int | None, tolerances: Tolerances | None) -> PeriodicOrbit:
    p = steady.p
    if steady.regime == "nonperiodic":
        return _unsolved(
            steady,
            f"the simulated motion did not settle within {steady.periods} periods (nonperiodic): no cycle to solve for",
        )
    if steady.regime == "chatter":
        return _unsolved(
            steady,
            "the cycle has a phase of persistent contact reached through an accumulation "
            "of impacts (chatter): the direct solve does not apply; values are the simulated cycle's",
        )
    k = steady.period_multiple
    m = _repeat_factor(period_multiple, k)
    if steady.regime in ("no_contact", "stuck"):
        if m != 1:
            raise ValueError(
                f"`period_multiple` = {period_multiple!r} is not allowed: the {steady.regime} motion has period T"
            )
        return _closed_form_orbit(p, steady.regime, steady.periods)
    times, after = [], []
    for imp in steady.impacts:
        e = min(steady.trajectory.impacts(imp.t - 1e-9 * p.T, imp.t + 1e-9 * p.T), key=lambda e: abs(e.t - imp.t))
        times.append(e.t)
        after.append(e.after)
    times, after = _repeat(np.array(times), np.array(after), k, m, p.T)
    return orbit_from_cycle(p, k * m, times, after, seed="simulate", periods=steady.periods, tolerances=tolerances)


def _repeat_factor(period_multiple: int | None, k: int) -> int:
    if period_multiple is None:
        return 1
    if not (isinstance(period_multiple, (int, np.integer)) and period_multiple >= 1 and period_multiple % k == 0):
        raise ValueError(
            f"`period_multiple` = {period_multiple!r} is not allowed: must be a positive multiple of "
            f"the seed's period multiple {k}"
        )
    return period_multiple // k


def _repeat(times: np.ndarray, after: np.ndarray, k: int, m: int, T: float):
    """The cycle of k T repeated m times, as one cycle of m k T."""
    return (np.concatenate([times + j * k * T for j in range(m)]), np.concatenate([after] * m))


def solve_orbit(
    p: Parameters,
    seed: str | SteadyState | Algorithm1Result = "auto",
    *,
    period_multiple: int | None = None,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    settle_tol: float = 1e-10,
    max_periods: int = 4000,
    max_period_multiple: int = 8,
) -> PeriodicOrbit:
    """Solve a periodic cycle directly (Newton shooting), check it and find its multipliers.

    Parameters
    ----------
    p : Parameters
    seed : {"auto", "alg1", "simulate"} or SteadyState or Algorithm1Result
        ``"alg1"``: Algorithm No. 1's one-impact orbit (exact already; Newton only confirms
        it), reported even when it is not admissible. ``"simulate"``: the settled cycle of
        :func:`steady_state` (with ``t0``, ``state``, ``tolerances``, ``settle_tol``,
        ``max_periods``, ``max_period_multiple``). ``"auto"``: Algorithm No. 1's orbit if it
        is admissible and stable, else ``"simulate"``. A SteadyState or Algorithm1Result
        already computed may be given instead.
    period_multiple : int, optional
        Solve for the seed's cycle repeated to this period multiple (a multiple of the seed's
        k, at most ``MAX_ORBIT_PERIOD_MULTIPLE``); default the seed's own.

    Returns
    -------
    PeriodicOrbit

    Raises
    ------
    OrbitError
        Newton did not converge, or Algorithm No. 1 has no orbit (seed ``"alg1"``).
    TypeError, ValueError
        A bad argument, named (``state`` or ``t0`` with seed ``"alg1"``, which has no start).
    SearchLimitError
        The seed's simulation exceeded its work bound.
    """
    p = require_parameters(p)
    tolerances = check_tolerances(tolerances)
    t0 = finite_argument("t0", t0)
    state = check_state(state, p)  # (checked even where "auto" takes Algorithm No. 1's orbit)
    if period_multiple is not None:
        period_multiple = integer_argument("period_multiple", period_multiple, 1, MAX_ORBIT_PERIOD_MULTIPLE)
    if isinstance(seed, str) and seed == "alg1":
        for name, given in (("state", state is not None), ("t0", t0 != 0.0)):
            if given:
                raise ValueError(
                    f"`{name}` is not allowed with seed = 'alg1': Algorithm No. 1's orbit is closed-form and "
                    "has no start (seed 'simulate' starts from it)"
                )
    if not p.native_scales():
        # The same relative problem in the reference case's units, converted back.
        q = p.canonical()
        to_q = ScaleMap(p, q)
        if isinstance(seed, Algorithm1Result):
            seed = rescale_algorithm1(seed, to_q)
        elif isinstance(seed, PeriodicOrbit):
            seed = rescale_orbit(seed, to_q)
        elif isinstance(seed, SteadyState):
            seed = rescale_steady(seed, to_q)
        o = solve_orbit(
            q,
            seed,
            period_multiple=period_multiple,
            t0=to_q.apply(start_in_first_period(p, t0), "time"),
            state=None if state is None else to_q.full(state),
            tolerances=tolerances,
            settle_tol=settle_tol,
            max_periods=max_periods,
            max_period_multiple=max_period_multiple,
        )
        return rescale_orbit(o, ScaleMap(q, p))
    if isinstance(seed, str):
        if seed not in SEEDS:
            raise ValueError(f"`seed` = {seed!r} is not allowed: must be one of {', '.join(SEEDS)}")
        if seed in ("alg1", "auto"):
            try:
                a1 = algorithm1(p, gap_tol=tolerances.gap_tol)
            except (ValueError, SearchLimitError):
                if seed == "alg1":
                    raise
                a1 = None  # auto: no closed-form orbit here (a resonance of the impacts): simulate
            if seed == "alg1":
                if not a1.exists:
                    raise OrbitError(f"Algorithm No. 1 has no orbit: {a1.reason}")
                return orbit_from_algorithm1(a1, period_multiple, tolerances)
            orbit = stable_algorithm1_orbit(a1, period_multiple, tolerances)
            if orbit is not None:
                return orbit
        seed = steady_state(
            p,
            t0=t0,
            state=state,
            tolerances=tolerances,
            settle_tol=settle_tol,
            max_periods=max_periods,
            max_period_multiple=max_period_multiple,
        )
    if isinstance(seed, Algorithm1Result):
        if not seed.exists:
            raise OrbitError(f"Algorithm No. 1 has no orbit: {seed.reason}")
        return orbit_from_algorithm1(seed, period_multiple, tolerances)
    if isinstance(seed, SteadyState):
        return _from_steady(seed, period_multiple, tolerances)
    raise ValueError(
        f"`seed` = {seed!r} is not allowed: must be one of {', '.join(SEEDS)}, a SteadyState or an Algorithm1Result"
    )


def orbit_from_algorithm1(
    a1: Algorithm1Result, period_multiple: int | None = None, tolerances: Tolerances | None = None
) -> PeriodicOrbit:
    """Algorithm No. 1's one-impact orbit (eqs. 7-17) confirmed by the Newton shooting.

    Parameters
    ----------
    a1 : Algorithm1Result
        An existing orbit (``a1.exists``).
    period_multiple : int, optional
        Solve it repeated to this period multiple (default 1).
    tolerances : Tolerances, optional
        Event-solver tolerances (the gap tolerance of the admissibility check).

    Raises
    ------
    OrbitError
        If Newton does not converge.
    """
    m = _repeat_factor(period_multiple, 1)
    times, after = _repeat(np.array([a1.t_impact]), np.array([a1.state_after]), 1, m, a1.p.T)
    return orbit_from_cycle(a1.p, m, times, after, seed="alg1", tolerances=tolerances)


def stable_algorithm1_orbit(
    a1: Algorithm1Result | None, period_multiple: int | None = None, tolerances: Tolerances | None = None
) -> PeriodicOrbit | None:
    """Algorithm No. 1's orbit if it exists, is admissible, and its Newton-confirmed cycle is
    admissible and stable (an attractor); else None.

    The cheap route to a settled one-impact motion: no transient is simulated. Used by
    :func:`solve_orbit` (seed ``"auto"``) and
    ``impactdamper.steady_state(p, attractor=True)``.

    Parameters
    ----------
    a1 : Algorithm1Result or None
        None where Algorithm No. 1 failed (a resonance of the impacts).
    period_multiple : int, optional
        As for :func:`orbit_from_algorithm1`.
    tolerances : Tolerances, optional
    """
    if a1 is None or not (a1.exists and a1.admissible):
        return None
    try:
        orbit = orbit_from_algorithm1(a1, period_multiple, tolerances)
    except OrbitError:
        return None
    return orbit if (orbit.admissible and orbit.stable) else None
