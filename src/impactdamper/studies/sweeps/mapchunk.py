"""One chunk of a two-parameter regime map (Peterka-style), computed where its labels change and
checked against the brute force on some of its rows.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100. A map has Delta0/x_st on
one axis and a second parameter (theta = omega/omega1, or the damping ratio delta = delta1 =
delta2) on the other (:func:`impactdamper.studies.sweeps.gapsweep.map_axes`). For each value of
the second parameter the gap is swept one way (``maps.direction``), each cell from its left
neighbour's settled motion (Algorithm No. 2 with the stroboscopic period test; the Newton
rescue of cells that do not settle only with ``maps.rescue``), computed where the labels change
(:func:`impactdamper.analysis.adaptive.adaptive_regime_map`). Some of the chunk's rows are swept
cell by cell as well, the brute force (the same call with ``brute_force=True``), and the two compared
(:func:`impactdamper.analysis.adaptive.label_differences`).

The rows are dealt to ``maps.chunks`` chunks in turn (:func:`chunk_rows`: the costly rows near
resonance lie together), so that a map runs as independent jobs, locally or on a cluster.
"""

from __future__ import annotations

import numpy as np

from impactdamper.analysis.adaptive import adaptive_regime_map, label_differences
from impactdamper.reporting.records import Timer
from impactdamper.studies.config import parameters, sweep_settings
from impactdamper.studies.sweeps.gapsweep import SETTLED_COLUMNS, map_axes, regime_of_label

__all__ = ["CHUNK_COLUMNS", "check_rows", "regime_map_chunk"]

# A chunk's record, one row per cell (``computed`` false where the cell was filled).
CHUNK_COLUMNS = ["i", "j", "slow", "gap", *SETTLED_COLUMNS, "fallback", "computed"]


def _chunk_rows(rows: int, chunks: int, chunk: int) -> np.ndarray:
    """The rows of chunk ``chunk``: ``chunk``, ``chunk + chunks``, ... (dealt in turn)."""
    if not (0 <= chunk < chunks):
        raise ValueError(f"`chunk` = {chunk!r} is not allowed: must be in [0, {chunks})")
    return np.arange(chunk, rows, chunks)


def check_rows(rows: int, check_every: int, chunks: int) -> list[int]:
    """Positions among a chunk's ``rows`` rows that the brute force sweeps too: every
    ``check_every / chunks``-th, so that chunk c checks the map's rows c, c + check_every, ...
    (where ``chunks`` divides ``check_every``), every chunk alike; none with ``check_every`` 0."""
    return list(range(0, rows, max(1, check_every // chunks))) if check_every else []


def regime_map_chunk(
    reference: dict, solver: dict, maps: dict, name: str, chunk: int, log=None
) -> tuple[list[dict], dict, Timer]:
    """Chunk ``chunk`` of the regime map ``name`` (config ``maps``), and its brute-force check.

    Returns
    -------
    rows : list of dict
        One per cell (:data:`CHUNK_COLUMNS`).
    counts : dict
        The chunk's cells computed, settlings, rounds, fallbacks by reason, the check against the
        brute force (cells that differ, their distances to a label change, its rows and
        processor time) and the periods simulated.
    timer : Timer
        The adaptive map's wall and processor time (the check's is in ``counts``).
    """
    base = parameters(reference)
    settings = sweep_settings(maps, solver, continuation=False, rescue=bool(maps["rescue"]))
    slow, slow_values, gaps = map_axes(maps, name)
    rows_idx = _chunk_rows(len(slow_values), int(maps["chunks"]), chunk)
    check_idx = check_rows(len(rows_idx), int(maps["check_every"]), int(maps["chunks"]))
    with Timer() as timer:
        m = adaptive_regime_map(
            base,
            "gap",
            gaps,
            slow,
            slow_values[rows_idx],
            direction=maps["direction"],
            settings=settings,
            coarse_step=int(maps["coarse_step"]),
        )
    labels = m.label
    if log is not None:
        log.info(
            "map %s chunk %d: %d rows, %d of %d cells computed (%d settlings in %d rounds), %.1f s",
            name,
            chunk,
            len(rows_idx),
            int(m.computed.sum()),
            m.computed.size,
            m.settlings,
            len(m.points_per_round),
            timer.wall,
        )
    check = _brute_force_check(
        base, settings, maps, name, chunk, (gaps, slow, slow_values), rows_idx, check_idx, m, labels, log
    )
    return _cell_rows(m, labels, rows_idx, slow_values), _counts(m, name, chunk, rows_idx, settings, check), timer


def _brute_force_check(
    base, settings, maps: dict, name: str, chunk: int, axes: tuple, rows_idx, check_idx, m, labels, log
) -> dict:
    """The chunk's rows ``check_idx`` swept cell by cell (the brute force) and their labels
    compared with the adaptive map ``m``'s ``labels`` (:func:`~impactdamper.analysis.adaptive.label_differences`),
    with the check's rows (of the map) and processor time."""
    gaps, slow, slow_values = axes
    with Timer() as check_timer:
        brute = adaptive_regime_map(
            base,
            "gap",
            gaps,
            slow,
            slow_values[rows_idx[check_idx]],
            direction=maps["direction"],
            settings=settings,
            brute_force=True,
        )
    reference_labels = labels.copy()
    reference_labels[check_idx] = brute.label
    check = label_differences(labels, reference_labels, rows=check_idx, computed=m.computed)
    check.update(rows=[int(rows_idx[n]) for n in check_idx], cpu_s=check_timer.cpu)
    if log is not None:
        log.info(
            "map %s chunk %d: brute force on rows %s: %d of %d cells differ (distances to a change %s), %.1f s",
            name,
            chunk,
            check["rows"],
            check["differences"],
            check["cells"],
            check["distances"],
            check_timer.wall,
        )
    return check


def _cell_rows(m, labels, rows_idx, slow_values) -> list[dict]:
    """The chunk's record, one row per cell of the adaptive map ``m`` with its ``labels``
    (:data:`CHUNK_COLUMNS`)."""
    return [
        {
            "i": int(i),
            "j": j,
            "slow": float(slow_values[i]),
            "gap": float(gap),
            "label": labels[n, j],
            "regime": regime_of_label(labels[n, j]),
            "k": int(m.period_multiple[n, j]),
            "z": int(m.impacts_per_cycle[n, j]),
            "x1_max": float(m.x1_max[n, j]),
            "method": m.method[n, j],
            "periods": int(m.periods[n, j]),
            "fallback": m.fallback[n, j],
            "computed": bool(m.computed[n, j]),
        }
        for n, i in enumerate(rows_idx)
        for j, gap in enumerate(m.fast_values)
    ]


def _counts(m, name: str, chunk: int, rows_idx, settings, check: dict) -> dict:
    """The chunk's counts (:func:`regime_map_chunk`'s ``counts``)."""
    return {
        "map": name,
        "chunk": chunk,
        "rows": len(rows_idx),
        "cells": int(m.computed.size),
        "computed": int(m.computed.sum()),
        "settlings": m.settlings,
        "points_per_round": m.points_per_round,
        "coarse_step": m.coarse_step,
        "rescue": settings.rescue,
        "fallbacks": m.fallbacks,
        "check": check,
        "periods_simulated": int(m.periods.sum()),
    }
