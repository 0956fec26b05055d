"""The peaks along one sweep's branches, located: where a slow sweep's samples rise to a maximum
or its motion changes, a bracket, shrunk by continuation to a given width.

Steps 2-3 of :func:`impactdamper.analysis.peaks.worst_branches` (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100: Algorithm No. 2 with the impact law of eqs. 21-22 settles every
point, through :func:`impactdamper.steady_states`), for many suppressors per batch call:

2. **Candidates.** Along each sweep's path: every local maximum of the samples, and every pair
   of neighbours between which the motion changes (its label z/k, or a jump in max|x1| far
   larger than its neighbours' steps): a branch that ends between a lower and a higher sample
   is bracketed there. The ``candidates`` largest per path within ``CANDIDATE_MARGIN`` of the
   path's largest sample are located.
3. **Location.** A bracket is continued from its first point's settled motion (a slow sweep,
   ``ZOOM_POINTS`` steps across it), and the bracket shrinks to the steps around the largest
   value of that continuation, until it is at most ``theta_tol`` wide. At a smooth maximum the
   value then holds to ~(curvature x theta_tol^2); where the maximum ends a branch, the value is
   the branch's last point inside the final bracket (the branch's side of the jump, the worse
   side), and ``change`` (the value's change over the last shrink) measures how far it still
   moves.

The batch calls here take rows of the suppressors' relative parameters (:data:`NAMES`, theta
varied); :mod:`impactdamper.analysis.peaks` sweeps and starts at random on the same rows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactdamper.analysis.point import label_of
from impactdamper.core.parameters import RELATIVE_PARAMETERS, Parameters
from impactdamper.core.steady import REGIMES

__all__ = [
    "BranchPeak",
    "SweepPath",
    "locate_peaks",
    "band_row",
    "settle_rows",
    "labels_of",
    "NAMES",
    "FAILED_CODE",
    "CANDIDATES",
    "CANDIDATE_MARGIN",
    "ZOOM_POINTS",
    "MIN_CHAINS_PER_WORKER",
]

# Steps of one continuation across a bracket: the bracket shrinks by ZOOM_POINTS/2 each time.
ZOOM_POINTS = 8
# Brackets located per sweep path at most (the largest), and only those whose samples are
# within this fraction of the path's largest sample: a branch end can rise above its bracket's
# samples by ~(slope x step), far less than 30 % at these steps.
CANDIDATES = 6
CANDIDATE_MARGIN = 0.3
# A jump between neighbours with the same label: their max|x1| differs by more than this
# (relative) and by more than JUMP_RATIO times the neighbouring steps.
JUMP_RTOL = 1e-3
# A bracket keeps shrinking while its best value is within PRUNE_MARGIN / 4^level of its case's
# best so far: near a resonance max|x1| changes by <~ its own value per 0.04 of theta (the
# peaks are >= 0.05 wide), and a bracket of the first continuation is 0.04/4 wide.
PRUNE_MARGIN = 1.0
JUMP_RATIO = 3.0
# Chains per worker below which a batch call runs in this process (a fork costs more).
MIN_CHAINS_PER_WORKER = 8
# The parameters of a suppressor a batch row sets (its scales are the base's).
NAMES = tuple(RELATIVE_PARAMETERS)
FAILED_CODE = len(REGIMES)


@dataclass(frozen=True)
class BranchPeak:
    """One located maximum of max|x1|/x_st along a branch.

    Attributes
    ----------
    theta, value : float
        Where and how high (over x_st).
    source : str
        ``up`` or ``down`` (the sweep whose path it is on), ``no contact`` (the closed form)
        or ``random`` (an attractor from a random start).
    label : str
        The motion there, z/k (``0/1`` without contact).
    kind : str
        ``maximum`` (a smooth maximum), ``branch end`` (the branch ends there: the motion
        changes in the next step of the final bracket), ``first contact`` (the motion without
        contact first touches the stop there), ``sample`` (a grid sample or a random start,
        not refined).
    bracket : float
        Width of the final theta bracket (0 for the closed form).
    change : float
        Relative change of the value over the last shrink of the bracket.
    """

    theta: float
    value: float
    source: str
    label: str
    kind: str
    bracket: float = 0.0
    change: float = 0.0

    def to_dict(self) -> dict:
        return {name: getattr(self, name) for name in self.__dataclass_fields__}


def band_row(p: Parameters, theta: float) -> list[float]:
    """The batch row (:data:`NAMES` columns) of suppressor ``p`` at ``theta``."""
    return [float(theta) if n == "theta" else float(getattr(p, n)) for n in NAMES]


def settle_rows(base: Parameters, rows: list, settings, chain_length: int, states=None, workers: int = 1, chain=True):
    """One :func:`impactdamper.steady_states` call on ``rows`` (NAMES columns), on up to
    ``workers`` processes when there are chains enough to share, by ``settings.backend``."""
    from impactdamper.analysis.batch import steady_states

    chains = len(rows) // chain_length if chain else len(rows)
    w = max(1, min(int(workers), chains // MIN_CHAINS_PER_WORKER))
    kw = dict(chain_length=chain_length) if chain else dict(chain=False)
    backend = getattr(settings, "backend", "auto")
    values = np.array(rows, float)
    return steady_states(base, NAMES, values, settings=settings, states=states, workers=w, backend=backend, **kw)


def labels_of(res, sl: slice) -> list[str]:
    """The motions z/k (``failed``: the solver's work bound) of the points ``sl`` of a batch result."""
    codes, ks, zs = res.regime_code[sl], res.period_multiple[sl], res.impacts_per_cycle[sl]
    return ["failed" if c == FAILED_CODE else label_of(REGIMES[c], int(k), int(z)) for c, k, z in zip(codes, ks, zs)]


@dataclass
class SweepPath:
    """One sweep's path through a band: theta, max|x1|, labels and sections in the sweep's order."""

    case: int
    direction: str
    t: np.ndarray
    y: np.ndarray
    labels: list
    sections: np.ndarray


@dataclass
class _Bracket:
    case: int
    direction: str
    t_a: float
    y_a: float
    label_a: str
    s_a: np.ndarray
    t_b: float
    best_t: float
    best_y: float
    best_label: str
    kind: str = "sample"
    change: float = math.inf
    p: Parameters | None = None


def _candidates(path: SweepPath, limit: int) -> list[_Bracket]:
    """The brackets of a path (module docstring, 2), the ``limit`` largest within the margin."""
    t, y, lab, n = path.t, np.nan_to_num(path.y, nan=-np.inf), path.labels, len(path.t)
    spans = {}
    for i in range(n):
        if np.isfinite(y[i]) and (i == 0 or y[i] >= y[i - 1]) and (i == n - 1 or y[i] >= y[i + 1]):
            spans[(max(i - 1, 0), min(i + 1, n - 1))] = y[i]
    d = np.nan_to_num(np.abs(np.diff(path.y)), nan=0.0)
    for i in range(n - 1):
        near = max(d[i - 1] if i > 0 else 0.0, d[i + 1] if i + 1 < n - 1 else 0.0)
        jump = lab[i] != lab[i + 1] or (d[i] > JUMP_RTOL * abs(y[i]) and d[i] > JUMP_RATIO * near)
        if jump and np.isfinite(y[i]) and not any(a <= i and i + 1 <= b for a, b in spans):
            spans[(i, i + 1)] = max(y[i], y[i + 1])
    top = max(spans.values(), default=-np.inf)
    keep = sorted((k for k, v in spans.items() if v >= (1.0 - CANDIDATE_MARGIN) * top), key=lambda k: -spans[k])
    out = []
    for a, b in keep[:limit]:
        j = a + int(np.argmax(y[a : b + 1]))
        out.append(_Bracket(path.case, path.direction, t[a], y[a], lab[a], path.sections[a], t[b], t[j], y[j], lab[j]))
    return out


def _prune(active: list[_Bracket], floors: list[float], level: int) -> list[_Bracket]:
    """The brackets still worth shrinking after ``level`` shrinks: those within PRUNE_MARGIN /
    4^level of their case's best value so far (a branch end rises above its bracket's best by
    at most ~slope x width, and the width shrinks fourfold per level)."""
    best = {}
    for b in active:
        best[b.case] = max(best.get(b.case, floors[b.case]), b.best_y)
    margin = PRUNE_MARGIN / 4.0**level
    return [b for b in active if b.best_y >= (1.0 - margin) * best[b.case]]


def _zoom(base, brackets: list[_Bracket], floors: list[float], settings, theta_tol: float, workers: int) -> None:
    """Shrink the brackets to ``theta_tol`` (module docstring, 3), all in one batch call per
    shrink; brackets that cannot hold the case's largest value any more stop early
    (:func:`_prune`)."""
    m = ZOOM_POINTS
    active = [b for b in brackets if abs(b.t_b - b.t_a) > theta_tol]
    level = 0
    while active:
        rows, states = [], []
        for b in active:
            ts = b.t_a + (b.t_b - b.t_a) * np.arange(1, m + 1) / m
            rows += [band_row(b.p, t) for t in ts]
            states.append(b.s_a)
        res = settle_rows(base, rows, settings, m, np.array(states), workers)
        for j, b in enumerate(active):
            sl = slice(j * m, (j + 1) * m)
            ts = np.concatenate([[b.t_a], res.values[sl, 0]])
            ys = np.concatenate([[b.y_a], np.asarray(res.x1_max[sl], float)])
            labs = [b.label_a] + labels_of(res, sl)
            secs = np.vstack([b.s_a[None, :], res.sections[sl]])
            k = int(np.nanargmax(np.nan_to_num(ys, nan=-np.inf)))
            previous = b.best_y
            if ys[k] >= b.best_y:
                b.best_t, b.best_y, b.best_label = float(ts[k]), float(ys[k]), labs[k]
            b.change = abs(b.best_y - previous) / max(abs(b.best_y), 1e-300)
            nxt = min(k + 1, m)
            ends = nxt > k and (labs[nxt] != labs[k] or ys[nxt] < (1.0 - 1e-2) * ys[k])
            b.kind = "branch end" if ends else "maximum"
            lo = max(k - 1, 0)
            b.t_a, b.y_a, b.label_a, b.s_a = float(ts[lo]), float(ys[lo]), labs[lo], secs[lo].copy()
            b.t_b = float(ts[nxt])
        level += 1
        active = _prune([b for b in active if abs(b.t_b - b.t_a) > theta_tol], floors, level)


def locate_peaks(
    base, cases, paths: list[SweepPath], floors: list[float], candidates: int, settings, theta_tol: float, workers: int
) -> list[list[BranchPeak]]:
    """The peaks along the sweeps' ``paths`` of ``cases``, located (module docstring): each
    path's ``candidates`` largest brackets, shrunk to ``theta_tol`` while they can still hold
    their case's largest value (``floors[c]``: the case's known lower bound). One list per case."""
    brackets = []
    for path in paths:
        for b in _candidates(path, candidates):
            b.p = cases[path.case]
            brackets.append(b)
    _zoom(base, brackets, floors, settings, theta_tol, workers)
    located = [[] for _ in cases]
    for b in brackets:
        located[b.case].append(
            BranchPeak(b.best_t, b.best_y, b.direction, b.best_label, b.kind, abs(b.t_b - b.t_a), b.change)
        )
    return located
