"""The paper's Fig. 2 claims over two parameters (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100): claim (a), Algorithm No. 1's gap negative on (t1, t2);
claim (b), Algorithm No. 2 settles with T_c = 2T and three impacts per cycle; maps of both and
their adaptive refinement.

A map's uniform grid (the record's resolution) is computed where its picture changes
(:func:`adaptive_claims_map`): every ``coarse_step``-th grid point first, then a block of the
grid whose corners differ in what the record says of a cell (claim (a), whether Algorithm
No. 1's orbit exists, the settled motion's regime, k and z: :data:`CELL_KEY`) or that has an
unsettled corner is split at its edge midpoints and centre
(:func:`impactdamper.analysis.adaptive.refine_lattice`), down to blocks one grid step wide; the
grid points inside a block whose corners agree are filled from them (no periods: they were
not simulated). Every cell is independent (Algorithm No. 2 from the paper's step 1), so a
computed cell is the brute-force grid's; a filled cell differs only where a window narrower
than the blocks lies inside a block whose corners agree (rows every ``check_every``-th are
computed in full to measure it).

Beyond the grid (:func:`refine_claims_map`), a grid cell whose corners do not all carry the
same claims label (:func:`map_label`: both claims, (a) only, (b) only, neither; or ``np`` when
Algorithm No. 2 did not settle) is split in four the same way, at most ``levels`` times; the
floor, the finest step, is the grid step / 2^levels. The same spirit as the one-parameter
refinement (:func:`impactdamper.studies.claims.search.refine_grid`): a window wider than the
floor that touches a grid point, or sits between points of different labels, is resolved to
the floor; a window inside a cell whose four corners agree is not (nothing there asks for
refinement).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from impactdamper.analysis.adaptive import coarse_indices, fill_blocks, refine_lattice
from impactdamper.analysis.parallel import map_blocks
from impactdamper.core.algorithm1 import algorithm1
from impactdamper.studies.replication.claims import CLAIM_B_IMPACTS, CLAIM_B_PERIOD_MULTIPLE, claim_a

MAP_COLUMNS = [
    "x",
    "y",
    "claim_a",
    "claim_b",
    "both",
    "alg1_exists",
    "regime",
    "period_multiple",
    "impacts_per_cycle",
    "periods",
    "label",
]


def claims_map(
    p, x: str, xs: Sequence[float], y: str, ys: Sequence[float], *, gap_tol: float, settings, workers: int = 1
) -> list[dict]:
    """Both claims at every cell of the grid ``xs`` x ``ys`` of parameters ``x`` and ``y`` (the
    others as in ``p``): Algorithm No. 1 (closed form, ``gap_tol``) and Algorithm No. 2 from the
    paper's step 1 on the compiled batch (:func:`impactdamper.steady_states`, each
    cell alone, ``settings``), every cell (the brute force of :func:`adaptive_claims_map`).

    Returns
    -------
    list of dict
        One per cell, rows of y outer, x inner, with :data:`MAP_COLUMNS`.
    """
    if x == y:
        raise ValueError(f"`y` = {y!r} is not allowed: must differ from `x`")
    points = [(float(a), float(b)) for b in ys for a in xs]
    return claims_cells(p, x, y, points, gap_tol=gap_tol, settings=settings, workers=workers)


# Fewest cells a worker process is given (below, forking costs more than it saves).
MIN_BLOCK = 32


def claims_cells(
    p, x: str, y: str, points: Sequence[tuple[float, float]], *, gap_tol: float, settings, workers: int = 1
) -> list[dict]:
    """Both claims at each point ``(x value, y value)`` of ``points`` (any set, in the given
    order), as :func:`claims_map` computes them at its cells: the points in contiguous blocks,
    one batch call each, in ``workers`` processes (:func:`impactdamper.analysis.parallel.map_blocks`;
    every point is independent, so the result does not depend on ``workers``).

    Returns
    -------
    list of dict
        One per point, with :data:`MAP_COLUMNS`.
    """
    if x == y:
        raise ValueError(f"`y` = {y!r} is not allowed: must differ from `x`")
    cells = [(float(a), float(b)) for a, b in points]
    return map_blocks(lambda block: _claims_cells(p, x, y, block, gap_tol, settings), cells, workers, MIN_BLOCK)


def _claims_cells(p, x: str, y: str, cells: list, gap_tol: float, settings) -> list[dict]:
    """:func:`claims_cells` in this process: one batch call for all ``cells``."""
    from impactdamper import steady_states

    if not cells:
        return []
    res = steady_states(p, (x, y), np.array(cells, float).reshape(-1, 2), settings=settings, chain=False)
    regimes, labels = res.regime, res.label  # (each property builds its array: once, not per cell)
    out = []
    for i, (a, b) in enumerate(cells):
        alg1 = algorithm1(p.replace(**{x: a, y: b}), gap_tol=gap_tol)
        ca = claim_a(alg1)
        rg, k, z = str(regimes[i]), int(res.period_multiple[i]), int(res.impacts_per_cycle[i])
        cb = rg == "multi_impact" and k == CLAIM_B_PERIOD_MULTIPLE and z == CLAIM_B_IMPACTS
        out.append(
            {
                "x": a,
                "y": b,
                "claim_a": ca,
                "claim_b": cb,
                "both": ca and cb,
                "alg1_exists": bool(alg1.exists),
                "regime": rg,
                "period_multiple": k,
                "impacts_per_cycle": z,
                "periods": int(res.periods[i]),
                "label": str(labels[i]),
            }
        )
    return out


# What the map's record says of a cell, but its periods: a filled grid cell takes these from
# the corners of its block, which all agree on them (claim (b), both and the label follow).
CELL_KEY = ("claim_a", "alg1_exists", "regime", "period_multiple", "impacts_per_cycle")
# Regimes of a cell that did not settle: a block with such a corner is always split.
UNSETTLED_REGIMES = ("nonperiodic", "failed")


def _cell_key(row: dict) -> tuple:
    return tuple(str(row[k]).lower() for k in CELL_KEY)


def _split_cells(keys: list[tuple]) -> bool:
    """A grid block is split where its corners' cells differ or one did not settle."""
    return len(set(keys)) > 1 or any(k[CELL_KEY.index("regime")] in UNSETTLED_REGIMES for k in keys)


def adaptive_claims_map(
    p,
    x: str,
    x_axis: tuple[float, float, int],
    y: str,
    y_axis: tuple[float, float, int],
    *,
    coarse_step: int,
    check_every: int,
    gap_tol: float,
    settings,
    workers: int = 1,
) -> tuple[list[dict], dict]:
    """The uniform grid of :func:`claims_map` computed where its cells change (the module
    docstring says how).

    Parameters
    ----------
    p, x, y, gap_tol, settings, workers
        As :func:`claims_map`.
    x_axis, y_axis : (start, stop, points)
        The grid (``numpy.linspace(start, stop, points)`` per axis).
    coarse_step : int
        Grid steps between the points computed first, per axis (1: every cell, the brute force).
    check_every : int
        Every ``check_every``-th row of y (from the first) is computed in full as well: the
        filled cells there are compared with their computed values (0: no check).

    Returns
    -------
    rows : list of dict
        Every grid cell (:data:`MAP_COLUMNS`; ``periods`` None where filled), rows of y outer,
        x inner.
    stats : dict
        ``grid_points``, ``computed`` (cells simulated), ``filled``, ``coarse_step``,
        ``points_per_round``, ``check`` (``every``, ``rows``, ``cells`` compared, ``filled``
        among them, ``differences`` in the record's cell, ``label_differences`` in the claims
        label (:func:`map_label`), ``share``).
    """
    _check_axes(x, x_axis, y, y_axis)
    (x0, x1, nx), (y0, y1, ny) = x_axis, y_axis
    xs, ys = np.linspace(float(x0), float(x1), nx), np.linspace(float(y0), float(y1), ny)

    def cells(points: list[tuple[int, int]]) -> list[dict]:
        return claims_cells(
            p, x, y, [(xs[i], ys[j]) for i, j in points], gap_tol=gap_tol, settings=settings, workers=workers
        )

    rows, filled, computed, points_per_round = _refined_and_filled(cells, xs, ys, int(coarse_step))
    check = _check_filled(cells, rows, filled, nx, ny, int(check_every))
    out = [rows[(i, j)] for j in range(ny) for i in range(nx)]
    return out, {
        "grid_points": nx * ny,
        "computed": computed,
        "filled": len(filled),
        "computed_share": computed / (nx * ny),
        "coarse_step": int(coarse_step),
        "points_per_round": points_per_round,
        "check": check,
    }


def _refined_and_filled(cells, xs: np.ndarray, ys: np.ndarray, coarse_step: int):
    """The coarse lattice computed by ``cells``, its blocks split where their cells differ
    (:func:`refine_lattice`), and the cells inside the blocks left whole filled from the block's
    corner (``periods`` None).

    Returns the rows by grid index (i, j), the filled indices, the number of cells computed and
    the points computed per round (the coarse lattice first)."""
    nx, ny = len(xs), len(ys)
    rows: dict[tuple[int, int], dict] = {}

    def evaluate(points: list[tuple[int, int]]) -> list[tuple]:
        out = cells(points)
        rows.update(zip(points, out))
        return [_cell_key(r) for r in out]

    ci, cj = coarse_indices(nx, coarse_step), coarse_indices(ny, coarse_step)
    first = sorted(((i, j) for i in ci for j in cj), key=lambda ij: (ij[1], ij[0]))
    known = dict(zip(first, evaluate(first)))
    blocks = [(a, b, c, d) for a, b in zip(ci, ci[1:]) for c, d in zip(cj, cj[1:])]
    known, final, stats = refine_lattice(known, blocks, evaluate, _split_cells)
    filled = fill_blocks(known, final)
    corner = {ij: rows[(b[0], b[2])] for b in final for ij in fill_blocks(known, [b])}
    computed = len(rows)
    for i, j in filled:
        rows[(i, j)] = dict(corner[(i, j)], x=float(xs[i]), y=float(ys[j]), periods=None)
    return rows, filled, computed, [len(first), *stats["points_per_round"]]


def _check_filled(cells, rows: dict, filled, nx: int, ny: int, check_every: int) -> dict:
    """Every ``check_every``-th row of y computed in full by ``cells`` and its filled cells
    compared with their computed values (the ``check`` statistics of
    :func:`adaptive_claims_map`; 0: no check)."""
    check = {"every": check_every, "rows": 0, "cells": 0, "filled": 0, "differences": 0, "label_differences": 0}
    if check_every:
        check_rows = list(range(0, ny, check_every))
        todo = [(i, j) for j in check_rows for i in range(nx) if (i, j) in filled]
        fresh = cells(todo)
        check.update(rows=len(check_rows), cells=len(check_rows) * nx, filled=len(todo))
        for ij, r in zip(todo, fresh):
            check["differences"] += _cell_key(r) != _cell_key(rows[ij])
            check["label_differences"] += _map_label(r) != _map_label(rows[ij])
        check["share"] = check["differences"] / check["cells"] if check["cells"] else 0.0
    return check


# Columns of the refined points' record: the map's, then the refinement level of the point
# (0: the uniform grid, n: added at the n-th halving).
REFINED_COLUMNS = [*MAP_COLUMNS, "level"]
# Coordinates of refined points rounded to this many decimals, as refine_grid's midpoints: the
# same value however it is reached (the motion next to a bifurcation changes with the last bit).
COORD_DECIMALS = 12
# Most halvings allowed: 2^6 = 64 points per grid step per axis is far below any step the
# workflow's maps need and bounds the lattice indices.
MAX_LEVELS = 6


def _true(v) -> bool:
    """A claim flag from a row (bool, or the CSV record's "true"/"false")."""
    return v is True or str(v).lower() == "true"


def _map_label(row: dict) -> str:
    """A map point's label: ``np`` when Algorithm No. 2 did not settle (regime nonperiodic),
    otherwise ``both``, ``a``, ``b`` or ``neither`` (which of the paper's claims hold).
    Accepts rows of :func:`claims_map` or of its CSV record."""
    if row["regime"] == "nonperiodic":
        return "np"
    a, b = _true(row["claim_a"]), _true(row["claim_b"])
    return "both" if a and b else "a" if a else "b" if b else "neither"


def _axis_value(start: float, stop: float, points: int, scale: int, k: int) -> float:
    """Value at lattice index ``k`` of an axis of ``points`` grid values, ``scale`` lattice
    steps per grid step."""
    return round(start + k * (stop - start) / ((points - 1) * scale), COORD_DECIMALS)


def _check_axes(x: str, x_axis: tuple, y: str, y_axis: tuple) -> None:
    """Raises ValueError unless the map's two parameters differ and each axis is a grid."""
    if x == y:
        raise ValueError(f"`y` = {y!r} is not allowed: must differ from `x`")
    _check_axis("x", *x_axis)
    _check_axis("y", *y_axis)


def _check_axis(name: str, start, stop, points) -> None:
    if not (isinstance(points, int) and points >= 2):
        raise ValueError(f"`{name}_points` = {points!r} is not allowed: must be an integer >= 2")
    if not (float(stop) > float(start)):
        raise ValueError(f"`{name}_stop` = {stop!r} is not allowed: must exceed `{name}_start` = {start!r}")


def _lattice_labels(base: Sequence[dict], x_axis: tuple, y_axis: tuple, s: int) -> dict[tuple[int, int], str]:
    """The uniform grid's labels by lattice index (grid index times ``s``, the finest level's
    points per grid step), every grid point once."""
    (x0, x1, nx), (y0, y1, ny) = x_axis, y_axis
    dx, dy = (x1 - x0) / (nx - 1), (y1 - y0) / (ny - 1)
    label: dict[tuple[int, int], str] = {}
    for r in base:
        i, j = round((float(r["x"]) - x0) / dx), round((float(r["y"]) - y0) / dy)
        off = max(abs(float(r["x"]) - (x0 + i * dx)) / dx, abs(float(r["y"]) - (y0 + j * dy)) / dy)
        if not (0 <= i < nx and 0 <= j < ny) or off > 1e-6:
            raise ValueError(f"`base` point ({r['x']}, {r['y']}) is not allowed: not on the {nx} x {ny} grid")
        label[(i * s, j * s)] = _map_label(r)
    if len(label) != nx * ny:
        raise ValueError(f"`base` has {len(label)} distinct grid points: must have all {nx} x {ny}")
    return label


def refine_claims_map(
    p,
    x: str,
    x_axis: tuple[float, float, int],
    y: str,
    y_axis: tuple[float, float, int],
    *,
    levels: int,
    gap_tol: float,
    settings,
    base: Sequence[dict] | None = None,
    workers: int = 1,
) -> tuple[list[dict], dict]:
    """Refines a uniform map of both claims where its labels change or a point does not settle.

    Parameters
    ----------
    p : Parameters
        The others as stated.
    x, y : str
        The map's parameters.
    x_axis, y_axis : (start, stop, points)
        The uniform grid (``numpy.linspace(start, stop, points)`` per axis).
    levels : int
        Halvings of the grid step at most (0 to :data:`MAX_LEVELS`); the floor is the step / 2^levels.
    gap_tol : float
        Algorithm No. 1's tolerance (:func:`claims_cells`).
    settings : SweepSettings
        The compiled batch's settings for the new points (those of the grid).
    base : sequence of dict, optional
        The uniform grid's rows (from :func:`claims_map`, :func:`adaptive_claims_map` or
        their CSV record, any order); computed here when not given.
    workers : int
        Processes of each level's batch (:func:`claims_cells`).

    Returns
    -------
    rows : list of dict
        The points added by the refinement only (:data:`REFINED_COLUMNS`, ``level`` >= 1),
        sorted by (y, x).
    stats : dict
        ``levels``, ``grid_points``, ``refined_points``, ``points_per_level`` (added at each
        level), ``cells_split_per_level``, ``x_step``, ``y_step``, ``x_floor``, ``y_floor``.
    """
    if not (isinstance(levels, int) and not isinstance(levels, bool) and 0 <= levels <= MAX_LEVELS):
        raise ValueError(f"`levels` = {levels!r} is not allowed: must be an integer in [0, {MAX_LEVELS}]")
    _check_axes(x, x_axis, y, y_axis)
    (x0, x1, nx), (y0, y1, ny) = x_axis, y_axis
    s = 2**levels
    dx, dy = (x1 - x0) / (nx - 1), (y1 - y0) / (ny - 1)
    if base is None:
        base = claims_map(p, x, np.linspace(x0, x1, nx), y, np.linspace(y0, y1, ny), gap_tol=gap_tol, settings=settings)
    label = _lattice_labels(base, x_axis, y_axis, s)
    blocks = [(i * s, (i + 1) * s, j * s, (j + 1) * s) for j in range(ny - 1) for i in range(nx - 1)]

    def cells(points: list[tuple[int, int]]) -> list[dict]:
        pts = [(_axis_value(x0, x1, nx, s, i), _axis_value(y0, y1, ny, s, j)) for i, j in points]
        return claims_cells(p, x, y, pts, gap_tol=gap_tol, settings=settings, workers=workers)

    added, per_level, split_per_level = _refine_levels(cells, label, blocks, levels)
    stats = {
        "levels": levels,
        "grid_points": nx * ny,
        "refined_points": len(added),
        "points_per_level": per_level,
        "cells_split_per_level": split_per_level,
        "x_step": dx,
        "y_step": dy,
        "x_floor": dx / s,
        "y_floor": dy / s,
    }
    return added, stats


def _refine_levels(cells, label: dict, blocks: list, levels: int) -> tuple[list[dict], list[int], list[int]]:
    """Halves the lattice blocks whose corner labels differ or include ``np``, at most ``levels``
    times, the new points computed by ``cells``.

    Returns the added rows (with their ``level``, sorted by (y, x)), the points added and the
    blocks split at each level (every level listed, those where nothing was split too)."""
    added: list[dict] = []
    per_level: list[int] = []

    def evaluate(points: list[tuple[int, int]]) -> list[str]:
        rows = cells(points)
        level = len(per_level) + 1
        per_level.append(len(points))
        added.extend(dict(r, level=level) for r in rows)
        return [_map_label(r) for r in rows]

    _, _, rounds = refine_lattice(
        label, blocks, evaluate, lambda labels: len(set(labels)) > 1 or "np" in labels, max_rounds=levels
    )
    per_level += [0] * (levels - len(per_level))
    split_per_level = rounds["blocks_split_per_round"] + [0] * (levels - len(rounds["blocks_split_per_round"]))
    added.sort(key=lambda r: (r["y"], r["x"]))
    return added, per_level, split_per_level
