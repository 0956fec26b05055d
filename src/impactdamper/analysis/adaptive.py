"""Maps computed where the picture changes: a coarse grid refined where neighbours differ.

A two-parameter map shows a label per cell (Peterka's z/k of the settled motion, or which of
the paper's claims hold); most neighbouring cells carry the same label, and a cell between
neighbours of one settled label is filled with it instead of being computed. Two kinds of map:

* **Chained rows** (:func:`adaptive_regime_map`, the regime maps of the sweeps stage): each row
  sweeps the fast parameter one way, every cell starting from its left neighbour's settled
  section (the brute force: ``brute_force=True``, every cell settled). Where motions
  coexist the label a cell shows depends on that history (hysteresis), so a cell can only be
  settled from a cell of its own row: each row is refined along itself. Its cells every
  ``coarse_step`` along the row are settled first, as one chain (each from the previous one's
  section); a gap between two settled cells whose labels differ, or where either did not
  settle (``np``, ``err``), gets its middle cell, settled from the nearest settled cell on its
  left, until every such gap is one cell wide; a cell just right of a label change is then
  settled again from its left neighbour if it started from farther away (so every change of
  label is the step of the brute-force chain), and if that changes its label the cells that
  started from it are settled again. The cells left between two settled cells of one settled
  label are filled with it. A settled cell starts from exactly the state the brute force
  would give it when its left neighbour is the brute force's (the carried section,
  :func:`impactdamper.analysis.ladder.carry_state`, bit for bit); elsewhere it starts from a
  cell farther left on the same motion, and lands on the same label unless the jump crosses
  into another basin: where the labels differ from the brute force's, they differ next to a
  label change or inside a window narrower than ``coarse_step`` that no settled cell touches
  (:func:`label_differences` measures both against a brute-force map).
* **Independent cells** (:func:`refine_lattice`, the claims maps): every cell from its own start;
  a block of a lattice whose corners differ (or one is unsettled, as the caller's ``split``
  says) is split at its edge midpoints and centre, a quadtree, down to blocks one lattice step
  wide; a block whose corners agree is final and its inside is filled from them
  (:func:`fill_blocks`).

The cells computed are counted (``computed``); the rest are ``filled``.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass, field

import numpy as np

from impactdamper.analysis.batch import BATCH_REGIMES, steady_states
from impactdamper.analysis.ladder import carry_state
from impactdamper.analysis.point import SweepSettings, label_of
from impactdamper.analysis.sweeps import check_direction, with_value
from impactdamper.core.model import FREE, STUCK
from impactdamper.core.parameters import Parameters, require_parameters

__all__ = [
    "adaptive_regime_map",
    "coarse_indices",
    "refine_lattice",
    "fill_blocks",
    "label_differences",
    "UNSETTLED_LABELS",
]

# Labels of cells that did not settle: a gap or block with one at a corner is always split.
UNSETTLED_LABELS = ("np", "err")
# Regime codes (BATCH_REGIMES) of a cell whose successor gets max_periods_after_nonperiodic:
# the kernels' chain gives the shorter cap after a point that did not settle on a cycle.
_NONPERIODIC_CODE = BATCH_REGIMES.index("nonperiodic")
# Rounds of refinement at most: each round halves every open gap or settles a cell again from
# its left neighbour; a 400-cell row needs about 10 (the bound only stops a runaway).
MAX_ROUNDS = 200


def coarse_indices(n: int, step: int) -> list[int]:
    """Indices 0, step, 2 step, ... of a grid of ``n`` points, and its last (``n - 1``)."""
    if n < 1 or step < 1:
        raise ValueError(f"`coarse_step` = {step!r} is not allowed: must be an integer >= 1 (grid of {n} points)")
    return sorted(set(range(0, n, step)) | {n - 1})


@dataclass
class _AdaptiveMap:
    """A regime map of chained rows computed where its labels change
    (:func:`adaptive_regime_map`): every cell's result, computed or filled.

    Attributes
    ----------
    fast_values : ndarray, shape (n,)
        The fast parameter's values, increasing (columns).
    slow_values : ndarray, shape (R,)
        The slow parameter's values (rows).
    regime_code, period_multiple, impacts_per_cycle : ndarray of int, shape (R, n)
        As :class:`~impactdamper.analysis.batch.BatchResult`'s; a filled cell has its left
        settled neighbour's.
    x1_max : ndarray, shape (R, n)
        max|x1|/x_st; NaN where filled.
    periods : ndarray of int, shape (R, n)
        Forcing periods simulated for the cell (all its settlings); 0 where filled.
    method : ndarray of object, shape (R, n)
        ``simulation``, ``rescue``, ``error`` (computed) or ``filled``.
    fallback : ndarray of object, shape (R, n)
        Why the Python reference settled a computed cell ("" where the backend did).
    computed : ndarray of bool, shape (R, n)
        Cells settled (the rest filled).
    settlings : int
        Settlings made, counting cells settled again.
    points_per_round : list of int
        Cells settled per round (round 0: the coarse chains).
    coarse_step : int
        Cells between the first settled cells of a row.
    """

    fast_values: np.ndarray
    slow_values: np.ndarray
    regime_code: np.ndarray
    period_multiple: np.ndarray
    impacts_per_cycle: np.ndarray
    x1_max: np.ndarray
    periods: np.ndarray
    method: np.ndarray
    fallback: np.ndarray
    computed: np.ndarray
    settlings: int = 0
    points_per_round: list = field(default_factory=list)
    coarse_step: int = 1

    @property
    def label(self) -> np.ndarray:
        """Peterka's labels, shape (R, n)."""
        return _labels(self.regime_code, self.period_multiple, self.impacts_per_cycle)

    @property
    def fallbacks(self) -> dict:
        """Computed cells settled by the Python reference, by reason."""
        reasons, counts = np.unique(self.fallback[self.fallback != ""].astype(str), return_counts=True)
        return {str(r): int(c) for r, c in zip(reasons, counts)}

    @property
    def computed_share(self) -> float:
        """Share of the cells settled."""
        return float(self.computed.mean()) if self.computed.size else 0.0


def _labels(codes: np.ndarray, ks: np.ndarray, zs: np.ndarray) -> np.ndarray:
    return np.vectorize(lambda c, k, z: label_of(BATCH_REGIMES[c], int(k), int(z)), otypes=[object])(codes, ks, zs)


def adaptive_regime_map(
    base: Parameters,
    fast: str,
    fast_values: Sequence[float],
    slow: str,
    slow_values: Sequence[float],
    *,
    direction: str = "up",
    settings: SweepSettings | None = None,
    coarse_step: int = 8,
    brute_force: bool = False,
    backend: str = "auto",
    workers: int = 1,
) -> _AdaptiveMap:
    """A regime map: each row sweeps ``fast`` in ``direction``, every cell from its left
    neighbour's settled section (:func:`~impactdamper.analysis.batch.steady_states`, one chain
    per row), settling only the cells where the labels change (the module docstring says how,
    and what may differ from the brute force), or every cell with ``brute_force``.

    Parameters
    ----------
    base : Parameters
        The parameters not varied.
    fast, fast_values
        The swept parameter and its values (sorted here; the columns).
    slow, slow_values
        The other parameter and its values (the rows, each an independent sweep).
    direction : {"up", "down"}
        Which way each row is swept.
    settings : SweepSettings, optional
        The cells' caps and tolerances and ``rescue``, as for the brute force.
    coarse_step : int
        Cells between the first settled cells of a row (1: the brute force itself).
    brute_force : bool
        Every cell settled, each row one chain (``coarse_step`` 1, whatever is given): the
        map the adaptive one is checked against.
    backend, workers
        As :func:`~impactdamper.analysis.batch.steady_states`: every round's cells go to it in
        one call (whole rows' coarse chains, then single cells), in ``workers`` processes.

    Returns
    -------
    AdaptiveMap
    """
    check_direction(direction)
    base = require_parameters(base, "base")
    settings = settings or SweepSettings()
    fast_sorted = np.array(sorted(float(v) for v in fast_values))
    slows = np.array([float(v) for v in slow_values])
    R, n = len(slows), len(fast_sorted)
    coarse_step = 1 if brute_force else coarse_step
    coarse = coarse_indices(n, int(coarse_step)) if n else []
    # Work in chain order (position q is the q-th cell swept); column of position q:
    column = np.arange(n) if direction == "up" else np.arange(n)[::-1]
    rows = _RowState(R, n)

    @functools.cache
    def point(r: int, q: int) -> Parameters:
        return with_value(with_value(base, fast, fast_sorted[column[q]]), slow, slows[r])

    if R and n:
        _settle_coarse(rows, coarse, base, fast, slow, fast_sorted, slows, column, settings, backend, workers)
    for _ in range(MAX_ROUNDS):
        tasks = rows.tasks()
        if not tasks:
            break
        _settle_tasks(tasks, rows, point, base, fast, slow, fast_sorted, slows, column, settings, backend, workers)
    else:
        raise RuntimeError(f"adaptive_regime_map: no end after {MAX_ROUNDS} rounds (a cycle of settlings)")
    return rows.result(fast_sorted, slows, column, int(coarse_step))


class _RowState:
    """The settled cells of every row, by position along the sweep, and what each started from."""

    def __init__(self, R: int, n: int):
        self.code = np.zeros((R, n), np.int64)
        self.k = np.zeros((R, n), np.int64)
        self.z = np.zeros((R, n), np.int64)
        self.x1_max = np.full((R, n), np.nan)
        self.periods = np.zeros((R, n), np.int64)
        self.method = np.full((R, n), "filled", dtype=object)
        self.fallback = np.full((R, n), "", dtype=object)
        self.label = np.full((R, n), "", dtype=object)
        self.sections = np.zeros((R, n, 4))
        self.modes = np.zeros((R, n), np.int64)
        self.source = np.full((R, n), -2, np.int64)  # -2 not settled, -1 step 1, else a position
        self.dirty: set[tuple[int, int]] = set()
        self.settlings = 0
        self.points_per_round: list[int] = []

    def store(self, r: int, q: int, source: int, res, i: int, labels) -> None:
        again = self.source[r, q] != -2
        changed = again and self.label[r, q] != labels[i]
        self.code[r, q], self.k[r, q], self.z[r, q] = (
            res.regime_code[i],
            res.period_multiple[i],
            res.impacts_per_cycle[i],
        )
        self.x1_max[r, q] = res.x1_max[i]
        self.periods[r, q] += res.periods[i]
        self.method[r, q], self.fallback[r, q], self.label[r, q] = res.method[i], res.fallback[i], labels[i]
        self.sections[r, q], self.modes[r, q] = res.sections[i], res.section_modes[i]
        self.source[r, q] = source
        self.settlings += 1
        if changed:  # the cells that started from this one started from another motion
            self.dirty.update((r, int(c)) for c in np.flatnonzero(self.source[r] == q))

    def tasks(self) -> list[tuple[int, int, int]]:
        """(row, position, source position) of every cell to settle in the next round."""
        todo: dict[tuple[int, int], int] = {}
        for r in range(self.code.shape[0]):
            pos = np.flatnonzero(self.source[r] != -2)
            lab = self.label[r, pos]
            unsettled = np.isin(lab, UNSETTLED_LABELS)
            split = (lab[:-1] != lab[1:]) | unsettled[:-1] | unsettled[1:]
            for a, b in zip(pos[:-1][split], pos[1:][split]):
                if b - a > 1:
                    todo[(r, (a + b) // 2)] = a
                elif self.source[r, b] != a:
                    todo[(r, b)] = a
        for r, c in sorted(self.dirty):
            todo.setdefault((r, c), int(self.source[r, c]))
        self.dirty.clear()
        return sorted((r, q, s) for (r, q), s in todo.items())

    def result(self, fast_sorted, slows, column, coarse_step: int) -> _AdaptiveMap:
        R, n = self.code.shape
        fill = {name: getattr(self, name).copy() for name in ("code", "k", "z")}
        for r in range(R):
            pos = np.flatnonzero(self.source[r] != -2)
            for a, b in zip(pos[:-1], pos[1:]):
                for name in fill:
                    fill[name][r, a + 1 : b] = fill[name][r, a]
        # Back from positions along the sweep to columns of increasing fast values.
        order = np.argsort(column)
        return _AdaptiveMap(
            fast_values=fast_sorted,
            slow_values=slows,
            regime_code=fill["code"][:, order],
            period_multiple=fill["k"][:, order],
            impacts_per_cycle=fill["z"][:, order],
            x1_max=self.x1_max[:, order],
            periods=self.periods[:, order],
            method=self.method[:, order],
            fallback=self.fallback[:, order],
            computed=(self.source != -2)[:, order],
            settlings=self.settlings,
            points_per_round=list(self.points_per_round),
            coarse_step=coarse_step,
        )


def _settle_coarse(
    rows: _RowState, coarse, base, fast, slow, fast_sorted, slows, column, settings, backend, workers
) -> None:
    """Round 0: every row's coarse cells as one chain each (the first from Algorithm No. 2's
    step 1)."""
    values = np.array([[fast_sorted[column[q]], s] for s in slows for q in coarse])
    res = steady_states(
        base,
        (fast, slow),
        values,
        settings=settings,
        chain_length=len(coarse),
        backend=backend,
        workers=workers,
    )
    labels = res.label
    for r in range(len(slows)):
        for k, q in enumerate(coarse):
            rows.store(r, q, coarse[k - 1] if k else -1, res, r * len(coarse) + k, labels)
    rows.points_per_round.append(len(values))


def _settle_tasks(
    tasks, rows: _RowState, point, base, fast, slow, fast_sorted, slows, column, settings, backend, workers
):
    """One round: every task's cell settled from its source's section carried to it (as the
    brute-force chain does), those after a cell that did not settle with the shorter cap."""
    groups: dict[bool, list] = {}
    for r, q, s in tasks:
        groups.setdefault(bool(rows.code[r, s] >= _NONPERIODIC_CODE), []).append((r, q, s))
    for after_nonperiodic, group in sorted(groups.items()):
        st = settings
        if after_nonperiodic:
            cap = settings.max_periods_after_nonperiodic
            st = dataclasses.replace(settings, max_periods=cap, max_periods_after_nonperiodic=cap)
        values = np.array([[fast_sorted[column[q]], slows[r]] for r, q, _ in group])
        states = np.array(
            [
                carry_state(point(r, q), rows.sections[r, s], STUCK if rows.modes[r, s] == 1 else FREE)[0]
                for r, q, s in group
            ]
        )
        res = steady_states(
            base, (fast, slow), values, settings=st, chain=False, states=states, backend=backend, workers=workers
        )
        labels = res.label
        for i, (r, q, s) in enumerate(group):
            rows.store(r, q, s, res, i, labels)
    rows.points_per_round.append(len(tasks))


# --- independent cells: a quadtree on a lattice ------------------------------------------------
Block = tuple[int, int, int, int]  # (i0, i1, j0, j1): the lattice points i0..i1 x j0..j1


def refine_lattice(
    known: dict[tuple[int, int], Hashable],
    blocks: Sequence[Block],
    evaluate: Callable[[list[tuple[int, int]]], list[Hashable]],
    split: Callable[[list[Hashable]], bool],
    *,
    max_rounds: int | None = None,
) -> tuple[dict[tuple[int, int], Hashable], list[Block], dict]:
    """Quadtree refinement of a lattice of independent cells.

    Parameters
    ----------
    known : dict
        The label (any hashable key) of every lattice point computed so far, by (i, j); at
        least every block's corners. Extended in place.
    blocks : sequence of (i0, i1, j0, j1)
        The blocks to start from (e.g. the cells of a coarse grid).
    evaluate : callable
        ``evaluate(points)`` -> their labels, one call per round with all the round's new
        points (lattice indices, sorted by (j, i)).
    split : callable
        ``split(corner_labels)`` -> whether a block with these corners is split.
    max_rounds : int, optional
        Rounds at most (default: until every block is final).

    Returns
    -------
    known : dict
        Every point computed.
    final : list of blocks
        The blocks not split (whose corners agree, or one lattice step wide): their insides
        are :func:`fill_blocks`'s to fill.
    stats : dict
        ``points_per_round`` (new points each round) and ``blocks_split_per_round``.
    """
    final: list[Block] = []
    open_blocks = list(blocks)
    points_per_round, split_per_round = [], []
    rounds = 0
    while open_blocks and (max_rounds is None or rounds < max_rounds):
        to_split, children, new = [], [], set()
        for i0, i1, j0, j1 in open_blocks:
            corners = [known[(i0, j0)], known[(i1, j0)], known[(i0, j1)], known[(i1, j1)]]
            if (i1 - i0 <= 1 and j1 - j0 <= 1) or not split(corners):
                final.append((i0, i1, j0, j1))
                continue
            to_split.append((i0, i1, j0, j1))
            im = (i0 + i1) // 2 if i1 - i0 > 1 else None
            jm = (j0 + j1) // 2 if j1 - j0 > 1 else None
            ii = [i0, i1] if im is None else [i0, im, i1]
            jj = [j0, j1] if jm is None else [j0, jm, j1]
            new.update((i, j) for i in ii for j in jj if (i, j) not in known)
            children += [(a, b, c, d) for a, b in zip(ii, ii[1:]) for c, d in zip(jj, jj[1:])]
        if not to_split:
            break
        points = sorted(new, key=lambda ij: (ij[1], ij[0]))
        for ij, key in zip(points, evaluate(points)):
            known[ij] = key
        points_per_round.append(len(points))
        split_per_round.append(len(to_split))
        open_blocks = children
        rounds += 1
    final += open_blocks  # (blocks left when max_rounds stopped the refinement)
    return known, final, {"points_per_round": points_per_round, "blocks_split_per_round": split_per_round}


def fill_blocks(known: dict[tuple[int, int], Hashable], final: Sequence[Block]) -> dict[tuple[int, int], Hashable]:
    """The lattice points inside (and on the edges of) the final blocks that were not computed,
    each with its block's corner label (the corners of a final block wider than one step agree).

    Returns
    -------
    dict
        (i, j) -> label of every filled point.
    """
    filled: dict[tuple[int, int], Hashable] = {}
    for i0, i1, j0, j1 in final:
        if i1 - i0 <= 1 and j1 - j0 <= 1:
            continue
        key = known[(i0, j0)]
        for i in range(i0, i1 + 1):
            for j in range(j0, j1 + 1):
                if (i, j) not in known:
                    filled[(i, j)] = key
    return filled


def label_differences(
    labels: np.ndarray, reference: np.ndarray, rows: Sequence[int] | None = None, computed: np.ndarray | None = None
) -> dict:
    """Where a map's labels differ from a reference (a brute-force map) and how far each
    difference is from a change of the reference's labels.

    Parameters
    ----------
    labels, reference : ndarray, shape (R, n)
        The two maps' labels (rows of ``reference`` not computed may be anything, see ``rows``).
    rows : sequence of int, optional
        The rows to compare (default: all); a difference's distance is measured along its row
        (one-parameter chains) when rows are given, else in both directions (Chebyshev).
    computed : ndarray of bool, shape (R, n), optional
        Which cells of ``labels`` were computed (the rest filled, :class:`AdaptiveMap`); with it
        the differences are split into filled cells (the fill's error, or a history effect) and
        computed cells (a computed cell that reached another motion than the reference's from
        another start: history, where motions coexist).

    Returns
    -------
    dict
        ``cells`` compared, ``differences``, ``share`` (differences / cells), ``distances``: per
        difference, the number of cells to the nearest cell whose reference label differs from
        the reference label at the difference (1: next to a boundary), ``max_distance`` (0
        without differences); with ``computed``, also ``filled_differences`` and
        ``computed_differences``.
    """
    labels, reference = np.asarray(labels, dtype=object), np.asarray(reference, dtype=object)
    if labels.shape != reference.shape:
        raise ValueError(f"`labels` of shape {labels.shape} is not allowed: the reference's is {reference.shape}")
    along_rows = rows is not None
    rows = list(range(labels.shape[0])) if rows is None else [int(r) for r in rows]
    distances, at_computed = [], 0
    for r in rows:
        for c in np.flatnonzero(labels[r] != reference[r]):
            at_computed += bool(computed[r, c]) if computed is not None else 0
            if along_rows:
                other = np.flatnonzero(reference[r] != reference[r, c])
                d = int(np.min(np.abs(other - c))) if len(other) else labels.shape[1]
            else:
                other = np.argwhere(reference != reference[r, c])
                d = int(np.min(np.maximum(np.abs(other[:, 0] - r), np.abs(other[:, 1] - c)))) if len(other) else 0
            distances.append(d)
    cells = len(rows) * labels.shape[1]
    out = {
        "cells": cells,
        "differences": len(distances),
        "share": len(distances) / cells if cells else 0.0,
        "distances": sorted(distances),
        "max_distance": max(distances, default=0),
    }
    if computed is not None:
        out.update(filled_differences=len(distances) - at_computed, computed_differences=at_computed)
    return out
