"""The linear part: motion between events, exactly.

Between impacts the suppressor is a linear system with constant coefficients under
harmonic forcing (eqs. 2 and 9 of Timofeev et al. 2019). Its motion is the sum of the
periodic forced response (complex amplitudes, eqs. 10-11) and a free response, eqs. (1),
(6) and (18). This module owns that closed form; it knows nothing of gaps or impacts.

A mode of motion is written as a first-order system for the state y (shape (n,)):

    y'(t) = M y(t) + b sin(omega t),

with n = 4 while the bodies move apart (y = x1, x2, x1', x2') and n = 2 while they move as one
mass (y = x1, x1'). Its exact flow from (t0, y0) is

    y(t) = Y(t) + Phi(t - t0) (y0 - Y(t0)),   Y(t) = Im(Yhat e^{i omega t}),

where (i omega I - M) Yhat = b is eq. (10) and Phi(tau) = e^{M tau} is the free response.

The paper writes Phi in modal form (eqs. 3-6 and 19): Phi(tau) = V diag(e^{lambda_j tau}) V^-1,
with the eigenvector columns (1, A_j, lambda_j, A_j lambda_j). That form is exact and fast
for simple roots, but breaks where roots coalesce (V becomes singular). Here the modal form
is used while V is well conditioned, and the matrix exponential (scaling and squaring, which
needs no eigenvectors) otherwise, so repeated roots, zero damping and real roots are all
handled.
"""

from __future__ import annotations

import cmath
import functools
from dataclasses import dataclass

import numpy as np

from impactdamper.core.parameters import Parameters

__all__ = [
    "LinearMode",
    "characteristic_coefficients",
    "characteristic_roots",
    "mode_shape_ratios",
    "forced_amplitudes",
    "free_mode",
    "stuck_mode",
    "scaled_condition",
]

# Above this condition number of the eigenvector matrix the modal form loses more than
# ~1e4 * eps ~ 2e-12 of relative accuracy; the matrix exponential takes over. The condition is
# that of the eigenvectors in the mode's own units (scaled_condition): in (x, v) units it grew
# with the rate itself (12 at omega1 = 10, 2.4e4 at omega1 = 2e4, 1.2e10 at theta = 1e-9 for
# the same relative problem, whose scaled condition is 2.3), and points inside the native range
# left the kernels for repeated roots they did not have.
MODAL_CONDITION_LIMIT = 1.0e4


def scaled_condition(V: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """The condition number of eigenvectors ``V`` (columns (x, v), positions in the first half
    of the rows) of roots ``lam`` in the mode's own units: the velocity rows over the fastest rate
    max|lambda| and each column of unit length. It depends on the relative problem only (not on
    omega, x_st or m1), and it is large only where roots (nearly) coalesce. Stacks of shape
    (..., n, n) and (..., n) give shape (...)."""
    V = np.array(V, dtype=complex)
    n = V.shape[-1]
    with np.errstate(all="ignore"):
        rate = np.max(np.abs(lam), axis=-1)
        rate = np.where(rate > 0.0, rate, 1.0)
        V[..., n // 2 :, :] /= rate[..., None, None]
        V /= np.linalg.norm(V, axis=-2, keepdims=True)
        finite = np.all(np.isfinite(V), axis=(-2, -1))
        return np.where(finite, np.linalg.cond(np.where(finite[..., None, None], V, np.eye(n))), np.inf)


def characteristic_coefficients(p: Parameters) -> np.ndarray:
    """Coefficients (d5, d4, d3, d2, d1) of the characteristic equation (4).

    Returns
    -------
    ndarray, shape (5,)
        Highest power first, ready for :func:`numpy.roots`.
    """
    w1, w2, h1, h2, m1, m2 = p.omega1, p.omega2, p.h1, p.h2, p.m1, p.m2
    d1 = m1 * w1**2 * w2**2
    d2 = 2.0 * m1 * (w2**2 * h1 + w1**2 * h2)
    d3 = m1 * (w1**2 + 4.0 * h1 * h2) + w2**2 * (m1 + m2)
    d4 = 2.0 * (m1 * h1 + h2 * (m1 + m2))
    d5 = m1
    return np.array([d5, d4, d3, d2, d1])


def characteristic_roots(p: Parameters) -> np.ndarray:
    """Roots lambda_j of eq. (4), in 1/s, sorted by real then imaginary part. Shape (4,)."""
    roots = np.roots(characteristic_coefficients(p))
    return roots[np.lexsort((roots.imag, roots.real))]


def mode_shape_ratios(p: Parameters, roots: np.ndarray) -> np.ndarray:
    """Ratios A_j = x2s/x1s of eq. (5) for the given roots. Shape as ``roots``."""
    lam = np.asarray(roots, dtype=complex)
    return (2.0 * p.h2 * lam + p.omega2**2) / (lam**2 + 2.0 * p.h2 * lam + p.omega2**2)


def forced_amplitudes(p: Parameters) -> tuple[complex, complex]:
    """Complex amplitudes (x1p_hat, x2p_hat) of the forced response, eq. (10).

    x_ip(t) = |x_ip_hat| sin(omega t + arg x_ip_hat) for the force P0 sin(omega t), eq. (11).
    """
    w, m1, m2, c1, c2, k1, k2 = p.omega, p.m1, p.m2, p.c1, p.c2, p.k1, p.k2
    Z = np.array(
        [
            [-m1 * w**2 + 1j * w * (k1 + k2) + (c1 + c2), -1j * w * k2 - c2],
            [-1j * w * k2 - c2, -m2 * w**2 + 1j * w * k2 + c2],
        ]
    )
    x1, x2 = np.linalg.solve(Z, np.array([p.P0, 0.0], dtype=complex))
    return complex(x1), complex(x2)


@dataclass(frozen=True)
class LinearMode:
    """One linear mode of motion y' = M y + b sin(omega t), with its exact flow.

    Parameters
    ----------
    M : ndarray, shape (n, n)
        State matrix.
    b : ndarray, shape (n,)
        Forcing direction (force over mass in the velocity rows).
    omega : float
        Forcing frequency, rad/s.
    energy_weight : ndarray, shape (n, n)
        Symmetric positive definite W such that y^T W y / 2 is the mechanical energy of the
        free motion. It never increases in free motion (the damping is non-negative); the
        event search uses that to bound the free response's derivatives.

    Attributes
    ----------
    Yhat : ndarray, shape (n,), complex
        Complex amplitudes of the forced response, Y(t) = Im(Yhat e^{i omega t}) (eq. 10-11:
        for the free mode Yhat[:2] are x1p_hat, x2p_hat).
    roots : ndarray, shape (n,), complex
        Eigenvalues of M (for the free mode, the roots of eq. 4).
    modal : bool
        Whether the modal form is used (else the matrix exponential).
    forced_amplitude : float
        Largest modulus of the position entries of Yhat (m): unbounded (inf) or huge at an
        undamped or nearly undamped resonance.
    finite : bool
        M^k (k <= 5) and the energy weight's factor are finite (not so for extreme parameters).
    """

    M: np.ndarray
    b: np.ndarray
    omega: float
    energy_weight: np.ndarray

    def __post_init__(self) -> None:
        M = np.asarray(self.M, dtype=float)
        n = M.shape[0]
        lam, V = np.linalg.eig(M)
        condition = scaled_condition(V, lam)
        modal = bool(np.isfinite(condition) and condition < MODAL_CONDITION_LIMIT)
        Vinv = np.linalg.inv(V) if modal else None
        try:
            Yhat = np.linalg.solve(1j * self.omega * np.eye(n) - M, np.asarray(self.b, dtype=complex))
        except np.linalg.LinAlgError:
            # The forcing sits exactly on an undamped natural frequency: no periodic forced
            # response exists (the caller, Model, reports the resonance by name).
            Yhat = np.full(n, np.inf + 0j)
        # W = L L^T; the free response's k-th derivative c.M^k z is bounded by
        # |c M^k L^-T| sqrt(z^T W z).
        L = np.linalg.cholesky(np.asarray(self.energy_weight, dtype=float))
        object.__setattr__(self, "M", M)
        object.__setattr__(self, "roots", lam)
        # One root of each conjugate pair (and each real root), with whether it stands for a
        # pair: the terms of the event search's modal sums (events.Segment.evaluator).
        object.__setattr__(
            self, "pair_roots", tuple((j, r, r.imag > 0.0) for j, r in enumerate(lam.tolist()) if r.imag >= 0.0)
        )
        object.__setattr__(self, "modal", modal)
        object.__setattr__(self, "eigenvectors", V)
        object.__setattr__(self, "eigenvectors_inv", Vinv)
        object.__setattr__(self, "Yhat", Yhat)
        # forced()'s first product for the state itself (derivative 0), kept for
        # Segment.state's scalar path, which must give forced()'s numbers to the bit.
        object.__setattr__(self, "Yhat_state", (1j * self.omega) ** 0 * Yhat)
        object.__setattr__(self, "forced_amplitude", float(np.max(np.abs(Yhat[: n // 2]))))
        object.__setattr__(self, "L_inv_T", np.linalg.inv(L).T)
        powers = [np.eye(n)]
        with np.errstate(over="ignore", invalid="ignore"):  # (see `finite`)
            for _ in range(5):
                powers.append(powers[-1] @ M)
        object.__setattr__(self, "M_powers", powers)
        # kappa per (functional, order): functionals of one mode differ only in their offset
        # (the gap's Delta0), and kappa does not depend on it.
        object.__setattr__(self, "_bound_factors", {})
        # Whether the matrices the flow and the event search use are finite: extreme parameters
        # (delta1 = 1e300) overflow M^k, and the caller (Model) reports it by name.
        object.__setattr__(
            self, "finite", bool(all(np.all(np.isfinite(P)) for P in powers) and np.all(np.isfinite(self.L_inv_T)))
        )

    @property
    def n(self) -> int:
        return self.M.shape[0]

    # --- forced (periodic) response -------------------------------------------------
    def forced(self, t: np.ndarray | float, derivative: int = 0) -> np.ndarray:
        """Periodic forced response Y(t) (or its derivative), shape t.shape + (n,)."""
        if isinstance(t, float):  # the solver's scalar hot path, without array set-up
            return ((1j * self.omega) ** derivative * cmath.exp(1j * self.omega * t) * self.Yhat).imag
        t = np.asarray(t, dtype=float)
        phase = np.exp(1j * self.omega * t)[..., None]
        return np.imag((1j * self.omega) ** derivative * self.Yhat * phase)

    # --- free response --------------------------------------------------------------
    def propagator(self, tau: np.ndarray | float) -> np.ndarray:
        """Phi(tau) = e^{M tau}, shape tau.shape + (n, n)."""
        tau = np.asarray(tau, dtype=float)
        if self.modal:
            V, Vinv = self.eigenvectors, self.eigenvectors_inv
            e = np.exp(self.roots * tau[..., None])
            return np.real(np.einsum("ij,...j,jk->...ik", V, e, Vinv))
        import scipy.linalg  # (loaded on first use: the package import stays light)

        return scipy.linalg.expm(self.M * tau[..., None, None])

    def free(self, tau: np.ndarray | float, z0: np.ndarray) -> np.ndarray:
        """Free response z(tau) = Phi(tau) z0, shape tau.shape + (n,)."""
        tau = np.asarray(tau, dtype=float)
        if self.modal:
            return self.free_modal(tau, self.eigenvectors_inv @ z0)  # the paper's alpha_j (eq. 19)
        return np.einsum("...ij,j->...i", self.propagator(tau), z0)

    def free_modal(self, tau: np.ndarray | float, alpha: np.ndarray) -> np.ndarray:
        """Free response Re V (alpha e^{lambda tau}) from the modal coefficients alpha_j of
        eq. (19), shape tau.shape + (n,) (a modal mode only)."""
        e = np.exp(self.roots * np.asarray(tau, dtype=float)[..., None]) * alpha
        return np.real(e @ self.eigenvectors.T)

    def state_modal(self, t: np.ndarray | float, t0: float, alpha: np.ndarray) -> np.ndarray:
        """:meth:`state` from the modal coefficients alpha_j of eq. (19) at t0 (a modal mode
        only), shape t.shape + (n,): a segment's state, its alpha_j computed once."""
        if type(t) is float:  # the event loop's scalar hot path: forced() and free_modal() below,
            # operation for operation (numpy's complex products, which may fuse a multiply-add,
            # in the same operand order; cmath's exponential of an imaginary number is numpy's),
            # without their array set-up; tests/unit/test_fast_paths.py holds the two to the bit
            e = np.exp(self.roots * (t - t0)) * alpha
            return (self.Yhat_state * cmath.exp(1j * self.omega * t)).imag + (e @ self.eigenvectors.T).real
        t = np.asarray(t, dtype=float)
        return self.forced(t) + self.free_modal(t - t0, alpha)

    # --- the exact flow -------------------------------------------------------------
    def state(self, t: np.ndarray | float, t0: float, y0: np.ndarray) -> np.ndarray:
        """Exact state at time(s) t from state y0 at t0, shape t.shape + (n,)."""
        z0 = np.asarray(y0, dtype=float) - self.forced(t0)
        t = np.asarray(t, dtype=float)
        return self.forced(t) + self.free(t - t0, z0)

    def states_from(self, t: np.ndarray, t0: np.ndarray, y0: np.ndarray) -> np.ndarray:
        """Exact states at times t[i] from states y0[i] at t0[i] (shapes (m,), (m,), (m, n)),
        shape (m, n): :meth:`state` for many starts at once (the shooting's flights)."""
        t, t0 = np.asarray(t, dtype=float), np.asarray(t0, dtype=float)
        z0 = np.asarray(y0, dtype=float) - self.forced(t0)
        tau = t - t0
        if self.modal:
            e = np.exp(self.roots * tau[:, None]) * (z0 @ self.eigenvectors_inv.T)  # alpha_j e^{lambda_j tau}
            return self.forced(t) + np.real(e @ self.eigenvectors.T)
        return self.forced(t) + np.einsum("mij,mj->mi", self.propagator(tau), z0)

    def rhs(self, t: np.ndarray | float, y: np.ndarray) -> np.ndarray:
        """y' = M y + b sin(omega t) for states y of shape (..., n)."""
        t = np.asarray(t, dtype=float)
        return y @ self.M.T + np.sin(self.omega * t)[..., None] * self.b

    def energy(self, z: np.ndarray) -> np.ndarray:
        """z^T W z (twice the mechanical energy of a free-response state), shape z.shape[:-1]."""
        return np.einsum("...i,ij,...j->...", z, self.energy_weight, z)

    def derivative_bound_factor(self, c: np.ndarray, order: int) -> float:
        """kappa with |d^order/dt^order (c . z)| <= kappa sqrt(z^T W z) for free motion (inf if
        it overflows, at extreme scales: the event search then refuses to step)."""
        c = np.asarray(c, dtype=float)
        key = (c.tobytes(), order)
        kappa = self._bound_factors.get(key)
        if kappa is None:
            with np.errstate(over="ignore"):
                kappa = float(np.linalg.norm(c @ self.M_powers[order] @ self.L_inv_T))
            self._bound_factors[key] = kappa
        return kappa


# Modes are built once per distinct set of the values they depend on (neither Delta0 nor R):
# a scan of the gap (Algorithm No. 1 along a map row, a sweep of Delta0/x_st) builds the same
# two modes at every point, and building them (eigenvectors, energy factors) cost half of
# Algorithm No. 1. A LinearMode is never changed after __post_init__, so sharing it is safe.
MODE_CACHE_SIZE = 256


def _clear_mode_cache() -> None:
    """Forget the built modes (after changing this module's constants, as the tests do)."""
    _free_mode.cache_clear()
    _stuck_mode.cache_clear()


def free_mode(p: Parameters) -> LinearMode:
    """The bodies apart: eqs. (2) and (9), state (x1, x2, x1', x2')."""
    return _free_mode(p.m1, p.m2, p.c1, p.c2, p.k1, p.k2, p.P0, p.omega)


@functools.lru_cache(maxsize=MODE_CACHE_SIZE)
def _free_mode(m1: float, m2: float, c1: float, c2: float, k1: float, k2: float, P0: float, omega: float) -> LinearMode:
    mass = np.diag([m1, m2])
    K = np.array([[c1 + c2, -c2], [-c2, c2]])
    C = np.array([[k1 + k2, -k2], [-k2, k2]])
    Minv = np.diag([1.0 / m1, 1.0 / m2])
    M = np.block([[np.zeros((2, 2)), np.eye(2)], [-Minv @ K, -Minv @ C]])
    b = np.array([0.0, 0.0, P0 / m1, 0.0])
    W = np.block([[K, np.zeros((2, 2))], [np.zeros((2, 2)), mass]])
    return LinearMode(M, b, omega, W)


def stuck_mode(p: Parameters) -> LinearMode:
    """The bodies in contact, moving as one mass m1 + m2 on c1, k1: state (x1, x1').

    The suppressor then sits at x2 = x1 + Delta0; the spring c2 and damper k2 act between the
    two bodies only, so they drop out of the motion and reappear in the contact force.
    """
    return _stuck_mode(p.m1 + p.m2, p.c1, p.k1, p.P0, p.omega)


@functools.lru_cache(maxsize=MODE_CACHE_SIZE)
def _stuck_mode(m: float, c1: float, k1: float, P0: float, omega: float) -> LinearMode:
    M = np.array([[0.0, 1.0], [-c1 / m, -k1 / m]])
    b = np.array([0.0, P0 / m])
    W = np.diag([c1, m])
    return LinearMode(M, b, omega, W)
