"""What one settled cycle of a frequency response does: its excursions, loads and energies.

A cycle (:func:`cycle_metrics`) is read from a fresh event-driven run of one cycle from a sweep
point's section state (t = n T, forcing phase zero; the sweep point keeps that state, not the
trajectory), and described by what a designer needs (:class:`CycleMetrics`):

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
  energy over the window, which a settled cycle leaves at the settle tolerance.

:mod:`~impactdamper.analysis.response` gathers them over a band, both sweep directions.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from impactdamper.analysis.point import FAILED, SweepPoint
from impactdamper.core.simulate import EventDrivenSolver, Trajectory

# Gauss-Legendre nodes per quadrature piece; a piece spans at most QUAD_PIECES_PER_PERIOD-th of a
# period of one smooth mode, where the integrands (sums of exponentials and sinusoids of
# frequency <= 2 max(omega, omega2)) are resolved to rounding with 16 nodes.
QUAD_NODES = 16
QUAD_PIECES_PER_PERIOD = 16
# Samples per forcing period when searching the largest |x1| and |x2| (then refined locally).
SAMPLES_PER_PERIOD = 512
# Forcing periods read for a motion that did not settle (the window steady_state describes).
NONPERIODIC_PERIODS = 8


@dataclass(frozen=True)
class CycleMetrics:
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


def _nan_metrics(point: SweepPoint) -> CycleMetrics:
    nan = math.nan
    return CycleMetrics(
        point.regime, point.label, point.period_multiple, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan
    )


def cycle_metrics(point: SweepPoint) -> CycleMetrics:
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
    return CycleMetrics(
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
