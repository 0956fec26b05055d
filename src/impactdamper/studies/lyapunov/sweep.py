"""The largest Lyapunov exponent along the gap sweep, and the labels of its nonperiodic points.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the gap sweep (the sweeps
stage's table, each point started from its neighbour's settled section) labels a point ``np``
where its run has not settled within the cap of periods. Here each point of that table is run
again from its own start state (the table's x1_0, x2_0, v1_0, v2_0: the state the sweep's run
for the point started from, at the forcing's phase 0), so that it follows the motion the sweep
followed, and its Lyapunov spectrum is computed by the exact tangent map
(:func:`impactdamper.analysis.lyapunov.lyapunov_spectrum`) after a transient: a short run for
every point (the exponent panel under the bifurcation diagram) and, for a point the sweep
called ``np``, a run long enough to label it (:data:`impactdamper.analysis.lyapunov.LABELS`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactdamper.analysis.lyapunov import DEFAULT_BLOCKS, LyapunovSpectrum, lyapunov_spectrum
from impactdamper.core.events import SearchLimitError
from impactdamper.core.parameters import Parameters
from impactdamper.core.validation import Tolerances

__all__ = ["RunLengths", "COLUMNS", "NP", "start_state", "sweep_exponents"]

# The sweep table's label of a point that did not settle within the cap.
NP = "np"
# The columns of the exponents' table (one row per sweep point, in the sweep table's order).
COLUMNS = [
    "direction",
    "index",
    "value",
    "label",
    "motion",
    "exponent",
    "error",
    "exponent2",
    "error2",
    "dimension",
    "periods",
    "impacts_per_period",
    "backend",
    "fallback",
    "half1",
    "half2",
    "half_error",
    "settled_period",
    "settled_since",
]


@dataclass(frozen=True)
class RunLengths:
    """Forcing periods of a point's spectrum run: the motion's ``transient``, then the walk's
    ``warmup`` and the ``periods`` averaged (for every point), or ``classify_periods`` after
    ``classify_warmup`` (for a point to label)."""

    transient: int
    warmup: int
    periods: int
    classify_warmup: int
    classify_periods: int

    @classmethod
    def from_config(cls, section: dict) -> RunLengths:
        return cls(
            *(int(section[k]) for k in ("transient", "warmup", "periods", "classify_warmup", "classify_periods"))
        )


def start_state(p: Parameters, row: dict) -> np.ndarray:
    """A sweep row's start state (x1, x2, x1', x2'), m and m/s, read from its 12 significant
    digits: a start on the stop may come out with its gap -1e-12 x_st (the sweep's own run starts
    on the stop exactly), so x2 is put back on the stop where the gap is negative, as the sweep's
    carry of a neighbour's section does."""
    y = np.array([float(row[c]) for c in ("x1_0", "x2_0", "v1_0", "v2_0")])
    if p.Delta0 - (y[1] - y[0]) < 0.0:
        y[1] = y[0] + p.Delta0
    return y


def _spectrum_row(row: dict, s: LyapunovSpectrum, label: bool) -> dict:
    """One row of the exponents' table from a sweep row and its spectrum (``label``: its motion
    is labelled, else ""): with the largest exponent over each half of the window (and the
    halves' pooled error), and the cycle k T the motion settled onto by the window's end and the
    period it did so from, counted from the run's start ("" if not)."""
    halves, half_errors = s.halves
    settled = s.settled or ("", "")
    return {
        "direction": row["direction"],
        "index": int(row["index"]),
        "value": float(row["value"]),
        "label": row["label"],
        "motion": s.label if label else "",
        "exponent": float(s.exponents[0]),
        "error": float(s.errors[0]),
        "exponent2": float(s.exponents[1]),
        "error2": float(s.errors[1]),
        "dimension": int(s.dimension),
        "periods": int(s.periods),
        "impacts_per_period": s.impacts / s.periods,
        "backend": s.backend,
        "fallback": s.fallback,
        "half1": float(halves[0]),
        "half2": float(halves[1]),
        "half_error": float(half_errors[0]),
        "settled_period": settled[0],
        "settled_since": settled[1],
    }


def sweep_exponents(
    base: Parameters, rows: list[dict], run: RunLengths, tolerances: Tolerances, backend: str = "auto", say=None
) -> list[dict]:
    """The exponents' table of sweep rows (``rows``: the sweep table's rows, read as text, its
    swept parameter the gap): each point's spectrum from its start state at t0 = 0, the ``np``
    points with the labelling run; a point whose run reaches the solver's work bound has no
    exponent (nan, its fallback column says why). ``say``: a function of one progress line."""
    out = []
    for n, row in enumerate(rows):
        p = base.replace(gap=float(row["value"]))
        label = row["label"] == NP
        warmup, periods = (run.classify_warmup, run.classify_periods) if label else (run.warmup, run.periods)
        try:
            s = lyapunov_spectrum(
                p,
                state=start_state(p, row),
                transient=run.transient,
                warmup=warmup,
                periods=periods,
                blocks=DEFAULT_BLOCKS,
                tolerances=tolerances,
                backend=backend,
            )
        except SearchLimitError:
            out.append({**dict.fromkeys(COLUMNS, ""), **{k: row[k] for k in ("direction", "index", "value", "label")}})
            out[-1].update(exponent=np.nan, error=np.nan, exponent2=np.nan, error2=np.nan, fallback="work bound")
            continue
        out.append(_spectrum_row(row, s, label))
        if say and (n + 1) % 200 == 0:
            say(f"{n + 1} of {len(rows)} sweep points")
    return out
