"""The exact event-driven solver, compiled: Algorithm No. 2 and the settled motion in numba.

The same algorithm as the readable reference, step for step, with the same constants:

* the exact flow between events, eq. (18) with alpha_j of eq. (19) in modal form, and the
  periodic forced response of eqs. (10)-(11) (:mod:`impactdamper.core.linear`);
* the certified root march of the gap, eq. (20), and of the contact force, with the same
  Taylor lower bound, departure orders, Newton polish and step budget
  (:mod:`impactdamper.core.events`);
* the impact law of eqs. (21)-(22), the capture into persistent contact, lift-off, the
  brief-dip rule and grazing (:mod:`impactdamper.core.simulate`);
* the stroboscopic sections, the period test with its divisor rule, the re-basing of the
  clock and the description of the cycle (:mod:`impactdamper.core.steady`).

The matrices (modal eigenvectors, forced amplitudes, derivative-bound factors) are computed once
per parameter set by the reference classes (:class:`~impactdamper.core.model.Model`) and packed
into arrays; the kernels only evaluate. Whatever the kernels do not reproduce falls back to the
pure-Python solver, and the result says so (``fallback``):

* a mode whose eigenvector matrix is ill conditioned (repeated roots of eq. (4)), where the
  reference uses the matrix exponential;
* parameters outside the native scales (the reference rescales them);
* any error of the reference (step budget, degenerate contact, a resonance in contact): the
  reference is re-run so that its exception, with its message, is raised.

The maximum excursion x1_max is refined by golden-section search where the reference uses
scipy's bounded Brent search; both stop at 1e-12 T, and the maximum's value differs by the
square of that (far below 1e-12 x_st).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numba import njit

from impactdamper.core.events import MAX_STEPS, MIN_BOUND, NEWTON_ITERATIONS, NEWTON_MAX_STEP
from impactdamper.core.linear import MODAL_CONDITION_LIMIT
from impactdamper.core.model import FORCED_AMPLITUDE_LIMIT, Model
from impactdamper.core.parameters import (NATIVE_SCALES, Parameters, finite_argument, integer_argument, real_argument,
                                          require_parameters)
from impactdamper.core.simulate import (DEFAULT_KICK, DIP_SAMPLES, MAX_EVENTS_AT_ONE_TIME, MAX_SIMULATE_PERIODS,
                                        STEPS_AT_START, STEPS_PER_PERIOD, Event, EventDrivenSolver, Tolerances,
                                        Trajectory, check_start_time, check_state, check_tolerances, simulate)
from impactdamper.core.steady import (DIVISOR_DECAY, DIVISOR_FLOOR_FACTOR, DIVISOR_SUSPECT,
                                      EXCURSION_SAMPLES_PER_PERIOD, MAX_PERIODS_LIMIT, NONPERIODIC_WINDOW,
                                      PERIODS_BEFORE_CYCLE, REBASE_PERIODS, REGIMES, STALL_WINDOW,
                                      start_in_first_period, steady_state)

__all__ = ["CompiledRun", "CompiledSteady", "Pack", "pack_many", "pack_parameters", "run_compiled",
           "simulate_compiled", "steady_state_compiled", "count_events_compiled", "warm_up", "EVENT_KINDS",
           "FALLBACK_REASONS"]

EVENT_KINDS = ("impact", "stick", "liftoff")
_IMPACT, _STICK, _LIFTOFF = 0, 1, 2
_FREE, _STUCK = 0, 1
# The functionals of the pack: the gap on the free mode, the contact force on the stuck mode,
# and minus the contact force (the brief-dip search of the reference's _dip_unresolved).
_GAP, _FORCE, _NEG_FORCE = 0, 1, 2
# Kernel outcomes. 0 is success; the errors mirror the reference's exceptions (which the
# wrapper then raises by re-running the reference), CAPACITY asks for larger event buffers.
OK, ERR_BUDGET, ERR_SEARCH, ERR_DEGENERATE, ERR_STUCK_RESONANT, ERR_CAPACITY = 0, 1, 2, 3, 4, 5
# Why a point was not solved by the kernels (see the module docstring).
FALLBACK_REASONS = ("", "matrix_exponential", "scales", "error", "rescue")
# Golden-section iterations of the x1_max refinement: 0.618^80 ~ 2e-17 of a bracket of 2/256 T,
# below the reference's xatol of 1e-12 T.
GOLDEN_ITERATIONS = 80
_GOLD = 0.5 * (3.0 - math.sqrt(5.0))
# Events and segments held before the buffers grow (the run is repeated with 4 times as many):
# a settled cycle's description holds ~10 periods of a few events each; larger buffers cost more
# to allocate than the rare repeat.
INITIAL_CAPACITY = 256
# Events per forcing period a run's buffers are first sized for (a periodic impacting motion has
# 1-3; a chatter cycle ~30, found by growing them).
EVENTS_PER_PERIOD_GUESS = 4
# The default tolerances, made once (constructing and validating them costs more than packing's
# compiled part).
_DEFAULT_TOLERANCES = Tolerances()
# Scalars of the pack, by index.
(_OMEGA, _T, _DELTA0, _R, _M1, _M2, _MRED, _OMEGA1, _LSCALE, _FSCALE, _GAP_EPS, _CHATTER, _FORCE_EPS,
 _STUCK_RES, _XST, _N_SCALARS) = range(16)


@dataclass(frozen=True)
class Pack:
    """One parameter set's arrays for the kernels (see :func:`pack_parameters`).

    Attributes
    ----------
    s : ndarray, shape (16,)
        Scalars (omega, T, Delta0, R, m1, m2, reduced mass, omega1, length and force scales,
        gap and force tolerances in units, chatter tolerance, stuck resonance flag, x_st).
    cm : ndarray, shape (2, 10, 4), complex
        Per mode (free, stuck): roots, forced amplitudes Yhat, V (rows 2-5), V^-1 (rows 6-9).
    fm : ndarray, shape (2, 5, 4)
        Per mode: energy weight W (rows 0-3), forcing direction b (row 4).
    fc : ndarray, shape (3, 8, 6)
        Per functional (gap, force, -force): c M^k (rows 0-5), (g0, d_s) (row 6), c M^k b (row 7).
    fk : ndarray, shape (3, 6)
        Derivative-bound factors kappa_k.
    fg : ndarray, shape (3, 5), complex
        G, then c . V_j.
    fallback : int
        Index into :data:`FALLBACK_REASONS` (0: the kernels apply).

    Built by :func:`pack_many` (one leading axis per parameter set) or :func:`pack_parameters`.
    """

    s: np.ndarray
    cm: np.ndarray
    fm: np.ndarray
    fc: np.ndarray
    fk: np.ndarray
    fg: np.ndarray
    fallback: int


# The relative parameters, in the columns of pack_many's input.
PARAMETER_COLUMNS = ("theta", "mu", "N", "delta1", "delta2", "R", "gap", "omega", "x_st", "m1")
# Pack flags (pack_many's second output), as in FALLBACK_REASONS: 0 the kernels apply.
_PACK_OK, _PACK_EXPM, _PACK_SCALES, _PACK_ERROR = 0, 1, 2, 3


def _stacked_mode(M: np.ndarray, b: np.ndarray, omega: np.ndarray, W: np.ndarray):
    """The reference's LinearMode.__post_init__ for a stack of modes (shapes (P, n, n), (P, n),
    (P,), (P, n, n)), with the same LAPACK calls: (roots, V, V^-1, Yhat, L^-T, powers, modal, ok)."""
    P, n = M.shape[0], M.shape[1]
    with np.errstate(all="ignore"):
        lam, V = np.linalg.eig(M)
        condition = np.linalg.cond(V)
        modal = np.isfinite(condition) & (condition < MODAL_CONDITION_LIMIT)
        Vinv = np.zeros_like(V)
        if modal.any():
            Vinv[modal] = np.linalg.inv(V[modal])
        A = 1j * omega[:, None, None] * np.eye(n) - M
        try:
            Yhat = np.linalg.solve(A, b.astype(complex)[..., None])[..., 0]
        except np.linalg.LinAlgError:  # a singular one in the stack: solve them one by one
            Yhat = np.full((P, n), np.inf + 0j)
            for i in range(P):
                try:
                    Yhat[i] = np.linalg.solve(A[i], b[i].astype(complex))
                except np.linalg.LinAlgError:
                    pass
        ok = np.ones(P, bool)
        try:
            L = np.linalg.cholesky(W)
        except np.linalg.LinAlgError:
            L = np.empty_like(W)
            for i in range(P):
                try:
                    L[i] = np.linalg.cholesky(W[i])
                except np.linalg.LinAlgError:
                    L[i], ok[i] = np.eye(n), False
        LiT = np.swapaxes(np.linalg.inv(L), -1, -2)
        powers = [np.broadcast_to(np.eye(n), M.shape)]
        for _ in range(5):
            powers.append(powers[-1] @ M)
        powers = np.stack(powers, axis=1)  # (P, 6, n, n)
        ok &= np.isfinite(powers).all(axis=(1, 2, 3)) & np.isfinite(LiT).all(axis=(1, 2))
    return lam, V, Vinv, Yhat, LiT, powers, modal, ok


def pack_many(values: np.ndarray, tolerances: Tolerances | None = None) -> tuple[Pack, np.ndarray]:
    """The kernels' arrays for many parameter sets at once (numpy over the stack).

    Parameters
    ----------
    values : ndarray, shape (P, 10)
        Relative parameters in the order of :data:`PARAMETER_COLUMNS`, each row valid for
        :class:`Parameters` (the caller validates).
    tolerances : Tolerances, optional

    Returns
    -------
    pack : Pack
        Arrays with a leading axis P (s (P, 16), cm (P, 2, 10, 4), ...).
    flags : ndarray of int, shape (P,)
        Per row, an index into :data:`FALLBACK_REASONS`: 0 where the kernels apply; 1 where a
        mode is not modal (repeated roots); 2 outside the native scales; 3 where the reference
        Model raises (extreme parameters, resonance), so that the reference reports it.
    """
    tol = check_tolerances(tolerances)
    v = np.asarray(values, dtype=float).reshape(-1, len(PARAMETER_COLUMNS))
    P = v.shape[0]
    Mf, bf, Wf, Ms, bs, Ws, D = _state_matrices_many(v)
    omega1, m2, c1, c2, k1, P0, Delta0, T, mred = D.T
    omega, x_st, R = v[:, 7], v[:, 8], v[:, 5]
    m = v[:, 9] + m2
    z = np.zeros(P)
    flags = np.zeros(P, np.int64)
    cm = np.zeros((P, 2, 10, 4), complex)
    fm = np.zeros((P, 2, 5, 4))
    modes = []
    for i, (M, b, W) in enumerate(((Mf, bf, Wf), (Ms, bs, Ws))):
        good = np.isfinite(M).all(axis=(1, 2)) & np.isfinite(W).all(axis=(1, 2)) & np.isfinite(b).all(axis=1)
        Mg, bg, Wg = (np.where(good[:, None, None], M, np.eye(M.shape[1])), np.where(good[:, None], b, 0.0),
                      np.where(good[:, None, None], W, np.eye(M.shape[1])))
        lam, V, Vinv, Yhat, LiT, powers, modal, ok = _stacked_mode(Mg, bg, omega, Wg)
        n = M.shape[1]
        ok &= good
        flags[~ok] = _PACK_ERROR
        flags[(flags == 0) & ~modal] = _PACK_EXPM
        cm[:, i, 0, :n], cm[:, i, 1, :n] = lam, Yhat
        cm[:, i, 2:2 + n, :n], cm[:, i, 6:6 + n, :n] = V, Vinv
        fm[:, i, :n, :n], fm[:, i, 4, :n] = W, b
        modes.append((V, Yhat, LiT, powers, b, np.abs(Yhat[:, : n // 2]).max(axis=1)))
    # The reference Model's checks: a free-mode forced response beyond FORCED_AMPLITUDE_LIMIT x_st
    # is refused (a resonance), a stuck-mode one only when the bodies stay in contact.
    with np.errstate(invalid="ignore"):
        flags[(flags == 0) & ~(modes[0][5] <= FORCED_AMPLITUDE_LIMIT * x_st)] = _PACK_ERROR
        stuck_res = ~(modes[1][5] <= FORCED_AMPLITUDE_LIMIT * x_st)
    native = np.ones(P, bool)
    for name, (lo, hi) in NATIVE_SCALES.items():
        col = v[:, PARAMETER_COLUMNS.index(name)]
        native &= (lo <= col) & (col <= hi)
    flags[~native] = _PACK_SCALES
    # The functionals: the gap (eq. 20), the contact force and minus it.
    cg = np.broadcast_to(np.array([1.0, -1.0, 0.0, 0.0]), (P, 4))
    cf = np.stack([m2 * c1 / m, m2 * k1 / m], -1)
    fc = np.zeros((P, 3, 8, 6))
    fk = np.zeros((P, 3, 6))
    fg = np.zeros((P, 3, 5), complex)
    specs = ((0, cg, Delta0, z), (1, cf, -c2 * Delta0, -m2 * P0 / m), (1, -cf, -(-c2 * Delta0), -(-m2 * P0 / m)))
    with np.errstate(all="ignore"):
        for f, (mi, c, g0, d_s) in enumerate(specs):
            V, Yhat, LiT, powers, b, _ = modes[mi]
            n = c.shape[1]
            cM = np.einsum("pi,pkij->pkj", c, powers)  # c M^k, (P, 6, n)
            fc[:, f, :6, :n] = cM
            fc[:, f, 7, :6] = np.einsum("pkj,pj->pk", cM, b)
            fc[:, f, 6, 0], fc[:, f, 6, 1] = g0, d_s
            fk[:, f] = np.linalg.norm(np.einsum("pkj,pjl->pkl", cM, LiT), axis=2)
            fg[:, f, 0] = np.einsum("pi,pi->p", c, Yhat) + d_s
            fg[:, f, 1:1 + n] = np.einsum("pi,pij->pj", c, V)
    s = np.zeros((P, _N_SCALARS))
    s[:, _OMEGA], s[:, _T], s[:, _DELTA0], s[:, _R] = omega, T, Delta0, R
    s[:, _M1], s[:, _M2], s[:, _MRED], s[:, _OMEGA1] = v[:, 9], m2, mred, omega1
    s[:, _LSCALE] = x_st
    s[:, _FSCALE] = mred * x_st * np.maximum(np.maximum(omega, omega1), v[:, 2] * omega1) ** 2
    s[:, _GAP_EPS] = tol.gap_tol * x_st
    s[:, _CHATTER] = tol.chatter_tol
    s[:, _FORCE_EPS] = tol.force_tol * s[:, _FSCALE]
    s[:, _STUCK_RES] = stuck_res
    s[:, _XST] = x_st
    return Pack(s, cm, fm, fc, fk, fg, 0), flags


@njit(cache=True)
def _pack_mode(i, n, M, b, W, lam, V, omega, cm, fm, powers, LiT):
    """One mode of the reference's LinearMode.__post_init__ (eigen-decomposition given).
    Returns (modal, forced amplitude, finite)."""
    condition = np.linalg.cond(V)
    modal = math.isfinite(condition) and condition < MODAL_CONDITION_LIMIT
    A = np.zeros((n, n), np.complex128)
    for r in range(n):
        for c in range(n):
            A[r, c] = -M[r, c]
        A[r, r] += 1j * omega
    Yhat = np.linalg.solve(A, b.astype(np.complex128))
    L = np.linalg.cholesky(W)
    Li = np.linalg.inv(L)
    for r in range(n):
        for c in range(n):
            LiT[r, c] = Li[c, r]
    cm[i, 0, :n] = lam
    cm[i, 1, :n] = Yhat
    cm[i, 2:2 + n, :n] = V
    if modal:
        cm[i, 6:6 + n, :n] = np.linalg.inv(V)
    fm[i, :n, :n] = W
    fm[i, 4, :n] = b
    finite = True
    P = np.eye(n)
    for k in range(6):
        powers[k, :n, :n] = P
        for r in range(n):
            for c in range(n):
                if not math.isfinite(P[r, c]):
                    finite = False
        P = P @ M
    for r in range(n):
        for c in range(n):
            if not math.isfinite(LiT[r, c]):
                finite = False
    amp = 0.0
    for r in range(n // 2):
        amp = max(amp, abs(Yhat[r]))
    return modal, amp, finite


@njit(cache=True)
def _pack_functional(f, n, c, g0, d_s, powers, LiT, b, Yhat, V, fc, fk, fg):
    """One functional of the reference's LinearFunctional.__post_init__."""
    for k in range(6):
        acc_b = 0.0
        for j in range(n):
            acc = 0.0
            for r in range(n):
                acc += c[r] * powers[k, r, j]
            fc[f, k, j] = acc
            acc_b += acc * b[j]
        fc[f, 7, k] = acc_b
        sq = 0.0
        for l in range(n):
            acc = 0.0
            for j in range(n):
                acc += fc[f, k, j] * LiT[j, l]
            sq += acc * acc
        fk[f, k] = math.sqrt(sq)
    fc[f, 6, 0], fc[f, 6, 1] = g0, d_s
    G = 0j
    for r in range(n):
        G += c[r] * Yhat[r]
    fg[f, 0] = G + d_s
    for j in range(n):
        acc = 0j
        for r in range(n):
            acc += c[r] * V[r, j]
        fg[f, 1 + j] = acc


@njit(cache=True)
def _eig2(M):
    """Eigenvalues and unit eigenvectors of the stuck mode's M = [[0, 1], [a, b]] in closed form
    (what LAPACK returns up to rounding: a complex pair as exact conjugates, the one with the
    positive imaginary part first; real roots without cancellation)."""
    a, b = M[1, 0], M[1, 1]
    h = 0.5 * b
    disc = h * h + a
    lam = np.empty(2, np.complex128)
    if disc < 0.0:
        w = math.sqrt(-disc)
        lam[0], lam[1] = complex(h, w), complex(h, -w)
    else:
        r = h + math.copysign(math.sqrt(disc), h)  # the root of larger modulus
        lam[0] = r
        lam[1] = -a / r if r != 0.0 else 0.0
    V = np.empty((2, 2), np.complex128)
    for j in range(2):
        norm = math.sqrt(1.0 + abs(lam[j]) ** 2)
        V[0, j], V[1, j] = 1.0 / norm, lam[j] / norm
    return lam, V


@njit(cache=True)
def _pack_one(v, tols, lam_f, V_f):
    """The kernels' arrays (s, cm, fm, fc, fk, fg, flag) for one parameter set (relative
    values v in PARAMETER_COLUMNS order, tolerances (gap, chatter, force)) given the free
    mode's eigen-decomposition (see _state_matrices); flag indexes FALLBACK_REASONS."""
    s, cm, fm = np.zeros(_N_SCALARS), np.zeros((2, 10, 4), np.complex128), np.zeros((2, 5, 4))
    fc, fk, fg = np.zeros((3, 8, 6)), np.zeros((3, 6)), np.zeros((3, 5), np.complex128)
    theta, mu, N, delta1, delta2, R, gap, omega, x_st, m1 = v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9]
    Mf, bf, Wf, Ms, bs, Ws, d = _state_matrices(v)
    lam_s, V_s = _eig2(Ms)
    omega1, m2, c1, c2, k1, P0, Delta0, T, mred = d[0], d[1], d[2], d[3], d[4], d[5], d[6], d[7], d[8]
    omega2 = N * omega1
    m = m1 + m2
    powers_f, LiT_f = np.zeros((6, 4, 4)), np.zeros((4, 4))
    powers_s, LiT_s = np.zeros((6, 2, 2)), np.zeros((2, 2))
    modal_f, amp_f, fin_f = _pack_mode(0, 4, Mf, bf, Wf, lam_f, V_f, omega, cm, fm, powers_f, LiT_f)
    modal_s, amp_s, fin_s = _pack_mode(1, 2, Ms, bs, Ws, lam_s, V_s, omega, cm, fm, powers_s, LiT_s)
    cg = np.array([1.0, -1.0, 0.0, 0.0])
    cf = np.array([m2 * c1 / m, m2 * k1 / m])
    _pack_functional(_GAP, 4, cg, Delta0, 0.0, powers_f, LiT_f, bf, cm[0, 1], V_f, fc, fk, fg)
    _pack_functional(_FORCE, 2, cf, -c2 * Delta0, -m2 * P0 / m, powers_s, LiT_s, bs, cm[1, 1], V_s, fc, fk, fg)
    _pack_functional(_NEG_FORCE, 2, -cf, -(-c2 * Delta0), -(-m2 * P0 / m), powers_s, LiT_s, bs, cm[1, 1], V_s,
                     fc, fk, fg)
    s[_OMEGA], s[_T], s[_DELTA0], s[_R] = omega, T, Delta0, R
    s[_M1], s[_M2], s[_MRED], s[_OMEGA1] = m1, m2, mred, omega1
    s[_LSCALE] = x_st
    s[_FSCALE] = mred * x_st * max(omega, omega1, omega2) ** 2
    s[_GAP_EPS] = tols[0] * x_st
    s[_CHATTER] = tols[1]
    s[_FORCE_EPS] = tols[2] * s[_FSCALE]
    s[_STUCK_RES] = 0.0 if amp_s <= FORCED_AMPLITUDE_LIMIT * x_st else 1.0
    s[_XST] = x_st
    flag = _PACK_OK
    if not (fin_f and fin_s) or not amp_f <= FORCED_AMPLITUDE_LIMIT * x_st:
        flag = _PACK_ERROR
    elif not (modal_f and modal_s):
        flag = _PACK_EXPM
    return s, cm, fm, fc, fk, fg, flag


@njit(cache=True)
def _state_matrices(v):
    """The two modes' (M, b, W) (the reference's free_mode and stuck_mode) and the derived
    values (omega1, m2, c1, c2, k1, P0, Delta0, T, reduced mass), with the operations of
    Parameters.__post_init__ (same rounding)."""
    theta, mu, N, delta1, delta2, R, gap, omega, x_st, m1 = v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9]
    omega1 = omega / theta
    omega2 = N * omega1
    m2 = mu * m1
    c1 = m1 * (omega1 * omega1)
    c2 = m2 * (omega2 * omega2)
    k1 = 2.0 * m1 * omega1 * delta1
    k2 = 2.0 * m2 * omega1 * delta2
    P0 = m1 * (omega1 * omega1) * x_st
    Delta0 = gap * x_st
    T = 2.0 * math.pi / omega
    mred = m1 * m2 / (m1 + m2)
    if mred == 0.0 or not math.isfinite(mred):
        mred = m1 * (mu / (1.0 + mu))
    Mf = np.zeros((4, 4))
    Mf[0, 2] = Mf[1, 3] = 1.0
    Mf[2, 0], Mf[2, 1] = -(1.0 / m1) * (c1 + c2), -(1.0 / m1) * -c2
    Mf[3, 0], Mf[3, 1] = -(1.0 / m2) * -c2, -(1.0 / m2) * c2
    Mf[2, 2], Mf[2, 3] = -(1.0 / m1) * (k1 + k2), -(1.0 / m1) * -k2
    Mf[3, 2], Mf[3, 3] = -(1.0 / m2) * -k2, -(1.0 / m2) * k2
    bf = np.array([0.0, 0.0, P0 / m1, 0.0])
    Wf = np.zeros((4, 4))
    Wf[0, 0], Wf[0, 1], Wf[1, 0], Wf[1, 1] = c1 + c2, -c2, -c2, c2
    Wf[2, 2], Wf[3, 3] = m1, m2
    m = m1 + m2
    Ms = np.zeros((2, 2))
    Ms[0, 1] = 1.0
    Ms[1, 0], Ms[1, 1] = -c1 / m, -k1 / m
    bs = np.array([0.0, P0 / m])
    Ws = np.zeros((2, 2))
    Ws[0, 0], Ws[1, 1] = c1, m
    d = np.array([omega1, m2, c1, c2, k1, P0, Delta0, T, mred])
    return Mf, bf, Wf, Ms, bs, Ws, d


@njit(cache=True)
def _state_matrices_many(values):
    """_state_matrices for each row of values (P, 10): stacked (M, b, W) of both modes and the
    derived values (P, 9)."""
    P = values.shape[0]
    Mf, bf, Wf = np.zeros((P, 4, 4)), np.zeros((P, 4)), np.zeros((P, 4, 4))
    Ms, bs, Ws = np.zeros((P, 2, 2)), np.zeros((P, 2)), np.zeros((P, 2, 2))
    D = np.zeros((P, 9))
    for i in range(P):
        Mf[i], bf[i], Wf[i], Ms[i], bs[i], Ws[i], D[i] = _state_matrices(values[i])
    return Mf, bf, Wf, Ms, bs, Ws, D


def pack_parameters(p: Parameters, tolerances: Tolerances | None = None) -> Pack:
    """The kernels' arrays for one parameter set (the free mode's eigen-decomposition by numpy,
    as the reference; the rest compiled); its ``fallback`` is the set's flag (FALLBACK_REASONS)."""
    p = require_parameters(p)
    tol = _DEFAULT_TOLERANCES if tolerances is None else check_tolerances(tolerances)
    if not p.native_scales():
        return Pack(np.zeros(_N_SCALARS), np.zeros((2, 10, 4), complex), np.zeros((2, 5, 4)), np.zeros((3, 8, 6)),
                    np.zeros((3, 6)), np.zeros((3, 5), complex), _PACK_SCALES)
    v = np.array([p.theta, p.mu, p.N, p.delta1, p.delta2, p.R, p.gap, p.omega, p.x_st, p.m1])
    try:
        lam_f, V_f = np.linalg.eig(_free_matrix(v))
        *arrays, flag = _pack_one(v, np.array([tol.gap_tol, tol.chatter_tol, tol.force_tol]),
                                  lam_f.astype(complex), V_f.astype(complex))
    except (np.linalg.LinAlgError, ValueError, ZeroDivisionError):
        # (a singular or indefinite matrix: extreme parameters or an undamped resonance, which
        # the reference Model reports by name)
        return Pack(np.zeros(_N_SCALARS), np.zeros((2, 10, 4), complex), np.zeros((2, 5, 4)), np.zeros((3, 8, 6)),
                    np.zeros((3, 6)), np.zeros((3, 5), complex), _PACK_ERROR)
    return Pack(*arrays, int(flag))


@njit(cache=True)
def _free_matrix(v):
    return _state_matrices(v)[0]


# ------------------------------------------------------------------------------------------
# Kernels: the flow (eqs. 10-11, 18-19)
# ------------------------------------------------------------------------------------------
@njit(cache=True)
def _n_of(mode):
    return 4 if mode == _FREE else 2


@njit(cache=True)
def _alpha(cm, s, mode, t0, y0, alpha):
    """alpha = V^-1 (y0 - Y(t0)), eq. (19)."""
    n = _n_of(mode)
    rot = np.exp(1j * s[_OMEGA] * t0)
    z0 = np.empty(4)
    for i in range(n):
        z0[i] = y0[i] - (rot * cm[mode, 1, i]).imag
    for i in range(n):
        acc = 0j
        for j in range(n):
            acc += cm[mode, 6 + i, j] * z0[j]
        alpha[i] = acc


@njit(cache=True)
def _free_part(cm, mode, alpha, tau, out):
    """z(tau) = Re V (alpha e^{lambda tau}), the free response."""
    # Summed over j in the same order as Re(V e) (the real part of a complex sum is the sum of
    # the real parts), without a temporary array: this is the state's hot path.
    n = _n_of(mode)
    for i in range(n):
        out[i] = 0.0
    for j in range(n):
        e = alpha[j] * np.exp(cm[mode, 0, j] * tau)
        for i in range(n):
            out[i] += (cm[mode, 2 + i, j] * e).real


@njit(cache=True)
def _state(cm, s, mode, t0, alpha, t, out):
    """The mode's state at t, eq. (18): forced response plus free response."""
    n = _n_of(mode)
    _free_part(cm, mode, alpha, t - t0, out)
    rot = np.exp(1j * s[_OMEGA] * t)
    for i in range(n):
        out[i] += (cm[mode, 1, i] * rot).imag


@njit(cache=True)
def _full_state(s, mode, y, out):
    """(x1, x2, x1', x2') from a state of either mode."""
    if mode == _FREE:
        for i in range(4):
            out[i] = y[i]
    else:
        out[0], out[1], out[2], out[3] = y[0], y[0] + s[_DELTA0], y[1], y[1]


@njit(cache=True)
def _evaluate(cm, fc, fg, s, f, mode, t0, alpha, t):
    """(g(t), g'(t)) of functional f on the segment: the modal sums over one root of each
    conjugate pair (the reference's Segment.evaluator)."""
    n = _n_of(mode)
    tau = t - t0
    s0 = 0j
    s1 = 0j
    for j in range(n):
        lam = cm[mode, 0, j]
        if lam.imag < 0.0:
            continue
        b = fg[f, 1 + j] * alpha[j]
        if lam.imag > 0.0:
            b = 2.0 * b
        e = b * np.exp(lam * tau)
        s0 += e
        s1 += lam * e
    w = s[_OMEGA]
    rot = np.exp(1j * w * t) * fg[f, 0]
    return fc[f, 6, 0] + rot.imag + s0.real, w * rot.real + s1.real


@njit(cache=True)
def _of_state(fc, s, f, mode, t, y, derivative):
    """g^(derivative)(t) from a state y, using y' = M y + b sin(omega t)."""
    n = _n_of(mode)
    w = s[_OMEGA]
    if derivative == 0:
        acc = 0.0
        for i in range(n):
            acc += y[i] * fc[f, 0, i]
        return fc[f, 6, 0] + fc[f, 6, 1] * math.sin(w * t) + acc
    value = 0.0
    for i in range(n):
        value += y[i] * fc[f, derivative, i]
    for j in range(derivative):
        value = value + fc[f, 7, derivative - 1 - j] * w ** j * math.sin(w * t + j * math.pi / 2)
    return value + fc[f, 6, 1] * w ** derivative * math.sin(w * t + derivative * math.pi / 2)


# ------------------------------------------------------------------------------------------
# Kernels: the certified march (events.march)
# ------------------------------------------------------------------------------------------
@njit(cache=True)
def _lower_bound_root(g, g1, K):
    disc = math.sqrt(g1 * g1 + 2.0 * K * g)
    if disc == math.inf:
        disc = math.hypot(g1, math.sqrt(2.0 * K) * math.sqrt(g))
    if g1 <= 0.0:
        return 2.0 * g / (disc - g1) if disc - g1 > 0.0 else 0.0
    return (g1 + disc) / K


@njit(cache=True)
def _polish(cm, fc, fg, s, f, mode, t0, alpha, t, g, g1):
    max_step = NEWTON_MAX_STEP * 2.0 * math.pi / s[_OMEGA]
    for _ in range(NEWTON_ITERATIONS):
        if g1 >= 0.0 or g == 0.0:
            break
        dt = -g / g1
        if t + dt == t or abs(dt) > max_step:
            break
        t_new = t + dt
        g_new, g1_new = _evaluate(cm, fc, fg, s, f, mode, t0, alpha, t_new)
        if abs(g_new) >= abs(g) or g1_new > 0.0:
            break
        t, g, g1 = t_new, g_new, g1_new
    return t, g1


@njit(cache=True)
def _march(cm, fm, fc, fk, fg, s, f, mode, t0, alpha, t_from, t_to, tol, dep_m, dep_g, budget):
    """The reference's events.march. budget = [limit, used] (floats), updated.

    Returns (status, t_root, dg, reached): status 1 a root, 0 none, else an error code."""
    n = _n_of(mode)
    w = s[_OMEGA]
    z = np.empty(4)
    _free_part(cm, mode, alpha, t_from - t0, z)
    q = 0.0
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += fm[mode, i, j] * z[j]
        q += z[i] * acc
    energy = math.sqrt(max(q, 0.0))
    Gabs = abs(fg[f, 0])
    a = t_from
    if dep_m > 0:
        K = max(Gabs * w ** (dep_m + 1) + fk[f, dep_m + 1] * energy, MIN_BOUND)
        if not math.isfinite(K):
            return ERR_SEARCH, 0.0, 0.0, a
        a += (dep_m + 1) * dep_g / K
        if a >= t_to:
            return 0, 0.0, 0.0, a
    K = max(Gabs * w * w + fk[f, 2] * energy, MIN_BOUND)
    if not math.isfinite(K):
        return ERR_SEARCH, 0.0, 0.0, a
    remaining = max(budget[0] - budget[1], 0.0)
    limit = MAX_STEPS if remaining >= MAX_STEPS else int(remaining)
    steps = 0
    for steps in range(1, limit + 1):
        g, g1 = _evaluate(cm, fc, fg, s, f, mode, t0, alpha, a)
        if g <= tol and g1 <= 0.0:
            budget[1] += steps
            tr, dg = _polish(cm, fc, fg, s, f, mode, t0, alpha, a, g, g1)
            return 1, tr, dg, tr
        step = _lower_bound_root(max(g, 0.0), g1, K)
        if a + step <= a:
            budget[1] += steps
            return 1, a, g1, a
        if step != step:
            budget[1] += steps
            return ERR_SEARCH, 0.0, 0.0, a
        a += step
        if a >= t_to:
            budget[1] += steps
            return 0, 0.0, 0.0, a
    budget[1] += steps
    return ERR_BUDGET if limit < MAX_STEPS else ERR_SEARCH, 0.0, 0.0, a


# ------------------------------------------------------------------------------------------
# Kernels: the event-driven solver (simulate.EventDrivenSolver)
# ------------------------------------------------------------------------------------------
# Solver state: sf = [segment t0, search_from, departure value, run start, budget limit,
# budget used, last event time]; si = [mode, departure order (0: none), same-time events,
# events, segments, record flag, error]; y0 (4,) and alpha (4,) of the segment.
_SF_T0, _SF_FROM, _SF_DEPG, _SF_START, _SF_LIMIT, _SF_USED, _SF_LAST = range(7)
_SI_MODE, _SI_DEPM, _SI_SAME, _SI_NEV, _SI_NSEG, _SI_REC, _SI_ERR = range(7)


@njit(cache=True)
def _no_room(si, k, rows):
    """Whether row k is past a buffer of ``rows`` rows (then the capacity error is set)."""
    if k >= rows:
        si[_SI_ERR] = ERR_CAPACITY
        return True
    return False


@njit(cache=True)
def _record_event(s, sf, si, ev_k, ev_f, t, kind, v, S, before, after, t_acc):
    if si[_SI_NEV] > 0 and t - sf[_SF_LAST] <= 4 * np.spacing(max(abs(t), 1.0)):
        si[_SI_SAME] += 1
        if si[_SI_SAME] > MAX_EVENTS_AT_ONE_TIME:
            si[_SI_ERR] = ERR_DEGENERATE
            return
    else:
        si[_SI_SAME] = 0
    k = si[_SI_NEV]
    if si[_SI_REC]:
        if _no_room(si, k, ev_k.shape[0]):
            return
        ev_k[k] = kind
        ev_f[k, 0], ev_f[k, 1], ev_f[k, 2], ev_f[k, 11] = t, v, S, t_acc
        for i in range(4):
            ev_f[k, 3 + i] = before[i]
            ev_f[k, 7 + i] = after[i]
    si[_SI_NEV] = k + 1
    sf[_SF_LAST] = t


@njit(cache=True)
def _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, mode, t, y, dep_m, dep_g):
    if mode == _STUCK and s[_STUCK_RES] != 0.0:
        si[_SI_ERR] = ERR_STUCK_RESONANT
        return
    si[_SI_MODE] = mode
    n = _n_of(mode)
    for i in range(4):
        y0[i] = y[i] if i < n else 0.0
        alpha[i] = 0j
    _alpha(cm, s, mode, t, y0, alpha)
    sf[_SF_T0] = t
    k = si[_SI_NSEG]
    if si[_SI_REC] and not _no_room(si, k, seg_m.shape[0]):
        seg_m[k] = mode
        seg_f[k, 0] = t
        for i in range(4):
            seg_f[k, 1 + i] = y0[i]
            seg_a[k, i] = alpha[i]
    si[_SI_NSEG] = k + 1
    sf[_SF_FROM] = t
    si[_SI_DEPM] = dep_m
    sf[_SF_DEPG] = dep_g


@njit(cache=True)
def _gap_departure(fc, s, t, full, rebound):
    """(order, value) of the gap's first non-zero derivative leaving the stop; order 0: none."""
    scale = s[_LSCALE]
    w = max(s[_OMEGA], s[_OMEGA1])
    if rebound > 1e-14 * scale * w:
        return 1, rebound
    derivs = np.empty(5)
    for k in range(5):
        derivs[k] = _of_state(fc, s, _GAP, _FREE, t, full, k)
    for order in range(2, 5):
        threshold = 1e-12 * scale * w ** order
        if order < 4:
            threshold = max(threshold, 8.0 * np.spacing(max(abs(t), 1.0)) * abs(derivs[order + 1]))
        if derivs[order] > threshold:
            return order, derivs[order]
        if derivs[order] < -threshold:
            return 0, 0.0
    return 0, 0.0


@njit(cache=True)
def _force_departure(fc, s, t, stuck):
    F = _of_state(fc, s, _FORCE, _STUCK, t, stuck, 0)
    scale = s[_FORCE_EPS]
    if F > scale:
        return 0, 0.0
    w = max(s[_OMEGA], s[_OMEGA1])
    for order in range(1, 4):
        d = _of_state(fc, s, _FORCE, _STUCK, t, stuck, order)
        if d > scale * w ** order:
            return order, d
        if d < -scale * w ** order:
            return 0, 0.0
    return 0, 0.0


@njit(cache=True)
def _stick(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full, t_inf):
    m1, m2 = s[_M1], s[_M2]
    v_cm = (m1 * full[2] + m2 * full[3]) / (m1 + m2)
    stuck = np.empty(4)
    stuck[0], stuck[1], stuck[2], stuck[3] = full[0], v_cm, 0.0, 0.0
    S = m1 * (v_cm - full[2])
    after = np.empty(4)
    _full_state(s, _STUCK, stuck, after)
    _record_event(s, sf, si, ev_k, ev_f, t, _STICK, 0.0, S, full, after, t_inf)
    if si[_SI_ERR]:
        return
    dm, dg = _force_departure(fc, s, t, stuck)
    _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, _STUCK, t, stuck, dm, dg)


@njit(cache=True)
def _leave_contact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full, rebound):
    F = fc[_FORCE, 6, 0] + fc[_FORCE, 6, 1] * math.sin(s[_OMEGA] * t) + fc[_FORCE, 0, 0] * full[0] \
        + fc[_FORCE, 0, 1] * full[2]
    a = F / s[_MRED]
    if a > 0.0 and rebound * rebound <= 2.0 * a * s[_CHATTER] * s[_LSCALE]:
        R = s[_R]
        t_inf = t + (2.0 * rebound / ((1.0 - R) * a) if R < 1.0 else 0.0)
        _stick(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full, t_inf)
        return
    dm, dg = _gap_departure(fc, s, t, full, rebound)
    if dm == 0:
        _stick(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full, t)
        return
    _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, _FREE, t, full, dm, dg)


@njit(cache=True)
def _impact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, full):
    """Eqs. (21)-(22): the pulse S = m_red (1 + R) v; then rebound, separate or stick."""
    v = max(full[3] - full[2], 0.0)
    S = s[_MRED] * (1.0 + s[_R]) * v
    after = full.copy()
    after[2] += S / s[_M1]
    after[3] -= S / s[_M2]
    _record_event(s, sf, si, ev_k, ev_f, t, _IMPACT, v, S, full, after, t)
    if si[_SI_ERR]:
        return
    _leave_contact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t, after, s[_R] * v)


@njit(cache=True)
def _dip_unresolved(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, t, full):
    """The reference's _dip_unresolved: a contact-force dip too brief to part the bodies by
    more than the grazing resolution keeps the contact. Returns True if it does."""
    T = s[_T]
    stuck = np.empty(4)
    t0 = sf[_SF_T0]
    _state(cm, s, _STUCK, t0, alpha, t, stuck)
    slope = _of_state(fc, s, _FORCE, _STUCK, t, stuck, 1)
    budget = np.array([sf[_SF_LIMIT], sf[_SF_USED]])
    dm, dg = (1, -slope) if slope < 0.0 else (0, 0.0)
    status, t_up, _, _ = _march(cm, fm, fc, fk, fg, s, _NEG_FORCE, _STUCK, t0, alpha, t, t + T, s[_FORCE_EPS],
                                dm, dg, budget)
    sf[_SF_USED] = budget[1]
    if status > 1:
        si[_SI_ERR] = status
        return False
    if status == 0 or t_up <= t:
        return False
    a_free = np.empty(4, np.complex128)
    _alpha(cm, s, _FREE, t, full, a_free)
    y = np.empty(4)
    ts = np.linspace(t, t_up, DIP_SAMPLES)
    gmax = -math.inf
    for i in range(DIP_SAMPLES):
        _state(cm, s, _FREE, t, a_free, ts[i], y)
        gmax = max(gmax, s[_DELTA0] - (y[1] - y[0]))
    if gmax > s[_GAP_EPS]:
        return False
    _state(cm, s, _STUCK, t0, alpha, t_up, stuck)
    slope_up = _of_state(fc, s, _FORCE, _STUCK, t_up, stuck, 1)
    sf[_SF_FROM] = t_up
    if slope_up > 0.0:
        si[_SI_DEPM], sf[_SF_DEPG] = 1, slope_up
    else:
        si[_SI_DEPM], sf[_SF_DEPG] = 0, 0.0
    return True


@njit(cache=True)
def _liftoff(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t):
    stuck = np.empty(4)
    _state(cm, s, _STUCK, sf[_SF_T0], alpha, t, stuck)
    full = np.empty(4)
    _full_state(s, _STUCK, stuck, full)
    dm, dg = _gap_departure(fc, s, t, full, 0.0)
    if dm == 0:
        F2 = _of_state(fc, s, _FORCE, _STUCK, t, stuck, 2)
        sf[_SF_FROM] = t
        si[_SI_DEPM], sf[_SF_DEPG] = 2, max(F2, 1e-300)
        return
    if _dip_unresolved(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, t, full) or si[_SI_ERR]:
        return
    _record_event(s, sf, si, ev_k, ev_f, t, _LIFTOFF, 0.0, 0.0, full, full, t)
    if si[_SI_ERR]:
        return
    _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, _FREE, t, full, dm, dg)


@njit(cache=True)
def _init(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, state):
    """The reference solver's constructor (state already checked: gap >= -gap_tol)."""
    sf[:] = 0.0
    record = si[_SI_REC]
    si[:] = 0
    si[_SI_REC] = record
    sf[_SF_START] = t0
    sf[_SF_LIMIT] = STEPS_AT_START
    full = state.copy()
    gap = s[_DELTA0] - (full[1] - full[0])
    if gap <= s[_GAP_EPS]:
        full[1] = full[0] + s[_DELTA0]
        if full[3] - full[2] > 0.0:
            _impact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, full)
        else:
            _leave_contact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, full,
                           full[2] - full[3])
    else:
        _start(cm, s, sf, si, y0, alpha, seg_m, seg_f, seg_a, _FREE, t0, full, 0, 0.0)


@njit(cache=True)
def _advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_target):
    """The reference's EventDrivenSolver.advance; sets si[_SI_ERR] on an error."""
    T = s[_T]
    sf[_SF_LIMIT] = STEPS_AT_START + int(STEPS_PER_PERIOD * max(t_target - sf[_SF_START], 0.0) / T)
    budget = np.empty(2)
    full = np.empty(4)
    while si[_SI_ERR] == 0:
        mode = si[_SI_MODE]
        if mode == _FREE:
            f = _GAP
            eps = s[_GAP_EPS]
        else:
            f = _FORCE
            eps = s[_FORCE_EPS]
        if sf[_SF_FROM] >= t_target:
            return
        budget[0], budget[1] = sf[_SF_LIMIT], sf[_SF_USED]
        status, t_event, _, reached = _march(cm, fm, fc, fk, fg, s, f, mode, sf[_SF_T0], alpha, sf[_SF_FROM],
                                             t_target, eps, si[_SI_DEPM], sf[_SF_DEPG], budget)
        sf[_SF_USED] = budget[1]
        if status > 1:
            si[_SI_ERR] = status
            return
        if status == 0:
            sf[_SF_FROM] = reached
            si[_SI_DEPM], sf[_SF_DEPG] = 0, 0.0
            return
        if mode == _FREE:
            _state(cm, s, _FREE, sf[_SF_T0], alpha, t_event, full)
            full[1] = full[0] + s[_DELTA0]
            _impact(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_event, full.copy())
        else:
            _liftoff(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_event)


@njit(cache=True)
def _state_at(cm, s, sf, si, alpha, t, out):
    y = np.empty(4)
    _state(cm, s, si[_SI_MODE], sf[_SF_T0], alpha, t, y)
    _full_state(s, si[_SI_MODE], y, out)


@njit(cache=True)
def _solver_buffers(capacity):
    """A solver's state (sf, si, y0, alpha) and its event and segment buffers of ``capacity``
    rows (0: not recorded)."""
    return (np.zeros(8), np.zeros(8, np.int64), np.zeros(4), np.zeros(4, np.complex128),
            np.empty(capacity, np.int64), np.empty((capacity, 12)), np.empty(capacity, np.int64),
            np.empty((capacity, 5)), np.empty((capacity, 4), np.complex128))


@njit(cache=True)
def _simulate_kernel(cm, fm, fc, fk, fg, s, t0, state, t_end, capacity):
    """A recorded run from (t0, state) to t_end. Returns (error, events' kinds and values,
    segments' modes, values and alphas), cut to their lengths."""
    sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a = _solver_buffers(capacity)
    si[_SI_REC] = 1
    _init(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, state)
    if si[_SI_ERR] == 0:
        _advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_end)
    ne = min(si[_SI_NEV], capacity)
    ns = min(si[_SI_NSEG], capacity)
    return si[_SI_ERR], ev_k[:ne].copy(), ev_f[:ne].copy(), seg_m[:ns].copy(), seg_f[:ns].copy(), seg_a[:ns].copy()


@njit(cache=True)
def _count_kernel(cm, fm, fc, fk, fg, s, t0, state, t_end):
    """An unrecorded run: (error, events) only (the benchmark's per-impact cost)."""
    sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a = _solver_buffers(0)
    _init(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0, state)
    if si[_SI_ERR] == 0:
        _advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t_end)
    return si[_SI_ERR], si[_SI_NEV]


# ------------------------------------------------------------------------------------------
# Kernels: the settled motion (steady._steady_state)
# ------------------------------------------------------------------------------------------
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
    _state(cm, s, seg_m[k], seg_f[k, 0], seg_a[k], t, y)
    _full_state(s, seg_m[k], y, out)
    return seg_m[k]


@njit(cache=True)
def _abs_x1(cm, s, seg_m, seg_f, seg_a, k, t, y):
    """|x1(t)| on segment k: the first row of eq. (18) alone, one root of each conjugate pair
    (as the event search's evaluator), the excursion search's hot path. It differs from the
    full state's x1 by rounding only, which moves the maximum's value by rounding only."""
    mode = seg_m[k]
    n = _n_of(mode)
    tau = t - seg_f[k, 0]
    acc = 0.0
    for j in range(n):
        lam = cm[mode, 0, j]
        if lam.imag < 0.0:
            continue
        term = (cm[mode, 2, j] * seg_a[k, j] * np.exp(lam * tau)).real
        acc += 2.0 * term if lam.imag > 0.0 else term
    return abs(acc + (cm[mode, 1, 0] * np.exp(1j * s[_OMEGA] * t)).imag)


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
    T = s[_T]
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
    return best / s[_XST]


# Regime codes: indices into steady.REGIMES.
_RG_NO_CONTACT, _RG_STUCK, _RG_CHATTER, _RG_SINGLE, _RG_MULTI, _RG_NONPERIODIC = range(6)


@njit(cache=True)
def _describe(cm, s, ev_k, ev_f, ne, seg_m, seg_f, seg_a, ns, window_start, k, settled, out_imp, section):
    """The reference's steady._describe. Fills out_imp rows (t, t/T since start, phase,
    velocity, impulse) and section (state at the first section in the cycle, then its mode).
    Returns (regime code, impacts, cycle start, contact fraction, x1_max)."""
    T = s[_T]
    Tc = k * T
    window_end = window_start + Tc
    start = window_start
    best_flight = -math.inf
    t_begin = seg_f[0, 0]
    for i in range(ne):
        if ev_k[i] == _IMPACT and window_start <= ev_f[i, 0] < window_end:
            flight = ev_f[i, 0] - (ev_f[i - 1, 0] if i else t_begin)
            if flight > best_flight:
                best_flight = flight
                start = ev_f[i, 0]
    z = 0
    contact_events = False
    for i in range(ne):
        t = ev_f[i, 0]
        if start - 1e-9 * T <= t < start + Tc - 1e-9 * T:
            if ev_k[i] == _IMPACT:
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
        if seg_m[i] != _STUCK:
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
def _steady_kernel(cm, fm, fc, fk, fg, s, t0, state, default_start, settle_tol, max_periods, kmax, capacity,
                   out_imp, section):
    """The reference's _steady_state. Returns (error, regime, k, impacts, cycle start, contact
    fraction, x1_max, periods, residual); out_imp and section filled by _describe."""
    T = s[_T]
    scale = np.array([s[_XST], s[_XST], s[_XST] * s[_OMEGA], s[_XST] * s[_OMEGA]])
    sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a = _solver_buffers(0)
    _init(cm, fc, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t0, state)
    if si[_SI_ERR]:
        return si[_SI_ERR], 0, 0, 0, 0.0, 0.0, 0.0, 0, 0.0
    start_state = np.empty(4)
    if default_start:
        _state_at(cm, s, sf, si, alpha, t0, start_state)
    else:
        start_state[:] = state
    states = np.empty((max_periods, 4))
    sections = np.empty((max_periods, 4))
    modes = np.empty(max_periods, np.int64)
    found_k, n, residual = 0, 0, math.inf
    base = 0
    for n in range(1, max_periods + 1):
        if n - 1 - base >= REBASE_PERIODS:
            _init(cm, fc, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t0, states[n - 2].copy())
            if si[_SI_ERR]:
                return si[_SI_ERR], 0, 0, 0, 0.0, 0.0, 0.0, 0, 0.0
            base = n - 1
        t_n = t0 + (n - base) * T
        _advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, e_k, e_f, s_m, s_f, s_a, t_n)
        if si[_SI_ERR]:
            return si[_SI_ERR], 0, 0, 0, 0.0, 0.0, 0.0, 0, 0.0
        _state_at(cm, s, sf, si, alpha, t_n, states[n - 1])
        for c in range(4):
            sections[n - 1, c] = states[n - 1, c] / scale[c]
        modes[n - 1] = si[_SI_MODE]
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
        if found_k:
            break
    k = found_k if found_k else min(NONPERIODIC_WINDOW, n)
    first = max(n - k - max(k, PERIODS_BEFORE_CYCLE), 0)
    _, _, _, _, ev_k, ev_f, seg_m, seg_f, seg_a = _solver_buffers(capacity)
    si[_SI_REC] = 1
    _init(cm, fc, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a, t0,
          states[first - 1].copy() if first else start_state)
    if si[_SI_ERR] == 0:
        _advance(cm, fm, fc, fk, fg, s, sf, si, y0, alpha, ev_k, ev_f, seg_m, seg_f, seg_a,
                 t0 + (n - first + k + 1) * T)
    if si[_SI_ERR]:
        return si[_SI_ERR], 0, 0, 0, 0.0, 0.0, 0.0, n, residual
    regime, z, start, frac, x1_max = _describe(cm, s, ev_k, ev_f, si[_SI_NEV], seg_m, seg_f, seg_a, si[_SI_NSEG],
                                               t0 + (n - first - k) * T, k, found_k > 0, out_imp, section)
    return OK, regime, (k if found_k else 0), z, start, frac, x1_max, n, residual


# ------------------------------------------------------------------------------------------
# Kernels: many points per call (a sweep's or a map row's points, each from its neighbour)
# ------------------------------------------------------------------------------------------
# Stop codes of _row_kernel: the row is done, or point i needs the reference (its pack flag,
# an error of the kernels, a nonperiodic point to rescue).
ROW_DONE, ROW_FLAGGED, ROW_ERROR, ROW_RESCUE = 0, 1, 2, 3


@njit(cache=True)
def _row_kernel(S, CM, FM, FC, FK, FG, flags, i0, have_prev, prev_section, prev_mode, prev_periodic, chain, rescue,
                settle_tol, max_periods, max_periods_np, kmax, capacity, regime, kk, zz, x1max, frac, periods,
                residual, starts, sections, sec_mode, phases, vels):
    """Settle points i0, i0 + 1, ... in order, as the reference's solve_point without its
    accelerators: each from its predecessor's section (``chain``, the reference's carry_state)
    or from Algorithm No. 2's step 1. Fills the output arrays; returns (stop code, index)."""
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
            if prev_mode == _STUCK:
                full[1] = full[0] + s[_DELTA0]
                full[3] = full[2]
            elif s[_DELTA0] - (full[1] - full[0]) < 0.0:
                full[1] = full[0] + s[_DELTA0]
        else:
            S0 = DEFAULT_KICK * s[_M1] * s[_OMEGA1] * s[_XST]
            full[0], full[1], full[2], full[3] = 0.0, s[_DELTA0], S0 / s[_M1], -S0 / s[_M2]
        cap = max_periods_np if (chain and have_prev and not prev_periodic) else max_periods
        while True:
            err, rg, k, z, start, fr, x1, n, res = _steady_kernel(CM[i], FM[i], FC[i], FK[i], FG[i], S[i], 0.0,
                                                                  full.copy(), False, settle_tol, cap, kmax, capacity,
                                                                  out_imp, section)
            if err != ERR_CAPACITY:
                break
            capacity *= 4
        if err != OK or z > out_imp.shape[0]:
            return ROW_ERROR, i
        starts[i] = full
        if rg == _RG_NONPERIODIC and rescue:
            return ROW_RESCUE, i
        regime[i], kk[i], zz[i], x1max[i], frac[i] = rg, k, z, x1, fr
        periods[i] = n + max(k, 1) + 1
        residual[i] = res
        sections[i] = section[:4]
        sec_mode[i] = int(section[4])
        for j in range(min(z, phases.shape[1])):
            phases[i, j] = out_imp[j, 2]
            vels[i, j] = out_imp[j, 3] / (s[_XST] * s[_OMEGA])
        have_prev = True
        prev_section = section[:4].copy()
        prev_mode = int(section[4])
        prev_periodic = rg != _RG_NONPERIODIC
    return ROW_DONE, P


# ------------------------------------------------------------------------------------------
# Python API
# ------------------------------------------------------------------------------------------
def _default_state(p: Parameters) -> np.ndarray:
    """Algorithm No. 2's step 1 (the reference's default_initial_state)."""
    S0 = DEFAULT_KICK * p.m1 * p.omega1 * p.x_st
    return np.array([0.0, p.Delta0, S0 / p.m1, -S0 / p.m2])


def _checked_state(p: Parameters, state, tol: Tolerances) -> np.ndarray:
    """The start state, validated as the reference's solver does (by constructing it when the
    state is unusual: the reference raises the named error)."""
    full = check_state(state, p)
    if full is None:
        return _default_state(p)
    gap = p.Delta0 - (full[1] - full[0])
    if gap < -tol.gap_tol * p.x_st:
        EventDrivenSolver(p, t0=0.0, state=full, tolerances=tol)  # raises the reference's message
    return full


@dataclass(frozen=True)
class CompiledRun:
    """A compiled run's events and segments, as arrays (no Python object per event).

    Attributes
    ----------
    kinds : ndarray of int, shape (E,)
        Indices into :data:`EVENT_KINDS`.
    events : ndarray, shape (E, 12)
        Per event: t (s), closing velocity (m/s), pulse (N s), state before (4), after (4),
        accumulation time t_inf (s).
    segment_modes : ndarray of int, shape (S,)
        0 free, 1 stuck.
    segments : ndarray, shape (S, 5)
        Per segment: start time t0 (s) and start state (4; stuck: x1, x1', 0, 0).
    """

    kinds: np.ndarray
    events: np.ndarray
    segment_modes: np.ndarray
    segments: np.ndarray

    @property
    def times(self) -> np.ndarray:
        return self.events[:, 0]


def run_compiled(p: Parameters, t_end: float, t0: float = 0.0, state: np.ndarray | None = None,
                 tolerances: Tolerances | None = None, *, pack: Pack | None = None) -> CompiledRun | None:
    """Algorithm No. 2 with contact modes from ``t0`` to ``t_end`` in the kernels, as arrays.

    Parameters
    ----------
    p, t_end, t0, state, tolerances
        As for :func:`simulate_compiled` (validated there, not here).
    pack : Pack, optional
        :func:`pack_parameters` of ``p`` and ``tolerances``, if already made.

    Returns
    -------
    CompiledRun, or None where the kernels do not apply or stopped on an error (the caller
    then runs the reference).
    """
    pack = pack_parameters(p, tolerances) if pack is None else pack
    if pack.fallback:
        return None
    full = _default_state(p) if state is None else np.asarray(state, dtype=float)
    capacity = max(INITIAL_CAPACITY, int(EVENTS_PER_PERIOD_GUESS * (float(t_end) - float(t0)) / p.T))
    while True:
        err, ev_k, ev_f, seg_m, seg_f, _ = _simulate_kernel(pack.cm, pack.fm, pack.fc, pack.fk, pack.fg, pack.s,
                                                            float(t0), full, float(t_end), capacity)
        if err != ERR_CAPACITY:
            break
        capacity *= 4
    return None if err else CompiledRun(ev_k, ev_f, seg_m, seg_f)


def simulate_compiled(p: Parameters, t_end: float, t0: float = 0.0, state: np.ndarray | None = None,
                      tolerances: Tolerances | None = None) -> Trajectory:
    """Algorithm No. 2 with contact modes from ``t0`` to ``t_end``, compiled.

    The same motion as :func:`impactdamper.core.simulate.simulate` (the same events, kinds and
    order; times to rounding, see the tests): a :class:`Trajectory` whose segments are the
    reference's :class:`~impactdamper.core.events.Segment` objects, so ``sample`` works as
    there. Where the kernels do not apply (see the module docstring) the reference runs
    instead; the returned trajectory's ``compiled`` attribute says which ran.

    Parameters
    ----------
    p : Parameters
    t_end, t0 : float
        End and start, s.
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0; default Algorithm No. 2's step 1.
    tolerances : Tolerances, optional

    Raises
    ------
    TypeError, ValueError, SearchLimitError
        As :func:`~impactdamper.core.simulate.simulate` (the reference raises them).
    """
    p = require_parameters(p)
    tol = check_tolerances(tolerances)
    t_endf = finite_argument("t_end", t_end)
    t0f = check_start_time(t0, p)
    check_start_time(t_endf, p, "t_end")
    if not t_endf > t0f or (t_endf - t0f) / p.T > MAX_SIMULATE_PERIODS:
        simulate(p, t_end, t0, state, tolerances)  # raises the reference's named error
    full = _checked_state(p, state, tol)
    run = run_compiled(p, t_endf, t0f, full, tol)
    if run is None:
        traj = simulate(p, t_end, t0, state, tolerances)  # raises the reference's error, or runs where it must
        traj.compiled = False
        return traj
    return _trajectory(p, run.kinds, run.events, run.segment_modes, run.segments)


def _trajectory(p: Parameters, ev_k, ev_f, seg_m, seg_f) -> Trajectory:
    from impactdamper.core.events import Segment
    from impactdamper.core.model import FREE, STUCK

    model = Model(p)
    traj = Trajectory(model)
    for m, row in zip(seg_m.tolist(), seg_f):
        name = FREE if m == _FREE else STUCK
        n = 4 if m == _FREE else 2
        traj.segments.append((name, Segment(model.mode(name), float(row[0]), row[1:1 + n].copy())))
    for k, row in zip(ev_k.tolist(), ev_f):
        traj.events.append(Event(float(row[0]), EVENT_KINDS[k], float(row[1]), float(row[2]), row[3:7].copy(),
                                 row[7:11].copy(), float(row[11])))
    traj.compiled = True
    return traj


def count_events_compiled(p: Parameters, t_end: float, t0: float = 0.0, state: np.ndarray | None = None,
                          tolerances: Tolerances | None = None) -> int:
    """Events of the run from ``t0`` to ``t_end`` without recording them (the solver's pure
    cost, for benchmarks). Raises ValueError if the kernels do not apply to ``p``."""
    pack = pack_parameters(p, tolerances)
    if pack.fallback:
        raise ValueError(f"`p` = {p!r} is not allowed here: the kernels do not apply "
                         f"({FALLBACK_REASONS[pack.fallback]})")
    full = _checked_state(p, state, check_tolerances(tolerances))
    err, n = _count_kernel(pack.cm, pack.fm, pack.fc, pack.fk, pack.fg, pack.s, float(t0), full, float(t_end))
    if err:
        raise RuntimeError(f"the compiled run failed with error code {err}; run simulate() for the message")
    return int(n)


@dataclass(frozen=True)
class CompiledSteady:
    """The settled motion's fields that sweeps and maps read (those of
    :class:`~impactdamper.core.steady.SteadyState`).

    Attributes
    ----------
    regime : str
        One of :data:`impactdamper.core.steady.REGIMES`.
    period_multiple : int
        k in T_c = k T (0 when nonperiodic).
    impact_times, impact_phases, velocities, impulses : ndarray, shape (z,)
        The cycle's impacts: absolute times (s), forcing phases t/T mod 1, closing velocities
        (m/s), pulses (N s).
    cycle_start : float
        Time the reported cycle starts, s.
    contact_fraction : float
    x1_max : float
        max |x1|/x_st over the cycle.
    periods : int
        Forcing periods simulated until settled.
    residual : float
        Largest relative section mismatch over the final cycle.
    section : ndarray, shape (4,)
        State at the first section t = n T in the cycle (carried to a sweep's next point).
    section_mode : str
        ``free`` or ``stuck`` there.
    fallback : str
        "" if the kernels computed it, else why the reference did (see :data:`FALLBACK_REASONS`).
    """

    regime: str
    period_multiple: int
    impact_times: np.ndarray
    impact_phases: np.ndarray
    velocities: np.ndarray
    impulses: np.ndarray
    cycle_start: float
    contact_fraction: float
    x1_max: float
    periods: int
    residual: float
    section: np.ndarray
    section_mode: str
    fallback: str = ""

    @property
    def impacts_per_cycle(self) -> int:
        return len(self.impact_phases)


def _from_reference(p: Parameters, s, reason: str) -> CompiledSteady:
    from impactdamper.analysis.sweeps import _section_of  # (the reference's own reading of the section)

    section, mode = _section_of(s)
    return CompiledSteady(
        regime=s.regime, period_multiple=s.period_multiple,
        impact_times=np.array([i.t for i in s.impacts]), impact_phases=np.array([i.phase for i in s.impacts]),
        velocities=np.array([i.velocity for i in s.impacts]), impulses=np.array([i.impulse for i in s.impacts]),
        cycle_start=s.cycle_start, contact_fraction=float(s.contact_fraction), x1_max=float(s.x1_max),
        periods=s.periods, residual=float(s.residual), section=np.asarray(section, float), section_mode=mode,
        fallback=reason)


def steady_state_compiled(p: Parameters, *, t0: float = 0.0, state: np.ndarray | None = None,
                          tolerances: Tolerances | None = None, settle_tol: float = 1e-10, max_periods: int = 4000,
                          max_period_multiple: int = 8) -> CompiledSteady:
    """The settled motion, compiled: :func:`impactdamper.core.steady.steady_state`'s result.

    Parameters and their meaning as there. The reference runs instead (and ``fallback`` says
    why) where the kernels do not apply, or where they stopped on an error (the reference then
    raises its own exception, with its message).

    Raises
    ------
    TypeError, ValueError, SearchLimitError
        As :func:`~impactdamper.core.steady.steady_state`.
    """
    p = require_parameters(p)
    tol = check_tolerances(tolerances)
    t0 = finite_argument("t0", t0)
    settle_tol = real_argument("settle_tol", settle_tol)
    if not (math.isfinite(settle_tol) and 0 < settle_tol < 1):
        raise ValueError(f"`settle_tol` = {settle_tol!r} is not allowed: must be in (0, 1)")
    max_periods = integer_argument("max_periods", max_periods, 2, MAX_PERIODS_LIMIT)
    max_period_multiple = integer_argument("max_period_multiple", max_period_multiple, 1, max_periods - 1)
    pack = pack_parameters(p, tol)
    args = dict(t0=t0, state=state, tolerances=tolerances, settle_tol=settle_tol, max_periods=max_periods,
                max_period_multiple=max_period_multiple)
    if pack.fallback:
        return _from_reference(p, steady_state(p, **args), FALLBACK_REASONS[pack.fallback])
    start = start_in_first_period(p, t0)
    full = _checked_state(p, state, tol)
    result = _steady_run(pack, start, full, state is None, settle_tol, max_periods, max_period_multiple)
    if result is None:
        return _from_reference(p, steady_state(p, **args), "error")
    return result


def _steady_run(pack: Pack, t0: float, full: np.ndarray, default_start: bool, settle_tol: float, max_periods: int,
                kmax: int) -> CompiledSteady | None:
    """One kernel run; None if the kernels stopped on an error."""
    capacity = INITIAL_CAPACITY
    out_imp = np.zeros((64 * kmax, 5))
    section = np.zeros(5)
    while True:
        (err, regime, k, z, start, frac, x1_max, n,
         residual) = _steady_kernel(pack.cm, pack.fm, pack.fc, pack.fk, pack.fg, pack.s, t0, full, default_start,
                                    settle_tol, max_periods, kmax, capacity, out_imp, section)
        if err == ERR_CAPACITY:
            capacity *= 4
            continue
        if err == OK and z > out_imp.shape[0]:
            out_imp = np.zeros((z, 5))
            continue
        break
    if err:
        return None
    imp = out_imp[:z]
    return CompiledSteady(regime=REGIMES[regime], period_multiple=int(k), impact_times=imp[:, 0].copy(),
                          impact_phases=imp[:, 2].copy(), velocities=imp[:, 3].copy(), impulses=imp[:, 4].copy(),
                          cycle_start=float(start), contact_fraction=float(frac), x1_max=float(x1_max),
                          periods=int(n), residual=float(residual), section=section[:4].copy(),
                          section_mode="free" if section[4] == _FREE else "stuck")


def warm_up() -> float:
    """Compile (or load from the cache) every kernel on the reference case; the seconds it took."""
    t = time.perf_counter()
    p = Parameters()
    steady_state_compiled(p, max_periods=40)
    from impactdamper.analysis.batch import settled_batch

    settled_batch(p, ("gap",), np.array([[-5.8], [-5.0]]))
    simulate_compiled(p, 2 * p.T)
    count_events_compiled(p, 2 * p.T)
    return time.perf_counter() - t
