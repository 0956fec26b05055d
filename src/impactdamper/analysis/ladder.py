"""The settled motion at one sweep point, found the cheapest way that is still right.

:func:`solve_point` answers "the settled motion at this sweep point, continuing its
neighbour's": the sweeps of :mod:`impactdamper.analysis.sweeps` call it for every point. Its
settings and result are in :mod:`impactdamper.analysis.point` (with the labels), its last step in
:mod:`impactdamper.analysis.rescue`.

How one point is computed (:func:`solve_point`)
-----------------------------------------------
A sweep point starts from its neighbour's motion, carried at a stroboscopic section: the
state (x1, x2, x1', x2') at a time t = n T (forcing phase zero) becomes the new point's state
at t0 = 0. The gap Delta = Delta0 - (x2 - x1) of that state refers to the old Delta0; at the
new one it may be negative (the bodies would overlap). The state is then **projected onto the
stop**: x2 := x1 + Delta0 (object and velocities unchanged, gap zero). A state that was in
persistent contact is kept on the stop the same way (its gap stays zero), so the persistent
contact carries over exactly. The first point of a sweep starts from Algorithm No. 2's step 1
(:func:`~impactdamper.core.simulate.default_initial_state`); any point can be recomputed on its own
from the state it started from (:attr:`SweepPoint.start_state`).

The settled motion is then found, cheapest first. Each accelerator accepts only a continuation
of the neighbour's motion that is still admissible and stable: the motion a sweep with a
vanishing step follows. A plain simulation from the carried state (a finite step) settles on
the same motion, except close to a bifurcation where that motion's basin shrinks to nothing
(approaching a grazing, say): there it can jump to a coexisting motion a little early, while
the sweep reports the continued motion up to the bifurcation itself. (Reference case: with
every point simulated at a step of 0.005, the downward sweep leaves the one-impact motion at
Delta0/x_st = -8.845, 0.004 above the grazing of Algorithm No. 1's orbit at -8.849.)

1. **closed form** -- the neighbour was ``stuck`` (``no_contact``) and the joined bodies'
   contact force (the free mode's gap) on the forced response stays positive: that forced
   response is the motion (the carried state lies on it already; it is damped, so stable).
2. **orbit continuation** -- the neighbour was a periodic impacting cycle: its impact times and
   states seed the Newton shooting of :func:`impactdamper.analysis.orbits.orbit_from_cycle` at the new
   parameter, which also checks admissibility (certified gap search) and stability
   (saltation-matrix Floquet multipliers). Accepted if admissible and stable.
3. **stroboscopic Newton** -- for cycles the shooting does not cover (``chatter``, with a
   phase of persistent contact) or where it failed: Newton on the map y(0) -> y(k T) of the
   event-driven solver (:func:`impactdamper.analysis.strobe.strobe_newton`), with a
   finite-difference Jacobian (the neighbour's, Broyden-updated; fresh where the iteration
   stalls or a multiplier exceeds :data:`~impactdamper.analysis.strobe.FRESH_JACOBIAN_ABOVE`; its
   eigenvalues are the multipliers). Accepted if stable and if one simulated cycle from the
   solution returns to it to ``settle_tol``; that cycle is described exactly as
   :func:`~impactdamper.core.steady.steady_state` describes a settled one.
4. **simulation** -- :func:`~impactdamper.core.steady.steady_state` from the carried state, capped
   at ``max_periods`` forcing periods.
5. **rescue** -- if that did not settle, the closest recurrence of the last sections (period k
   <= ``max_period_multiple`` with mismatch below ``RESCUE_MISMATCH``) seeds step 2 or 3; a
   stable, admissible orbit found so is the motion the capped run was still converging to.

What ``nonperiodic`` means here
-------------------------------
The sweep caps the simulation (``max_periods``, default 150 periods, against 4000 for a single
run of :func:`steady_state`): a point is ``nonperiodic`` when the capped run did not repeat
with a period k <= ``max_period_multiple`` to ``settle_tol`` and the rescue found no stable
orbit near its closest recurrence. That covers chaotic motion, periods above
``max_period_multiple`` T, quasi-periodic motion, and transients slower than the cap whose
end is not near a period-k recurrence. It is a statement about the sweep's budget, not a proof
of chaos.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from impactdamper.analysis.cycle import forced_response
from impactdamper.analysis.point import (
    STABILITY_MARGIN,
    SweepPoint,
    SweepSettings,
    failed_point,
    point_from_steady,
    shoot_cycle,
    verify_cycle,
)
from impactdamper.analysis.rescue import rescue_run
from impactdamper.analysis.strobe import strobe_newton
from impactdamper.core.backends import get_backend
from impactdamper.core.model import FREE, STUCK, Model
from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import Tolerances, default_initial_state
from impactdamper.core.validation import SettleOptions, check_start_state

__all__ = ["carry_state", "solve_point"]

# Relative tolerance on the contact force / gap of the closed-form motions (rounding guard).
CLOSED_FORM_MARGIN = 1e-12


def carry_state(p: Parameters, state: np.ndarray, mode: str) -> tuple[np.ndarray, str]:
    """The neighbour's section state made valid for ``p``: projected onto the stop if its gap
    would be negative, kept on the stop if it was in persistent contact.

    Returns the state (x1, x2, x1', x2') and ``"neighbour"`` or ``"projected"``."""
    full = np.array(state, dtype=float)
    gap = p.Delta0 - (full[1] - full[0])
    if mode == STUCK:
        full[1] = full[0] + p.Delta0
        full[3] = full[2]
        return full, "neighbour"
    if gap < 0.0:
        full[1] = full[0] + p.Delta0
        return full, "projected"
    return full, "neighbour"


def _closed_form(p: Parameters, value: float, regime: str, start: str, start_state: np.ndarray) -> SweepPoint | None:
    """The no-contact or persistent-contact forced response, if admissible at p."""
    model = Model(p)
    mode, fn, scale = forced_response(model, regime)
    if fn.g0 - abs(fn.G) <= CLOSED_FORM_MARGIN * scale:
        return None
    mult = float(np.max(np.abs(np.linalg.eigvals(mode.propagator(p.T)))))
    section = model.full_state(FREE if regime == "no_contact" else STUCK, mode.forced(0.0))
    return SweepPoint.labelled(
        p,
        value,
        regime,
        1,
        0,
        stable=mult < 1.0,
        multiplier=mult,
        x1_max=float(abs(mode.Yhat[0])) / p.x_st,
        velocities=(),
        phases=(),
        contact_fraction=1.0 if regime == "stuck" else 0.0,
        method="closed_form",
        periods=0,
        start=start,
        start_state=np.array(start_state, float),
        section=section,
        section_mode=FREE if regime == "no_contact" else STUCK,
    )


def _continue_orbit(
    p: Parameters, value: float, prev: SweepPoint, start: str, start_state: np.ndarray, tol: Tolerances
) -> SweepPoint | None:
    """Newton shooting of the neighbour's impacting cycle at p
    (:func:`~impactdamper.analysis.orbits.orbit_from_cycle`)."""
    if not prev.cycle:
        return None
    times, after = prev.cycle
    after = np.array(after, float)
    after[:, 1] = after[:, 0] + p.Delta0  # the impact states on the new stop
    o = shoot_cycle(p, prev.period_multiple, times, after, tol)
    if o is None or not (o.admissible and o.stable and o.spectral_radius < 1.0 - STABILITY_MARGIN):
        return None
    return point_from_steady(
        p,
        value,
        o,
        method="continuation",
        start=start,
        start_state=start_state,
        periods=0,
        multiplier=o.spectral_radius,
        stable=True,
    )


def solve_point(
    p: Parameters,
    value: float | None = None,
    previous: SweepPoint | None = None,
    *,
    state: np.ndarray | None = None,
    settings: SweepSettings | None = None,
    start: str | None = None,
) -> SweepPoint:
    """The settled motion at ``p``, continuing ``previous`` (a neighbour's point) if given.

    Parameters
    ----------
    p : Parameters
    value : float, optional
        The swept parameter's value (recorded only); default ``p.gap``.
    previous : SweepPoint, optional
        The neighbour whose motion this point starts from (see the module docstring).
    state : ndarray, shape (4,), optional
        Start state at t0 = 0 instead (no accelerators): a random start, say.
    settings : SweepSettings, optional
    start : str, optional
        Label of the start recorded in the result (default from how it started).

    Returns
    -------
    SweepPoint
    """
    settings = settings or SweepSettings()
    value = p.gap if value is None else float(value)
    t_begin = time.perf_counter()
    if previous is not None and state is not None:
        raise ValueError("`state` is not allowed together with `previous`: give one start")
    full, how = _start_state(p, previous, state, settings)
    start = start or how
    backend = get_backend(settings.backend)[0]
    result = None
    if previous is not None and settings.continuation and previous.periodic:
        result = _continued(p, value, previous, start, full, settings, backend)
    if result is None:
        result = _simulated(p, value, previous, start, full, settings, backend)
    return replace(result, elapsed=time.perf_counter() - t_begin)


def _start_state(p: Parameters, previous: SweepPoint | None, state: np.ndarray | None, settings: SweepSettings):
    """The start (x1, x2, x1', x2') at t0 = 0 and its label: the neighbour's section carried
    over, the given ``state`` (``random``) or the default initial state."""
    if previous is not None:
        return carry_state(p, previous.section, previous.section_mode)
    if state is not None:
        return check_start_state(state, p, settings.tolerances), "random"
    return default_initial_state(p), "default"


def _continued(p, value, previous: SweepPoint, start: str, full, settings: SweepSettings, backend):
    """The accelerators from a periodic neighbour: the closed form of a stuck or contact-free
    motion, the impact shooting of an impacting cycle, else Newton on the stroboscopic map
    kept if it is stable by ``STABILITY_MARGIN`` and verified; None where none answers."""
    result = None
    if previous.regime in ("stuck", "no_contact"):
        result = _closed_form(p, value, previous.regime, start, full)
    elif previous.regime in ("single_impact", "multi_impact"):
        result = _continue_orbit(p, value, previous, start, full, settings.tolerances)
    if result is None and previous.regime in ("chatter", "single_impact", "multi_impact"):
        res = strobe_newton(
            p,
            full,
            previous.section_mode,
            previous.period_multiple,
            settings.tolerances,
            jacobian=previous.jacobian,
            step=backend.map_step(p, settings.tolerances),
        )
        if res is not None and res.spectral_radius < 1.0 - STABILITY_MARGIN:
            result = verify_cycle(
                p,
                value,
                res.state,
                previous.period_multiple,
                settings,
                method="newton",
                start=start,
                start_state=full,
                periods=res.periods,
                rho=res.spectral_radius,
                jacobian=res.jacobian,
            )
    return result


def _simulated(p, value, previous: SweepPoint | None, start: str, full, settings: SweepSettings, backend) -> SweepPoint:
    """The point by settling the motion from ``full`` (the shorter budget after a nonperiodic
    neighbour), rescued if it does not settle; a failed point where the solver's guards stop it."""
    cap = settings.max_periods
    if previous is not None and not previous.periodic:
        cap = settings.max_periods_after_nonperiodic
    try:
        # (the cycle described by the reference, x1_max by its Brent search, as the sweeps report)
        options = SettleOptions(settings.settle_tol, cap, settings.max_period_multiple, describe="reference")
        s = backend.settle(p, 0.0, full, settings.tolerances, options)
    except RuntimeError as err:  # the event solver's guards (SearchLimitError, degenerate contact)
        return failed_point(p, value, start, full, err)
    periods = s.periods + max(s.period_multiple, 1) + 1
    result = None
    if not s.settled and settings.rescue:
        result = rescue_run(p, value, s, settings, start=start, start_state=full, periods=periods)
    if result is None:
        result = point_from_steady(p, value, s, method="simulation", start=start, start_state=full, periods=periods)
    return result
