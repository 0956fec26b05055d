"""The settled motion, compiled: the stroboscopic period test and the cycle's description.

The reference's :func:`impactdamper.core.steady.steady_state` on arrays: the event loop
(:mod:`~impactdamper.core.compiled.loop`) is sampled at the sections t = n T, the period test
with its divisor rule finds the least period k, the clock is re-based every ``REBASE_PERIODS``,
and the cycle is described (regime, impacts, contact fraction, x1_max, the section carried to a
sweep's next point). :func:`row_kernel` settles a sweep's or a map row's points one after the
other, each from its neighbour's section.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactdamper.core.compiled.flow import full_state, mode_size, mode_state
from impactdamper.core.compiled.layout import (
    ERR_CAPACITY,
    IMPACT,
    MODE_STUCK,
    OK,
    SI_ERR,
    SI_MODE,
    SI_NEV,
    SI_NSEG,
    SI_REC,
    S_DELTA0,
    S_M1,
    S_M2,
    S_OMEGA,
    S_OMEGA1,
    S_T,
    S_XST,
)
from impactdamper.core.compiled.loop import advance, init_solver, solver_buffers, solver_state
from impactdamper.core.simulate import DEFAULT_KICK
from impactdamper.core.steady import (
    CONVERGENCE_NOISE,
    CONVERGENCE_WINDOW,
    DIVISOR_DECAY,
    DIVISOR_FLOOR_FACTOR,
    DIVISOR_SUSPECT,
    EXCURSION_SAMPLES_PER_PERIOD,
    NONPERIODIC_WINDOW,
    PERIODS_BEFORE_CYCLE,
    REBASE_PERIODS,
    ROUNDING_FLOOR,
    STALL_WINDOW,
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
def _least_period(sections, modes, n, k, settle_tol):
    window = max(STALL_WINDOW, 2 * k)
    for d in range(1, k):
        m = _mismatch(sections, modes, n, d) if k % d == 0 else math.inf
        if m >= DIVISOR_SUSPECT:
            continue
        if n < 2 * window + d:
            return 0, m
        first = 0.0
        second = 0.0
        for r in range(2 * window):
            row = n - 2 * window + r
            worst = 0.0
            for c in range(4):
                worst = max(worst, abs(sections[row, c] - sections[row - d, c]))
            if r < window:
                first = max(first, worst)
            else:
                second = max(second, worst)
        if second < DIVISOR_DECAY * first:
            return 0, m
        if m < DIVISOR_FLOOR_FACTOR * settle_tol:
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
    older = 0.0
    recent = 0.0
    for r in range(2 * w):
        row = n - 2 * w + r
        worst = 0.0
        for c in range(4):
            worst = max(worst, abs(sections[row, c] - sections[row - k, c]))
        if r < w:
            older = max(older, worst)
        else:
            recent = max(recent, worst)
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


@njit(cache=True)
def steady_kernel(
    cm, fm, fc, fk, fg, s, t0, state, default_start, settle_tol, max_periods, kmax, capacity, out_imp, section, tail
):
    """The reference's _steady_state. Returns (error, regime, k, impacts, cycle start, contact
    fraction, x1_max, periods, residual); out_imp and section filled by _describe; ``tail``
    (shape (R, 5), R may be 0) gets the run's last R section states and modes, oldest first
    (rows before the run's first section NaN): what the reference's Newton rescue reads."""
    T = s[S_T]
    scale = np.array([s[S_XST], s[S_XST], s[S_XST] * s[S_OMEGA], s[S_XST] * s[S_OMEGA]])
    sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a = solver_buffers(0)
    init_solver(cm, fc, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t0, state)
    if si[SI_ERR]:
        return si[SI_ERR], 0, 0, 0, 0.0, 0.0, 0.0, 0, 0.0
    start_state = np.empty(4)
    if default_start:
        solver_state(cm, s, sf, si, alpha, t0, start_state)
    else:
        start_state[:] = state
    states = np.empty((max_periods, 4))
    sections = np.empty((max_periods, 4))
    modes = np.empty(max_periods, np.int64)
    found_k, n, residual = 0, 0, math.inf
    base = 0
    for n in range(1, max_periods + 1):
        if n - 1 - base >= REBASE_PERIODS:
            init_solver(cm, fc, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t0, states[n - 2].copy())
            if si[SI_ERR]:
                return si[SI_ERR], 0, 0, 0, 0.0, 0.0, 0.0, 0, 0.0
            base = n - 1
        t_n = t0 + (n - base) * T
        advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t_n)
        if si[SI_ERR]:
            return si[SI_ERR], 0, 0, 0, 0.0, 0.0, 0.0, 0, 0.0
        solver_state(cm, s, sf, si, alpha, t_n, states[n - 1])
        for c in range(4):
            sections[n - 1, c] = states[n - 1, c] / scale[c]
        modes[n - 1] = si[SI_MODE]
        lags = min(kmax, (n - 1) // 2)
        if lags == 0:
            continue
        residual = math.inf
        for j in range(1, lags + 1):
            worst = 0.0
            for c in range(4):
                worst = max(worst, abs(sections[n - 1 - j, c] - sections[n - 1, c]))
            residual = min(residual, worst)
        if residual >= settle_tol:
            found_k = 0
            continue
        found_k, residual = _period(sections, modes, n, kmax, settle_tol)
        if found_k:
            found_k, residual = _least_period(sections, modes, n, found_k, settle_tol)
        if found_k and residual < settle_tol and not _converged(sections, n, found_k, settle_tol):
            found_k = 0
        if found_k:
            break
    R = tail.shape[0]
    for j in range(R):
        m = n - R + j
        if m < 0:
            tail[j, :] = np.nan
        else:
            tail[j, :4] = states[m]
            tail[j, 4] = modes[m]
    k = found_k if found_k else min(NONPERIODIC_WINDOW, n)
    first = max(n - k - max(k, PERIODS_BEFORE_CYCLE), 0)
    _, _, _, _, ev_k, ev_f, seg_m, seg_f, seg_a = solver_buffers(capacity)
    si[SI_REC] = 1
    init_solver(
        cm,
        fc,
        s,
        sf,
        si,
        y0,
        alpha,
        ev_k,
        ev_f,
        seg_m,
        seg_f,
        seg_a,
        t0,
        states[first - 1].copy() if first else start_state,
    )
    if si[SI_ERR] == 0:
        advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0 + (n - first + k + 1) * T)
    if si[SI_ERR]:
        return si[SI_ERR], 0, 0, 0, 0.0, 0.0, 0.0, n, residual
    regime, z, start, frac, x1_max = _describe(
        cm,
        s,
        ev_k,
        ev_f,
        si[SI_NEV],
        seg_m,
        seg_f,
        seg_a,
        si[SI_NSEG],
        t0 + (n - first - k) * T,
        k,
        found_k > 0,
        out_imp,
        section,
    )
    return OK, regime, (k if found_k else 0), z, start, frac, x1_max, n, residual


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
    have_prev,
    prev_section,
    prev_mode,
    prev_periodic,
    chain,
    rescue,
    settle_tol,
    max_periods,
    max_periods_np,
    kmax,
    capacity,
    regime,
    kk,
    zz,
    x1max,
    frac,
    periods,
    residual,
    starts,
    sections,
    sec_mode,
    phases,
    vels,
    given,
    tail,
):
    """Settle points i0, i0 + 1, ... in order, as the reference's solve_point without its
    accelerators: each from its predecessor's section (``chain``, the reference's carry_state),
    from its row of ``given`` (shape (P, 4): the reference's ``state=``; shape (0, 4): none) or
    from Algorithm No. 2's step 1. Fills the output arrays; returns (stop code, index). A
    nonperiodic point with ``rescue`` stops the row after its outputs are filled, with its
    run's last sections in ``tail`` (see steady_kernel), for the Newton rescue."""
    P = S.shape[0]
    out_imp = np.zeros((64 * kmax, 5))
    section = np.zeros(5)
    full = np.empty(4)
    for i in range(i0, P):
        if flags[i] != 0:
            return ROW_FLAGGED, i
        s = S[i]
        if chain and have_prev:
            full[:] = prev_section
            if prev_mode == MODE_STUCK:
                full[1] = full[0] + s[S_DELTA0]
                full[3] = full[2]
            elif s[S_DELTA0] - (full[1] - full[0]) < 0.0:
                full[1] = full[0] + s[S_DELTA0]
        elif given.shape[0] > 0:
            full[:] = given[i]
        else:
            S0 = DEFAULT_KICK * s[S_M1] * s[S_OMEGA1] * s[S_XST]
            full[0], full[1], full[2], full[3] = 0.0, s[S_DELTA0], S0 / s[S_M1], -S0 / s[S_M2]
        cap = max_periods_np if (chain and have_prev and not prev_periodic) else max_periods
        while True:
            err, rg, k, z, start, fr, x1, n, res = steady_kernel(
                CM[i],
                FM[i],
                FC[i],
                FK[i],
                FG[i],
                S[i],
                0.0,
                full.copy(),
                False,
                settle_tol,
                cap,
                kmax,
                capacity,
                out_imp,
                section,
                tail,
            )
            if err != ERR_CAPACITY:
                break
            capacity *= 4
        if err != OK or z > out_imp.shape[0]:
            return ROW_ERROR, i
        starts[i] = full
        regime[i], kk[i], zz[i], x1max[i], frac[i] = rg, k, z, x1, fr
        periods[i] = n + max(k, 1) + 1
        residual[i] = res
        sections[i] = section[:4]
        sec_mode[i] = int(section[4])
        for j in range(min(z, phases.shape[1])):
            phases[i, j] = out_imp[j, 2]
            vels[i, j] = out_imp[j, 3] / (s[S_XST] * s[S_OMEGA])
        have_prev = True
        prev_section = section[:4].copy()
        prev_mode = int(section[4])
        prev_periodic = rg != _RG_NONPERIODIC
        if rg == _RG_NONPERIODIC and rescue:
            return ROW_RESCUE, i
    return ROW_DONE, P
