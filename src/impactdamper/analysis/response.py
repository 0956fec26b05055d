"""Frequency response: the settled motion against the forcing frequency theta = omega/omega1.

The paper's motivation (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100,
introduction) is an object whose forcing frequency varies; its figures fix theta = 1. This
module sweeps theta upward and downward once (each point started from its neighbour's settled
motion, in one batch call: :func:`impactdamper.analysis.band_sweeps.band_sweeps`, on the worst
branch locator's grid with the response's thetas added; the worst branch is located on the same
sweeps), and describes every settled cycle at the response's thetas
by what a designer needs (:mod:`~impactdamper.analysis.cycle_metrics`: the largest |x1| and |x2|,
impacts and pulses per period, the energy put in, lost at the impacts and dissipated, and their
balance), and whether the upward and downward sweeps settle on different motions (hysteresis).

The exact linear response without a stop (eq. 10) is given beside it, in closed form
(:class:`impactdamper.analysis.linear_device.LinearDevice`). The peak
over the band is not the grid's largest sample but the worst branch located
(:func:`impactdamper.analysis.peaks.worst_branch`: every branch a slow sweep in either
direction follows, jumps bracketed, the no-contact floor in closed form, random starts at the
peaks), to 1e-6 in theta. A peak is a settled motion's: a sample that did not settle within its
cap (``nonperiodic``: its max|x1| a transient's) is never the peak; it is counted beside it, with
the periods it ran (``unsettled_points``, ``unsettled``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from impactdamper.analysis.band_sweeps import BandSweeps, band_sweeps
from impactdamper.analysis.cycle_metrics import CycleMetrics, cycle_metrics
from impactdamper.analysis.ladder import solve_point
from impactdamper.analysis.linear_device import LinearDevice
from impactdamper.analysis.peaks import STEP, worst_branch
from impactdamper.analysis.point import FAILED, SweepSettings
from impactdamper.analysis.sweeps import with_value
from impactdamper.core.events import SearchLimitError
from impactdamper.core.parameters import Parameters, require_parameters
from impactdamper.core.validation import finite_argument, integer_argument

__all__ = [
    "frequency_response",
    "HYSTERESIS_TOL",
    "MAX_POINTS",
]

# Regimes whose sample is not a settled motion's (left out of the peak).
UNSETTLED = ("nonperiodic", FAILED)

# Two directions count as different motions (hysteresis) when their max|x1|/x_st differ by more
# than this, relative: the settled cycles agree to the settle tolerance (1e-9), and 1e-4 is well
# above that and the refinement of the maximum, yet far below a jump to another branch (>1e-2).
HYSTERESIS_TOL = 1e-4
# Bound on the number of theta values of one response (each is two settled motions and their
# cycles described: at the reference case on one core 1000 points take ~9 s with the location,
# 19 s when the response and the locator swept apart; the documented 10000 ran 6 minutes
# without a sign of life).
MAX_POINTS = 1_000


@dataclass(frozen=True)
class _ResponsePoint:
    """One forcing frequency: the motions of the upward and the downward sweep.

    Attributes
    ----------
    theta : float
    up, down : CycleMetrics
    hysteresis : bool
        The two directions settled on different motions (labels differ, or max|x1| by more
        than ``HYSTERESIS_TOL`` relative).
    linear_x1, linear_x2 : float
        |x1p_hat|/x_st and |x2p_hat|/x_st of the linear forced response without a stop (eq. 10).
    """

    theta: float
    up: CycleMetrics
    down: CycleMetrics
    hysteresis: bool
    linear_x1: float
    linear_x2: float

    @property
    def worst_x1(self) -> float:
        """The larger max|x1|/x_st of the two directions (a designer cannot pick the branch)."""
        known = [x for x in (self.up.max_abs_x1, self.down.max_abs_x1) if not math.isnan(x)]
        return float(max(known)) if known else math.nan  # (nan where both directions failed)

    @property
    def settled_x1(self) -> float:
        """The larger max|x1|/x_st of the directions that settled (nan where neither did)."""
        known = [m.max_abs_x1 for m in (self.up, self.down) if m.regime not in UNSETTLED and m.max_abs_x1 >= 0]
        return float(max(known)) if known else math.nan

    def to_dict(self) -> dict:
        return {
            "theta": self.theta,
            "up": self.up.to_dict(),
            "down": self.down.to_dict(),
            "hysteresis": self.hysteresis,
            "linear_max_abs_x1": self.linear_x1,
            "linear_max_abs_x2": self.linear_x2,
        }

    def rows(self) -> list[dict]:
        """Two flat CSV rows, one per direction."""
        out = []
        for direction, m in (("up", self.up), ("down", self.down)):
            out.append(
                {
                    "theta": self.theta,
                    "direction": direction,
                    **m.to_dict(),
                    "hysteresis": int(self.hysteresis),
                    "linear_max_abs_x1": self.linear_x1,
                    "linear_max_abs_x2": self.linear_x2,
                }
            )
        return out


@dataclass(frozen=True)
class _FrequencyResponse:
    """The frequency response over a theta grid (see :func:`frequency_response`).

    Attributes
    ----------
    p : Parameters
        The other parameters (its theta is not used).
    points : tuple of ResponsePoint
        In increasing theta.
    located : WorstBranch or None
        The worst branch over the band, located (None for a band of one theta).
    unsettled : tuple of dict
        The grid samples that did not settle (``theta``, ``source`` the direction, ``periods``
        run, ``max_abs_x1`` of the transient), left out of the peak. (The located search's own,
        :attr:`located`'s, are on the same sweeps: :meth:`unsettled_all` counts each sample once.)
    """

    p: Parameters = field(repr=False)
    points: tuple
    located: object = field(default=None, repr=False)
    unsettled: tuple = ()

    @property
    def thetas(self) -> np.ndarray:
        return np.array([q.theta for q in self.points])

    def worst_x1(self) -> np.ndarray:
        """max|x1|/x_st, the larger of the two directions, per theta. Shape (points,)."""
        return np.array([q.worst_x1 for q in self.points])

    def settled_x1(self) -> np.ndarray:
        """max|x1|/x_st, the larger of the settled directions, per theta (nan: neither settled)."""
        return np.array([q.settled_x1 for q in self.points])

    def grid_peak(self) -> float:
        """Largest max|x1|/x_st over the grid's settled samples, both directions (nan if none)."""
        y = self.settled_x1()
        return float(np.nanmax(y)) if np.any(np.isfinite(y)) else math.nan

    def peak(self) -> float:
        """The worst branch's peak over the band, located (never below the grid's largest
        settled sample; the grid's alone for a band of one theta; nan if nothing settled)."""
        both = [self.grid_peak()] + ([] if self.located is None else [self.located.settled_peak])
        return float(np.nanmax(both)) if np.any(np.isfinite(both)) else math.nan

    def peak_where(self) -> tuple[float, str]:
        """(theta, branch in words) of :meth:`peak`."""
        grid = self.grid_peak()
        top = None if self.located is None else self.located.settled
        if top is not None and not top.value < grid:
            return top.theta, f"{top.source}, {top.label}, {top.kind}"
        if math.isnan(grid):
            return math.nan, "none settled"
        i = int(np.nanargmax(self.settled_x1()))
        q = self.points[i]
        m = q.up if q.up.max_abs_x1 == q.settled_x1 and q.up.regime not in UNSETTLED else q.down
        return q.theta, ("up" if m is q.up else "down") + f", {m.label}, sample"

    def bound(self) -> float:
        """The conservative bound: the peak with every unsettled sample counted (the worst
        branch's :attr:`~impactdamper.analysis.peaks.WorstBranch.peak`, the grid's samples)."""
        both = [np.nanmax(self.worst_x1())] + ([] if self.located is None else [self.located.peak])
        return float(np.nanmax(both))

    def unsettled_all(self) -> list[dict]:
        """Every sample left out of the peak: the grid's and the located search's, each once
        (the search's sweeps are the grid's: a sample at a grid theta is the grid's)."""
        seen = {(u["theta"], u["source"]) for u in self.unsettled}
        more = [] if self.located is None else self.located.unsettled
        return list(self.unsettled) + [u for u in more if (u["theta"], u["source"]) not in seen]

    def band_average(self) -> float:
        """Trapezoidal mean over theta of the worst settled max|x1|/x_st (the unsettled sample
        where neither direction settled; the grid's first point alone if it has one)."""
        x, y = self.thetas, self.settled_x1()
        y = np.where(np.isnan(y), self.worst_x1(), y)
        if len(x) == 1:
            return float(y[0])
        return float(np.trapezoid(y, x) / (x[-1] - x[0]))

    def loads(self) -> dict:
        """Largest peak pulse and impacts per period over the grid and both directions."""
        ms = [m for q in self.points for m in (q.up, q.down)]
        return {
            "peak_impulse": float(np.nanmax([m.peak_impulse for m in ms])),
            "impacts_per_period": float(np.nanmax([m.impacts_per_period for m in ms])),
        }

    def to_dict(self) -> dict:
        """The JSON object of ``python -m impactdamper response --json``."""
        theta, branch = self.peak_where()
        unsettled = self.unsettled_all()
        return {
            "parameters": self.p.to_dict(),
            "peak_max_abs_x1": _or_none(self.peak()),
            "peak_theta": _or_none(theta),
            "peak_branch": branch,
            "grid_peak_max_abs_x1": _or_none(self.grid_peak()),
            "no_contact_floor": None if self.located is None else self.located.floor.value,
            "band_average_max_abs_x1": self.band_average(),
            **self.loads(),
            "hysteresis_points": int(sum(q.hysteresis for q in self.points)),
            # theta values where a sweep direction failed: the peak and loads are over the others
            "failed_points": int(sum(q.up.regime == FAILED or q.down.regime == FAILED for q in self.points)),
            # samples that did not settle within their cap, left out of the peak (their max|x1| a transient's)
            "unsettled_points": len(unsettled),
            "peak_including_unsettled": self.bound(),
            "unsettled": unsettled,
            "points": [q.to_dict() for q in self.points],
        }

    def rows(self) -> list[dict]:
        return [r for q in self.points for r in q.rows()]


def _theta_grid(theta_start: object, theta_stop: object, points: object) -> np.ndarray:
    """``points`` equally spaced theta values from ``theta_start`` to ``theta_stop``, checked.

    Raises
    ------
    ValueError, TypeError
        One line naming the argument: theta must be finite and > 0, the stop above the start
        (or equal with one point), and 1 <= points <= ``MAX_POINTS``.
    """
    a = finite_argument("theta_start", theta_start)
    b = finite_argument("theta_stop", theta_stop)
    n = integer_argument("points", points, 1, MAX_POINTS)
    if not a > 0:
        raise ValueError(f"`theta_start` = {a!r} is not allowed: must be > 0")
    if n == 1 and b != a:
        raise ValueError(f"`theta_stop` = {b!r} is not allowed with points = 1: must equal theta_start = {a!r}")
    if n > 1 and not b > a:
        raise ValueError(f"`theta_stop` = {b!r} is not allowed: must be > theta_start = {a!r}")
    return np.linspace(a, b, n)


def _or_none(x: float) -> float | None:
    return None if math.isnan(x) else x


def _unsettled(sweep: dict) -> tuple:
    """The sweep points that did not settle, as :attr:`FrequencyResponse.unsettled` lists them."""
    return tuple(
        {"theta": float(q.value), "source": d, "periods": int(q.periods), "max_abs_x1": float(q.x1_max)}
        for d in ("up", "down")
        for q in sweep[d]
        if q.regime == "nonperiodic"
    )


def _differ(a: CycleMetrics, b: CycleMetrics, tol: float) -> bool:
    if a.label != b.label:
        return True
    if not (math.isfinite(a.max_abs_x1) and math.isfinite(b.max_abs_x1)):
        return False
    return abs(a.max_abs_x1 - b.max_abs_x1) > tol * max(abs(a.max_abs_x1), abs(b.max_abs_x1), 1e-300)


def frequency_response(
    p: Parameters,
    theta_start: float = 0.5,
    theta_stop: float = 1.5,
    points: int = 41,
    *,
    settings: SweepSettings | None = None,
    hysteresis_tol: float = HYSTERESIS_TOL,
    progress: Callable[[str], None] | None = None,
    on_point: Callable[[], None] | None = None,
    locate: bool = True,
) -> _FrequencyResponse:
    """Settled motion against theta, by an upward and a downward sweep, with its metrics.

    Parameters
    ----------
    p : Parameters
        The other parameters (its own theta is ignored).
    theta_start, theta_stop : float
        The band, omega/omega1 (> 0, stop > start).
    points : int
        Number of equally spaced theta values (1 to ``MAX_POINTS``).
    settings : SweepSettings, optional
        How each point is settled.
    hysteresis_tol : float
        Relative difference of max|x1| above which the two directions differ (> 0).
    progress : callable(str), optional
        Called with a one-line message after each direction and every ~10 % of the points.
    on_point : callable(), optional
        Called after each settled motion of the two sweeps is described (``2 points`` calls in
        all), for a progress bar (:mod:`impactdamper.reporting.progress`); the sweeps themselves
        run in one batch call before.
    locate : bool
        Locate the worst branch over the band (:func:`impactdamper.analysis.peaks.worst_branch`,
        with the same settings) on the same sweeps; False: the grid's largest sample is the peak.

    The two sweeps run once, in one batch call (:func:`impactdamper.analysis.band_sweeps.band_sweeps`):
    on the locator's grid (steps of at most :data:`~impactdamper.analysis.peaks.STEP`) with the
    response's thetas added, with or without ``locate`` (the table does not depend on it); the
    table's rows are the sweeps' points at the response's thetas.

    Returns
    -------
    FrequencyResponse

    Raises
    ------
    ValueError, TypeError
        A bad argument, in one line naming it.
    SearchLimitError
        Every point of both sweeps failed (the solver's work bound at every theta): the first
        point's line, naming its cause.
    """
    p = require_parameters(p)
    thetas = _theta_grid(theta_start, theta_stop, points)
    tol = finite_argument("hysteresis_tol", hysteresis_tol)
    if not tol > 0:
        raise ValueError(f"`hysteresis_tol` = {tol!r} is not allowed: must be > 0")
    if settings is not None and not isinstance(settings, SweepSettings):
        raise TypeError(f"`settings` = {settings!r} is not allowed: must be a SweepSettings")
    for end in (thetas[0], thetas[-1]):  # an invalid combination fails here, named, before the sweep
        with_value(p, "theta", end)
    settings = settings or SweepSettings()
    band = (float(thetas[0]), float(thetas[-1]))
    sweeps = band_sweeps([p], [band], step=STEP, thetas=[thetas], settings=settings)
    sweep = sweeps.points(0, thetas)
    _all_failed(p, thetas, sweep, settings)
    if progress is not None:
        progress(
            f"theta sweeps done ({len(sweeps.grids[0])} points each, {len(thetas)} of them the response's): "
            f"{sweeps.result.elapsed:.2f} s"
        )
    linear = LinearDevice.of(p)
    lin1, lin2 = linear.amplitude(thetas), linear.absorber(thetas)
    out = _response_points(thetas, sweep, tol, (lin1, lin2), progress, on_point)
    located = _located(p, sweeps, thetas, settings, progress) if locate and len(thetas) > 1 else None
    return _FrequencyResponse(p, tuple(out), located, _unsettled(sweep))


def _all_failed(p: Parameters, thetas, sweep: dict, settings: SweepSettings) -> None:
    """Raise SearchLimitError if every point of both sweeps failed, with the first point's line
    (the upward sweep's first, from Algorithm No. 2's step 1, settled again alone for its line:
    the batch keeps a failed point's cause in its log only)."""
    if not all(q.regime == FAILED for q in sweep["up"] + sweep["down"]):
        return
    first = solve_point(with_value(p, "theta", thetas[0]), float(thetas[0]), None, settings=settings)
    raise SearchLimitError(f"every point of the response failed (the first at theta = {thetas[0]:.6g}): {first.error}")


def _response_points(thetas, sweep: dict, tol: float, linear, progress, on_point) -> list[_ResponsePoint]:
    """Each theta's two settled cycles described, their hysteresis and the linear response
    (``on_point`` called after each cycle)."""
    lin1, lin2 = linear
    out = []
    every = max(len(thetas) // 10, 1)
    for i, (theta, up, down) in enumerate(zip(thetas, sweep["up"], sweep["down"])):
        mu = cycle_metrics(up)
        if on_point is not None:
            on_point()
        md = cycle_metrics(down)
        if on_point is not None:
            on_point()
        out.append(_ResponsePoint(float(theta), mu, md, _differ(mu, md, tol), float(lin1[i]), float(lin2[i])))
        if progress is not None and ((i + 1) % every == 0 or i + 1 == len(thetas)):
            progress(
                f"metrics {i + 1}/{len(thetas)}: theta = {theta:.4g}, {up.label}/{down.label}, "
                f"max|x1|/x_st = {mu.max_abs_x1:.4g}/{md.max_abs_x1:.4g}"
            )
    return out


def _located(p: Parameters, sweeps: BandSweeps, thetas, settings, progress):
    """The worst branch over the band (:func:`impactdamper.analysis.peaks.worst_branch`),
    located on the response's own sweeps."""
    located = worst_branch(p, sweeps.bands[0], thetas=thetas, settings=settings, sweeps=sweeps)
    if progress is not None:
        progress(
            f"worst branch located: {located.settled_peak:.8g} over the settled motions, {located.peak:.8g} with "
            f"{len(located.unsettled)} unsettled samples counted ({located.branch()})"
        )
    return located
