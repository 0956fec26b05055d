"""Established oscillations: run Algorithm No. 2 until the motion repeats, then read the cycle.

The run is settled with period T_c = k T when its stroboscopic sections (the state once per
forcing period, t_n = t0 + n T) repeat after k periods and have converged to that cycle: the
period test of :mod:`impactdamper.core.periodicity`, after every period. The settled cycle is
then read from the run (:func:`~impactdamper.core.settled_cycle.describe_run`): what it is, its
impacts and its regime, is :mod:`impactdamper.core.settled_cycle`.
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper.core.excursion import EXCURSION_SAMPLES_PER_PERIOD, max_excursion
from impactdamper.core.parameters import Parameters, ScaleMap, state_scale
from impactdamper.core.periodicity import settled_period
from impactdamper.core.settled_cycle import (
    NONPERIODIC_WINDOW,
    PERIODS_BEFORE_CYCLE,
    REGIMES,
    CycleImpact,
    SteadyState,
    describe_cycle,
    describe_run,
    rescale_steady,
    section_of,
)
from impactdamper.core.simulate import EventDrivenSolver, Tolerances
from impactdamper.core.validation import SettleOptions, check_settle_call

__all__ = [
    "steady_state",
    "settle",
    "start_in_first_period",
    "REBASE_PERIODS",
    # The settled motion this search returns, importable from here as before
    # (core/settled_cycle.py, core/excursion.py: the batch's regimes, the kernels' thresholds):
    "SteadyState",
    "CycleImpact",
    "REGIMES",
    "NONPERIODIC_WINDOW",
    "PERIODS_BEFORE_CYCLE",
    "EXCURSION_SAMPLES_PER_PERIOD",
    "describe_cycle",
    "describe_run",
    "max_excursion",
    "rescale_steady",
    "section_of",
]


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


# The solver restarts from its section state every REBASE_PERIODS forcing periods, with its
# clock back at t0 (the forcing's phase is the same there). A long run's absolute time
# would otherwise put ulp(t) ~ 1e-12 s of rounding into every event: near a bifurcation, where
# a multiplier is close to 1 in modulus and amplifies it, that noise floor (~1e-9 after
# 3000 periods at gap -9.49) exceeds settle_tol, and a period-2 motion passed for period 4.
REBASE_PERIODS = 100
