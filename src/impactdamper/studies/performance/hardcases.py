"""Hard cases: where impact solvers usually break, each with what it stresses and its checks.

Each :class:`HardCase` changes the reference case (Timofeev et al. 2019, Fig. 2) in one way
and says what that stresses. :func:`run_case` runs the settled-motion search
(:func:`impactdamper.steady_state`, Algorithm No. 2 with contact modes) on it and checks it:
``terminated``, ``gap_nonnegative``, ``impact_law`` and ``reference``, each stated with its
tolerances in :mod:`impactdamper.studies.performance.hardcase_checks`.

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
from impactdamper.core.model import Model
from impactdamper.core.parameters import REFERENCE, Parameters
from impactdamper.core.simulate import simulate
from impactdamper.core.steady import REGIMES, steady_state
from impactdamper.studies.performance.hardcase_checks import (
    GAP_CHECK_TOL,
    IVP_STATE_TOL,
    IVP_TIME_TOL,
    LAW_TOL,
    MP_AMPLITUDE_TOL,
    MP_PHASE_TOL,
    TOUCH_VELOCITY,
    check_gap_nonnegative,
    check_impact_law,
    check_reference,
    steady_end_time,
)
from impactdamper.studies.vocabulary import SPEC

__all__ = [
    "run_suite",
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
# A hang is a failure, not a stuck workflow (s of wall clock per case).
CASE_WALL_LIMIT = 600


@dataclass(frozen=True)
class _HardCase:
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


def _no_contact_threshold(p: Parameters = REFERENCE) -> float:
    """Delta0/x_st at which the no-contact forced response just touches the stop: its
    relative amplitude |x2p - x1p|/x_st (eq. 10), computed in mpmath."""
    return hp.forced_amplitudes_mp(p)["free_relative"]


def _alg1_onset_gap(p: Parameters = REFERENCE, start: float | None = None, step: float = 0.5) -> float:
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


def _hard_cases(base: Parameters = REFERENCE) -> list[_HardCase]:
    """The suite (thresholds computed for ``base``)."""
    g_touch = _no_contact_threshold(base)
    g_onset = _alg1_onset_gap(base)
    repeated_delta2 = 0.8829865207640838  # eq. (4) has a double root at N = 0.9 (solved in mpmath)
    gap, theta, mu = SPEC["gap"].symbol, SPEC["theta"].symbol, SPEC["mu"].symbol  # the labels' symbols
    d1, d2 = SPEC["delta1"].symbol, SPEC["delta2"].symbol
    undamped = {"delta1": 0.0, "delta2": 0.0}  # (and the conservative case: elastic besides)
    return [
        _HardCase(
            "grazing_no_contact",
            f"${gap} = {g_touch:.6f}$ (no-contact threshold), start on the forced response",
            "zero-velocity grazing: the no-contact orbit touches the stop tangentially",
            {"gap": g_touch},
            start="forced_orbit",
        ),
        _HardCase(
            "grazing_alg1_onset",
            f"${gap} = {g_onset:.6f}$ (onset of crossing), start on Alg.~1's orbit",
            "grazing inside the period: Algorithm No. 1's orbit touches the stop between impacts",
            {"gap": g_onset},
            start="alg1_orbit",
        ),
        _HardCase(
            "chatter", f"${gap} = -13$", "impacts accumulating into persistent contact, and lift-off", {"gap": -13.0}
        ),
        _HardCase("plastic", r"$R = 0$", "plastic impacts: capture or separation at every impact", {"R": 0.0}),
        _HardCase(
            "elastic", r"$R = 1$", "elastic impacts: no accumulation possible, energy kept at impacts", {"R": 1.0}
        ),
        _HardCase(
            "zero_damping",
            f"${d1} = {d2} = 0$",
            "purely imaginary roots (no decay of the free motion)",
            undamped,
        ),
        _HardCase(
            "conservative",
            f"${d1} = {d2} = 0$, $R = 1$",
            "no dissipation at all: the run can only end at its period limit",
            {**undamped, "R": 1.0},
        ),
        _HardCase(
            "repeated_roots",
            f"$N = 0.9$, ${d2} = {repeated_delta2:.6f}$",
            "a double root of the paper's eq. (4): the modal form breaks, the matrix exponential takes over",
            {"N": 0.9, "delta2": repeated_delta2},
        ),
        _HardCase(
            "light_damping",
            f"${d1} = {d2} = 10^{{-3}}$",
            "very light damping: long transients",
            {"delta1": 1e-3, "delta2": 1e-3},
        ),
        _HardCase(
            "tiny_mass", f"${mu} = 10^{{-4}}$", "a suppressor $10^4$ times lighter than the object", {"mu": 1e-4}
        ),
        _HardCase("stiff_suppressor", r"$N = 50$", "a suppressor frequency 50 times the object's (stiff)", {"N": 50.0}),
        _HardCase("slow_forcing", f"${theta} = 0.1$", "forcing far below resonance", {"theta": 0.1}),
        _HardCase("fast_forcing", f"${theta} = 10$", "forcing far above resonance", {"theta": 10.0}),
        _HardCase("zero_gap", r"$\Delta_0 = 0$", "the stop exactly at the static position", {"gap": 0.0}),
        _HardCase("large_positive_gap", f"${gap} = 10^3$", "a gap never closed again", {"gap": 1e3}),
        _HardCase("large_negative_gap", f"${gap} = -10^3$", "a huge preload: the bodies never separate", {"gap": -1e3}),
    ]


@dataclass
class _CaseResult:
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


def _did(s, run, touches: int) -> str:
    ev = run.events
    sticks = sum(e.kind == "stick" for e in ev)
    text = f"{s.regime}, k = {s.period_multiple}, z = {s.impacts_per_cycle}"
    if sticks:
        text += f"; {sticks} capture{'s' if sticks > 1 else ''}"
    if touches:
        text += f"; {touches} grazing touch{'es' if touches > 1 else ''}"
    return text


def _run_case(case: _HardCase, base: Parameters = REFERENCE, wall_limit: int = CASE_WALL_LIMIT) -> _CaseResult:
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
        return _CaseResult(
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
    ok, info = check_reference(case, p, t0, state, s, traj)
    checks["reference"] = ok
    details.update(info)
    vscale = p.x_st * p.omega
    touches = sum(1 for e in traj.events if e.kind == "impact" and e.velocity < TOUCH_VELOCITY * vscale)
    return _CaseResult(
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


def run_suite(base: Parameters = REFERENCE, names=None, log=print) -> list[_CaseResult]:
    """Run every hard case (or those named)."""
    cases = _hard_cases(base)
    if names is not None:
        unknown = set(names) - {c.name for c in cases}
        if unknown:
            raise ValueError(f"`names` has unknown cases {sorted(unknown)}: allowed are {[c.name for c in cases]}")
        cases = [c for c in cases if c.name in names]
    out = []
    for case in cases:
        r = _run_case(case, base)
        log(
            f"[hard case] {case.name}: {r.did}; {r.cpu_seconds:.3f} s; "
            + ", ".join(f"{c}={'ok' if r.checks.get(c) else 'FAIL'}" for c in CHECKS)
        )
        out.append(r)
    return out
