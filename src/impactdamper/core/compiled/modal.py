"""Each contact mode and each functional packed for the kernels: the modal part of a packed set.

A mode (free, stuck) is its roots and eigenvectors (V, V^-1), the forced amplitudes Yhat of eqs.
(10)-(11), the energy weight's Cholesky factor (L^-T) and the powers M^k; a functional (the gap
of eq. 20, the contact force, minus it) is c M^k, c M^k b, its derivative-bound factors kappa_k
and its modal coefficients G, c . V_j. Both are computed with the operations of the reference
classes (:class:`~impactdamper.core.linear.LinearMode`,
:class:`~impactdamper.core.events.LinearFunctional`), so that they round the same way: for a
stack of sets with numpy (:func:`stacked_modes`, :func:`stacked_functional`) and for one set in
compiled code (:func:`pack_mode`, :func:`pack_functional`, the eigen-decompositions
:func:`real_eig` and :func:`stuck_eig`). Which functional is which, and the scalars, are
:mod:`~impactdamper.core.compiled.pack`'s.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, types
from numba.np.linalg import _LAPACK, ensure_lapack

from impactdamper.core.linear import MODAL_CONDITION_LIMIT, scaled_condition

# LAPACK's dgeev as numpy's eig calls it for a real matrix, reached from compiled code through
# numba's own binding (numba's np.linalg.eig refuses a real matrix with complex roots before numpy
# 2.5, and calling numpy's from Python cost a third of a single set's packing).
ensure_lapack()
_RGEEV = _LAPACK().numba_ez_rgeev(types.float64)
_GEEV_KIND, _JOB_N, _JOB_V = ord("d"), ord("N"), ord("V")


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


def stacked_modes(matrices, omega: np.ndarray):
    """Both modes of a stack of sets (``matrices``: (M, b, W) per mode, free first, each stacked
    (P, n, n), (P, n), (P, n, n)): the arrays cm (P, 2, 10, 4) and fm (P, 2, 5, 4) filled as
    :class:`~impactdamper.core.compiled.pack.Pack` holds them, and per mode (in order) its
    ``(V, Yhat, L^-T, powers, b, largest |Yhat| of the positions)``, its modal flags and its ok
    flags (finite matrices and factors; a non-finite mode is packed as the identity)."""
    P = omega.shape[0]
    cm = np.zeros((P, 2, 10, 4), complex)
    fm = np.zeros((P, 2, 5, 4))
    modes, modal_flags, ok_flags = [], [], []
    for i, (M, b, W) in enumerate(matrices):
        good = np.isfinite(M).all(axis=(1, 2)) & np.isfinite(W).all(axis=(1, 2)) & np.isfinite(b).all(axis=1)
        Mg, bg, Wg = (
            np.where(good[:, None, None], M, np.eye(M.shape[1])),
            np.where(good[:, None], b, 0.0),
            np.where(good[:, None, None], W, np.eye(M.shape[1])),
        )
        lam, V, Vinv, Yhat, LiT, powers, modal, ok = _stacked_mode(Mg, bg, omega, Wg)
        n = M.shape[1]
        ok &= good
        cm[:, i, 0, :n], cm[:, i, 1, :n] = lam, Yhat
        cm[:, i, 2 : 2 + n, :n], cm[:, i, 6 : 6 + n, :n] = V, Vinv
        fm[:, i, :n, :n], fm[:, i, 4, :n] = W, b
        modes.append((V, Yhat, LiT, powers, b, np.abs(Yhat[:, : n // 2]).max(axis=1)))
        modal_flags.append(modal)
        ok_flags.append(ok)
    return cm, fm, modes, modal_flags, ok_flags


def stacked_functional(f: int, c: np.ndarray, g0, d_s, mode, fc: np.ndarray, fk: np.ndarray, fg: np.ndarray) -> None:
    """Functional ``f`` (c (P, n), g0 and d_s (P,)) on a stack of sets' mode (as
    :func:`stacked_modes` gives it) into fc (P, 3, 8, 6), fk (P, 3, 6), fg (P, 3, 5): the
    reference's LinearFunctional.__post_init__ over the stack."""
    with np.errstate(all="ignore"):
        V, Yhat, LiT, powers, b, _ = mode
        n = c.shape[1]
        cM = np.einsum("pi,pkij->pkj", c, powers)  # c M^k, (P, 6, n)
        fc[:, f, :6, :n] = cM
        fc[:, f, 7, :6] = np.einsum("pkj,pj->pk", cM, b)
        fc[:, f, 6, 0], fc[:, f, 6, 1] = g0, d_s
        fk[:, f] = np.linalg.norm(np.einsum("pkj,pjl->pkl", cM, LiT), axis=2)
        fg[:, f, 0] = np.einsum("pi,pi->p", c, Yhat) + d_s
        fg[:, f, 1 : 1 + n] = np.einsum("pi,pij->pj", c, V)


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
def pack_mode(i, n, M, b, W, lam, V, omega, cm, fm, powers, LiT):
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
def pack_functional(f, n, c, g0, d_s, powers, LiT, b, Yhat, V, fc, fk, fg):
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
def stuck_eig(M):
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
def real_eig(M):
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
