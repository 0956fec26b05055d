"""A parameter set packed into the compiled kernels' arrays.

The kernels only evaluate: the matrices of both contact modes (modal eigenvectors, forced
amplitudes of eqs. (10)-(11), the energy weight) and of the functionals (the gap of eq. (20),
the contact force and minus it, with their derivative-bound factors) are computed here, with the
operations of the reference classes (:class:`~impactdamper.core.model.Model`,
:class:`~impactdamper.core.linear.LinearMode`) so that they round the same way, and packed into
a :class:`Pack`. A set the kernels do not cover is flagged with its reason
(:data:`~impactdamper.core.compiled.layout.FALLBACK_REASONS`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit, types
from numba.np.linalg import _LAPACK, ensure_lapack

from impactdamper.core.compiled.layout import (
    FORCE,
    GAP,
    NEG_FORCE,
    N_SCALARS,
    S_CHATTER,
    S_DELTA0,
    S_FORCE_EPS,
    S_FSCALE,
    S_GAP_EPS,
    S_LSCALE,
    S_M1,
    S_M2,
    S_MRED,
    S_OMEGA,
    S_OMEGA1,
    S_R,
    S_STUCK_RES,
    S_T,
    S_XST,
)
from impactdamper.core.linear import MODAL_CONDITION_LIMIT, scaled_condition
from impactdamper.core.model import FORCED_AMPLITUDE_LIMIT
from impactdamper.core.parameters import NATIVE_SCALES, Parameters
from impactdamper.core.validation import Tolerances


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


# The relative parameters, in the columns of pack_many's input: the parameter table's order
# (core/parameters.py's PARAMETER_TABLE). The kernels read a column by its name's index below
# (compile-time constants), never by position, so a parameter inserted in the table shifts
# nothing silently.
PARAMETER_COLUMNS = Parameters.names()
_COLUMN = {name: i for i, name in enumerate(PARAMETER_COLUMNS)}
C_THETA, C_MU, C_N = _COLUMN["theta"], _COLUMN["mu"], _COLUMN["N"]
C_DELTA1, C_DELTA2 = _COLUMN["delta1"], _COLUMN["delta2"]
C_R, C_GAP = _COLUMN["R"], _COLUMN["gap"]
C_OMEGA, C_XST, C_M1 = _COLUMN["omega"], _COLUMN["x_st"], _COLUMN["m1"]
# Pack flags (pack_many's second output), as in FALLBACK_REASONS: 0 the kernels apply.
_PACK_OK, _PACK_EXPM, _PACK_SCALES, _PACK_ERROR = 0, 1, 2, 3
# LAPACK's dgeev as numpy's eig calls it for a real matrix, reached from compiled code through
# numba's own binding (numba's np.linalg.eig refuses a real matrix with complex roots before numpy
# 2.5, and calling numpy's from Python cost a third of a single set's packing).
ensure_lapack()
_RGEEV = _LAPACK().numba_ez_rgeev(types.float64)
_GEEV_KIND, _JOB_N, _JOB_V = ord("d"), ord("N"), ord("V")
# The default tolerances, made once (constructing and validating them costs more than packing's
# compiled part).
_DEFAULT_TOLERANCES = Tolerances()
_DEFAULT_TOLERANCE_VALUES = np.array(
    [_DEFAULT_TOLERANCES.gap_tol, _DEFAULT_TOLERANCES.chatter_tol, _DEFAULT_TOLERANCES.force_tol]
)


def _stacked_mode(M: np.ndarray, b: np.ndarray, omega: np.ndarray, W: np.ndarray):
    """The reference's LinearMode.__post_init__ for a stack of modes (shapes (P, n, n), (P, n),
    (P,), (P, n, n)), with the same LAPACK calls: (roots, V, V^-1, Yhat, L^-T, powers, modal, ok)."""
    P, n = M.shape[0], M.shape[1]
    with np.errstate(all="ignore"):
        lam, V = np.linalg.eig(M)
        condition = scaled_condition(V, lam)
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
    values : ndarray, shape (P, len(PARAMETER_COLUMNS))
        Relative parameters in the order of :data:`PARAMETER_COLUMNS`, each row valid for
        :class:`Parameters` (the caller validates).
    tolerances : Tolerances, optional
        Validated by the caller (None: the defaults).

    Returns
    -------
    pack : Pack
        Arrays with a leading axis P (s (P, 16), cm (P, 2, 10, 4), ...).
    flags : ndarray of int, shape (P,)
        Per row, an index into :data:`FALLBACK_REASONS`: 0 where the kernels apply; 1 where a
        mode is not modal (repeated roots); 2 outside the native scales; 3 where the reference
        Model raises (extreme parameters, resonance), so that the reference reports it.
    """
    tol = tolerances or _DEFAULT_TOLERANCES
    v = np.asarray(values, dtype=float).reshape(-1, len(PARAMETER_COLUMNS))
    P = v.shape[0]
    Mf, bf, Wf, Ms, bs, Ws, D = _state_matrices_many(v)
    omega1, m2, c1, c2, k1, P0, Delta0, T, mred = D.T
    omega, x_st, R = v[:, C_OMEGA], v[:, C_XST], v[:, C_R]
    m = v[:, C_M1] + m2
    z = np.zeros(P)
    flags = np.zeros(P, np.int64)
    cm = np.zeros((P, 2, 10, 4), complex)
    fm = np.zeros((P, 2, 5, 4))
    modes = []
    for i, (M, b, W) in enumerate(((Mf, bf, Wf), (Ms, bs, Ws))):
        good = np.isfinite(M).all(axis=(1, 2)) & np.isfinite(W).all(axis=(1, 2)) & np.isfinite(b).all(axis=1)
        Mg, bg, Wg = (
            np.where(good[:, None, None], M, np.eye(M.shape[1])),
            np.where(good[:, None], b, 0.0),
            np.where(good[:, None, None], W, np.eye(M.shape[1])),
        )
        lam, V, Vinv, Yhat, LiT, powers, modal, ok = _stacked_mode(Mg, bg, omega, Wg)
        n = M.shape[1]
        ok &= good
        flags[~ok] = _PACK_ERROR
        flags[(flags == 0) & ~modal] = _PACK_EXPM
        cm[:, i, 0, :n], cm[:, i, 1, :n] = lam, Yhat
        cm[:, i, 2 : 2 + n, :n], cm[:, i, 6 : 6 + n, :n] = V, Vinv
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
            fg[:, f, 1 : 1 + n] = np.einsum("pi,pij->pj", c, V)
    s = np.zeros((P, N_SCALARS))
    s[:, S_OMEGA], s[:, S_T], s[:, S_DELTA0], s[:, S_R] = omega, T, Delta0, R
    s[:, S_M1], s[:, S_M2], s[:, S_MRED], s[:, S_OMEGA1] = v[:, C_M1], m2, mred, omega1
    s[:, S_LSCALE] = x_st
    s[:, S_FSCALE] = mred * x_st * np.maximum(np.maximum(omega, omega1), v[:, C_N] * omega1) ** 2
    s[:, S_GAP_EPS] = tol.gap_tol * x_st
    s[:, S_CHATTER] = tol.chatter_tol
    s[:, S_FORCE_EPS] = tol.force_tol * s[:, S_FSCALE]
    s[:, S_STUCK_RES] = stuck_res
    s[:, S_XST] = x_st
    return Pack(s, cm, fm, fc, fk, fg, 0), flags


@njit(cache=True)
def _scaled_condition(n, V, lam):
    """linear.scaled_condition of one mode, in compiled code."""
    rate = 0.0
    for j in range(n):
        rate = max(rate, abs(lam[j]))
    if not math.isfinite(rate):
        return math.inf
    if not rate > 0.0:
        rate = 1.0
    Vs = V.copy()
    for r in range(n // 2, n):
        for j in range(n):
            Vs[r, j] = Vs[r, j] / rate
    for j in range(n):
        norm = 0.0
        for r in range(n):
            norm += abs(Vs[r, j]) ** 2
        norm = math.sqrt(norm)
        if not (norm > 0.0 and math.isfinite(norm)):
            return math.inf
        for r in range(n):
            Vs[r, j] = Vs[r, j] / norm
    return np.linalg.cond(Vs)


@njit(cache=True)
def _pack_mode(i, n, M, b, W, lam, V, omega, cm, fm, powers, LiT):
    """One mode of the reference's LinearMode.__post_init__ (eigen-decomposition given).
    Returns (modal, forced amplitude, finite)."""
    condition = _scaled_condition(n, V, lam)
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
    cm[i, 2 : 2 + n, :n] = V
    if modal:
        cm[i, 6 : 6 + n, :n] = np.linalg.inv(V)
    fm[i, :n, :n] = W
    fm[i, 4, :n] = b
    finite = True
    for r in range(n):
        powers[0, r, r] = 1.0
    for k in range(6):
        if k > 0:  # M^k = M^(k-1) M, summed in index order (a BLAS call costs more on 4 x 4)
            for r in range(n):
                for c in range(n):
                    acc = 0.0
                    for j in range(n):
                        acc += powers[k - 1, r, j] * M[j, c]
                    powers[k, r, c] = acc
        for r in range(n):
            for c in range(n):
                if not math.isfinite(powers[k, r, c]):
                    finite = False
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
    s, cm, fm = np.zeros(N_SCALARS), np.zeros((2, 10, 4), np.complex128), np.zeros((2, 5, 4))
    fc, fk, fg = np.zeros((3, 8, 6)), np.zeros((3, 6)), np.zeros((3, 5), np.complex128)
    N, R, omega, x_st, m1 = v[C_N], v[C_R], v[C_OMEGA], v[C_XST], v[C_M1]
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
    _pack_functional(GAP, 4, cg, Delta0, 0.0, powers_f, LiT_f, bf, cm[0, 1], V_f, fc, fk, fg)
    _pack_functional(FORCE, 2, cf, -c2 * Delta0, -m2 * P0 / m, powers_s, LiT_s, bs, cm[1, 1], V_s, fc, fk, fg)
    _pack_functional(
        NEG_FORCE, 2, -cf, -(-c2 * Delta0), -(-m2 * P0 / m), powers_s, LiT_s, bs, cm[1, 1], V_s, fc, fk, fg
    )
    s[S_OMEGA], s[S_T], s[S_DELTA0], s[S_R] = omega, T, Delta0, R
    s[S_M1], s[S_M2], s[S_MRED], s[S_OMEGA1] = m1, m2, mred, omega1
    s[S_LSCALE] = x_st
    s[S_FSCALE] = mred * x_st * max(omega, omega1, omega2) ** 2
    s[S_GAP_EPS] = tols[0] * x_st
    s[S_CHATTER] = tols[1]
    s[S_FORCE_EPS] = tols[2] * s[S_FSCALE]
    s[S_STUCK_RES] = 0.0 if amp_s <= FORCED_AMPLITUDE_LIMIT * x_st else 1.0
    s[S_XST] = x_st
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
    theta, mu, N, delta1, delta2 = v[C_THETA], v[C_MU], v[C_N], v[C_DELTA1], v[C_DELTA2]
    gap, omega, x_st, m1 = v[C_GAP], v[C_OMEGA], v[C_XST], v[C_M1]
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
    """_state_matrices for each row of values (P, len(PARAMETER_COLUMNS)): stacked (M, b, W) of both modes and the
    derived values (P, 9)."""
    P = values.shape[0]
    Mf, bf, Wf = np.zeros((P, 4, 4)), np.zeros((P, 4)), np.zeros((P, 4, 4))
    Ms, bs, Ws = np.zeros((P, 2, 2)), np.zeros((P, 2)), np.zeros((P, 2, 2))
    D = np.zeros((P, 9))
    for i in range(P):
        Mf[i], bf[i], Wf[i], Ms[i], bs[i], Ws[i], D[i] = _state_matrices(values[i])
    return Mf, bf, Wf, Ms, bs, Ws, D


@njit(cache=True)
def _real_eig(M):
    """numpy.linalg.eig of a real square matrix (LAPACK dgeev), in compiled code: (ok, roots,
    unit eigenvectors as columns), a complex pair as exact conjugates with the positive imaginary
    part first and its vectors built from dgeev's real and imaginary columns, as numpy does."""
    n = M.shape[0]
    a = M.T.copy()  # C order of the transpose: M in Fortran order, as LAPACK reads it
    wr, wi = np.empty(n), np.empty(n)
    vl, vr = np.empty((n, 1)), np.empty((n, n))
    info = _RGEEV(_GEEV_KIND, _JOB_N, _JOB_V, n, a.ctypes, n, wr.ctypes, wi.ctypes, vl.ctypes, 1, vr.ctypes, n)
    lam = np.empty(n, np.complex128)
    V = np.empty((n, n), np.complex128)
    i = 0
    while i < n:  # row i of vr (C order) is LAPACK's column i
        if wi[i] == 0.0 or i + 1 == n:
            lam[i] = complex(wr[i], wi[i])
            for r in range(n):
                V[r, i] = vr[i, r]
            i += 1
        else:
            lam[i], lam[i + 1] = complex(wr[i], wi[i]), complex(wr[i + 1], wi[i + 1])
            for r in range(n):
                V[r, i] = complex(vr[i, r], vr[i + 1, r])
                V[r, i + 1] = complex(vr[i, r], -vr[i + 1, r])
            i += 2
    # (keeps the arrays LAPACK wrote through pointers alive until here)
    ok = info == 0 and a.size + vl.size + vr.size + wr.size + wi.size > 0
    return ok, lam, V


@njit(cache=True)
def pack_single(v, tols):
    """_pack_one with the free mode's eigen-decomposition computed here (one compiled call per
    parameter set, which the kernels can share with a run); flag _PACK_ERROR where dgeev fails.
    v and tols as :func:`packing_values` gives them."""
    ok, lam_f, V_f = _real_eig(_state_matrices(v)[0])
    if not ok:
        return (
            np.zeros(N_SCALARS),
            np.zeros((2, 10, 4), np.complex128),
            np.zeros((2, 5, 4)),
            np.zeros((3, 8, 6)),
            np.zeros((3, 6)),
            np.zeros((3, 5), np.complex128),
            _PACK_ERROR,
        )
    return _pack_one(v, tols, lam_f, V_f)


def _empty_pack(flag: int) -> Pack:
    return Pack(
        np.zeros(N_SCALARS),
        np.zeros((2, 10, 4), complex),
        np.zeros((2, 5, 4)),
        np.zeros((3, 8, 6)),
        np.zeros((3, 6)),
        np.zeros((3, 5), complex),
        flag,
    )


def packing_values(p: Parameters, tolerances: Tolerances | None = None) -> tuple[np.ndarray, np.ndarray, int]:
    """(v, tols, flag): the set's relative values in PARAMETER_COLUMNS order and the tolerances
    (gap, chatter, force) that :func:`pack_single` takes (both validated by the caller; None:
    the default tolerances); flag is _PACK_SCALES outside the native scales (then the kernels
    do not apply), else 0."""
    if tolerances is None:
        tols = _DEFAULT_TOLERANCE_VALUES
    else:
        tols = np.array([tolerances.gap_tol, tolerances.chatter_tol, tolerances.force_tol])
    v = np.array([getattr(p, name) for name in PARAMETER_COLUMNS])
    return v, tols, (_PACK_OK if p.native_scales() else _PACK_SCALES)


# What packing raises on a singular or indefinite matrix (extreme parameters or an undamped
# resonance, which the reference Model reports by name): the set is flagged _PACK_ERROR.
PACKING_ERRORS = (np.linalg.LinAlgError, ValueError, ZeroDivisionError)


def pack_parameters(p: Parameters, tolerances: Tolerances | None = None) -> Pack:
    """The kernels' arrays for one parameter set, in one compiled call (the free mode's
    eigen-decomposition by LAPACK's dgeev, as numpy's); its ``fallback`` is the set's flag
    (FALLBACK_REASONS)."""
    v, tols, flag = packing_values(p, tolerances)
    if flag:
        return _empty_pack(flag)
    try:
        *arrays, flag = pack_single(v, tols)
    except PACKING_ERRORS:
        return _empty_pack(_PACK_ERROR)
    return Pack(*arrays, int(flag))
