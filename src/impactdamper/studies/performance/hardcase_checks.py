"""The hard cases' checks (:mod:`impactdamper.studies.performance.hardcases`): what a run of
the settled-motion search must satisfy, each check with its tolerances.

``terminated``
    The run ended (``max_periods`` bounds it; a wall-clock guard turns a hang into a failure)
    with one of :data:`impactdamper.REGIMES`.
``gap_nonnegative``
    Between events the gap never goes below zero: every free segment of the whole run is
    sampled (32 points per period, at least 4) and every sampled local minimum refined;
    the minimum must be >= -``GAP_CHECK_TOL`` (x_st + |Delta0|), less what the time
    resolution makes unavoidable (a few ulps of t times the gap's rate). In contact, the
    contact force is likewise checked non-negative.
``impact_law``
    At every impact: the gap is zero, the closing velocity non-negative, the relative velocity
    becomes -R times itself, momentum is conserved, energy does not rise; at every capture
    (``stick``) momentum is conserved and the relative velocity vanishes; at every lift-off
    the contact force is zero.
``reference``
    Agreement with an independent computation: the solve_ivp cross-check
    (:func:`impactdamper.baselines.ivp.simulate_ivp`, DOP853, rtol = atol = 1e-10) from the same
    start over a window (the same events, the same states), and, where there is one, the
    high-precision closed form (:mod:`impactdamper.baselines.highprecision`): the settled one-impact
    orbit (mpmath fixed point), the no-contact or stuck forced response, or the grazing
    tangency's time (the solve_ivp window then ends before the touch: after a touch the
    motion depends on how deep the rounding let the gap dip, ~sqrt(1e-15) in velocity).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.optimize

from impactdamper.baselines import highprecision as hp
from impactdamper.baselines.ivp import simulate_ivp
from impactdamper.core.algorithm1 import algorithm1
from impactdamper.core.impact_law import rebound
from impactdamper.core.model import FREE
from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import simulate

__all__ = [
    "check_gap_nonnegative",
    "check_impact_law",
    "check_reference",
    "steady_end_time",
]

# Gap overlap tolerated by the check, relative to x_st + |Delta0|: the solver's grazing
# resolution is 1e-12 x_st, and rounding of x2 - x1 grows with |Delta0|.
GAP_CHECK_TOL = 1e-9
# Time resolution allowed for in the gap check: a few ulps of t times the gap's rate.
TIME_ULPS = 8
# Impact-law tolerances, relative to the closing velocity's scale / the energy.
LAW_TOL = 1e-10
# Sampling of free segments for the gap check.
GAP_SAMPLES_PER_PERIOD = 32
# Agreement with the solve_ivp cross-check (rtol = atol = 1e-10): event times in units of T,
# states relative to their scale. Far above the cross-check's error (~1e-9), far below any
# change of the motion.
IVP_RTOL = 1e-10
IVP_TIME_TOL = 1e-6
IVP_STATE_TOL = 1e-5
# Agreement with the high-precision closed form: the settled phase is converged to the
# steady state's settle_tol (1e-10); a grazing touch's time is ill-conditioned (a square
# root of the rounding of the gap), 1e-6 T is generous.
MP_PHASE_TOL = 1e-9
# The settled amplitude, in x_st: the steady state stops when sections repeat to settle_tol
# (1e-10) per period; with a slow contraction (theta = 10: 3 % per period in contact) the
# distance left to the orbit is ~settle_tol / 0.03 ~ 3e-9.
MP_AMPLITUDE_TOL = 1e-7
TOUCH_TIME_TOL = 1e-6
# A touch: an impact whose closing velocity is below this (relative to x_st omega).
TOUCH_VELOCITY = 1e-4


def _segment_ends(traj, t_end: float) -> list[float]:
    starts = [seg.t0 for _, seg in traj.segments]
    return starts[1:] + [max(t_end, starts[-1])]


def steady_end_time(s) -> float:
    """Where :func:`steady_state`'s run stopped: its last stroboscopic section. (Its
    ``trajectory`` holds only the reported cycle's window, re-simulated with the clock near
    t0; the checks here replay the whole run from the start instead, see :func:`~.hardcases.run_case`.)"""
    return float(s.section_times[-1])


def check_gap_nonnegative(traj, t_end: float) -> tuple[bool, float]:
    """Smallest gap over every free segment up to ``t_end`` (where the solver stopped; events
    beyond it were not processed), relative to x_st + |Delta0|, and smallest contact force
    over every stuck segment, relative to the model's force scale: (ok, worst).

    Allowed below zero: ``GAP_CHECK_TOL`` plus what the time resolution makes unavoidable,
    ``TIME_ULPS`` ulp(t) times the largest rate of the segment (at t ~ 2400 s and a closing
    velocity of 750 m/s, as in the conservative case, that is 3e-10 m)."""
    model = traj.model
    p = model.p
    length = p.x_st + abs(p.Delta0)
    T = p.T
    worst = math.inf
    ok = True
    for (mode, seg), end in zip(traj.segments, _segment_ends(traj, t_end)):
        if end <= seg.t0:
            continue
        n = max(int(math.ceil(GAP_SAMPLES_PER_PERIOD * (end - seg.t0) / T)), 4)
        ts = np.linspace(seg.t0, end, n + 1)
        ys = seg.state(ts)
        if mode == FREE:

            def value(t, seg=seg):
                return float(model.gap_of(seg.state(t))) / length

            vals = model.gap_of(ys) / length
            rate = float(np.max(np.abs(ys[:, 2] - ys[:, 3]))) / length
        else:
            fn = model.contact_force

            def value(t, seg=seg, fn=fn):
                return float(fn.of_state(t, seg.state(t))) / model.force_scale

            vals = np.array([fn.of_state(t, y) for t, y in zip(ts, ys)]) / model.force_scale
            rate = float(np.max(np.abs([fn.of_state(t, y, 1) for t, y in zip(ts, ys)]))) / model.force_scale
        low = float(np.min(vals))
        inner = np.flatnonzero((vals[1:-1] <= vals[:-2]) & (vals[1:-1] <= vals[2:])) + 1
        for k in inner:
            res = scipy.optimize.minimize_scalar(
                value, bounds=(ts[k - 1], ts[k + 1]), method="bounded", options={"xatol": 1e-13 * T}
            )
            low = min(low, float(res.fun))
        worst = min(worst, low)
        ok &= low >= -(GAP_CHECK_TOL + TIME_ULPS * math.ulp(max(abs(end), abs(seg.t0))) * rate)
    return bool(ok), worst


def check_impact_law(traj) -> tuple[bool, dict]:
    """Every event obeys its law; returns (ok, worst residual per law)."""
    model = traj.model
    p = model.p
    vscale = p.x_st * max(p.omega, p.omega1, p.omega2)
    length = p.x_st + abs(p.Delta0)
    worst = {"gap": 0.0, "restitution": 0.0, "momentum": 0.0, "energy_rise": 0.0, "closing": 0.0, "liftoff_force": 0.0}

    def momentum(y):
        return p.m1 * y[2] + p.m2 * y[3]

    for e in traj.events:
        b, a = np.asarray(e.before), np.asarray(e.after)
        mscale = p.m1 * (abs(b[2]) + vscale) + p.m2 * (abs(b[3]) + vscale)
        escale = float(model.energy(b)) + p.m1 * vscale**2
        if e.kind in ("impact", "stick"):
            worst["gap"] = max(worst["gap"], abs(float(model.gap_of(b))) / length)
            worst["momentum"] = max(worst["momentum"], abs(momentum(a) - momentum(b)) / mscale)
            worst["energy_rise"] = max(worst["energy_rise"], (float(model.energy(a)) - float(model.energy(b))) / escale)
        if e.kind == "impact":
            v = b[3] - b[2]
            worst["closing"] = max(worst["closing"], -v / vscale)
            worst["restitution"] = max(worst["restitution"], abs((a[3] - a[2]) + rebound(p, v)) / vscale)
        elif e.kind == "stick":
            worst["restitution"] = max(worst["restitution"], abs(a[3] - a[2]) / vscale)
        elif e.kind == "liftoff":
            F = model.force_in_contact(e.t, b)
            worst["liftoff_force"] = max(worst["liftoff_force"], abs(F) / model.force_scale)
    ok = (
        worst["gap"] <= GAP_CHECK_TOL
        and all(worst[k] <= LAW_TOL for k in ("momentum", "restitution", "closing"))
        and worst["energy_rise"] <= LAW_TOL
        and worst["liftoff_force"] <= 1e-8
    )
    return ok, worst


def _state_scale(states: np.ndarray, p: Parameters) -> np.ndarray:
    pos = max(p.x_st, float(np.max(np.abs(states[:, :2]))))
    vel = max(p.x_st * p.omega, float(np.max(np.abs(states[:, 2:]))))
    return np.array([pos, pos, vel, vel])


def _compare_with_ivp(p: Parameters, t0: float, state, t_end: float) -> tuple[bool, dict]:
    """Exact solver against the solve_ivp cross-check over [t0, t_end]: event kinds and times,
    and states on a grid (away from events, where velocities jump)."""
    exact = simulate(p, t_end, t0=t0, state=state)
    ivp = simulate_ivp(p, t_end, t0=t0, state=state, method="DOP853", rtol=IVP_RTOL, atol=IVP_RTOL * p.x_st)
    ev_a = [(e.kind, e.t) for e in exact.events]
    ev_b = [(e.kind, e.t) for e in ivp.events]
    info = {"events_exact": len(ev_a), "events_ivp": len(ev_b)}
    if [k for k, _ in ev_a] != [k for k, _ in ev_b]:
        info["mismatch"] = "event sequences differ"
        return False, info
    dt = max((abs(a[1] - b[1]) for a, b in zip(ev_a, ev_b)), default=0.0) / p.T
    ts = np.linspace(t0, t_end, max(int(200 * (t_end - t0) / p.T), 50) + 1)
    times = np.array([t for _, t in ev_a])
    if times.size:
        near = np.min(np.abs(ts[:, None] - times[None, :]), axis=1) < 1e-4 * p.T
        ts = ts[~near]
    ya, _ = exact.sample(ts)
    yb, _ = ivp.sample(ts)
    scale = _state_scale(ya, p)
    dy = float(np.max(np.abs(ya - yb) / scale)) if ts.size else 0.0
    info.update(event_time_diff=dt, state_diff=dy)
    return dt <= IVP_TIME_TOL and dy <= IVP_STATE_TOL, info


def _first_touch(traj, p: Parameters):
    vscale = p.x_st * p.omega
    for e in traj.events:
        if e.kind == "impact" and e.velocity < TOUCH_VELOCITY * vscale:
            return e
    return None


def check_reference(case, p: Parameters, t0: float, state, s, traj) -> tuple[bool, dict]:
    """The high-precision check that applies to ``case`` (a :class:`~.hardcases.HardCase`: its
    start and window), and the solve_ivp window (``traj``: the whole run from the start)."""
    info: dict = {}
    ok = True
    kinds = []
    T = p.T
    window_end = t0 + case.window * T
    if case.start in ("forced_orbit", "alg1_orbit"):
        # Grazing: the first touch must be at the tangency of the closed-form motion (mpmath).
        kinds.append("mp tangency")
        touch = _first_touch(traj, p)
        if touch is None:
            return False, {"reference_kind": "mp tangency", "mismatch": "no touch found"}
        lo, hi = touch.t - 1e-3 * T, touch.t + 1e-3 * T
        t_min, g_min = hp.gap_minimum(p, t0, state, lo, hi)
        dt = abs(touch.t - float(t_min)) / T
        info.update(touch_time_diff=dt, mp_gap_min=float(g_min) / p.x_st)
        ok &= dt <= TOUCH_TIME_TOL and abs(float(g_min)) <= 1e-10 * (p.x_st + abs(p.Delta0))
        window_end = min(window_end, touch.t - 0.01 * T)
    if s.regime == "single_impact":
        a1 = algorithm1(p)
        if a1.admissible:
            kinds.append("mp settled cycle")
            cyc = hp.settled_cycle(p)
            d = abs((s.impacts[0].phase - float(cyc.impact_phase) + 0.5) % 1.0 - 0.5)
            info["settled_phase_diff"] = d
            ok &= d <= MP_PHASE_TOL
    elif s.regime in ("no_contact", "stuck"):
        kinds.append("mp forced response")
        amp = hp.forced_amplitudes_mp(p)["free_x1" if s.regime == "no_contact" else "stuck_x1"]
        d = abs(s.x1_max - amp)  # both relative to x_st
        info["amplitude_diff"] = d
        ok &= d <= MP_AMPLITUDE_TOL
    kinds.append("solve_ivp window")
    if window_end > t0:
        ivp_ok, ivp_info = _compare_with_ivp(p, t0, state, window_end)
        info.update({f"ivp_{k}": v for k, v in ivp_info.items()})
        ok &= ivp_ok
    info["reference_kind"] = " + ".join(kinds)
    return bool(ok), info
