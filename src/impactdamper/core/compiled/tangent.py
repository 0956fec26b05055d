"""The tangent walk, compiled: Lyapunov growths along the kernels' own event loop.

The reference's :func:`impactdamper.core.tangent.tangent_walk` on arrays. The motion is the
event loop of :mod:`~impactdamper.core.compiled.loop` (its ``init_solver`` and ``advance``,
period by period, the clock re-based every ``REBASE_PERIODS`` as the settled-motion search
does, at a safe restart point as the reference's walk), with its work bound; this module adds no event search of its own. After each period
the walk reads that period's events from the loop's buffers (time, kind, state before) and
carries an orthonormal frame of perturbations across them with the pieces of
:mod:`impactdamper.core.tangent`, mirrored here on arrays: the modal transition matrix
Re(V e^{Lambda tau} V^-1) over each flight (the tangent of eq. (18)), the impact's saltation
matrix (eqs. (21)-(22), det = R^2), the capture's closed form (2 x 4), the lift-off's (4 x 2),
a Gram-Schmidt QR (twice, which is enough in floating point) after every event and period.

The buffers hold one period's events: before each period the last event is moved to the first
row (the loop's same-time guard reads it) and the rest dropped, so a run of any length needs
only a period's room; a period that outgrows it is run again, from the state saved before it,
with buffers four times larger (as :func:`~impactdamper.core.compiled.loop.recorded_run`
grows its own).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactdamper.core.compiled.impact import impact_jump
from impactdamper.core.compiled.layout import (
    ERR_CAPACITY,
    ERR_WALK,
    FORCE,
    IMPACT,
    LIFTOFF,
    MODE_FREE,
    MODE_STUCK,
    OK,
    SI_ERR,
    SI_MODE,
    SI_NEV,
    SI_NSEG,
    SI_REC,
    STICK,
    S_DELTA0,
    S_GAP_EPS,
    S_M1,
    S_M2,
    S_OMEGA,
    S_T,
    S_XST,
)
from impactdamper.core.compiled.loop import advance, diagnose, init_solver, solver_buffers, solver_state
from impactdamper.core.constants import STEPS_AT_START, STEPS_PER_PERIOD
from impactdamper.core.steady import REBASE_PERIODS
from impactdamper.core.tangent import GRAZING_VELOCITY, REBASE_CLEARANCE

# Events a period's buffers first hold (a periodic impacting motion has 1-4 a period, a chatter
# cycle ~40; grown four-fold where a period needs more).
FIRST_CAPACITY = 64
# The most they grow to: every event costs a certified step and a run between two re-basings
# has at most this many (the work bound ends it first).
MOST_CAPACITY = 2 * (STEPS_AT_START + STEPS_PER_PERIOD * (REBASE_PERIODS + 1)) + 4
# Counts of the averaged periods' events (tangent_kernel's ``counts``).
C_IMPACTS, C_CAPTURES, C_LIFTOFFS, C_GRAZING = range(4)


@njit(cache=True)
def _mode_matrix(cm, mode, n, d, out):
    """Re(V diag(d) V^-1) of a mode (cm rows 2-5: V, 6-9: V^-1) into out[:n, :n]: with d = the
    roots, the state matrix M; with d = e^{lambda tau}, the transition matrix e^{M tau}."""
    for i in range(n):
        for k in range(n):
            acc = 0j
            for j in range(n):
                acc += cm[mode, 2 + i, j] * d[j] * cm[mode, 6 + j, k]
            out[i, k] = acc.real


@njit(cache=True)
def _field(M, b, n, w, t, y, out):
    """y' = M y + b sin(omega t) of a mode (eqs. 2, 9) into out[:n]."""
    sn = math.sin(w * t)
    for i in range(n):
        acc = 0.0
        for k in range(n):
            acc += M[i, k] * y[k]
        out[i] = acc + b[i] * sn


@njit(cache=True)
def _apply(A, n_in, n_out, d_in, d_out, Q, dim, work):
    """Q[:n_out, :dim] <- D_out^-1 A D_in Q[:n_in, :dim] (the frame's images, not orthonormal)."""
    for i in range(n_out):
        for j in range(dim):
            acc = 0.0
            for k in range(n_in):
                acc += (A[i, k] * d_in[k] / d_out[i]) * Q[k, j]
            work[i, j] = acc
    for i in range(4):
        for j in range(dim):
            Q[i, j] = work[i, j] if i < n_out else 0.0


@njit(cache=True)
def _orthonormalise(Q, n, dim, growth):
    """Gram-Schmidt QR of Q[:n, :dim], twice per column; log |R_jj| added to growth[j].
    Returns the frame's dimension after it, min(n, dim) (the columns past it are dropped and
    their growth set to -inf)."""
    keep = min(n, dim)
    for j in range(keep):
        for _ in range(2):
            for i in range(j):
                c = 0.0
                for r in range(n):
                    c += Q[r, i] * Q[r, j]
                for r in range(n):
                    Q[r, j] -= c * Q[r, i]
        norm = 0.0
        for r in range(n):
            norm += Q[r, j] * Q[r, j]
        norm = math.sqrt(norm)
        if norm > 0.0:
            growth[j] += math.log(norm)
            for r in range(n):
                Q[r, j] /= norm
        else:
            growth[j] = -math.inf
    for j in range(keep, 4):
        growth[j] = -math.inf
    return keep


@njit(cache=True)
def _flow(cm, mode, n, tau, Q, dim, scale, trans, e, work):
    """The frame carried by the mode's exact transition matrix over tau (tau > 0 only)."""
    if tau <= 0.0:
        return
    for j in range(n):
        e[j] = np.exp(cm[mode, 0, j] * tau)
    _mode_matrix(cm, mode, n, e, trans)
    _apply(trans, n, n, scale, scale, Q, dim, work)


@njit(cache=True)
def _impact_saltation(Mf, bf, s, t, before, S, f_minus, f_plus, after):
    """The impact's saltation matrix into S (4 x 4): J_R + (f+ - J_R f-) n^T / (n . f-),
    n = (1, -1, 0, 0); the identity at a touch of zero closing velocity (see
    :func:`impactdamper.core.tangent.impact_saltation`)."""
    w = s[S_OMEGA]
    impact_jump(s, S)
    _field(Mf, bf, 4, w, t, before, f_minus)
    rate = f_minus[0] - f_minus[1]
    if rate == 0.0:
        for i in range(4):
            for k in range(4):
                S[i, k] = 1.0 if i == k else 0.0
        return
    for i in range(4):
        acc = 0.0
        for k in range(4):
            acc += S[i, k] * before[k]
        after[i] = acc
    _field(Mf, bf, 4, w, t, after, f_plus)
    for i in range(4):
        acc = 0.0
        for k in range(4):
            acc += S[i, k] * f_minus[k]
        diff = f_plus[i] - acc
        S[i, 0] += diff / rate
        S[i, 1] -= diff / rate


@njit(cache=True)
def _capture_saltation(s, fc, S):
    """The capture's closed form into S[:2, :4] (:func:`impactdamper.core.tangent.capture_saltation`);
    k1 m2/M^2 read from the contact force's c = (m2 c1/M, m2 k1/M)."""
    m1, m2 = s[S_M1], s[S_M2]
    M = m1 + m2
    k = fc[FORCE, 0, 1] / M
    S[0, 0], S[0, 1], S[0, 2], S[0, 3] = m1 / M, m2 / M, 0.0, 0.0
    S[1, 0], S[1, 1], S[1, 2], S[1, 3] = k, -k, m1 / M, m2 / M


@njit(cache=True)
def _liftoff_saltation(Mf, bf, Ms, bs, s, fc, t, x1, v1, S, f_minus, f_plus, full):
    """The lift-off's saltation matrix into S[:4, :2]: G + (f+ - G f-) c^T / (c . f- + d_s
    omega cos(omega t)), G the embedding of (x1, x1') (:func:`impactdamper.core.tangent.liftoff_saltation`)."""
    w = s[S_OMEGA]
    stuck = np.empty(2)
    stuck[0], stuck[1] = x1, v1
    full[0], full[1], full[2], full[3] = x1, x1 + s[S_DELTA0], v1, v1
    _field(Ms, bs, 2, w, t, stuck, f_minus)
    _field(Mf, bf, 4, w, t, full, f_plus)
    c0, c1 = fc[FORCE, 0, 0], fc[FORCE, 0, 1]
    rate = c0 * f_minus[0] + c1 * f_minus[1] + fc[FORCE, 6, 1] * w * math.cos(w * t)
    for i in range(4):
        g0 = 1.0 if i < 2 else 0.0  # G's row: (1, 0), (1, 0), (0, 1), (0, 1)
        g1 = 1.0 - g0
        diff = f_plus[i] - (g0 * f_minus[0] + g1 * f_minus[1])
        S[i, 0] = g0 + diff * c0 / rate
        S[i, 1] = g1 + diff * c1 / rate


@njit(cache=True)
def _frame_matrices(cm, fm, s):
    """The walk's constant arrays: both modes' state matrices M (2, 4, 4), forcing directions b
    (2, 4) and relative units D (2, 4), indexed by mode."""
    w, xst = s[S_OMEGA], s[S_XST]
    M, b, D = np.zeros((2, 4, 4)), np.zeros((2, 4)), np.zeros((2, 4))
    _mode_matrix(cm, MODE_FREE, 4, cm[MODE_FREE, 0], M[MODE_FREE])
    _mode_matrix(cm, MODE_STUCK, 2, cm[MODE_STUCK, 0], M[MODE_STUCK])
    b[MODE_FREE], b[MODE_STUCK] = fm[MODE_FREE, 4], fm[MODE_STUCK, 4]
    D[MODE_FREE, 0], D[MODE_FREE, 1], D[MODE_FREE, 2], D[MODE_FREE, 3] = xst, xst, xst * w, xst * w
    D[MODE_STUCK, 0], D[MODE_STUCK, 1] = xst, xst * w
    return M, b, D


@njit(cache=True)
def _start_frame(mode, Q, growth, shape):
    """The identity frame in ``mode``; shape = (mode, rows, columns)."""
    n = 4 if mode == MODE_FREE else 2
    for i in range(4):
        for j in range(4):
            Q[i, j] = 1.0 if i == j and i < n else 0.0
        growth[i] = 0.0 if i < n else -math.inf
    shape[0], shape[1], shape[2] = mode, n, n


@njit(cache=True)
def _capture(s, fc, D, Q, growth, shape, S, work):
    """The frame across a capture into persistent contact (closed form, 2 x 4)."""
    _capture_saltation(s, fc, S)
    _apply(S, 4, 2, D[MODE_FREE], D[MODE_STUCK], Q, shape[2], work)
    shape[0], shape[1] = MODE_STUCK, 2
    shape[2] = _orthonormalise(Q, 2, shape[2], growth)


@njit(cache=True)
def _walk_events(cm, fc, s, M, b, D, ev_k, ev_f, first, nev, t, t_to, Q, growth, shape, counts, averaged, scratch):
    """Carry the frame over the events ev_*[first:nev] of one period, from t to t_to, then QR.
    ``shape`` (mode, rows, columns) is updated; ``counts`` gets the events where ``averaged``.
    An impact followed at the same time by a capture is one event, the capture (its matrix
    reads the state before the impact that ends in contact). Returns the time in contact."""
    S, trans, work = scratch[0], scratch[1], scratch[2]
    e = np.empty(4, np.complex128)
    f_minus, f_plus, vec, full = np.empty(4), np.empty(4), np.empty(4), np.empty(4)
    contact = 0.0
    i = first
    while i < nev:
        te, kind = ev_f[i, 0], ev_k[i]
        if shape[0] == MODE_STUCK and averaged:
            contact += te - t
        _flow(cm, shape[0], shape[1], te - t, Q, shape[2], D[shape[0]], trans, e, work)
        t = te
        if kind == IMPACT:
            captured = i + 1 < nev and ev_k[i + 1] == STICK and ev_f[i + 1, 0] == te
            if averaged:
                counts[C_IMPACTS] += 1
                counts[C_GRAZING] += 1 if ev_f[i, 1] < GRAZING_VELOCITY * s[S_XST] * s[S_OMEGA] else 0
                counts[C_CAPTURES] += 1 if captured else 0
            if captured:
                _capture(s, fc, D, Q, growth, shape, S, work)
                i += 1
            else:
                for k in range(4):
                    vec[k] = ev_f[i, 3 + k]
                _impact_saltation(M[MODE_FREE], b[MODE_FREE], s, te, vec, S, f_minus, f_plus, full)
                _apply(S, 4, 4, D[MODE_FREE], D[MODE_FREE], Q, shape[2], work)
                shape[2] = _orthonormalise(Q, 4, shape[2], growth)
        elif kind == STICK and shape[0] == MODE_FREE:  # (a restart on the stop keeps a contact)
            counts[C_CAPTURES] += 1 if averaged else 0
            _capture(s, fc, D, Q, growth, shape, S, work)
        elif kind == LIFTOFF:
            counts[C_LIFTOFFS] += 1 if averaged else 0
            x1, v1 = ev_f[i, 3], ev_f[i, 5]
            _liftoff_saltation(
                M[MODE_FREE], b[MODE_FREE], M[MODE_STUCK], b[MODE_STUCK], s, fc, te, x1, v1, S, f_minus, f_plus, full
            )
            _apply(S, 2, 4, D[MODE_STUCK], D[MODE_FREE], Q, shape[2], work)
            shape[0], shape[1] = MODE_FREE, 4
            shape[2] = _orthonormalise(Q, 4, shape[2], growth)
        i += 1
    if shape[0] == MODE_STUCK and averaged:
        contact += t_to - t
    _flow(cm, shape[0], shape[1], t_to - t, Q, shape[2], D[shape[0]], trans, e, work)
    shape[2] = _orthonormalise(Q, shape[1], shape[2], growth)
    return contact


@njit(cache=True)
def _advance_period(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_to, cap):
    """The loop advanced to t_to; a period that outgrows the buffers is run again, from the
    state saved before it, with buffers four times larger (the rows already kept copied).
    Returns the buffers (new ones where they grew) and their capacity."""
    saved_sf, saved_si, saved_y0, saved_alpha = sf.copy(), si.copy(), y0.copy(), alpha.copy()
    kept = si[SI_NEV]
    while True:
        advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_to)
        if si[SI_ERR] != ERR_CAPACITY or cap >= MOST_CAPACITY:
            return ev_k, ev_f, seg_m, seg_f, seg_a, cap
        cap = min(4 * cap, MOST_CAPACITY)
        _, _, _, _, new_k, new_f, seg_m, seg_f, seg_a = solver_buffers(cap)
        new_k[:kept] = ev_k[:kept]
        new_f[:kept] = ev_f[:kept]
        ev_k, ev_f = new_k, new_f
        sf[:] = saved_sf
        si[:] = saved_si
        y0[:] = saved_y0
        alpha[:] = saved_alpha


@njit(cache=True)
def _keep_last_event(ev_k, ev_f, si):
    """Drop the period's events but the last (the loop's same-time guard reads it) and return
    the row the next period's events start at."""
    last = si[SI_NEV] - 1
    if last >= 0:
        ev_k[0] = ev_k[last]
        ev_f[0, :] = ev_f[last, :]
        si[SI_NEV] = 1
    return si[SI_NEV]


@njit(cache=True)
def _restartable(s, si, full):
    """Whether the section state ``full`` is a safe restart point: in contact, or clear of the
    stop by more than REBASE_CLEARANCE times the grazing resolution (core/tangent.py)."""
    return si[SI_MODE] == MODE_STUCK or s[S_DELTA0] - (full[1] - full[0]) > REBASE_CLEARANCE * s[S_GAP_EPS]


@njit(cache=True)
def tangent_kernel(cm, fm, fc, fk, fg, s, t0, state, transient, warmup, periods, increments, sections, counts, diag):
    """The reference's tangent_walk: from (t0, state) the loop runs ``transient`` periods, then
    the frame is walked, ``warmup`` periods discarded and ``periods`` written into
    ``increments`` and ``sections`` (shape (periods, 4)); ``counts`` (4,) gets the averaged
    periods' impacts, captures, lift-offs and grazing impacts.

    Returns (error, the frame's final dimension, time in contact in the averaged periods);
    ``diag`` gets a failed run's diagnostics (layout.DIAG_*). ERR_WALK: the walk's mode and the
    loop's disagreed at a period's end (never expected)."""
    T = s[S_T]
    cap = FIRST_CAPACITY
    sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a = solver_buffers(cap)
    si[SI_REC] = 1
    init_solver(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, state)
    if si[SI_ERR]:
        diagnose(sf, si, diag)
        return si[SI_ERR], 0, 0.0
    M, b, D = _frame_matrices(cm, fm, s)
    Q, growth, shape = np.zeros((4, 4)), np.zeros(4), np.zeros(3, np.int64)
    scratch, full = np.zeros((3, 4, 4)), np.empty(4)
    contact = 0.0
    done = 0  # periods since the loop's (re)start
    for p in range(transient + warmup + periods):
        if p == transient:  # the frame starts in the mode the motion is in
            _start_frame(si[SI_MODE], Q, growth, shape)
        averaged, row = p >= transient + warmup, p - transient - warmup
        if averaged:
            solver_state(cm, s, sf, si, alpha, t0 + done * T, sections[row])
        if done >= REBASE_PERIODS:
            solver_state(cm, s, sf, si, alpha, t0 + done * T, full)
        if done >= REBASE_PERIODS and _restartable(s, si, full):
            # (a restart's own events, such as a capture at t0, are this period's)
            init_solver(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, full.copy())
            done, first = 0, 0
        else:
            first = _keep_last_event(ev_k, ev_f, si)
        si[SI_NSEG] = 0  # (the segments are not read)
        if si[SI_ERR] == 0:
            ev_k, ev_f, seg_m, seg_f, seg_a, cap = _advance_period(
                cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0 + (done + 1) * T, cap
            )
        if si[SI_ERR]:
            diagnose(sf, si, diag)
            return si[SI_ERR], shape[2], contact
        done += 1
        if p < transient:
            continue
        t_from, t_to = t0 + (done - 1) * T, t0 + done * T
        contact += _walk_events(
            cm, fc, s, M, b, D, ev_k, ev_f, first, si[SI_NEV], t_from, t_to, Q, growth, shape, counts, averaged, scratch
        )
        for j in range(4):
            if averaged:
                increments[row, j] = growth[j]
            growth[j] = 0.0 if math.isfinite(growth[j]) else -math.inf
        if shape[0] != si[SI_MODE]:
            return ERR_WALK, shape[2], contact
    return OK, shape[2], contact
