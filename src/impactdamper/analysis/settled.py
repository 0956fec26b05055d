"""The settled motion at one point, found the cheapest way that is still right.

Two questions share this module. :func:`steady_state_auto` answers "the settled motion at
these parameters": Algorithm No. 1's orbit of Timofeev et al. (2019), eqs. (7)-(17), when it
is an attractor, else the simulation of :func:`~impactdamper.core.steady.steady_state`.
:func:`solve_point` answers "the settled motion at this sweep point, continuing its
neighbour's": the sweeps of :mod:`impactdamper.analysis.sweeps` call it for every point.

How one point is computed (:func:`solve_point`)
-----------------------------------------------
A sweep point starts from its neighbour's motion, carried at a stroboscopic section: the
state (x1, x2, x1', x2') at a time t = n T (forcing phase zero) becomes the new point's state
at t0 = 0. The gap Delta = Delta0 - (x2 - x1) of that state refers to the old Delta0; at the
new one it may be negative (the bodies would overlap). The state is then **projected onto the
stop**: x2 := x1 + Delta0 (object and velocities unchanged, gap zero). A state that was in
persistent contact is kept on the stop the same way (its gap stays zero), so the persistent
contact carries over exactly. The first point of a sweep starts from Algorithm No. 2's step 1
(:func:`~impactdamper.core.simulate.default_initial_state`); any point can be recomputed on its own
from the state it started from (:attr:`SweepPoint.start_state`).

The settled motion is then found, cheapest first. Each accelerator accepts only a continuation
of the neighbour's motion that is still admissible and stable: the motion a sweep with a
vanishing step follows. A plain simulation from the carried state (a finite step) settles on
the same motion, except close to a bifurcation where that motion's basin shrinks to nothing
(approaching a grazing, say): there it can jump to a coexisting motion a little early, while
the sweep reports the continued motion up to the bifurcation itself. (Reference case: with
every point simulated at a step of 0.005, the downward sweep leaves the one-impact motion at
Delta0/x_st = -8.845, 0.004 above the grazing of Algorithm No. 1's orbit at -8.849.)

1. **closed form** -- the neighbour was ``stuck`` (``no_contact``) and the joined bodies'
   contact force (the free mode's gap) on the forced response stays positive: that forced
   response is the motion (the carried state lies on it already; it is damped, so stable).
2. **orbit continuation** -- the neighbour was a periodic impacting cycle: its impact times and
   states seed the Newton shooting of :func:`impactdamper.analysis.orbits.orbit_from_cycle` at the new
   parameter, which also checks admissibility (certified gap search) and stability
   (saltation-matrix Floquet multipliers). Accepted if admissible and stable.
3. **stroboscopic Newton** -- for cycles the shooting does not cover (``chatter``, with a
   phase of persistent contact) or where it failed: Newton on the map y(0) -> y(k T) of the
   event-driven solver (:func:`impactdamper.analysis.strobe.strobe_newton`), with a
   finite-difference Jacobian (the neighbour's, Broyden-updated; fresh where the iteration
   stalls or a multiplier exceeds :data:`~impactdamper.analysis.strobe.FRESH_JACOBIAN_ABOVE`; its
   eigenvalues are the multipliers). Accepted if stable and if one simulated cycle from the
   solution returns to it to ``settle_tol``; that cycle is described exactly as
   :func:`~impactdamper.core.steady.steady_state` describes a settled one.
4. **simulation** -- :func:`~impactdamper.core.steady.steady_state` from the carried state, capped
   at ``max_periods`` forcing periods.
5. **rescue** -- if that did not settle, the closest recurrence of the last sections (period k
   <= ``max_period_multiple`` with mismatch below ``RESCUE_MISMATCH``) seeds step 2 or 3; a
   stable, admissible orbit found so is the motion the capped run was still converging to.

What ``nonperiodic`` means here
-------------------------------
The sweep caps the simulation (``max_periods``, default 150 periods, against 4000 for a single
run of :func:`steady_state`): a point is ``nonperiodic`` when the capped run did not repeat
with a period k <= ``max_period_multiple`` to ``settle_tol`` and the rescue found no stable
orbit near its closest recurrence. That covers chaotic motion, periods above
``max_period_multiple`` T, quasi-periodic motion, and transients slower than the cap whose
end is not near a period-k recurrence. It is a statement about the sweep's budget, not a proof
of chaos.

Labels
------
``stuck`` (persistent contact, "S"), ``0/1`` (no contact), ``z/k`` for an impacting periodic
motion, ``c/k`` for a period-k cycle with a phase of persistent contact (chatter: the number of
impacts before the capture depends on the solver's ``chatter_tol`` and is not a label),
``np`` for nonperiodic. A point whose simulation raised one of the event solver's guards
(:class:`~impactdamper.core.events.SearchLimitError`; met at a lift-off whose contact force touches
zero almost tangentially, within ~1e-6 x_st of the lift-off threshold) gets regime ``failed``,
label ``err``; the next point starts from the state it started from.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from impactdamper.analysis.orbits import OrbitError, PeriodicOrbit, orbit_from_cycle, stable_algorithm1_orbit
from impactdamper.core.algorithm1 import algorithm1
from impactdamper.core.events import SearchLimitError
from impactdamper.core.model import FREE, STUCK, Model
from impactdamper.core.parameters import ArgumentTypeError, Parameters, require_parameters, state_scale
from impactdamper.core.simulate import EventDrivenSolver, Tolerances, check_tolerances, default_initial_state
from impactdamper.core.steady import SteadyState, describe_cycle, section_of, steady_state
from impactdamper.analysis.strobe import strobe_newton

__all__ = [
    "rescue_from_sections",
    "SweepSettings",
    "SweepPoint",
    "FAILED",
    "LABELS_ORDER",
    "label_of",
    "carry_state",
    "solve_point",
    "steady_state_auto",
    "STEADY_KEYWORDS",
]

log = logging.getLogger(__name__)

# A closest recurrence of the capped run below this (relative section mismatch) seeds the
# rescue Newton: close enough for Newton's basin, far above settle_tol (a still-converging
# transient with a multiplier of modulus 0.97 leaves ~1e-4 after 150 periods).
RESCUE_MISMATCH = 1e-2
# The rescue tries periods up to this k (Newton for k = 8 costs 8x a period-1 solve).
RESCUE_MAX_K = 8
# Orbits whose largest Floquet multiplier is within this of 1 are too close to a bifurcation
# to be trusted as the attractor the simulation would settle on: the simulation decides there.
STABILITY_MARGIN = 1e-6
# Relative tolerance on the contact force / gap of the closed-form motions (rounding guard).
CLOSED_FORM_MARGIN = 1e-12

# Regime of a point whose simulation raised (the event solver's guards, e.g. its step budget
# at a lift-off whose contact force touches zero almost tangentially); label "err".
FAILED = "failed"
# Legend order of the labels' regime classes (figures, tables).
LABELS_ORDER = ("stuck", "chatter", "multi_impact", "single_impact", "no_contact", "nonperiodic", FAILED)


@dataclass(frozen=True)
class SweepSettings:
    """How each sweep point is settled.

    Attributes
    ----------
    settle_tol : float
        Relative section mismatch for a settled motion (see :func:`steady_state`).
    max_periods : int
        Forcing periods a point's simulation may take before it is ``nonperiodic``.
    max_periods_after_nonperiodic : int
        The same cap when the neighbour the point starts from was itself nonperiodic (inside
        a chaotic band most points are; a periodic window there is found within this cap or
        by the rescue from its closest recurrence).
    max_period_multiple : int
        Largest k tried for T_c = k T.
    continuation : bool
        Use the accelerators 1-3 (closed form, orbit continuation, stroboscopic Newton);
        False: every point is simulated (steps 4-5 only, and the rescue with simulation).
    rescue : bool
        Try the Newton rescue on points that did not settle.
    tolerances : Tolerances
        Event-solver tolerances.
    compiled : bool
        Run each simulation's period loop in the compiled kernels
        (:func:`~impactdamper.core.compiled.steady_state_hybrid`: the same motion, its cycle
        described by the pure-Python solver); False: the pure-Python
        :func:`~impactdamper.core.steady.steady_state` throughout (the reference).
    """

    settle_tol: float = 1e-9
    max_periods: int = 150
    max_periods_after_nonperiodic: int = 50
    max_period_multiple: int = 8
    continuation: bool = True
    rescue: bool = True
    tolerances: Tolerances = field(default_factory=Tolerances)
    compiled: bool = True

    def __post_init__(self) -> None:
        for name in ("continuation", "rescue", "compiled"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"`{name}` = {getattr(self, name)!r} is not allowed: must be True or False")
        if not (math.isfinite(self.settle_tol) and 0 < self.settle_tol < 1):
            raise ValueError(f"`settle_tol` = {self.settle_tol!r} is not allowed: must be in (0, 1)")
        if not (isinstance(self.max_period_multiple, int) and self.max_period_multiple >= 1):
            raise ValueError(
                f"`max_period_multiple` = {self.max_period_multiple!r} is not allowed: must be an integer >= 1"
            )
        if not (isinstance(self.max_periods, int) and self.max_periods > 2 * self.max_period_multiple):
            raise ValueError(
                f"`max_periods` = {self.max_periods!r} is not allowed: must be an integer > "
                f"2 max_period_multiple = {2 * self.max_period_multiple}"
            )
        if not (
            isinstance(self.max_periods_after_nonperiodic, int)
            and 2 * self.max_period_multiple < self.max_periods_after_nonperiodic <= self.max_periods
        ):
            raise ValueError(
                f"`max_periods_after_nonperiodic` = {self.max_periods_after_nonperiodic!r} is not allowed: "
                f"must be an integer in (2 max_period_multiple, max_periods]"
            )


@dataclass(frozen=True)
class SweepPoint:
    """The settled motion at one parameter value.

    Attributes
    ----------
    p : Parameters
    value : float
        The swept parameter's value.
    regime : str
        One of :data:`impactdamper.core.steady.REGIMES`.
    period_multiple : int
        k in T_c = k T (0 when nonperiodic).
    impacts_per_cycle : int
        z, impacts in the cycle (for ``nonperiodic``: in the last ``NONPERIODIC_WINDOW`` T).
    label : str
        Peterka's z/k label (see the module docstring).
    stable : bool or None
        True if the motion attracted a simulation (it settled) or its largest Floquet
        multiplier is below 1; None when nonperiodic.
    multiplier : float
        Largest Floquet multiplier modulus where computed (orbit continuation, stroboscopic
        Newton, closed form), else nan.
    x1_max : float
        max |x1|/x_st over the cycle.
    velocities : tuple of float
        Closing velocities of the cycle's impacts over x_st omega, in cycle order.
    phases : tuple of float
        Their forcing phases t/T mod 1.
    contact_fraction : float
        Share of the cycle in persistent contact.
    method : str
        How it was found: ``closed_form``, ``continuation``, ``newton``, ``simulation``,
        ``rescue``.
    periods : int
        Forcing periods simulated for this point (all solver runs together).
    start : str
        ``default`` (Algorithm No. 2's step 1), ``neighbour``, ``projected`` (the neighbour's
        state moved onto the stop) or ``random``.
    start_state : ndarray, shape (4,)
        The state (x1, x2, x1', x2') the point started from at t0 = 0.
    section : ndarray, shape (4,)
        The settled motion's state at a section t = n T (carried to the next point).
    section_mode : str
        ``free`` or ``stuck`` at that section.
    cycle : tuple
        (times, states_after) of the cycle's impacts, for the orbit continuation; () if none.
    jacobian : ndarray or None
        The stroboscopic Newton's Jacobian (relative coordinates), reused by the next point.
    elapsed : float
        Wall time spent on the point, s (not part of the result's identity).
    """

    p: Parameters = field(repr=False)
    value: float
    regime: str
    period_multiple: int
    impacts_per_cycle: int
    label: str
    stable: bool | None
    multiplier: float
    x1_max: float
    velocities: tuple
    phases: tuple
    contact_fraction: float
    method: str
    periods: int
    start: str
    start_state: np.ndarray = field(repr=False, compare=False)
    section: np.ndarray = field(repr=False, compare=False)
    section_mode: str = field(repr=False, default=FREE)
    cycle: tuple = field(repr=False, default=(), compare=False)
    jacobian: np.ndarray | None = field(repr=False, default=None, compare=False)
    elapsed: float = field(repr=False, default=0.0, compare=False)

    @property
    def periodic(self) -> bool:
        return self.regime not in ("nonperiodic", FAILED)

    def row(self) -> dict:
        """A flat dict for a CSV row (velocities and phases joined by ';')."""
        return {
            "value": self.value,
            "regime": self.regime,
            "k": self.period_multiple,
            "z": self.impacts_per_cycle,
            "label": self.label,
            "stable": "" if self.stable is None else int(self.stable),
            "multiplier": self.multiplier,
            "x1_max": self.x1_max,
            "contact_fraction": self.contact_fraction,
            "method": self.method,
            "periods": self.periods,
            "start": self.start,
            "x1_0": self.start_state[0],
            "x2_0": self.start_state[1],
            "v1_0": self.start_state[2],
            "v2_0": self.start_state[3],
            "velocities": ";".join(f"{v:.6g}" for v in self.velocities),
            "phases": ";".join(f"{v:.6g}" for v in self.phases),
        }


def label_of(regime: str, k: int, z: int) -> str:
    """Peterka's label of a motion: ``stuck``, ``0/1``, ``z/k``, ``c/k``, ``np`` (or ``err``)."""
    if regime == "stuck":
        return "stuck"
    if regime == "no_contact":
        return "0/1"
    if regime == "chatter":
        return f"c/{k}"
    if regime == "nonperiodic":
        return "np"
    if regime == FAILED:
        return "err"
    return f"{z}/{k}"


# ----------------------------------------------------------------------------------------
# The settled motion at given parameters
# ----------------------------------------------------------------------------------------
# The keywords of steady_state, which steady_state_auto passes on.
STEADY_KEYWORDS = ("t0", "state", "tolerances", "settle_tol", "max_periods", "max_period_multiple")


def steady_state_auto(p: Parameters, **kwargs) -> SteadyState:
    """The steady state, cheaply where it can be.

    If Algorithm No. 1's one-impact orbit exists, is admissible, and its Newton-confirmed
    cycle is stable (:func:`~impactdamper.analysis.orbits.stable_algorithm1_orbit`), that orbit
    is returned (a :class:`PeriodicOrbit`, a SteadyState with
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

    .. deprecated:: use ``impactdamper.steady_state(p, attractor=True)``.
    """
    warnings.warn(
        "steady_state_auto is deprecated: use impactdamper.steady_state(p, attractor=True)",
        DeprecationWarning,
        stacklevel=2,
    )
    p = require_parameters(p)
    unknown = sorted(set(kwargs) - set(STEADY_KEYWORDS))
    if unknown:
        raise ArgumentTypeError(
            f"`{unknown[0]}` is not allowed: steady_state_auto takes the keywords of steady_state, "
            f"{', '.join(STEADY_KEYWORDS)}"
        )
    gap_tol = check_tolerances(kwargs.get("tolerances")).gap_tol
    try:
        a1 = algorithm1(p, gap_tol=gap_tol)
    except (ValueError, SearchLimitError):
        a1 = None  # no closed-form orbit here (a resonance of the impacts): simulate
    orbit = stable_algorithm1_orbit(a1, None, kwargs.get("tolerances") or Tolerances())
    if orbit is not None:
        return orbit
    return steady_state(p, **kwargs)


# ----------------------------------------------------------------------------------------
# One sweep point
# ----------------------------------------------------------------------------------------
def _compiled_step(p: Parameters, settings: SweepSettings):
    """The compiled stroboscopic map for strobe_newton's ``step`` with ``settings.compiled``, else
    None (the pure-Python map). The compiled backend is imported here, on first use."""
    if not settings.compiled:
        return None
    from impactdamper.core.compiled import map_step

    return map_step(p, settings.tolerances)


def _compiled_settle():
    """steady_state_hybrid, the compiled backend imported on first use (``import impactdamper``
    loads no numba)."""
    from impactdamper.core.compiled import steady_state_hybrid

    return steady_state_hybrid


def carry_state(p: Parameters, state: np.ndarray, mode: str) -> tuple[np.ndarray, str]:
    """The neighbour's section state made valid for ``p``: projected onto the stop if its gap
    would be negative, kept on the stop if it was in persistent contact.

    Returns the state (x1, x2, x1', x2') and ``"neighbour"`` or ``"projected"``."""
    full = np.array(state, dtype=float)
    gap = p.Delta0 - (full[1] - full[0])
    if mode == STUCK:
        full[1] = full[0] + p.Delta0
        full[3] = full[2]
        return full, "neighbour"
    if gap < 0.0:
        full[1] = full[0] + p.Delta0
        return full, "projected"
    return full, "neighbour"


def _cycle_of(s: SteadyState) -> tuple:
    """(times, states_after) of the reported cycle's impacts, from its trajectory."""
    if not s.impacts:
        return ()
    T = s.p.T
    events = s.trajectory.impacts(s.cycle_start - 1e-9 * T, s.cycle_start + max(s.period_multiple, 1) * T)
    times, after = [], []
    for imp in s.impacts:
        e = min(events, key=lambda e: abs(e.t - imp.t))
        times.append(e.t)
        after.append(e.after)
    return np.array(times), np.array(after)


def _point_from_steady(
    p: Parameters,
    value: float,
    s: SteadyState,
    *,
    method: str,
    start: str,
    start_state: np.ndarray,
    periods: int,
    multiplier: float = math.nan,
    stable: bool | None = None,
) -> SweepPoint:
    vs = p.x_st * p.omega
    if stable is None and s.regime != "nonperiodic":
        stable = True  # it attracted the simulation
    if isinstance(s, PeriodicOrbit) and s.solved:
        section, mode = _orbit_section(s)
    else:
        section, mode = section_of(s)
    return SweepPoint(
        p=p,
        value=value,
        regime=s.regime,
        period_multiple=s.period_multiple,
        impacts_per_cycle=s.impacts_per_cycle,
        label=label_of(s.regime, s.period_multiple, s.impacts_per_cycle),
        stable=stable,
        multiplier=multiplier,
        x1_max=s.x1_max,
        velocities=tuple(float(i.velocity / vs) for i in s.impacts),
        phases=tuple(float(i.phase) for i in s.impacts),
        contact_fraction=float(s.contact_fraction),
        method=method,
        periods=periods,
        start=start,
        start_state=np.array(start_state, float),
        section=section,
        section_mode=mode,
        cycle=_cycle_of(s) if s.regime in ("single_impact", "multi_impact") else (),
    )


def _orbit_section(o) -> tuple[np.ndarray, str]:
    """State at a section t = n T inside a solved orbit's stored trajectory."""
    T = o.p.T
    t = math.ceil(o.cycle_start / T) * T
    full, modes = o.trajectory.sample(np.array([t]))
    return full[0], str(modes[0])


def _closed_form(p: Parameters, value: float, regime: str, start: str, start_state: np.ndarray) -> SweepPoint | None:
    """The no-contact or persistent-contact forced response, if admissible at p."""
    model = Model(p)
    if regime == "no_contact":
        mode, fn, scale = model.free, model.gap, p.x_st
    else:
        mode, fn, scale = model.stuck, model.contact_force, model.force_scale
    # On the forced response the functional is g0 + Im(G e^{i w t}): its least value g0 - |G|.
    if fn.g0 - abs(fn.G) <= CLOSED_FORM_MARGIN * scale:
        return None
    mult = float(np.max(np.abs(np.linalg.eigvals(mode.propagator(p.T)))))
    section = model.full_state(FREE if regime == "no_contact" else STUCK, mode.forced(0.0))
    return SweepPoint(
        p=p,
        value=value,
        regime=regime,
        period_multiple=1,
        impacts_per_cycle=0,
        label=label_of(regime, 1, 0),
        stable=mult < 1.0,
        multiplier=mult,
        x1_max=float(abs(mode.Yhat[0])) / p.x_st,
        velocities=(),
        phases=(),
        contact_fraction=1.0 if regime == "stuck" else 0.0,
        method="closed_form",
        periods=0,
        start=start,
        start_state=np.array(start_state, float),
        section=section,
        section_mode=FREE if regime == "no_contact" else STUCK,
    )


def _shooting(p: Parameters, k: int, times: np.ndarray, after: np.ndarray, tol: Tolerances):
    """orbit_from_cycle, reduced to the cycle's least period; None if Newton fails."""
    try:
        # Newton's line search may try far-off impact times: overflow there is a failed trial.
        with np.errstate(over="ignore", invalid="ignore"):
            o = orbit_from_cycle(p, k, times, after, seed="orbit", tolerances=tol)
            d = _least_period(o)
            if d < k:
                zz = o.impacts_per_cycle * d // k
                o = orbit_from_cycle(p, d, o.times[:zz], o.states_after[:zz], seed="orbit", tolerances=tol)
    except (OrbitError, ValueError, np.linalg.LinAlgError, RuntimeError):
        return None
    return o


def _least_period(o) -> int:
    """Least d | k such that the solved cycle is a cycle of period d T repeated."""
    k, z, T = o.period_multiple, o.impacts_per_cycle, o.p.T
    D = state_scale(o.p)
    for d in range(1, k):
        if k % d or (z * d) % k:
            continue
        zz = z * d // k
        dt = o.times[zz:] - o.times[:-zz] - d * T
        dy = (o.states_after[zz:] - o.states_after[:-zz]) / D
        if np.all(np.abs(dt) < 1e-8 * T) and np.all(np.abs(dy) < 1e-8):
            return d
    return k


def _continue_orbit(
    p: Parameters, value: float, prev: SweepPoint, start: str, start_state: np.ndarray, tol: Tolerances
) -> SweepPoint | None:
    """Newton shooting of the neighbour's impacting cycle at p
    (:func:`~impactdamper.analysis.orbits.orbit_from_cycle`)."""
    if not prev.cycle:
        return None
    times, after = prev.cycle
    after = np.array(after, float)
    after[:, 1] = after[:, 0] + p.Delta0  # the impact states on the new stop
    o = _shooting(p, prev.period_multiple, times, after, tol)
    if o is None or not (o.admissible and o.stable and o.spectral_radius < 1.0 - STABILITY_MARGIN):
        return None
    return _point_from_steady(
        p,
        value,
        o,
        method="continuation",
        start=start,
        start_state=start_state,
        periods=0,
        multiplier=o.spectral_radius,
        stable=True,
    )


def _verify(
    p: Parameters,
    value: float,
    full: np.ndarray,
    k: int,
    settings: SweepSettings,
    *,
    method: str,
    start: str,
    start_state: np.ndarray,
    periods: int,
    rho: float,
    jacobian: np.ndarray | None = None,
) -> SweepPoint | None:
    """Simulate one cycle from a Newton solution: it must return to itself (to ``settle_tol``)
    after its least period d | k; the cycle is then described as :func:`steady_state` would
    (its :func:`~impactdamper.core.steady.describe_cycle`, on two cycles of the exact motion)."""
    T = p.T
    D = state_scale(p)
    try:
        solver = EventDrivenSolver(p, 0.0, full, settings.tolerances)
        mode0 = solver.mode
        d, mismatch = 0, math.inf
        for j in range(1, k + 1):
            solver.advance(j * T)
            if k % j == 0 and solver.mode == mode0:
                mismatch = float(np.max(np.abs(solver.state_at(j * T) - full) / D))
                if mismatch < settings.settle_tol:
                    d = j
                    break
        if not d:
            return None
        solver.advance(2 * d * T)  # the cycle and the next one (the description reads both)
        s = describe_cycle(p, solver.trajectory, 0.0, d, True, d, mismatch)
    except (RuntimeError, ValueError):
        return None
    point = _point_from_steady(
        p,
        value,
        s,
        method=method,
        start=start,
        start_state=start_state,
        periods=periods + 2 * d,
        multiplier=rho,
        stable=True,
    )
    return replace(point, jacobian=jacobian)


def _closest_recurrence(s: SteadyState, kmax: int) -> tuple[int, float]:
    """Period k <= kmax whose last k sections best repeat those k periods earlier.

    The sections are the run's (``SteadyState.sections``); without them, those of the stored
    trajectory around the reported window."""
    p = s.p
    sections = getattr(s, "sections", None)
    if sections is not None and len(sections):
        sec = np.asarray(sections, float)[-(2 * kmax + 1) :] / state_scale(p)
    else:
        T = p.T
        last = math.floor((s.cycle_start + s.cycle_duration) / T + 1e-9)
        ts = np.arange(last - 2 * kmax, last + 1) * T
        ts = ts[ts >= s.trajectory.segments[0][1].t0]
        sec = s.trajectory.sample(ts)[0] / state_scale(p)
    return _recurrence_of(sec, kmax)


def _recurrence_of(sec: np.ndarray, kmax: int) -> tuple[int, float]:
    """(k, mismatch) of the closest recurrence among scaled sections ``sec`` (oldest first)."""
    m = len(sec)
    best_k, best = 0, math.inf
    for k in range(1, kmax + 1):
        if m < 2 * k + 1:
            break
        worst = max(float(np.max(np.abs(sec[m - 1 - j] - sec[m - 1 - j - k]))) for j in range(k))
        if worst < best:
            best_k, best = k, worst
    return best_k, best


def _rescue(
    p: Parameters,
    value: float,
    s: SteadyState,
    settings: SweepSettings,
    *,
    start: str,
    start_state: np.ndarray,
    periods: int,
) -> SweepPoint | None:
    k, mismatch = _closest_recurrence(s, min(settings.max_period_multiple, RESCUE_MAX_K))
    if not k or mismatch > RESCUE_MISMATCH:
        return None
    T = p.T
    # k periods of the reported window as a cycle seed for the shooting.
    a = s.cycle_start
    b = a + k * T
    if settings.continuation:
        events = s.trajectory.impacts(a, b)
        has_contact = any(e.kind != "impact" and a <= e.t < b for e in s.trajectory.events)
        if events and not has_contact:
            times = np.array([e.t for e in events])
            after = np.array([e.after for e in events])
            o = _shooting(p, k, times, after, settings.tolerances)
            if o is not None and o.admissible and o.stable and o.spectral_radius < 1.0 - STABILITY_MARGIN:
                # Report the shortest period: verify by simulation from the orbit (settles at once).
                section, mode = _orbit_section(o)
                return _verify(
                    p,
                    value,
                    section,
                    o.period_multiple,
                    settings,
                    method="rescue",
                    start=start,
                    start_state=start_state,
                    periods=periods,
                    rho=o.spectral_radius,
                )
    full, mode = section_of(s)
    return _strobe_rescue(p, value, full, mode, k, settings, start=start, start_state=start_state, periods=periods)


def _strobe_rescue(
    p: Parameters,
    value: float,
    full: np.ndarray,
    mode: str,
    k: int,
    settings: SweepSettings,
    *,
    start: str,
    start_state: np.ndarray,
    periods: int,
) -> SweepPoint | None:
    """Step 3 of the rescue: Newton on the stroboscopic map from section state ``full``."""
    res = strobe_newton(p, full, mode, k, settings.tolerances, step=_compiled_step(p, settings))
    if res is None:
        return None
    sol, rho, used, J = res.state, res.spectral_radius, res.periods, res.jacobian
    if rho >= 1.0 - STABILITY_MARGIN:
        return None
    return _verify(
        p,
        value,
        sol,
        k,
        settings,
        method="rescue",
        start=start,
        start_state=start_state,
        periods=periods + used,
        rho=rho,
        jacobian=J,
    )


def rescue_from_sections(
    p: Parameters,
    value: float,
    sections: np.ndarray,
    section: np.ndarray,
    section_mode: str,
    settings: SweepSettings,
    *,
    start: str,
    start_state: np.ndarray,
    periods: int,
) -> SweepPoint | None:
    """The Newton rescue of a point that did not settle, from its run's last sections instead
    of its :class:`~impactdamper.core.steady.SteadyState` (the compiled batch hands them over,
    so the run is not repeated in Python). Only the rescue without accelerators
    (``settings.continuation`` False): the closest recurrence k of the last sections, then
    Newton on the stroboscopic map from ``section`` (the section state at the start of the
    reported window, in mode ``section_mode``), then the cycle verified by simulation.

    Parameters
    ----------
    sections : ndarray, shape (m, 4)
        The run's last section states (x1, x2, x1', x2'), oldest first (at least
        2 min(max_period_multiple, RESCUE_MAX_K) + 1 of them; fewer: fewer k are tried).
    periods : int
        Forcing periods the run simulated (the point's count, as solve_point's).

    Returns
    -------
    SweepPoint with method ``rescue``, or None where the rescue finds no stable cycle.
    """
    if settings.continuation:
        raise ValueError(
            "`settings` is not allowed: rescue_from_sections is the rescue without accelerators (continuation=False)"
        )
    kmax = min(settings.max_period_multiple, RESCUE_MAX_K)
    sec = np.asarray(sections, float)
    sec = sec[np.all(np.isfinite(sec), axis=1)][-(2 * kmax + 1) :] / state_scale(p)
    k, mismatch = _recurrence_of(sec, kmax)
    if not k or mismatch > RESCUE_MISMATCH:
        return None
    return _strobe_rescue(
        p,
        value,
        np.asarray(section, float),
        section_mode,
        k,
        settings,
        start=start,
        start_state=start_state,
        periods=periods,
    )


def solve_point(
    p: Parameters,
    value: float | None = None,
    previous: SweepPoint | None = None,
    *,
    state: np.ndarray | None = None,
    settings: SweepSettings | None = None,
    start: str | None = None,
) -> SweepPoint:
    """The settled motion at ``p``, continuing ``previous`` (a neighbour's point) if given.

    Parameters
    ----------
    p : Parameters
    value : float, optional
        The swept parameter's value (recorded only); default ``p.gap``.
    previous : SweepPoint, optional
        The neighbour whose motion this point starts from (see the module docstring).
    state : ndarray, shape (4,), optional
        Start state at t0 = 0 instead (no accelerators): a random start, say.
    settings : SweepSettings, optional
    start : str, optional
        Label of the start recorded in the result (default from how it started).

    Returns
    -------
    SweepPoint
    """
    settings = settings or SweepSettings()
    value = p.gap if value is None else float(value)
    t_begin = time.perf_counter()
    if previous is not None and state is not None:
        raise ValueError("`state` is not allowed together with `previous`: give one start")
    if previous is not None:
        full, how = carry_state(p, previous.section, previous.section_mode)
    elif state is not None:
        full, how = np.array(state, float), "random"
        if full.shape != (4,) or not np.all(np.isfinite(full)):
            raise ValueError(f"`state` = {state!r} is not allowed: must be 4 finite numbers (x1, x2, x1', x2')")
    else:
        full, how = default_initial_state(p), "default"
    start = start or how
    result = None
    if previous is not None and settings.continuation and previous.periodic:
        if previous.regime in ("stuck", "no_contact"):
            result = _closed_form(p, value, previous.regime, start, full)
        elif previous.regime in ("single_impact", "multi_impact"):
            result = _continue_orbit(p, value, previous, start, full, settings.tolerances)
        if result is None and previous.regime in ("chatter", "single_impact", "multi_impact"):
            res = strobe_newton(
                p,
                full,
                previous.section_mode,
                previous.period_multiple,
                settings.tolerances,
                jacobian=previous.jacobian,
                step=_compiled_step(p, settings),
            )
            if res is not None and res.spectral_radius < 1.0 - STABILITY_MARGIN:
                result = _verify(
                    p,
                    value,
                    res.state,
                    previous.period_multiple,
                    settings,
                    method="newton",
                    start=start,
                    start_state=full,
                    periods=res.periods,
                    rho=res.spectral_radius,
                    jacobian=res.jacobian,
                )
    if result is None:
        cap = settings.max_periods
        if previous is not None and not previous.periodic:
            cap = settings.max_periods_after_nonperiodic
        try:
            settle = _compiled_settle() if settings.compiled else steady_state
            s = settle(
                p,
                state=full,
                tolerances=settings.tolerances,
                settle_tol=settings.settle_tol,
                max_periods=cap,
                max_period_multiple=settings.max_period_multiple,
            )
        except RuntimeError as err:  # the event solver's guards (SearchLimitError, degenerate contact)
            log.warning("the simulation failed at value %r (%s): %s", value, p, err)
            return SweepPoint(
                p=p,
                value=value,
                regime=FAILED,
                period_multiple=0,
                impacts_per_cycle=0,
                label=label_of(FAILED, 0, 0),
                stable=None,
                multiplier=math.nan,
                x1_max=math.nan,
                velocities=(),
                phases=(),
                contact_fraction=math.nan,
                method="error",
                periods=0,
                start=start,
                start_state=np.array(full, float),
                section=np.array(full, float),
                section_mode=FREE,
                elapsed=time.perf_counter() - t_begin,
            )
        periods = s.periods + max(s.period_multiple, 1) + 1
        if not s.settled and settings.rescue:
            result = _rescue(p, value, s, settings, start=start, start_state=full, periods=periods)
        if result is None:
            result = _point_from_steady(
                p, value, s, method="simulation", start=start, start_state=full, periods=periods
            )
    return replace(result, elapsed=time.perf_counter() - t_begin)
