"""Argument checks: each returns the checked value or raises a one-line error naming the argument.

Every public call of the library checks its arguments before it computes: a bad value (a config
value, a command-line flag, an API argument) gets a one-line ``ValueError`` (or
:class:`ArgumentTypeError`, also a ValueError, for a wrong type) of the form "`name` = value is
not allowed: must be ...", never a traceback from deep inside the solver or a silent wrong
answer. This is the one module to import an argument check from:

* the generic checks, which know nothing of the model (:func:`real_argument`,
  :func:`finite_argument`, :func:`integer_argument`, :func:`check_value`, :func:`show_value`):
  defined in :mod:`impactdamper.core.arguments`, below :mod:`impactdamper.core.parameters`,
  which checks its own values with them;
* the solver's, for the arguments of Timofeev et al. (2019)'s Algorithms No. 1 and No. 2
  (:mod:`impactdamper.core.algorithm1`, :mod:`impactdamper.core.simulate`): the tolerances
  (:class:`Tolerances`, :func:`check_tolerances`, :func:`check_gap_tol`), the start state and
  time (:func:`check_state`, :func:`check_start_time`), the settled-motion search's options
  (:class:`SettleOptions`) and the lines for a run beyond the work
  bound (:func:`work_limit_message`, :func:`work_bound_message`), which both backends word alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactdamper.core.arguments import (
    ArgumentTypeError,
    check_value,
    finite_argument,
    integer_argument,
    real_argument,
    show_value,
)
from impactdamper.core.constants import STEPS_PER_PERIOD
from impactdamper.core.linear import characteristic_roots
from impactdamper.core.parameters import RELATIVE_PARAMETERS, Parameters, most_extreme, require_parameters, state_scale

__all__ = [
    "ArgumentTypeError",
    "show_value",
    "check_value",
    "real_argument",
    "finite_argument",
    "integer_argument",
    "Tolerances",
    "check_gap_tol",
    "check_tolerances",
    "check_state",
    "check_start_state",
    "check_start_time",
    "work_limit_message",
    "work_bound_message",
    "check_settle_call",
    "check_run_call",
    "SettleOptions",
    "CHATTER_BLAME_IMPACTS",
    "MAX_CLOCK_PERIODS",
    "MAX_STATE",
    "MAX_PERIODS_LIMIT",
    "SETTLE_TOL_FLOOR",
    "TOLERANCE_FLOOR",
]


@dataclass(frozen=True)
class Tolerances:
    """Solver tolerances, all relative (lengths to x_st, velocities to x_st omega).

    Attributes
    ----------
    gap_tol : float
        A gap minimum at or below gap_tol * x_st is a contact (grazing touch).
    chatter_tol : float
        Rebound height (relative to x_st) below which an accumulating impact sequence is
        replaced by persistent contact: the rebound R v rises at most (R v)^2 / (2 a) with
        a = F/m_red the relative acceleration that presses the bodies together.
    force_tol : float
        Contact force (relative to m_red x_st omega_max^2) counted as zero at lift-off.
    """

    gap_tol: float = 1e-12
    chatter_tol: float = 1e-9
    force_tol: float = 1e-12

    def __post_init__(self) -> None:
        for name in ("gap_tol", "chatter_tol", "force_tol"):
            # Relative to x_st: a finite number in (0, 1) (NaN used to pass algorithm1 unchecked,
            # and gap_tol = 10 counted the orbit's whole excursion as grazing), and at least
            # TOLERANCE_FLOOR (below it the answer is decided by the machine's last bits).
            floor_why = "the rounding of the state in double precision (below it a result is decided by the last bits)"
            object.__setattr__(self, name, _fraction_above(name, getattr(self, name), TOLERANCE_FLOOR, floor_why))


# Smallest gap_tol, chatter_tol and force_tol (relative to x_st, x_st omega_max^2): the rounding
# of the state in double precision. Positions of a motion up to ~50 x_st (gaps and preloads of
# the native range) are rounded to 50 x 2.2e-16 = 1.1e-14 x_st, so a gap, a rebound height or a
# contact force below that level is round-off: at chatter_tol = 1e-300 and gap -28 the compiled
# kernels (built for the host CPU) settled a chatter cycle whose last impact had velocity 0.0 by
# round-off while the Python backend reached the work bound, and which happened depended on the
# CPU. From 1e-9 down to 1e-20 both backends agree there (chatter, 1 T); the floor keeps every
# accepted tolerance above the rounding.
TOLERANCE_FLOOR = 1e-14


def check_gap_tol(gap_tol: object) -> float:
    """``gap_tol`` as a float in (0, 1) (relative to x_st), else an error naming it."""
    return Tolerances(gap_tol=gap_tol).gap_tol


def check_tolerances(tolerances: object) -> Tolerances:
    """``tolerances`` if it is a Tolerances, the defaults for None, else an error naming it."""
    if tolerances is None:
        return Tolerances()
    if not isinstance(tolerances, Tolerances):
        raise ArgumentTypeError(f"`tolerances` = {tolerances!r} is not allowed: must be a Tolerances or None")
    return tolerances


# Largest initial state, relative to x_st (positions) and x_st omega (velocities): a motion
# 1e12 times the static deflection is far outside the model, and squares of much larger ones
# (energies, derivative bounds) overflow.
MAX_STATE = 1e12


def check_state(state: object, p: Parameters) -> np.ndarray | None:
    """``state`` as a float array (x1, x2, x1', x2') of finite values within MAX_STATE (relative),
    or None; else an error naming it."""
    if state is None:
        return None
    try:
        full = np.array(state, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError(
            f"`state` = {state!r} is not allowed: must be 4 finite numbers (x1, x2, x1', x2')"
        ) from None
    if full.shape != (4,) or not np.all(np.isfinite(full)):
        raise ValueError(f"`state` = {state!r} is not allowed: must be 4 finite numbers (x1, x2, x1', x2')")
    # In the paper's relative coordinates: x1/x_st, (x2 - Delta0)/x_st and the velocities over
    # x_st omega (x2 itself is Delta0 at the stop, whatever the gap).
    relative = full - np.array([0.0, p.Delta0, 0.0, 0.0])
    scale = state_scale(p)
    with np.errstate(over="ignore"):  # (an overflowing ratio is just too large)
        too_large = not np.all(np.abs(relative) / scale <= MAX_STATE)
    if too_large:
        raise ValueError(
            f"`state` = {state!r} is not allowed: x1 and x2 - Delta0 must be within {MAX_STATE:.0e} x_st "
            f"and the velocities within {MAX_STATE:.0e} x_st omega (x_st = {p.x_st!r} m, "
            f"omega = {p.omega!r} rad/s)"
        )
    return full


def check_start_state(state: object, p: Parameters, tolerances: Tolerances) -> np.ndarray | None:
    """:func:`check_state`, and the bodies not overlapping: the gap Delta0 - (x2 - x1) at least
    -gap_tol x_st (the event-driven solver's own check, made before a run)."""
    full = check_state(state, p)
    if full is not None:
        gap = p.Delta0 - (full[1] - full[0])
        if gap < -tolerances.gap_tol * p.x_st:
            raise ValueError(f"`state` has gap Delta0 - (x2 - x1) = {gap:.6g} m < 0: the bodies would overlap")
    return full


# Largest |t| of the solver's clock, in forcing periods: one ulp of t is ~1e-10 T there, the
# resolution event times need (at t0 = 1e16 s an ulp was 2 s, longer than T). The forcing is
# T-periodic: a later start is the same motion from t0 modulo T (steady_state reduces it so).
MAX_CLOCK_PERIODS = 1e6


def check_start_time(t0: object, p: Parameters, name: str = "t0") -> float:
    """``t0`` as a finite float within the solver's clock (MAX_CLOCK_PERIODS), else an error."""
    t0 = finite_argument(name, t0)
    limit = MAX_CLOCK_PERIODS * p.T
    if abs(t0) > limit:
        raise ValueError(
            f"`{name}` = {t0!r} is not allowed: must be within {MAX_CLOCK_PERIODS:.0e} forcing periods of 0 "
            f"(|{name}| <= {limit:.6g} s), where the clock resolves event times to ~1e-10 T; the forcing is "
            "T-periodic, so a start modulo T is the same motion (steady_state reduces it itself)"
        )
    return t0


def work_limit_message(p: Parameters, what: str) -> str:
    """One line for a run that hit a work bound, naming the parameter farthest from the
    reference case (the usual cause: a free motion far faster or stiffer than the forcing)."""
    with np.errstate(all="ignore"):  # (only for the message: an overflow just shows as inf)
        rate = float(np.max(np.abs(characteristic_roots(p)))) / p.omega
    name = most_extreme(p, RELATIVE_PARAMETERS)
    return (
        f"`{name}` = {getattr(p, name)!r} is beyond what the solver resolves: {what} (the free motion's fastest "
        f"rate is {rate:.3g} omega); allowed are parameters nearer the reference case (theta = 1, mu = 0.08, "
        "N = 0.5, delta1 = delta2 = 0.05, R = 0.7, gap = -5.8)"
    )


# A run that reaches its work bound with this many impacts in a row (a chatter sequence) blames
# the impact law, not the parameter farthest from the reference case: ``chatter_tol`` where it
# is below its default (which ends such sequences sooner), ``R`` where it is 1 (elastic impacts
# on a preloaded stop do not accumulate, so the sequence never ends in persistent contact: at
# theta = 0.5 the impacts came 3e-5 T apart after 17 periods, while R = 0.99 settles there) or
# so close to 1 that the sequence needs more impacts than a period's budget of steps (R =
# 0.99999 at theta 1.4, N 1.5, gap -2.5 named N before).
CHATTER_BLAME_IMPACTS = 20


def work_bound_message(p: Parameters, tolerances: Tolerances, what: str, impacts_in_a_row: int) -> str:
    """The line for a run that reached a work bound (``what``: which, and where), the same for
    both backends: in a chatter sequence (the run's last ``impacts_in_a_row`` events impacts, at
    least :data:`CHATTER_BLAME_IMPACTS`) it names ``chatter_tol`` below its default or ``R`` = 1,
    else :func:`work_limit_message`'s parameter."""
    if impacts_in_a_row >= CHATTER_BLAME_IMPACTS:
        default = Tolerances.chatter_tol
        if tolerances.chatter_tol < default:
            return (
                f"`chatter_tol` = {tolerances.chatter_tol!r} is beyond what the solver resolves here: {what}, in "
                f"a chatter sequence followed to rebounds below {tolerances.chatter_tol:.3g} x_st; allowed are "
                f"values nearer the default {default!r}, which ends such a sequence in persistent contact sooner"
            )
        if p.R == 1.0:
            return (
                f"`R` = {p.R!r} is beyond what the solver resolves here: {what}, in a sequence of impacts on the "
                "stop that does not accumulate (elastic impacts: the rebounds do not shrink, so the sequence "
                "never ends in persistent contact); allowed are R < 1 (each rebound R times the last)"
            )
        # Rebound heights shrink by R^2 per impact: from ~x_st to chatter_tol x_st takes this many.
        needed = math.log(tolerances.chatter_tol) / (2.0 * math.log(p.R)) if 0.0 < p.R < 1.0 else 0.0
        if needed > STEPS_PER_PERIOD:
            return (
                f"`R` = {p.R!r} is beyond what the solver resolves here: {what}, in a sequence of impacts on the "
                f"stop that accumulates too slowly (each rebound R times the last: about {needed:.2g} impacts to "
                f"end in persistent contact, more than the {STEPS_PER_PERIOD} steps per forcing period of the work "
                "bound); allowed are smaller R"
            )
    return work_limit_message(p, what)


# Largest max_periods of a settled-motion search: the work of one run (the pure-Python loop
# advances ~7000 forcing periods a second, so a run that does not settle ends within ~15 s; the
# run keeps every section, 2 arrays of max_periods x 4 floats). The slowest settling case of
# the workflow takes ~4000.
MAX_PERIODS_LIMIT = 100_000
# Smallest settle_tol: the run's rounding noise in the relative sections. After the transient
# the sections' lag-k differences level off at 2e-14 to 4e-12 (reference case, gaps -20 to 2,
# theta 0.8 to 1.2, both backends; 3.8e-12 at gap -9, theta 1); below the noise the period test
# never passes (at settle_tol = 1e-13 the reference case's 1/1 cycle came out nonperiodic with 8
# impacts per cycle). Twice the noise's largest measured level keeps the test decidable.
SETTLE_TOL_FLOOR = 1e-11


def _check_settle_tol(settle_tol: object) -> float:
    """``settle_tol`` as a float in [SETTLE_TOL_FLOOR, 1), else an error naming it and the floor."""
    floor_why = "the rounding noise of the section mismatch (below it the period test cannot pass)"
    return _fraction_above("settle_tol", settle_tol, SETTLE_TOL_FLOOR, floor_why)


def _fraction_above(name: str, value: object, floor: float, floor_why: str) -> float:
    """Argument ``name`` as a finite float in (0, 1) and at least ``floor``, else an error naming
    it, the bound it breaks and (for the floor) ``floor_why``, what the floor stands above."""
    value = real_argument(name, value)
    if not (math.isfinite(value) and 0.0 < value < 1.0):
        raise ValueError(f"`{name}` = {value!r} is not allowed: must be in (0, 1)")
    if value < floor:
        raise ValueError(
            f"`{name}` = {value!r} is not allowed: must be at least {floor:g}, the floor above {floor_why}"
        )
    return value


@dataclass(frozen=True)
class SettleOptions:
    """The settled-motion search's options (:func:`impactdamper.core.steady.steady_state`): the
    one carrier of these keywords, built once by a front door (``steady_state``,
    ``solve_orbit``; the sweeps' :class:`~impactdamper.analysis.point.SweepSettings` holds one)
    and handed to every backend's ``settle`` and ``settle_row``. Checked on construction: a
    TypeError or ValueError naming the field and what is allowed.

    Attributes
    ----------
    settle_tol : float
        Relative section mismatch of a settled motion, in [SETTLE_TOL_FLOOR, 1).
    max_periods : int
        Forcing periods after which an unsettled motion is ``nonperiodic``.
    max_period_multiple : int
        Largest k tried for T_c = k T.
    describe : str
        Who describes the settled cycle: ``"backend"`` (the backend itself; the kernels refine
        x1_max by golden-section search) or ``"reference"`` (the reference's
        :func:`~impactdamper.core.settled_cycle.describe_run` on the backend's run, x1_max by scipy's
        Brent search: what the sweeps' ladder has always reported). Both stop at 1e-12 T; the
        maxima differ by rounding.
    """

    settle_tol: float = 1e-10
    max_periods: int = 4000
    max_period_multiple: int = 8
    describe: str = "backend"

    def __post_init__(self) -> None:
        settle_tol = _check_settle_tol(self.settle_tol)
        max_periods = integer_argument("max_periods", self.max_periods, 2, MAX_PERIODS_LIMIT)
        max_period_multiple = integer_argument(
            "max_period_multiple", self.max_period_multiple, 1, MAX_PERIODS_LIMIT - 1
        )
        if max_period_multiple >= max_periods:
            # Named first: max_periods, the bound usually given (``steady --max-periods 2`` blamed
            # --max-period-multiple, a flag never given, at its default 8); the CLI names the flag given.
            raise ValueError(
                f"`max_periods` = {max_periods!r} is not allowed with `max_period_multiple` = "
                f"{max_period_multiple!r}: max_periods must exceed max_period_multiple"
            )
        object.__setattr__(self, "settle_tol", settle_tol)
        object.__setattr__(self, "max_periods", max_periods)
        object.__setattr__(self, "max_period_multiple", max_period_multiple)
        if self.describe not in ("backend", "reference"):
            raise ValueError(f"`describe` = {self.describe!r} is not allowed: must be 'backend' or 'reference'")


def check_settle_call(p, t0, state, tolerances, **options):
    """A settled-motion call's arguments (the front door's ``steady_state``, the reference's
    :func:`impactdamper.core.steady.steady_state`), checked once and in that order (the first
    bad one raises a TypeError or ValueError naming it): (p, t0, state or None, Tolerances,
    :class:`SettleOptions` of ``options``, its fields by name)."""
    p = require_parameters(p)
    t0 = finite_argument("t0", t0)
    tolerances = check_tolerances(tolerances)
    state = check_start_state(state, p, tolerances)
    return p, t0, state, tolerances, SettleOptions(**options)


def check_run_call(p, t_end, t0, state, tolerances, max_periods: int):
    """A run's arguments (:func:`impactdamper.core.simulate.simulate`, the front door's
    ``simulate``), checked once and in that order (the first bad one raises a TypeError or
    ValueError naming it): (p, t_end, t0, state or None, Tolerances). ``max_periods`` bounds the
    run's length (t_end - t0)/T, a bound on its work."""
    p = require_parameters(p)
    t_end = finite_argument("t_end", t_end)
    if not math.isfinite(real_argument("t0", t0)):
        raise ValueError(f"`t0` = {t0!r} is not allowed: must be a finite number, before `t_end` = {t_end!r}")
    t0 = check_start_time(t0, p)
    max_periods = integer_argument("max_periods", max_periods, 1)
    if not t_end > t0:
        raise ValueError(f"`t_end` = {t_end!r} is not allowed: must be > t0 = {t0!r}")
    if (t_end - t0) / p.T > max_periods:
        raise ValueError(
            f"`t_end` = {t_end!r} is not allowed: (t_end - t0)/T = {(t_end - t0) / p.T:.6g} forcing periods "
            f"is more than max_periods = {max_periods} (a bound on the work; pass a larger max_periods)"
        )
    check_start_time(t_end, p, "t_end")
    tolerances = check_tolerances(tolerances)
    return p, t_end, t0, check_start_state(state, p, tolerances), tolerances
