"""Where a predicate holds along one parameter: runs of True on a grid, each inner end bisected
to a relative tolerance, their intersections and the distance to the nearest.

The claims of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100, are located this
way along the gap (the replication's gap scan), along each other parameter (the claims
stage's search) and on the orbits' branches (their stable and admissible stretches):
:func:`claim_intervals` finds, along one parameter with the others fixed, the intervals where
each claim holds: a grid, then every end of a run bisected to a relative tolerance.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass

__all__ = ["Interval", "true_runs", "true_intervals", "intersect", "distance_to"]


@dataclass(frozen=True)
class Interval:
    """A run of parameter values where a predicate holds.

    ``lo``/``hi`` are the ends (the midpoint of the final bracket, or the window's edge when
    ``lo_open``/``hi_open``: the run reaches the searched range's end); ``lo_bracket`` and
    ``hi_bracket`` are (inside, outside) values from the bisection (None at an open end).
    """

    lo: float
    hi: float
    lo_open: bool
    hi_open: bool
    lo_bracket: tuple | None
    hi_bracket: tuple | None

    @property
    def width(self) -> float:
        return self.hi - self.lo

    def to_dict(self) -> dict:
        return asdict(self)


def _resolution(x: float, rel_tol: float, floor: float, abs_tol: float | None = None) -> float:
    """Bisection stops at a bracket this wide: ``abs_tol`` when given, else ``rel_tol``
    relative to the value, with an absolute floor ``rel_tol * floor`` for ends near zero
    (damping, R)."""
    return abs_tol if abs_tol is not None else rel_tol * max(abs(x), floor)


def _bisect(
    pred: Callable[[float], bool], x_in: float, x_out: float, rel_tol: float, floor: float, abs_tol: float | None = None
) -> tuple:
    """Shrink [x_in, x_out] (pred True at x_in, False at x_out) until its width is within
    ``rel_tol`` of the end's value, or ``abs_tol`` (see :func:`_resolution`)."""
    while abs(x_out - x_in) > _resolution(0.5 * (x_in + x_out), rel_tol, floor, abs_tol):
        mid = 0.5 * (x_in + x_out)
        if pred(mid):
            x_in = mid
        else:
            x_out = mid
    return x_in, x_out


def true_runs(flags: Sequence[bool]) -> list[tuple[int, int]]:
    """The maximal runs of True in ``flags``, as (first, last) indices, in order."""
    out, i, n = [], 0, len(flags)
    while i < n:
        if not flags[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and flags[j + 1]:
            j += 1
        out.append((i, j))
        i = j + 1
    return out


def true_intervals(
    xs: Sequence[float],
    flags: Sequence[bool],
    pred: Callable[[float], bool],
    rel_tol: float,
    floor: float,
    abs_tol: float | None = None,
) -> list[Interval]:
    """Maximal runs of True on the grid ``xs`` (increasing), each inner end bisected with
    ``pred`` to ``rel_tol`` (or ``abs_tol``); a run reaching the grid's end is open there. A
    run narrower than the grid step between two False grid points is not seen: the grid sets
    the search's resolution."""
    out, n = [], len(xs)
    for i, j in true_runs(flags):
        ends = {}
        for side, k_in, k_out in (("lo", i, i - 1), ("hi", j, j + 1)):
            if 0 <= k_out < n:
                x_in, x_out = _bisect(pred, float(xs[k_in]), float(xs[k_out]), rel_tol, floor, abs_tol)
                ends[side] = (0.5 * (x_in + x_out), False, (x_in, x_out))
            else:
                ends[side] = (float(xs[k_in]), True, None)
        out.append(Interval(ends["lo"][0], ends["hi"][0], ends["lo"][1], ends["hi"][1], ends["lo"][2], ends["hi"][2]))
    return out


def intersect(ra: Sequence[Interval], rb: Sequence[Interval]) -> list[Interval]:
    """Intersections of two lists of intervals (each end taken from the interval bounding it)."""
    out = []
    for a in ra:
        for b in rb:
            lo_src = a if a.lo >= b.lo else b
            hi_src = a if a.hi <= b.hi else b
            if lo_src.lo < hi_src.hi:
                out.append(
                    Interval(lo_src.lo, hi_src.hi, lo_src.lo_open, hi_src.hi_open, lo_src.lo_bracket, hi_src.hi_bracket)
                )
    return out


def _claim_intervals(
    xs: Sequence[float],
    claim_a_at: Callable[[float], bool],
    claim_b_at: Callable[[float], bool],
    rel_tol: float,
    floor: float,
    flags_a: Sequence[bool] | None = None,
    flags_b: Sequence[bool] | None = None,
) -> dict:
    """Intervals of ``xs`` (an increasing grid of one parameter) where claim (a), claim (b)
    and both hold; ``claim_*_at(x)`` evaluates a claim at one value (the grid's flags may be
    passed in when already computed). Returns ``{"a": [...], "b": [...], "both": [...]}``."""
    fa = list(flags_a) if flags_a is not None else [claim_a_at(float(x)) for x in xs]
    fb = list(flags_b) if flags_b is not None else [claim_b_at(float(x)) for x in xs]
    ia = true_intervals(xs, fa, claim_a_at, rel_tol, floor)
    ib = true_intervals(xs, fb, claim_b_at, rel_tol, floor)
    return {"a": ia, "b": ib, "both": intersect(ia, ib)}


def distance_to(intervals: Sequence[Interval], x: float) -> tuple[float, float | None]:
    """Distance from ``x`` to the nearest interval, and that interval's nearest point
    (0 and ``x`` itself when ``x`` lies inside one; inf and None when there is none)."""
    best = (math.inf, None)
    for r in intervals:
        nearest = min(max(x, r.lo), r.hi)
        d = abs(nearest - x)
        if d < best[0]:
            best = (d, nearest)
    return best
