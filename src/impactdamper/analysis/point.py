"""A sweep point: how it is settled, its result and its label, and how a solved motion becomes one.

The vocabulary shared by the cheapest-first ladder (:func:`impactdamper.analysis.ladder.solve_point`)
and the Newton rescue (:mod:`impactdamper.analysis.rescue`): the settings
(:class:`SweepSettings`), the result (:class:`SweepPoint`), Peterka's label (:func:`label_of`), and
the steps that turn a solved motion into a point -- a settled run or an orbit of Timofeev et al.
(2019)'s Algorithm No. 1 / the Newton shooting (:func:`point_from_steady`), a Newton solution on the
stroboscopic map verified by one simulated cycle (:func:`verify_cycle`), an impacting cycle solved
by shooting at its least period (:func:`shoot_cycle`).

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
from dataclasses import MISSING, dataclass, field, fields, replace

import numpy as np

from impactdamper.analysis.cycle import PeriodicOrbit, impact_states, least_period
from impactdamper.analysis.lyapunov import DEFAULT_BLOCKS, DEFAULT_PERIODS
from impactdamper.analysis.orbits import OrbitError, orbit_from_cycle
from impactdamper.core.backends import Backend, check_backend
from impactdamper.core.model import FREE
from impactdamper.core.parameters import ArgumentTypeError, Parameters, state_scale
from impactdamper.core.simulate import EventDrivenSolver, Tolerances
from impactdamper.core.settled_cycle import SteadyState, describe_cycle, section_of
from impactdamper.core.validation import MAX_PERIODS_LIMIT, SettleOptions

__all__ = [
    "SweepSettings",
    "SWEEP_SETTLE",
    "SweepPoint",
    "FAILED",
    "LABELS_ORDER",
    "STABILITY_MARGIN",
    "label_of",
    "point_from_steady",
    "orbit_section",
    "shoot_cycle",
    "verify_cycle",
    "failed_point",
]

log = logging.getLogger(__name__)

# Orbits whose largest Floquet multiplier is within this of 1 are too close to a bifurcation
# to be trusted as the attractor the simulation would settle on: the simulation decides there.
STABILITY_MARGIN = 1e-6

# Regime of a point whose simulation raised (the event solver's guards, e.g. its step budget
# at a lift-off whose contact force touches zero almost tangentially); label "err".
FAILED = "failed"
# Legend order of the labels' regime classes (figures, tables).
LABELS_ORDER = ("stuck", "chatter", "multi_impact", "single_impact", "no_contact", "nonperiodic", FAILED)


# A sweep point's settled-motion search: looser and shorter than a single point's (the
# SettleOptions defaults), since each point starts from its settled neighbour.
SWEEP_SETTLE = SettleOptions(settle_tol=1e-9, max_periods=150)


class _SettleField:
    """A field of :class:`SweepSettings`' ``settle`` read as its own (on the class: the default's)."""

    def __set_name__(self, owner, name: str) -> None:
        self.name = name

    def __get__(self, settings, owner=None):
        return getattr(SWEEP_SETTLE if settings is None else settings.settle, self.name)


@dataclass(frozen=True, init=False)
class SweepSettings:
    """How each sweep point is settled.

    Built by keyword: ``SweepSettings(settle=SettleOptions(...), rescue=False)``, or with
    :class:`~impactdamper.core.validation.SettleOptions`' fields by name (``settle_tol``,
    ``max_periods``, ``max_period_multiple``), which replace those of ``settle``; they read back
    as attributes (``settings.max_periods``).

    Attributes
    ----------
    settle : SettleOptions
        The settled-motion search of each point's simulation (default :data:`SWEEP_SETTLE`):
        its section mismatch, its cap of forcing periods before a point is ``nonperiodic``
        (more than twice its largest k, which the rescue needs) and the largest k tried.
    max_periods_after_nonperiodic : int
        The same cap when the neighbour the point starts from was itself nonperiodic (inside
        a chaotic band most points are; a periodic window there is found within this cap or
        by the rescue from its closest recurrence).
    continuation : bool
        Use the accelerators 1-3 (closed form, orbit continuation, stroboscopic Newton);
        False: every point is simulated (steps 4-5 only, and the rescue with simulation).
    rescue : bool
        Try the Newton rescue on points that did not settle.
    tolerances : Tolerances
        Event-solver tolerances.
    backend : str or Backend
        Who runs each simulation and each stroboscopic map (:data:`~impactdamper.core.backends.BACKENDS`:
        ``"auto"``, ``"compiled"`` or ``"python"``, or a :class:`~impactdamper.core.backends.Backend`,
        resolved by :func:`~impactdamper.core.backends.get_backend`): the same motion either way.
    classify : bool
        The many-point call (:func:`~impactdamper.analysis.batch.steady_states`) labels each
        point left ``nonperiodic`` after the rescue by its Lyapunov spectrum
        (:func:`~impactdamper.analysis.lyapunov.lyapunov_spectrum` from the section its run
        hands on: chaotic, quasi-periodic, periodic or not settled). False (default): no
        spectrum, the labels left empty.
    classify_periods : int
        Forcing periods the spectrum averages (a multiple of its 10 blocks), after its 200
        periods of warm-up.
    """

    settle: SettleOptions = SWEEP_SETTLE
    max_periods_after_nonperiodic: int = 50
    continuation: bool = True
    rescue: bool = True
    tolerances: Tolerances = field(default_factory=Tolerances)
    backend: str | Backend = "auto"
    classify: bool = False
    classify_periods: int = DEFAULT_PERIODS

    settle_tol = _SettleField()
    max_periods = _SettleField()
    max_period_multiple = _SettleField()

    def __init__(self, settle: SettleOptions = SWEEP_SETTLE, **changes) -> None:
        if not isinstance(settle, SettleOptions):
            raise ArgumentTypeError(f"`settle` = {settle!r} is not allowed: must be a SettleOptions")
        own = fields(SweepSettings)[1:]
        settle_changes = {f.name: changes.pop(f.name) for f in fields(SettleOptions) if f.name in changes}
        for name in changes.keys() - {f.name for f in own}:
            raise TypeError(f"SweepSettings() got an unexpected keyword argument {name!r}")
        multiple = settle_changes.get("max_period_multiple", settle.max_period_multiple)
        if isinstance(multiple, int) and 2 * multiple >= MAX_PERIODS_LIMIT:  # (no max_periods could hold it)
            raise ValueError(
                f"`max_period_multiple` = {multiple!r} is not allowed: must be below "
                f"{MAX_PERIODS_LIMIT // 2} (max_periods, at most {MAX_PERIODS_LIMIT}, must exceed twice it)"
            )
        object.__setattr__(self, "settle", replace(settle, **settle_changes))
        for f in own:
            default = f.default_factory() if f.default is MISSING else f.default
            object.__setattr__(self, f.name, changes.get(f.name, default))
        self.__post_init__()

    def __post_init__(self) -> None:
        for name in ("continuation", "rescue", "classify"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"`{name}` = {getattr(self, name)!r} is not allowed: must be True or False")
        check_backend(self.backend)
        if not isinstance(self.tolerances, Tolerances):
            raise ValueError(f"`tolerances` = {self.tolerances!r} is not allowed: must be a Tolerances")
        if not 2 * self.max_period_multiple < self.max_periods:  # (the rescue looks back over 2 k periods)
            raise ValueError(
                f"`max_periods` = {self.max_periods!r} is not allowed: must be an integer > "
                f"2 max_period_multiple = {2 * self.max_period_multiple}, at most {MAX_PERIODS_LIMIT}"
            )
        if not (
            isinstance(self.max_periods_after_nonperiodic, int)
            and 2 * self.max_period_multiple < self.max_periods_after_nonperiodic <= self.max_periods
        ):
            raise ValueError(
                f"`max_periods_after_nonperiodic` = {self.max_periods_after_nonperiodic!r} is not allowed: "
                f"must be an integer in (2 max_period_multiple, max_periods]"
            )
        if not (
            isinstance(self.classify_periods, int)
            and not isinstance(self.classify_periods, bool)
            and DEFAULT_BLOCKS <= self.classify_periods <= MAX_PERIODS_LIMIT
            and self.classify_periods % DEFAULT_BLOCKS == 0
        ):
            raise ValueError(
                f"`classify_periods` = {self.classify_periods!r} is not allowed: must be a multiple of "
                f"{DEFAULT_BLOCKS} in [{DEFAULT_BLOCKS}, {MAX_PERIODS_LIMIT}]"
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
        One of :data:`impactdamper.core.settled_cycle.REGIMES`.
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
    error : str
        For regime ``failed``: the solver's one-line error ("" otherwise; not part of the
        result's identity).
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
    error: str = field(repr=False, default="", compare=False)

    @classmethod
    def labelled(cls, p: Parameters, value: float, regime: str, k: int, z: int, **fields) -> SweepPoint:
        """The point of a motion of ``regime`` with k = ``k``, z = ``z``, its ``label`` theirs
        (:func:`label_of`); ``fields`` the other attributes."""
        label = label_of(regime, k, z)
        return cls(p=p, value=value, regime=regime, period_multiple=k, impacts_per_cycle=z, label=label, **fields)

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


def failed_point(
    p: Parameters, value: float, start: str, start_state: np.ndarray, error: BaseException | str
) -> SweepPoint:
    """The point whose simulation stopped on one of the event solver's guards (a work bound:
    :class:`~impactdamper.core.events.SearchLimitError`, degenerate contact): regime ``failed``,
    label ``err``, its section the state it started from (the next point starts there too).
    The error's line is logged as a warning."""
    log.warning("the simulation failed at value %r (%s): %s", value, p, error)
    full = np.array(start_state, float)
    return SweepPoint.labelled(
        p,
        value,
        FAILED,
        0,
        0,
        stable=None,
        multiplier=math.nan,
        x1_max=math.nan,
        velocities=(),
        phases=(),
        contact_fraction=math.nan,
        method="error",
        periods=0,
        start=start,
        start_state=full,
        section=full.copy(),
        section_mode=FREE,
        error=str(error),
    )


def point_from_steady(
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
        section, mode = orbit_section(s)
    else:
        section, mode = section_of(s)
    return SweepPoint.labelled(
        p,
        value,
        s.regime,
        s.period_multiple,
        s.impacts_per_cycle,
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
        cycle=impact_states(s) if s.regime in ("single_impact", "multi_impact") else (),
    )


def orbit_section(o) -> tuple[np.ndarray, str]:
    """State at a section t = n T inside a solved orbit's stored trajectory."""
    T = o.p.T
    t = math.ceil(o.cycle_start / T) * T
    full, modes = o.trajectory.sample(np.array([t]))
    return full[0], str(modes[0])


def shoot_cycle(p: Parameters, k: int, times: np.ndarray, after: np.ndarray, tol: Tolerances):
    """orbit_from_cycle, reduced to the cycle's least period; None if Newton fails."""
    try:
        # Newton's line search may try far-off impact times: overflow there is a failed trial.
        with np.errstate(over="ignore", invalid="ignore"):
            o = orbit_from_cycle(p, k, times, after, seed="orbit", tolerances=tol)
            d = least_period(p, k, o.times, o.states_after, 1e-8)
            if d < k:
                zz = o.impacts_per_cycle * d // k
                o = orbit_from_cycle(p, d, o.times[:zz], o.states_after[:zz], seed="orbit", tolerances=tol)
    except (OrbitError, ValueError, np.linalg.LinAlgError, RuntimeError):
        return None
    return o


def verify_cycle(
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
    (its :func:`~impactdamper.core.settled_cycle.describe_cycle`, on two cycles of the exact motion)."""
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
    point = point_from_steady(
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
