"""The settled motion, compiled: the stroboscopic period test and the cycle's description.

The reference's :func:`impactdamper.core.steady.steady_state` on arrays: the event loop
(:mod:`~impactdamper.core.compiled.loop`) is sampled at the sections t = n T, the period test
with its divisor rule finds the least period k, the clock is re-based every ``REBASE_PERIODS``,
and the cycle is described (regime, impacts, contact fraction, x1_max, the section carried to a
sweep's next point). :func:`row_kernel` settles a sweep's or a map row's points one after the
other, each from its neighbour's section (or from its own start).

Both end in bounded time: the event loop spends the reference's step budget
(:mod:`~impactdamper.core.compiled.loop`), the period loop stops at ``max_periods``, and the run
that describes the cycle grows its buffers only as far as that budget allows
(:func:`~impactdamper.core.compiled.loop.recorded_run`, the one capacity-retry loop).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactdamper.core.compiled.flow import full_state, mode_size, mode_state
from impactdamper.core.compiled.layout import (
    IMPACT,
    MODE_STUCK,
    OK,
    SI_ERR,
    SI_MODE,
    S_DELTA0,
    S_M1,
    S_M2,
    S_OMEGA,
    S_OMEGA1,
    S_T,
    S_XST,
)
from impactdamper.core.compiled.loop import advance, diagnose, init_solver, recorded_run, solver_buffers, solver_state
from impactdamper.core.simulate import DEFAULT_KICK
from impactdamper.core.periodicity import (
    CONVERGENCE_NOISE,
    CONVERGENCE_WINDOW,
    DIVISOR_DECAY,
    DIVISOR_FLOOR_FACTOR,
    DIVISOR_SUSPECT,
    ROUNDING_FLOOR,
    STALL_WINDOW,
)
from impactdamper.core.steady import (
    EXCURSION_SAMPLES_PER_PERIOD,
    NONPERIODIC_WINDOW,
    PERIODS_BEFORE_CYCLE,
    REBASE_PERIODS,
)

# Golden-section iterations of the x1_max refinement: 0.618^80 ~ 2e-17 of a bracket of 2/256 T,
# below the reference's xatol of 1e-12 T.
GOLDEN_ITERATIONS = 80
_GOLD = 0.5 * (3.0 - math.sqrt(5.0))


@njit(cache=True)
def _mismatch(sections, modes, n, k):
    if n < 2 * k + 1:
        return math.inf
    for j in range(k):
        if modes[n - k + j] != modes[n - 2 * k + j]:
            return math.inf
    worst = 0.0
    for j in range(k):
        for c in range(4):
            worst = max(worst, abs(sections[n - k + j, c] - sections[n - 2 * k + j, c]))
    return worst


@njit(cache=True)
def _period(sections, modes, n, kmax, tol):
    best = math.inf
    for k in range(1, kmax + 1):
        worst = _mismatch(sections, modes, n, k)
        best = min(best, worst)
        if worst < tol:
            return k, worst
    return 0, best


@njit(cache=True)
def _lag_windows(sections, n, lag, window):
    """The largest change over ``lag`` periods in each of the two last windows of ``window``
    sections before n: (the older window's, the recent one's). Whether it decays from one to
    the next tells a transient from a settled motion (the divisor rule, the convergence test)."""
    older = 0.0
    recent = 0.0
    for r in range(2 * window):
        row = n - 2 * window + r
        worst = 0.0
        for c in range(4):
            worst = max(worst, abs(sections[row, c] - sections[row - lag, c]))
        if r < window:
            older = max(older, worst)
        else:
            recent = max(recent, worst)
    return older, recent


@njit(cache=True)
def _least_period(sections, modes, n, k, settle_tol):
    window = max(STALL_WINDOW, 2 * k)
    for d in range(1, k):
        m = _mismatch(sections, modes, n, d) if k % d == 0 else math.inf
        if m >= max(DIVISOR_SUSPECT, DIVISOR_FLOOR_FACTOR * settle_tol):
            continue
        if n < 2 * window + d:
            return 0, m
        first, second = _lag_windows(sections, n, d, window)
        if second < DIVISOR_DECAY * first:
            return 0, m
        if m < min(DIVISOR_FLOOR_FACTOR * settle_tol, DIVISOR_SUSPECT):
            return d, m
    return k, _mismatch(sections, modes, n, k)


@njit(cache=True)
def _converged(sections, n, k, settle_tol):
    """The reference's _converged on the first n sections."""
    w = -(-max(CONVERGENCE_WINDOW, 2 * k) // k) * k
    if n < 2 * w + k:
        return False
    spread = 0.0
    for i in range(w):
        for c in range(4):
            spread = max(spread, abs(sections[n - 1 - i, c] - sections[n - 1 - i % k, c]))
    older, recent = _lag_windows(sections, n, k, w)
    if recent < max(CONVERGENCE_NOISE * settle_tol, ROUNDING_FLOOR):
        tail = 0.0
    elif recent < older:
        g = (recent / older) ** (k / w)
        tail = recent * g / (1.0 - g)
    else:
        tail = math.inf
    return max(spread, tail) < settle_tol


@njit(cache=True)
def _seg_index(seg_f, ns, t):
    """The reference's Trajectory._segment_index for one time."""
    lo, hi = 0, ns
    while lo < hi:  # searchsorted(starts, t, side="right")
        mid = (lo + hi) // 2
        if seg_f[mid, 0] <= t:
            lo = mid + 1
        else:
            hi = mid
    return min(max(lo - 1, 0), ns - 1)


@njit(cache=True)
def _sample(cm, s, seg_m, seg_f, seg_a, ns, t, out, y):
    """Full state at t (into out; y is scratch), and the mode there."""
    k = _seg_index(seg_f, ns, t)
    mode_state(cm, s, seg_m[k], seg_f[k, 0], seg_a[k], t, y)
    full_state(s, seg_m[k], y, out)
    return seg_m[k]


@njit(cache=True)
def _abs_x1(cm, s, seg_m, seg_f, seg_a, k, t, y):
    """|x1(t)| on segment k: the first row of eq. (18) alone, one root of each conjugate pair
    (as the event search's evaluator), the excursion search's hot path. It differs from the
    full state's x1 by rounding only, which moves the maximum's value by rounding only."""
    mode = seg_m[k]
    n = mode_size(mode)
    tau = t - seg_f[k, 0]
    acc = 0.0
    for j in range(n):
        lam = cm[mode, 0, j]
        if lam.imag < 0.0:
            continue
        term = (cm[mode, 2, j] * seg_a[k, j] * np.exp(lam * tau)).real
        acc += 2.0 * term if lam.imag > 0.0 else term
    return abs(acc + (cm[mode, 1, 0] * np.exp(1j * s[S_OMEGA] * t)).imag)


@njit(cache=True)
def _golden_max(cm, s, seg_m, seg_f, seg_a, k, lo, hi):
    """max |x1| on [lo, hi] of segment k by golden-section search."""
    y = np.empty(4)
    a, b = lo, hi
    c = a + _GOLD * (b - a)
    d = b - _GOLD * (b - a)
    fc_ = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, c, y)
    fd_ = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, d, y)
    for _ in range(GOLDEN_ITERATIONS):
        if fc_ >= fd_:
            b, d, fd_ = d, c, fc_
            c = a + _GOLD * (b - a)
            fc_ = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, c, y)
        else:
            a, c, fc_ = c, d, fd_
            d = b - _GOLD * (b - a)
            fd_ = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, d, y)
    return max(fc_, fd_)


@njit(cache=True)
def _max_excursion(cm, s, seg_m, seg_f, seg_a, ns, a, b):
    T = s[S_T]
    n = max(int(EXCURSION_SAMPLES_PER_PERIOD * (b - a) / T), 16)
    ts = np.linspace(a, b, n + 1)
    x1 = np.empty(n + 1)
    y = np.empty(4)
    k = _seg_index(seg_f, ns, ts[0])
    for j in range(n + 1):
        # The samples increase: the segment index only moves forward (the same index as
        # _seg_index gives, without a search per sample).
        while k + 1 < ns and seg_f[k + 1, 0] <= ts[j]:
            k += 1
        x1[j] = _abs_x1(cm, s, seg_m, seg_f, seg_a, k, ts[j], y)
    i = int(np.argmax(x1))
    best = x1[i]
    for end in range(2):
        if end == 1:
            if i != 0 and i != n:
                break
            j = n if i == 0 else 0
            lo, hi = ts[max(j - 1, 0)], ts[min(j + 1, n)]
            k = _seg_index(seg_f, ns, 0.5 * (lo + hi))
        else:
            lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, n)]
            k = _seg_index(seg_f, ns, ts[i])
        seg_end = seg_f[k + 1, 0] if k + 1 < ns else math.inf
        lo, hi = max(lo, seg_f[k, 0]), min(hi, seg_end)
        if hi > lo:
            best = max(best, _golden_max(cm, s, seg_m, seg_f, seg_a, k, lo, hi))
    return best / s[S_XST]


# Regime codes: indices into steady.REGIMES.
_RG_NO_CONTACT, _RG_STUCK, _RG_CHATTER, _RG_SINGLE, _RG_MULTI, _RG_NONPERIODIC = range(6)


@njit(cache=True)
def _describe(cm, s, ev_k, ev_f, ne, seg_m, seg_f, seg_a, ns, window_start, k, settled, out_imp, section):
    """The compiled counterpart of :func:`impactdamper.core.steady.describe_cycle`. Fills out_imp
    rows (t, t/T since start, phase, velocity, impulse) and section (state at the first section in
    the cycle, then its mode).
    Returns (regime code, impacts, cycle start, contact fraction, x1_max)."""
    T = s[S_T]
    Tc = k * T
    window_end = window_start + Tc
    start = window_start
    best_flight = -math.inf
    t_begin = seg_f[0, 0]
    for i in range(ne):
        if ev_k[i] == IMPACT and window_start <= ev_f[i, 0] < window_end:
            flight = ev_f[i, 0] - (ev_f[i - 1, 0] if i else t_begin)
            if flight > best_flight:
                best_flight = flight
                start = ev_f[i, 0]
    # The cycle's events (the reference's _cycle_events): [start, start + T_c - flight / 2)
    # after the start impact's (longest) flight, never a window with a fixed margin, which a
    # loose settle_tol's drift per period made count one impact twice; without impacts, or for
    # no cycle, [start, start + T_c).
    end_t = start + Tc
    if settled and best_flight > -math.inf:
        end_t = start + Tc - 0.5 * best_flight
    first = ne
    end = ne
    for i in range(ne):
        if first == ne and ev_f[i, 0] >= start:
            first = i
        if ev_f[i, 0] >= end_t:
            end = i
            break
    if end < first:
        end = first
    z = 0
    contact_events = False
    for i in range(first, end):
        t = ev_f[i, 0]
        if ev_k[i] == IMPACT:
            if z < out_imp.shape[0]:
                out_imp[z, 0] = t
                out_imp[z, 1] = (t - start) / T
                out_imp[z, 2] = (t / T) % 1.0
                out_imp[z, 3] = ev_f[i, 1]
                out_imp[z, 4] = ev_f[i, 2]
            z += 1
        else:
            contact_events = True
    contact_time = 0.0
    a, b = start, start + Tc
    for i in range(ns):
        if seg_m[i] != MODE_STUCK:
            continue
        s1 = seg_f[i + 1, 0] if i + 1 < ns else math.inf
        lo, hi = max(seg_f[i, 0], a), min(s1, b)
        if hi > lo:
            contact_time += hi - lo
    contact_fraction = min(contact_time / Tc, 1.0)
    if not settled:
        regime = _RG_NONPERIODIC
    elif contact_fraction >= 1.0 - 1e-12 and z == 0:
        regime = _RG_STUCK
    elif z == 0 and contact_fraction == 0.0:
        regime = _RG_NO_CONTACT
    elif contact_events or contact_fraction > 0.0:
        regime = _RG_CHATTER
    elif k == 1 and z == 1:
        regime = _RG_SINGLE
    else:
        regime = _RG_MULTI
    x1_max = _max_excursion(cm, s, seg_m, seg_f, seg_a, ns, start, start + Tc)
    t_sec = math.ceil(start / T - 1e-9) * T
    full = np.empty(4)
    section[4] = _sample(cm, s, seg_m, seg_f, seg_a, ns, t_sec, full, np.empty(4))
    section[:4] = full
    return regime, z, start, contact_fraction, x1_max


# Events a settled cycle's description is first given room for (the run of a few cycles that
# describes it; grown by recorded_run where a chatter cycle needs more).
INITIAL_CAPACITY = 256


@njit(cache=True)
def _failed(err, n, residual, states, section):
    """steady_kernel's values for a run that stopped on an error (empty arrays)."""
    no_events, no_segments = np.empty((0, 12)), np.empty((0, 5))
    empty = np.empty(0, np.int64)
    return (
        err,
        0,
        0,
        0.0,
        0.0,
        0.0,
        n,
        residual,
        states[:0],
        np.empty((0, 5)),
        section,
        empty,
        no_events,
        empty,
        no_segments,
    )


@njit(cache=True)
def _settled_period(sections, modes, n, kmax, settle_tol):
    """The reference's settling test after ``n`` sections: (k, residual), k the cycle's least
    period in forcing periods once the motion has settled (0 before), residual the sections'
    mismatch (inf before two sections can be compared). A quick look first: the smallest
    mismatch of the last section with one up to ``kmax`` periods back; only below
    ``settle_tol`` are the period, its least divisor and the convergence checked."""
    lags = min(kmax, (n - 1) // 2)
    if lags == 0:
        return 0, math.inf
    residual = math.inf
    for j in range(1, lags + 1):
        worst = 0.0
        for c in range(4):
            worst = max(worst, abs(sections[n - 1 - j, c] - sections[n - 1, c]))
        residual = min(residual, worst)
    if residual >= settle_tol:
        return 0, residual
    k, residual = _period(sections, modes, n, kmax, settle_tol)
    if k:
        k, residual = _least_period(sections, modes, n, k, settle_tol)
    if k and residual < settle_tol and not _converged(sections, n, k, settle_tol):
        k = 0
    return k, residual


@njit(cache=True)
def steady_kernel(cm, fm, fc, fk, fg, s, t0, state, default_start, settle_tol, max_periods, kmax, diag):
    """The reference's _steady_state and describe_cycle. Returns (error, regime, k, cycle start,
    contact fraction, x1_max, periods, residual, section states (periods, 4), impacts (z, 5):
    t, t/T since the cycle's start, phase, velocity, pulse; section (5,): the state at the
    first section in the cycle and its mode; then the describing run's events and segments
    (kinds, values, modes, values): the motion the reference's describe_run would simulate).
    ``diag`` gets a failed run's diagnostics (layout.DIAG_*)."""
    T = s[S_T]
    scale = np.array([s[S_XST], s[S_XST], s[S_XST] * s[S_OMEGA], s[S_XST] * s[S_OMEGA]])
    states = np.empty((max_periods, 4))
    section = np.zeros(5)
    sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a = solver_buffers(0)
    init_solver(cm, fc, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t0, state)
    if si[SI_ERR]:
        diagnose(sf, si, diag)
        return _failed(si[SI_ERR], 0, 0.0, states, section)
    start_state = np.empty(4)
    if default_start:
        solver_state(cm, s, sf, si, alpha, t0, start_state)
    else:
        start_state[:] = state
    sections = np.empty((max_periods, 4))
    modes = np.empty(max_periods, np.int64)
    found_k, n, residual = 0, 0, math.inf
    base = 0
    for n in range(1, max_periods + 1):
        if n - 1 - base >= REBASE_PERIODS:
            init_solver(cm, fc, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t0, states[n - 2].copy())
            base = n - 1
        if si[SI_ERR] == 0:
            advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t0 + (n - base) * T)
        if si[SI_ERR]:
            diagnose(sf, si, diag)
            return _failed(si[SI_ERR], n, 0.0, states, section)
        solver_state(cm, s, sf, si, alpha, t0 + (n - base) * T, states[n - 1])
        for c in range(4):
            sections[n - 1, c] = states[n - 1, c] / scale[c]
        modes[n - 1] = si[SI_MODE]
        found_k, residual = _settled_period(sections, modes, n, kmax, settle_tol)
        if found_k:
            break
    # The describing run (the reference's describe_run): from a section one cycle (and
    # PERIODS_BEFORE_CYCLE periods) before the reported cycle to one cycle after it.
    k = found_k if found_k else min(NONPERIODIC_WINDOW, n)
    first = max(n - k - max(k, PERIODS_BEFORE_CYCLE), 0)
    err, ev_k, ev_f, seg_m, seg_f, seg_a = recorded_run(
        cm,
        fm,
        fc,
        fk,
        fg,
        s,
        t0,
        states[first - 1].copy() if first else start_state,
        t0 + (n - first + k + 1) * T,
        INITIAL_CAPACITY,
        diag,
    )
    if err:
        return _failed(err, n, residual, states, section)
    imp = np.empty((ev_k.shape[0], 5))
    regime, z, start, frac, x1_max = _describe(
        cm,
        s,
        ev_k,
        ev_f,
        ev_k.shape[0],
        seg_m,
        seg_f,
        seg_a,
        seg_m.shape[0],
        t0 + (n - first - k) * T,
        k,
        found_k > 0,
        imp,
        section,
    )
    return (
        OK,
        regime,
        (k if found_k else 0),
        start,
        frac,
        x1_max,
        n,
        residual,
        states[:n],
        imp[:z].copy(),
        section,
        ev_k,
        ev_f,
        seg_m,
        seg_f,
    )


# ------------------------------------------------------------------------------------------
# Many points per call (a sweep's or a map row's points, each from its neighbour)
# ------------------------------------------------------------------------------------------
# Stop codes of row_kernel: the row is done, or point i needs the reference (its pack flag,
# an error of the kernels, a nonperiodic point to rescue).
ROW_DONE, ROW_FLAGGED, ROW_ERROR, ROW_RESCUE = 0, 1, 2, 3


@njit(cache=True)
def row_kernel(
    S,
    CM,
    FM,
    FC,
    FK,
    FG,
    flags,
    i0,
    prev,
    chain_length,
    rescue,
    settle_tol,
    max_periods,
    max_periods_np,
    kmax,
    given,
    out_i,
    out_f,
    starts,
    sections,
    phases,
    vels,
    tail,
    diag,
):
    """Settle points i0, i0 + 1, ... in order, as the reference's solve_point without its
    accelerators: each from its predecessor's section (the reference's carry_state) where the
    row is chained (``chain_length`` > 0: point i continues point i - 1 unless i is a multiple
    of chain_length, the start of a new chain), else from its row of ``given`` (shape (P, 4):
    the reference's ``state=``; shape (0, 4): none) or from Algorithm No. 2's step 1.

    ``prev`` (shape (7,)): the predecessor of point i0 as (have one, its section (4), its
    section's mode, periodic), updated point by point. Outputs per point: ``out_i`` (P, 5) regime
    code, k, z, periods, section mode; ``out_f`` (P, 3) x1_max, contact fraction, residual;
    ``starts``, ``sections`` (P, 4); ``phases``, ``vels`` (P, M): the first impacts. Returns
    (stop code, index): a point the kernels did not settle stops the row (its flag, an error
    with ``diag`` set, or a nonperiodic point with ``rescue``, its outputs filled and its run's
    last sections in ``tail``, oldest first, rows before the run NaN)."""
    P = S.shape[0]
    full = np.empty(4)
    for i in range(i0, P):
        if flags[i] != 0:
            return ROW_FLAGGED, i
        s = S[i]
        chained = chain_length > 0 and i % chain_length != 0 and prev[0] != 0.0
        if chained:
            full[:] = prev[1:5]
            if prev[5] == MODE_STUCK:
                full[1] = full[0] + s[S_DELTA0]
                full[3] = full[2]
            elif s[S_DELTA0] - (full[1] - full[0]) < 0.0:
                full[1] = full[0] + s[S_DELTA0]
        elif given.shape[0] > 0:
            full[:] = given[i]
        else:
            S0 = DEFAULT_KICK * s[S_M1] * s[S_OMEGA1] * s[S_XST]
            full[0], full[1], full[2], full[3] = 0.0, s[S_DELTA0], S0 / s[S_M1], -S0 / s[S_M2]
        cap = max_periods_np if (chained and prev[6] == 0.0) else max_periods
        starts[i] = full
        err, rg, k, _, fr, x1, n, res, states, imp, section, _, _, _, _ = steady_kernel(
            CM[i], FM[i], FC[i], FK[i], FG[i], S[i], 0.0, full.copy(), False, settle_tol, cap, kmax, diag
        )
        if err != OK:
            return ROW_ERROR, i
        z = imp.shape[0]
        out_i[i, 0], out_i[i, 1], out_i[i, 2], out_i[i, 3], out_i[i, 4] = rg, k, z, n + max(k, 1) + 1, int(section[4])
        out_f[i, 0], out_f[i, 1], out_f[i, 2] = x1, fr, res
        sections[i] = section[:4]
        for j in range(min(z, phases.shape[1])):
            phases[i, j] = imp[j, 2]
            vels[i, j] = imp[j, 3] / (s[S_XST] * s[S_OMEGA])
        prev[0] = 1.0
        prev[1:5] = section[:4]
        prev[5] = section[4]
        prev[6] = 1.0 if rg != _RG_NONPERIODIC else 0.0
        if rg == _RG_NONPERIODIC and rescue:
            R = tail.shape[0]
            for j in range(R):
                m = n - R + j
                if m < 0:
                    tail[j, :] = np.nan
                else:
                    tail[j, :] = states[m]
            return ROW_RESCUE, i
    return ROW_DONE, P
