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

__all__ = ["parameters", "tolerances", "steady_options", "sweep_settings", "located_gap", "chunk_indices"]


def parameters(d: dict) -> Parameters:
    """Parameters from a config-like dict holding every relative parameter (other keys are
    ignored)."""
    return Parameters(**{name: float(d[name]) for name in Parameters.names()})


def tolerances(solver: dict) -> Tolerances:
    """The event tolerances of the config's ``solver`` section."""
    return Tolerances(gap_tol=float(solver["gap_tol"]), chatter_tol=float(solver["chatter_tol"]))


def steady_options(solver: dict) -> dict:
    """Keyword arguments of :func:`impactdamper.steady_state` from the config's ``solver``."""
    return {"tolerances": tolerances(solver), "settle_tol": float(solver["settle_tol"]),
            "max_periods": int(solver["max_periods"]), "max_period_multiple": int(solver["max_period_multiple"])}


def sweep_settings(section: dict, solver: dict, **changes):
    """:class:`impactdamper.analysis.sweeps.SweepSettings` from a ``sweep:`` or ``maps:``
    config section and the ``solver:`` one (``changes`` override single fields)."""
    from impactdamper.analysis.settled import SweepSettings

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
