"""Many parameter points per call: settled motions for sweeps, maps, searches and designs.

:func:`steady_states` (the front door's many-point call, re-exported by
:mod:`impactdamper.analysis.solve`) settles points in order: a sweep or a map row each from its
neighbour's settled motion (:func:`impactdamper.analysis.ladder.solve_point` with a
``previous``), a grid or random starts each from its own start, or many independent chains of
equal length (``chain_length``: a frequency sweep up and down for each of many designs, a map's
rows) -- in parallel processes with ``workers``, the result the same bit for bit as the serial
call's. The backend (:func:`impactdamper.core.backends.get_backend`) settles a whole row at
once where it can (the compiled kernels: the parameter sets packed together, each settled
section carried to the next point without Python work per point) and hands the rest back here.

What is computed is :func:`~impactdamper.analysis.ladder.solve_point` **without its
accelerators** (``SweepSettings(continuation=False)``): every point is simulated until it
settles (Algorithm No. 2 with the stroboscopic period test of
:func:`~impactdamper.core.steady.steady_state`). The points the backend does not settle itself
go to that reference, one by one, and are counted in ``BatchResult.fallbacks``:

* ``rescue``: a nonperiodic point with ``settings.rescue`` that the Newton rescue (Python,
  :func:`~impactdamper.analysis.rescue.rescue_from_sections`, from the run's last sections)
  settled on a stable cycle; where it finds none, the nonperiodic point stands and no fallback
  is counted;
* ``matrix_exponential``: a mode whose roots (nearly) coalesce, so that no modal form holds
  (its eigenvectors in the mode's own units, velocities over the fastest rate, have condition
  >= 1e4: :func:`~impactdamper.core.linear.scaled_condition`; the rate itself never causes it);
* ``scales``: no longer arises here: a point whose free scales are outside the native range
  is settled in the canonical units (:meth:`~impactdamper.core.parameters.Parameters.canonical`,
  relative results do not depend on x_st, m1, omega) like every other point, its start and
  section converted back;
* ``error``: the kernels stopped on an error other than the work bound; the reference then
  gives its ``failed`` point or raises its own error.

A point whose run reaches the solver's work bound is ``failed`` (method ``error``) in either
backend, with the reference's line logged; the next point of its chain starts from its start.

With ``settings.classify`` each point still ``nonperiodic`` after the rescue is labelled by its
Lyapunov spectrum (:func:`~impactdamper.analysis.lyapunov.lyapunov_spectrum`, the same backend),
from the section its run hands on: ``chaotic``, ``quasi-periodic``, ``periodic`` (a transient
slower than the cap, every perturbation decaying) or ``not settled``
(:func:`~impactdamper.analysis.lyapunov.classify_spectrum`), with its largest exponent and
that exponent's error.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from dataclasses import dataclass, field
from collections.abc import Sequence

import numpy as np

from impactdamper.analysis.batch_input import (
    COLUMNS,
    checked_chain_length,
    checked_names,
    checked_start_states,
    checked_values,
    checked_workers,
    point_values,
)
from impactdamper.analysis.ladder import solve_point
from impactdamper.analysis.lyapunov import spectrum_from_section
from impactdamper.analysis.parallel import map_tasks
from impactdamper.analysis.point import FAILED, SweepPoint, SweepSettings, failed_point, label_of
from impactdamper.analysis.rescue import RESCUE_MAX_K, rescue_from_sections
from impactdamper.analysis.sweeps import random_start_states
from impactdamper.core.backends import RowArrays, get_backend, row_arrays
from impactdamper.core.events import SearchLimitError
from impactdamper.core.model import FREE, STUCK
from impactdamper.core.parameters import (
    CANONICAL_SCALES,
    NATIVE_SCALES,
    ArgumentTypeError,
    Parameters,
    ScaleMap,
    require_parameters,
)
from impactdamper.core.steady import REGIMES

__all__ = [
    "BatchResult",
    "steady_states",
    "random_starts_batch",
    "BATCH_REGIMES",
    "MAX_REPORTED_IMPACTS",
]

# Regime codes of BatchResult.regime_code: steady.REGIMES, then the failed point of solve_point.
BATCH_REGIMES = REGIMES + (FAILED,)
# Impacts per cycle whose phase and velocity are kept per point (a map reads k, z and x1_max;
# a sweep's table the first few impacts); z itself is always exact.
MAX_REPORTED_IMPACTS = 16
# The arrays of a result that settle_row does not fill: the Lyapunov labels of the points left
# nonperiodic (SweepSettings.classify).
CLASSIFICATION_FIELDS = ("lyapunov_label", "lyapunov_exponent", "lyapunov_error")
NONPERIODIC = BATCH_REGIMES.index("nonperiodic")

log = logging.getLogger(__name__)


@dataclass
class BatchResult(RowArrays):
    """Settled motions of P points, as arrays (the fields of
    :class:`~impactdamper.core.backends.RowArrays`, phases and velocities of the first
    :data:`MAX_REPORTED_IMPACTS` impacts, regime codes indexing :data:`BATCH_REGIMES`, and):

    Attributes
    ----------
    values : ndarray, shape (P, len(names))
        The points, as given.
    names : tuple of str
        The varied parameters.
    elapsed : float
        Wall time of the call, s.
    backend : str
        ``compiled`` (the kernels, with the reference where ``fallback`` says) or ``python``
        (every point by the pure-Python reference).
    lyapunov_label : ndarray of object, shape (P,)
        With ``SweepSettings(classify=True)``: a nonperiodic point's label by its Lyapunov
        spectrum (:data:`~impactdamper.analysis.lyapunov.LABELS`); "" elsewhere.
    lyapunov_exponent, lyapunov_error : ndarray, shape (P,)
        Its largest exponent per forcing period and that exponent's standard error (nan
        elsewhere).
    """

    values: np.ndarray = None
    names: tuple = ()
    elapsed: float = field(default=0.0)
    backend: str = "compiled"
    lyapunov_label: np.ndarray = None
    lyapunov_exponent: np.ndarray = None
    lyapunov_error: np.ndarray = None

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

    def sweep_point(self, i: int, p: Parameters) -> SweepPoint:
        """Point ``i`` as a :class:`~impactdamper.analysis.point.SweepPoint` of parameters ``p``
        (its own, the point's value set): regime, k, z, x1_max, impacts, its section."""
        return _sweep_point(self, i, p)

    @property
    def fallbacks(self) -> dict:
        """Points settled by the reference, by reason ({} when the backend did them all)."""
        reasons, counts = np.unique(self.fallback[self.fallback != ""].astype(str), return_counts=True)
        return {str(r): int(c) for r, c in zip(reasons, counts)}


def _parameters(row: np.ndarray) -> Parameters:
    return Parameters(**{c: float(x) for c, x in zip(COLUMNS, row)})


def _sweep_point(res: BatchResult, i: int, p: Parameters) -> SweepPoint:
    """Point i as the reference's SweepPoint (what solve_point reads of a ``previous``)."""
    rg = BATCH_REGIMES[res.regime_code[i]]
    z = int(res.impacts_per_cycle[i])
    m = min(z, MAX_REPORTED_IMPACTS)
    return SweepPoint.labelled(
        p,
        float(res.values[i, 0]),
        rg,
        int(res.period_multiple[i]),
        z,
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


def _store(res: BatchResult, i: int, pt: SweepPoint, reason: str) -> None:
    res.regime_code[i] = BATCH_REGIMES.index(pt.regime)
    res.period_multiple[i], res.impacts_per_cycle[i] = pt.period_multiple, pt.impacts_per_cycle
    res.x1_max[i], res.contact_fraction[i], res.periods[i] = pt.x1_max, pt.contact_fraction, pt.periods
    m = min(len(pt.phases), MAX_REPORTED_IMPACTS)
    res.phases[i, :m], res.velocities[i, :m] = pt.phases[:m], pt.velocities[:m]
    res.start_states[i], res.sections[i] = pt.start_state, pt.section
    res.section_modes[i] = 1 if pt.section_mode == STUCK else 0
    res.fallback[i], res.method[i] = reason, pt.method


def steady_states(
    base: Parameters,
    names: Sequence[str],
    values,
    *,
    settings: SweepSettings | None = None,
    chain: bool = True,
    chain_length: int | None = None,
    states=None,
    backend: str = "auto",
    workers: int = 1,
) -> BatchResult:
    """Settled motions at many points in one call: a sweep, a grid or a map row, random starts,
    many independent chains.

    Parameters
    ----------
    base : Parameters
        The parameters not varied.
    names : sequence of str
        The varied parameters (``gap``, ``theta``, ... see
        :func:`~impactdamper.analysis.sweeps.swept_names`), each once.
    values : array_like, shape (P, len(names))
        The points, in the order they are settled: one row per point, one real number per name.
    settings : SweepSettings, optional
        Caps and tolerances of each point's settling (period cap ``max_periods``,
        ``settle_tol``, ``max_period_multiple``), ``rescue`` (a point that did not settle within
        the cap is handed to the stroboscopic Newton rescue from its last sections,
        :func:`~impactdamper.analysis.rescue.rescue_from_sections`, before it is called
        ``nonperiodic``); its ``continuation`` is not used (no accelerators, see the module
        docstring) and its ``backend`` is replaced by ``backend``.
    chain : bool
        True (a sweep, a map row): each point starts from the previous point's settled section
        (the reference's ``solve_point(p, previous=...)``); False (a grid of independent
        points, random starts): each from Algorithm No. 2's step 1 or its row of ``states``.
    chain_length : int, optional
        With ``chain``: the points are independent chains of this many consecutive points each
        (the first of each from Algorithm No. 2's step 1); P must be a multiple. Default: one
        chain of all P points.
    states : array_like, optional
        Start states (x1, x2, x1', x2') at t0 = 0, each with a non-negative gap (the reference's
        ``solve_point(p, state=...)``): with ``chain=False`` shape (P, 4), one per point (random
        starts); with ``chain=True`` shape (P / chain_length, 4), one per chain, its first point's
        start instead of Algorithm No. 2's step 1 (a branch continued from a known motion).
    backend : {"auto", "compiled", "python"}
        Who settles the points (:mod:`impactdamper.analysis.solve`); ``python``: every point
        by the reference's ladder, the same motions point by point.
    workers : int
        Processes that settle independent blocks of points (whole chains; single points
        without ``chain``) at once, by the 'fork' start method: the result is the serial
        call's, bit for bit and in the same order (each block is settled as the serial call
        settles it). 1 (default): in this process.

    Returns
    -------
    BatchResult
        Arrays per point (regime, k, z, x1_max, phases, sections, ...), ``fallback`` per point
        and ``backend``.

    Raises
    ------
    TypeError, ValueError
        A bad argument, named in one line (for a bad value: its point and name).
    """
    t_begin = time.perf_counter()
    run, why = get_backend(backend)
    base = require_parameters(base, "base")
    names = checked_names(names)
    values = checked_values(values, names)
    settings = _checked_settings(chain, settings)
    P = len(values)
    chain_length = checked_chain_length(chain_length, chain, P)
    workers = checked_workers(workers)
    res = _settle_blocks(base, names, values, states, settings, chain, chain_length, run, workers)
    res.names, res.backend = names, run.name
    if why:
        res.fallback[:] = why
    res.elapsed = time.perf_counter() - t_begin
    return res


def _checked_settings(chain, settings) -> SweepSettings:
    """``settings`` (the default where None) once ``chain`` and it are checked."""
    if not isinstance(chain, bool):
        raise ArgumentTypeError(f"`chain` = {chain!r} is not allowed: must be True or False")
    settings = settings or SweepSettings()
    if not isinstance(settings, SweepSettings):
        raise ArgumentTypeError(f"`settings` = {settings!r} is not allowed: must be a SweepSettings or None")
    return settings


def _settle_blocks(base, names, values, states, settings, chain: bool, chain_length, run, workers: int) -> BatchResult:
    """The checked points ``values`` settled by ``run``: as rows of relative parameters with
    their start states (checked here), in independent block units (whole chains, single points
    without ``chain``); rows outside the native scales in the canonical units (as steady_state
    settles a single point) and mapped back; on up to ``workers`` processes where there are
    units enough."""
    P = len(values)
    rows = point_values(base, names, values)
    length = (chain_length or max(P, 1)) if chain else 1  # points per independent block unit
    given = checked_start_states(states, chain, length, rows, settings.tolerances.gap_tol)
    units = P // length if P else 0
    outside = ~_native_rows(rows)
    if outside.any():
        rows, given, back = _canonical_rows(rows, given, outside)
    if workers > 1 and units > 1:
        res = _settle_in_workers(values, names, rows, given, settings, chain, length, run, min(workers, units))
    else:
        res = _settle(values, rows, given, settings, chain, length, run)
    if outside.any():
        for i, to_p in back.items():
            res.start_states[i], res.sections[i] = to_p.full(res.start_states[i]), to_p.full(res.sections[i])
    return res


FREE_SCALES = tuple(COLUMNS.index(name) for name in NATIVE_SCALES)


def _native_rows(rows: np.ndarray) -> np.ndarray:
    """Which points' free scales (x_st, m1, omega) are within the native range."""
    inside = np.ones(len(rows), bool)
    for c, (lo, hi) in zip(FREE_SCALES, NATIVE_SCALES.values()):
        inside &= (rows[:, c] >= lo) & (rows[:, c] <= hi)
    return inside


def _canonical_rows(rows: np.ndarray, given: np.ndarray, outside: np.ndarray):
    """The points outside the native scales put in the canonical units
    (:meth:`~impactdamper.core.parameters.Parameters.canonical`), their given starts converted:
    the rows, the starts, and per such point the ScaleMap back to its own units. Every point is
    then settled by the kernels with the same rescue and caps as at the reference scales (these
    points went to the reference one by one before, without the rescue, and in a chain each
    nonperiodic one put the next under the short cap: np spread)."""
    rows, given, back = rows.copy(), given.copy(), {}
    for i in np.flatnonzero(outside):
        p = _parameters(rows[i])
        q = p.canonical()
        if len(given):
            given[i] = ScaleMap(p, q).full(given[i])
        back[int(i)] = ScaleMap(q, p)
        rows[i, list(FREE_SCALES)] = [CANONICAL_SCALES[name] for name in NATIVE_SCALES]
    return rows, given, back


def _settle_in_workers(values, names, rows, given, settings, chain: bool, length: int, run, blocks: int) -> BatchResult:
    """The points in ``blocks`` forked processes, each a run of whole blocks of ``length`` points
    (chains, or single points) settled as the serial call settles them, joined in order: the
    serial call's result, bit for bit."""
    run.warm_up()  # (the kernels loaded once, here: the forked workers inherit them)
    units = len(values) // length
    cuts = [length * int(u) for u in np.linspace(0, units, blocks + 1).round()]
    jobs = [
        (values[a:b], rows[a:b], given[a:b] if len(given) else given, settings, chain, length, run.name)
        for a, b in zip(cuts[:-1], cuts[1:])
    ]
    parts = map_tasks(_settle_job, jobs, len(jobs))
    return BatchResult(
        values=values,
        names=names,
        **{
            name: np.concatenate([getattr(part, name) for part in parts])
            for name in [f.name for f in dataclasses.fields(RowArrays)] + list(CLASSIFICATION_FIELDS)
        },
    )


def _settle_job(job) -> BatchResult:
    values, rows, given, settings, chain, length, name = job
    return _settle(values, rows, given, settings, chain, length, get_backend(name)[0])


def _settle(values, rows, given, settings: SweepSettings, chain: bool, length: int, run) -> BatchResult:
    """The points in this process: the backend's row, and here the points it hands back."""
    P = len(rows)
    res = BatchResult(
        values=values,
        **vars(row_arrays(P, MAX_REPORTED_IMPACTS)),
        lyapunov_label=np.full(P, "", dtype=object),
        lyapunov_exponent=np.full(P, np.nan),
        lyapunov_error=np.full(P, np.nan),
    )
    if not P:
        return res
    rescue_settings = dataclasses.replace(settings, continuation=False, backend=run)
    reference = dataclasses.replace(rescue_settings, backend="python")
    points = run.settle_row(
        rows,
        res,
        tolerances=settings.tolerances,
        options=settings.settle,
        max_periods_after_nonperiodic=settings.max_periods_after_nonperiodic,
        chain_length=length if chain else 0,
        rescue=settings.rescue,
        given=given,
        tail_rows=2 * max(settings.max_period_multiple, RESCUE_MAX_K) + 1,
    )
    for i, reason, detail in points:
        p, value = _parameters(rows[i]), float(values[i, 0])
        if reason == "rescue":
            # The backend ran the point and it did not settle: the Newton rescue (Python)
            # starts from the run's last sections, as the reference's would; where it finds no
            # stable cycle, the backend's nonperiodic point stands.
            mode = STUCK if res.section_modes[i] == 1 else FREE
            periods = int(res.periods[i])
            pt = rescue_from_sections(
                p,
                value,
                detail,
                res.sections[i],
                mode,
                rescue_settings,
                start="",
                start_state=res.start_states[i].copy(),
                periods=periods,
            )
            if pt is not None:
                _store(res, i, pt, "rescue")
        elif reason == "failed":  # the work bound, as the reference's ladder meets it
            _store(res, i, failed_point(p, value, "", res.start_states[i], detail), "")
        else:  # the ladder, from the same neighbour or start: the reference's where the backend
            # gave the point up (``reason``), else the backend's own (its row settles no point)
            chained = chain and i % length != 0
            previous = _sweep_point(res, i - 1, _parameters(rows[i - 1])) if chained else None
            state = given[i].copy() if len(given) and not chained else None
            ladder = reference if reason else rescue_settings
            _store(res, i, solve_point(p, value, previous, state=state, settings=ladder), reason)
    if settings.classify:
        _classify(res, rows, settings, run)
    return res


def _classify(res: BatchResult, rows: np.ndarray, settings: SweepSettings, backend: str) -> None:
    """The Lyapunov label of each point left nonperiodic, from the section its run hands on
    (at a time of the forcing's phase 0: the runs start at t0 = 0), by the same backend."""
    for i in np.flatnonzero(res.regime_code == NONPERIODIC):
        p = _parameters(rows[i])
        try:
            s = spectrum_from_section(
                p, res.sections[i], periods=settings.classify_periods, tolerances=settings.tolerances, backend=backend
            )
        except SearchLimitError as err:  # (left unlabelled: the work bound, logged)
            log.warning("point %d: no Lyapunov label: %s", i, err)
            continue
        res.lyapunov_label[i] = s.label
        res.lyapunov_exponent[i], res.lyapunov_error[i] = s.exponents[0], s.errors[0]


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
    """``count`` random initial states per value (no neighbour), deterministic, in one
    :func:`steady_states` call: the states of
    :func:`~impactdamper.analysis.sweeps.random_start_states` (the generator of value
    ``indices[i]``, default i, start j is ``numpy.random.default_rng([seed, indices[i], j])``, so
    that a state does not depend on how the values are split into jobs), each settled from its
    state (no accelerators).

    Returns
    -------
    list (per value) of list (per start) of SweepPoint (``start`` is ``random``).
    """
    base = require_parameters(base, "base")
    plan = random_start_states(base, parameter, values, count, seed, indices)
    if not plan:
        return []
    points = np.array([[v] for v, _, states in plan for _ in states])
    states = np.array([state for _, _, states in plan for state in states])
    res = steady_states(base, (parameter,), points, settings=settings, chain=False, states=states)
    return [
        [dataclasses.replace(_sweep_point(res, n * count + j, p), start="random") for j in range(count)]
        for n, (_, p, _) in enumerate(plan)
    ]
