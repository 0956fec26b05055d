"""Choosing a suppressor: the linear baselines and the design charts over the gap.

Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100, compute the suppressor's motion
for a given gap; a designer wants the gap (and spring, restitution) that keeps the object's
amplitude lowest over the band of forcing frequencies it will meet. This module sets the
paper's suppressor, over a range of gaps, beside three linear references, each in the closed
form of eq. (10) (:class:`impactdamper.analysis.linear_device.LinearDevice`):

* the bare object (no suppressor): |x1|/x_st = 1/|1 - theta^2 + 2 i delta1 theta|;
* the absorber without a stop: the same mu, N, delta2 (eq. 10 with no contact);
* the optimal linear tuned-mass damper (TMD) of the same mu on the object's own damping
  delta1 (:func:`impactdamper.studies.design.optimum.optimal_tmd`). For delta1 = 0 and an
  unbounded band Den Hartog's closed form holds
  (:func:`impactdamper.analysis.linear_device.den_hartog`); it checks the design search.

The design chart (:func:`gap_chart`) judges the impact suppressor at each gap on its worst
branch over the band (:func:`impactdamper.analysis.peaks.worst_branches`: both sweep
directions, peaks located, the no-contact floor, random starts): its peak and its band average;
the best gap of the chart is then located (:func:`best_gap`), not read off the chart's grid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from collections.abc import Callable, Sequence

import numpy as np
import scipy.optimize

from impactdamper.analysis.linear_device import LinearDevice, check_band, linear_maxima, linear_peak
from impactdamper.analysis.peaks import RANDOM_COUNT, SEARCH_THETA_TOL, THETA_TOL, WorstBranch, worst_branches
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.sweeps import with_value
from impactdamper.core.parameters import RELATIVE_PARAMETERS, Parameters, finite_argument, require_parameters

__all__ = [
    "CHART_COLUMNS",
    "AT_THETA_COLUMN",
    "gap_chart",
    "best_gap",
    "design_chart_2d",
    "CRITERIA",
    "GOOD_GAP_TOLERANCE",
    "LINEAR_GRID_POINTS",
    "DESIGN_FIELDS",
    "design_parameters",
    "design_band",
    "design_gaps",
    "response_gaps",
    "LinearDevice",
    "linear_maxima",
    "linear_peak",
    "GAP_XTOL",
]

CRITERIA = ("peak", "band_average")
# A gap is "good" when its criterion is within this fraction of the best gap's: 10 % is about
# the spread of max|x1| between the two sweep directions in the hysteretic part of the band, so
# finer differences do not distinguish designs.
GOOD_GAP_TOLERANCE = 0.10
# Theta samples over a band for the linear references' band averages (trapezoidal): the TMD's
# resonance peaks are ~0.1 wide in theta at mu = 0.08, so 801 points over a band of 1 put 80
# samples on each.
LINEAR_GRID_POINTS = 801
# The parameters the config's ``design`` section may set for the suppressor it studies: the
# relative ones but the gap (the design variable) and theta (the band); those and the scales
# stay the reference case's.
DESIGN_FIELDS = tuple(n for n in RELATIVE_PARAMETERS if n not in ("theta", "gap"))
# Two gaps closer than this (Delta0/x_st) are one gap of the frequency responses: far below the
# design chart's step.
SAME_GAP = 1e-12
# The columns of :meth:`GapChart.rows`, in the order the chart's CSV records write them; with a
# theta, the rows also hold the worst motion's max|x1|/x_st at it.
CHART_COLUMNS = (
    "gap",
    "peak_max_abs_x1",
    "peak_theta",
    "band_average_max_abs_x1",
    "no_contact_floor",
    "peak_impulse",
    "impacts_per_period",
)
AT_THETA_COLUMN = "max_abs_x1_at_theta"


def design_parameters(reference: dict, design: dict) -> Parameters:
    """The suppressor the design stage studies: the config's ``reference`` case with the
    ``design`` section's own values of :data:`DESIGN_FIELDS` (those it gives).

    Parameters
    ----------
    reference : dict
        Every relative parameter (the config's ``reference`` section).
    design : dict
        The config's ``design`` section; keys other than :data:`DESIGN_FIELDS` are ignored.
    """
    values = {name: float(reference[name]) for name in Parameters.names()}
    values.update({name: float(design[name]) for name in DESIGN_FIELDS if name in design})
    return Parameters(**values)


def design_band(design: dict) -> tuple[float, float]:
    """The band of forcing frequencies theta = omega/omega1 (``theta_start``, ``theta_stop``
    of the config's ``design`` section)."""
    return float(design["theta_start"]), float(design["theta_stop"])


def design_gaps(design: dict, second: bool = False) -> np.ndarray:
    """The design chart's gaps Delta0/x_st, evenly spaced from ``gap_start`` to ``gap_stop`` of
    the config's ``design`` section: ``gap_points`` of them, or ``second_gap_points`` for the
    chart against a second parameter (``second=True``). Shape (points,)."""
    points = design["second_gap_points" if second else "gap_points"]
    return np.linspace(float(design["gap_start"]), float(design["gap_stop"]), int(points))


def response_gaps(best: float, gaps: Sequence[float]) -> list[float]:
    """The gaps of the frequency-response figure: the design chart's best gap ``best``, then
    ``gaps`` (the config's ``response_gaps``) in order, each once (within :data:`SAME_GAP`)."""
    out = [float(best)]
    for g in gaps:
        if all(abs(float(g) - x) > SAME_GAP for x in out):
            out.append(float(g))
    return out


def _runs_where(thetas: Sequence[float], flags: Sequence[bool]) -> list[tuple[float, float]]:
    """The contiguous runs of ``thetas`` (increasing) where ``flags`` holds, as (first theta,
    last theta) of each run; a run of one theta has first == last."""
    runs, start, last = [], None, None
    for t, b in zip(list(thetas) + [math.nan], list(flags) + [False]):
        if b and start is None:
            start = last = t
        elif b:
            last = t
        elif start is not None:
            runs.append((start, last))
            start = None
    return runs


# The best gap of a chart is located to this (Delta0/x_st) by Brent's method between the chart's
# neighbours of its best grid gap.
GAP_XTOL = 1e-3


def _pulse_unit(p: Parameters, thetas: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """The pulse of eq. (21) over P0/omega1, from closing velocities v over x_st omega at each
    theta: the model's impact law (:meth:`impactdamper.core.model.Model.impact`, linear in v)
    applied to a unit closing velocity, times v, over m1 x_st omega1 (= P0/omega1)."""
    from impactdamper.core.model import Model

    contact = np.array([0.0, p.Delta0, 0.0, 1.0])  # at the stop, closing at 1 m/s
    per_velocity = Model(p).impact(contact)[2]  # N s per m/s
    # S = per_velocity v x_st omega, and P0/omega1 = m1 x_st omega1 = m1 x_st omega/theta.
    return per_velocity * np.asarray(velocity) * np.asarray(thetas) / p.m1


@dataclass(frozen=True)
class _GapChart:
    """The worst branch at each gap, and the design criteria it gives.

    Attributes
    ----------
    p : Parameters
        The other parameters.
    gaps : ndarray, shape (n,)
        Delta0/x_st, increasing.
    branches : tuple of WorstBranch
        One per gap, over the same band.
    """

    p: Parameters = field(repr=False)
    gaps: np.ndarray
    branches: tuple = field(repr=False)

    def criterion(self, name: str) -> np.ndarray:
        """``peak`` (the worst branch's located peak) or ``band_average``, per gap."""
        if name not in CRITERIA:
            raise ValueError(f"`criterion` = {name!r} is not allowed: must be one of {', '.join(CRITERIA)}")
        return np.array([w.peak if name == "peak" else w.band_average for w in self.branches])

    def at_theta(self, theta: float) -> np.ndarray:
        """The worst motion's max|x1|/x_st at one theta of the grid, per gap (the gap sweep of
        the sweeps stage reads the gap at the reference theta = 1 only)."""
        theta = finite_argument("theta", theta)
        thetas = self.branches[0].thetas
        i = int(np.argmin(np.abs(thetas - theta)))
        if abs(thetas[i] - theta) > 1e-9 * max(abs(theta), 1.0):
            raise ValueError(
                f"`theta` = {theta!r} is not allowed: must be on the chart's theta grid "
                f"({thetas[0]:g} to {thetas[-1]:g} in {len(thetas)} points)"
            )
        return np.array([w.worst_sample[i] for w in self.branches])

    def loads(self) -> tuple[np.ndarray, np.ndarray]:
        """Per gap over the grid and both sweeps: the largest pulse per impact over P0/omega1
        and the most impacts per period (settled motions)."""
        pulse, impacts = [], []
        for w in self.branches:
            v = np.fmax(_pulse_unit(w.p, w.thetas, w.up_velocity), _pulse_unit(w.p, w.thetas, w.down_velocity))
            pulse.append(float(np.nanmax(v)))
            impacts.append(float(np.nanmax(np.r_[w.up_impacts, w.down_impacts, 0.0])))
        return np.array(pulse), np.array(impacts)

    def best(self, name: str, tolerance: float = GOOD_GAP_TOLERANCE) -> dict:
        """The chart's gap minimising criterion ``name`` and its band of good gaps (see
        :func:`good_band`)."""
        values = self.criterion(name)
        i = int(np.nanargmin(values))
        lo, hi = _good_band(self.gaps, values, tolerance)
        pulse, impacts = self.loads()
        return {
            "criterion": name,
            "gap": float(self.gaps[i]),
            "value": float(values[i]),
            "tolerance": tolerance,
            "good_from": lo,
            "good_to": hi,
            "peak_impulse": float(pulse[i]),
            "impacts_per_period": float(impacts[i]),
            "index": i,
        }

    def rows(self, theta: float | None = None) -> list[dict]:
        """One dict per gap; with ``theta``, also ``max_abs_x1_at_theta`` (see :meth:`at_theta`)."""
        peak, mean = self.criterion("peak"), self.criterion("band_average")
        pulse, impacts = self.loads()
        at = self.at_theta(theta) if theta is not None else [None] * len(self.gaps)
        out = []
        for g, w, a, b, s, z, x in zip(self.gaps, self.branches, peak, mean, pulse, impacts, at):
            row = {
                "gap": float(g),
                "peak_max_abs_x1": float(a),
                "peak_theta": float(w.peak_theta),
                "band_average_max_abs_x1": float(b),
                "no_contact_floor": float(w.floor.value),
                "peak_impulse": float(s),
                "impacts_per_period": float(z),
            }
            if theta is not None:
                row[AT_THETA_COLUMN] = float(x)
            out.append(row)
        return out


def _good_band(gaps: Sequence[float], values: Sequence[float], tolerance: float = GOOD_GAP_TOLERANCE) -> tuple:
    """The contiguous run of gaps around the best one whose value is within ``tolerance`` of it
    (value <= (1 + tolerance) best). Returns (first gap, last gap) of the run."""
    tolerance = finite_argument("tolerance", tolerance)
    if not tolerance >= 0:
        raise ValueError(f"`tolerance` = {tolerance!r} is not allowed: must be >= 0")
    g = np.asarray(gaps, dtype=float)
    v = np.asarray(values, dtype=float)
    i = int(np.nanargmin(v))
    limit = (1.0 + tolerance) * v[i]
    lo = i
    while lo > 0 and v[lo - 1] <= limit:
        lo -= 1
    hi = i
    while hi < len(v) - 1 and v[hi + 1] <= limit:
        hi += 1
    return float(g[lo]), float(g[hi])


def gap_chart(
    p: Parameters,
    gaps: Sequence[float],
    band: tuple[float, float] = (0.5, 1.5),
    step: float = 0.02,
    *,
    theta_tol: float = SEARCH_THETA_TOL,
    settings: SweepSettings | None = None,
    workers: int = 1,
    progress: Callable[[str], None] | None = None,
) -> _GapChart:
    """The worst branch over ``band`` at each gap (one batch of all gaps,
    :func:`~impactdamper.analysis.peaks.worst_branches`: grid steps of at most ``step``, peaks
    located to ``theta_tol``, no random starts).

    Parameters
    ----------
    p : Parameters
        The other parameters (its gap and theta are not used).
    gaps : sequence of float
        Delta0/x_st values (sorted here).
    band : (float, float)
    step, theta_tol : float
    settings : SweepSettings, optional
    workers : int
    progress : callable(str), optional
        Called with a one-line summary.
    """
    p = require_parameters(p)
    band = check_band(band)
    gaps = np.array(sorted(finite_argument("gaps", g) for g in gaps))
    if len(gaps) == 0:
        raise ValueError("`gaps` = [] is not allowed: must hold at least one value")
    cases = [with_value(p, "gap", float(g)) for g in gaps]
    ws = worst_branches(
        cases, [band] * len(cases), step=step, theta_tol=theta_tol, random_count=0, settings=settings, workers=workers
    )
    if progress is not None:
        i = int(np.argmin([w.peak for w in ws]))
        progress(f"{len(gaps)} gaps from {gaps[0]:g} to {gaps[-1]:g}: lowest peak {ws[i].peak:.4g} at {gaps[i]:g}")
    return _GapChart(p, gaps, tuple(ws))


def best_gap(
    chart: _GapChart,
    name: str = "peak",
    *,
    step: float = 0.02,
    settings: SweepSettings | None = None,
    workers: int = 1,
    xtol: float = GAP_XTOL,
) -> dict:
    """The gap minimising criterion ``name`` of the chart's suppressor, located: Brent's method
    between the chart's neighbours of its best grid gap (to ``xtol``), each value the worst
    branch located to THETA_TOL with the random starts. Returns {gap, value, peak_theta,
    branch, evaluations, bracket}."""
    values = chart.criterion(name)
    i = int(np.nanargmin(values))
    lo, hi = chart.gaps[max(i - 1, 0)], chart.gaps[min(i + 1, len(chart.gaps) - 1)]
    band = chart.branches[0].band
    seen: dict = {}

    def located(g: float) -> WorstBranch:
        if g not in seen:
            q = with_value(chart.p, "gap", float(g))
            seen[g] = worst_branches(
                [q],
                [band],
                step=step,
                theta_tol=THETA_TOL,
                random_count=RANDOM_COUNT,
                settings=settings,
                workers=workers,
            )[0]
        return seen[g]

    def f(g: float) -> float:
        w = located(g)
        return w.peak if name == "peak" else w.band_average

    if hi > lo:
        res = scipy.optimize.minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": xtol})
        g = float(res.x)
    else:
        g = float(lo)
    candidates = [g, float(chart.gaps[i])]
    g = min(candidates, key=f)
    w = located(g)
    return {
        "gap": g,
        "value": f(g),
        "peak": w.peak,
        "band_average": w.band_average,
        "peak_theta": w.peak_theta,
        "peak_branch": w.branch(),
        "evaluations": len(seen),
        "bracket": [float(lo), float(hi)],
        "xtol": xtol,
    }


def design_chart_2d(
    p: Parameters,
    name: str,
    values: Sequence[float],
    gaps: Sequence[float],
    band: tuple[float, float] = (0.5, 1.5),
    step: float = 0.02,
    *,
    settings: SweepSettings | None = None,
    workers: int = 1,
    progress: Callable[[str], None] | None = None,
) -> dict[float, _GapChart]:
    """:func:`gap_chart` at each value of a second parameter ``name`` (``N`` or ``R``, or any
    field of Parameters but ``gap`` and ``theta``). Returns {value: GapChart}."""
    if name in ("gap", "theta") or name not in Parameters.names():
        allowed = ", ".join(n for n in Parameters.names() if n not in ("gap", "theta"))
        raise ValueError(f"`name` = {name!r} is not allowed: must be one of {allowed}")
    out = {}
    for v in values:
        q = with_value(require_parameters(p), name, finite_argument("values", v))
        if progress is not None:
            progress(f"{name} = {v:.4g}")
        out[float(v)] = gap_chart(q, gaps, band, step, settings=settings, workers=workers, progress=progress)
    return out
