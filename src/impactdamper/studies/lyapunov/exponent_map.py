"""The largest Lyapunov exponent over a plane of a regime map: Delta0/x_st against theta.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100. The plane of the sweeps
stage's theta map, on a grid of its own: each row (one value of the second parameter) sweeps
the gap upward, each cell settled from its neighbour's section by the many-point call
(:func:`impactdamper.analysis.batch.steady_states`, no accelerators, the Newton rescue of the
cells that do not settle within the caps) with ``SweepSettings(classify=True)``: a cell left
nonperiodic after the rescue is labelled by its Lyapunov spectrum from its own section (the
labelling run). Every other cell gets its largest exponent from a short spectrum run from its
settled section (no transient: the section is on the settled cycle).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactdamper.analysis.batch import BATCH_REGIMES, steady_states
from impactdamper.analysis.lyapunov import spectrum_from_section
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.sweeps import with_value
from impactdamper.core.events import SearchLimitError
from impactdamper.core.parameters import Parameters
from impactdamper.studies.lyapunov.sweep import RunLengths

__all__ = ["COLUMNS", "map_axes", "map_rows"]

COLUMNS = ["i", "j", "slow", "gap", "label", "regime", "motion", "exponent", "error", "periods", "fallback"]
NONPERIODIC = BATCH_REGIMES.index("nonperiodic")


def map_axes(section: dict) -> tuple[str, np.ndarray, np.ndarray]:
    """(second parameter, its values, the gap values) of the config's ``lyapunov.map``."""
    return (
        section["parameter"],
        np.linspace(float(section["start"]), float(section["stop"]), int(section["points"])),
        np.linspace(float(section["gap_start"]), float(section["gap_stop"]), int(section["gap_points"])),
    )


def map_rows(
    base: Parameters,
    slow: str,
    slow_values,
    gaps: np.ndarray,
    indices,
    settings: SweepSettings,
    run: RunLengths,
    backend: str = "auto",
    say=None,
) -> list[dict]:
    """The map's rows ``indices`` (into ``slow_values``): one table row per cell, in (i, j)
    order. ``settings``: how a cell settles (its ``classify`` and ``classify_periods`` are set
    here from ``run``)."""
    settings = dataclasses.replace(settings, classify=True, classify_periods=run.classify_periods)
    out = []
    for n, i in enumerate(indices):
        values = np.column_stack([gaps, np.full(len(gaps), float(slow_values[i]))])
        res = steady_states(base, ("gap", slow), values, settings=settings, backend=backend)
        for j, gap in enumerate(gaps):
            row = {
                "i": int(i),
                "j": j,
                "slow": float(slow_values[i]),
                "gap": float(gap),
                "label": res.label[j],
                "regime": res.regime[j],
                "motion": res.lyapunov_label[j],
                "exponent": float(res.lyapunov_exponent[j]),
                "error": float(res.lyapunov_error[j]),
                "periods": run.classify_periods if res.regime_code[j] == NONPERIODIC else run.periods,
                "fallback": res.fallback[j],
            }
            if res.regime_code[j] != NONPERIODIC and res.regime[j] != "failed":
                p = with_value(with_value(base, "gap", float(gap)), slow, float(slow_values[i]))
                try:
                    s = spectrum_from_section(
                        p,
                        res.sections[j],
                        warmup=run.warmup,
                        periods=run.periods,
                        tolerances=settings.tolerances,
                        backend=backend,
                    )
                    row["exponent"], row["error"] = float(s.exponents[0]), float(s.errors[0])
                except SearchLimitError:
                    row["fallback"] = "work bound"
            out.append(row)
        if say:
            say(f"row {n + 1} of {len(indices)} ({slow} = {float(slow_values[i]):.6g})")
    return out
