"""The paper's Fig. 2 claims over two parameters (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100): claim (a), Algorithm No. 1's gap negative on (t1, t2);
claim (b), Algorithm No. 2 settles with T_c = 2T and three impacts per cycle; maps of both and
their adaptive refinement.

The map starts as a uniform grid (:func:`claims_map`). A cell (the
square between four neighbouring grid points) whose corners do not all carry the same label
(:func:`map_label`: both claims, (a) only, (b) only, neither; or ``np`` when Algorithm No. 2
did not settle) is split in four: its edge midpoints and its centre are evaluated (one batch
call per level), a quadtree subdivision, at most ``levels`` times; the floor, the finest step,
is the grid step / 2^levels. The same spirit as the one-parameter refinement
(:func:`impactdamper.studies.claims.search.refine_grid`): a window wider than the floor that touches a
grid point, or sits between points of different labels, is resolved to the floor; a window
inside a cell whose four corners agree is not (nothing there asks for refinement).
"""

from __future__ import annotations

from collections.abc import Sequence

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


def claims_map(p, x: str, xs: Sequence[float], y: str, ys: Sequence[float], *, gap_tol: float, settings) -> list[dict]:
    """Both claims at every cell of the grid ``xs`` x ``ys`` of parameters ``x`` and ``y`` (the
    others as in ``p``): Algorithm No. 1 (closed form, ``gap_tol``) and Algorithm No. 2 from the
    paper's step 1 on the compiled batch (:func:`impactdamper.steady_states`, each
    cell alone, ``settings``), in one call for all cells.

    Returns
    -------
    list of dict
        One per cell, rows of y outer, x inner, with :data:`MAP_COLUMNS`.
    """
    if x == y:
        raise ValueError(f"`y` = {y!r} is not allowed: must differ from `x`")
    return claims_cells(p, x, y, [(float(a), float(b)) for b in ys for a in xs], gap_tol=gap_tol, settings=settings)


def claims_cells(p, x: str, y: str, points: Sequence[tuple[float, float]], *, gap_tol: float, settings) -> list[dict]:
    """Both claims at each point ``(x value, y value)`` of ``points`` (any set, in the given
    order), as :func:`claims_map` computes them at its cells (one batch call for all points).

    Returns
    -------
    list of dict
        One per point, with :data:`MAP_COLUMNS`.
    """
    import numpy as np

    from impactdamper import steady_states

    if x == y:
        raise ValueError(f"`y` = {y!r} is not allowed: must differ from `x`")
    if not len(points):
        return []
    cells = np.array(points, float).reshape(-1, 2)
    res = steady_states(p, (x, y), cells, settings=settings, chain=False)
    out = []
    for i, (a, b) in enumerate(cells):
        alg1 = algorithm1(p.replace(**{x: float(a), y: float(b)}), gap_tol=gap_tol)
        ca = claim_a(alg1)
        rg, k, z = str(res.regime[i]), int(res.period_multiple[i]), int(res.impacts_per_cycle[i])
        cb = rg == "multi_impact" and k == CLAIM_B_PERIOD_MULTIPLE and z == CLAIM_B_IMPACTS
        out.append(
            {
                "x": float(a),
                "y": float(b),
                "claim_a": ca,
                "claim_b": cb,
                "both": ca and cb,
                "alg1_exists": bool(alg1.exists),
                "regime": rg,
                "period_multiple": k,
                "impacts_per_cycle": z,
                "periods": int(res.periods[i]),
                "label": str(res.label[i]),
            }
        )
    return out


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


def map_label(row: dict) -> str:
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
        label[(i * s, j * s)] = map_label(r)
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
        The uniform grid's rows (from :func:`claims_map` or its CSV
        record, any order); computed here when not given.

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
    if x == y:
        raise ValueError(f"`y` = {y!r} is not allowed: must differ from `x`")
    (x0, x1, nx), (y0, y1, ny) = x_axis, y_axis
    _check_axis("x", x0, x1, nx)
    _check_axis("y", y0, y1, ny)
    s = 2**levels
    dx, dy = (x1 - x0) / (nx - 1), (y1 - y0) / (ny - 1)
    if base is None:
        import numpy as np

        base = claims_map(p, x, np.linspace(x0, x1, nx), y, np.linspace(y0, y1, ny), gap_tol=gap_tol, settings=settings)
    label = _lattice_labels(base, x_axis, y_axis, s)
    cells = [(i * s, j * s) for j in range(ny - 1) for i in range(nx - 1)]
    added: list[dict] = []
    per_level, split_per_level = [], []
    for level in range(1, levels + 1):
        h = s >> (level - 1)
        half = h // 2
        split = [
            (i, j)
            for i, j in cells
            if len({label[(i, j)], label[(i + h, j)], label[(i, j + h)], label[(i + h, j + h)]}) > 1
            or "np" in (label[(i, j)], label[(i + h, j)], label[(i, j + h)], label[(i + h, j + h)])
        ]
        new = sorted(
            {
                (i + di, j + dj)
                for i, j in split
                for di, dj in ((half, 0), (0, half), (half, h), (h, half), (half, half))
                if (i + di, j + dj) not in label
            },
            key=lambda k: (k[1], k[0]),
        )
        pts = [(_axis_value(x0, x1, nx, s, i), _axis_value(y0, y1, ny, s, j)) for i, j in new]
        rows = claims_cells(p, x, y, pts, gap_tol=gap_tol, settings=settings)
        for k, r in zip(new, rows):
            label[k] = map_label(r)
            added.append(dict(r, level=level))
        per_level.append(len(new))
        split_per_level.append(len(split))
        cells = [(i + di, j + dj) for i, j in split for di in (0, half) for dj in (0, half)]
    added.sort(key=lambda r: (r["y"], r["x"]))
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
