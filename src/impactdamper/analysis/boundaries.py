"""Every boundary of a regime map as a curve: seeds from one-parameter branches, curves followed.

A regime map (:mod:`impactdamper.analysis.adaptive`) labels cells of the plane of the gap
Delta0/x_st and a second parameter (theta, or delta = delta1 = delta2) by the settled motion.
Here its boundaries are computed as curves instead:

1. On each of a few rows (values of the second parameter), the cycles found there (Algorithm
   No. 1's one-impact orbit and the cycles the simulation settles on at a few gaps, solved
   directly by :func:`~impactdamper.analysis.orbits.solve_orbit`) are followed in the gap by
   :func:`~impactdamper.analysis.continuation.continue_orbit` up to their first grazing (the
   admissible part), and their special points collected.
2. Each special point of an admissible cycle that no curve already found passes through seeds
   a curve (:func:`~impactdamper.analysis.curves.follow_curve`) across the plane.
3. The closed-form boundaries are sampled along the second parameter: the first contact of the
   free forced response (U1/x_st, :func:`~impactdamper.analysis.transitions.no_contact_gap`) and
   the lift-off of the persistent contact (:func:`~impactdamper.analysis.transitions.stuck_liftoff_gap`).

:func:`plane_boundaries` returns the curves and the rows of ``figures/boundaries_{map}.csv``
(:data:`COLUMNS` with the plane's second parameter's name in place of ``value``).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.analysis.continuation import continue_orbit
from impactdamper.analysis.curves import Curve, curve_kind, follow_curve
from impactdamper.analysis.orbits import OrbitError, solve_orbit
from impactdamper.analysis.sweeps import with_value
from impactdamper.analysis.transitions import no_contact_gap, stuck_liftoff_gap
from impactdamper.core.parameters import Parameters
from impactdamper.analysis.solve import steady_state

__all__ = ["BoundarySettings", "plane_boundaries", "COLUMNS", "CLOSED_FORM_KINDS"]

COLUMNS = ["curve", "cycle", "kind", "gap", "value", "stable_side", "end_reason"]
CLOSED_FORM_KINDS = ("first_contact", "liftoff")
# A seed closer than this (in the plane scaled by its spans) to a curve of the same kind and
# cycle already followed lies on it. Curves are sampled at most max_step apart (~0.05), so their
# chords are within ~1e-4 of the curve.
SAME_CURVE = 2e-3


@dataclass(frozen=True)
class BoundarySettings:
    """How the boundaries of one plane are found.

    Attributes
    ----------
    seed_rows : int
        Rows (values of the second parameter, evenly spaced inside its range) whose branches seed curves.
    seed_gaps : int
        Gaps per row (evenly spaced inside the gap range) where the simulation's settled cycle
        is solved and followed (besides Algorithm No. 1's orbit).
    closed_form_points : int
        Samples of each closed-form curve along the second parameter.
    step, max_step, min_step : float
        Arclength steps of the curves (relative unknowns, parameters over their spans).
    max_points : int
        Most points of a curve per direction.
    branch_step, branch_max_step : float
        Initial and largest arclength step of the one-parameter branches.
    max_period_multiple : int
        Largest k of the simulation's settled cycles.
    extra_seeds : tuple of (float, float)
        (gap, second parameter) points whose settled cycles seed branches too (e.g. the
        one-parameter branches' seeds of the reference row: a settled cycle found there is easily
        missed by a coarse row).
    """

    seed_rows: int = 5
    seed_gaps: int = 12
    closed_form_points: int = 201
    step: float = 0.02
    max_step: float = 0.2
    min_step: float = 1e-5
    max_points: int = 300
    branch_step: float = 0.02
    branch_max_step: float = 0.5
    max_period_multiple: int = 8
    extra_seeds: tuple = ()


@dataclass(frozen=True)
class _Boundaries:
    """The boundaries of one plane: continued curves, closed-form curves, their CSV rows."""

    names: tuple
    curves: list = field(repr=False)
    rows: list = field(repr=False)
    seeds: int = 0
    duplicates: int = 0
    failures: list = field(default_factory=list)


def _label(k: int, z: int) -> str:
    return f"{z}/{k}"


def _row_cycles(p: Parameters, gaps: np.ndarray, settings: BoundarySettings) -> list:
    """Solved admissible impacting cycles on the row p: Algorithm No. 1's and the settled ones."""
    cycles = []
    for gap in gaps:
        q = p.replace(gap=float(gap))
        for seed in ("alg1", "simulate"):
            try:
                if seed == "alg1":
                    o = solve_orbit(q, "alg1")
                else:
                    s = steady_state(
                        q, settle_tol=1e-9, max_periods=1000, max_period_multiple=settings.max_period_multiple
                    )
                    if s.regime not in ("single_impact", "multi_impact"):
                        continue
                    o = solve_orbit(q, s)
            except (OrbitError, ValueError):
                continue
            if o.solved and o.admissible and o.impacts:
                cycles.append(o)
    return cycles


def _on_branch(o, branches: list) -> bool:
    """Whether a cycle lies on a branch already followed (same k, z; gap inside its range and
    the impact phases of its nearest point within 1e-6)."""
    for b in branches:
        if (b.period_multiple, b.impacts_per_cycle) != (o.period_multiple, o.impacts_per_cycle):
            continue
        values = b.values
        if not values.min() - 1e-9 <= o.p.gap <= values.max() + 1e-9:
            continue
        q = b.points[int(np.argmin(np.abs(values - o.p.gap)))]
        if abs(q.value - o.p.gap) < 1e-6 or _phase_close(q.phases, [i.phase for i in o.impacts], 0.05):
            return True
    return False


def _phase_close(a, b, tol: float) -> bool:
    if len(a) != len(b):
        return False
    d = [min(abs(x - y) % 1.0, 1.0 - abs(x - y) % 1.0) for x in a for y in b]
    return min(d) < tol


def _row_special_points(p: Parameters, gap_range, settings: BoundarySettings, gaps=None) -> list:
    """The special points of the admissible parts of every branch found on the row p (seeded
    at ``gaps``, default ``settings.seed_gaps`` evenly inside the range): a list of
    (k, z, SpecialPoint)."""
    lo, hi = gap_range
    if gaps is None:
        gaps = np.linspace(lo, hi, settings.seed_gaps + 2)[1:-1]
    branches, found = [], []
    for o in _row_cycles(p, gaps, settings):
        if _on_branch(o, branches):
            continue
        for direction, bounds in ((-1, (lo, o.p.gap)), (+1, (o.p.gap, hi))):
            if bounds[0] >= bounds[1]:
                continue
            try:
                with np.errstate(divide="ignore", invalid="ignore"):  # (a multiplier at a grazing: inf)
                    b = continue_orbit(
                        o,
                        "gap",
                        bounds,
                        direction=direction,
                        step=settings.branch_step,
                        max_step=settings.branch_max_step,
                        max_points=2000,
                    )
            except (OrbitError, ValueError):
                continue
            branches.append(b)
            for s in b.special:
                if s.point.admissible or s.kind.startswith("grazing"):
                    found.append((o.period_multiple, o.impacts_per_cycle, s))
    return found


def _near(curve: Curve, point, scales) -> bool:
    """Whether ``point`` (a, b) lies within SAME_CURVE of the curve's polyline (scaled plane)."""
    P = curve.points / scales
    x = np.asarray(point) / scales
    if len(P) == 1:
        return bool(np.hypot(*(P[0] - x)) < SAME_CURVE)
    A, B = P[:-1], P[1:]
    d = B - A
    t = np.clip(np.einsum("ij,ij->i", x - A, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0.0, 1.0)
    dist = np.hypot(*(A + t[:, None] * d - x).T)
    return bool(np.min(dist) < SAME_CURVE)


def plane_boundaries(
    base: Parameters,
    slow: str,
    gap_range: tuple,
    slow_range: tuple,
    settings: BoundarySettings | None = None,
    log: logging.Logger | None = None,
) -> _Boundaries:
    """Every boundary of the regime map of the gap against ``slow`` found from a few rows.

    Parameters
    ----------
    base : Parameters
        The parameters off the plane.
    slow : str
        The map's second parameter (a field of :class:`Parameters`, or ``delta``).
    gap_range, slow_range : (float, float)
        The map's ranges.
    settings : BoundarySettings, optional

    Returns
    -------
    Boundaries
        The continued curves and the CSV rows (:data:`COLUMNS`, ``value`` being ``slow``'s value).
    """
    settings = settings or BoundarySettings()
    log = log or logging.getLogger(__name__)
    names = ("gap", slow)
    bounds = (tuple(map(float, gap_range)), tuple(map(float, slow_range)))
    scales = np.array([bounds[0][1] - bounds[0][0], bounds[1][1] - bounds[1][0]])
    lo, hi = bounds[1]
    rows_b = lo + (hi - lo) * (np.arange(settings.seed_rows) + 0.5) / settings.seed_rows
    curves, failures, seeds, duplicates = [], [], 0, 0
    rows = [(float(b), None) for b in rows_b]
    rows += [(float(v), [float(g)]) for g, v in settings.extra_seeds if lo <= v <= hi]
    for b, seed_gaps in rows:
        p = with_value(base, slow, b)
        for k, z, s in _row_special_points(p, bounds[0], settings, seed_gaps):
            seeds += 1
            kind = curve_kind(s.kind)
            if any(
                (c.kind, c.period_multiple, c.impacts_per_cycle) == (kind, k, z) and _near(c, (s.value, b), scales)
                for c in curves
            ):
                duplicates += 1
                continue
            try:
                c = follow_curve(
                    p.replace(gap=s.value),
                    k,
                    s.point.times,
                    s.point.states_after,
                    kind,
                    names,
                    bounds,
                    **{key: getattr(settings, key) for key in ("step", "min_step", "max_step", "max_points")},
                )
            except (OrbitError, ValueError, np.linalg.LinAlgError) as err:
                failures.append(
                    {"kind": kind, "cycle": _label(k, z), "gap": s.value, slow: float(b), "error": str(err)}
                )
                continue
            log.info(
                "%s %s from (%.6f, %.6f): %d points, ends %s", _label(k, z), kind, s.value, b, len(c.points), c.ends
            )
            curves.append(c)
    rows = _curve_rows(curves, slow)
    rows += _closed_form_rows(base, slow, bounds, settings.closed_form_points)
    return _Boundaries(names=names, curves=curves, rows=rows, seeds=seeds, duplicates=duplicates, failures=failures)


def _curve_rows(curves: list, slow: str) -> list:
    """The CSV rows of continued curves: each curve as its two legs from the seed (ids ``NNa``,
    ``NNb``), each ending with its end reason on its last row."""
    rows = []
    for n, c in enumerate(curves, start=1):
        i0 = int(np.argmin(np.hypot(*(c.points - np.array(c.seed)).T)))
        legs = ((range(i0, -1, -1), c.ends[0][0]), (range(i0, len(c.points)), c.ends[1][0]))
        for tag, (idx, reason) in zip("ab", legs):
            idx = list(idx)
            for j, i in enumerate(idx):
                rows.append(
                    {
                        "curve": f"{n:02d}{tag}",
                        "cycle": c.label,
                        "kind": c.kind,
                        "gap": float(c.points[i, 0]),
                        slow: float(c.points[i, 1]),
                        "stable_side": c.stable_side[i],
                        "end_reason": reason if j == len(idx) - 1 else "",
                    }
                )
    return rows


def _closed_form_rows(base: Parameters, slow: str, bounds, points: int) -> list:
    """The first-contact (U1/x_st) and lift-off curves sampled along the second parameter,
    within the gap range (a curve leaving it is cut where it leaves)."""
    rows = []
    (glo, ghi), (lo, hi) = bounds
    values = np.linspace(lo, hi, points)
    for kind, fn, cycle in (("first_contact", no_contact_gap, "0/1"), ("liftoff", stuck_liftoff_gap, "stuck")):
        pts = [(float(fn(with_value(base, slow, float(v)))), float(v)) for v in values]
        inside = [(g, v) for g, v in pts if glo <= g <= ghi and math.isfinite(g)]
        for j, (g, v) in enumerate(inside):
            rows.append(
                {
                    "curve": kind,
                    "cycle": cycle,
                    "kind": kind,
                    "gap": g,
                    slow: v,
                    "stable_side": "",
                    "end_reason": "map_edge" if j == len(inside) - 1 else "",
                }
            )
    return rows
