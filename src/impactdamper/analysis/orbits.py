"""Periodic orbits solved directly from a seed: Newton shooting, checked, with multipliers.

Simulating until the motion settles (:func:`impactdamper.core.steady.steady_state`) is slow near
bifurcations and never shows an unstable orbit. Here a cycle of period T_c = k T with z
impacts is solved for directly, with the exact flow between impacts (eq. 18 of Timofeev et
al. 2019, :mod:`impactdamper.core.linear`) and the impact law of eqs. (21)-(22).

The cycle is the solution of the shooting equations of :mod:`impactdamper.analysis.shooting`
(unknowns: the impact times and the states after the impacts; equations: the gap of eq. 20
at each flight's end, the impact law between flights), solved by Newton's method from a seed:
Algorithm No. 1's one-impact orbit, a simulated settled cycle, or given impact times and
states. The solution is checked (admissibility, Floquet multipliers) as
:mod:`impactdamper.analysis.cycle` tells.

Scope
-----
Impacting cycles without persistent contact get the full treatment. The motion without
contact and the motion with the bodies in contact all the time (regimes ``no_contact`` and
``stuck``) are solved in closed form (:func:`~impactdamper.analysis.cycle.closed_form_orbit`).
Cycles with a phase of persistent contact reached through an accumulation of impacts
(``chatter``) are not solved: the result then carries the simulated cycle with
``solved = False`` and the reason.

Branches of these cycles in one parameter (pseudo-arclength continuation, folds, period
doublings, grazings) are followed by :mod:`impactdamper.analysis.continuation`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from impactdamper.analysis.cycle import (
    PeriodicOrbit,
    closed_form_orbit,
    impact_states,
    orbit_from_solution,
    rescale_orbit,
)
from impactdamper.analysis.shooting import OrbitError, Shooting
from impactdamper.core.backends import Backend, get_backend
from impactdamper.core.algorithm1 import Algorithm1Result, algorithm1, rescale_algorithm1
from impactdamper.core.events import SearchLimitError
from impactdamper.core.model import Model
from impactdamper.core.parameters import ArgumentTypeError, Parameters, ScaleMap, require_parameters
from impactdamper.core.simulate import Tolerances
from impactdamper.core.settled_cycle import SteadyState, rescale_steady
from impactdamper.core.steady import start_in_first_period
from impactdamper.core.validation import (
    SettleOptions,
    check_start_state,
    check_state,
    check_tolerances,
    finite_argument,
    integer_argument,
)

__all__ = [
    "OrbitError",
    "solve_orbit",
    "orbit_from_cycle",
    "algorithm1_attractor",
    "SEEDS",
]

# Ways to seed the direct solve.
SEEDS = ("auto", "alg1", "simulate")
# Bounds on the work of one direct solve: the largest period multiple k (as the workflow's
# max_period_multiple) and the most impacts per cycle (Newton solves 5 z equations densely).
MAX_ORBIT_PERIOD_MULTIPLE = 64
MAX_ORBIT_IMPACTS = 512


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
        return closed_form_orbit(p, steady.regime, steady.periods)
    times, after = _repeat(*impact_states(steady), k, m, p.T)
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
    backend: str | Backend = "python",
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
    backend : {"python", "compiled", "auto"} or Backend
        Who simulates the seed ``"simulate"`` (:func:`~impactdamper.core.backends.get_backend`);
        default the reference.

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
    run = get_backend(backend)[0]
    p = require_parameters(p)
    tolerances = check_tolerances(tolerances)
    t0 = finite_argument("t0", t0)
    state = check_state(state, p)  # (checked even where "auto" takes Algorithm No. 1's orbit)
    if period_multiple is not None:
        period_multiple = integer_argument("period_multiple", period_multiple, 1, MAX_ORBIT_PERIOD_MULTIPLE)
    options = SettleOptions(settle_tol, max_periods, max_period_multiple)
    if isinstance(seed, str) and seed == "alg1":
        for name, given in (("state", state is not None), ("t0", t0 != 0.0)):
            if given:
                raise ValueError(
                    f"`{name}` is not allowed with seed = 'alg1': Algorithm No. 1's orbit is closed-form and "
                    "has no start (seed 'simulate' starts from it)"
                )
    return _solve_orbit(p, seed, period_multiple, t0, state, tolerances, options, run)


def _solve_orbit(p, seed, period_multiple, t0, state, tolerances, options, run) -> PeriodicOrbit:
    """:func:`solve_orbit` on checked arguments (``run`` the backend, ``options`` the seed's
    :class:`~impactdamper.core.validation.SettleOptions`)."""
    if not p.native_scales():
        # The same relative problem in the reference case's units, converted back.
        q = p.canonical()
        to_q = ScaleMap(p, q)
        t0 = to_q.apply(start_in_first_period(p, t0), "time")
        state = None if state is None else to_q.full(state)
        o = _solve_orbit(q, _rescaled_seed(seed, to_q), period_multiple, t0, state, tolerances, options, run)
        return rescale_orbit(o, ScaleMap(q, p))
    if isinstance(seed, str):
        if seed not in SEEDS:
            raise ValueError(f"`seed` = {seed!r} is not allowed: must be one of {', '.join(SEEDS)}")
        if seed == "alg1":
            seed = algorithm1(p, gap_tol=tolerances.gap_tol)
        elif seed == "auto":
            orbit = algorithm1_attractor(p, period_multiple, tolerances)
            if orbit is not None:
                return orbit
    if isinstance(seed, str):  # "simulate", or "auto" without Algorithm No. 1's attractor
        seed = run.settle(p, t0, check_start_state(state, p, tolerances), tolerances, options)
    if isinstance(seed, Algorithm1Result):
        if not seed.exists:
            raise OrbitError(f"Algorithm No. 1 has no orbit: {seed.reason}")
        return _orbit_from_algorithm1(seed, period_multiple, tolerances)
    if isinstance(seed, SteadyState):
        return _from_steady(seed, period_multiple, tolerances)
    raise ValueError(
        f"`seed` = {seed!r} is not allowed: must be one of {', '.join(SEEDS)}, a SteadyState or an Algorithm1Result"
    )


def _rescaled_seed(seed, scales: ScaleMap):
    """A computed seed in ``scales.target``'s units (a named seed as it is)."""
    if isinstance(seed, Algorithm1Result):
        return rescale_algorithm1(seed, scales)
    if isinstance(seed, PeriodicOrbit):
        return rescale_orbit(seed, scales)
    return rescale_steady(seed, scales) if isinstance(seed, SteadyState) else seed


def _orbit_from_algorithm1(
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


def _stable_algorithm1_orbit(
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
        orbit = _orbit_from_algorithm1(a1, period_multiple, tolerances)
    except OrbitError:
        return None
    return orbit if (orbit.admissible and orbit.stable) else None


def algorithm1_attractor(
    p: Parameters, period_multiple: int | None = None, tolerances: Tolerances | None = None
) -> PeriodicOrbit | None:
    """:func:`stable_algorithm1_orbit` of Algorithm No. 1 at ``p``: its orbit where it exists,
    is admissible and its Newton-confirmed cycle is stable, else None (also where Algorithm
    No. 1 fails, at a resonance of the impacts: the caller then simulates)."""
    try:
        a1 = algorithm1(p, gap_tol=check_tolerances(tolerances).gap_tol)
    except (ValueError, SearchLimitError):
        return None
    return _stable_algorithm1_orbit(a1, period_multiple, tolerances)
