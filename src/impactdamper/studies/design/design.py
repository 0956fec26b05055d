"""Choosing a suppressor: linear baselines and design charts over the gap.

Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100, compute the suppressor's motion
for a given gap; a designer wants the gap (and spring, restitution) that keeps the object's
amplitude lowest over the band of forcing frequencies it will meet. This module answers that
by simulation (:func:`impactdamper.analysis.response.frequency_response` at each gap) and sets
the answer beside three linear references, each computed here:

* the bare object (no suppressor): |x1|/x_st = 1/|1 - theta^2 + 2 i delta1 theta|;
* the absorber without a stop: the same mu, N, delta2 (eq. 10 with no contact);
* the optimal linear tuned-mass damper (TMD) of the same mu on the object's own damping
  delta1: its tuning N and damping delta2 minimise the peak (or the band average) of |x1|/x_st
  over the band, numerically. For delta1 = 0 and an unbounded band Den Hartog's closed form
  holds: N = 1/(1 + mu), delta2 = sqrt(3 mu/(8 (1 + mu)^3)), peak sqrt(1 + 2/mu) (the peak is
  the height of the fixed points, the exact minimax value); it checks the optimiser.

In relative form (time in 1/omega1, lengths in x_st, B = N^2 + 2 i delta2 theta) the linear
two-mass system has

    x1_hat/x_st = (B - theta^2) / ((1 - theta^2 + 2 i delta1 theta)(B - theta^2) - mu B theta^2),

the relative form of eq. (10).

The design criterion of an impact suppressor at one gap is the worse of the upward and downward
sweeps at each theta (a designer cannot choose the branch), then its maximum over the band
(peak) or its trapezoidal mean (band average).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from collections.abc import Callable, Sequence

import numpy as np
import scipy.optimize

from impactdamper.analysis.response import frequency_response, theta_grid
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.sweeps import with_value
from impactdamper.core.parameters import RELATIVE_PARAMETERS, Parameters, finite_argument, require_parameters

__all__ = [
    "bare_object_amplitude",
    "two_mass_amplitude",
    "den_hartog",
    "TunedMassDamper",
    "optimal_tmd",
    "band_peak",
    "band_mean",
    "GapChart",
    "gap_chart",
    "good_band",
    "design_chart_2d",
    "CRITERIA",
    "GOOD_GAP_TOLERANCE",
    "LINEAR_GRID_POINTS",
    "DESIGN_FIELDS",
    "design_parameters",
    "design_band",
    "design_gaps",
    "response_gaps",
    "runs_where",
    "BAND_STEP",
    "THETA_TOL",
    "AMPLITUDE_RTOL",
    "band_grid",
    "LocatedPeak",
    "BandResponse",
    "impact_band_response",
    "LinearDevice",
    "linear_maxima",
    "linear_peak",
]

CRITERIA = ("peak", "band_average")
# A gap is "good" when its criterion is within this fraction of the best gap's: 10 % is about
# the spread of max|x1| between the two sweep directions in the hysteretic part of the band, so
# finer differences do not distinguish designs.
GOOD_GAP_TOLERANCE = 0.10
# Theta samples over a band for the linear peaks (then refined locally by a bounded search):
# the TMD's resonance peaks are ~0.1 wide in theta at mu = 0.08, so 801 points over a band of 1
# put 80 samples on each before refinement.
LINEAR_GRID_POINTS = 801
# Nelder-Mead stops when the peak changes by less than this (relative): the figures show 3 digits.
OPTIMISER_FTOL = 1e-10
# The parameters the config's ``design`` section may set for the suppressor it studies: the
# relative ones but the gap (the design variable) and theta (the band); those and the scales
# stay the reference case's.
DESIGN_FIELDS = tuple(n for n in RELATIVE_PARAMETERS if n not in ("theta", "gap"))
# Two gaps closer than this (Delta0/x_st) are one gap of the frequency responses: far below the
# design chart's step.
SAME_GAP = 1e-12


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


def runs_where(thetas: Sequence[float], flags: Sequence[bool]) -> list[tuple[float, float]]:
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


def bare_object_amplitude(delta1: float, thetas: Sequence[float]) -> np.ndarray:
    """|x1|/x_st of the object alone: 1/|1 - theta^2 + 2 i delta1 theta|. Shape (len(thetas),)."""
    th = np.asarray(thetas, dtype=float)
    return 1.0 / np.abs(1.0 - th**2 + 2j * delta1 * th)


def two_mass_amplitude(mu: float, N: float, delta1: float, delta2: float, thetas: Sequence[float]) -> np.ndarray:
    """|x1|/x_st of the linear two-mass system (absorber without a stop, or a TMD), closed form
    (see the module docstring). Shape (len(thetas),)."""
    th = np.asarray(thetas, dtype=float)
    B = N * N + 2j * delta2 * th
    return np.abs((B - th**2) / ((1.0 - th**2 + 2j * delta1 * th) * (B - th**2) - mu * B * th**2))


def den_hartog(mu: float) -> dict:
    """Den Hartog's optimal TMD on an undamped object: tuning N, damping delta2 and the peak of
    |x1|/x_st.

    Den Hartog (Mechanical Vibrations, 1956, sec. 3.3) gives the damping ratio on the
    absorber's own critical damping, zeta2 = k2/(2 m2 omega2) = sqrt(3 mu/(8 (1 + mu))); this
    project's delta2 = k2/(2 m2 omega1) = N zeta2 = sqrt(3 mu/(8 (1 + mu)^3)) (the same number as
    his c/c_c with c_c = 2 m2 Omega_n on the main system's frequency). An earlier version
    multiplied the latter by N once more, 1/(1 + mu) too small (8 % at mu = 0.08); the numerical
    minimax optimum of an undamped object sits within 1 % of this delta2 (tests).
    """
    N = 1.0 / (1.0 + mu)
    zeta2 = math.sqrt(3.0 * mu / (8.0 * (1.0 + mu)))
    return {"N": N, "delta2": N * zeta2, "peak": math.sqrt(1.0 + 2.0 / mu)}


def band_peak(
    amplitude: Callable[[np.ndarray], np.ndarray], band: tuple[float, float], points: int = LINEAR_GRID_POINTS
) -> float:
    """Maximum of a smooth ``amplitude(theta)`` over ``band``: a grid, then a bounded search
    around the largest sample."""
    th = np.linspace(band[0], band[1], points)
    y = amplitude(th)
    i = int(np.argmax(y))
    lo, hi = th[max(i - 1, 0)], th[min(i + 1, points - 1)]
    res = scipy.optimize.minimize_scalar(
        lambda t: -float(amplitude(np.array([t]))[0]), bounds=(lo, hi), method="bounded", options={"xatol": 1e-12}
    )
    return max(float(y[i]), -float(res.fun))


def band_mean(
    amplitude: Callable[[np.ndarray], np.ndarray], band: tuple[float, float], points: int = LINEAR_GRID_POINTS
) -> float:
    """Trapezoidal mean of a smooth ``amplitude(theta)`` over ``band`` (``points`` samples)."""
    th = np.linspace(band[0], band[1], points)
    return float(np.trapezoid(amplitude(th), th) / (band[1] - band[0]))


@dataclass(frozen=True)
class TunedMassDamper:
    """An optimal linear TMD of mass ratio ``mu`` on an object of damping ``delta1``.

    Attributes
    ----------
    mu, delta1 : float
    band : (float, float)
        The theta band optimised over.
    criterion : str
        ``peak`` or ``band_average`` of |x1|/x_st over the band.
    N, delta2 : float
        The optimal tuning omega2/omega1 and damping k2/(2 m2 omega1).
    peak, band_average : float
        Both criteria at the optimum.
    evaluations : int
        Objective evaluations the optimiser took.
    """

    mu: float
    delta1: float
    band: tuple
    criterion: str
    N: float
    delta2: float
    peak: float
    band_average: float
    evaluations: int

    def amplitude(self, thetas: Sequence[float]) -> np.ndarray:
        return two_mass_amplitude(self.mu, self.N, self.delta1, self.delta2, thetas)

    def to_dict(self) -> dict:
        d = {name: getattr(self, name) for name in self.__dataclass_fields__}
        d["band"] = list(self.band)
        return d


def _check_band(band: object) -> tuple[float, float]:
    try:
        a, b = band  # type: ignore[misc]
    except (TypeError, ValueError):
        raise ValueError(f"`band` = {band!r} is not allowed: must be two numbers (theta_start, theta_stop)") from None
    theta_grid(a, b, 2)
    return float(a), float(b)


def optimal_tmd(
    mu: float,
    delta1: float,
    band: tuple[float, float] = (0.5, 1.5),
    criterion: str = "peak",
    start: tuple[float, float] | None = None,
) -> TunedMassDamper:
    """The TMD of mass ratio ``mu`` that minimises ``criterion`` of |x1|/x_st over ``band``.

    Nelder-Mead in (N, log delta2) from Den Hartog's optimum (or ``start``); the peak is a
    minimax objective, whose optimum sits where two resonance peaks are equal, and the simplex
    method needs no gradient there.

    Parameters
    ----------
    mu : float
        Mass ratio m2/m1 (> 0).
    delta1 : float
        The object's damping k1/(2 m1 omega1) (>= 0).
    band : (float, float)
        Theta band.
    criterion : str
        ``peak`` or ``band_average``.
    start : (N, delta2), optional

    Returns
    -------
    TunedMassDamper
    """
    mu = finite_argument("mu", mu)
    delta1 = finite_argument("delta1", delta1)
    if not mu > 0:
        raise ValueError(f"`mu` = {mu!r} is not allowed: must be > 0")
    if not delta1 >= 0:
        raise ValueError(f"`delta1` = {delta1!r} is not allowed: must be >= 0")
    band = _check_band(band)
    if criterion not in CRITERIA:
        raise ValueError(f"`criterion` = {criterion!r} is not allowed: must be one of {', '.join(CRITERIA)}")
    guess = den_hartog(mu)
    x0 = (guess["N"], guess["delta2"]) if start is None else start
    measure = band_peak if criterion == "peak" else band_mean

    def objective(x: np.ndarray) -> float:
        N, d2 = float(x[0]), math.exp(float(x[1]))
        if not N > 0:
            return math.inf
        return measure(lambda th: two_mass_amplitude(mu, N, delta1, d2, th), band)

    res = scipy.optimize.minimize(
        objective,
        np.array([x0[0], math.log(x0[1])]),
        method="Nelder-Mead",
        options={"xatol": 1e-9, "fatol": OPTIMISER_FTOL, "maxiter": 4000},
    )
    N, d2 = float(res.x[0]), math.exp(float(res.x[1]))
    amp = lambda th: two_mass_amplitude(mu, N, delta1, d2, th)  # noqa: E731
    return TunedMassDamper(
        mu=mu,
        delta1=delta1,
        band=band,
        criterion=criterion,
        N=N,
        delta2=d2,
        peak=band_peak(amp, band),
        band_average=band_mean(amp, band),
        evaluations=int(res.nfev),
    )


@dataclass(frozen=True)
class GapChart:
    """The frequency response at each gap, and the design criteria it gives.

    Attributes
    ----------
    p : Parameters
        The other parameters.
    gaps : ndarray, shape (n,)
        Delta0/x_st, increasing.
    responses : tuple of FrequencyResponse
        One per gap, over the same theta grid.
    """

    p: Parameters = field(repr=False)
    gaps: np.ndarray
    responses: tuple = field(repr=False)

    def criterion(self, name: str) -> np.ndarray:
        """``peak`` or ``band_average`` of the worse direction's max|x1|/x_st, per gap."""
        if name not in CRITERIA:
            raise ValueError(f"`criterion` = {name!r} is not allowed: must be one of {', '.join(CRITERIA)}")
        return np.array([r.peak() if name == "peak" else r.band_average() for r in self.responses])

    def at_theta(self, theta: float) -> np.ndarray:
        """The worse direction's max|x1|/x_st at one theta of the grid, per gap (the gap sweep of
        the sweeps stage reads the gap at the reference theta = 1 only)."""
        theta = finite_argument("theta", theta)
        thetas = self.responses[0].thetas
        i = int(np.argmin(np.abs(thetas - theta)))
        if abs(thetas[i] - theta) > 1e-9 * max(abs(theta), 1.0):
            raise ValueError(
                f"`theta` = {theta!r} is not allowed: must be on the chart's theta grid "
                f"({thetas[0]:g} to {thetas[-1]:g} in {len(thetas)} points)"
            )
        return np.array([r.points[i].worst_x1 for r in self.responses])

    def loads(self) -> tuple[np.ndarray, np.ndarray]:
        """Per gap: largest peak pulse (over m1 x_st omega) and impacts per period over the band."""
        ls = [r.loads() for r in self.responses]
        return np.array([x["peak_impulse"] for x in ls]), np.array([x["impacts_per_period"] for x in ls])

    def best(self, name: str, tolerance: float = GOOD_GAP_TOLERANCE) -> dict:
        """The gap minimising criterion ``name`` and its band of good gaps (see :func:`good_band`)."""
        values = self.criterion(name)
        i = int(np.nanargmin(values))
        lo, hi = good_band(self.gaps, values, tolerance)
        impulse, impacts = self.loads()
        return {
            "criterion": name,
            "gap": float(self.gaps[i]),
            "value": float(values[i]),
            "tolerance": tolerance,
            "good_from": lo,
            "good_to": hi,
            "peak_impulse": float(impulse[i]),
            "impacts_per_period": float(impacts[i]),
            "index": i,
        }

    def rows(self, theta: float | None = None) -> list[dict]:
        """One dict per gap; with ``theta``, also ``max_abs_x1_at_theta`` (see :meth:`at_theta`)."""
        peak, mean = self.criterion("peak"), self.criterion("band_average")
        impulse, impacts = self.loads()
        at = self.at_theta(theta) if theta is not None else [None] * len(self.gaps)
        out = []
        for g, a, b, s, z, r, x in zip(self.gaps, peak, mean, impulse, impacts, self.responses, at):
            row = {
                "gap": float(g),
                "peak_max_abs_x1": float(a),
                "band_average_max_abs_x1": float(b),
                "peak_impulse": float(s),
                "impacts_per_period": float(z),
                "hysteresis_points": int(sum(q.hysteresis for q in r.points)),
            }
            if theta is not None:
                row["max_abs_x1_at_theta"] = float(x)
            out.append(row)
        return out


def good_band(gaps: Sequence[float], values: Sequence[float], tolerance: float = GOOD_GAP_TOLERANCE) -> tuple:
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
    points: int = 21,
    *,
    settings: SweepSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> GapChart:
    """The two-way frequency response over ``band`` (``points`` thetas) at each gap.

    Parameters
    ----------
    p : Parameters
        The other parameters (its gap and theta are not used).
    gaps : sequence of float
        Delta0/x_st values (sorted here).
    band : (float, float)
    points : int
    settings : SweepSettings, optional
    progress : callable(str), optional
        Called with a one-line message after each gap.
    """
    p = require_parameters(p)
    band = _check_band(band)
    theta_grid(band[0], band[1], points)
    gaps = np.array(sorted(finite_argument("gaps", g) for g in gaps))
    if len(gaps) == 0:
        raise ValueError("`gaps` = [] is not allowed: must hold at least one value")
    out = []
    for j, g in enumerate(gaps):
        r = frequency_response(with_value(p, "gap", float(g)), band[0], band[1], points, settings=settings)
        out.append(r)
        if progress is not None:
            progress(
                f"gap {j + 1}/{len(gaps)}: Delta0/x_st = {g:.4g}, peak max|x1|/x_st = {r.peak():.4g}, "
                f"band average {r.band_average():.4g}"
            )
    return GapChart(p, gaps, tuple(out))


def design_chart_2d(
    p: Parameters,
    name: str,
    values: Sequence[float],
    gaps: Sequence[float],
    band: tuple[float, float] = (0.5, 1.5),
    points: int = 21,
    *,
    settings: SweepSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict[float, GapChart]:
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
        out[float(v)] = gap_chart(q, gaps, band, points, settings=settings, progress=progress)
    return out


# ---------------------------------------------------------------------------------------------
# Peaks located, not sampled.
#
# One grid policy for every device: the band is sampled at theta steps of at most BAND_STEP
# (band_grid); the band average of every device is the trapezoidal mean on that grid; the peak
# of every device is located, not read off the grid: the linear devices' in closed form (the
# real roots of the derivative of |x1|^2, a rational function of theta), the impact
# suppressor's by zooming on every local maximum of both sweep directions (continuation from
# the neighbour, the bracket shrunk until it is THETA_TOL wide and the value changes by less
# than AMPLITUDE_RTOL from one zoom to the next).
# ---------------------------------------------------------------------------------------------

# The band grid's largest theta step: the impact suppressor's resonance peaks are ~0.05 wide in
# theta at mu = 0.08, so 0.01 puts ~5 samples on each, enough to see every local maximum the
# zoom then locates; the band average's trapezoidal error on that grid is ~1e-3 relative.
BAND_STEP = 0.01
# A located peak's final theta bracket is at most this wide (the maximum lies in it) ...
THETA_TOL = 1e-4
# ... and its value changed by less than this (relative) in the last zoom.
AMPLITUDE_RTOL = 1e-4
# Points per zoom: the bracket shrinks by ZOOM_POINTS/2 each zoom.
ZOOM_POINTS = 8
# Zooms at most: 0.02 * 4^-14 ~ 7e-11 in theta; near a jump (a fold, where the branch's amplitude
# behaves like sqrt(theta* - theta)) each zoom halves the amplitude error.
MAX_ZOOMS = 14
# Local maxima of one direction refined at most (the largest ones): a chaotic stretch of the band
# has a local maximum at nearly every grid point, and only the largest decide the peak.
MAX_LOCAL_MAXIMA = 6
# A drop by more than this fraction between the located maximum and its next zoom point (in the
# sweep's direction) marks the maximum as the end of a branch (a jump).
JUMP_DROP = 1e-2


def band_grid(band: tuple[float, float], step: float = BAND_STEP) -> np.ndarray:
    """The band's grid, for every device: equally spaced, from ``band[0]`` to ``band[1]``, with
    steps of at most ``step`` (ceil((b - a)/step) + 1 points). Shape (points,)."""
    a, b = _check_band(band)
    step = finite_argument("step", step)
    if not step > 0:
        raise ValueError(f"`step` = {step!r} is not allowed: must be > 0")
    n = int(math.ceil((b - a) / step - 1e-9)) + 1
    return theta_grid(a, b, max(n, 2))


@dataclass(frozen=True)
class LocatedPeak:
    """One local maximum of max|x1|/x_st over theta, located.

    Attributes
    ----------
    theta, value : float
        Where and how high (value over x_st).
    direction : str
        ``up`` or ``down``: the sweep (continuation) direction whose branch it is on.
    jump : bool
        The maximum is the end of a branch (the next point in the sweep's direction, within the
        final bracket, is more than ``JUMP_DROP`` lower): located by bisection of the jump.
    periodic : bool
        The motion there settled on a cycle. False: nonperiodic (a chaotic stretch), where
        max|x1| is the largest over the settle window and no tolerance applies.
    bracket : float
        Width of the final theta bracket (the maximum lies in it).
    change : float
        Relative change of the value in the last zoom.
    evaluations : int
        Settled motions the zoom took.
    """

    theta: float
    value: float
    direction: str
    jump: bool
    periodic: bool
    bracket: float
    change: float
    evaluations: int

    def to_dict(self) -> dict:
        return {name: getattr(self, name) for name in self.__dataclass_fields__}


@dataclass(frozen=True)
class BandResponse:
    """max|x1|/x_st of an impact suppressor over the band grid, both sweep directions, and its
    located local maxima (see :func:`impact_band_response`).

    Attributes
    ----------
    p : Parameters
    thetas : ndarray, shape (n,)
        The band grid (:func:`band_grid`).
    up, down : ndarray, shape (n,)
        max|x1|/x_st of the upward and the downward sweep.
    peaks : tuple of LocatedPeak
        Located local maxima (empty when ``locate`` was False), largest first.
    up_sections, down_sections : ndarray, shape (n, 4)
        The settled section states (for the cycles' loads).
    up_k, down_k : ndarray of int, shape (n,)
        Period multiples (0: nonperiodic).
    evaluations : int
        Settled motions in all.
    """

    p: Parameters = field(repr=False)
    thetas: np.ndarray
    up: np.ndarray
    down: np.ndarray
    peaks: tuple
    up_sections: np.ndarray = field(repr=False)
    down_sections: np.ndarray = field(repr=False)
    up_k: np.ndarray = field(repr=False)
    down_k: np.ndarray = field(repr=False)
    evaluations: int = 0

    def worst(self) -> np.ndarray:
        """The worse direction at each grid theta. Shape (n,)."""
        return np.fmax(self.up, self.down)

    def grid_peak(self) -> float:
        return float(np.nanmax(self.worst()))

    def interpolated_peak(self) -> float:
        """The grid's peak refined at no cost: at each interior local maximum of each direction
        the vertex of the parabola through it and its two neighbours (where it curves down),
        never below the grid's own value. Between the grid peak and the located one: the
        optimiser's local stage reads it, as a peak between two grid points otherwise hides."""
        best = self.grid_peak()
        for y in (self.up, self.down):
            y0, y1, y2 = y[:-2], y[1:-1], y[2:]
            curve = y0 - 2.0 * y1 + y2
            ok = (y1 >= y0) & (y1 >= y2) & (curve < 0) & np.isfinite(curve)
            if np.any(ok):
                vertex = y1[ok] - (y0[ok] - y2[ok]) ** 2 / (8.0 * curve[ok])
                best = max(best, float(np.max(vertex)))
        return best

    @property
    def peak(self) -> float:
        """The located peak: the largest located maximum (never below the grid's largest)."""
        return max([self.grid_peak()] + [q.value for q in self.peaks])

    @property
    def peak_theta(self) -> float:
        if self.peaks and self.peaks[0].value >= self.grid_peak():
            return self.peaks[0].theta
        return float(self.thetas[int(np.nanargmax(self.worst()))])

    @property
    def band_average(self) -> float:
        """Trapezoidal mean of the worse direction over the band grid."""
        x, y = self.thetas, self.worst()
        return float(np.trapezoid(y, x) / (x[-1] - x[0]))


def _settle_from(p: Parameters, thetas: Sequence[float], start: np.ndarray, settings) -> tuple:
    """Settle the thetas in order, each from the previous one's section (the first from
    ``start``): continuation, as a sweep. Returns (values, sections, period multiples), shapes
    (m,), (m, 4), (m,) (k = 0: nonperiodic)."""
    from impactdamper import steady_states

    values, sections, ks = [], [], []
    state = np.asarray(start, float)
    for t in thetas:
        r = steady_states(p, ("theta",), np.array([[float(t)]]), settings=settings, chain=False, states=state[None, :])
        values.append(float(r.x1_max[0]))
        ks.append(int(r.period_multiple[0]))
        state = r.sections[0].copy()
        sections.append(state)
    return np.array(values), np.array(sections), np.array(ks)


def _zoom(
    p: Parameters,
    a: float,
    b: float,
    y_a: float,
    s_a: np.ndarray,
    k_a: int,
    direction: str,
    settings,
    theta_tol: float,
    rtol: float,
) -> LocatedPeak:
    """The largest max|x1| on the branch continued from (a, y_a, s_a) towards b (b < a for the
    downward direction): zoom on the largest of ZOOM_POINTS continued points, from the point
    before it, until the bracket is theta_tol wide and the value changes by less than rtol."""
    best_t, best_y, best_k = a, y_a, k_a
    evaluations, change, jump = 0, math.inf, False
    for _ in range(MAX_ZOOMS):
        ts = a + (b - a) * np.arange(1, ZOOM_POINTS + 1) / ZOOM_POINTS
        ys, ss, ks = _settle_from(p, ts, s_a, settings)
        evaluations += len(ts)
        all_t = np.concatenate([[a], ts])
        all_y = np.concatenate([[y_a], ys])
        all_s = np.vstack([s_a[None, :], ss])
        all_k = np.concatenate([[k_a], ks])
        j = int(np.nanargmax(all_y))
        previous = best_y
        if all_y[j] >= best_y:
            best_t, best_y, best_k = float(all_t[j]), float(all_y[j]), int(all_k[j])
        change = abs(best_y - previous) / max(abs(best_y), 1e-300)
        jump = j + 1 < len(all_y) and all_y[j + 1] < (1.0 - JUMP_DROP) * all_y[j]
        lo = max(j - 1, 0)
        a, y_a, s_a, k_a = float(all_t[lo]), float(all_y[lo]), all_s[lo], int(all_k[lo])
        b = float(all_t[min(j + 1, len(all_t) - 1)])
        if abs(b - a) <= theta_tol and change <= rtol:
            break
    return LocatedPeak(
        theta=best_t,
        value=best_y,
        direction=direction,
        jump=bool(jump),
        periodic=best_k > 0,
        bracket=abs(b - a),
        change=float(change),
        evaluations=evaluations,
    )


def _local_maxima(y: np.ndarray) -> list[int]:
    """Indices of the local maxima of a sampled curve (ends included), largest first."""
    n = len(y)
    out = [
        i
        for i in range(n)
        if np.isfinite(y[i]) and (i == 0 or not y[i - 1] > y[i]) and (i == n - 1 or not y[i + 1] > y[i])
    ]
    return sorted(out, key=lambda i: -y[i])


def impact_band_response(
    p: Parameters,
    band: tuple[float, float] = (0.5, 1.5),
    step: float = BAND_STEP,
    *,
    locate: bool = True,
    settings: SweepSettings | None = None,
    theta_tol: float = THETA_TOL,
    rtol: float = AMPLITUDE_RTOL,
    peaks: int = MAX_LOCAL_MAXIMA,
) -> BandResponse:
    """max|x1|/x_st of an impact suppressor over a band, both sweep directions, peaks located.

    The band grid (:func:`band_grid`) is swept upward and downward by the compiled batch engine
    (:func:`impactdamper.steady_states`, each point from its neighbour's settled
    motion, Algorithm No. 2 of Timofeev et al. 2019 with eqs. 21-22 at the impacts). Then every
    local maximum of each direction's samples (the ``peaks`` largest) is located: the branch is
    continued from the grid point before it (in the sweep's direction) through ZOOM_POINTS
    points to the grid point after it, and the bracket around the largest is zoomed the same
    way until it is at most ``theta_tol`` wide and the value changed by less than ``rtol``
    (relative) in the last zoom. Where the maximum ends a branch (a jump to another motion),
    the zoom closes on the jump from the branch's side: a bisection of the jump, and the value
    is the branch's end, the worse side. The peak is the largest over both directions.

    Parameters
    ----------
    p : Parameters
        The suppressor (its theta is not used).
    band : (float, float)
    step : float
        Largest grid step.
    locate : bool
        False: the grid alone (no zoom).
    settings : SweepSettings, optional
    theta_tol, rtol : float
    peaks : int
        Local maxima located per direction, at most.

    Returns
    -------
    BandResponse
    """
    from impactdamper import steady_states

    p = require_parameters(p)
    th = band_grid(band, step)
    settings = settings or SweepSettings()
    up = steady_states(p, ("theta",), th[:, None], settings=settings)
    down = steady_states(p, ("theta",), th[::-1, None], settings=settings)
    located = []
    evaluations = 2 * len(th)
    if locate:
        for direction, res, order in (("up", up, th), ("down", down, th[::-1])):
            y = np.asarray(res.x1_max, float)
            for i in _local_maxima(y)[: int(peaks)]:
                f = max(i - 1, 0)
                nxt = min(i + 1, len(order) - 1)
                if i == len(order) - 1 and i > 0:
                    nxt = i
                q = _zoom(
                    p,
                    float(order[f]),
                    float(order[nxt]),
                    float(y[f]),
                    res.sections[f],
                    int(res.period_multiple[f]),
                    direction,
                    settings,
                    theta_tol,
                    rtol,
                )
                if y[i] > q.value:  # the grid's own sample is higher (the zoom never lowers it)
                    q = LocatedPeak(
                        float(order[i]),
                        float(y[i]),
                        direction,
                        q.jump,
                        bool(res.period_multiple[i] > 0),
                        q.bracket,
                        q.change,
                        q.evaluations,
                    )
                located.append(q)
                evaluations += q.evaluations
    located.sort(key=lambda q: -q.value)
    return BandResponse(
        p=p,
        thetas=th,
        up=np.asarray(up.x1_max, float),
        down=np.asarray(down.x1_max, float)[::-1],
        peaks=tuple(located),
        up_sections=up.sections.copy(),
        down_sections=down.sections[::-1].copy(),
        up_k=up.period_multiple.copy(),
        down_k=down.period_multiple[::-1].copy(),
        evaluations=evaluations,
    )


# ---------------------------------------------------------------------------------------------
# Linear devices in closed form.
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class LinearDevice:
    """A linear device on the object: the bare object (``mu`` = 0), the absorber without a stop
    or a TMD, as polynomials in theta (relative form of eq. 10, see the module docstring).

    x1_hat/x_st = (B - theta^2)/D(theta), (x2_hat - x1_hat)/x_st = theta^2/D(theta), with
    B = N^2 + 2 i delta2 theta and D = (1 - theta^2 + 2 i delta1 theta)(B - theta^2) - mu B theta^2.
    """

    mu: float
    N: float
    delta1: float
    delta2: float

    def _polys(self) -> tuple:
        P = np.polynomial.polynomial
        obj = np.array([1.0, 2j * self.delta1, -1.0])
        if self.mu == 0.0:
            return np.array([1.0 + 0j]), obj, np.array([0.0j])
        b = np.array([self.N**2, 2j * self.delta2, -1.0])
        den = P.polysub(P.polymul(obj, b), self.mu * np.array([0.0, 0.0, self.N**2, 2j * self.delta2]))
        return b, den, np.array([0.0, 0.0, 1.0 + 0j])

    def amplitude(self, thetas: Sequence[float]) -> np.ndarray:
        """|x1|/x_st. Shape (len(thetas),)."""
        num, den, _ = self._polys()
        th = np.asarray(thetas, float)
        P = np.polynomial.polynomial
        return np.abs(P.polyval(th, num) / P.polyval(th, den))

    def stroke(self, thetas: Sequence[float]) -> np.ndarray:
        """|x2 - x1|/x_st (0 for the bare object). Shape (len(thetas),)."""
        _, den, st = self._polys()
        th = np.asarray(thetas, float)
        P = np.polynomial.polynomial
        return np.abs(P.polyval(th, st) / P.polyval(th, den))

    def peak(self, band: tuple[float, float]) -> tuple[float, float]:
        """(theta, value) of the largest |x1|/x_st over the band, in closed form."""
        num, den, _ = self._polys()
        return linear_peak(num, den, band)

    def stroke_peak(self, band: tuple[float, float]) -> tuple[float, float]:
        """(theta, value) of the largest |x2 - x1|/x_st over the band, in closed form."""
        _, den, st = self._polys()
        if self.mu == 0.0:
            return float(band[0]), 0.0
        return linear_peak(st, den, band)

    def band_average(self, band: tuple[float, float], step: float = BAND_STEP) -> float:
        """Trapezoidal mean of |x1|/x_st on the band grid (:func:`band_grid`, as every device)."""
        th = band_grid(band, step)
        return float(np.trapezoid(self.amplitude(th), th) / (th[-1] - th[0]))


def linear_maxima(num: np.ndarray, den: np.ndarray, band: tuple[float, float]) -> list[tuple[float, float]]:
    """Every local maximum over ``band`` of |num(theta)/den(theta)|, num and den polynomials in
    theta with complex coefficients (ascending order), in closed form: the stationary points
    are the real roots of f' = 0 with f = |num|^2/|den|^2, i.e. of the real polynomial
    (|num|^2)' |den|^2 - |num|^2 (|den|^2)', polished by Newton's method; the band's ends count
    where the function falls away from them.

    Returns
    -------
    list of (theta, value), largest first.
    """
    a, b = _check_band(band)
    P = np.polynomial.polynomial
    n2 = np.real(P.polymul(num, np.conj(num)))
    d2 = np.real(P.polymul(den, np.conj(den)))
    g = P.polysub(P.polymul(P.polyder(n2), d2), P.polymul(n2, P.polyder(d2)))
    g = np.trim_zeros(g, "b")
    value = lambda t: float(np.sqrt(P.polyval(t, n2) / P.polyval(t, d2)))  # noqa: E731
    candidates = []
    if len(g) > 1:
        for r in P.polyroots(g):
            if abs(r.imag) <= 1e-6 * max(1.0, abs(r.real)) and a - 1e-9 <= r.real <= b + 1e-9:
                t = float(r.real)
                dg = P.polyder(g)
                for _ in range(3):  # Newton polish of the real root
                    d = P.polyval(t, dg)
                    if d == 0:
                        break
                    t -= P.polyval(t, g) / d
                candidates.append(min(max(t, a), b))
    candidates += [a, b]
    out = []
    # Neighbours 1e-5 of the band away: on a resonance of half-width >= 1e-3 of the band the
    # function changes there by >= ~1e-4 relative, far above the rounding that 1e-12 allows.
    h = 1e-5 * (b - a)
    values = {t: value(t) for t in sorted(set(candidates))}
    for t, v in values.items():
        left = value(t - h) if t - h >= a else -math.inf
        right = value(t + h) if t + h <= b else -math.inf
        # A flat maximum's neighbours may exceed it by rounding: 1e-12 relative is allowed.
        if v >= (1.0 - 1e-12) * left and v >= (1.0 - 1e-12) * right:
            out.append((t, v))
    top = max(values.items(), key=lambda x: x[1])  # the largest stationary point or end: always a maximum
    if top not in out:
        out.append(top)
    return sorted(out, key=lambda x: -x[1])


def linear_peak(num: np.ndarray, den: np.ndarray, band: tuple[float, float]) -> tuple[float, float]:
    """(theta, value) of the largest |num/den| over ``band`` (see :func:`linear_maxima`)."""
    return linear_maxima(num, den, band)[0]
