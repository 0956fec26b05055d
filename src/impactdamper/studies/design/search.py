"""One global search for every device and criterion, and the checks that vouch for its answer.

A design criterion (the worst branch's peak over a band, its band average, a worst case over an
uncertainty) is minimised over a box of the device's parameters by :func:`search`:

1. **Global stage.** A scrambled Sobol sample of the box (``Budget.samples`` points, seeded:
   deterministic), every point evaluated in one batch at the ``coarse`` fidelity.
2. **Local stage.** From the seeds (``seeds``: e.g. another box's optimum) and the
   ``Budget.starts`` best distinct samples, a compass search in the box scaled to the unit cube:
   each poll evaluates, for every active start in one batch, the 2 d moves +-h along every axis
   and the pattern move (the last successful step again); a start moves to its best move if
   that is lower, else halves h, down to ``Budget.last_step``, at most ``Budget.polls`` polls
   (steps above ``Budget.coarse_above`` at the ``coarse`` fidelity, the others at ``search``).
3. **Polish and check.** Nelder-Mead from the best result (``Budget.polish`` evaluations, the
   ``search`` fidelity): along a ridge where two peaks are equal the compass stalls. Then the
   result is evaluated at the ``final`` fidelity together with its moves by +-``CHECK_MOVE``
   (2 %) of each parameter's value along each axis (at least 0.2 % of the box's side); a move
   outside the box is not made (the parameter is then at a bound). While a move is lower by
   more than ``CHECK_RTOL``, the search goes that way (the move doubled while it keeps lowering
   the value) and checks again (at most ``Budget.checks`` rounds; the record says whether the
   last check passed). The answer is the best final value seen, also over ``incumbents``
   (answers of sub-boxes, with their final values), so that an optimum over a box is never
   worse than one over a box inside it.
4. **Sub-regions** (:func:`subregions`, a check of an answer after :func:`search`; the design
   table adopts a lower half's answer: :mod:`impactdamper.studies.design.subregions`). A passed
   2 % check certifies a local minimum only. The box is split at its midpoint along each
   parameter, and every half that does not hold the answer (d halves for d parameters) is
   searched by :func:`search` with a stated budget, from one scrambled Sobol sample of the whole
   box (``budget.samples`` points, a power of 2: each half holds exactly half of them), each
   half's answer at the ``final`` fidelity. The answer passes when no half's is lower by more
   than CHECK_RTOL (relative).

``evaluate(X, fidelity)`` takes the designs as rows of X (shape (k, d), the box's order) and
returns k values; every evaluation is counted per fidelity (the budget's record).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from collections.abc import Callable, Sequence

import numpy as np
import scipy.optimize
import scipy.stats

from impactdamper.analysis.compass import compass

__all__ = [
    "SPREAD_BEST",
    "Budget",
    "SearchResult",
    "search",
    "at_bound",
    "CHECK_MOVE",
    "CHECK_RTOL",
    "FIDELITIES",
    "halves",
    "subregions",
]

# The check's move along each axis: 2 % of the parameter's value.
CHECK_MOVE = 0.02
# A move lowers the answer when it is lower by more than this (relative): the final located
# peaks hold to ~1e-7 relative where the maximum ends a branch (its bracket's width times the
# branch's slope, theta_tol 1e-6), so a difference below 1e-6 is not a difference.
CHECK_RTOL = 1e-6
# A parameter closer to a bound than this fraction of the box's side is at the bound.
BOUND_FRACTION = 1e-3
FIDELITIES = ("coarse", "search", "final")
# Local searches that end further apart than this (relative) found different local minima.
SPREAD_BEST = 0.005


@dataclass(frozen=True)
class Budget:
    """How hard :func:`search` works (the same for every device and criterion).

    Attributes
    ----------
    samples : int
        Sobol points of the global stage (a power of 2).
    starts : int
        Local searches from the best distinct samples (besides the seeds).
    polls : int
        Compass polls of one local search at most (each 2 d evaluations).
    first_step, last_step : float
        The compass step's first and smallest value, fractions of each side.
    coarse_above : float
        Polls with steps above this are evaluated at the ``coarse`` fidelity.
    polish : int
        Nelder-Mead evaluations of the polish after the compass stage (0: none).
    checks : int
        Rounds of the 2 % check at most.
    """

    samples: int = 256
    starts: int = 3
    polls: int = 12
    first_step: float = 0.125
    last_step: float = 1.0 / 128.0
    coarse_above: float = 1.0 / 32.0
    polish: int = 40
    checks: int = 6

    def to_dict(self) -> dict:
        return {name: getattr(self, name) for name in self.__dataclass_fields__}


@dataclass(frozen=True)
class SearchResult:
    """A box's optimum and the record that vouches for it.

    Attributes
    ----------
    x : dict
        The optimum's parameters by name.
    value : float
        The criterion there, at the final fidelity.
    evaluations : dict
        Evaluations per fidelity.
    at_bound : tuple of str
        Parameters at a bound of the box (within BOUND_FRACTION of its side, or whose 2 % move
        leaves the box).
    check : dict
        {name: {"down": value or None, "up": value or None}}: the final values of the 2 % moves
        (None: outside the box); ``passed`` (no move lower by more than CHECK_RTOL),
        ``largest_gain`` (the largest relative decrease of any move, <= 0 when none is lower).
    bounds : dict
    source : str
        ``search``, or ``incumbent`` when a given sub-box answer was not improved on.
    starts : dict
        The global samples, the local searches' ends and their spread (:func:`starts_record`).
    """

    x: dict
    value: float
    evaluations: dict
    at_bound: tuple
    check: dict = field(repr=False)
    bounds: dict = field(repr=False)
    source: str = "search"
    starts: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {
            "parameters": dict(self.x),
            "value": self.value,
            "evaluations": dict(self.evaluations),
            "at_bound": list(self.at_bound),
            "check": self.check,
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "source": self.source,
            "starts": dict(self.starts),
        }


def _box(bounds: dict) -> tuple[list, np.ndarray, np.ndarray]:
    names = list(bounds)
    lo = np.array([float(bounds[n][0]) for n in names])
    hi = np.array([float(bounds[n][1]) for n in names])
    if not np.all(hi > lo):
        raise ValueError(f"`bounds` = {bounds!r} is not allowed: every (low, high) must have high > low")
    return names, lo, hi


def at_bound(x: dict, bounds: dict) -> tuple:
    """The parameters of ``x`` within BOUND_FRACTION of the side from a bound of ``bounds``."""
    return tuple(n for n, (a, b) in bounds.items() if min(x[n] - a, b - x[n]) <= BOUND_FRACTION * (b - a))


def _check_moves(x: dict, bounds: dict, move: float = CHECK_MOVE) -> list[tuple[str, str, dict | None]]:
    """The check's moves of ``x``: (name, "down"/"up", the moved parameters, or None where the
    move leaves the box). A move is ``move`` of the parameter's value, at least a tenth of that
    of the box's side (a value near 0 moves by 0.2 % of the side, not by nothing)."""
    out = []
    for n, (a, b) in bounds.items():
        h = max(move * abs(x[n]), 0.1 * move * (b - a))
        for side, sign in (("down", -1.0), ("up", 1.0)):
            v = x[n] + sign * h
            out.append((n, side, {**x, n: v} if a <= v <= b else None))
    return out


class _Counter:
    """``evaluate`` with its evaluations counted per fidelity and remembered (a design met again
    is not evaluated again: the values are deterministic)."""

    def __init__(self, evaluate: Callable, names: list) -> None:
        self.evaluate, self.names = evaluate, names
        self.count = dict.fromkeys(FIDELITIES, 0)
        self.known: dict = {}

    def __call__(self, X: np.ndarray, fidelity: str) -> np.ndarray:
        X = np.asarray(X, float)
        keys = [(fidelity, tuple(row)) for row in X]
        new = list(dict.fromkeys(k for k in keys if k not in self.known))
        if new:
            self.count[fidelity] += len(new)
            v = np.asarray(self.evaluate(np.array([k[1] for k in new]), fidelity), float)
            self.known.update(zip(new, np.where(np.isfinite(v), v, np.inf)))
        return np.array([self.known[k] for k in keys], float)


def _compass(f: _Counter, starts: np.ndarray, lo, hi, budget: Budget, first_step: float, say) -> tuple:
    """The compass searches from ``starts`` (unit cube, shape (s, d)) in lockstep (module
    docstring, 2; :func:`impactdamper.analysis.compass.compass`): each poll evaluates, for every
    active start, the 2 d moves +-h along the axes and the pattern move (the last successful
    displacement repeated: a ridge is followed along its direction, not only across it); steps
    above ``budget.coarse_above`` are polled at the ``coarse`` fidelity, smaller ones at
    ``search``. Returns the best (unit point, value)."""
    d = starts.shape[1]

    def moves(u: np.ndarray, h: float, last: np.ndarray) -> list:
        out = []
        for k in range(d):
            for sign in (-1.0, 1.0):
                m = u.copy()
                m[k] = min(max(m[k] + sign * h, 0.0), 1.0)
                out.append(m)
        if np.any(last):
            out.append(np.clip(u + last, 0.0, 1.0))
        return out

    polled = {}

    def judge(idx: np.ndarray, u: np.ndarray, h: np.ndarray, candidates: list) -> list:
        level = "coarse" if float(np.min(h)) > budget.coarse_above else "search"
        fu = f(lo + u * (hi - lo), level)
        fm = f(lo + np.array([m for c in candidates for m in c]) * (hi - lo), level)
        polled.update(level=level, fu=fu)
        out, start = [], 0
        for j, c in enumerate(candidates):
            mine = fm[start : start + len(c)]
            k = int(np.argmin(mine))
            out.append(k if mine[k] < fu[j] * (1.0 - 1e-12) else None)
            start += len(c)
        return out

    def after_poll(poll: int, h: np.ndarray) -> None:
        best = float(np.min(np.minimum(polled["fu"], np.inf)))
        say(f"poll {poll} ({polled['level']}): best {best:.6g}, steps {', '.join(f'{x:.3g}' for x in h)}")

    u, _ = compass(starts, first_step, budget.last_step, moves, judge, budget.polls, after_poll=after_poll)
    fu = f(lo + u * (hi - lo), "search")
    best = int(np.argmin(fu))
    return u[best], float(fu[best]), [float(v) for v in fu]


def _polish(f: _Counter, u: np.ndarray, fu: float, lo, hi, budget: Budget, say) -> np.ndarray:
    """Nelder-Mead from ``u`` (unit cube, bounded; initial simplex 4 last steps along each
    axis) at the ``search`` fidelity, ``budget.polish`` evaluations at most: along a ridge where
    two resonance peaks are equal (a minimax optimum) the compass's axis moves stall, and the
    simplex follows the ridge. Returns the better of ``u`` and the polish's point."""
    if budget.polish <= 0:
        return u
    d = len(u)
    step = 4.0 * budget.last_step
    simplex = np.vstack([u] + [np.clip(u + step * np.eye(d)[i] * (1 if u[i] < 0.5 else -1), 0, 1) for i in range(d)])
    res = scipy.optimize.minimize(
        lambda v: float(f(lo + np.clip(v, 0.0, 1.0)[None, :] * (hi - lo), "search")[0]),
        u,
        method="Nelder-Mead",
        bounds=[(0.0, 1.0)] * d,
        options={"maxfev": int(budget.polish), "xatol": 1e-6, "fatol": 1e-9, "initial_simplex": simplex},
    )
    say(f"polish: {fu:.8g} -> {float(res.fun):.8g} ({int(res.nfev)} evaluations)")
    return np.clip(res.x, 0.0, 1.0) if res.fun < fu else u


def _distinct_best(points: np.ndarray, values: np.ndarray, count: int, apart: float) -> list[int]:
    """Indices of the ``count`` lowest finite values whose points are > ``apart`` (max norm)
    from each other."""
    out = []
    for i in np.argsort(values, kind="stable"):
        if not np.isfinite(values[i]) or len(out) >= count:
            break
        if all(np.max(np.abs(points[i] - points[j])) > apart for j in out):
            out.append(int(i))
    return out


def _final_check(f: _Counter, x: dict, bounds: dict, names) -> tuple[float, dict, dict | None]:
    """The final value at ``x`` and its 2 % moves, in one batch. Returns (value, check record,
    the lowest move if it lowers the value by more than CHECK_RTOL, else None)."""
    moves = _check_moves(x, bounds)
    inside = [m for _, _, m in moves if m is not None]
    X = np.array([[x[n] for n in names]] + [[m[n] for n in names] for m in inside])
    v = f(X, "final")
    value, rest = float(v[0]), iter(v[1:])
    record, best = {}, (value, None)
    for n, side, m in moves:
        vm = None if m is None else float(next(rest))
        record.setdefault(n, {})[side] = vm
        if vm is not None and vm < best[0]:
            best = (vm, m)
    gain = (value - best[0]) / value if value > 0 else 0.0
    lowered = best[1] if best[0] < value * (1.0 - CHECK_RTOL) else None
    check = {**record, "passed": lowered is None, "largest_gain": float(gain), "move": CHECK_MOVE, "rtol": CHECK_RTOL}
    return value, check, lowered


def search(
    evaluate: Callable[[np.ndarray, str], np.ndarray],
    bounds: dict,
    *,
    budget: Budget = Budget(),
    seeds: Sequence[dict] = (),
    incumbents: Sequence[tuple[dict, float]] = (),
    sample: tuple[np.ndarray, np.ndarray] | None = None,
    searched: dict | None = None,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> SearchResult:
    """Minimise ``evaluate`` over the box ``bounds`` ({name: (low, high)}; module docstring).

    Parameters
    ----------
    evaluate : callable(X, fidelity) -> values
    bounds : dict
    budget : Budget
    seeds : sequence of dict
        Further starts of the local stage (clipped into the box).
    incumbents : sequence of (dict, float)
        Answers over boxes inside this one with their final values: the answer is never worse.
    sample : (points, values), optional
        A global stage already evaluated (points in the box's units, shape (k, d), and their
        coarse values): used instead of a new one (several criteria may share one sample).
        With ``budget.samples`` = 0 and no sample there is no global stage (the seeds alone).
    searched : dict, optional
        A box inside this one already searched (its answer among ``incumbents``): the local
        stage starts from the best ``budget.starts - 1`` samples outside it.
    seed : int
        Of the Sobol sample.
    progress : callable(str), optional

    Returns
    -------
    SearchResult
    """
    say = progress or (lambda m: None)
    names, lo, hi = _box(bounds)
    f = _Counter(evaluate, names)
    if sample is None and budget.samples == 0:
        U, values = np.zeros((0, len(names))), np.zeros(0)
    elif sample is None:
        U = scipy.stats.qmc.Sobol(len(names), scramble=True, seed=seed).random(int(budget.samples))
        values = f(lo + U * (hi - lo), "coarse")
    else:
        X, values = np.asarray(sample[0], float), np.asarray(sample[1], float)
        inside = np.all((X >= lo) & (X <= hi), axis=1)
        U, values = (X[inside] - lo) / (hi - lo), np.where(np.isfinite(values[inside]), values[inside], np.inf)
    say(f"global stage: {len(U)} samples, best {np.min(values) if len(values) else math.nan:.6g}")
    starts = [np.clip((np.array([s[n] for n in names]) - lo) / (hi - lo), 0.0, 1.0) for s in seeds]
    count = int(budget.starts)
    if searched is not None:  # (the sub-box's answer is one of the starts already: its incumbent)
        X = lo + U * (hi - lo)
        done = np.all([(X[:, k] >= searched[n][0]) & (X[:, k] <= searched[n][1]) for k, n in enumerate(names)], axis=0)
        values = np.where(done, np.inf, values)
        count = max(count - 1, 0 if seeds else 1)
    starts += [U[i] for i in _distinct_best(U, values, count, budget.first_step)]
    if not starts:
        raise ValueError("`evaluate` is not allowed: no design of the global stage has a finite criterion")
    u, fu, ends = _compass(f, np.array(starts), lo, hi, budget, budget.first_step, say)
    u = _polish(f, u, fu, lo, hi, budget, say)
    x, value, check = _checked(f, {n: float(v) for n, v in zip(names, lo + u * (hi - lo))}, bounds, budget, say)
    source = "search"
    for xi, vi in incumbents:
        if vi < value:
            # (its check in this box may move it lower still: never above vi, the same final value)
            x, value, check = _checked(f, dict(xi), bounds, budget, say)
            source = "incumbent"
    flags = set(at_bound(x, bounds)) | {n for n in names if None in (check[n]["down"], check[n]["up"])}
    flagged = tuple(n for n in names if n in flags)
    return SearchResult(x, value, dict(f.count), flagged, check, dict(bounds), source, _starts_record(ends, len(U)))


def _starts_record(ends: Sequence[float], samples: int) -> dict:
    """What a search certifies beside its 2 % check: the global samples it started from, the
    local searches' ends (``search`` fidelity) and their spread (the largest over the lowest,
    minus 1). Starts that end more than SPREAD_BEST apart found different local minima: the
    answer is then the best found, not a certified optimum (``best_found``)."""
    ends = [float(v) for v in ends]
    finite = [v for v in ends if math.isfinite(v)]
    spread = (max(finite) / min(finite) - 1.0) if finite and min(finite) > 0 else 0.0
    return {
        "samples": int(samples),
        "starts": len(ends),
        "ends": ends,
        "spread": spread,
        "best_found": spread > SPREAD_BEST,
    }


def _checked(f: _Counter, x: dict, bounds: dict, budget: Budget, say) -> tuple[dict, float, dict]:
    """The 2 % check of ``x`` (module docstring, 3): while a move lowers the final value by more
    than CHECK_RTOL, the search goes that way (the move doubled while it keeps lowering the value
    and stays in the box: :func:`_extend`) and checks again, at most ``budget.checks`` rounds.
    Returns (parameters, final value, check record)."""
    names, _, _ = _box(bounds)
    for _ in range(max(int(budget.checks), 1)):
        value, check, lowered = _final_check(f, x, bounds, names)
        say(f"check of {value:.8g}: {'passed' if lowered is None else 'a 2 % move is lower, going that way'}")
        if lowered is None:
            return x, value, check
        x = _extend(f, x, lowered, bounds, names)
    value, check, _ = _final_check(f, x, bounds, names)
    return x, value, check


def _extend(f: _Counter, x: dict, lowered: dict, bounds: dict, names: list) -> dict:
    """From ``x`` along the axis of its lower move ``lowered``: the move doubled while that lowers
    the final value further and stays in the box. Returns the lowest point met."""
    n = next(k for k in names if lowered[k] != x[k])
    step = lowered[n] - x[n]
    best = lowered
    value = float(f(np.array([[best[k] for k in names]]), "final")[0])
    a, b = bounds[n]
    while True:
        step *= 2.0
        v = best[n] + step
        if not a <= v <= b:
            return best
        trial = {**best, n: v}
        tv = float(f(np.array([[trial[k] for k in names]]), "final")[0])
        if not tv < value * (1.0 - CHECK_RTOL):
            return best
        best, value = trial, tv


def halves(bounds: dict, x: dict) -> list[tuple[str, str, dict]]:
    """The halves of the box ``bounds`` (split at the midpoint along each parameter) that do not
    hold ``x``: (parameter, ``lower`` or ``upper``, the half's bounds), one per parameter (the
    midpoint itself belongs to the lower half; both halves where ``x`` lies outside the box)."""
    out = []
    for n, (a, b) in bounds.items():
        a, b = float(a), float(b)
        m = 0.5 * (a + b)
        for side, box, holds in (("lower", (a, m), a <= x[n] <= m), ("upper", (m, b), m < x[n] <= b)):
            if not holds:
                out.append((n, side, {**{k: tuple(map(float, v)) for k, v in bounds.items()}, n: box}))
    return out


def subregions(
    evaluate: Callable[[np.ndarray, str], np.ndarray],
    bounds: dict,
    x: dict,
    value: float,
    *,
    budget: Budget,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """The sub-region check of the answer ``x`` (final value ``value``) over the box ``bounds``
    (module docstring, 4): every half of :func:`halves` searched by :func:`search` with
    ``budget``, from one Sobol sample of the whole box shared by the halves.

    Returns
    -------
    dict
        ``bounds``, ``parameters``, ``value``, ``budget``, ``rtol`` (CHECK_RTOL); ``halves``
        (per half: ``parameter``, ``half``, ``bounds``, ``value`` (its answer's final value),
        ``parameters``, ``margin`` (its value over ``value``, minus 1: negative where the half
        is lower), ``check_passed``, ``at_bound``, ``evaluations``); ``smallest_margin``,
        ``lower`` (the halves lower by more than CHECK_RTOL), ``passed`` (none is),
        ``evaluations`` (per fidelity, the sample's included).
    """
    say = progress or (lambda m: None)
    names, lo, hi = _box(bounds)
    if budget.samples < 2 or budget.samples & (budget.samples - 1):
        raise ValueError(f"`budget.samples` = {budget.samples!r} is not allowed: must be a power of 2, >= 2")
    f = _Counter(evaluate, names)
    X = lo + scipy.stats.qmc.Sobol(len(names), scramble=True, seed=seed).random(int(budget.samples)) * (hi - lo)
    values = f(X, "coarse")
    say(f"sample of the box: {len(X)} designs, best {np.min(values):.6g}")
    counts = dict(f.count)
    out = []
    for n, side, box in halves(bounds, x):
        r = search(evaluate, box, budget=budget, sample=(X, values), seed=seed)
        margin = (r.value - value) / abs(value) if value else r.value - value
        say(f"{n} {side} half: {r.value:.8g} ({margin:+.3e} against {value:.8g})")
        counts = {k: counts.get(k, 0) + r.evaluations.get(k, 0) for k in set(counts) | set(r.evaluations)}
        out.append(
            {
                "parameter": n,
                "half": side,
                "bounds": {k: list(v) for k, v in box.items()},
                "value": r.value,
                "parameters": dict(r.x),
                "margin": margin,
                "check_passed": bool(r.check["passed"]),
                "at_bound": list(r.at_bound),
                "evaluations": dict(r.evaluations),
            }
        )
    lower = [h for h in out if h["margin"] < -CHECK_RTOL]
    return {
        "bounds": {k: [float(a), float(b)] for k, (a, b) in bounds.items()},
        "parameters": dict(x),
        "value": value,
        "budget": budget.to_dict(),
        "rtol": CHECK_RTOL,
        "halves": out,
        "smallest_margin": min((h["margin"] for h in out), default=math.inf),
        "lower": [f"{h['parameter']} {h['half']}" for h in lower],
        "passed": not lower,
        "evaluations": {k: counts[k] for k in sorted(counts)},
    }
