"""The settled motion, compiled: the period loop and the describing run, one point or a row.

The reference's :func:`impactdamper.core.steady.steady_state` on arrays: the event loop
(:mod:`~impactdamper.core.compiled.loop`) is sampled at the sections t = n T, the period test
(:mod:`~impactdamper.core.compiled.periodicity`) with its divisor rule finds the least period k,
the clock is re-based every ``REBASE_PERIODS``, and the cycle is described on a fresh run
(:mod:`~impactdamper.core.compiled.settled_cycle`: regime, impacts, contact fraction, x1_max,
the section carried to a sweep's next point). :func:`row_kernel` settles a sweep's or a map
row's points one after the other, each from its neighbour's section (or from its own start).

Both end in bounded time: the event loop spends the reference's step budget
(:mod:`~impactdamper.core.compiled.loop`), the period loop stops at ``max_periods``, and the run
that describes the cycle grows its buffers only as far as that budget allows
(:func:`~impactdamper.core.compiled.loop.recorded_run`, the one capacity-retry loop).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactdamper.core.compiled.settled_cycle import RG_NONPERIODIC, describe_cycle
from impactdamper.core.compiled.layout import (
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
from impactdamper.core.compiled.periodicity import settled_period
from impactdamper.core.simulate import DEFAULT_KICK
from impactdamper.core.steady import (
    NONPERIODIC_WINDOW,
    PERIODS_BEFORE_CYCLE,
    REBASE_PERIODS,
)

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
def _period_loop(
    cm, fm, fc, fk, fg, s, t0, state, default_start, settle_tol, max_periods, kmax, diag, states, start_state
):
    """The reference's _steady_state up to its describe_run: the run from ``state`` at ``t0``
    (or Algorithm No. 2's step 1) sampled at the sections t0 + n T into ``states``, the clock
    re-based every ``REBASE_PERIODS``, until the period test finds the motion settled or
    ``max_periods`` sections are taken; ``start_state`` gets the state at t0. Returns (error,
    n, k, residual): the sections taken, the settled cycle's least period (0: none) and the
    sections' mismatch; on an error (``diag`` set) the sections before it and a residual 0."""
    T = s[S_T]
    scale = np.array([s[S_XST], s[S_XST], s[S_XST] * s[S_OMEGA], s[S_XST] * s[S_OMEGA]])
    sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a = solver_buffers(0)
    init_solver(cm, fc, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t0, state)
    if si[SI_ERR]:
        diagnose(sf, si, diag)
        return si[SI_ERR], 0, 0, 0.0
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
            return si[SI_ERR], n, 0, 0.0
        solver_state(cm, s, sf, si, alpha, t0 + (n - base) * T, states[n - 1])
        for c in range(4):
            sections[n - 1, c] = states[n - 1, c] / scale[c]
        modes[n - 1] = si[SI_MODE]
        found_k, residual = settled_period(sections, modes, n, kmax, settle_tol)
        if found_k:
            break
    return OK, n, found_k, residual


@njit(cache=True)
def steady_kernel(cm, fm, fc, fk, fg, s, t0, state, default_start, settle_tol, max_periods, kmax, diag):
    """The reference's _steady_state: its period loop (:func:`_period_loop`), then the cycle
    described on a fresh run (describe_run and describe_cycle). Returns (error, regime, k,
    cycle start, contact fraction, x1_max, periods, residual, section states (periods, 4),
    impacts (z, 5): t, t/T since the cycle's start, phase, velocity, pulse; section (5,): the
    state at the first section in the cycle and its mode; then the describing run's events and
    segments (kinds, values, modes, values): the motion the reference's describe_run would
    simulate). ``diag`` gets a failed run's diagnostics (layout.DIAG_*)."""
    T = s[S_T]
    states = np.empty((max_periods, 4))
    section = np.zeros(5)
    start_state = np.empty(4)
    err, n, found_k, residual = _period_loop(
        cm, fm, fc, fk, fg, s, t0, state, default_start, settle_tol, max_periods, kmax, diag, states, start_state
    )
    if err:
        return _failed(err, n, residual, states, section)
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
    regime, z, start, frac, x1_max = describe_cycle(
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
def _start_state(s, i, chained, prev, given, full):
    """Point i's start (into ``full``): its predecessor's section where ``chained`` (the
    reference's carry_state: kept on the stop where it was in persistent contact, projected
    onto it where its gap would be negative), else its row of ``given``, else Algorithm
    No. 2's step 1."""
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
        _start_state(s, i, chained, prev, given, full)
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
        prev[6] = 1.0 if rg != RG_NONPERIODIC else 0.0
        if rg == RG_NONPERIODIC and rescue:
            R = tail.shape[0]
            for j in range(R):
                m = n - R + j
                if m < 0:
                    tail[j, :] = np.nan
                else:
                    tail[j, :] = states[m]
            return ROW_RESCUE, i
    return ROW_DONE, P
