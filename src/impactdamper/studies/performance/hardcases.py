"""Hard cases: where impact solvers usually break, each with what it stresses and its checks.

Each :class:`HardCase` changes the reference case (Timofeev et al. 2019, Fig. 2) in one way
and says what that stresses. :func:`run_case` runs the settled-motion search
(:func:`impactdamper.steady_state`, Algorithm No. 2 with contact modes) on it and checks:

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

Timing (``cpu_seconds``, process CPU time of the steady-state run) is recorded, never checked.
"""

from __future__ import annotations

import math
import signal
import time
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np
import scipy.optimize

from impactdamper.baselines import highprecision as hp
from impactdamper.core.algorithm1 import algorithm1
from impactdamper.baselines.ivp import simulate_ivp
from impactdamper.core.model import FREE, Model
from impactdamper.core.parameters import REFERENCE, Parameters
from impactdamper.core.simulate import simulate
from impactdamper.core.steady import REGIMES, steady_state
from impactdamper.studies.vocabulary import SPEC

__all__ = [
    "HardCase",
    "CaseResult",
    "hard_cases",
    "run_case",
    "run_suite",
    "no_contact_threshold",
    "alg1_onset_gap",
    "check_gap_nonnegative",
    "check_impact_law",
    "CHECKS",
    "ROW_COLUMNS",
]

CHECKS = ("terminated", "gap_nonnegative", "impact_law", "reference")
# The keys of :meth:`CaseResult.row` in the suite's CSV record: the case and what the solver did,
# the checks' flags, then the measured numbers behind the flags, each beside its tolerance.
ROW_COLUMNS = (
    *("case", "label", "stresses", "regime", "k", "z", "periods", "events", "touches", "did", "cpu_seconds"),
    *(*CHECKS, "passed", "reference_kind", "min_gap_relative", "gap_tol", "max_law_residual", "law_tol"),
    *("ivp_event_time_diff", "ivp_time_tol", "ivp_state_diff", "ivp_state_tol", "mp_diff", "mp_tol"),
)
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
# A hang is a failure, not a stuck workflow (s of wall clock per case).
CASE_WALL_LIMIT = 600


@dataclass(frozen=True)
class HardCase:
    """One hard case.

    Attributes
    ----------
    name : str
        Identifier (used in files and tests).
    label : str
        The change, in LaTeX-friendly text.
    stresses : str
        What it stresses.
    changes : dict
        Relative parameters changed from the base case.
    start : str
        ``"default"`` (Algorithm No. 2's step 1), ``"forced_orbit"`` (on the no-contact forced
        response at t = 0) or ``"alg1_orbit"`` (just after the impact of Algorithm No. 1's
        orbit, computed in mpmath).
    window : float
        Periods of the solve_ivp comparison (cut before a grazing touch).
    """

    name: str
    label: str
    stresses: str
    changes: dict = field(default_factory=dict)
    start: str = "default"
    window: float = 3.0

    def parameters(self, base: Parameters = REFERENCE) -> Parameters:
        return base.replace(**self.changes)

    def initial(self, p: Parameters) -> tuple[float, np.ndarray | None]:
        """(t0, state) of the run; state None means the default start."""
        if self.start == "default":
            return 0.0, None
        if self.start == "forced_orbit":
            return 0.0, Model(p).free.forced(0.0)
        if self.start == "alg1_orbit":
            a = hp.algorithm1_mp(p)
            if not a.exists:
                raise ValueError(f"`{self.name}`: Algorithm No. 1 has no orbit to start on")
            return float(a.t_impact), hp.to_float(a.state_after)
        raise ValueError(f"`start` = {self.start!r} is not allowed: must be default, forced_orbit or alg1_orbit")


def no_contact_threshold(p: Parameters = REFERENCE) -> float:
    """Delta0/x_st at which the no-contact forced response just touches the stop: its
    relative amplitude |x2p - x1p|/x_st (eq. 10), computed in mpmath."""
    return hp.forced_amplitudes_mp(p)["free_relative"]


def alg1_onset_gap(p: Parameters = REFERENCE, start: float | None = None, step: float = 0.5) -> float:
    """Delta0/x_st where Algorithm No. 1's orbit starts to cross the stop between impacts
    (its interior gap minimum reaches zero), searched downward from ``start`` (default the
    base gap) and bisected (brentq) to 1e-14."""

    def min_gap(g: float) -> float:
        a = algorithm1(p.replace(gap=g))
        if not a.exists:
            return math.nan
        # An orbit without an interior minimum counts as clear of the stop.
        return a.min_gap if a.min_gap != 0.0 else 1.0

    hi = p.gap if start is None else start
    f_hi = min_gap(hi)
    for _ in range(200):
        lo = hi - step
        f_lo = min_gap(lo)
        if math.isnan(f_lo):
            break
        if f_lo < 0.0 < f_hi:
            return float(scipy.optimize.brentq(min_gap, lo, hi, xtol=1e-14, rtol=4 * np.finfo(float).eps))
        hi, f_hi = lo, f_lo
    raise ValueError("Algorithm No. 1's orbit never crosses the stop below the start gap")


def hard_cases(base: Parameters = REFERENCE) -> list[HardCase]:
    """The suite (thresholds computed for ``base``)."""
    g_touch = no_contact_threshold(base)
    g_onset = alg1_onset_gap(base)
    repeated_delta2 = 0.8829865207640838  # eq. (4) has a double root at N = 0.9 (solved in mpmath)
    gap, theta, mu = SPEC["gap"].symbol, SPEC["theta"].symbol, SPEC["mu"].symbol  # the labels' symbols
    d1, d2 = SPEC["delta1"].symbol, SPEC["delta2"].symbol
    return [
        HardCase(
            "grazing_no_contact",
            f"${gap} = {g_touch:.6f}$ (no-contact threshold), start on the forced response",
            "zero-velocity grazing: the no-contact orbit touches the stop tangentially",
            {"gap": g_touch},
            start="forced_orbit",
        ),
        HardCase(
            "grazing_alg1_onset",
            f"${gap} = {g_onset:.6f}$ (onset of crossing), start on Alg.~1's orbit",
            "grazing inside the period: Algorithm No. 1's orbit touches the stop between impacts",
            {"gap": g_onset},
            start="alg1_orbit",
        ),
        HardCase(
            "chatter", f"${gap} = -13$", "impacts accumulating into persistent contact, and lift-off", {"gap": -13.0}
        ),
        HardCase("plastic", r"$R = 0$", "plastic impacts: capture or separation at every impact", {"R": 0.0}),
        HardCase(
            "elastic", r"$R = 1$", "elastic impacts: no accumulation possible, energy kept at impacts", {"R": 1.0}
        ),
        HardCase(
            "zero_damping",
            f"${d1} = {d2} = 0$",
            "purely imaginary roots (no decay of the free motion)",
            {"delta1": 0.0, "delta2": 0.0},
        ),
        HardCase(
            "conservative",
            f"${d1} = {d2} = 0$, $R = 1$",
            "no dissipation at all: the run can only end at its period limit",
            {"delta1": 0.0, "delta2": 0.0, "R": 1.0},
        ),
        HardCase(
            "repeated_roots",
            f"$N = 0.9$, ${d2} = {repeated_delta2:.6f}$",
            "a double root of the paper's eq. (4): the modal form breaks, the matrix exponential takes over",
            {"N": 0.9, "delta2": repeated_delta2},
        ),
        HardCase(
            "light_damping",
            f"${d1} = {d2} = 10^{{-3}}$",
            "very light damping: long transients",
            {"delta1": 1e-3, "delta2": 1e-3},
        ),
        HardCase("tiny_mass", f"${mu} = 10^{{-4}}$", "a suppressor $10^4$ times lighter than the object", {"mu": 1e-4}),
        HardCase("stiff_suppressor", r"$N = 50$", "a suppressor frequency 50 times the object's (stiff)", {"N": 50.0}),
        HardCase("slow_forcing", f"${theta} = 0.1$", "forcing far below resonance", {"theta": 0.1}),
        HardCase("fast_forcing", f"${theta} = 10$", "forcing far above resonance", {"theta": 10.0}),
        HardCase("zero_gap", r"$\Delta_0 = 0$", "the stop exactly at the static position", {"gap": 0.0}),
        HardCase("large_positive_gap", f"${gap} = 10^3$", "a gap never closed again", {"gap": 1e3}),
        HardCase("large_negative_gap", f"${gap} = -10^3$", "a huge preload: the bodies never separate", {"gap": -1e3}),
    ]


@dataclass
class CaseResult:
    """Outcome of one hard case."""

    name: str
    label: str
    stresses: str
    regime: str
    period_multiple: int
    impacts_per_cycle: int
    periods: int
    events: int
    touches: int
    cpu_seconds: float
    checks: dict
    details: dict
    did: str = ""

    @property
    def passed(self) -> bool:
        return all(self.checks.get(c, False) for c in CHECKS)

    def row(self) -> dict:
        out = {
            "case": self.name,
            "label": self.label,
            "stresses": self.stresses,
            "regime": self.regime,
            "k": self.period_multiple,
            "z": self.impacts_per_cycle,
            "periods": self.periods,
            "events": self.events,
            "touches": self.touches,
            "did": self.did,
            "cpu_seconds": self.cpu_seconds,
        }
        for c in CHECKS:
            out[c] = bool(self.checks.get(c, False))
        out["passed"] = self.passed
        out["reference_kind"] = self.details.get("reference_kind", "")
        # The numbers behind the flags, each beside its tolerance (a flag is never shown alone).
        d = self.details
        law = d.get("impact_law_residuals", {})
        out["min_gap_relative"] = d.get("min_gap_relative")
        out["gap_tol"] = GAP_CHECK_TOL
        out["max_law_residual"] = max((v for k, v in law.items() if k not in ("gap", "liftoff_force")), default=None)
        out["law_tol"] = LAW_TOL
        out["ivp_event_time_diff"] = d.get("ivp_event_time_diff")
        out["ivp_time_tol"] = IVP_TIME_TOL
        out["ivp_state_diff"] = d.get("ivp_state_diff")
        out["ivp_state_tol"] = IVP_STATE_TOL
        out["mp_diff"] = d.get("settled_phase_diff", d.get("amplitude_diff"))
        out["mp_tol"] = (
            MP_PHASE_TOL if "settled_phase_diff" in d else MP_AMPLITUDE_TOL if "amplitude_diff" in d else None
        )
        return out


@contextmanager
def _wall_limit(seconds: int):
    """Raise TimeoutError after ``seconds`` of wall clock (main thread on POSIX only)."""
    try:
        previous = signal.signal(signal.SIGALRM, lambda *_: (_ for _ in ()).throw(TimeoutError("wall limit")))
    except (ValueError, AttributeError):  # not the main thread, or no SIGALRM
        yield
        return
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


# --- checks ---------------------------------------------------------------------------------
def _segment_ends(traj, t_end: float) -> list[float]:
    starts = [seg.t0 for _, seg in traj.segments]
    return starts[1:] + [max(t_end, starts[-1])]


def steady_end_time(s) -> float:
    """Where :func:`steady_state`'s run stopped: its last stroboscopic section. (Its
    ``trajectory`` holds only the reported cycle's window, re-simulated with the clock near
    t0; the checks here replay the whole run from the start instead, see :func:`run_case`.)"""
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
            worst["restitution"] = max(worst["restitution"], abs((a[3] - a[2]) + p.R * v) / vscale)
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


def compare_with_ivp(p: Parameters, t0: float, state, t_end: float) -> tuple[bool, dict]:
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


def _reference_checks(case: HardCase, p: Parameters, t0: float, state, s, traj) -> tuple[bool, dict]:
    """The high-precision check that applies, and the solve_ivp window (``traj``: the whole
    run from the start)."""
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
        ivp_ok, ivp_info = compare_with_ivp(p, t0, state, window_end)
        info.update({f"ivp_{k}": v for k, v in ivp_info.items()})
        ok &= ivp_ok
    info["reference_kind"] = " + ".join(kinds)
    return bool(ok), info


def _did(s, run, touches: int) -> str:
    ev = run.events
    sticks = sum(e.kind == "stick" for e in ev)
    text = f"{s.regime}, k = {s.period_multiple}, z = {s.impacts_per_cycle}"
    if sticks:
        text += f"; {sticks} capture{'s' if sticks > 1 else ''}"
    if touches:
        text += f"; {touches} grazing touch{'es' if touches > 1 else ''}"
    return text


def run_case(case: HardCase, base: Parameters = REFERENCE, wall_limit: int = CASE_WALL_LIMIT) -> CaseResult:
    """Run one hard case and all its checks."""
    p = case.parameters(base)
    t0, state = case.initial(p)
    checks: dict = {}
    details: dict = {}
    start = time.process_time()
    try:
        with _wall_limit(wall_limit):
            s = steady_state(p, t0=t0, state=state)
            # The whole run from the start, for the checks (s.trajectory is the cycle's window).
            run = simulate(p, steady_end_time(s), t0=t0, state=state)
    except TimeoutError:
        cpu = time.process_time() - start
        checks = {c: False for c in CHECKS}
        return CaseResult(
            case.name,
            case.label,
            case.stresses,
            "timeout",
            0,
            0,
            0,
            0,
            0,
            cpu,
            checks,
            {"error": f"no result within {wall_limit} s"},
            "did not end",
        )
    cpu = time.process_time() - start
    traj = run
    checks["terminated"] = s.regime in REGIMES
    ok, worst_gap = check_gap_nonnegative(traj, steady_end_time(s))
    window = s.trajectory  # the reported cycle and its neighbours, checked as well
    ok_w, worst_w = check_gap_nonnegative(window, window.segments[-1][1].t0)
    checks["gap_nonnegative"] = ok and ok_w
    details["min_gap_relative"] = min(worst_gap, worst_w)
    ok, worst = check_impact_law(traj)
    ok_w, _ = check_impact_law(window)
    checks["impact_law"] = ok and ok_w
    details["impact_law_residuals"] = worst
    ok, info = _reference_checks(case, p, t0, state, s, traj)
    checks["reference"] = ok
    details.update(info)
    vscale = p.x_st * p.omega
    touches = sum(1 for e in traj.events if e.kind == "impact" and e.velocity < TOUCH_VELOCITY * vscale)
    return CaseResult(
        case.name,
        case.label,
        case.stresses,
        s.regime,
        s.period_multiple,
        s.impacts_per_cycle,
        s.periods,
        len(traj.events),
        touches,
        cpu,
        checks,
        details,
        _did(s, traj, touches),
    )


def run_suite(base: Parameters = REFERENCE, names=None, log=print) -> list[CaseResult]:
    """Run every hard case (or those named)."""
    cases = hard_cases(base)
    if names is not None:
        unknown = set(names) - {c.name for c in cases}
        if unknown:
            raise ValueError(f"`names` has unknown cases {sorted(unknown)}: allowed are {[c.name for c in cases]}")
        cases = [c for c in cases if c.name in names]
    out = []
    for case in cases:
        r = run_case(case, base)
        log(
            f"[hard case] {case.name}: {r.did}; {r.cpu_seconds:.3f} s; "
            + ", ".join(f"{c}={'ok' if r.checks.get(c) else 'FAIL'}" for c in CHECKS)
        )
        out.append(r)
    return out
