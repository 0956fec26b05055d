"""Frequency response: the settled motion against the forcing frequency theta = omega/omega1.

The paper's motivation (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100,
introduction) is an object whose forcing frequency varies; its figures fix theta = 1. This
module sweeps theta upward and downward (each point started from its neighbour's settled
motion, :func:`impactdamper.analysis.sweeps.two_way_sweep`), and describes every settled cycle
by what a designer needs:

* ``max_abs_x1``, ``max_abs_x2``: the largest |x1| and |x2| over the cycle, over x_st. Here x2
  is the suppressor's displacement in the model's coordinates (zero where its spring c2 is
  unstretched with the object at rest, eqs. 2 and 9), not the paper's x2_bar = (x2 - Delta0)/x_st,
  which is shifted by the gap;
* impacts per forcing period, mean and peak pulse per impact S = m1 m2/(m1 + m2) (1 + R) v
  (eq. 21; equal to m2 times the jump of the suppressor's velocity), over m1 x_st omega;
* energy per forcing period, over c1 x_st^2: put in by the force P0 sin(omega t), lost at the
  impacts (kinetic energy, eqs. 21-22, and the plastic capture ending a chatter), and dissipated
  by the dampers k1 and k2 (integral of k1 x1'^2 + k2 (x2' - x1')^2). Over a settled cycle the
  input equals the two losses; ``balance`` is the mismatch, including the change of mechanical
  energy over the window, which a settled cycle leaves at the settle tolerance;
* whether the upward and downward sweeps settle on different motions (hysteresis).

The exact linear response without a stop (eq. 10) is given beside it, in closed form
(:class:`impactdamper.analysis.linear_device.LinearDevice`). The peak
over the band is not the grid's largest sample but the worst branch located
(:func:`impactdamper.analysis.peaks.worst_branch`: every branch a slow sweep in either
direction follows, jumps bracketed, the no-contact floor in closed form, random starts at the
peaks), to 1e-6 in theta. A peak is a settled motion's: a sample that did not settle within its
cap (``nonperiodic``: its max|x1| a transient's) is never the peak; it is counted beside it, with
the periods it ran (``unsettled_points``, ``unsettled``).

The cycle is read from a fresh event-driven run of one cycle from the sweep point's section
state (t = n T, forcing phase zero): the sweep point keeps that state, not the trajectory.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from collections.abc import Callable, Sequence

import numpy as np

from impactdamper.analysis.linear_device import LinearDevice
from impactdamper.analysis.point import FAILED, SweepPoint, SweepSettings
from impactdamper.analysis.sweeps import two_way_sweep, with_value
from impactdamper.core.events import SearchLimitError
from impactdamper.core.parameters import Parameters, require_parameters
from impactdamper.core.validation import finite_argument, integer_argument
from impactdamper.core.simulate import EventDrivenSolver, Trajectory

__all__ = [
    "_CycleMetrics",
    "_ResponsePoint",
    "_FrequencyResponse",
    "_cycle_metrics",
    "frequency_response",
    "_theta_grid",
    "_energy_balance",
    "HYSTERESIS_TOL",
    "MAX_POINTS",
]

# Regimes whose sample is not a settled motion's (left out of the peak).
UNSETTLED = ("nonperiodic", FAILED)

# Two directions count as different motions (hysteresis) when their max|x1|/x_st differ by more
# than this, relative: the settled cycles agree to the settle tolerance (1e-9), and 1e-4 is well
# above that and the refinement of the maximum, yet far below a jump to another branch (>1e-2).
HYSTERESIS_TOL = 1e-4
# Gauss-Legendre nodes per quadrature piece; a piece spans at most QUAD_PIECES_PER_PERIOD-th of a
# period of one smooth mode, where the integrands (sums of exponentials and sinusoids of
# frequency <= 2 max(omega, omega2)) are resolved to rounding with 16 nodes.
QUAD_NODES = 16
QUAD_PIECES_PER_PERIOD = 16
# Samples per forcing period when searching the largest |x1| and |x2| (then refined locally).
SAMPLES_PER_PERIOD = 512
# Forcing periods read for a motion that did not settle (the window steady_state describes).
NONPERIODIC_PERIODS = 8
# Bound on the number of theta values of one response (each is two settled motions, ~40 ms
# together at the reference case on one core: 1000 points take ~40 s, the documented 10000 ran
# 6 minutes without a sign of life).
MAX_POINTS = 1_000


@dataclass(frozen=True)
class _CycleMetrics:
    """What one settled cycle does, in relative units.

    Attributes
    ----------
    regime, label : str
        As in :class:`~impactdamper.analysis.point.SweepPoint` (``failed`` gives nan metrics).
    period_multiple : int
        k in T_c = k T (0 when nonperiodic: the metrics then cover ``NONPERIODIC_PERIODS`` T).
    max_abs_x1, max_abs_x2 : float
        max |x1|/x_st and max |x2|/x_st over the cycle.
    impacts_per_period : float
        Impacts in the cycle over k.
    mean_impulse, peak_impulse : float
        Mean and largest pulse per impact, S/(m1 x_st omega) (0 without impacts).
    energy_input, energy_impacts, energy_dampers : float
        Per forcing period, over c1 x_st^2.
    balance : float
        |input - impacts - dampers - change of mechanical energy| over the cycle, relative to the
        input (or to c1 x_st^2 if the input is smaller): the quadrature's check, ~1e-12.
    drift : float
        Change of mechanical energy over the cycle over c1 x_st^2 (a settled cycle: ~settle_tol).
    """

    regime: str
    label: str
    period_multiple: int
    max_abs_x1: float
    max_abs_x2: float
    impacts_per_period: float
    mean_impulse: float
    peak_impulse: float
    energy_input: float
    energy_impacts: float
    energy_dampers: float
    balance: float
    drift: float

    def to_dict(self) -> dict:
        return {name: getattr(self, name) for name in self.__dataclass_fields__}


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
    up: _CycleMetrics
    down: _CycleMetrics
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
        run, ``max_abs_x1`` of the transient), left out of the peak.
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
        """Every sample left out of the peak: the grid's and the located search's."""
        return list(self.unsettled) + ([] if self.located is None else list(self.located.unsettled))

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


def _pieces(a: float, b: float, cuts: Sequence[float], longest: float) -> list[tuple[float, float]]:
    """[a, b] split at ``cuts`` (segment starts, events) and into pieces no longer than ``longest``."""
    edges = sorted({a, b, *[c for c in cuts if a < c < b]})
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        n = max(int(math.ceil((hi - lo) / longest)), 1)
        e = np.linspace(lo, hi, n + 1)
        out.extend(zip(e[:-1], e[1:]))
    return out


def _energy_balance(traj: Trajectory, a: float, b: float) -> dict:
    """Work and dissipation over [a, b] of a trajectory, J (dimensional).

    Each piece of one mode between events is integrated by Gauss-Legendre quadrature of
    ``QUAD_NODES`` nodes, spanning at most T/``QUAD_PIECES_PER_PERIOD``: the integrands are
    smooth there, so the quadrature is exact to rounding.

    Returns
    -------
    dict
        ``input`` (integral of P0 sin(omega t) x1'), ``dampers`` (integral of k1 x1'^2 +
        k2 (x2' - x1')^2), ``impacts`` (kinetic energy lost at the impacts and captures in
        [a, b)), ``drift`` (mechanical energy at b minus at a), ``impulses`` (the impacts'
        pulses, N s).
    """
    model = traj.model
    p = model.p
    starts = [seg.t0 for _, seg in traj.segments]
    events = [e for e in traj.events if a <= e.t < b]
    nodes, weights = np.polynomial.legendre.leggauss(QUAD_NODES)
    pieces = np.array(_pieces(a, b, starts + [e.t for e in events], p.T / QUAD_PIECES_PER_PERIOD))
    # Every piece's nodes in one sample call (the nodes are interior, so each falls in its piece's
    # segment); summed piece by piece in order, as a loop over the pieces would.
    lo, hi = pieces[:, :1], pieces[:, 1:]
    t = 0.5 * (hi + lo) + 0.5 * (hi - lo) * nodes[None, :]
    full, _ = traj.sample(t.ravel())
    v1, v2 = full[:, 2].reshape(t.shape), full[:, 3].reshape(t.shape)
    w = 0.5 * (hi - lo) * weights[None, :]
    work = dissipated = 0.0
    for piece_work, piece_dissipated in zip(
        np.sum(w * p.P0 * np.sin(p.omega * t) * v1, axis=1),
        np.sum(w * (p.k1 * v1 * v1 + p.k2 * (v2 - v1) ** 2), axis=1),
    ):
        work += float(piece_work)
        dissipated += float(piece_dissipated)
    lost = float(sum(model.energy(e.before) - model.energy(e.after) for e in events))
    ends, _ = traj.sample(np.array([a, b]))
    drift = float(model.energy(ends[1]) - model.energy(ends[0]))
    return {
        "input": work,
        "dampers": dissipated,
        "impacts": lost,
        "drift": drift,
        "impulses": [e.impulse for e in events if e.kind == "impact"],
    }


def _largest(traj: Trajectory, a: float, b: float, column: int) -> float:
    """max |state[column]| on [a, b]: dense samples, refined in the segment of the largest."""
    p = traj.model.p
    n = max(int(SAMPLES_PER_PERIOD * (b - a) / p.T), 64)
    ts = np.linspace(a, b, n + 1)
    values = np.abs(traj.sample(ts)[0][:, column])
    i = int(np.argmax(values))
    best = float(values[i])
    lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, n)]
    k = int(traj.segment_index(np.array([ts[i]]))[0])
    name, seg = traj.segments[k]
    seg_end = traj.segments[k + 1][1].t0 if k + 1 < len(traj.segments) else math.inf
    lo, hi = max(lo, seg.t0), min(hi, seg_end)
    if hi > lo:

        def f(t):
            return -abs(float(traj.model.full_state(name, seg.state(float(t)))[column]))

        import scipy.optimize  # (loaded on first use: the package import stays light)

        res = scipy.optimize.minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-12 * p.T})
        best = max(best, -float(res.fun))
    return best


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


def _nan_metrics(point: SweepPoint) -> _CycleMetrics:
    nan = math.nan
    return _CycleMetrics(
        point.regime, point.label, point.period_multiple, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan
    )


def _cycle_metrics(point: SweepPoint) -> _CycleMetrics:
    """Describe the settled cycle of a sweep point (see the module docstring).

    The cycle is simulated afresh from ``point.section`` at t0 = 0 (the section is at forcing
    phase zero) for k periods (``NONPERIODIC_PERIODS`` if the point did not settle).

    Parameters
    ----------
    point : SweepPoint

    Returns
    -------
    CycleMetrics
        nan metrics for a point whose simulation failed (regime ``failed``).
    """
    if point.regime == FAILED:
        return _nan_metrics(point)
    p = point.p
    k = point.period_multiple if point.periodic and point.period_multiple > 0 else NONPERIODIC_PERIODS
    solver = EventDrivenSolver(p, t0=0.0, state=np.array(point.section, float))
    end = k * p.T
    solver.advance(end)
    traj = solver.trajectory
    x1 = _largest(traj, 0.0, end, 0) / p.x_st
    x2 = _largest(traj, 0.0, end, 1) / p.x_st
    e = _energy_balance(traj, 0.0, end)
    unit_e = p.c1 * p.x_st * p.x_st
    unit_s = p.m1 * p.x_st * p.omega
    pulses = np.array(e["impulses"]) / unit_s
    residual = abs(e["input"] - e["impacts"] - e["dampers"] - e["drift"]) / max(abs(e["input"]), unit_e)
    return _CycleMetrics(
        regime=point.regime,
        label=point.label,
        period_multiple=point.period_multiple,
        max_abs_x1=x1,
        max_abs_x2=x2,
        impacts_per_period=len(pulses) / k,
        mean_impulse=float(pulses.mean()) if len(pulses) else 0.0,
        peak_impulse=float(pulses.max()) if len(pulses) else 0.0,
        energy_input=e["input"] / unit_e / k,
        energy_impacts=e["impacts"] / unit_e / k,
        energy_dampers=e["dampers"] / unit_e / k,
        balance=float(residual),
        drift=e["drift"] / unit_e,
    )


def _differ(a: _CycleMetrics, b: _CycleMetrics, tol: float) -> bool:
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
        Called after each settled point of the two sweeps (``2 points`` calls in all), for a
        progress bar (:mod:`impactdamper.reporting.progress`).
    locate : bool
        Locate the worst branch over the band (:func:`impactdamper.analysis.peaks.worst_branch`,
        with the same settings); False: the grid's largest sample is the peak.

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
    with_value(p, "theta", thetas[0])  # an invalid combination fails here, named, before the sweep
    sweep = two_way_sweep(p, "theta", thetas, settings=settings, on_point=on_point)
    failed = [q for q in sweep["up"] + sweep["down"] if q.regime == FAILED]
    if len(failed) == 2 * len(thetas):
        first = min(failed, key=lambda q: q.value)
        raise SearchLimitError(
            f"every point of the response failed (the first at theta = {first.value:.6g}): {first.error}"
        )
    if progress is not None:
        progress(
            f"theta sweeps done ({len(thetas)} points each): up {sweep['cpu']['up']:.2f} s, "
            f"down {sweep['cpu']['down']:.2f} s processor time"
        )
    linear = LinearDevice.of(p)
    lin1, lin2 = linear.amplitude(thetas), linear.absorber(thetas)
    out = []
    every = max(len(thetas) // 10, 1)
    for i, (theta, up, down) in enumerate(zip(thetas, sweep["up"], sweep["down"])):
        mu, md = _cycle_metrics(up), _cycle_metrics(down)
        out.append(_ResponsePoint(float(theta), mu, md, _differ(mu, md, tol), float(lin1[i]), float(lin2[i])))
        if progress is not None and ((i + 1) % every == 0 or i + 1 == len(thetas)):
            progress(
                f"metrics {i + 1}/{len(thetas)}: theta = {theta:.4g}, {up.label}/{down.label}, "
                f"max|x1|/x_st = {mu.max_abs_x1:.4g}/{md.max_abs_x1:.4g}"
            )
    located = None
    if locate and len(thetas) > 1:
        from impactdamper.analysis.peaks import worst_branch

        located = worst_branch(p, (float(thetas[0]), float(thetas[-1])), settings=settings)
        if progress is not None:
            progress(
                f"worst branch located: {located.settled_peak:.8g} over the settled motions, {located.peak:.8g} with "
                f"{len(located.unsettled)} unsettled samples counted ({located.branch()})"
            )
    return _FrequencyResponse(p, tuple(out), located, _unsettled(sweep))
