"""The work a workflow config's grids imply, bounded: step 5 of
:mod:`impactdamper.studies.config_check`.

Each grid is counted by the points, cells or runs it makes (not by its raw key: a step of 1e-9
makes as many points as points: 1e9) and refused above its bound (:func:`too_large`).
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from impactdamper.analysis.response import MAX_POINTS
from impactdamper.core.simulate import MAX_SIMULATE_PERIODS
from impactdamper.studies.config_reading import Problem

__all__ = [
    "grid_sizes",
    "too_large",
    "claims_maps",
    "MAX_LINE_POINTS",
    "MAX_CLOSED_FORM_POINTS",
    "MAX_MAP_CELLS",
    "MAX_SETTLED_POINTS",
    "MAX_STEPS",
    "MAX_REPEATS",
]

# Bounds on the points a grid implies (not on its raw key: a step of 1e-9 makes as many points
# as points: 1e9). Each is several times the full config's largest such grid, so that a finer
# study fits, and well below what would run for days or exhaust memory; a library limit where
# the job has one (the theta grids' MAX_POINTS, simulate's MAX_SIMULATE_PERIODS).
MAX_LINE_POINTS = 10_000  # settled motions along one line (full config: 1001 sweep values, 2004 random starts)
MAX_CLOSED_FORM_POINTS = 1_000_000  # Algorithm No. 1 values (closed form; full config: 2001) or linear curves
MAX_MAP_CELLS = 1_000_000  # cells of a regime map, by the compiled batch (full config: 400 x 400)
# Settled motions of a grid in two or more parameters, each run on its own (a claims map's cells
# to 1000 periods each, a design chart's, the nearest set's ray points; full config: 9552 ray points).
MAX_SETTLED_POINTS = 100_000
MAX_STEPS = 100_000_000  # a fixed-step run's steps (full config: 2e6)
MAX_REPEATS = 1_000  # timed repeats of one measurement (full config: 15)


def claims_maps(config: dict) -> Iterator[tuple[tuple, dict]]:
    """(path, section) of the claims map and of every pair map."""
    search = config.get("claims_search", {})
    if isinstance(search.get("map"), dict):
        yield ("claims_search", "map"), search["map"]
    for name, section in search.get("pair_maps", {}).items():
        if isinstance(section, dict):
            yield ("claims_search", "pair_maps", name), section


def _steps(start: float, stop: float, step: float) -> float:
    """Points of a grid from ``start`` to ``stop`` in steps of ``step`` (both ends included)."""
    return math.floor((stop - start) / step + 1e-9) + 1


def _key(section: dict, path: tuple, limit: int, what: str, count=None) -> tuple:
    """A grid set by one key: (path, its value, the points it implies (the value itself by
    default), limit, what)."""
    value = section[path[-1]]
    return path, repr(value), value if count is None else count, limit, what


def _product(path: tuple, names: str, counts: tuple, limit: int, what: str) -> tuple:
    """A grid of several keys' product: (path of their section, "a x b = 3 x 4", product, ...)."""
    shown = f"{names} = {' x '.join(str(c) for c in counts)}"
    return path, shown, math.prod(counts), limit, what


def grid_sizes(config: dict) -> list[tuple[tuple, str, float, int, str]]:
    """Every grid of a (schema-valid, defaults filled) config with the points it implies.

    Returns
    -------
    list of (path, shown, count, limit, what): the key that sets the grid (its path in the
    config; a section's for a product of keys) and its value as a message shows it (``1e-09``,
    ``points x gap_points = 400 x 400``), the number of points, cells or runs it implies, the
    most allowed, and what they are.
    """
    grids = []
    v = config.get("verdict")
    if v:
        scan = "gap values from gap_min to gap_max"
        for key, limit, what in (
            ("gap_step", MAX_LINE_POINTS, "Algorithm No. 2"),
            ("alg1_gap_step", MAX_CLOSED_FORM_POINTS, "Algorithm No. 1"),
        ):
            grids.append(_key(v, ("verdict", key), limit, f"{what} {scan}", _steps(v["gap_min"], v["gap_max"], v[key])))
        grids.append(
            _key(v, ("verdict", "R_step"), MAX_LINE_POINTS, "R values in [0, 1]", _steps(0.0, 1.0, v["R_step"]))
        )
        grids.append(_key(v, ("verdict", "random_states"), MAX_LINE_POINTS, "runs from random states"))
    s = config.get("sweep")
    if s:
        grids.append(_key(s, ("sweep", "points"), MAX_LINE_POINTS, "sweep values"))
        counts = (-(-s["points"] // s["random_every"]), s["random_starts"])
        grids.append(
            _product(
                ("sweep",), "ceil(points / random_every) x random_starts", counts, MAX_LINE_POINTS, "random starts"
            )
        )
    for name, m in config.get("maps", {}).items():
        if isinstance(m, dict):
            counts = (m["points"], m["gap_points"])
            grids.append(_product(("maps", name), "points x gap_points", counts, MAX_MAP_CELLS, "map cells"))
            grids.append(_key(m, ("maps", name, "points"), MAX_LINE_POINTS, "map rows"))
            grids.append(_key(m, ("maps", name, "gap_points"), MAX_LINE_POINTS, "map columns"))
    search = config.get("claims_search", {})
    for name, r in search.get("parameters", {}).items():
        path = ("claims_search", "parameters", name)
        grids.append(_key(r, path + ("points",), MAX_LINE_POINTS, "Algorithm No. 2 values"))
        grids.append(_key(r, path + ("alg1_points",), MAX_CLOSED_FORM_POINTS, "Algorithm No. 1 values"))
    for path, m in claims_maps(config):
        counts = (m["x_points"], m["y_points"])
        grids.append(_product(path, "x_points x y_points", counts, MAX_SETTLED_POINTS, "map cells"))
        grids.append(_key(m, path + ("x_points",), MAX_LINE_POINTS, "map columns"))
        grids.append(_key(m, path + ("y_points",), MAX_LINE_POINTS, "map rows"))
    near = search.get("nearest")
    if near:
        # The rays: the 14 axes, 84 diagonals and `rays` random directions, each stepped to ray_max.
        counts = (98 + near["rays"], math.ceil(near["ray_max"] / near["ray_step"] - 1e-9))
        path = ("claims_search", "nearest")
        grids.append(_product(path, "(98 + rays) x ceil(ray_max / ray_step)", counts, MAX_SETTLED_POINTS, "ray points"))
        grids.append(_key(near, path + ("ball_points",), MAX_LINE_POINTS, "points on the ball"))
    if config.get("design"):
        grids += _design_grids(config["design"])
    perf = config.get("performance")
    if perf:
        path = ("performance",)
        grids.append(_key(perf, path + ("max_steps",), MAX_STEPS, "steps of a fixed-step run"))
        for i, n in enumerate(perf["growth_periods"]):
            grids.append((path + ("growth_periods", i), repr(n), n, MAX_SIMULATE_PERIODS, "simulated periods"))
        grids.append(_key(perf, path + ("settled_periods",), MAX_SIMULATE_PERIODS, "simulated periods"))
        grids.append(_key(perf, path + ("n_impacts",), MAX_LINE_POINTS, "impacts"))
        for i, n in enumerate(perf["compiled_speed_map_sizes"]):
            grids.append((path + ("compiled_speed_map_sizes", i), repr(n), n * n, MAX_MAP_CELLS, "map cells (n x n)"))
        grids.append(_key(perf, path + ("compiled_speed_batch_points",), MAX_MAP_CELLS, "batch points"))
        repeats = ("repeats", "reference_speed_repeats", "reference_speed_ivp_repeats", "compiled_speed_repeats")
        for key in (*repeats, "compiled_speed_map_repeats"):
            grids.append(_key(perf, path + (key,), MAX_REPEATS, "timed repeats"))
    if config.get("lyapunov"):
        grids += _lyapunov_grids(config["lyapunov"])
    if config.get("orbits"):
        from impactdamper.analysis.continuation import MAX_BRANCH_POINTS

        path = ("orbits", "continuation", "max_points")
        grids.append(_key(config["orbits"]["continuation"], path, MAX_BRANCH_POINTS, "orbits per leg"))
    return grids


def _lyapunov_grids(ly: dict) -> list[tuple[tuple, str, float, int, str]]:
    """The Lyapunov stage's grids (see :func:`grid_sizes`): the map's cells, rows and columns,
    and every run's length (transient, warm-up and averaged periods together, a run's work)."""
    m, path = ly["map"], ("lyapunov",)
    counts = (m["points"], m["gap_points"])
    grids = [
        _product(path + ("map",), "points x gap_points", counts, MAX_MAP_CELLS, "map cells"),
        _key(m, path + ("map", "points"), MAX_LINE_POINTS, "map rows"),
        _key(m, path + ("map", "gap_points"), MAX_LINE_POINTS, "map columns"),
    ]
    for names in (("transient", "warmup", "periods"), ("transient", "classify_warmup", "classify_periods")):
        counts = [ly[n] for n in names]
        shown = f"{' + '.join(names)} = {' + '.join(str(c) for c in counts)}"
        grids.append((path, shown, sum(counts), MAX_SIMULATE_PERIODS, "periods of a run"))
    grids.append(_key(ly, path + ("speed_repeats",), MAX_REPEATS, "timed repeats"))
    return grids


def _design_grids(d: dict) -> list[tuple[tuple, str, float, int, str]]:
    """The design stage's grids (see :func:`grid_sizes`)."""
    band = "theta values of the band"
    grids = [_key(d, ("design", "response_points"), MAX_POINTS, band)]
    n = math.ceil((d["theta_stop"] - d["theta_start"]) / d["band_step"] - 1e-9) + 1
    grids.append(_key(d, ("design", "band_step"), MAX_POINTS, band, n))
    grids.append(_key(d, ("design", "baseline_points"), MAX_CLOSED_FORM_POINTS, "theta values of the linear curves"))
    grids += [_key(d, ("design", key), MAX_LINE_POINTS, "gap values") for key in ("gap_points", "second_gap_points")]
    counts = (d["gap_points"], n)
    grids.append(_product(("design",), "gap_points x band points", counts, MAX_SETTLED_POINTS, "chart points"))
    counts = (len(d["second_values"]), d["second_gap_points"], n)
    names = "second_values x second_gap_points x band points"
    grids.append(_product(("design",), names, counts, MAX_SETTLED_POINTS, "chart points"))
    keys = ("search_samples", "search_polls", "search_polish", "robust_polls", "robust_polish", "search_checks")
    for key in (*keys, *(k for k in ("subregion_samples", "subregion_polls") if k in d)):
        grids.append(_key(d, ("design", key), MAX_LINE_POINTS, "evaluations"))
    grids.append(_key(d, ("design", "search_starts"), MAX_REPEATS, "searches"))
    grids.append(_key(d, ("design", "benchmark_objects"), MAX_REPEATS, "timed objects", len(d["benchmark_objects"])))
    return grids


def too_large(config: dict) -> Problem | None:
    """The first grid of :func:`grid_sizes` above its bound."""
    for path, shown, count, limit, what in grid_sizes(config):
        if count > limit:
            many = f"{count:.3g}" if count >= 1e12 else f"{int(count)}"
            return path, f": {shown} is not allowed: {many} {what}; at most {limit}"
    return None
