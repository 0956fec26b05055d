"""The Newton rescue of a sweep point whose capped simulation did not settle.

A run capped at ``max_periods`` forcing periods may still be converging to a cycle (a slow
transient, a multiplier of modulus near 1). The rescue takes the closest recurrence of the
run's last stroboscopic sections (period k <= min(``max_period_multiple``, :data:`RESCUE_MAX_K`)
with relative mismatch below :data:`RESCUE_MISMATCH`) as a seed: the Newton shooting of the k
periods' impacts (:func:`~impactdamper.analysis.point.shoot_cycle`, with the accelerators) or
Newton on the stroboscopic map y(0) -> y(k T) of Timofeev et al. (2019)'s Algorithm No. 2
(:func:`~impactdamper.analysis.strobe.strobe_newton`). A stable, admissible orbit found so,
verified by one simulated cycle (:func:`~impactdamper.analysis.point.verify_cycle`), is the
motion the capped run was still converging to; otherwise the point stays ``nonperiodic``.

:func:`rescue_run` rescues from the run's :class:`~impactdamper.core.settled_cycle.SteadyState` (step 5
of :func:`~impactdamper.analysis.ladder.solve_point`); :func:`rescue_from_sections` from the last
sections alone (the batch's points, :mod:`impactdamper.analysis.batch`).
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper.analysis.point import (
    STABILITY_MARGIN,
    SweepPoint,
    SweepSettings,
    orbit_section,
    shoot_cycle,
    verify_cycle,
)
from impactdamper.analysis.strobe import strobe_newton
from impactdamper.core.backends import get_backend
from impactdamper.core.parameters import Parameters, state_scale
from impactdamper.core.settled_cycle import SteadyState, section_of

__all__ = ["RESCUE_MISMATCH", "RESCUE_MAX_K", "rescue_run", "rescue_from_sections"]

# A closest recurrence of the capped run below this (relative section mismatch) seeds the
# rescue Newton: close enough for Newton's basin, far above settle_tol (a still-converging
# transient with a multiplier of modulus 0.97 leaves ~1e-4 after 150 periods).
RESCUE_MISMATCH = 1e-2
# The rescue tries periods up to this k (Newton for k = 8 costs 8x a period-1 solve).
RESCUE_MAX_K = 8


def _closest_recurrence(s: SteadyState, kmax: int) -> tuple[int, float]:
    """Period k <= kmax whose last k sections best repeat those k periods earlier.

    The sections are the run's (``SteadyState.sections``); without them, those of the stored
    trajectory around the reported window."""
    p = s.p
    sections = getattr(s, "sections", None)
    if sections is not None and len(sections):
        sec = np.asarray(sections, float)[-(2 * kmax + 1) :] / state_scale(p)
    else:
        T = p.T
        last = math.floor((s.cycle_start + s.cycle_duration) / T + 1e-9)
        ts = np.arange(last - 2 * kmax, last + 1) * T
        ts = ts[ts >= s.trajectory.segments[0][1].t0]
        sec = s.trajectory.sample(ts)[0] / state_scale(p)
    return _recurrence_of(sec, kmax)


def _recurrence_of(sec: np.ndarray, kmax: int) -> tuple[int, float]:
    """(k, mismatch) of the closest recurrence among scaled sections ``sec`` (oldest first)."""
    m = len(sec)
    best_k, best = 0, math.inf
    for k in range(1, kmax + 1):
        if m < 2 * k + 1:
            break
        worst = max(float(np.max(np.abs(sec[m - 1 - j] - sec[m - 1 - j - k]))) for j in range(k))
        if worst < best:
            best_k, best = k, worst
    return best_k, best


def rescue_run(
    p: Parameters,
    value: float,
    s: SteadyState,
    settings: SweepSettings,
    *,
    start: str,
    start_state: np.ndarray,
    periods: int,
) -> SweepPoint | None:
    """The rescue of a capped run ``s`` that did not settle (step 5 of ``solve_point``); None where
    it finds no stable cycle near the run's closest recurrence."""
    k, mismatch = _closest_recurrence(s, min(settings.max_period_multiple, RESCUE_MAX_K))
    if not k or mismatch > RESCUE_MISMATCH:
        return None
    T = p.T
    # k periods of the reported window as a cycle seed for the shooting.
    a = s.cycle_start
    b = a + k * T
    if settings.continuation:
        events = s.trajectory.impacts(a, b)
        has_contact = any(e.kind != "impact" and a <= e.t < b for e in s.trajectory.events)
        if events and not has_contact:
            times = np.array([e.t for e in events])
            after = np.array([e.after for e in events])
            o = shoot_cycle(p, k, times, after, settings.tolerances)
            if o is not None and o.admissible and o.stable and o.spectral_radius < 1.0 - STABILITY_MARGIN:
                # Report the shortest period: verify by simulation from the orbit (settles at once).
                section, mode = orbit_section(o)
                return verify_cycle(
                    p,
                    value,
                    section,
                    o.period_multiple,
                    settings,
                    method="rescue",
                    start=start,
                    start_state=start_state,
                    periods=periods,
                    rho=o.spectral_radius,
                )
    full, mode = section_of(s)
    return _stroberescue_run(p, value, full, mode, k, settings, start=start, start_state=start_state, periods=periods)


def _stroberescue_run(
    p: Parameters,
    value: float,
    full: np.ndarray,
    mode: str,
    k: int,
    settings: SweepSettings,
    *,
    start: str,
    start_state: np.ndarray,
    periods: int,
) -> SweepPoint | None:
    """Step 3 of the rescue: Newton on the stroboscopic map from section state ``full``."""
    step = get_backend(settings.backend)[0].map_step(p, settings.tolerances)
    res = strobe_newton(p, full, mode, k, settings.tolerances, step=step)
    if res is None:
        return None
    sol, rho, used, J = res.state, res.spectral_radius, res.periods, res.jacobian
    if rho >= 1.0 - STABILITY_MARGIN:
        return None
    return verify_cycle(
        p,
        value,
        sol,
        k,
        settings,
        method="rescue",
        start=start,
        start_state=start_state,
        periods=periods + used,
        rho=rho,
        jacobian=J,
    )


def rescue_from_sections(
    p: Parameters,
    value: float,
    sections: np.ndarray,
    section: np.ndarray,
    section_mode: str,
    settings: SweepSettings,
    *,
    start: str,
    start_state: np.ndarray,
    periods: int,
) -> SweepPoint | None:
    """The Newton rescue of a point that did not settle, from its run's last sections instead
    of its :class:`~impactdamper.core.settled_cycle.SteadyState` (the compiled batch hands them over,
    so the run is not repeated in Python). Only the rescue without accelerators
    (``settings.continuation`` False): the closest recurrence k of the last sections, then
    Newton on the stroboscopic map from ``section`` (the section state at the start of the
    reported window, in mode ``section_mode``), then the cycle verified by simulation.

    Parameters
    ----------
    sections : ndarray, shape (m, 4)
        The run's last section states (x1, x2, x1', x2'), oldest first (at least
        2 min(max_period_multiple, RESCUE_MAX_K) + 1 of them; fewer: fewer k are tried).
    periods : int
        Forcing periods the run simulated (the point's count, as solve_point's).

    Returns
    -------
    SweepPoint with method ``rescue``, or None where the rescue finds no stable cycle.
    """
    if settings.continuation:
        raise ValueError(
            "`settings` is not allowed: rescue_from_sections is the rescue without accelerators (continuation=False)"
        )
    kmax = min(settings.max_period_multiple, RESCUE_MAX_K)
    sec = np.asarray(sections, float)
    sec = sec[np.all(np.isfinite(sec), axis=1)][-(2 * kmax + 1) :] / state_scale(p)
    k, mismatch = _recurrence_of(sec, kmax)
    if not k or mismatch > RESCUE_MISMATCH:
        return None
    return _stroberescue_run(
        p,
        value,
        np.asarray(section, float),
        section_mode,
        k,
        settings,
        start=start,
        start_state=start_state,
        periods=periods,
    )
