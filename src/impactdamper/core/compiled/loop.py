"""The event loop, compiled: Algorithm No. 2 with contact modes.

The reference's :class:`impactdamper.core.simulate.EventDrivenSolver` on arrays: march the
current mode's functional to its first root (:mod:`~impactdamper.core.compiled.march`); on the
free mode that is an impact, on the stuck mode a lift-off. The impact law of eqs. (21)-(22) gives
the pulse and the velocities after it; a rebound too slow to part the bodies captures them into
persistent contact; a contact-force dip too brief to part them keeps the contact; the gap's or
the force's first non-zero derivative decides which way a grazing start leaves. Events and
segments are recorded into preallocated buffers (a capacity error asks for larger ones,
:func:`recorded_run`).

The work bound is the reference's: a run may take ``STEPS_AT_START`` plus ``STEPS_PER_PERIOD``
certified search steps per forcing period (``ERR_BUDGET``), at most ``MAX_EVENTS_AT_ONE_TIME``
events at one instant (``ERR_DEGENERATE``). Every event and every contact switch costs at least
one certified step (an impact, a lift-off or a touch of the contact force is the root of a
march), so the step budget bounds the events per period, the contact switches and the buffers
of a recorded run alike: no loop of the kernels runs without spending it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactdamper.core.compiled.flow import full_state, modal_coefficients, mode_size, mode_state, of_state
from impactdamper.core.compiled.impact import accumulation_time, apply_impact, rebound
from impactdamper.core.compiled.layout import (
    DIAG_ERR,
    DIAG_IMPACTS,
    DIAG_START,
    DIAG_TIME,
    DIAG_USED,
    ERR_CAPACITY,
    ERR_DEGENERATE,
    ERR_STUCK_RESONANT,
    FORCE,
    GAP,
    IMPACT,
    LIFTOFF,
    MARCH_NONE,
    MARCH_ROOT,
    MODE_FREE,
    MODE_STUCK,
    NEG_FORCE,
    SF_DEPG,
    SF_ERRT,
    SF_FROM,
    SF_LAST,
    SF_LIMIT,
    SF_START,
    SF_T0,
    SF_USED,
    SI_DEPM,
    SI_ERR,
    SI_IMPACTS,
    SI_MODE,
    SI_NEV,
    SI_NSEG,
    SI_REC,
    SI_SAME,
    STICK,
    S_CHATTER,
    S_DELTA0,
    S_FORCE_EPS,
    S_GAP_EPS,
    S_LSCALE,
    S_M1,
    S_M2,
    S_MRED,
    S_OMEGA,
    S_OMEGA1,
    S_STUCK_RES,
    S_T,
)
from impactdamper.core.compiled.march import march
from impactdamper.core.compiled.pack import pack_single
from impactdamper.core.constants import (
    CURVATURE_FLOOR,
    DEPARTURE_FLOOR,
    DEPARTURE_ULPS,
    REBOUND_FLOOR,
    SAME_TIME_ULPS,
    STEPS_AT_START,
    STEPS_PER_PERIOD,
)
from impactdamper.core.simulate import DIP_SAMPLES, MAX_EVENTS_AT_ONE_TIME


# The hot path (a march step, an impact, a segment start) is inlined into its callers at numba's
# IR level (inline="always"): measured 3.5 -> 2.5 us per impact, for about 20 s more compile time
# (the warm-up from an empty cache, 64 -> 85 s).


@njit(cache=True, inline="always")
def _no_room(si, k, rows):
    """Whether row k is past a buffer of ``rows`` rows (then the capacity error is set)."""
    if k >= rows:
        si[SI_ERR] = ERR_CAPACITY
        return True
    return False


@njit(cache=True, inline="always")
def _record_event(s, sf, si, ev_k, ev_f, t, kind, v, S, before, after, t_acc):
    if si[SI_NEV] > 0 and t - sf[SF_LAST] <= SAME_TIME_ULPS * np.spacing(max(abs(t), 1.0)):
        si[SI_SAME] += 1
        if si[SI_SAME] > MAX_EVENTS_AT_ONE_TIME:
            si[SI_ERR] = ERR_DEGENERATE
            sf[SF_ERRT] = t
            return
    else:
        si[SI_SAME] = 0
    # (a chatter sequence: impacts in a row, which the work bound's message reads)
    si[SI_IMPACTS] = si[SI_IMPACTS] + 1 if kind == IMPACT else 0
    k = si[SI_NEV]
    if si[SI_REC]:
        if _no_room(si, k, ev_k.shape[0]):
            return
        ev_k[k] = kind
        ev_f[k, 0], ev_f[k, 1], ev_f[k, 2], ev_f[k, 11] = t, v, S, t_acc
        for i in range(4):
            ev_f[k, 3 + i] = before[i]
            ev_f[k, 7 + i] = after[i]
    si[SI_NEV] = k + 1
    sf[SF_LAST] = t


@njit(cache=True, inline="always")
def _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, mode, t, y, dep_m, dep_g):
    if mode == MODE_STUCK and s[S_STUCK_RES] != 0.0:
        si[SI_ERR] = ERR_STUCK_RESONANT
        return
    si[SI_MODE] = mode
    n = mode_size(mode)
    for i in range(4):
        y0[i] = y[i] if i < n else 0.0
        alpha[i] = 0j
    modal_coefficients(cm, s, mode, t, y0, alpha)
    sf[SF_T0] = t
    k = si[SI_NSEG]
    if si[SI_REC] and not _no_room(si, k, seg_m.shape[0]):
        seg_m[k] = mode
        seg_f[k, 0] = t
        for i in range(4):
            seg_f[k, 1 + i] = y0[i]
            seg_a[k, i] = alpha[i]
    si[SI_NSEG] = k + 1
    sf[SF_FROM] = t
    si[SI_DEPM] = dep_m
    sf[SF_DEPG] = dep_g


@njit(cache=True, inline="always")
def _gap_departure(fc, s, t, full, rebound):
    """(order, value) of the gap's first non-zero derivative leaving the stop; order 0: none."""
    scale = s[S_LSCALE]
    w = max(s[S_OMEGA], s[S_OMEGA1])
    if rebound > REBOUND_FLOOR * scale * w:
        return 1, rebound
    derivs = np.empty(5)
    for k in range(5):
        derivs[k] = of_state(fc, s, GAP, MODE_FREE, t, full, k)
    for order in range(2, 5):
        threshold = DEPARTURE_FLOOR * scale * w**order
        if order < 4:
            threshold = max(threshold, DEPARTURE_ULPS * np.spacing(max(abs(t), 1.0)) * abs(derivs[order + 1]))
        if derivs[order] > threshold:
            return order, derivs[order]
        if derivs[order] < -threshold:
            return 0, 0.0
    return 0, 0.0


@njit(cache=True)
def _force_departure(fc, s, t, stuck):
    F = of_state(fc, s, FORCE, MODE_STUCK, t, stuck, 0)
    scale = s[S_FORCE_EPS]
    if F > scale:
        return 0, 0.0
    w = max(s[S_OMEGA], s[S_OMEGA1])
    for order in range(1, 4):
        d = of_state(fc, s, FORCE, MODE_STUCK, t, stuck, order)
        if d > scale * w**order:
            return order, d
        if d < -scale * w**order:
            return 0, 0.0
    return 0, 0.0


@njit(cache=True)
def _stick(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full, t_inf):
    m1, m2 = s[S_M1], s[S_M2]
    v_cm = (m1 * full[2] + m2 * full[3]) / (m1 + m2)
    stuck = np.empty(4)
    stuck[0], stuck[1], stuck[2], stuck[3] = full[0], v_cm, 0.0, 0.0
    S = m1 * (v_cm - full[2])
    after = np.empty(4)
    full_state(s, MODE_STUCK, stuck, after)
    _record_event(s, sf, si, ev_k, ev_f, t, STICK, 0.0, S, full, after, t_inf)
    if si[SI_ERR]:
        return
    dm, dg = _force_departure(fc, s, t, stuck)
    _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, MODE_STUCK, t, stuck, dm, dg)


@njit(cache=True, inline="always")
def _leave_contact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full, rebound):
    F = (
        fc[FORCE, 6, 0]
        + fc[FORCE, 6, 1] * math.sin(s[S_OMEGA] * t)
        + fc[FORCE, 0, 0] * full[0]
        + fc[FORCE, 0, 1] * full[2]
    )
    a = F / s[S_MRED]
    if a > 0.0 and rebound * rebound <= 2.0 * a * s[S_CHATTER] * s[S_LSCALE]:
        t_inf = accumulation_time(s, t, rebound, a)
        _stick(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full, t_inf)
        return
    dm, dg = _gap_departure(fc, s, t, full, rebound)
    if dm == 0:
        _stick(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full, t)
        return
    _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, MODE_FREE, t, full, dm, dg)


@njit(cache=True, inline="always")
def _impact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full):
    """Eqs. (21)-(22) (:mod:`~impactdamper.core.compiled.impact`): the pulse S = m_red (1 + R) v;
    then rebound, separate or stick."""
    after, v, S = apply_impact(s, full)
    _record_event(s, sf, si, ev_k, ev_f, t, IMPACT, v, S, full, after, t)
    if si[SI_ERR]:
        return
    _leave_contact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, after, rebound(s, v))


@njit(cache=True)
def _dip_unresolved(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, t, full):
    """The reference's _dip_unresolved: a contact-force dip too brief to part the bodies by
    more than the grazing resolution keeps the contact. Returns True if it does."""
    T = s[S_T]
    stuck = np.empty(4)
    t0 = sf[SF_T0]
    mode_state(cm, s, MODE_STUCK, t0, alpha, t, stuck)
    slope = of_state(fc, s, FORCE, MODE_STUCK, t, stuck, 1)
    budget = np.array([sf[SF_LIMIT], sf[SF_USED]])
    dm, dg = (1, -slope) if slope < 0.0 else (0, 0.0)
    status, t_up, _, reached = march(
        cm, fm, fc, fk, fg, s, NEG_FORCE, MODE_STUCK, t0, alpha, t, t + T, s[S_FORCE_EPS], dm, dg, budget
    )
    sf[SF_USED] = budget[1]
    if status > MARCH_ROOT:
        si[SI_ERR] = status
        sf[SF_ERRT] = reached
        return False
    if status == MARCH_NONE or t_up <= t:
        return False
    a_free = np.empty(4, np.complex128)
    modal_coefficients(cm, s, MODE_FREE, t, full, a_free)
    y = np.empty(4)
    ts = np.linspace(t, t_up, DIP_SAMPLES)
    gmax = -math.inf
    for i in range(DIP_SAMPLES):
        mode_state(cm, s, MODE_FREE, t, a_free, ts[i], y)
        gmax = max(gmax, s[S_DELTA0] - (y[1] - y[0]))
    if gmax > s[S_GAP_EPS]:
        return False
    mode_state(cm, s, MODE_STUCK, t0, alpha, t_up, stuck)
    slope_up = of_state(fc, s, FORCE, MODE_STUCK, t_up, stuck, 1)
    sf[SF_FROM] = t_up
    if slope_up > 0.0:
        si[SI_DEPM], sf[SF_DEPG] = 1, slope_up
    else:
        si[SI_DEPM], sf[SF_DEPG] = 0, 0.0
    return True


@njit(cache=True)
def _liftoff(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t):
    stuck = np.empty(4)
    mode_state(cm, s, MODE_STUCK, sf[SF_T0], alpha, t, stuck)
    full = np.empty(4)
    full_state(s, MODE_STUCK, stuck, full)
    dm, dg = _gap_departure(fc, s, t, full, 0.0)
    if dm == 0:
        F2 = of_state(fc, s, FORCE, MODE_STUCK, t, stuck, 2)
        sf[SF_FROM] = t
        si[SI_DEPM], sf[SF_DEPG] = 2, max(F2, CURVATURE_FLOOR)
        return
    if _dip_unresolved(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, t, full) or si[SI_ERR]:
        return
    _record_event(s, sf, si, ev_k, ev_f, t, LIFTOFF, 0.0, 0.0, full, full, t)
    if si[SI_ERR]:
        return
    _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, MODE_FREE, t, full, dm, dg)


@njit(cache=True)
def init_solver(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, state):
    """The reference solver's constructor (state already checked: gap >= -gap_tol)."""
    sf[:] = 0.0
    record = si[SI_REC]
    si[:] = 0
    si[SI_REC] = record
    sf[SF_START] = t0
    sf[SF_LIMIT] = STEPS_AT_START
    full = state.copy()
    gap = s[S_DELTA0] - (full[1] - full[0])
    if gap <= s[S_GAP_EPS]:
        full[1] = full[0] + s[S_DELTA0]
        if full[3] - full[2] > 0.0:
            _impact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, full)
        else:
            _leave_contact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, full, full[2] - full[3])
    else:
        _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, MODE_FREE, t0, full, 0, 0.0)


@njit(cache=True)
def advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_target):
    """The reference's EventDrivenSolver.advance; sets si[SI_ERR] on an error."""
    T = s[S_T]
    sf[SF_LIMIT] = STEPS_AT_START + int(STEPS_PER_PERIOD * max(t_target - sf[SF_START], 0.0) / T)
    budget = np.empty(2)
    full = np.empty(4)
    while si[SI_ERR] == 0:
        mode = si[SI_MODE]
        if mode == MODE_FREE:
            f = GAP
            eps = s[S_GAP_EPS]
        else:
            f = FORCE
            eps = s[S_FORCE_EPS]
        if sf[SF_FROM] >= t_target:
            return
        budget[0], budget[1] = sf[SF_LIMIT], sf[SF_USED]
        status, t_event, _, reached = march(
            cm,
            fm,
            fc,
            fk,
            fg,
            s,
            f,
            mode,
            sf[SF_T0],
            alpha,
            sf[SF_FROM],
            t_target,
            eps,
            si[SI_DEPM],
            sf[SF_DEPG],
            budget,
        )
        sf[SF_USED] = budget[1]
        if status > MARCH_ROOT:
            si[SI_ERR] = status
            sf[SF_ERRT] = reached
            return
        if status == MARCH_NONE:
            sf[SF_FROM] = reached
            si[SI_DEPM], sf[SF_DEPG] = 0, 0.0
            return
        if mode == MODE_FREE:
            mode_state(cm, s, MODE_FREE, sf[SF_T0], alpha, t_event, full)
            full[1] = full[0] + s[S_DELTA0]
            _impact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_event, full.copy())
        else:
            _liftoff(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_event)


@njit(cache=True)
def solver_state(cm, s, sf, si, alpha, t, out):
    y = np.empty(4)
    mode_state(cm, s, si[SI_MODE], sf[SF_T0], alpha, t, y)
    full_state(s, si[SI_MODE], y, out)


@njit(cache=True)
def solver_buffers(capacity):
    """A solver's state (sf, si, y0, alpha) and its event and segment buffers of ``capacity``
    rows (0: not recorded)."""
    return (
        np.zeros(8),
        np.zeros(8, np.int64),
        np.zeros(4),
        np.zeros(4, np.complex128),
        np.empty(capacity, np.int64),
        np.empty((capacity, 12)),
        np.empty(capacity, np.int64),
        np.empty((capacity, 5)),
        np.empty((capacity, 4), np.complex128),
    )


@njit(cache=True)
def diagnose(sf, si, diag):
    """A failed run's diagnostics into ``diag`` (see layout.DIAG_*)."""
    diag[DIAG_USED], diag[DIAG_TIME], diag[DIAG_START] = sf[SF_USED], sf[SF_ERRT], sf[SF_START]
    diag[DIAG_IMPACTS], diag[DIAG_ERR] = si[SI_IMPACTS], si[SI_ERR]


@njit(cache=True)
def recorded_run(cm, fm, fc, fk, fg, s, t0, state, t_end, capacity, diag):
    """A recorded run from (t0, state) to t_end, its buffers grown (4 times, rerun) until its
    events fit: never beyond what the run's work bound allows (every event costs a certified
    step, at most two events per step and two at the start), so the growth ends with the run or
    with its ERR_BUDGET. Returns (error, events' kinds and values, segments' modes, values and
    alphas), cut to their lengths; ``diag`` gets a failed run's diagnostics."""
    steps = STEPS_AT_START + STEPS_PER_PERIOD * max(t_end - t0, 0.0) / s[S_T]
    most = int(min(2.0 * steps + 4.0, 2.0**62))
    capacity = min(max(capacity, 1), most)
    while True:
        sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a = solver_buffers(capacity)
        si[SI_REC] = 1
        init_solver(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, state)
        if si[SI_ERR] == 0:
            advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_end)
        if si[SI_ERR] != ERR_CAPACITY or capacity >= most:
            break
        capacity = min(4 * capacity, most)
    diagnose(sf, si, diag)
    ne = min(si[SI_NEV], capacity)
    ns = min(si[SI_NSEG], capacity)
    return si[SI_ERR], ev_k[:ne].copy(), ev_f[:ne].copy(), seg_m[:ns].copy(), seg_f[:ns].copy(), seg_a[:ns].copy()


@njit(cache=True)
def simulate_kernel(cm, fm, fc, fk, fg, s, t0, state, t_end, capacity, diag):
    """:func:`recorded_run` without the alphas: (error, events' kinds and values, segments'
    modes and values)."""
    err, ev_k, ev_f, seg_m, seg_f, _ = recorded_run(cm, fm, fc, fk, fg, s, t0, state, t_end, capacity, diag)
    return err, ev_k, ev_f, seg_m, seg_f


@njit(cache=True)
def pack_simulate_kernel(v, tols, t0, state, t_end, capacity, diag):
    """pack_single, then simulate_kernel, in one call (a short run costs less than boxing the
    packed arrays). Returns (pack flag, then simulate_kernel's values; empty where flag != 0)."""
    s, cm, fm, fc, fk, fg, flag = pack_single(v, tols)
    if flag != 0:
        return flag, 0, np.empty(0, np.int64), np.empty((0, 12)), np.empty(0, np.int64), np.empty((0, 5))
    return (flag,) + simulate_kernel(cm, fm, fc, fk, fg, s, t0, state, t_end, capacity, diag)


@njit(cache=True)
def count_kernel(cm, fm, fc, fk, fg, s, t0, state, t_end):
    """An unrecorded run: (error, events) only (the benchmark's per-impact cost)."""
    sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a = solver_buffers(0)
    init_solver(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, state)
    if si[SI_ERR] == 0:
        advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_end)
    return si[SI_ERR], si[SI_NEV]
