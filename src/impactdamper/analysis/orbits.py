"""Periodic orbits solved directly: shooting, admissibility, saltation-matrix stability.

Simulating until the motion settles (:func:`impactdamper.core.steady.steady_state`) is slow near
bifurcations and never shows an unstable orbit. Here a cycle of period T_c = k T with z
impacts is solved for directly, with the exact flow between impacts (eq. 18 of Timofeev et
al. 2019, :mod:`impactdamper.core.linear`) and the impact law of eqs. (21)-(22).

Unknowns and equations (multiple shooting on the impact-to-impact map)
------------------------------------------------------------------------
The unknowns are the impact times and the states just after each impact,

    u = (t_1/T, ..., t_z/T, y_1^+/D, ..., y_z^+/D),    D = diag(x_st, x_st, x_st w, x_st w),

(5 z numbers; w = omega). Flight i is the exact free motion from (t_i, y_i^+) to t_{i+1}
(t_{z+1} = t_1 + k T), ending in the state y_i^-. The equations are, for each flight,

    Delta(y_i^-) / x_st = 0                     (the flight ends on the stop, eq. 20)
    (J_R y_i^- - y_{i+1}^+) / D = 0             (the impact law, eqs. 21-22; y_{z+1}^+ = y_1^+),

with J_R the impact map (linear: the pulse is proportional to the closing velocity). The
forcing is T-periodic, so closing the cycle after k T is periodicity. The Jacobian is exact:
d y_i^-/d y_i^+ = e^{M tau_i}, d y_i^-/d t_i = -e^{M tau_i} f(t_i, y_i^+),
d y_i^-/d t_{i+1} = f(t_{i+1}, y_i^-), with f the vector field of the free mode. Newton
stops when the step is below ``ORBIT_TOL`` (phases in units of T, states relative to D) and
the residual is below ``ORBIT_TOL`` too.

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
The Floquet multipliers are the eigenvalues of the monodromy matrix

    M_c = S_1 e^{M tau_z} S_z ... S_2 e^{M tau_1},

with the saltation matrix of each impact,

    S = J_R + (f^+ - J_R f^-) n^T / (n^T f^-),     n = grad Delta = (1, -1, 0, 0),

which corrects the impact map's Jacobian for the perturbed impact time (Leine & Nijmeijer 2004;
Di Bernardo et al. 2008, ch. 2). The orbit is stable when every multiplier has modulus < 1.
:func:`stroboscopic_jacobian` is the independent check: the finite-difference Jacobian of the
map y(t_s) -> y(t_s + k T) computed with the event-driven solver.

Continuation
------------
:func:`continue_orbit` follows a cycle in any field of :class:`Parameters` by pseudo-arclength
continuation (tangent predictor, bordered Newton corrector, adaptive step). Between
consecutive points it watches test functions and locates their zeros by Brent's method along
the arclength: the tangent's parameter component (fold), det(I + M_c) (period doubling), the
modulus of complex multipliers minus one (Neimark-Sacker), the least closing velocity
(grazing impact: it vanishes) and the least interior gap minimum (grazing touch: a new impact).
A located bifurcation is kept only if a multiplier is on the unit circle there. A grazing is
where the branch's impact sequence stops describing the motion: the branch ends there
(unless asked to go on) with the reason.

Scope
-----
Impacting cycles without persistent contact get the full treatment. The motion without
contact and the motion with the bodies in contact all the time (regimes ``no_contact`` and
``stuck``) are the forced responses of one linear mode, solved in closed form (their
multipliers are the eigenvalues of e^{M T}; for ``stuck`` those of the joined bodies, the
relative motion being pressed back into contact). Cycles with a phase of persistent contact
reached through an accumulation of impacts (``chatter``) are not solved: the result then
carries the simulated cycle with ``solved = False`` and the reason.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.optimize

from impactdamper.core.algorithm1 import Algorithm1Result, algorithm1
from impactdamper.core.algorithm1 import _rescale as _rescale_alg1
from impactdamper.core.events import SearchLimitError, Segment, first_root
from impactdamper.core.model import FREE, STUCK, Model
from impactdamper.core.parameters import (ArgumentTypeError, Parameters, ScaleMap, finite_argument, integer_argument,
                         require_parameters)
from impactdamper.core.simulate import (EventDrivenSolver, Event, Tolerances, Trajectory, check_state, check_tolerances,
                       work_limit_message)
from impactdamper.core.steady import CycleImpact, SteadyState, _max_excursion, rescale_steady, start_in_first_period, steady_state

__all__ = [
    "PeriodicOrbit",
    "solve_orbit",
    "orbit_from_cycle",
    "steady_state_auto",
    "stroboscopic_map",
    "stroboscopic_jacobian",
    "continue_orbit",
    "Branch",
    "BranchPoint",
    "SpecialPoint",
    "SEEDS",
    "OrbitError",
]

# Newton's convergence threshold on the step and the residual, relative (phases in units of
# T, positions to x_st, velocities to x_st omega): the issue asks for 1e-12; rounding of the
# exact flow is ~1e-15 relative, so 1e-12 is reached with room.
ORBIT_TOL = 1e-12
# Newton iterations allowed from a seed (quadratic convergence needs 3-6 from a settled cycle).
NEWTON_MAX_ITERATIONS = 40
# At a fold the Jacobian is singular and the orbit is determined only to ~sqrt(rounding) along
# its null direction: with the residual at ORBIT_TOL, Newton steps that stall below this after
# this many iterations are accepted.
NEWTON_STALL, NEWTON_STALL_STEP = 6, 1e-7
# Samples of the gap per forcing period when locating its interior minima (then refined).
GAP_SAMPLES_PER_PERIOD = 256
# Ways to seed the direct solve.
SEEDS = ("auto", "alg1", "simulate")
# Relative step of the finite-difference derivative in the continuation parameter.
PARAMETER_FD_STEP = 1e-6
# Bounds on the work of one direct solve: the largest period multiple k (as the workflow's
# max_period_multiple) and the most impacts per cycle (Newton solves 5 z equations densely).
MAX_ORBIT_PERIOD_MULTIPLE = 64
MAX_ORBIT_IMPACTS = 512
# Bound on a branch's points (continue_orbit's max_points).
MAX_BRANCH_POINTS = 1_000_000
# Each parameter's domain for continuation bounds: (low, high, low included).
PARAMETER_DOMAIN = {name: (0.0, math.inf, False) for name in ("theta", "mu", "N", "omega", "x_st", "m1")}
PARAMETER_DOMAIN.update(delta1=(0.0, math.inf, True), delta2=(0.0, math.inf, True), R=(0.0, 1.0, True),
                        gap=(-math.inf, math.inf, True))


class OrbitError(ValueError):
    """The direct solve failed (Newton did not converge) or does not apply."""


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
        return _monodromy(model, self.times, self.states_after, self.states_before, Tc, t_section)

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
# Shooting equations
# ----------------------------------------------------------------------------------------
class _Shooting:
    """The 5 z shooting equations of a cycle with z impacts in k T, with exact Jacobian."""

    def __init__(self, p: Parameters, k: int, z: int, model: Model | None = None):
        self.p, self.k, self.z = p, int(k), int(z)
        self.model = model or Model(p)
        self.mode = self.model.free
        self.T = p.T
        self.D = np.array([p.x_st, p.x_st, p.x_st * p.omega, p.x_st * p.omega])
        self.n = np.array([1.0, -1.0, 0.0, 0.0])
        self.JR = _impact_matrix(p)

    def times_states(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        z = self.z
        return u[:z] * self.T, u[z:].reshape(z, 4) * self.D

    def pack(self, times: np.ndarray, states: np.ndarray) -> np.ndarray:
        return np.concatenate([np.asarray(times, float) / self.T, (np.asarray(states, float) / self.D).ravel()])

    def flights(self, u: np.ndarray):
        """Start times, durations, states after and before the impacts ending each flight."""
        t, y = self.times_states(u)
        t_next = np.append(t[1:], t[0] + self.k * self.T)
        tau = t_next - t
        before = np.array([self.mode.state(t_next[i], t[i], y[i]) for i in range(self.z)])
        return t, tau, y, before, t_next

    def residual(self, u: np.ndarray, jacobian: bool = True):
        """Shooting residual F (shape (5 z,)) and its Jacobian (shape (5 z, 5 z)) at u."""
        try:
            with np.errstate(over="raise", invalid="raise"):
                return self._residual(u, jacobian)
        except FloatingPointError:
            raise OrbitError("the shooting equations overflow at this guess") from None

    def _residual(self, u: np.ndarray, jacobian: bool):
        z, T, D, mode = self.z, self.T, self.D, self.mode
        if not np.all(np.isfinite(u)):
            raise OrbitError("non-finite guess")
        t, tau, y, before, t_next = self.flights(u)
        if np.any(tau <= 0.0):
            raise OrbitError("impact times out of order (a flight of non-positive duration)")
        F = np.empty(5 * z)
        F[:z] = self.model.gap_of(before) / self.p.x_st
        after_next = before @ self.JR.T
        F[z:] = ((after_next - np.roll(y, -1, axis=0)) / D).ravel()
        if not jacobian:
            return F, None
        J = np.zeros((5 * z, 5 * z))
        for i in range(z):
            j = (i + 1) % z
            Phi = mode.propagator(tau[i])
            f_start = mode.rhs(t[i], y[i])
            f_end = mode.rhs(t_next[i], before[i])
            # d before_i / d u: columns of phase i, phase j, state i.
            d_phase_i = -Phi @ f_start * T
            d_phase_j = f_end * T
            d_state_i = Phi * D[None, :]
            rows_gap = i
            rows_state = slice(z + 4 * i, z + 4 * i + 4)
            for d_before, cols in ((d_phase_i, [i]), (d_phase_j, [j])):
                J[rows_gap, cols[0]] += self.n @ d_before / self.p.x_st
                J[rows_state, cols[0]] += (self.JR @ d_before) / D
            J[rows_gap, z + 4 * i: z + 4 * i + 4] += self.n @ d_state_i / self.p.x_st
            J[rows_state, z + 4 * i: z + 4 * i + 4] += (self.JR @ d_state_i) / D[:, None]
            J[rows_state, z + 4 * j: z + 4 * j + 4] -= np.eye(4)
        return F, J


def _impact_matrix(p: Parameters) -> np.ndarray:
    """J_R of eqs. (21)-(22): x1' += S/m1, x2' -= S/m2 with S = m_red (1 + R)(x2' - x1')."""
    D = p.reduced_mass * (1.0 + p.R)
    e = np.array([0.0, 0.0, 1.0 / p.m1, -1.0 / p.m2])
    w = np.array([0.0, 0.0, -1.0, 1.0])
    return np.eye(4) + D * np.outer(e, w)


def _saltation(model: Model, t: float, before: np.ndarray) -> np.ndarray:
    """Saltation matrix of the impact at (t, before), shape (4, 4)."""
    JR = _impact_matrix(model.p)
    n = np.array([1.0, -1.0, 0.0, 0.0])
    f_minus = model.free.rhs(t, before)
    f_plus = model.free.rhs(t, JR @ before)
    return JR + np.outer(f_plus - JR @ f_minus, n) / (n @ f_minus)


def _monodromy(model: Model, times: np.ndarray, after: np.ndarray, before: np.ndarray, Tc: float,
               t_section: float | None = None) -> np.ndarray:
    """Product of flows and saltation matrices around the cycle from the section t_section."""
    z = len(times)
    t_next = np.append(times[1:], times[0] + Tc)
    mode = model.free
    if t_section is None:
        start, ts = 0, times[0]
    else:
        s = times[0] + (t_section - times[0]) % Tc
        start = int(np.searchsorted(times, s, side="right") - 1)
        ts = s
    # From the section (inside flight `start`) to the end of that flight, then around.
    M = mode.propagator(t_next[start] - ts)
    for m in range(1, z + 1):
        i = (start + m) % z
        M = _saltation(model, times[i], before[i]) @ M  # impact i (times mod T_c)
        if m == z:
            break
        M = mode.propagator(t_next[i] - times[i]) @ M
    # Back in flight `start` (one cycle later): from its impact to the section.
    M = mode.propagator(ts - times[start]) @ M
    return M


def _newton(shoot: _Shooting, u: np.ndarray, max_iterations: int = NEWTON_MAX_ITERATIONS):
    """Damped Newton on the shooting equations. Returns (u, iterations, residual norm)."""
    F, J = shoot.residual(u)
    norm = float(np.max(np.abs(F)))
    for it in range(1, max_iterations + 1):
        try:
            du = np.linalg.solve(J, -F)
        except np.linalg.LinAlgError as err:
            raise OrbitError(f"singular shooting Jacobian ({err})") from None
        lam = 1.0
        while True:
            u_new = u + lam * du
            try:
                F_new, J_new = shoot.residual(u_new)
                norm_new = float(np.max(np.abs(F_new)))
            except OrbitError:
                norm_new = math.inf
            if norm_new < norm or norm_new <= ORBIT_TOL or lam < 1e-3:
                break
            lam *= 0.5
        if not math.isfinite(norm_new):
            raise OrbitError("Newton left the region where the impact times are ordered")
        step = float(np.max(np.abs(lam * du)))
        u, F, J, norm = u_new, F_new, J_new, norm_new
        if norm <= ORBIT_TOL and (step <= ORBIT_TOL or (it >= NEWTON_STALL and step <= NEWTON_STALL_STEP)):
            return u, it, norm
    raise OrbitError(f"Newton did not converge in {max_iterations} iterations (residual {norm:.3g})")


# ----------------------------------------------------------------------------------------
# Admissibility: the gap between impacts
# ----------------------------------------------------------------------------------------
def _flight_scan(model: Model, t_a: float, y_a: np.ndarray, t_b: float, v_end: float, gap_tol: float):
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
            start = t_a if i == 1 else scipy.optimize.brentq(gap_at, ts[i - 1], ts[i], xtol=1e-14 * T)
            end = t_b if j + 1 == n else scipy.optimize.brentq(gap_at, ts[j], ts[j + 1], xtol=1e-14 * T)
            intervals.append((float((start - t_a) / T), float((end - t_a) / T)))
            i = j + 1
        else:
            i += 1
    # Interior local minima: samples, refined on their brackets.
    minima = []
    for i in np.flatnonzero((g[1:-1] <= g[:-2]) & (g[1:-1] <= g[2:])) + 1:
        res = scipy.optimize.minimize_scalar(gap_at, bounds=(ts[i - 1], ts[i + 1]), method="bounded",
                                             options={"xatol": 1e-14 * T})
        minima.append((float((res.x - t_a) / T), float(res.fun) / p.x_st))
    return contact, intervals, minima, opens


# ----------------------------------------------------------------------------------------
# Building the result
# ----------------------------------------------------------------------------------------
def _orbit_from_solution(p: Parameters, model: Model, k: int, times: np.ndarray, after: np.ndarray,
                         seed: str, iterations: int, residual: float, periods: int,
                         gap_tol: float) -> PeriodicOrbit:
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
        contact, intervals, minima, opens = _flight_scan(model, times[i], after[i], t_next[i],
                                                         float(velocities[(i + 1) % z]), gap_tol)
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
    mono = _monodromy(model, times, after, before_of, Tc)
    mult = np.linalg.eigvals(mono)
    mult = mult[np.argsort(-np.abs(mult), kind="stable")]
    stable = bool(np.max(np.abs(mult)) < 1.0)

    traj = Trajectory(model)
    R_of = _impact_matrix(p)
    for c in range(2):
        for i in range(z):
            t_i = times[i] + c * Tc
            D = p.reduced_mass * (1.0 + p.R)
            traj.events.append(Event(t_i, "impact", float(velocities[i]), float(D * velocities[i]),
                                     before_of[i].copy(), (R_of @ before_of[i]).copy(), t_i))
            traj.segments.append((FREE, Segment(model.free, t_i, after[i])))
    impacts = tuple(CycleImpact(float(t), float((t - times[0]) / T), float((t / T) % 1.0), float(v),
                                float(p.reduced_mass * (1.0 + p.R) * v)) for t, v in zip(times, velocities))
    regime = "single_impact" if (k == 1 and z == 1) else "multi_impact"
    return PeriodicOrbit(
        p=p, regime=regime, period_multiple=k, impacts=impacts, cycle_start=float(times[0]),
        contact_fraction=0.0, contact_phases=(), x1_max=_max_excursion(p, traj, times[0], times[0] + Tc),
        periods=periods, residual=residual, trajectory=traj,
        solved=True, admissible=admissible, stable=stable, multipliers=mult, reason="; ".join(reasons),
        seed=seed, newton_iterations=iterations, min_gap=min_gap,
        min_velocity=float(np.min(velocities) / (p.x_st * p.omega)),
        times=times, states_after=after.copy(), states_before=before_of.copy(),
    )


def orbit_from_cycle(p: Parameters, period_multiple: int, times, states_after, *, seed: str = "orbit",
                     periods: int = 0, tolerances: Tolerances | None = None) -> PeriodicOrbit:
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
        raise ValueError(f"`states_after` is not allowed: must be {len(times)} finite rows (x1, x2, x1', x2'), "
                         f"got shape {states.shape}")
    tol = check_tolerances(tolerances)
    if not p.native_scales():
        q = p.canonical()
        to_q = ScaleMap(p, q)
        o = orbit_from_cycle(q, period_multiple, to_q.apply(times, "time"), to_q.full(states), seed=seed, periods=periods,
                             tolerances=tol)
        return rescale_orbit(o, ScaleMap(q, p))
    # The forcing is T-periodic: shift the cycle so the first impact is in [0, T). Large
    # absolute times would cost digits in sin(omega t) (~1e-13 after 500 periods).
    times = times - math.floor(times[0] / p.T) * p.T
    model = Model(p)
    shoot = _Shooting(p, period_multiple, len(times), model)
    u, iterations, residual = _newton(shoot, shoot.pack(times, states))
    t, y = shoot.times_states(u)
    return _orbit_from_solution(p, model, period_multiple, t, y, seed, iterations, residual, periods, tol.gap_tol)


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
    t_least = ((math.atan2(fn.G.real, fn.G.imag) + math.pi) % (2 * math.pi) - 0.5 * math.pi) / p.omega % T
    # (Im(G e^{iwt}) = |G| sin(wt + arg G) is least where wt + arg G = -pi/2.)
    t_least = ((-0.5 * math.pi - math.atan2(fn.G.imag, fn.G.real)) / p.omega) % T
    admissible = least > 0.0
    reason = "" if admissible else (
        f"the {what} of the forced response reaches {least:.6g} (relative) at phase {t_least / T:.6f}: "
        + ("the bodies would overlap" if regime == "no_contact" else "the stop would have to pull"))
    mult = np.linalg.eigvals(mode.propagator(T))
    mult = mult[np.argsort(-np.abs(mult), kind="stable")]
    traj = Trajectory(model)
    traj.segments.append((STUCK if regime == "stuck" else FREE, Segment(mode, 0.0, mode.forced(0.0))))
    min_gap = least if regime == "no_contact" else 0.0
    return PeriodicOrbit(
        p=p, regime=regime, period_multiple=1, impacts=(), cycle_start=0.0,
        contact_fraction=1.0 if regime == "stuck" else 0.0,
        contact_phases=((0.0, 1.0),) if regime == "stuck" else (),
        x1_max=float(abs(mode.Yhat[0])) / p.x_st, periods=periods, residual=0.0, trajectory=traj,
        solved=True, admissible=admissible, stable=bool(np.max(np.abs(mult)) < 1.0), multipliers=mult,
        reason=reason, seed="closed_form", min_gap=min_gap,
    )


def rescale_orbit(o: PeriodicOrbit, scales: ScaleMap) -> PeriodicOrbit:
    """The same orbit in ``scales.target``'s units (relative fields and multipliers unchanged)."""
    base = rescale_steady(o, scales)
    return dataclasses.replace(base, times=scales.apply(o.times, "time"), states_after=scales.full(o.states_after),
                               states_before=scales.full(o.states_before))


def _unsolved(steady: SteadyState, reason: str) -> PeriodicOrbit:
    base = {f.name: getattr(steady, f.name) for f in dataclasses.fields(SteadyState)}
    return PeriodicOrbit(**base, solved=False, admissible=False, stable=None, reason=reason, seed="simulate")


def _from_steady(steady: SteadyState, period_multiple: int | None, tolerances: Tolerances | None) -> PeriodicOrbit:
    p = steady.p
    if steady.regime == "nonperiodic":
        return _unsolved(steady, f"the simulated motion did not settle within {steady.periods} periods "
                                 "(nonperiodic): no cycle to solve for")
    if steady.regime == "chatter":
        return _unsolved(steady, "the cycle has a phase of persistent contact reached through an accumulation "
                                 "of impacts (chatter): the direct solve does not apply; values are the simulated cycle's")
    k = steady.period_multiple
    m = _repeat_factor(period_multiple, k)
    if steady.regime in ("no_contact", "stuck"):
        if m != 1:
            raise ValueError(f"`period_multiple` = {period_multiple!r} is not allowed: the {steady.regime} motion has period T")
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
        raise ValueError(f"`period_multiple` = {period_multiple!r} is not allowed: must be a positive multiple of "
                         f"the seed's period multiple {k}")
    return period_multiple // k


def _repeat(times: np.ndarray, after: np.ndarray, k: int, m: int, T: float):
    """The cycle of k T repeated m times, as one cycle of m k T."""
    return (np.concatenate([times + j * k * T for j in range(m)]), np.concatenate([after] * m))


def solve_orbit(p: Parameters, seed: str | SteadyState | Algorithm1Result = "auto", *,
                period_multiple: int | None = None, t0: float = 0.0, state: np.ndarray | None = None,
                tolerances: Tolerances | None = None, settle_tol: float = 1e-10, max_periods: int = 4000,
                max_period_multiple: int = 8) -> PeriodicOrbit:
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
                raise ValueError(f"`{name}` is not allowed with seed = 'alg1': Algorithm No. 1's orbit is closed-form and "
                                 "has no start (seed 'simulate' starts from it)")
    if not p.native_scales():
        # The same relative problem in the reference case's units, converted back.
        q = p.canonical()
        to_q = ScaleMap(p, q)
        if isinstance(seed, Algorithm1Result):
            seed = _rescale_alg1(seed, to_q)
        elif isinstance(seed, PeriodicOrbit):
            seed = rescale_orbit(seed, to_q)
        elif isinstance(seed, SteadyState):
            seed = rescale_steady(seed, to_q)
        o = solve_orbit(q, seed, period_multiple=period_multiple, t0=to_q.apply(start_in_first_period(p, t0), "time"),
                        state=None if state is None else to_q.full(state), tolerances=tolerances,
                        settle_tol=settle_tol, max_periods=max_periods, max_period_multiple=max_period_multiple)
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
                return _from_alg1(a1, period_multiple, tolerances)
            if a1 is not None and a1.exists and a1.admissible:
                try:
                    orbit = _from_alg1(a1, period_multiple, tolerances)
                except OrbitError:
                    orbit = None
                if orbit is not None and orbit.admissible and orbit.stable:
                    return orbit
        seed = steady_state(p, t0=t0, state=state, tolerances=tolerances, settle_tol=settle_tol,
                            max_periods=max_periods, max_period_multiple=max_period_multiple)
    if isinstance(seed, Algorithm1Result):
        if not seed.exists:
            raise OrbitError(f"Algorithm No. 1 has no orbit: {seed.reason}")
        return _from_alg1(seed, period_multiple, tolerances)
    if isinstance(seed, SteadyState):
        return _from_steady(seed, period_multiple, tolerances)
    raise ValueError(f"`seed` = {seed!r} is not allowed: must be one of {', '.join(SEEDS)}, a SteadyState "
                     "or an Algorithm1Result")


def _from_alg1(a1: Algorithm1Result, period_multiple: int | None, tolerances: Tolerances) -> PeriodicOrbit:
    m = _repeat_factor(period_multiple, 1)
    times, after = _repeat(np.array([a1.t_impact]), np.array([a1.state_after]), 1, m, a1.p.T)
    return orbit_from_cycle(a1.p, m, times, after, seed="alg1", tolerances=tolerances)


# The keywords of steady_state, which steady_state_auto passes on.
STEADY_KEYWORDS = ("t0", "state", "tolerances", "settle_tol", "max_periods", "max_period_multiple")


def steady_state_auto(p: Parameters, **kwargs) -> SteadyState:
    """The steady state, cheaply where it can be.

    If Algorithm No. 1's one-impact orbit exists, is admissible, and its Newton-confirmed
    cycle is stable, that orbit is returned (a :class:`PeriodicOrbit`, a SteadyState with
    ``periods = 0``) without simulating a transient. Otherwise this is
    :func:`steady_state` with the same keyword arguments.

    The stable one-impact orbit is an attractor; where attractors coexist, the transient of
    :func:`steady_state` from its start may settle on another one (for the reference
    parameters it does at some gaps, e.g. Delta0/x_st = -8.8, where a 4-impact 3T cycle
    coexists with the one-impact orbit). ``steady_state`` itself is unchanged.

    Raises
    ------
    TypeError
        A keyword that :func:`steady_state` does not take, named.
    """
    p = require_parameters(p)
    unknown = sorted(set(kwargs) - set(STEADY_KEYWORDS))
    if unknown:
        raise ArgumentTypeError(f"`{unknown[0]}` is not allowed: steady_state_auto takes the keywords of steady_state, "
                                f"{', '.join(STEADY_KEYWORDS)}")
    gap_tol = check_tolerances(kwargs.get("tolerances")).gap_tol
    try:
        a1 = algorithm1(p, gap_tol=gap_tol)
    except (ValueError, SearchLimitError):
        a1 = None  # no closed-form orbit here (a resonance of the impacts): simulate
    if a1 is not None and a1.exists and a1.admissible:
        try:
            orbit = _from_alg1(a1, None, kwargs.get("tolerances") or Tolerances())
        except OrbitError:
            orbit = None
        if orbit is not None and orbit.admissible and orbit.stable:
            return orbit
    return steady_state(p, **kwargs)


# ----------------------------------------------------------------------------------------
# The independent check: finite differences of the stroboscopic map by simulation
# ----------------------------------------------------------------------------------------
def stroboscopic_map(p: Parameters, t0: float, state: np.ndarray, periods: int,
                     tolerances: Tolerances | None = None) -> np.ndarray:
    """State at t0 + periods T from ``state`` at t0, by the event-driven solver. Shape (4,)."""
    solver = EventDrivenSolver(p, t0=t0, state=state, tolerances=tolerances)
    solver.advance(t0 + periods * p.T)
    return solver.state_at(t0 + periods * p.T)


def stroboscopic_jacobian(p: Parameters, t0: float, state: np.ndarray, periods: int,
                          rel_step: float = 1e-6, tolerances: Tolerances | None = None) -> np.ndarray:
    """Central finite-difference Jacobian of :func:`stroboscopic_map`, shape (4, 4).

    Steps are ``rel_step`` times x_st (positions) and x_st omega (velocities). The section t0
    must lie inside a free flight, away from impacts.
    """
    D = np.array([p.x_st, p.x_st, p.x_st * p.omega, p.x_st * p.omega])
    J = np.empty((4, 4))
    for j in range(4):
        h = rel_step * D[j]
        plus, minus = np.array(state, float), np.array(state, float)
        plus[j] += h
        minus[j] -= h
        J[:, j] = (stroboscopic_map(p, t0, plus, periods, tolerances)
                   - stroboscopic_map(p, t0, minus, periods, tolerances)) / (2 * h)
    return J


# ----------------------------------------------------------------------------------------
# Continuation
# ----------------------------------------------------------------------------------------
# Kinds of special point a branch reports (see SpecialPoint).
SPECIAL_KINDS = ("fold", "period_doubling", "neimark_sacker", "grazing_velocity", "grazing_interior")


@dataclass(frozen=True)
class BranchPoint:
    """One orbit on a branch.

    Attributes
    ----------
    value : float
        The continuation parameter's value.
    phases : tuple of float
        Impact times over T modulo 1, in cycle order.
    t_over_T : tuple of float
        Impact times since the cycle's first impact, over T.
    velocities : tuple of float
        Closing velocities over x_st omega.
    multipliers : tuple of complex
        Floquet multipliers, largest modulus first.
    stable, admissible : bool
    min_gap : float
        Smallest interior gap minimum over x_st (inf if none).
    x1_max : float
        max |x1|/x_st over the cycle.
    times : tuple of float
        Absolute impact times, s (first in [0, T)).
    states_after : tuple of tuple
        (x1, x2, x1', x2') just after each impact: with ``times``, a seed for
        :func:`orbit_from_cycle` or a start for the simulation.
    """

    value: float
    phases: tuple
    t_over_T: tuple
    velocities: tuple
    multipliers: tuple
    stable: bool
    admissible: bool
    min_gap: float
    x1_max: float
    times: tuple = field(default=(), repr=False)
    states_after: tuple = field(default=(), repr=False)

    def to_dict(self) -> dict:
        return {
            "value": self.value, "phases": list(self.phases), "t_over_T": list(self.t_over_T),
            "velocities_rel": list(self.velocities),
            "multipliers": [abs(m) for m in self.multipliers],
            "multipliers_complex": [[m.real, m.imag] for m in self.multipliers],
            "stable": self.stable, "admissible": self.admissible,
            "min_gap": self.min_gap if math.isfinite(self.min_gap) else None, "x1_max": self.x1_max,
            "times": list(self.times), "states_after": [list(y) for y in self.states_after],
        }


@dataclass(frozen=True)
class SpecialPoint:
    """A located bifurcation or grazing on a branch.

    Attributes
    ----------
    kind : str
        One of ``fold`` (turning point, a multiplier at +1), ``period_doubling`` (a multiplier
        at -1), ``neimark_sacker`` (a complex pair on the unit circle), ``grazing_velocity`` (an
        impact's closing velocity reaches zero: the impact disappears), ``grazing_interior``
        (the gap's interior minimum reaches zero: a new impact appears).
    value : float
        Parameter value where it happens.
    index : int
        It lies between branch points ``index - 1`` and ``index``.
    point : BranchPoint
        The orbit there.
    detail : str
        What changes (e.g. which impact, the impact sequence before and after).
    """

    kind: str
    value: float
    index: int
    point: BranchPoint
    detail: str

    def to_dict(self) -> dict:
        return {"kind": self.kind, "value": self.value, "index": self.index, "detail": self.detail,
                "point": self.point.to_dict()}


@dataclass(frozen=True)
class Branch:
    """A followed branch of z-impact cycles of period k T.

    Attributes
    ----------
    parameter : str
        Name of the continuation parameter (a field of :class:`Parameters`).
    period_multiple, impacts_per_cycle : int
        k and z (Peterka's z/k label).
    points : tuple of BranchPoint
    special : tuple of SpecialPoint
        Detected folds, period doublings, Neimark-Sacker points and grazings, in order.
    end_reason : str
        Why the branch ends: ``bound`` (the parameter range's end), ``grazing_velocity`` or
        ``grazing_interior`` (the impact sequence changes there), ``newton_failure``,
        ``max_points``.
    end_value : float
        The parameter where it ends.
    """

    parameter: str
    period_multiple: int
    impacts_per_cycle: int
    points: tuple
    special: tuple
    end_reason: str
    end_value: float

    @property
    def values(self) -> np.ndarray:
        return np.array([q.value for q in self.points])

    def to_dict(self) -> dict:
        return {
            "parameter": self.parameter, "period_multiple": self.period_multiple,
            "impacts_per_cycle": self.impacts_per_cycle, "end_reason": self.end_reason,
            "end_value": self.end_value,
            "special": [s.to_dict() for s in self.special],
            "points": [q.to_dict() for q in self.points],
        }


class _Continuation:
    """Pseudo-arclength continuation of the shooting equations in one parameter."""

    def __init__(self, p: Parameters, parameter: str, k: int, z: int, gap_tol: float):
        self.p0, self.parameter, self.k, self.z, self.gap_tol = p, parameter, k, z, gap_tol
        self._cache: dict = {}
        # Arclength metric: the 5 z unknowns count as one (their mean square), the parameter as
        # one, so a step moves the parameter by a similar amount whatever z is.
        n = 5 * z
        self.W = np.append(np.full(n, 1.0 / n), 1.0)

    def norm(self, v: np.ndarray) -> float:
        return float(np.sqrt(v @ (self.W * v)))

    def shooting(self, lam: float) -> _Shooting:
        s = self._cache.get(lam)
        if s is None:
            s = _Shooting(self.p0.replace(**{self.parameter: float(lam)}), self.k, self.z)
            if len(self._cache) > 64:
                self._cache.clear()
            self._cache[lam] = s
        return s

    def F(self, x: np.ndarray, jacobian: bool = True):
        """Residual and [J | dF/dlam] at x = (u, lam)."""
        u, lam = x[:-1], float(x[-1])
        F, J = self.shooting(lam).residual(u, jacobian)
        if not jacobian:
            return F, None
        h = PARAMETER_FD_STEP * max(1.0, abs(lam))
        try:
            Fp, _ = self.shooting(lam + h).residual(u, False)
        except ValueError:
            Fp, h_p = F, 0.0
        else:
            h_p = h
        try:
            Fm, _ = self.shooting(lam - h).residual(u, False)
        except ValueError:
            Fm, h_m = F, 0.0
        else:
            h_m = h
        if h_p + h_m == 0.0:
            raise OrbitError(f"cannot vary `{self.parameter}` at {lam!r}")
        dF = (Fp - Fm) / (h_p + h_m)
        return F, np.column_stack([J, dF])

    def tangent(self, x: np.ndarray, previous: np.ndarray) -> np.ndarray:
        _, A = self.F(x)
        B = np.vstack([A, self.W * previous])
        rhs = np.zeros(len(x))
        rhs[-1] = 1.0
        t = np.linalg.solve(B, rhs)
        return t / self.norm(t)

    def correct(self, x0: np.ndarray, t0: np.ndarray, h: float, max_iterations: int = 10):
        """Newton on F = 0, <t0, x - x0>_W = h from the predictor x0 + h t0."""
        x = x0 + h * t0
        row = self.W * t0
        for it in range(1, max_iterations + 1):
            try:
                F, A = self.F(x)
            except (OrbitError, ValueError):
                return None, it
            G = np.append(F, row @ (x - x0) - h)
            B = np.vstack([A, row])
            try:
                dx = np.linalg.solve(B, -G)
            except np.linalg.LinAlgError:
                return None, it
            x = x + dx
            if not np.all(np.isfinite(x)):
                return None, it
            if np.max(np.abs(dx)) <= ORBIT_TOL * max(1.0, abs(h)):
                try:
                    F, _ = self.F(x, jacobian=False)
                except (OrbitError, ValueError):
                    return None, it
                if np.max(np.abs(F)) <= 10 * ORBIT_TOL:
                    return x, it
        return None, max_iterations

    def orbit(self, x: np.ndarray) -> PeriodicOrbit:
        s = self.shooting(float(x[-1]))
        t, y = s.times_states(x[:-1])
        F, _ = s.residual(x[:-1], False)
        return _orbit_from_solution(s.p, s.model, self.k, t, y, "orbit", 0, float(np.max(np.abs(F))), 0,
                                    self.gap_tol)


def _point(value: float, o: PeriodicOrbit) -> BranchPoint:
    return BranchPoint(
        value=float(value), phases=tuple(i.phase for i in o.impacts), t_over_T=tuple(i.t_over_T for i in o.impacts),
        velocities=tuple(i.velocity / (o.p.x_st * o.p.omega) for i in o.impacts),
        multipliers=tuple(complex(m) for m in o.multipliers), stable=bool(o.stable), admissible=bool(o.admissible),
        min_gap=float(o.min_gap), x1_max=float(o.x1_max), times=tuple(float(t) for t in o.times),
        states_after=tuple(tuple(float(v) for v in y) for y in o.states_after),
    )


def _tests(o: PeriodicOrbit, tangent_lam: float) -> dict:
    """Test functions whose sign changes mark special points."""
    mono = o.monodromy()
    n = mono.shape[0]
    mult = o.multipliers
    complex_moduli = [abs(m) for m in mult if abs(m.imag) > 1e-12 * max(abs(m), 1.0)]
    return {
        "fold": tangent_lam,
        "period_doubling": float(np.linalg.det(np.eye(n) + mono)),
        "neimark_sacker": (max(complex_moduli) - 1.0) if complex_moduli else math.nan,
        "grazing_velocity": o.min_velocity,
        "grazing_interior": o.min_gap if math.isfinite(o.min_gap) else math.nan,
    }


def continue_orbit(orbit: PeriodicOrbit, parameter: str = "gap", bounds: tuple[float, float] | None = None, *,
                   direction: int = +1, step: float = 0.01, min_step: float = 1e-7, max_step: float = 0.25,
                   max_points: int = 5000, stop_at_grazing: bool = True,
                   tolerances: Tolerances | None = None) -> Branch:
    """Follow a solved impacting cycle as one parameter varies (pseudo-arclength continuation).

    Parameters
    ----------
    orbit : PeriodicOrbit
        The starting cycle (solved, with at least one impact).
    parameter : str
        A field of :class:`Parameters` (``gap`` is Delta0/x_st).
    bounds : (float, float)
        The parameter range; the branch ends at its edge (a last point exactly there).
    direction : {+1, -1}
        Initial direction of the parameter.
    step, min_step, max_step : float
        Initial, smallest and largest arclength step (in the scaled unknowns and the
        parameter). The step grows after fast corrector convergence and shrinks on failure;
        the branch ends with ``newton_failure`` below ``min_step``.
    stop_at_grazing : bool
        End the branch at the first grazing (where its impact sequence stops being the
        motion's); otherwise follow the (then inadmissible) orbit on.

    Returns
    -------
    Branch
        Points, located special points and the reason the branch ends.
    """
    if not (isinstance(parameter, str) and parameter in Parameters.names()):
        raise ValueError(f"`parameter` = {parameter!r} is not allowed: must be one of {', '.join(Parameters.names())}")
    if not isinstance(orbit, PeriodicOrbit) or not orbit.solved or not orbit.impacts:
        raise ValueError("`orbit` is not allowed: must be a solved PeriodicOrbit with impacts")
    if isinstance(direction, bool) or direction not in (1, -1):
        raise ValueError(f"`direction` = {direction!r} is not allowed: must be +1 or -1")
    step, min_step, max_step = (finite_argument(name, value) for name, value in
                                (("step", step), ("min_step", min_step), ("max_step", max_step)))
    if not (0 < min_step <= step <= max_step):
        raise ValueError(f"`step` = {step!r} is not allowed: need 0 < min_step <= step <= max_step")
    max_points = integer_argument("max_points", max_points, 1, MAX_BRANCH_POINTS)
    lam0 = float(getattr(orbit.p, parameter))
    if bounds is None:
        raise ValueError("`bounds` is not allowed: must be given as (low, high)")
    try:
        lo, hi = (finite_argument("bounds", b) for b in bounds)
    except (TypeError, ValueError):
        raise ValueError(f"`bounds` = {bounds!r} is not allowed: must be two finite numbers (low, high)") from None
    if not (lo < hi and lo <= lam0 <= hi):
        raise ValueError(f"`bounds` = {bounds!r} is not allowed: need low < high around {parameter} = {lam0!r}")
    dom_lo, dom_hi, closed = PARAMETER_DOMAIN[parameter]
    if not ((lo >= dom_lo if closed else lo > dom_lo) and hi <= dom_hi):
        allowed = {(0.0, math.inf, False): "> 0", (0.0, math.inf, True): ">= 0", (0.0, 1.0, True): "in [0, 1]"}
        raise ValueError(f"`bounds` = {bounds!r} is not allowed: `{parameter}` must be "
                         f"{allowed[(dom_lo, dom_hi, closed)]}, so must both bounds")
    tol = check_tolerances(tolerances)
    if not orbit.p.native_scales() and parameter not in ("x_st", "m1", "omega"):
        # The same relative problem in the reference case's units, converted back.
        q = orbit.p.canonical()
        branch = continue_orbit(rescale_orbit(orbit, ScaleMap(orbit.p, q)), parameter, (lo, hi), direction=direction,
                                step=step, min_step=min_step, max_step=max_step, max_points=max_points,
                                stop_at_grazing=stop_at_grazing, tolerances=tol)
        return _rescale_branch(branch, ScaleMap(q, orbit.p))
    cont = _Continuation(orbit.p, parameter, orbit.period_multiple, orbit.impacts_per_cycle, tol.gap_tol)
    shoot = cont.shooting(lam0)
    x = np.append(shoot.pack(orbit.times, orbit.states_after), lam0)
    e = np.zeros(len(x))
    e[-1] = float(direction)
    t = cont.tangent(x, e)
    if t[-1] * direction < 0:
        t = -t
    o = cont.orbit(x)
    points = [_point(lam0, o)]
    tests = _tests(o, t[-1])
    special: list[SpecialPoint] = []
    h = step
    end_reason, end_value = "max_points", lam0
    seq = _sequence(orbit.period_multiple, orbit.impacts_per_cycle)
    while len(points) < max_points:
        x_new, its = cont.correct(x, t, h)
        if x_new is not None:
            lam_new = float(x_new[-1])
            if lam_new > hi or lam_new < lo:
                # Land exactly on the bound: secant in the step length.
                edge = hi if lam_new > hi else lo
                frac = (edge - float(x[-1])) / (lam_new - float(x[-1]))
                x_edge = _locate_parameter(cont, x, t, h * frac, edge)
                if x_edge is not None:
                    x_new, lam_new = x_edge, edge
                    o_new = cont.orbit(x_new)
                    t_new = cont.tangent(x_new, t)
                    tests_new = _tests(o_new, t_new[-1])
                    stop = _detect(cont, x, t, h * frac, tests, tests_new, points, bool(o_new.stable),
                                   special, seq, stop_at_grazing)
                    if stop is None:
                        points.append(_point(edge, o_new))
                        end_reason, end_value = "bound", edge
                    else:
                        end_reason, end_value = stop
                    break
                x_new = None
        if x_new is None:
            h *= 0.5
            if h < min_step:
                end_reason, end_value = "newton_failure", float(x[-1])
                break
            continue
        o_new = cont.orbit(x_new)
        t_new = cont.tangent(x_new, t)
        tests_new = _tests(o_new, t_new[-1])
        stop = _detect(cont, x, t, h, tests, tests_new, points, bool(o_new.stable), special, seq,
                       stop_at_grazing)
        if stop is not None:
            end_reason, end_value = stop
            break
        points.append(_point(lam_new, o_new))
        x, t, tests = x_new, t_new, tests_new
        h = min(h * 1.5, max_step) if its <= 3 else (h * 0.7 if its >= 6 else h)
        h = max(h, min_step)
    return Branch(parameter=parameter, period_multiple=orbit.period_multiple,
                  impacts_per_cycle=orbit.impacts_per_cycle, points=tuple(points), special=tuple(special),
                  end_reason=end_reason, end_value=float(end_value))


def _rescale_branch(branch: Branch, scales: ScaleMap) -> Branch:
    """A branch's impact times and states in ``scales.target``'s units (all else is relative)."""
    def point(q: BranchPoint) -> BranchPoint:
        return dataclasses.replace(q, times=tuple(scales.apply(t, "time") for t in q.times),
                                   states_after=tuple(tuple(float(v) for v in scales.full(np.array(y)))
                                                      for y in q.states_after))

    return dataclasses.replace(branch, points=tuple(point(q) for q in branch.points),
                               special=tuple(dataclasses.replace(sp, point=point(sp.point)) for sp in branch.special))


def _sequence(k: int, z: int) -> str:
    return f"{z}/{k} ({z} impact{'s' if z != 1 else ''} in {k} T)"


def _locate_parameter(cont: _Continuation, x0: np.ndarray, t0: np.ndarray, h_guess: float, target: float):
    """The branch point with the parameter exactly ``target``, by Newton with lam fixed."""
    x, _ = cont.correct(x0, t0, h_guess)
    if x is None:
        return None
    u = x[:-1].copy()
    s = cont.shooting(target)
    try:
        u, _, _ = _newton(s, u)
    except OrbitError:
        return None
    return np.append(u, target)


def _locate(cont: _Continuation, x0: np.ndarray, t0: np.ndarray, h: float, key: str, f0: float, f1: float):
    """Zero of test function ``key`` between the arclength 0 and h from x0 (Brent's method)."""
    cache = {}

    def g(s: float) -> float:
        if s == 0.0:
            return f0
        x, _ = cont.correct(x0, t0, s)
        if x is None:
            raise OrbitError("corrector failed while locating a special point")
        o = cont.orbit(x)
        tl = cont.tangent(x, t0)[-1]
        v = _tests(o, tl)[key]
        cache[s] = (x, o, v)
        return v

    try:
        s_star = scipy.optimize.brentq(g, 0.0, h, xtol=1e-13 * max(1.0, h), rtol=4 * np.finfo(float).eps,
                                       maxiter=100)
        if s_star not in cache:
            g(s_star)
        x, o, _ = cache[s_star]
        return x, o
    except (OrbitError, ValueError, RuntimeError):
        x, _ = cont.correct(x0, t0, h)
        if x is None:
            return None, None
        return x, cont.orbit(x)


# A located bifurcation is kept only if a multiplier really sits on the unit circle there
# (distance below this): a test function can also change sign through a pole, as det(I + M_c)
# does at a grazing impact, where the saltation matrix grows like 1/v.
MULTIPLIER_CHECK = 1e-6


def _multiplier_check(key: str, o: PeriodicOrbit) -> bool:
    mult = o.multipliers
    if key == "period_doubling":
        return bool(np.min(np.abs(mult + 1.0)) < MULTIPLIER_CHECK)
    if key == "fold":
        return bool(np.min(np.abs(mult - 1.0)) < MULTIPLIER_CHECK)
    if key == "neimark_sacker":
        pairs = [abs(m) for m in mult if abs(m.imag) > 1e-12]
        return bool(pairs and min(abs(np.array(pairs) - 1.0)) < MULTIPLIER_CHECK)
    return True


def _detect(cont, x, t, h, tests, tests_new, points, stable_after, special, seq, stop_at_grazing):
    """Locate special points between the last point and the new one; return (reason, value)
    if the branch ends there."""
    found = []
    for key in ("grazing_velocity", "grazing_interior", "period_doubling", "neimark_sacker", "fold"):
        a, b = tests[key], tests_new[key]
        if not (math.isfinite(a) and math.isfinite(b)) or (a > 0) == (b > 0):
            continue
        xs, o = _locate(cont, x, t, h, key, a, b)
        if o is None or not _multiplier_check(key, o):
            continue
        found.append((key, xs, o))
    if not found:
        return None
    # A turning point at a grazing impact is the grazing itself (the impact time folds there).
    if any(f[0] == "grazing_velocity" for f in found):
        found = [f for f in found if f[0] != "fold"]
    # In order along the step; coinciding points (a velocity grazing is often an interior touch
    # of the neighbouring flight too) with the velocity grazing first.
    priority = {"grazing_velocity": 0, "grazing_interior": 1, "period_doubling": 2, "neimark_sacker": 3, "fold": 4}
    found.sort(key=lambda f: (round(float((cont.W * t) @ (f[1] - x)) / (1e-9 * max(h, 1e-12))), priority[f[0]]))
    k, z = cont.k, cont.z
    stability = ""
    if points[-1].stable != stable_after:
        stability = "; the orbit " + ("gains" if stable_after else "loses") + " stability"
    stop = None
    for key, xs, o in found:
        value = float(xs[-1])
        if stop is not None and abs(value - stop[1]) > 1e-9 * (1.0 + abs(value)):
            break  # beyond the end of the branch
        if key == "grazing_velocity":
            i = int(np.argmin([imp.velocity for imp in o.impacts]))
            kk, zz = _reduced(o, i)
            detail = (f"impact {i + 1} of the {seq} cycle reaches zero closing velocity at phase "
                      f"{o.impacts[i].phase:.6f}: the impact sequence changes, {seq} -> "
                      f"{_sequence(kk, zz)} if the cycle persists")
        elif key == "grazing_interior":
            j = min(range(z), key=lambda i: _flight_min(o, i))
            detail = (f"the gap's interior minimum touches the stop in the flight after impact {j + 1}: "
                      f"the impact sequence changes, {seq} -> {_sequence(k, z + 1)} if the cycle persists")
        elif key == "period_doubling":
            detail = f"a multiplier passes through -1: a {_sequence(2 * k, 2 * z)} cycle branches off" + stability
        elif key == "neimark_sacker":
            detail = "a complex pair of multipliers crosses the unit circle" + stability
        else:
            detail = "turning point of the branch: a multiplier passes through +1" + stability
        special.append(SpecialPoint(kind=key, value=value, index=len(points), point=_point(value, o), detail=detail))
        if stop is None and stop_at_grazing and key.startswith("grazing"):
            stop = (key, value)
    return stop


def _reduced(o: PeriodicOrbit, drop: int) -> tuple[int, int]:
    """(k, z) of the cycle left when impact ``drop`` vanishes, reduced to its least period
    (e.g. a 3/2 cycle whose middle impact vanishes may be a 1/1 cycle repeated)."""
    k, T = o.period_multiple, o.p.T
    keep = [i for i in range(len(o.times)) if i != drop]
    t = o.times[keep]
    y = o.states_after[keep] / np.array([o.p.x_st, o.p.x_st, o.p.x_st * o.p.omega, o.p.x_st * o.p.omega])
    z = len(keep)
    for d in range(1, k):
        if k % d or (z * d) % k or z * d // k == 0:
            continue
        m = z * d // k
        if np.all(np.abs(t[m:] - t[:-m] - d * T) < 1e-6 * T) and np.all(np.abs(y[m:] - y[:-m]) < 1e-6):
            return d, m
    return k, z


def _flight_min(o: PeriodicOrbit, i: int) -> float:
    """Smallest interior gap minimum (relative) of flight i of a solved orbit (inf if none)."""
    model = o.trajectory.model
    z, Tc = len(o.times), o.cycle_duration
    t_b = o.times[i + 1] if i + 1 < z else o.times[0] + Tc
    v_end = o.states_before[(i + 1) % z]
    _, _, minima, _ = _flight_scan(model, o.times[i], o.states_after[i], t_b, float(v_end[3] - v_end[2]), 1e-12)
    return min((m[1] for m in minima), default=math.inf)
