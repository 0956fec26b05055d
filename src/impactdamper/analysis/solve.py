"""The front door: one public call per question, fast by default.

=====================================  ==========================================================
question                               call (result)
=====================================  ==========================================================
the motion from a start                :func:`simulate` (:class:`~impactdamper.core.simulate.Trajectory`)
the settled motion at one point        :func:`steady_state` (:class:`~impactdamper.core.steady.SteadyState`)
settled motions at many points         :func:`steady_states` (:class:`~impactdamper.analysis.batch.BatchResult`)
=====================================  ==========================================================

Each takes ``backend``:

* ``"python"`` -- the pure-Python reference of Timofeev et al. (2019), Algorithm No. 2
  (eqs. (18)-(22): exact flow, certified event search, impact law, contact modes), readable
  and the other side of the equivalence tests (``tests/unit/test_compiled.py``);
* ``"compiled"`` -- the same algorithm in numba (:mod:`impactdamper.core.compiled`), 20-50 times
  faster; where the kernels do not apply (repeated roots of eq. (4), free scales outside the
  native range, a free motion beyond the event search's work bound) or stop on an error, the
  reference runs instead and the result's ``fallback`` says why;
* ``"auto"`` (default) -- ``compiled`` where numba can be imported, else ``python`` (fallback
  ``numba_unavailable``).

The compiled backend is imported on first use: ``import impactdamper`` loads no numba. The
results are the same motion whichever backend ran (regime, k, z, impact phases to the
rounding of the arithmetic, see the tests); the result names the backend (``backend``,
``Trajectory.compiled``) and, for a settled motion, the method (``simulation``, or
``algorithm1`` with ``attractor=True``).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Sequence

import numpy as np

from impactdamper.core.parameters import ArgumentTypeError, Parameters, require_parameters
from impactdamper.core.linear import characteristic_roots
from impactdamper.core.simulate import STEPS_PER_PERIOD, Tolerances, Trajectory
from impactdamper.core.simulate import simulate as simulate_python
from impactdamper.core.steady import SteadyState
from impactdamper.core.steady import steady_state as steady_state_python

__all__ = [
    "BACKENDS",
    "simulate",
    "steady_state",
    "steady_states",
    "resolve_backend",
    "steady_state_auto",
    "STEADY_KEYWORDS",
]

# The values of every front-door call's ``backend``.
BACKENDS = ("auto", "compiled", "python")
# Why ``auto`` ran the reference: numba (a dependency) could not be imported.
NUMBA_UNAVAILABLE = "numba_unavailable"
# A free motion faster than this many omega cannot be followed within the event search's work
# bound: a certified step is at most of the order of the fastest time scale 1/|lambda|, so a
# forcing period takes more than 2 pi |lambda|/omega steps, beyond STEPS_PER_PERIOD. There the
# reference raises its named work-bound error at once, while the kernels ran without end (delta1
# = delta2 = 1e6, theta = 1e-9: tests/unit/test_hardening.py); such parameters go to the reference.
MAX_RATE = STEPS_PER_PERIOD / (2 * math.pi)
# Why: the free motion is beyond the work bound (see MAX_RATE).
BEYOND_WORK_BOUND = "work_bound"
# Why: a chatter tolerance below the default. The kernels follow a chatter sequence to rebounds
# below chatter_tol as the reference does, but without its bound on the sequence's work: at
# chatter_tol = 1e-300 (gap -28, where the default settles to chatter) they ran for minutes,
# while the reference stops at once with a one-line error naming `chatter_tol`
# (tests/unit/test_cli.py). Such settings go to the reference.
CHATTER_BELOW_DEFAULT = "chatter_tol"


def resolve_backend(backend: object) -> tuple[str, str]:
    """(the backend to run, why it is not the one asked for or ""): ``auto`` is ``compiled``
    where numba imports, else ``python``.

    Raises
    ------
    ValueError
        ``backend`` not one of :data:`BACKENDS`, named.
    """
    if not isinstance(backend, str) or backend not in BACKENDS:
        raise ValueError(
            f"`backend` = {backend!r} is not allowed: must be one of {', '.join(repr(b) for b in BACKENDS)}"
        )
    if backend != "auto":
        return backend, ""
    try:
        import impactdamper.core.compiled  # noqa: F401  (the kernels, loaded on first use)
    except ImportError:
        return "python", NUMBA_UNAVAILABLE
    return "compiled", ""


def _kernels_refuse(p: Parameters, tolerances: Tolerances | None = None) -> str:
    """Why the kernels are not tried at ``p`` ("" where they are): a free motion beyond the
    work bound (:data:`MAX_RATE`), or a chatter tolerance below the default
    (:data:`CHATTER_BELOW_DEFAULT`)."""
    if isinstance(tolerances, Tolerances) and tolerances.chatter_tol < Tolerances.chatter_tol:
        return CHATTER_BELOW_DEFAULT
    with np.errstate(all="ignore"):
        rate = float(np.max(np.abs(characteristic_roots(p)))) / p.omega
    return BEYOND_WORK_BOUND if not rate <= MAX_RATE else ""


def simulate(
    p: Parameters,
    t_end: float,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    *,
    backend: str = "auto",
) -> Trajectory:
    """Algorithm No. 2 with contact modes from ``t0`` to ``t_end``: the exact motion, eqs. (18)-(22).

    Parameters
    ----------
    p : Parameters
    t_end, t0 : float
        End and start, s.
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0; default Algorithm No. 2's step 1.
    tolerances : Tolerances, optional
        Event-solver tolerances.
    backend : {"auto", "compiled", "python"}
        See the module docstring.

    Returns
    -------
    Trajectory
        Its ``compiled`` says which backend ran, ``fallback`` why the reference ran where
        the kernels were asked.

    Raises
    ------
    TypeError, ValueError, SearchLimitError
        A bad argument or a work bound, named (as :func:`impactdamper.core.simulate.simulate`).
    """
    run, why = resolve_backend(backend)
    if run == "compiled":
        p = require_parameters(p)
        why = _kernels_refuse(p, tolerances)
        run = "python" if why else run
    if run == "python":
        traj = simulate_python(p, t_end, t0, state, tolerances)
        traj.fallback = why
        return traj
    from impactdamper.core.compiled import simulate_compiled

    return simulate_compiled(p, t_end, t0, state, tolerances)


def steady_state(
    p: Parameters,
    *,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    settle_tol: float = 1e-10,
    max_periods: int = 4000,
    max_period_multiple: int = 8,
    attractor: bool = False,
    backend: str = "auto",
) -> SteadyState:
    """The settled motion at ``p``: Algorithm No. 2 from its step 1 (or ``state`` at ``t0``)
    until the motion repeats, and the settled cycle described (period T_c = k T, impacts with
    their phases, velocities and pulses of eq. (21), regime, contact phases, x1_max).

    Parameters
    ----------
    p : Parameters
    t0, state, tolerances, settle_tol, max_periods, max_period_multiple
        As for :func:`impactdamper.core.steady.steady_state` (the reference).
    attractor : bool
        True: Algorithm No. 1's closed-form one-impact orbit (eqs. (7)-(17)) where it exists,
        is admissible and its Newton-confirmed cycle is stable
        (:func:`~impactdamper.analysis.orbits.stable_algorithm1_orbit`), without simulating a
        transient (``method`` ``algorithm1``, a :class:`~impactdamper.analysis.orbits.PeriodicOrbit`);
        elsewhere the simulation. Where attractors coexist it may differ from the motion the
        simulation from ``state`` settles on (reference case, Delta0/x_st = -8.8). False
        (default): always the simulation.
    backend : {"auto", "compiled", "python"}
        Who runs the simulation (module docstring).

    Returns
    -------
    SteadyState
        With ``method`` (``simulation`` or ``algorithm1``), ``backend`` (``compiled`` or
        ``python``) and ``fallback`` (why the reference ran where the kernels were asked; "").

    Raises
    ------
    TypeError, ValueError, SearchLimitError
        As :func:`impactdamper.core.steady.steady_state`.
    """
    run, why = resolve_backend(backend)
    if not isinstance(attractor, bool):
        raise ArgumentTypeError(f"`attractor` = {attractor!r} is not allowed: must be True or False")
    kwargs = dict(
        t0=t0,
        state=state,
        tolerances=tolerances,
        settle_tol=settle_tol,
        max_periods=max_periods,
        max_period_multiple=max_period_multiple,
    )
    if run == "compiled":
        p = require_parameters(p)
        why = _kernels_refuse(p, tolerances)
        run = "python" if why else run
    if attractor:
        orbit = _algorithm1_attractor(p, tolerances)
        if orbit is not None:
            return dataclasses.replace(orbit, method="algorithm1", backend="python")
    if run == "python":
        return dataclasses.replace(steady_state_python(p, **kwargs), fallback=why)
    from impactdamper.core.compiled import steady_state_full

    return steady_state_full(p, **kwargs)


def _algorithm1_attractor(p: Parameters, tolerances: Tolerances | None):
    """Algorithm No. 1's stable one-impact orbit at ``p``, or None (no orbit, not admissible,
    not stable)."""
    from impactdamper.analysis.orbits import stable_algorithm1_orbit
    from impactdamper.core.algorithm1 import algorithm1
    from impactdamper.core.events import SearchLimitError
    from impactdamper.core.simulate import check_tolerances

    p = require_parameters(p)
    tol = check_tolerances(tolerances)
    try:
        a1 = algorithm1(p, gap_tol=tol.gap_tol)
    except (ValueError, SearchLimitError):
        return None  # no closed-form orbit here (a resonance of the impacts): simulate
    return stable_algorithm1_orbit(a1, None, tol)


def steady_states(
    base: Parameters,
    names: Sequence[str],
    values,
    *,
    settings=None,
    chain: bool = True,
    states=None,
    backend: str = "auto",
):
    """Settled motions at many points in one call: a sweep, a grid or a map row, random starts.

    Parameters
    ----------
    base : Parameters
        The parameters not varied.
    names : sequence of str
        The varied parameters (``gap``, ``theta``, ... see
        :func:`~impactdamper.analysis.sweeps.swept_names`).
    values : array_like, shape (P, len(names))
        The points, in the order they are settled.
    settings : SweepSettings, optional
        Caps and tolerances of each point's settling (period cap ``max_periods``,
        ``settle_tol``, ``max_period_multiple``) and ``rescue``: a point that did not settle
        within the cap is handed to the stroboscopic Newton rescue from its last sections
        (:func:`~impactdamper.analysis.rescue.rescue_from_sections`) before it is called
        ``nonperiodic``.
    chain : bool
        True (a sweep, a map row): each point starts from the previous point's settled
        section; False (a grid of independent points, random starts): each from Algorithm
        No. 2's step 1 or its row of ``states``.
    states : array_like, shape (P, 4), optional
        Start states at t0 = 0, one per point (only with ``chain=False``).
    backend : {"auto", "compiled", "python"}
        See the module docstring; ``python`` settles every point by the reference.

    Returns
    -------
    BatchResult
        Arrays per point (regime, k, z, x1_max, phases, sections, ...), ``fallback`` per point
        and ``backend``. :func:`~impactdamper.analysis.batch.sweep_points` turns it into the
        reference's :class:`~impactdamper.analysis.point.SweepPoint` objects.

    Raises
    ------
    TypeError, ValueError
        A bad argument, named.
    """
    run, why = resolve_backend(backend)
    from impactdamper.analysis.batch import settled_batch

    res = settled_batch(base, names, values, settings=settings, chain=chain, states=states, backend=run)
    if why:
        res.fallback[:] = why
    return res


# The keywords of steady_state, which steady_state_auto passes on.
STEADY_KEYWORDS = ("t0", "state", "tolerances", "settle_tol", "max_periods", "max_period_multiple")


def steady_state_auto(p: Parameters, **kwargs) -> SteadyState:
    """The steady state, cheaply where it can be.

    If Algorithm No. 1's one-impact orbit exists, is admissible, and its Newton-confirmed
    cycle is stable (:func:`~impactdamper.analysis.orbits.stable_algorithm1_orbit`), that orbit
    is returned (a :class:`PeriodicOrbit`, a SteadyState with
    ``periods = 0``) without simulating a transient. Otherwise this is
    :func:`~impactdamper.core.steady.steady_state` with the same keyword arguments.

    The stable one-impact orbit is an attractor; where attractors coexist, the transient of
    :func:`~impactdamper.core.steady.steady_state` from its start may settle on another one (for the reference
    parameters it does at some gaps, e.g. Delta0/x_st = -8.8, where a 4-impact 3T cycle
    coexists with the one-impact orbit). ``steady_state`` itself is unchanged.

    Raises
    ------
    TypeError
        A keyword that :func:`~impactdamper.core.steady.steady_state` does not take, named.

    .. deprecated:: use ``impactdamper.steady_state(p, attractor=True)``.
    """
    from impactdamper.analysis.orbits import stable_algorithm1_orbit
    from impactdamper.core.algorithm1 import algorithm1
    from impactdamper.core.events import SearchLimitError
    from impactdamper.core.simulate import check_tolerances

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
    return steady_state_python(p, **kwargs)
