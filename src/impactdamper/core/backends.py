"""Backends: who computes a motion, chosen by name in one registry.

The same algorithm of Timofeev et al. (2019) -- Algorithm No. 2 with the exact flow, the
certified event search, the impact law of eqs. (21)-(22) and the contact modes, and the
stroboscopic period test of the settled motion -- runs in two implementations:

* ``"python"`` -- the readable reference (:mod:`impactdamper.core.simulate`,
  :mod:`impactdamper.core.steady`), :data:`PYTHON` below;
* ``"compiled"`` -- the same in numba (:mod:`impactdamper.core.compiled`), 20-50 times faster;
  it hands a point it does not cover to the reference and says why (``fallback``:
  ``matrix_exponential``, ``scales``, ``error``).

A backend is a :class:`Backend`: it writes ``run`` and ``settle``, and the other operations
default to the reference's. Every caller (the front door, the sweeps' ladder and rescue, the
batch, the Lyapunov spectrum) asks :func:`get_backend` for one, by name or as the object itself.
``"auto"`` is resolved here and only here: the compiled backend where numba imports, else the
reference with the reason ``numba_unavailable``. A new backend is one module with a
:class:`Backend` object and one line of :data:`REGISTRY` (or the object passed as ``backend``).

The compiled backend's module is imported on first use: ``import impactdamper`` loads no numba.
"""

from __future__ import annotations

import importlib
import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from impactdamper.core.parameters import Parameters
from impactdamper.core.settled_cycle import SteadyState
from impactdamper.core.simulate import EventDrivenSolver, simulate_checked
from impactdamper.core.steady import settle
from impactdamper.core.trajectory import Trajectory
from impactdamper.core.tangent import TangentRun, tangent_walk
from impactdamper.core.validation import SettleOptions, Tolerances

__all__ = [
    "Backend",
    "PYTHON",
    "REGISTRY",
    "BACKENDS",
    "NUMBA_UNAVAILABLE",
    "get_backend",
    "check_backend",
    "warm_up",
    "RowArrays",
    "row_arrays",
]


@dataclass
class RowArrays:
    """Settled motions of P points as arrays: what a backend's ``settle_row`` fills.

    Attributes
    ----------
    regime_code : ndarray of int, shape (P,)
        Index into :data:`~impactdamper.core.settled_cycle.REGIMES` (one past its end: a point whose
        run failed, ``failed``).
    period_multiple, impacts_per_cycle : ndarray of int, shape (P,)
        k and z.
    x1_max, contact_fraction, residual : ndarray, shape (P,)
        max|x1|/x_st, the share of the cycle in persistent contact, the last section mismatch.
    periods : ndarray of int, shape (P,)
        Forcing periods simulated per point.
    phases, velocities : ndarray, shape (P, M)
        The first M impacts' forcing phases t/T mod 1 and closing velocities over x_st omega
        (NaN beyond z).
    start_states, sections : ndarray, shape (P, 4)
        Each point's start state and settled section state (x1, x2, x1', x2').
    section_modes : ndarray of int, shape (P,)
        0 free, 1 stuck at the section.
    fallback : ndarray of object, shape (P,)
        "" where the backend settled the point, else why the reference did.
    method : ndarray of object, shape (P,)
        ``simulation``, ``rescue`` or ``error``.
    """

    regime_code: np.ndarray
    period_multiple: np.ndarray
    impacts_per_cycle: np.ndarray
    x1_max: np.ndarray
    contact_fraction: np.ndarray
    residual: np.ndarray
    periods: np.ndarray
    phases: np.ndarray
    velocities: np.ndarray
    start_states: np.ndarray
    sections: np.ndarray
    section_modes: np.ndarray
    fallback: np.ndarray
    method: np.ndarray


def row_arrays(points: int, impacts: int) -> RowArrays:
    """Empty :class:`RowArrays` for ``points`` points, ``impacts`` impacts kept per point."""
    return RowArrays(
        regime_code=np.zeros(points, np.int64),
        period_multiple=np.zeros(points, np.int64),
        impacts_per_cycle=np.zeros(points, np.int64),
        x1_max=np.full(points, np.nan),
        contact_fraction=np.full(points, np.nan),
        residual=np.full(points, np.nan),
        periods=np.zeros(points, np.int64),
        phases=np.full((points, impacts), np.nan),
        velocities=np.full((points, impacts), np.nan),
        start_states=np.zeros((points, 4)),
        sections=np.zeros((points, 4)),
        section_modes=np.zeros(points, np.int64),
        fallback=np.full(points, "", dtype=object),
        method=np.full(points, "simulation", dtype=object),
    )


class Backend(ABC):
    """What a backend does (arguments already validated, once, by the caller:
    :mod:`impactdamper.core.validation`). A new backend subclasses this and writes ``run`` and
    ``settle``; the other operations default to the reference's (a backend overrides those it
    computes itself, as the compiled one does all of them).

    ``run(p, t_end, t0, state, tolerances)``
        Algorithm No. 2 from ``state`` (None: its step 1) at ``t0`` to ``t_end``: a
        :class:`~impactdamper.core.trajectory.Trajectory` (``backend``, ``fallback`` set).
    ``settle(p, t0, state, tolerances, options)``
        The settled motion (:class:`~impactdamper.core.settled_cycle.SteadyState`, ``backend`` and
        ``fallback`` set) with :class:`~impactdamper.core.validation.SettleOptions`.
    ``map_step(p, tolerances)``
        The stroboscopic map of ``p``: a callable ``step(state, k)`` -> (state, mode) k periods
        on from ``state`` at t = 0, or None where it does not apply (the caller then runs the
        reference's :func:`~impactdamper.analysis.strobe.stroboscopic_step`). Default: the
        reference's event-driven solver.
    ``settle_row(rows, out, **options)``
        A generator settling many points (``rows``: shape (P, len(Parameters.names())), each a
        valid parameter set) into ``out``'s arrays (:class:`RowArrays`), in order; it yields ``(i, reason, detail)``
        for each point it does not settle itself, and the caller fills point i of ``out``
        before the generator goes on (chained points then continue from it). ``reason``:
        ``"rescue"`` (nonperiodic within the cap; ``detail`` the run's last sections),
        ``"failed"`` (a work bound; ``detail`` the error's one line), else a fallback reason
        for the reference's ladder ("" where the backend settles no point itself). Default:
        every point to the caller's reference ladder.
    ``lyapunov(p, t0, state, tolerances, periods, transient, warmup)``
        The growth of an orthonormal frame of perturbations along the motion from ``state``
        (None: step 1) at ``t0`` in [0, T), period by period: ``transient`` periods of motion,
        ``warmup`` periods of the walk discarded, ``periods`` returned
        (:class:`~impactdamper.core.tangent.TangentRun`, ``backend`` and ``fallback`` set;
        ``p`` in the native scales). Default: the reference's
        :func:`~impactdamper.core.tangent.tangent_walk`.
    ``warm_up()``
        Compile what the backend compiles (default: nothing).
    """

    name: str

    @abstractmethod
    def run(self, p: Parameters, t_end: float, t0: float, state, tolerances: Tolerances) -> Trajectory: ...

    @abstractmethod
    def settle(
        self, p: Parameters, t0: float, state, tolerances: Tolerances, options: SettleOptions
    ) -> SteadyState: ...

    def map_step(self, p: Parameters, tolerances: Tolerances) -> Callable | None:
        def step(state, k):
            solver = EventDrivenSolver(p, t0=0.0, state=state, tolerances=tolerances)
            solver.advance(k * p.T)
            return solver.state_at(k * p.T), solver.mode

        return step

    def settle_row(self, rows: np.ndarray, out: RowArrays, **options) -> Iterator[tuple[int, str, object]]:
        for i in range(len(rows)):
            yield i, "", None

    def lyapunov(
        self, p: Parameters, t0: float, state, tolerances: Tolerances, periods: int, transient: int, warmup: int
    ) -> TangentRun:
        return tangent_walk(p, t0, state, tolerances, periods, transient, warmup)

    def warm_up(self) -> None:  # noqa: B027 (a default, not an operation to write)
        """Nothing to compile."""


class _PythonBackend(Backend):
    """The pure-Python reference as a backend: its two own operations on checked arguments
    (the others are :class:`Backend`'s defaults, the reference's)."""

    name = "python"

    def run(self, p, t_end, t0, state, tolerances):
        return simulate_checked(p, t_end, t0, state, tolerances)

    def settle(self, p, t0, state, tolerances, options):
        return settle(p, t0, state, tolerances, options)


PYTHON = _PythonBackend()
# The backends by name: where each one's object lives ("module:attribute"), imported on first use.
REGISTRY = {
    "compiled": "impactdamper.core.compiled.backend:COMPILED",
    "python": "impactdamper.core.backends:PYTHON",
}
# The values of every call's ``backend``: a registered name, or "auto".
BACKENDS = ("auto", *REGISTRY)
# What "auto" tries first, and why the reference ran where that backend cannot be imported.
AUTO = "compiled"
NUMBA_UNAVAILABLE = "numba_unavailable"


def check_backend(backend: object) -> str | Backend:
    """``backend`` if it is one of :data:`BACKENDS` or a :class:`Backend` object, else a
    one-line error naming it."""
    if isinstance(backend, Backend):
        return backend
    if not isinstance(backend, str) or not (backend == "auto" or backend in REGISTRY):
        allowed = ", ".join(repr(b) for b in ("auto", *REGISTRY))
        raise ValueError(f"`backend` = {backend!r} is not allowed: must be one of {allowed} or a Backend")
    return backend


def _load(name: str) -> Backend:
    module, attribute = REGISTRY[name].split(":")
    return getattr(importlib.import_module(module), attribute)


def get_backend(backend: object = "auto") -> tuple[Backend, str]:
    """(the backend to run, why it is not the one asked for or ""): a :class:`Backend` object
    itself, a registered name's object; ``"auto"`` is the compiled backend where numba imports,
    else the reference (:data:`NUMBA_UNAVAILABLE`).

    Raises
    ------
    ValueError
        ``backend`` not one of :data:`BACKENDS`, named.
    """
    if isinstance(check_backend(backend), Backend):
        return backend, ""
    if backend != "auto":
        return _load(backend), ""
    try:
        return _load(AUTO), ""
    except ImportError:
        return PYTHON, NUMBA_UNAVAILABLE


def warm_up(backend: str | Backend = "auto") -> float:
    """Compile (or load from numba's cache) a backend's kernels, so that later calls and forked
    workers pay no compilation. Returns the seconds it took."""
    t = time.perf_counter()
    get_backend(backend)[0].warm_up()
    return time.perf_counter() - t
