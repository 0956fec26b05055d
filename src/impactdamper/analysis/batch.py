"""Many parameter points per call: settled motions for sweeps, maps and searches, compiled.

A sweep or a map row settles its points in order, each from its neighbour's settled motion
(:func:`impactdamper.analysis.ladder.solve_point` with a ``previous``). Here a whole row goes to
the compiled kernels (:mod:`impactdamper.core.compiled`) in one call, so that no per-point Python
work remains: the parameter sets are packed together (numpy over the stack), and the kernels run
the points one after the other, carrying each settled section to the next point.

What is computed is :func:`~impactdamper.analysis.ladder.solve_point` **without its
accelerators** (``SweepSettings(continuation=False)``): every point is simulated until it
settles (Algorithm No. 2 with the stroboscopic period test of
:func:`~impactdamper.core.steady.steady_state`). The points the kernels do not settle themselves
go to that reference, one by one, and are counted in ``BatchResult.fallbacks``:

* ``rescue``: a nonperiodic point with ``settings.rescue`` that the Newton rescue (Python,
  :func:`~impactdamper.analysis.rescue.rescue_from_sections`, from the kernels' last
  sections) settled on a stable cycle; where it finds none, the kernels' nonperiodic point
  stands and no fallback is counted;
* ``matrix_exponential``: a mode with repeated roots (no modal form);
* ``scales``: free scales outside the native range;
* ``error``: the kernels stopped on an error (step budget, degenerate contact, resonance);
  the reference then gives its ``failed`` point or raises its own error.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from dataclasses import dataclass, field
from collections.abc import Sequence

import numpy as np

from impactdamper.analysis.ladder import solve_point
from impactdamper.analysis.point import FAILED, SweepPoint, SweepSettings, label_of
from impactdamper.analysis.rescue import RESCUE_MAX_K, rescue_from_sections
from impactdamper.analysis.sweeps import random_initial_state, swept_names, with_value
from impactdamper.core import compiled as cc
from impactdamper.core.model import FREE, STUCK
from impactdamper.core.parameters import ArgumentTypeError, Parameters, require_parameters
from impactdamper.core.steady import REGIMES

__all__ = [
    "BatchResult",
    "settled_batch",
    "sweep_points",
    "two_way_batch",
    "regime_map_batch",
    "random_starts_batch",
    "warm_up",
    "BATCH_REGIMES",
    "MAX_REPORTED_IMPACTS",
]

# Regime codes of BatchResult.regime_code: steady.REGIMES, then the failed point of solve_point.
BATCH_REGIMES = REGIMES + (FAILED,)
# Impacts per cycle whose phase and velocity are kept per point (a map reads k, z and x1_max;
# a sweep's table the first few impacts); z itself is always exact.
MAX_REPORTED_IMPACTS = 16


@dataclass
class BatchResult:
    """Settled motions of P points, as arrays.

    Attributes
    ----------
    values : ndarray, shape (P, len(names))
        The points, as given.
    names : tuple of str
        The swept parameters.
    regime_code : ndarray of int, shape (P,)
        Index into :data:`BATCH_REGIMES`.
    period_multiple, impacts_per_cycle : ndarray of int, shape (P,)
        k and z.
    x1_max, contact_fraction, residual : ndarray, shape (P,)
        As in :class:`~impactdamper.analysis.point.SweepPoint` (x1_max in x_st).
    periods : ndarray of int, shape (P,)
        Forcing periods simulated per point (SweepPoint's count).
    phases, velocities : ndarray, shape (P, MAX_REPORTED_IMPACTS)
        The first impacts' forcing phases t/T mod 1 and closing velocities over x_st omega
        (NaN beyond z).
    start_states, sections : ndarray, shape (P, 4)
        Each point's start state and settled section state (x1, x2, x1', x2').
    section_modes : ndarray of int, shape (P,)
        0 free, 1 stuck at the section.
    fallback : ndarray of object, shape (P,)
        "" where the kernels settled the point, else why the reference did (module docstring).
    method : ndarray of object, shape (P,)
        ``simulation``, ``rescue`` or ``error`` (SweepPoint's method).
    elapsed : float
        Wall time of the call, s.
    backend : str
        ``compiled`` (the kernels, with the reference where ``fallback`` says) or ``python``
        (every point by the pure-Python reference).
    """

    values: np.ndarray
    names: tuple
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
    elapsed: float = field(default=0.0)
    backend: str = "compiled"

    @property
    def regime(self) -> np.ndarray:
        """Regime names, shape (P,)."""
        return np.array([BATCH_REGIMES[c] for c in self.regime_code], dtype=object)

    @property
    def label(self) -> np.ndarray:
        """Peterka's z/k labels (:func:`~impactdamper.analysis.point.label_of`), shape (P,)."""
        return np.array(
            [
                label_of(BATCH_REGIMES[c], int(k), int(z))
                for c, k, z in zip(self.regime_code, self.period_multiple, self.impacts_per_cycle)
            ],
            dtype=object,
        )

    @property
    def fallbacks(self) -> dict:
        """Points settled by the reference, by reason ({} when the kernels did them all)."""
        reasons, counts = np.unique(self.fallback[self.fallback != ""].astype(str), return_counts=True)
        return {str(r): int(c) for r, c in zip(reasons, counts)}


def _shown(values) -> str:
    """A bad ``values`` argument as an error message shows it (made only for the message: the
    repr of a map row's array cost as much as settling the row's cheap cells)."""
    text = repr(values)
    return text if len(text) <= 60 else text[:40] + "...(truncated)"


@functools.lru_cache(maxsize=4096)
def _changed_columns(base: Parameters, name: str, value: float) -> tuple:
    """((column index, value), ...) where ``with_value(base, name, value)`` differs from base;
    raises its named error for a bad value. Cached: a map's rows repeat the same values of
    their fast parameter, and constructing Parameters was a third of a cheap row's time."""
    q = with_value(base, name, value)
    return tuple(
        (c, getattr(q, col)) for c, col in enumerate(cc.PARAMETER_COLUMNS) if getattr(q, col) != getattr(base, col)
    )


def _point_values(base: Parameters, names: tuple, values: np.ndarray) -> np.ndarray:
    """(P, 10) relative parameters (columns of compiled.PARAMETER_COLUMNS), validated: every
    distinct value of each swept name goes through Parameters once (its named errors)."""
    out = np.tile(np.array([getattr(base, c) for c in cc.PARAMETER_COLUMNS], float), (len(values), 1))
    for j, name in enumerate(names):
        for v in np.unique(values[:, j]):
            changed = _changed_columns(base, name, float(v))
            rows = values[:, j] == v
            for c, x in changed:
                out[rows, c] = x
    return out


def _parameters(row: np.ndarray) -> Parameters:
    return Parameters(**{c: float(x) for c, x in zip(cc.PARAMETER_COLUMNS, row)})


def _sweep_point(res: BatchResult, i: int, p: Parameters) -> SweepPoint:
    """Point i as the reference's SweepPoint (what solve_point reads of a ``previous``)."""
    rg = BATCH_REGIMES[res.regime_code[i]]
    z = int(res.impacts_per_cycle[i])
    m = min(z, MAX_REPORTED_IMPACTS)
    return SweepPoint(
        p=p,
        value=float(res.values[i, 0]),
        regime=rg,
        period_multiple=int(res.period_multiple[i]),
        impacts_per_cycle=z,
        label=label_of(rg, int(res.period_multiple[i]), z),
        stable=None,
        multiplier=math.nan,
        x1_max=float(res.x1_max[i]),
        velocities=tuple(res.velocities[i, :m]),
        phases=tuple(res.phases[i, :m]),
        contact_fraction=float(res.contact_fraction[i]),
        method=str(res.method[i]),
        periods=int(res.periods[i]),
        start="",
        start_state=res.start_states[i].copy(),
        section=res.sections[i].copy(),
        section_mode=STUCK if res.section_modes[i] == 1 else FREE,
    )


def _store_reference(res: BatchResult, i: int, pt: SweepPoint, reason: str) -> None:
    res.regime_code[i] = BATCH_REGIMES.index(pt.regime)
    res.period_multiple[i], res.impacts_per_cycle[i] = pt.period_multiple, pt.impacts_per_cycle
    res.x1_max[i], res.contact_fraction[i], res.periods[i] = pt.x1_max, pt.contact_fraction, pt.periods
    m = min(len(pt.phases), MAX_REPORTED_IMPACTS)
    res.phases[i, :m], res.velocities[i, :m] = pt.phases[:m], pt.velocities[:m]
    res.start_states[i], res.sections[i] = pt.start_state, pt.section
    res.section_modes[i] = 1 if pt.section_mode == STUCK else 0
    res.fallback[i], res.method[i] = reason, pt.method


def _start_states(states, chain: bool, rows: np.ndarray, gap_tol: float) -> np.ndarray:
    """The batch's given start states, checked: shape (P, 4) finite with a non-negative gap at
    every point (within the solver's ``gap_tol``), or shape (0, 4) when none are given. ``rows``:
    the points' parameters (_point_values)."""
    if states is None:
        return np.zeros((0, 4))
    if chain:
        raise ValueError("`states` is not allowed with `chain=True`: a chained point starts from its neighbour")
    allowed = f"must be finite numbers of shape ({len(rows)}, 4), one start (x1, x2, x1', x2') per point"
    try:
        given = np.array(states, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"`states` is not allowed: {allowed}") from None
    if given.shape != (len(rows), 4) or not np.all(np.isfinite(given)):
        raise ValueError(f"`states` of shape {given.shape} is not allowed: {allowed}")
    delta0 = rows[:, cc.PARAMETER_COLUMNS.index("gap")] * rows[:, cc.PARAMETER_COLUMNS.index("x_st")]
    gap = delta0 - (given[:, 1] - given[:, 0])
    bad = np.flatnonzero(gap < -gap_tol * rows[:, cc.PARAMETER_COLUMNS.index("x_st")])
    if len(bad):
        raise ValueError(
            f"`states` row {int(bad[0])} is not allowed: its gap Delta0 - (x2 - x1) = {gap[bad[0]]:.6g} m "
            "is negative (the bodies would overlap); allowed are states with x2 - x1 <= Delta0"
        )
    return given


def settled_batch(
    base: Parameters,
    names: Sequence[str],
    values,
    *,
    settings: SweepSettings | None = None,
    chain: bool = True,
    states=None,
    backend: str = "compiled",
) -> BatchResult:
    """Settle many parameter points in one call.

    Parameters
    ----------
    base : Parameters
        The parameters not swept.
    names : sequence of str
        Swept parameters (see :func:`~impactdamper.analysis.sweeps.swept_names`).
    values : array_like, shape (P, len(names))
        The points, in the order they are settled.
    settings : SweepSettings, optional
        As for :func:`~impactdamper.analysis.ladder.solve_point`; its ``continuation`` is not
        used (no accelerators, see the module docstring).
    chain : bool
        Each point from the previous point's settled section (a sweep: the reference's
        ``solve_point(p, previous=...)``); False: each from Algorithm No. 2's step 1, or from
        its row of ``states``.
    states : array_like, shape (P, 4), optional
        Start states (x1, x2, x1', x2') at t0 = 0, one per point, each with a non-negative gap
        (the reference's ``solve_point(p, state=...)``, random starts); only with ``chain=False``.
    backend : str
        ``compiled`` (the kernels) or ``python``: every point by the pure-Python reference
        (:func:`~impactdamper.analysis.ladder.solve_point` without accelerators, its
        simulations in Python), the same motions point by point.

    Returns
    -------
    BatchResult

    Raises
    ------
    TypeError, ValueError
        A bad argument, named (``ArgumentTypeError`` is both).
    """
    t_begin = time.perf_counter()
    base = require_parameters(base, "base")
    if isinstance(names, str) or not all(isinstance(n, str) for n in names):
        raise ArgumentTypeError(f"`names` = {names!r} is not allowed: must be a sequence of parameter names")
    names = tuple(names)
    for n in names:
        if n not in swept_names():
            raise ValueError(f"`names` = {names!r} is not allowed: {n!r} is not one of {', '.join(swept_names())}")
    given_values = values
    allowed = f"must be finite numbers of shape (P, {len(names)}), one column per name"
    try:
        values = np.array(values, dtype=float).reshape(-1, len(names)) if len(names) else None
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"`values` = {_shown(given_values)} is not allowed: {allowed}") from None
    if values is None or not np.all(np.isfinite(values)):
        raise ValueError(f"`values` = {_shown(given_values)} is not allowed: {allowed}")
    if not isinstance(chain, bool):
        raise ArgumentTypeError(f"`chain` = {chain!r} is not allowed: must be True or False")
    settings = settings or SweepSettings()
    if not isinstance(settings, SweepSettings):
        raise ArgumentTypeError(f"`settings` = {settings!r} is not allowed: must be a SweepSettings or None")
    ref_settings = dataclasses.replace(settings, continuation=False)
    rows = _point_values(base, names, values)
    given = _start_states(states, chain, rows, settings.tolerances.gap_tol)
    pack, flags = cc.pack_many(rows, settings.tolerances)
    P = len(rows)
    res = BatchResult(
        values=values,
        names=names,
        regime_code=np.zeros(P, np.int64),
        period_multiple=np.zeros(P, np.int64),
        impacts_per_cycle=np.zeros(P, np.int64),
        x1_max=np.full(P, np.nan),
        contact_fraction=np.full(P, np.nan),
        residual=np.full(P, np.nan),
        periods=np.zeros(P, np.int64),
        phases=np.full((P, MAX_REPORTED_IMPACTS), np.nan),
        velocities=np.full((P, MAX_REPORTED_IMPACTS), np.nan),
        start_states=np.zeros((P, 4)),
        sections=np.zeros((P, 4)),
        section_modes=np.zeros(P, np.int64),
        fallback=np.full(P, "", dtype=object),
        method=np.full(P, "simulation", dtype=object),
    )
    if backend not in ("compiled", "python"):
        raise ValueError(f"`backend` = {backend!r} is not allowed: must be 'compiled' or 'python'")
    if backend == "python":
        python_settings = dataclasses.replace(ref_settings, compiled=False)
        previous = None
        for i in range(P):
            p = _parameters(rows[i])
            pt = solve_point(
                p,
                float(values[i, 0]),
                previous if chain else None,
                state=given[i].copy() if len(given) else None,
                settings=python_settings,
            )
            _store_reference(res, i, pt, "")
            previous = pt
        res.backend, res.elapsed = "python", time.perf_counter() - t_begin
        return res
    tail = np.full((2 * max(settings.max_period_multiple, RESCUE_MAX_K) + 1, 5), np.nan)
    i, have_prev = 0, False
    while i < P:
        prev = i - 1
        code, stop = cc.row_kernel(
            pack.s,
            pack.cm,
            pack.fm,
            pack.fc,
            pack.fk,
            pack.fg,
            flags,
            i,
            have_prev,
            res.sections[prev].copy() if have_prev else np.zeros(4),
            int(res.section_modes[prev]) if have_prev else 0,
            bool(have_prev and res.regime_code[prev] < BATCH_REGIMES.index("nonperiodic")),
            chain,
            settings.rescue,
            settings.settle_tol,
            settings.max_periods,
            settings.max_periods_after_nonperiodic,
            settings.max_period_multiple,
            cc.INITIAL_CAPACITY,
            res.regime_code,
            res.period_multiple,
            res.impacts_per_cycle,
            res.x1_max,
            res.contact_fraction,
            res.periods,
            res.residual,
            res.start_states,
            res.sections,
            res.section_modes,
            res.phases,
            res.velocities,
            given,
            tail,
        )
        if code == cc.ROW_DONE:
            break
        if code == cc.ROW_RESCUE:
            # The kernels ran the point and it did not settle: the Newton rescue (Python) starts
            # from the run's last sections, as the reference's would; where it finds no stable
            # cycle, the kernels' nonperiodic point stands.
            p = _parameters(rows[stop])
            pt = rescue_from_sections(
                p,
                float(values[stop, 0]),
                tail[:, :4],
                res.sections[stop],
                STUCK if res.section_modes[stop] == 1 else FREE,
                ref_settings,
                start="",
                start_state=res.start_states[stop].copy(),
                periods=int(res.periods[stop]),
            )
            if pt is not None:
                _store_reference(res, stop, pt, "rescue")
            i, have_prev = stop + 1, True
            continue
        # Point `stop` goes to the reference, from the same neighbour.
        p = _parameters(rows[stop])
        previous = _sweep_point(res, stop - 1, _parameters(rows[stop - 1])) if (chain and stop > 0) else None
        reason = {
            cc.ROW_FLAGGED: cc.FALLBACK_REASONS[int(flags[stop])] if stop < P else "error",
            cc.ROW_ERROR: "error",
        }[int(code)]
        state = given[stop].copy() if len(given) else None
        pt = solve_point(p, float(values[stop, 0]), previous, state=state, settings=ref_settings)
        _store_reference(res, stop, pt, reason)
        i, have_prev = stop + 1, True
    res.elapsed = time.perf_counter() - t_begin
    return res


def sweep_points(res: BatchResult, base: Parameters) -> list[SweepPoint]:
    """A batch's points as the reference's :class:`~impactdamper.analysis.point.SweepPoint`
    objects, in the batch's order (``stable`` None, ``multiplier`` nan: the batch does not
    solve the orbits)."""
    out = []
    for i in range(len(res.values)):
        p = base
        for name, v in zip(res.names, res.values[i]):
            p = with_value(p, name, float(v))
        out.append(_sweep_point(res, i, p))
    return out


def two_way_batch(
    base: Parameters, parameter: str, values: Sequence[float], *, settings: SweepSettings | None = None
) -> dict:
    """:func:`impactdamper.analysis.sweeps.two_way_sweep` in two compiled batches (each point
    from its neighbour, no accelerators).

    Returns
    -------
    dict
        ``{"up": [...], "down": [...]}``, each a list of SweepPoint in increasing order of the
        value, and ``"cpu"``/``"wall"``: ``{"up": s, "down": s}``.
    """
    values = sorted(float(v) for v in values)
    out = {"cpu": {}, "wall": {}}
    for direction, order in (("up", values), ("down", values[::-1])):
        cpu, wall = time.process_time(), time.perf_counter()
        res = settled_batch(base, (parameter,), np.array(order)[:, None], settings=settings)
        points = sweep_points(res, base)
        out[direction] = points if direction == "up" else points[::-1]
        out["cpu"][direction], out["wall"][direction] = time.process_time() - cpu, time.perf_counter() - wall
    return out


def regime_map_batch(
    base: Parameters,
    fast: str,
    fast_values: Sequence[float],
    slow: str,
    slow_values: Sequence[float],
    *,
    direction: str = "up",
    settings: SweepSettings | None = None,
) -> list[BatchResult]:
    """A regime map, one :func:`settled_batch` call per value of ``slow``: the row sweeps
    ``fast`` over its sorted values in ``direction``, each point from its neighbour (as
    :func:`~impactdamper.analysis.sweeps.regime_map` with ``continuation=False``).

    Returns
    -------
    list of BatchResult
        One per slow value, its points in increasing ``fast`` (whatever the direction).
    """
    if direction not in ("up", "down"):
        raise ValueError(f"`direction` = {direction!r} is not allowed: must be 'up' or 'down'")
    fast_sorted = np.array(sorted(float(v) for v in fast_values))
    order = fast_sorted if direction == "up" else fast_sorted[::-1]
    out = []
    for s in slow_values:
        pts = np.column_stack([order, np.full(len(order), float(s))])
        r = settled_batch(base, (fast, slow), pts, settings=settings)
        if direction == "down":
            idx = np.arange(len(order))[::-1]
            for f in dataclasses.fields(r):
                v = getattr(r, f.name)
                if isinstance(v, np.ndarray) and v.shape[:1] == (len(order),):
                    setattr(r, f.name, v[idx])
        out.append(r)
    return out


def random_starts_batch(
    base: Parameters,
    parameter: str,
    values: Sequence[float],
    count: int,
    seed: int,
    *,
    indices: Sequence[int] | None = None,
    settings: SweepSettings | None = None,
) -> list[list[SweepPoint]]:
    """:func:`impactdamper.analysis.sweeps.random_starts` in one compiled batch: the same random
    states (the generator of value ``indices[i]``, start j is ``numpy.random.default_rng([seed,
    indices[i], j])``), each settled from its state (no neighbour, no accelerators).

    Returns
    -------
    list (per value) of list (per start) of SweepPoint (``start`` is ``random``).
    """
    base = require_parameters(base, "base")
    if not (isinstance(count, int) and not isinstance(count, bool) and count >= 1):
        raise ValueError(f"`count` = {count!r} is not allowed: must be an integer >= 1")
    values = [float(v) for v in values]
    indices = list(range(len(values))) if indices is None else [int(i) for i in indices]
    if len(indices) != len(values):
        raise ValueError(f"`indices` is not allowed: has {len(indices)} entries for {len(values)} values")
    if not values:
        return []
    points, states = [], []
    for i, v in zip(indices, values):
        p = with_value(base, parameter, v)
        for j in range(count):
            points.append([v])
            states.append(random_initial_state(p, np.random.default_rng([int(seed), i, j])))
    res = settled_batch(base, (parameter,), np.array(points), settings=settings, chain=False, states=np.array(states))
    out = []
    for n, v in enumerate(values):
        p = with_value(base, parameter, v)
        out.append([dataclasses.replace(_sweep_point(res, n * count + j, p), start="random") for j in range(count)])
    return out


def warm_up() -> float:
    """Compile (or load from the numba cache) every compiled kernel, on the reference case.

    The single-point entry points of :mod:`impactdamper.core.compiled` and :func:`settled_batch`
    each run once, briefly, so that later calls pay no compilation.

    Returns
    -------
    float
        The wall time it took, s.
    """
    t = time.perf_counter()
    p = Parameters()
    cc.steady_state_full(p, max_periods=40)
    settled_batch(p, ("gap",), np.array([[-5.8], [-5.0]]))
    random_starts_batch(p, "gap", [-5.8], 1, 0)
    cc.simulate_compiled(p, 2 * p.T)
    cc.run_compiled(p, 2 * p.T)  # (packs in its own kernel call)
    cc.count_events_compiled(p, 2 * p.T)
    return time.perf_counter() - t
