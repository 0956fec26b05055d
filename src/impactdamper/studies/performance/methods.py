"""The work-precision methods, in one table, and the one protocol of their results.

Like scipy's ``solve_ivp`` with its ``METHODS`` table, the work-precision study
(:mod:`impactdamper.studies.performance.workprecision`) knows its methods only through :data:`METHODS`:
each entry names the method, its family, its labels in the report and the figure, the setting
swept (and the ``performance`` config key that lists its values), and how it runs. Every run
returns a :class:`Solution`, read through one protocol: ``impacts()`` (the impact times) and
``state_at(t)`` (the state (x1, x2, x1', x2')). The study, the report's tables and the
figure's legend take the method vocabulary from here.

The methods compute the motion of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100:

* ``exact``: Algorithm No. 2 (:func:`impactdamper.core.simulate`: exact flow, certified event
  search) across ``gap_tol``;
* ``alg1``: Algorithm No. 1's closed-form one-impact orbit (eqs. 6-17,
  :func:`impactdamper.core.algorithm1`): the settled cycle only;
* the ``solve_ivp`` methods of :data:`impactdamper.baselines.ivp.METHODS` (RK45, DOP853, Radau,
  LSODA; :func:`impactdamper.baselines.ivp.simulate_ivp`, event location) across ``rtol``,
  with ``atol = rtol * x_st``;
* ``RK4``: fixed-step RK4 with bisection on the gap (:func:`impactdamper.baselines.rk4.simulate_rk4`)
  across steps per period;
* ``Moreau-Jean``: Siconos's time-stepping (:func:`impactdamper.baselines.siconos_bridge.simulate_siconos`),
  across steps per period, when its Python module is present (it times itself, in a subprocess).

Adding a method: a ``solve`` function returning a :class:`Solution` and one :class:`Method`
entry (with the config key of its settings in ``workflow/schemas/config.schema.yaml`` and
the configs, and a colour in ``workflow/scripts/fig_work_precision.py``'s ``STYLE``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from collections.abc import Callable

import numpy as np

from impactdamper.baselines.ivp import METHODS as IVP_METHODS
from impactdamper.baselines.ivp import simulate_ivp
from impactdamper.baselines.rk4 import simulate_rk4
from impactdamper.baselines.siconos_bridge import siconos_status, simulate_siconos
from impactdamper.core.algorithm1 import algorithm1
from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import Tolerances, simulate

__all__ = [
    "Method",
    "METHODS",
    "IVP_METHODS",
    "FAMILY_OF",
    "selected",
    "reported_alone",
]

# solve_ivp and RK4 stop after this many events: a run that chatters without end fails (error
# inf) instead of running for ever; the reference windows hold tens of impacts.
IVP_MAX_EVENTS = 100_000
RK4_MAX_EVENTS = 10_000
# Siconos runs longer than this many steps are timed once (its Python loop takes ~25 us a step).
SICONOS_SLOW_STEPS = 40_000


@dataclass(frozen=True)
class _Solution:
    """One run of a method, as the work-precision study reads it.

    Attributes
    ----------
    times : ndarray, shape (n,)
        Impact times, s (:meth:`impacts`).
    state_of : callable
        ``t -> ndarray, shape (4,)``: the state (x1, x2, x1', x2') at ``t`` (:meth:`state_at`);
        a time-stepping method knows its final state only.
    nfev : int
        Right-hand-side evaluations (0 where the method has none).
    cpu_seconds : float
        The CPU time the run measured itself (a subprocess's), else nan: the caller times it.
    """

    times: np.ndarray
    state_of: Callable[[float], np.ndarray] = field(repr=False)
    nfev: int = 0
    cpu_seconds: float = math.nan

    def impacts(self) -> np.ndarray:
        """The impact times, s."""
        return self.times

    def state_at(self, t: float) -> np.ndarray:
        """The state (x1, x2, x1', x2') at time ``t``, shape (4,)."""
        return np.asarray(self.state_of(t), dtype=float)


def _final_only(t_end: float, state: np.ndarray) -> Callable[[float], np.ndarray]:
    def state_of(t: float) -> np.ndarray:
        if t != t_end:
            raise ValueError(
                f"`t` = {t!r} is not allowed: a time-stepping run knows its state at t_end = {t_end!r} only"
            )
        return state

    return state_of


def _times(traj) -> np.ndarray:
    return np.array([e.t for e in traj.impacts()], dtype=float)


def _solve_exact(
    p: Parameters, t_end: float, t0: float, state: np.ndarray, value: float, repeats: int = 1
) -> _Solution:
    """Algorithm No. 2 with grazing resolution ``gap_tol = value``."""
    traj = simulate(p, t_end, t0=t0, state=state, tolerances=Tolerances(gap_tol=value))
    return _Solution(_times(traj), lambda t: traj.sample(t)[0])


def _solve_alg1(
    p: Parameters, t_end: float, t0: float, state: np.ndarray, value: float = math.nan, repeats: int = 1
) -> _Solution | None:
    """Algorithm No. 1's orbit over (t0, t_end) (no transient: the start ``state`` is not
    used); None where it has no admissible orbit."""
    a1 = algorithm1(p)
    if not a1.admissible:
        return None
    T = p.T
    k0 = math.floor((t0 - a1.t_impact) / T) + 1
    times = [a1.t_impact + k * T for k in range(k0, k0 + math.ceil((t_end - t0) / T) + 2)]
    return _Solution(np.array(times), lambda t: a1.sample((t - a1.t_impact) % T))


def _solve_ivp_with(method: str):
    def solve(p: Parameters, t_end: float, t0: float, state: np.ndarray, value: float, repeats: int = 1) -> _Solution:
        traj = simulate_ivp(
            p, t_end, t0=t0, state=state, method=method, rtol=value, atol=value * p.x_st, max_events=IVP_MAX_EVENTS
        )
        return _Solution(_times(traj), lambda t: traj.sample(t)[0], traj.nfev)

    solve.__doc__ = f"``solve_ivp``'s {method} with ``rtol = value``, ``atol = value * x_st``."
    return solve


def _solve_rk4(p: Parameters, t_end: float, t0: float, state: np.ndarray, value: float, repeats: int = 1) -> _Solution:
    """Fixed-step RK4 with ``value`` steps per period and bisection on the gap."""
    traj = simulate_rk4(p, t_end, t0=t0, state=state, steps_per_period=int(value), max_events=RK4_MAX_EVENTS)
    return _Solution(_times(traj), _final_only(t_end, traj.state), traj.nfev)


def _solve_moreau_jean(
    p: Parameters, t_end: float, t0: float, state: np.ndarray, value: float, repeats: int = 1
) -> _Solution:
    """Siconos's Moreau-Jean scheme with ``value`` steps per period, timed in its subprocess:
    the median of half the study's ``repeats`` runs (its runs take seconds), or of one above
    :data:`SICONOS_SLOW_STEPS` steps."""
    steps = value * (t_end - t0) / p.T
    res = simulate_siconos(
        p,
        t_end,
        t0=t0,
        state=state,
        steps_per_period=int(value),
        repeats=max(1, repeats // 2) if steps <= SICONOS_SLOW_STEPS else 1,
    )
    return _Solution(
        np.asarray(res.impacts, dtype=float), _final_only(t_end, res.final_state), cpu_seconds=res.cpu_seconds
    )


def _always() -> tuple[bool, str]:
    return True, ""


@dataclass(frozen=True)
class Method:
    """One work-precision method.

    Attributes
    ----------
    name : str
        The key in :data:`METHODS` and the ``family`` column of the study's runs.
    family : str
        What kind of method: ``exact``, ``closed form``, ``solve_ivp``, ``fixed step``,
        ``time stepping``.
    label : str
        Its row in the report's tables (TeX).
    plot_label : str
        Its entry in the figure's legend (plain text).
    setting : str
        The setting swept (``gap_tol``, ``rtol``, ``steps_per_period``; ``-`` for none).
    settings_key : str or None
        The ``performance`` config key listing the setting's values (None: one run).
    solve : callable
        ``solve(p, t_end, t0, state, value, repeats) -> Solution`` (None: no such motion).
    steps : bool
        Whether the setting is steps per period (runs beyond ``max_steps`` steps are skipped).
    settled_only : bool
        Whether the method computes the settled cycle only (no transient).
    catches : tuple of exception types
        Errors a run may end in (recorded as a failed run with its message).
    status : callable
        ``() -> (available, detail)``: whether the method can run here.
    times_itself : bool
        Whether a run measures its own CPU time (:attr:`Solution.cpu_seconds`), once.
    no_solution : str
        What it means when ``solve`` returns None (the run's note).
    macro : str
        Its part of the report's TeX macro names (letters only).
    """

    name: str
    family: str
    label: str
    plot_label: str
    setting: str
    settings_key: str | None
    solve: Callable = field(repr=False)
    steps: bool = False
    settled_only: bool = False
    catches: tuple = ()
    status: Callable[[], tuple[bool, str]] = field(default=_always, repr=False)
    times_itself: bool = False
    no_solution: str = ""
    macro: str = ""

    @property
    def finer_when_larger(self) -> bool:
        """Whether the setting gets finer as it grows (steps) rather than as it falls (tolerances)."""
        return self.steps


def _ivp_entry(method: str) -> Method:
    return Method(
        method,
        "solve_ivp",
        rf"\texttt{{solve\_ivp}} {method}",
        method,
        "rtol",
        "ivp_rtols",
        _solve_ivp_with(method),
        catches=(RuntimeError,),
        macro="Ivp" + "".join(filter(str.isalpha, method)),
    )


METHODS: dict[str, Method] = {
    m.name: m
    for m in (
        Method(
            "exact",
            "exact",
            "exact, Alg.~2 (this work)",
            "exact (Alg. 2)",
            "gap_tol",
            "exact_gap_tols",
            _solve_exact,
            macro="Exact",
        ),
        Method(
            "alg1",
            "closed form",
            "Alg.~1, closed form (this work)",
            "Alg. 1 (closed form)",
            "-",
            None,
            _solve_alg1,
            settled_only=True,
            no_solution="Algorithm No. 1 has no admissible orbit",
            macro="AlgOne",
        ),
        *(_ivp_entry(m) for m in IVP_METHODS),
        Method(
            "RK4",
            "fixed step",
            "RK4, fixed step + bisection",
            "RK4 + bisection",
            "steps_per_period",
            "rk4_steps_per_period",
            _solve_rk4,
            steps=True,
            catches=(RuntimeError,),
            macro="RkFour",
        ),
        Method(
            "Moreau-Jean",
            "time stepping",
            "Moreau--Jean (Siconos)",
            "Moreau-Jean (Siconos)",
            "steps_per_period",
            "siconos_steps_per_period",
            _solve_moreau_jean,
            steps=True,
            status=siconos_status,
            times_itself=True,
            macro="MoreauJean",
        ),
    )
}
"""The work-precision methods by name, in the order of the report's tables and the legend."""

FAMILY_OF = {name: m.family for name, m in METHODS.items()}


def _methods_of_family(family: str) -> tuple[str, ...]:
    """The names of the methods of one family, in table order (e.g. the ``solve_ivp`` ones)."""
    return tuple(name for name, m in METHODS.items() if m.family == family)


def selected(cfg: dict) -> list[Method]:
    """The methods a ``performance`` config runs: every method but the ``solve_ivp`` ones not
    in ``cfg["ivp_methods"]``."""
    chosen = set(cfg.get("ivp_methods", IVP_METHODS))
    return [m for m in METHODS.values() if m.family != "solve_ivp" or m.name in chosen]


def reported_alone() -> tuple[str, ...]:
    """The methods the report quotes one by one (best error, cost), beside the exact solver
    and the best of the ``solve_ivp`` family: every other family's methods, in table order."""
    return tuple(name for name, m in METHODS.items() if m.family not in ("exact", "solve_ivp"))
