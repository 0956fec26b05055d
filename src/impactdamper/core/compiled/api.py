"""The compiled solver's Python entry points: arguments checked, kernels run, results typed.

Each entry point validates its arguments as the reference does, packs the parameters
(:mod:`~impactdamper.core.compiled.pack`), runs a kernel and returns a small dataclass or the
reference's :class:`~impactdamper.core.simulate.Trajectory`. Where the kernels do not apply or
stop on an error, the reference runs instead, and the result says so.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass

import numpy as np

from impactdamper.core.compiled.layout import ERR_CAPACITY, EVENT_KINDS, FALLBACK_REASONS, MODE_FREE, OK
from impactdamper.core.compiled.loop import count_kernel, pack_simulate_kernel, simulate_kernel
from impactdamper.core.compiled.pack import PACKING_ERRORS, Pack, pack_parameters, packing_values
from impactdamper.core.compiled.settle import steady_kernel
from impactdamper.core.events import Segment
from impactdamper.core.model import FREE, STUCK, Model
from impactdamper.core.parameters import Parameters, finite_argument, require_parameters
from impactdamper.core.simulate import (
    MAX_SIMULATE_PERIODS,
    default_initial_state,
    Event,
    EventDrivenSolver,
    Tolerances,
    Trajectory,
    check_start_time,
    check_state,
    check_tolerances,
    simulate,
)
from impactdamper.core.steady import (
    NONPERIODIC_WINDOW,
    PERIODS_BEFORE_CYCLE,
    REGIMES,
    CycleImpact,
    SteadyState,
    check_settle_options,
    describe_run,
    section_of,
    start_in_first_period,
    steady_state,
)

__all__ = [
    "CompiledRun",
    "CompiledSteady",
    "run_compiled",
    "simulate_compiled",
    "steady_state_compiled",
    "steady_state_hybrid",
    "steady_state_full",
    "strobe_step_compiled",
    "map_step",
    "count_events_compiled",
    "INITIAL_CAPACITY",
]

# Events and segments held before the buffers grow (the run is repeated with 4 times as many):
# a settled cycle's description holds ~10 periods of a few events each; larger buffers cost more
# to allocate than the rare repeat.
INITIAL_CAPACITY = 256
# Events per forcing period a run's buffers are first sized for (a periodic impacting motion has
# 1-3; a chatter cycle ~30, found by growing them).
EVENTS_PER_PERIOD_GUESS = 4


def _checked_state(p: Parameters, state, tol: Tolerances) -> np.ndarray:
    """The start state, validated as the reference's solver does (by constructing it when the
    state is unusual: the reference raises the named error)."""
    full = check_state(state, p)
    if full is None:
        return default_initial_state(p)
    gap = p.Delta0 - (full[1] - full[0])
    if gap < -tol.gap_tol * p.x_st:
        EventDrivenSolver(p, t0=0.0, state=full, tolerances=tol)  # raises the reference's message
    return full


@dataclass(frozen=True)
class CompiledRun:
    """A compiled run's events and segments, as arrays (no Python object per event).

    Attributes
    ----------
    kinds : ndarray of int, shape (E,)
        Indices into :data:`EVENT_KINDS`.
    events : ndarray, shape (E, 12)
        Per event: t (s), closing velocity (m/s), pulse (N s), state before (4), after (4),
        accumulation time t_inf (s).
    segment_modes : ndarray of int, shape (S,)
        0 free, 1 stuck.
    segments : ndarray, shape (S, 5)
        Per segment: start time t0 (s) and start state (4; stuck: x1, x1', 0, 0).
    """

    kinds: np.ndarray
    events: np.ndarray
    segment_modes: np.ndarray
    segments: np.ndarray

    @property
    def times(self) -> np.ndarray:
        return self.events[:, 0]


def run_compiled(
    p: Parameters,
    t_end: float,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    *,
    pack: Pack | None = None,
) -> CompiledRun | None:
    """Algorithm No. 2 with contact modes from ``t0`` to ``t_end`` in the kernels, as arrays.

    Parameters
    ----------
    p, t_end, t0, state, tolerances
        As for :func:`simulate_compiled` (validated there, not here).
    pack : Pack, optional
        :func:`pack_parameters` of ``p`` and ``tolerances``, if already made.

    Returns
    -------
    CompiledRun, or None where the kernels do not apply or stopped on an error (the caller
    then runs the reference).
    """
    if pack is None:  # packed in the same compiled call as the run
        v, tols, flag = packing_values(p, tolerances)
    else:
        flag = pack.fallback
    if flag:
        return None
    full = default_initial_state(p) if state is None else np.asarray(state, dtype=float)
    capacity = max(INITIAL_CAPACITY, int(EVENTS_PER_PERIOD_GUESS * (float(t_end) - float(t0)) / p.T))
    while True:
        if pack is None:
            try:
                flag, err, ev_k, ev_f, seg_m, seg_f, _ = pack_simulate_kernel(
                    v, tols, float(t0), full, float(t_end), capacity
                )
            except PACKING_ERRORS:
                return None
        else:
            err, ev_k, ev_f, seg_m, seg_f, _ = simulate_kernel(
                pack.cm, pack.fm, pack.fc, pack.fk, pack.fg, pack.s, float(t0), full, float(t_end), capacity
            )
        if flag or err != ERR_CAPACITY:
            break
        capacity *= 4
    return None if flag or err else CompiledRun(ev_k, ev_f, seg_m, seg_f)


def simulate_compiled(
    p: Parameters, t_end: float, t0: float = 0.0, state: np.ndarray | None = None, tolerances: Tolerances | None = None
) -> Trajectory:
    """Algorithm No. 2 with contact modes from ``t0`` to ``t_end``, compiled.

    The same motion as :func:`impactdamper.core.simulate.simulate` (the same events, kinds and
    order; times to rounding, see the tests): a :class:`Trajectory` whose segments are the
    reference's :class:`~impactdamper.core.events.Segment` objects, so ``sample`` works as
    there. Where the kernels do not apply (see the package docstring) the reference runs
    instead; the returned trajectory's ``compiled`` attribute says which ran.

    Parameters
    ----------
    p : Parameters
    t_end, t0 : float
        End and start, s.
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0; default Algorithm No. 2's step 1.
    tolerances : Tolerances, optional

    Raises
    ------
    TypeError, ValueError, SearchLimitError
        As :func:`~impactdamper.core.simulate.simulate` (the reference raises them).
    """
    p = require_parameters(p)
    tol = check_tolerances(tolerances)
    t_endf = finite_argument("t_end", t_end)
    t0f = check_start_time(t0, p)
    check_start_time(t_endf, p, "t_end")
    if not t_endf > t0f or (t_endf - t0f) / p.T > MAX_SIMULATE_PERIODS:
        simulate(p, t_end, t0, state, tolerances)  # raises the reference's named error
    full = _checked_state(p, state, tol)
    run = run_compiled(p, t_endf, t0f, full, tol)
    if run is None:
        traj = simulate(p, t_end, t0, state, tolerances)  # raises the reference's error, or runs where it must
        traj.fallback = _fallback_reason(p, tol)
        return traj
    return _trajectory(p, run.kinds, run.events, run.segment_modes, run.segments)


def _trajectory(p: Parameters, ev_k, ev_f, seg_m, seg_f) -> Trajectory:
    model = Model(p)
    traj = Trajectory(model, compiled=True)
    for m, row in zip(seg_m.tolist(), seg_f):
        name = FREE if m == MODE_FREE else STUCK
        n = 4 if m == MODE_FREE else 2
        traj.segments.append((name, Segment(model.mode(name), float(row[0]), row[1 : 1 + n].copy())))
    for k, row in zip(ev_k.tolist(), ev_f):
        traj.events.append(
            Event(
                float(row[0]),
                EVENT_KINDS[k],
                float(row[1]),
                float(row[2]),
                row[3:7].copy(),
                row[7:11].copy(),
                float(row[11]),
            )
        )
    return traj


def _fallback_reason(p: Parameters, tol: Tolerances) -> str:
    """Why the kernels did not run ``p``: a :data:`FALLBACK_REASONS` entry, or "error" (they
    stopped on an error)."""
    flag = pack_parameters(p, tol).fallback
    return FALLBACK_REASONS[flag] if flag else "error"


def count_events_compiled(
    p: Parameters, t_end: float, t0: float = 0.0, state: np.ndarray | None = None, tolerances: Tolerances | None = None
) -> int:
    """Events of the run from ``t0`` to ``t_end`` without recording them (the solver's pure
    cost, for benchmarks). Raises ValueError if the kernels do not apply to ``p``."""
    pack = pack_parameters(p, tolerances)
    if pack.fallback:
        raise ValueError(
            f"`p` = {p!r} is not allowed here: the kernels do not apply ({FALLBACK_REASONS[pack.fallback]})"
        )
    full = _checked_state(p, state, check_tolerances(tolerances))
    err, n = count_kernel(pack.cm, pack.fm, pack.fc, pack.fk, pack.fg, pack.s, float(t0), full, float(t_end))
    if err:
        raise RuntimeError(f"the compiled run failed with error code {err}; run simulate() for the message")
    return int(n)


@dataclass(frozen=True)
class CompiledSteady:
    """The settled motion's fields that sweeps and maps read (those of
    :class:`~impactdamper.core.steady.SteadyState`).

    Attributes
    ----------
    regime : str
        One of :data:`impactdamper.core.steady.REGIMES`.
    period_multiple : int
        k in T_c = k T (0 when nonperiodic).
    impact_times, impact_phases, velocities, impulses : ndarray, shape (z,)
        The cycle's impacts: absolute times (s), forcing phases t/T mod 1, closing velocities
        (m/s), pulses (N s).
    cycle_start : float
        Time the reported cycle starts, s.
    contact_fraction : float
    x1_max : float
        max |x1|/x_st over the cycle.
    periods : int
        Forcing periods simulated until settled.
    residual : float
        Largest relative section mismatch over the final cycle.
    section : ndarray, shape (4,)
        State at the first section t = n T in the cycle (carried to a sweep's next point).
    section_mode : str
        ``free`` or ``stuck`` there.
    fallback : str
        "" if the kernels computed it, else why the reference did (see :data:`FALLBACK_REASONS`).
    """

    regime: str
    period_multiple: int
    impact_times: np.ndarray
    impact_phases: np.ndarray
    velocities: np.ndarray
    impulses: np.ndarray
    cycle_start: float
    contact_fraction: float
    x1_max: float
    periods: int
    residual: float
    section: np.ndarray
    section_mode: str
    fallback: str = ""

    @property
    def impacts_per_cycle(self) -> int:
        return len(self.impact_phases)


def _from_reference(p: Parameters, s, reason: str) -> CompiledSteady:
    section, mode = section_of(s)  # the reference's own reading of the section
    return CompiledSteady(
        regime=s.regime,
        period_multiple=s.period_multiple,
        impact_times=np.array([i.t for i in s.impacts]),
        impact_phases=np.array([i.phase for i in s.impacts]),
        velocities=np.array([i.velocity for i in s.impacts]),
        impulses=np.array([i.impulse for i in s.impacts]),
        cycle_start=s.cycle_start,
        contact_fraction=float(s.contact_fraction),
        x1_max=float(s.x1_max),
        periods=s.periods,
        residual=float(s.residual),
        section=np.asarray(section, float),
        section_mode=mode,
        fallback=reason,
    )


def steady_state_compiled(
    p: Parameters,
    *,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    settle_tol: float = 1e-10,
    max_periods: int = 4000,
    max_period_multiple: int = 8,
) -> CompiledSteady:
    """The settled motion, compiled: :func:`impactdamper.core.steady.steady_state`'s result.

    Parameters and their meaning as there. The reference runs instead (and ``fallback`` says
    why) where the kernels do not apply, or where they stopped on an error (the reference then
    raises its own exception, with its message).

    Raises
    ------
    TypeError, ValueError, SearchLimitError
        As :func:`~impactdamper.core.steady.steady_state`.

    .. deprecated:: use ``impactdamper.steady_state(p, backend="compiled")`` (a full
       :class:`~impactdamper.core.steady.SteadyState` in about the same time).
    """
    warnings.warn(
        "steady_state_compiled is deprecated: use impactdamper.steady_state(p, backend='compiled')",
        DeprecationWarning,
        stacklevel=2,
    )
    p = require_parameters(p)
    tol = check_tolerances(tolerances)
    t0 = finite_argument("t0", t0)
    settle_tol, max_periods, max_period_multiple = check_settle_options(settle_tol, max_periods, max_period_multiple)
    pack = pack_parameters(p, tol)
    args = dict(
        t0=t0,
        state=state,
        tolerances=tolerances,
        settle_tol=settle_tol,
        max_periods=max_periods,
        max_period_multiple=max_period_multiple,
    )
    if pack.fallback:
        return _from_reference(p, steady_state(p, **args), FALLBACK_REASONS[pack.fallback])
    start = start_in_first_period(p, t0)
    full = _checked_state(p, state, tol)
    result = _steady_run(pack, start, full, state is None, settle_tol, max_periods, max_period_multiple)
    if result is None:
        return _from_reference(p, steady_state(p, **args), "error")
    return result


# steady_kernel's section tail, not wanted here.
NO_TAIL = np.zeros((0, 5))


def _steady_run(
    pack: Pack, t0: float, full: np.ndarray, default_start: bool, settle_tol: float, max_periods: int, kmax: int
) -> CompiledSteady | None:
    """One kernel run; None if the kernels stopped on an error."""
    capacity = INITIAL_CAPACITY
    out_imp = np.zeros((64 * kmax, 5))
    section = np.zeros(5)
    while True:
        (err, regime, k, z, start, frac, x1_max, n, residual) = steady_kernel(
            pack.cm,
            pack.fm,
            pack.fc,
            pack.fk,
            pack.fg,
            pack.s,
            t0,
            full,
            default_start,
            settle_tol,
            max_periods,
            kmax,
            capacity,
            out_imp,
            section,
            NO_TAIL,
        )
        if err == ERR_CAPACITY:
            capacity *= 4
            continue
        if err == OK and z > out_imp.shape[0]:
            out_imp = np.zeros((z, 5))
            continue
        break
    if err:
        return None
    imp = out_imp[:z]
    return CompiledSteady(
        regime=REGIMES[regime],
        period_multiple=int(k),
        impact_times=imp[:, 0].copy(),
        impact_phases=imp[:, 2].copy(),
        velocities=imp[:, 3].copy(),
        impulses=imp[:, 4].copy(),
        cycle_start=float(start),
        contact_fraction=float(frac),
        x1_max=float(x1_max),
        periods=int(n),
        residual=float(residual),
        section=section[:4].copy(),
        section_mode="free" if section[4] == MODE_FREE else "stuck",
    )


def steady_state_hybrid(
    p: Parameters,
    *,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    settle_tol: float = 1e-10,
    max_periods: int = 4000,
    max_period_multiple: int = 8,
) -> SteadyState:
    """:func:`impactdamper.core.steady.steady_state`'s full result (a
    :class:`~impactdamper.core.steady.SteadyState` with its trajectory and sections), its period
    loop run by the kernels: the run until the motion repeats is compiled, and the settled cycle
    is then described as there (:func:`~impactdamper.core.steady.describe_run`, on a fresh
    compiled run of a few cycles from the kernels' section state, as the reference's
    :class:`~impactdamper.core.simulate.Trajectory`). Where the kernels do not apply, or stop on
    an error, the reference runs the whole of it.

    Arguments, result and errors as :func:`~impactdamper.core.steady.steady_state`'s.
    """
    p = require_parameters(p)
    tol = check_tolerances(tolerances)
    t0f = finite_argument("t0", t0)
    settle_tol, max_periods, max_period_multiple = check_settle_options(settle_tol, max_periods, max_period_multiple)
    args = dict(
        t0=t0,
        state=state,
        tolerances=tolerances,
        settle_tol=settle_tol,
        max_periods=max_periods,
        max_period_multiple=max_period_multiple,
    )
    pack = pack_parameters(p, tol)
    if pack.fallback:
        return steady_state(p, **args)
    start = start_in_first_period(p, t0f)
    full = _checked_state(p, state, tol)
    tail = np.full((max_periods, 5), np.nan)
    out_imp = np.zeros((64 * max_period_multiple, 5))
    section = np.zeros(5)
    capacity = INITIAL_CAPACITY
    while True:
        err, _, k, _, _, _, _, n, residual = steady_kernel(
            pack.cm,
            pack.fm,
            pack.fc,
            pack.fk,
            pack.fg,
            pack.s,
            start,
            full,
            state is None,
            settle_tol,
            max_periods,
            max_period_multiple,
            capacity,
            out_imp,
            section,
            tail,
        )
        if err != ERR_CAPACITY:
            break
        capacity *= 4
    if err:
        return steady_state(p, **args)  # the reference's own error, or its result
    # The reference's start state (its solver's state at the start: the given one or step 1).
    start_state = full if state is not None else EventDrivenSolver(p, t0=start, tolerances=tol).state_at(start)
    return describe_run(
        p,
        start,
        tail[max_periods - n :, :4],
        int(k),
        float(residual),
        start_state,
        tol,
        simulate_from=simulate_compiled,
    )


def strobe_step_compiled(
    p: Parameters,
    t0: float,
    state: np.ndarray,
    periods: int,
    tolerances: Tolerances | None = None,
    *,
    pack: Pack | None = None,
    model: Model | None = None,
) -> tuple[np.ndarray, str] | None:
    """:func:`impactdamper.analysis.strobe.stroboscopic_step` by the kernels: the state and mode at
    t0 + periods T from ``state`` at t0 (the last segment flowed to there by the Python flow).
    ``pack`` and ``model`` (of ``p`` and ``tolerances``), if already made: a Newton iteration
    evaluates the map many times at one parameter set.

    Returns None where the kernels do not apply or stopped on an error (the caller runs the
    reference, which raises its own error where there is one).
    """
    pack = pack_parameters(p, tolerances) if pack is None else pack
    if pack.fallback:
        return None
    t_end = float(t0) + periods * p.T
    run = run_compiled(p, t_end, float(t0), np.asarray(state, dtype=float), tolerances, pack=pack)
    if run is None:
        return None
    model = Model(p) if model is None else model
    name = FREE if run.segment_modes[-1] == MODE_FREE else STUCK
    row = run.segments[-1]
    seg = Segment(model.mode(name), float(row[0]), row[1 : 1 + (4 if name == FREE else 2)].copy())
    return model.full_state(name, seg.state(np.array([t_end])))[0], name


def map_step(p: Parameters, tolerances: Tolerances | None = None):
    """The stroboscopic map of ``p`` by the kernels, for
    :func:`impactdamper.analysis.strobe.strobe_newton`'s ``step``: ``step(state, k)`` -> the
    state and mode at t = k T from ``state`` at t = 0 (:func:`strobe_step_compiled`, its
    parameters packed once: a Newton iteration evaluates the map many times at one parameter
    set), or None where the kernels do not apply (strobe_newton then runs the reference)."""
    pack = pack_parameters(p, tolerances)
    model = Model(p)

    def step(state, k):
        return strobe_step_compiled(p, 0.0, state, k, tolerances, pack=pack, model=model)

    return step


class _DeferredTrajectory(Trajectory):
    """A :class:`Trajectory` run on first use: ``build()`` makes it when its model, segments or
    events are first read (the settled motion's numbers come from the kernels; the stored motion
    around the cycle costs as much again, and most callers never read it)."""

    def __init__(self, build):  # (no Trajectory.__init__: its attributes come from build())
        self._build = build

    def _made(self) -> None:
        build = self.__dict__.pop("_build", None)
        if build is not None:
            self.__dict__.update(build().__dict__)

    def __getattr__(self, name: str):  # (only for attributes not yet there)
        if "_build" not in self.__dict__:
            raise AttributeError(name)
        self._made()
        return getattr(self, name)

    def __getstate__(self):  # (pickled as the built trajectory, not as its recipe)
        self._made()
        return self.__dict__


def steady_state_full(
    p: Parameters,
    *,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    settle_tol: float = 1e-10,
    max_periods: int = 4000,
    max_period_multiple: int = 8,
) -> SteadyState:
    """:func:`impactdamper.core.steady.steady_state`'s full result by the kernels: the period
    loop and the cycle's description (impacts, regime, contact fraction, x1_max) compiled, the
    stored trajectory around the cycle run (compiled) when first read. A cycle with persistent
    contact has its contact phases described as :func:`steady_state_hybrid` does. Where the
    kernels do not apply, or stop on an error, the reference runs the whole of it and
    ``fallback`` says why (the reference raises its own errors).

    The same motion as the reference (regime, k, z, impact phases; tests/unit/test_compiled.py);
    x1_max is refined by golden-section search where the reference uses Brent's (both to
    1e-12 T). Arguments and errors as :func:`~impactdamper.core.steady.steady_state`'s; the
    result's ``backend`` is ``compiled`` or, with ``fallback`` set, ``python``.
    """
    p = require_parameters(p)
    tol = check_tolerances(tolerances)
    t0f = finite_argument("t0", t0)
    settle_tol, max_periods, max_period_multiple = check_settle_options(settle_tol, max_periods, max_period_multiple)
    args = dict(
        t0=t0,
        state=state,
        tolerances=tolerances,
        settle_tol=settle_tol,
        max_periods=max_periods,
        max_period_multiple=max_period_multiple,
    )
    pack = pack_parameters(p, tol)
    if pack.fallback:
        return dataclasses.replace(steady_state(p, **args), fallback=FALLBACK_REASONS[pack.fallback])
    start = start_in_first_period(p, t0f)
    full = _checked_state(p, state, tol)
    tail = np.full((max_periods, 5), np.nan)
    out_imp = np.zeros((64 * max_period_multiple, 5))
    section = np.zeros(5)
    capacity = INITIAL_CAPACITY
    while True:
        (err, regime, k, z, cycle_start, frac, x1_max, n, residual) = steady_kernel(
            pack.cm,
            pack.fm,
            pack.fc,
            pack.fk,
            pack.fg,
            pack.s,
            start,
            full,
            state is None,
            settle_tol,
            max_periods,
            max_period_multiple,
            capacity,
            out_imp,
            section,
            tail,
        )
        if err == ERR_CAPACITY:
            capacity *= 4
            continue
        if err == OK and z > out_imp.shape[0]:
            out_imp = np.zeros((z, 5))
            continue
        break
    if err:
        return dataclasses.replace(
            steady_state(p, **args), fallback="error"
        )  # the reference's own error, or its result
    states = tail[max_periods - n :, :4]
    if frac > 0.0:  # contact phases: described on the trajectory, as the hybrid does
        start_state = full if state is not None else EventDrivenSolver(p, t0=start, tolerances=tol).state_at(start)
        s = describe_run(p, start, states, int(k), float(residual), start_state, tol, simulate_from=simulate_compiled)
        return dataclasses.replace(s, backend="compiled")
    # The run describe_run would make (steady.describe_run): from a section one cycle (and 4
    # periods) before the reported one to one cycle after it, on the clock of the run's start.
    kk = int(k) if k else min(NONPERIODIC_WINDOW, n)
    first = max(n - kk - max(kk, PERIODS_BEFORE_CYCLE), 0)
    t_end = start + (n - first + kk + 1) * p.T
    from_state = states[first - 1].copy() if first else full

    def build() -> Trajectory:
        return simulate_compiled(p, t_end, start, from_state, tol)

    imp = out_imp[:z]
    impacts = tuple(CycleImpact(float(r[0]), float(r[1]), float(r[2]), float(r[3]), float(r[4])) for r in imp)
    return SteadyState(
        p=p,
        regime=REGIMES[regime],
        period_multiple=int(k),
        impacts=impacts,
        cycle_start=float(cycle_start),
        contact_fraction=float(frac),
        contact_phases=(),
        x1_max=float(x1_max),
        periods=int(n),
        residual=float(residual),
        trajectory=_DeferredTrajectory(build),
        section_times=start + p.T * np.arange(1, n + 1),
        sections=np.array(states, float),
        backend="compiled",
    )
