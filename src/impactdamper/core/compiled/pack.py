"""A parameter set packed into the compiled kernels' arrays.

The kernels only evaluate: the matrices of both contact modes (modal eigenvectors, forced
amplitudes of eqs. (10)-(11), the energy weight) and of the functionals (the gap of eq. (20),
the contact force and minus it, with their derivative-bound factors) are computed here, with the
operations of the reference classes (:class:`~impactdamper.core.model.Model`,
:class:`~impactdamper.core.linear.LinearMode`) so that they round the same way, and packed into
a :class:`Pack`. A set the kernels do not cover is flagged with its reason
(:data:`~impactdamper.core.compiled.layout.FALLBACK_REASONS`).

This module holds the parameter arrays: the packed set's layout (:class:`Pack`), the relative
parameters' columns, the two modes' matrices from them (as ``Parameters`` derives them), which
functional is which and the scalars; each mode's and functional's modal arrays are computed in
:mod:`~impactdamper.core.compiled.modal`, for one set in compiled code (:func:`pack_single`)
and for a stack with numpy (:func:`pack_many`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

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
from impactdamper.core.compiled.modal import (
    pack_functional,
    pack_mode,
    real_eig,
    stacked_functional,
    stacked_modes,
    stuck_eig,
)
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
# The default tolerances, made once (constructing and validating them costs more than packing's
# compiled part).
_DEFAULT_TOLERANCES = Tolerances()
_DEFAULT_TOLERANCE_VALUES = np.array(
    [_DEFAULT_TOLERANCES.gap_tol, _DEFAULT_TOLERANCES.chatter_tol, _DEFAULT_TOLERANCES.force_tol]
)


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
    Mf, bf, Wf, Ms, bs, Ws, D = _state_matrices_many(v)
    cm, fm, modes, modal, ok = stacked_modes(((Mf, bf, Wf), (Ms, bs, Ws)), v[:, C_OMEGA])
    flags, stuck_res = _flags_many(v, modes, modal, ok)
    fc, fk, fg = _functionals_many(v, D, modes)
    s = _scalars_many(v, D, tol, stuck_res)
    return Pack(s, cm, fm, fc, fk, fg, 0), flags


def _flags_many(v: np.ndarray, modes, modal, ok) -> tuple[np.ndarray, np.ndarray]:
    """Per set, its pack flag (FALLBACK_REASONS) and whether its stuck mode is at a resonance."""
    P = v.shape[0]
    x_st = v[:, C_XST]
    flags = np.zeros(P, np.int64)
    for mode_modal, mode_ok in zip(modal, ok):
        flags[~mode_ok] = _PACK_ERROR
        flags[(flags == 0) & ~mode_modal] = _PACK_EXPM
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
    return flags, stuck_res


def _functionals_many(v: np.ndarray, D: np.ndarray, modes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """fc, fk, fg of a stack of sets: the gap (eq. 20) on the free mode, the contact force and
    minus it on the stuck mode."""
    P = v.shape[0]
    omega1, m2, c1, c2, k1, P0, Delta0, T, mred = D.T
    m = v[:, C_M1] + m2
    z = np.zeros(P)
    cg = np.broadcast_to(np.array([1.0, -1.0, 0.0, 0.0]), (P, 4))
    cf = np.stack([m2 * c1 / m, m2 * k1 / m], -1)
    fc = np.zeros((P, 3, 8, 6))
    fk = np.zeros((P, 3, 6))
    fg = np.zeros((P, 3, 5), complex)
    specs = ((0, cg, Delta0, z), (1, cf, -c2 * Delta0, -m2 * P0 / m), (1, -cf, -(-c2 * Delta0), -(-m2 * P0 / m)))
    for f, (mi, c, g0, d_s) in enumerate(specs):
        stacked_functional(f, c, g0, d_s, modes[mi], fc, fk, fg)
    return fc, fk, fg


def _scalars_many(v: np.ndarray, D: np.ndarray, tol: Tolerances, stuck_res: np.ndarray) -> np.ndarray:
    """The scalars s (P, N_SCALARS) of a stack of sets (the slots of layout's ``S_*``)."""
    P = v.shape[0]
    omega1, m2, c1, c2, k1, P0, Delta0, T, mred = D.T
    omega, x_st, R = v[:, C_OMEGA], v[:, C_XST], v[:, C_R]
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
    return s


@njit(cache=True)
def _pack_one(v, tols, lam_f, V_f):
    """The kernels' arrays (s, cm, fm, fc, fk, fg, flag) for one parameter set (relative
    values v in PARAMETER_COLUMNS order, tolerances (gap, chatter, force)) given the free
    mode's eigen-decomposition (see _state_matrices); flag indexes FALLBACK_REASONS."""
    s, cm, fm = np.zeros(N_SCALARS), np.zeros((2, 10, 4), np.complex128), np.zeros((2, 5, 4))
    fc, fk, fg = np.zeros((3, 8, 6)), np.zeros((3, 6)), np.zeros((3, 5), np.complex128)
    N, R, omega, x_st, m1 = v[C_N], v[C_R], v[C_OMEGA], v[C_XST], v[C_M1]
    Mf, bf, Wf, Ms, bs, Ws, d = _state_matrices(v)
    lam_s, V_s = stuck_eig(Ms)
    omega1, m2, c1, c2, k1, P0, Delta0, T, mred = d[0], d[1], d[2], d[3], d[4], d[5], d[6], d[7], d[8]
    omega2 = N * omega1
    m = m1 + m2
    powers_f, LiT_f = np.zeros((6, 4, 4)), np.zeros((4, 4))
    powers_s, LiT_s = np.zeros((6, 2, 2)), np.zeros((2, 2))
    modal_f, amp_f, fin_f = pack_mode(0, 4, Mf, bf, Wf, lam_f, V_f, omega, cm, fm, powers_f, LiT_f)
    modal_s, amp_s, fin_s = pack_mode(1, 2, Ms, bs, Ws, lam_s, V_s, omega, cm, fm, powers_s, LiT_s)
    cg = np.array([1.0, -1.0, 0.0, 0.0])
    cf = np.array([m2 * c1 / m, m2 * k1 / m])
    pack_functional(GAP, 4, cg, Delta0, 0.0, powers_f, LiT_f, bf, cm[0, 1], V_f, fc, fk, fg)
    pack_functional(FORCE, 2, cf, -c2 * Delta0, -m2 * P0 / m, powers_s, LiT_s, bs, cm[1, 1], V_s, fc, fk, fg)
    pack_functional(NEG_FORCE, 2, -cf, -(-c2 * Delta0), -(-m2 * P0 / m), powers_s, LiT_s, bs, cm[1, 1], V_s, fc, fk, fg)
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
def pack_single(v, tols):
    """_pack_one with the free mode's eigen-decomposition computed here (one compiled call per
    parameter set, which the kernels can share with a run); flag _PACK_ERROR where dgeev fails.
    v and tols as :func:`packing_values` gives them."""
    ok, lam_f, V_f = real_eig(_state_matrices(v)[0])
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
