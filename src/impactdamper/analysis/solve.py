"""The front door: one public call per question, fast by default.

=====================================  ==========================================================
question                               call (result)
=====================================  ==========================================================
the motion from a start                :func:`simulate` (:class:`~impactdamper.core.trajectory.Trajectory`)
the settled motion at one point        :func:`steady_state` (:class:`~impactdamper.core.settled_cycle.SteadyState`)
settled motions at many points         :func:`steady_states` (:class:`~impactdamper.analysis.batch.BatchResult`):
                                       sweeps, grids, map rows, random starts; many independent
                                       chains (``chain_length``) in parallel (``workers``);
                                       ``SweepSettings(classify=True)``: the points left
                                       nonperiodic labelled by their Lyapunov spectrum
the Lyapunov spectrum of a motion      :func:`lyapunov_spectrum` (:class:`~impactdamper.analysis.lyapunov.LyapunovSpectrum`):
(chaotic, quasi-periodic, periodic?)   four exponents per forcing period with errors, a label
=====================================  ==========================================================

Each takes ``backend`` (:data:`~impactdamper.core.backends.BACKENDS`, or a
:class:`~impactdamper.core.backends.Backend` object, resolved by
:func:`~impactdamper.core.backends.get_backend`):

* ``"python"`` -- the pure-Python reference of Timofeev et al. (2019), Algorithm No. 2
  (eqs. (18)-(22): exact flow, certified event search, impact law, contact modes), readable
  and the other side of the equivalence tests (``tests/unit/test_compiled.py``);
* ``"compiled"`` -- the same algorithm in numba (:mod:`impactdamper.core.compiled`), 20-50 times
  faster; where the kernels do not apply (repeated roots of eq. (4), free scales outside the
  native range) or stop on an error other than the work bound, the reference runs instead and
  the result's ``fallback`` says why; the work bound (the reference's step budget) ends a run
  in the kernels with the reference's named error;
* ``"auto"`` (default) -- ``compiled`` where numba can be imported, else ``python`` (fallback
  ``numba_unavailable``).

The arguments are checked once, here (:mod:`impactdamper.core.validation`), before a backend
runs. The compiled backend is imported on first use: ``import impactdamper`` loads no numba.
The results are the same motion whichever backend ran (regime, k, z, impact phases to the
rounding of the arithmetic, see the tests); the result names the backend (``backend``) and,
for a settled motion, the method (``simulation``, or ``algorithm1`` with ``attractor=True``).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactdamper.analysis.batch import steady_states
from impactdamper.analysis.lyapunov import lyapunov_spectrum
from impactdamper.core.backends import BACKENDS, Backend, get_backend
from impactdamper.core.parameters import ArgumentTypeError, Parameters
from impactdamper.core.settled_cycle import SteadyState
from impactdamper.core.simulate import MAX_SIMULATE_PERIODS, Tolerances
from impactdamper.core.trajectory import Trajectory
from impactdamper.core.validation import check_run_call, check_settle_call

__all__ = ["BACKENDS", "simulate", "steady_state", "steady_states", "lyapunov_spectrum"]


def simulate(
    p: Parameters,
    t_end: float,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    *,
    backend: str | Backend = "auto",
) -> Trajectory:
    """Algorithm No. 2 with contact modes from ``t0`` to ``t_end``: the exact motion, eqs. (18)-(22).

    Parameters
    ----------
    p : Parameters
    t_end, t0 : float
        End and start, s (at most ``MAX_SIMULATE_PERIODS`` forcing periods apart).
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0; default Algorithm No. 2's step 1.
    tolerances : Tolerances, optional
        Event-solver tolerances.
    backend : {"auto", "compiled", "python"} or Backend
        See the module docstring.

    Returns
    -------
    Trajectory
        Its ``backend`` says which backend ran, ``fallback`` why the reference ran where the
        kernels were asked. A compiled run makes its events' and segments' objects when first
        read.

    Raises
    ------
    TypeError, ValueError, SearchLimitError
        A bad argument or a work bound, named (as :func:`impactdamper.core.simulate.simulate`).
    """
    run, why = get_backend(backend)
    p, t_end, t0, state, tol = check_run_call(p, t_end, t0, state, tolerances, MAX_SIMULATE_PERIODS)
    traj = run.run(p, t_end, t0, state, tol)
    traj.fallback = traj.fallback or why
    return traj


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
    backend: str | Backend = "auto",
) -> SteadyState:
    """The settled motion at ``p``: Algorithm No. 2 from its step 1 (or ``state`` at ``t0``)
    until the motion repeats, and the settled cycle described (period T_c = k T, impacts with
    their phases, velocities and pulses of eq. (21), regime, contact phases, x1_max).

    Parameters
    ----------
    p : Parameters
    t0, state, tolerances, settle_tol, max_periods, max_period_multiple
        As for :func:`impactdamper.core.steady.steady_state` (the reference); ``settle_tol`` at
        least :data:`~impactdamper.core.validation.SETTLE_TOL_FLOOR` (the rounding floor of the
        section mismatch).
    attractor : bool
        True: Algorithm No. 1's closed-form one-impact orbit (eqs. (7)-(17)) where it exists,
        is admissible and its Newton-confirmed cycle is stable
        (:func:`~impactdamper.analysis.orbits.algorithm1_attractor`), without simulating a
        transient (``method`` ``algorithm1``, a :class:`~impactdamper.analysis.cycle.PeriodicOrbit`);
        elsewhere the simulation. Where attractors coexist it may differ from the motion the
        simulation from ``state`` settles on (reference case, Delta0/x_st = -8.8). False
        (default): always the simulation.
    backend : {"auto", "compiled", "python"} or Backend
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
    run, why = get_backend(backend)
    if not isinstance(attractor, bool):
        raise ArgumentTypeError(f"`attractor` = {attractor!r} is not allowed: must be True or False")
    p, t0, state, tol, options = check_settle_call(
        p,
        t0,
        state,
        tolerances,
        settle_tol=settle_tol,
        max_periods=max_periods,
        max_period_multiple=max_period_multiple,
    )
    if attractor:
        from impactdamper.analysis.orbits import algorithm1_attractor  # (the orbits load on first use)

        orbit = algorithm1_attractor(p, None, tol)
        if orbit is not None:
            return dataclasses.replace(orbit, method="algorithm1", backend="python")
    s = run.settle(p, t0, state, tol, options)
    return dataclasses.replace(s, fallback=s.fallback or why) if why else s
