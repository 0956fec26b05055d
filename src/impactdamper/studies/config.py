"""The library's objects from the workflow's config sections.

The config (``config/config.yaml``, validated against ``workflow/schemas``) holds the paper's
relative parameters under ``reference`` and the solver's tolerances under ``solver``; every
stage turns them into :class:`impactdamper.Parameters`, :class:`impactdamper.Tolerances` and
keyword arguments here, once.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from impactdamper import Parameters, Tolerances

__all__ = [
    "parameters",
    "tolerances",
    "steady_options",
    "sweep_settings",
    "located_gap",
    "chunk_indices",
    "config_problem",
    "MAX_CHUNKS",
]

# Most Snakemake jobs one chunked computation may be split into: every chunk is a job of the DAG,
# and building a DAG of 3000 map chunks took 27 s (100000 spun); the stages' largest useful
# split is a few per core of a cluster's allocation.
MAX_CHUNKS = 1000


def parameters(d: dict) -> Parameters:
    """Parameters from a config-like dict holding every relative parameter (other keys are
    ignored)."""
    return Parameters(**{name: float(d[name]) for name in Parameters.names()})


def tolerances(solver: dict) -> Tolerances:
    """The event tolerances of the config's ``solver`` section."""
    return Tolerances(gap_tol=float(solver["gap_tol"]), chatter_tol=float(solver["chatter_tol"]))


def steady_options(solver: dict) -> dict:
    """Keyword arguments of :func:`impactdamper.steady_state` from the config's ``solver``."""
    return {
        "tolerances": tolerances(solver),
        "settle_tol": float(solver["settle_tol"]),
        "max_periods": int(solver["max_periods"]),
        "max_period_multiple": int(solver["max_period_multiple"]),
    }


def sweep_settings(section: dict, solver: dict, **changes):
    """:class:`impactdamper.analysis.sweeps.SweepSettings` from a ``sweep:`` or ``maps:``
    config section and the ``solver:`` one (``changes`` override single fields)."""
    from impactdamper.analysis.point import SweepSettings

    kw = dict(
        settle_tol=float(section["settle_tol"]),
        max_periods=int(section["max_periods"]),
        max_periods_after_nonperiodic=int(section["max_periods_after_nonperiodic"]),
        max_period_multiple=int(section["max_period_multiple"]),
        tolerances=tolerances(solver),
    )
    kw.update(changes)
    return SweepSettings(**kw)


def located_gap(located_json) -> float:
    """The located case's Delta0/x_st from the reference stage (figures/located_case.json)."""
    return float(json.loads(Path(located_json).read_text())["located"]["gap"])


def chunk_indices(n: int, chunks: int, chunk: int) -> np.ndarray:
    """Indices of chunk ``chunk`` of ``chunks`` contiguous, near-equal blocks of range(n)."""
    if not (0 <= chunk < chunks):
        raise ValueError(f"`chunk` = {chunk!r} is not allowed: must be in [0, {chunks})")
    return np.array_split(np.arange(n), chunks)[chunk]


def _parameter_sets(config: dict):
    """(path, changes) of every parameter set the workflow's jobs build from the reference
    case: each searched or swept range's ends, the design stage's values."""
    claims = config.get("claims_search", {})
    for name, rng in claims.get("parameters", {}).items():
        for end in ("start", "stop"):
            yield ("claims_search", "parameters", name, end), {name: rng[end]}
    cmap = claims.get("map")
    if cmap:
        for axis in ("x", "y"):
            for end in (f"{axis}_start", f"{axis}_stop"):
                yield ("claims_search", "map", end), {cmap[axis]: cmap[end]}
    design = config.get("design")
    if design:  # (the system is the reference case's: the schema holds no other parameter there)
        for end in ("theta_start", "theta_stop"):
            yield ("design", end), {"theta": design[end]}
        for value in design.get("second_values", ()):
            yield ("design", "second_values"), {design["second"]: value}
    lmap = config.get("lyapunov", {}).get("map")
    if lmap:
        for end in ("start", "stop"):
            value = lmap[end]
            yield (
                ("lyapunov", "map", end),
                ({"theta": value} if lmap["parameter"] == "theta" else {"delta1": value, "delta2": value}),
            )
    for name, m in config.get("maps", {}).items():
        if isinstance(m, dict):
            for end in ("start", "stop"):
                value = m[end]
                yield (
                    ("maps", name, end),
                    ({"theta": value} if m["parameter"] == "theta" else {"delta1": value, "delta2": value}),
                )


def config_problem(config: dict) -> tuple[tuple, str] | None:
    """The first value of a config (already valid against its schema) that a job would refuse.

    The schema bounds each key alone; the library's own checks bound what they make together:
    the reference case and every parameter set built from it (a searched range's ends, the
    design stage's values: R above 1, theta 0, mu 1e-320 that underflows m2), the solver's and
    the sweeps' settle options, and the chunk counts (at most :data:`MAX_CHUNKS`, and at most the
    rows they split). Each refused here, not in the job, with the library's message.

    Returns
    -------
    (path, message), the key's path in the config and ": <why>", or None if every job would
    accept its values.
    """
    from impactdamper.core.validation import SettleOptions

    reference = config["reference"]
    try:
        parameters(reference)
    except ValueError as err:
        return ("reference",), ": " + str(err)
    for path, changes in _parameter_sets(config):
        try:
            parameters({**reference, **changes})
        except ValueError as err:
            return path, ": " + str(err)
    solver = config.get("solver")
    if solver:
        try:
            SettleOptions(solver["settle_tol"], solver["max_periods"], solver["max_period_multiple"])
        except ValueError as err:
            return ("solver",), ": " + str(err)
        for section in ("sweep", "maps"):
            if section in config:
                try:
                    sweep_settings(config[section], solver)
                except ValueError as err:
                    return (section,), ": " + str(err)
        if "lyapunov" in config:
            try:
                sweep_settings(
                    config["lyapunov"]["map"], solver, classify_periods=config["lyapunov"]["classify_periods"]
                )
            except ValueError as err:
                return ("lyapunov", "map"), ": " + str(err)
    chunked = []
    maps = config.get("maps")
    if maps:
        rows = min((m["points"] for m in maps.values() if isinstance(m, dict)), default=MAX_CHUNKS)
        chunked.append((("maps", "chunks"), maps["chunks"], rows, "rows of the smallest map (its points)"))
    sweep = config.get("sweep")
    if sweep:
        starts = -(-sweep["points"] // sweep["random_every"])
        chunked.append(
            (
                ("sweep", "random_chunks"),
                sweep["random_chunks"],
                starts,
                "sweep points with random starts (points / random_every)",
            )
        )
    lyapunov = config.get("lyapunov")
    if lyapunov:
        chunked.append(
            (("lyapunov", "map", "chunks"), lyapunov["map"]["chunks"], lyapunov["map"]["points"], "map's rows")
        )
        if sweep:
            rows = 2 * sweep["points"]
            chunked.append((("lyapunov", "sweep_chunks"), lyapunov["sweep_chunks"], rows, "sweep's rows (2 points)"))
    for path, chunks, rows, what in chunked:
        if chunks > min(rows, MAX_CHUNKS):
            return path, (
                f": {chunks!r} is not allowed: must be at most {min(rows, MAX_CHUNKS)} (the {what}, "
                f"and at most MAX_CHUNKS = {MAX_CHUNKS}): a chunk beyond that has no rows"
            )
    return None
