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
  time (:func:`check_state`, :func:`check_start_time`) and the line for a run beyond the work
  bound (:func:`work_limit_message`).
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
from impactdamper.core.linear import characteristic_roots
from impactdamper.core.parameters import RELATIVE_PARAMETERS, Parameters, most_extreme, state_scale

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
    "check_start_time",
    "work_limit_message",
    "MAX_CLOCK_PERIODS",
    "MAX_STATE",
]


# Largest |t| of the solver's clock, in forcing periods: one ulp of t is ~1e-10 T there, the
# resolution event times need (at t0 = 1e16 s an ulp was 2 s, longer than T). The forcing is
# T-periodic: a later start is the same motion from t0 modulo T (steady_state reduces it so).
MAX_CLOCK_PERIODS = 1e6
# Largest initial state, relative to x_st (positions) and x_st omega (velocities): a motion
# 1e12 times the static deflection is far outside the model, and squares of much larger ones
# (energies, derivative bounds) overflow.
MAX_STATE = 1e12


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
            # and gap_tol = 10 counted the orbit's whole excursion as grazing).
            value = real_argument(name, getattr(self, name))
            if not (math.isfinite(value) and 0.0 < value < 1.0):
                raise ValueError(f"`{name}` = {value!r} is not allowed: must be in (0, 1)")
            object.__setattr__(self, name, value)


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
