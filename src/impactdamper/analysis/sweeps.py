"""Parameter sweeps: which motion the suppressor settles on, and where it changes.

The introduction of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100, says that
with a negative initial gap the object and the suppressor move together at small forcing, that
the suppressor works with one impact per period at large forcing, and that several impacts per
period occur in between. This module maps that: one parameter (typically the gap
Delta0/x_st, but any field of :class:`~impactdamper.core.parameters.Parameters`) is swept up and
down, each point starting from its neighbour's settled motion, plus random initial states
(settled by :func:`impactdamper.analysis.batch.random_starts_batch`), and the motion of every point is labelled with Peterka's z/k (z impacts in k forcing periods).

The label changes along a two-way sweep are bisected by :func:`find_transitions`.

Each point is solved by :func:`impactdamper.analysis.ladder.solve_point` (how, and what its
labels and ``nonperiodic`` mean, is told there); the closed-form band edges a sweep must
bracket are in :mod:`impactdamper.analysis.transitions`.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass
from collections.abc import Callable, Sequence

import numpy as np

from impactdamper.analysis.ladder import solve_point
from impactdamper.analysis.parallel import map_tasks
from impactdamper.analysis.point import FAILED, SweepPoint, SweepSettings
from impactdamper.analysis.transitions import rigid_amplitude
from impactdamper.core.linear import forced_amplitudes
from impactdamper.core.parameters import Parameters

__all__ = [
    "sweep",
    "two_way_sweep",
    "random_initial_state",
    "random_start_states",
    "locate_transition",
    "find_transitions",
    "swept_names",
    "check_direction",
    "with_value",
    "PSEUDO_PARAMETERS",
]


# ----------------------------------------------------------------------------------------
# Sweeps
# ----------------------------------------------------------------------------------------
# Swept names beyond the fields of Parameters: "delta" sets delta1 = delta2 (Peterka-style
# damping maps with one damping ratio).
PSEUDO_PARAMETERS = {"delta": ("delta1", "delta2")}


def check_direction(direction: str) -> None:
    """A one-way sweep's ``direction``: ``up`` or ``down`` (else the one-line error naming it)."""
    if direction not in ("up", "down"):
        raise ValueError(f"`direction` = {direction!r} is not allowed: must be 'up' or 'down'")


def swept_names() -> tuple[str, ...]:
    """Names a sweep accepts: the fields of Parameters and ``delta`` (delta1 = delta2)."""
    return Parameters.names() + tuple(PSEUDO_PARAMETERS)


def with_value(base: Parameters, name: str, value: float) -> Parameters:
    """``base`` with the swept parameter ``name`` set to ``value`` (see :func:`swept_names`)."""
    if name in PSEUDO_PARAMETERS:
        return base.replace(**{field_: float(value) for field_ in PSEUDO_PARAMETERS[name]})
    if name not in Parameters.names():
        raise ValueError(f"`parameter` = {name!r} is not allowed: must be one of {', '.join(swept_names())}")
    return base.replace(**{name: float(value)})


def sweep(
    base: Parameters,
    parameter: str,
    values: Sequence[float],
    *,
    settings: SweepSettings | None = None,
    progress: Callable[[int, int, SweepPoint], None] | None = None,
) -> list[SweepPoint]:
    """Sweep ``parameter`` over ``values`` in the given order, each point from its neighbour.

    Parameters
    ----------
    base : Parameters
        The other parameters.
    parameter : str
        A field of :class:`Parameters` (``gap`` = Delta0/x_st).
    values : sequence of float
        In sweep order (increasing for an upward sweep, decreasing for a downward one); the
        first point starts from Algorithm No. 2's step 1.
    progress : callable(i, n, point), optional
        Called after each point.

    Returns
    -------
    list of SweepPoint, in the order of ``values``.
    """
    settings = settings or SweepSettings()
    values = [float(v) for v in values]
    if not values:
        raise ValueError("`values` is not allowed: must hold at least one value")
    out: list[SweepPoint] = []
    prev = None
    for i, v in enumerate(values):
        point = solve_point(with_value(base, parameter, v), v, prev, settings=settings)
        out.append(point)
        prev = point
        if progress is not None:
            progress(i, len(values), point)
    return out


def _sweep_job(args):
    base, parameter, values, settings, tag, on_point = args
    logger = logging.getLogger(__name__)
    n = len(values)
    every = max(n // 20, 1)
    t0 = time.perf_counter()

    def progress(i, n, point):
        if on_point is not None:
            on_point()
        if (i + 1) % every == 0 or i + 1 == n:
            logger.info(
                "%s sweep: %d/%d points (%s = %.6g: %s), %.1f s",
                tag,
                i + 1,
                n,
                parameter,
                point.value,
                point.label,
                time.perf_counter() - t0,
            )

    cpu = time.process_time()
    points = sweep(base, parameter, values, settings=settings, progress=progress)
    return points, time.process_time() - cpu, time.perf_counter() - t0


def two_way_sweep(
    base: Parameters,
    parameter: str,
    values: Sequence[float],
    *,
    settings: SweepSettings | None = None,
    processes: int = 1,
    on_point: Callable[[], None] | None = None,
) -> dict[str, list[SweepPoint]]:
    """Upward and downward sweeps over the sorted ``values``.

    Parameters
    ----------
    processes : int
        1: one after the other; 2: the two directions in parallel processes.
    on_point : callable(), optional
        Called after each settled point (``2 len(values)`` calls in all), for a progress bar;
        only with ``processes`` = 1 (a parallel direction cannot call back).

    Returns
    -------
    dict
        ``{"up": [...], "down": [...]}``, each list in increasing order of the value, and
        ``"cpu"``/``"wall"``: ``{"up": s, "down": s}``, the processor and wall time of each
        direction.
    """
    settings = settings or SweepSettings()
    values = sorted(float(v) for v in values)
    tick = on_point if processes < 2 else None
    jobs = [(base, parameter, values, settings, "up", tick), (base, parameter, values[::-1], settings, "down", tick)]
    up, down = map_tasks(_sweep_job, jobs, 2 if processes >= 2 else 1)
    return {
        "up": up[0],
        "down": down[0][::-1],
        "cpu": {"up": up[1], "down": down[1]},
        "wall": {"up": up[2], "down": down[2]},
    }


def random_initial_state(p: Parameters, rng: np.random.Generator) -> np.ndarray:
    """A random state with a non-negative gap, on the scale of the forced motions.

    x1 = A u1, x1' = A omega u2 with A = max(|x1p_hat|, rigid amplitude, 1) x_st; the gap is
    B |u3| and the relative velocity x2' - x1' = B omega u4 with B = max(U1, |Delta0|, x_st);
    u_i uniform on (-1, 1).
    """
    x1p, x2p = forced_amplitudes(p)
    A = max(abs(x1p), rigid_amplitude(p) * p.x_st, p.x_st)
    B = max(abs(x2p - x1p), abs(p.Delta0), p.x_st)
    u = rng.uniform(-1.0, 1.0, size=4)
    x1 = A * u[0]
    x2 = x1 + p.Delta0 - B * abs(u[2])
    v1 = A * p.omega * u[1]
    return np.array([x1, x2, v1, v1 + B * p.omega * u[3]])


def random_start_states(
    base: Parameters,
    parameter: str,
    values: Sequence[float],
    count: int,
    seed: int,
    indices: Sequence[int] | None = None,
) -> list[tuple[float, Parameters, list[np.ndarray]]]:
    """``count`` random initial states per value, deterministic: the generator of value
    ``indices[i]`` (default i), start j is ``numpy.random.default_rng([seed, indices[i], j])``,
    so a state does not depend on how the values are split into jobs.

    Returns
    -------
    list (per value) of (value, its parameters, its states).
    """
    if not (isinstance(count, int) and not isinstance(count, bool) and count >= 1):
        raise ValueError(f"`count` = {count!r} is not allowed: must be an integer >= 1")
    values = [float(v) for v in values]
    indices = list(range(len(values))) if indices is None else [int(i) for i in indices]
    if len(indices) != len(values):
        raise ValueError(f"`indices` is not allowed: has {len(indices)} entries for {len(values)} values")
    out = []
    for i, v in zip(indices, values):
        p = with_value(base, parameter, v)
        out.append((v, p, [random_initial_state(p, np.random.default_rng([int(seed), i, j])) for j in range(count)]))
    return out


# ----------------------------------------------------------------------------------------
# Transitions
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Transition:
    """A change of label between neighbouring sweep points, located by bisection.

    Attributes
    ----------
    direction : str
        ``up`` or ``down``.
    value : float
        Midpoint of the final bracket.
    lower, upper : float
        The final bracket (lower < upper).
    before, after : str
        Labels before and after the transition, in the sweep's direction.
    evaluations : int
        Points solved by the bisection.
    stopped : bool
        The bisection stopped early because a midpoint's simulation failed (label ``err``):
        the bracket is then wider than asked.
    one_sided : bool
        The far end of the bracket moved at most once: the changed motion was found at a single
        evaluated point (the neighbour itself or the first midpoint) and every later midpoint
        kept the first label. Typical of a periodic window entered from a nonperiodic band,
        where whether a start lands in the window depends on the start, not only on the value.
    """

    direction: str
    value: float
    lower: float
    upper: float
    before: str
    after: str
    evaluations: int
    stopped: bool = False
    one_sided: bool = False

    def row(self) -> dict:
        """A flat dict for a CSV row (the flags as 0 or 1)."""
        return {**dataclasses.asdict(self), "stopped": int(self.stopped), "one_sided": int(self.one_sided)}


def locate_transition(
    base: Parameters,
    parameter: str,
    first: SweepPoint,
    second: SweepPoint,
    direction: str,
    *,
    settings: SweepSettings | None = None,
    xtol: float = 1e-6,
) -> _Transition:
    """Bisect the label change between ``first`` and ``second`` (neighbours, in sweep order).

    Each midpoint starts from ``first``'s motion, as a finer sweep would; the side of the
    bracket that keeps ``first``'s label moves. The result is where the motion followed from
    ``first`` stops being that motion.
    """
    settings = settings or SweepSettings()
    check_direction(direction)
    a, b = first, second
    n, stopped, b_moves = 0, False, 0
    while abs(b.value - a.value) > xtol:
        m = 0.5 * (a.value + b.value)
        point = solve_point(with_value(base, parameter, m), m, a, settings=settings)
        n += 1
        if point.regime == FAILED:
            stopped = True
            break
        if point.label == a.label:
            a = point
        else:
            b = point
            b_moves += 1
    lo, hi = sorted((a.value, b.value))
    return _Transition(
        direction, 0.5 * (lo + hi), lo, hi, a.label, b.label, n, stopped, one_sided=b_moves <= 1 and n >= 4
    )


def find_transitions(
    base: Parameters,
    parameter: str,
    points: dict,
    *,
    settings: SweepSettings | None = None,
    xtol: float = 1e-6,
    workers: int = 1,
) -> dict[str, list[_Transition]]:
    """Every label change along both directions of a two-way sweep, each bisected on its own
    (:func:`locate_transition`) in ``workers`` processes, each handed to whichever is free: the
    same transitions as one direction after the other, in the same order.

    Parameters
    ----------
    points : dict
        ``{"up": [...], "down": [...]}`` (:func:`two_way_sweep`), each in increasing values;
        neighbours are taken in each sweep's own order.

    Returns
    -------
    dict
        direction -> list of Transition, in the sweep's order.
    """
    pairs = []
    for direction in ("up", "down"):
        order = list(points[direction]) if direction == "up" else list(points[direction])[::-1]
        pairs += [(direction, a, b) for a, b in zip(order[:-1], order[1:]) if a.label != b.label]
    found = map_tasks(
        lambda pair: locate_transition(base, parameter, pair[1], pair[2], pair[0], settings=settings, xtol=xtol),
        pairs,
        workers,
    )
    return {d: [t for (dd, _, _), t in zip(pairs, found) if dd == d] for d in ("up", "down")}
