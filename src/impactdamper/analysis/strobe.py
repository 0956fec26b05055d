"""The stroboscopic map of the event-driven motion, its Jacobian and Newton's method on it.

The forcing P0 sin(omega t) of Timofeev et al. (2019), eq. (1), is T-periodic, so the state
y = (x1, x2, x1', x2') sampled at the sections t_n = t0 + n T obeys a map y_n -> y_{n+1}
that does not depend on n: the stroboscopic (Poincare) map. A cycle of period T_c = k T is a
fixed point of its k-th iterate, and the eigenvalues of that iterate's Jacobian at the fixed
point are the cycle's Floquet multipliers. The map is evaluated here with the event-driven
solver (Algorithm No. 2 of the paper, eqs. (18)-(22): exact flow, impacts and contact
modes), so it covers every motion, chatter included.

This module holds (sections compared in the units of
:func:`~impactdamper.core.parameters.state_scale`, x_st and x_st omega)

* :func:`stroboscopic_step` and :func:`stroboscopic_map`, the k-th iterate;
* :func:`stroboscopic_jacobian`, its central finite-difference Jacobian (the independent
  check of the saltation-matrix multipliers of :mod:`impactdamper.analysis.cycle`);
* :func:`section_coordinates` / :func:`section_state`, Newton's unknowns on a section;
* :func:`strobe_newton`, Newton's method for a fixed point of the k-th iterate with a
  Broyden-updated finite-difference Jacobian (the sweeps' accelerator for cycles the impact
  shooting does not cover).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactdamper.core.model import STUCK
from impactdamper.core.parameters import Parameters, state_scale
from impactdamper.core.simulate import EventDrivenSolver, Tolerances

__all__ = [
    "stroboscopic_step",
    "stroboscopic_jacobian",
    "strobe_newton",
    "CHECK_FD_STEP",
    "STROBE_FD_STEP",
    "STROBE_TOL",
    "STROBE_MAX_ITERATIONS",
    "FRESH_JACOBIAN_ABOVE",
]

# Relative step of the central-difference check (stroboscopic_jacobian): with central
# differences the truncation error is ~step^2 = 1e-12 and the rounding error ~1e-14/step =
# 1e-8 relative, which is what the check of the saltation-matrix multipliers needs.
CHECK_FD_STEP = 1e-6
# Finite-difference step of the Newton Jacobian, relative (x_st, x_st omega): the map is
# evaluated to ~1e-14, so the derivative error is ~1e-7 (rounding) plus the curvature term.
STROBE_FD_STEP = 1e-7
# Newton on the stroboscopic map stops at this relative residual.
STROBE_TOL = 1e-10
# Iterations allowed (Broyden converges superlinearly from a neighbour's fixed point: 2-4).
STROBE_MAX_ITERATIONS = 8
# Above this multiplier modulus the stability verdict of the stroboscopic Newton is taken
# from a freshly differenced Jacobian, not from the Broyden-updated one.
FRESH_JACOBIAN_ABOVE = 0.9


def stroboscopic_step(
    p: Parameters, t0: float, state: np.ndarray, periods: int, tolerances: Tolerances | None = None
) -> tuple[np.ndarray, str]:
    """The state and contact mode at t0 + periods T from ``state`` at t0 (Algorithm No. 2).

    Parameters
    ----------
    p : Parameters
    t0 : float
        Section time, s.
    state : ndarray, shape (4,)
        (x1, x2, x1', x2') at t0.
    periods : int
        k, the iterate of the map.
    tolerances : Tolerances, optional
        Event-solver tolerances.

    Returns
    -------
    state : ndarray, shape (4,)
        (x1, x2, x1', x2') at t0 + k T.
    mode : str
        ``free`` or ``stuck`` there.
    """
    solver = EventDrivenSolver(p, t0=t0, state=state, tolerances=tolerances)
    solver.advance(t0 + periods * p.T)
    return solver.state_at(t0 + periods * p.T), solver.mode


def _stroboscopic_map(
    p: Parameters, t0: float, state: np.ndarray, periods: int, tolerances: Tolerances | None = None
) -> np.ndarray:
    """State at t0 + periods T from ``state`` at t0, by the event-driven solver. Shape (4,)."""
    return stroboscopic_step(p, t0, state, periods, tolerances)[0]


def stroboscopic_jacobian(
    p: Parameters,
    t0: float,
    state: np.ndarray,
    periods: int,
    rel_step: float = CHECK_FD_STEP,
    tolerances: Tolerances | None = None,
) -> np.ndarray:
    """Central finite-difference Jacobian of :func:`stroboscopic_map`, shape (4, 4).

    Steps are ``rel_step`` times x_st (positions) and x_st omega (velocities). The section t0
    must lie inside a free flight, away from impacts. At a fixed point its eigenvalues are
    the cycle's Floquet multipliers (the monodromy matrix seen from the section).
    """
    D = state_scale(p)
    J = np.empty((4, 4))
    for j in range(4):
        h = rel_step * D[j]
        plus, minus = np.array(state, float), np.array(state, float)
        plus[j] += h
        minus[j] -= h
        J[:, j] = (
            _stroboscopic_map(p, t0, plus, periods, tolerances) - _stroboscopic_map(p, t0, minus, periods, tolerances)
        ) / (2 * h)
    return J


def _section_coordinates(p: Parameters, full: np.ndarray, stuck: bool) -> np.ndarray:
    """Newton's unknowns at a section: (x1, v1) on the stop, else (x1, x2 - x1 - Delta0, x1',
    x2' - x1'), all relative (x_st, x_st omega). Shape (2,) or (4,).

    The second free coordinate is minus the gap Delta = Delta0 - (x2 - x1) of eq. (20), so
    that the stop is the coordinate plane ``u[1] = 0``."""
    xs, vs = p.x_st, p.x_st * p.omega
    if stuck:
        return np.array([full[0] / xs, full[2] / vs])
    return np.array([full[0] / xs, (full[1] - full[0] - p.Delta0) / xs, full[2] / vs, (full[3] - full[2]) / vs])


def _section_state(p: Parameters, u: np.ndarray, stuck: bool) -> np.ndarray:
    """The state (x1, x2, x1', x2') of section coordinates ``u`` (inverse of
    :func:`section_coordinates`; a free state's gap is clipped to be non-negative). Shape (4,)."""
    xs, vs = p.x_st, p.x_st * p.omega
    if stuck:
        x1, v1 = u[0] * xs, u[1] * vs
        return np.array([x1, x1 + p.Delta0, v1, v1])
    x1, r, v1, dv = u[0] * xs, min(u[1], 0.0) * xs, u[2] * vs, u[3] * vs  # gap >= 0
    return np.array([x1, x1 + p.Delta0 + r, v1, v1 + dv])


@dataclass(frozen=True)
class _StrobeSolution:
    """A fixed point of the k-th stroboscopic map found by :func:`strobe_newton`.

    Attributes
    ----------
    state : ndarray, shape (4,)
        (x1, x2, x1', x2') at the section t = 0.
    spectral_radius : float
        Largest modulus of the Jacobian's eigenvalues (the Floquet multipliers).
    periods : int
        Forcing periods simulated by the iteration (all map evaluations together).
    jacobian : ndarray, shape (n, n)
        The Jacobian in section coordinates (n = 2 on the stop, 4 free), reusable as the
        starting Jacobian of a neighbouring parameter's iteration.
    """

    state: np.ndarray
    spectral_radius: float
    periods: int
    jacobian: np.ndarray


def _map_step(p: Parameters, tol: Tolerances, step):
    """(state, k) -> the state and mode k periods on from ``state`` at t = 0: ``step(state, k)``
    (another backend, made for ``p`` and ``tol`` by the caller) where it applies (not None),
    else the pure-Python solver."""

    def evaluate(state, k):
        result = step(state, k) if step is not None else None
        return result if result is not None else stroboscopic_step(p, 0.0, state, k, tol)

    return evaluate


def strobe_newton(
    p: Parameters, full0: np.ndarray, mode0: str, k: int, tol: Tolerances, jacobian: np.ndarray | None = None, step=None
) -> _StrobeSolution | None:
    """Newton on y(0) -> y(k T) from ``full0``.

    The Jacobian is ``jacobian`` (the neighbour's, if it has the right shape) or finite
    differences, updated by Broyden's rank-one formula between iterations and recomputed by
    finite differences if the iteration stalls or the orbit comes near a bifurcation
    (multiplier modulus above ``FRESH_JACOBIAN_ABOVE``), so that the stability verdict there
    rests on a fresh Jacobian.

    Parameters
    ----------
    p : Parameters
    full0 : ndarray, shape (4,)
        Starting state (x1, x2, x1', x2') at t = 0.
    mode0 : str
        ``stuck`` to iterate on the stop (2 unknowns), else free (4 unknowns).
    k : int
        Period multiple of the sought cycle.
    tol : Tolerances
        Event-solver tolerances.
    jacobian : ndarray, optional
        Starting Jacobian in section coordinates.
    step : callable, optional
        ``step(state, k)`` -> (state, mode) at t = k T from ``state`` at t = 0, or None where
        it does not apply: each map evaluation by a backend made for ``p`` and ``tol``
        (:meth:`impactdamper.core.backends.Backend.map_step`); where it returns None, and
        without it, the pure-Python solver.

    Returns
    -------
    StrobeSolution or None
        None if the iteration failed (no convergence in ``STROBE_MAX_ITERATIONS``, a non-finite
        residual, a singular system or a solver guard).
    """
    stuck = mode0 == STUCK
    u = _section_coordinates(p, full0, stuck)
    strobe = _SectionMap(p, stuck, k, _map_step(p, tol, step))
    n = len(u)
    fresh = jacobian is None or jacobian.shape != (n, n)
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            Pu = strobe(u)
            J = strobe.jacobian(u, Pu) if fresh else np.array(jacobian, float)
            fixed_point = _broyden_newton(strobe, u, Pu, J, fresh)
            if fixed_point is None:
                return None
            u, Pu, J, fresh = fixed_point
            J, rho = _stability(strobe, u, Pu, J, fresh)
    except (RuntimeError, ValueError, np.linalg.LinAlgError):
        return None
    return _StrobeSolution(_section_state(p, u, stuck), rho, strobe.periods, J)


class _SectionMap:
    """The k-th stroboscopic map in section coordinates, counting the periods it simulates.

    ``evaluate(state, k)`` is the map on full states (:func:`_map_step`); a free section's
    gap coordinate ``u[1]`` is stepped only to open the gap, never to close it."""

    def __init__(self, p: Parameters, stuck: bool, k: int, evaluate):
        self.p, self.stuck, self.k, self.evaluate = p, stuck, k, evaluate
        self.periods = 0

    def __call__(self, v: np.ndarray) -> np.ndarray:
        self.periods += self.k
        return _section_coordinates(self.p, self.evaluate(_section_state(self.p, v, self.stuck), self.k)[0], self.stuck)

    def jacobian(self, v: np.ndarray, Pv: np.ndarray) -> np.ndarray:
        """Forward finite-difference Jacobian at ``v`` (``Pv`` the map there), shape (n, n)."""
        n = len(v)
        J = np.empty((n, n))
        for j in range(n):
            # Open the gap, never close it.
            h = -STROBE_FD_STEP if (not self.stuck and j == 1) else STROBE_FD_STEP
            w = v.copy()
            w[j] += h
            J[:, j] = (self(w) - Pv) / h
        return J


def _broyden_newton(strobe: _SectionMap, u: np.ndarray, Pu: np.ndarray, J: np.ndarray, fresh: bool):
    """Newton's iteration on u = P(u) with Broyden's rank-one update of ``J``.

    A stalled iteration (the residual falling by less than half) gets a freshly differenced
    Jacobian. Returns (u, P(u), J, fresh) at the fixed point, or None if the residual is not
    finite or ``STROBE_MAX_ITERATIONS`` do not reach ``STROBE_TOL``."""
    n = len(u)
    r = Pu - u
    previous_norm = math.inf
    for _ in range(STROBE_MAX_ITERATIONS):
        norm = float(np.max(np.abs(r)))
        if not math.isfinite(norm):
            return None
        if norm < STROBE_TOL:
            return u, Pu, J, fresh
        if norm > 0.5 * previous_norm and norm > 100 * STROBE_TOL and not fresh:
            J, fresh = strobe.jacobian(u, Pu), True  # stalled: a fresh Jacobian
        du = np.linalg.solve(J - np.eye(n), -r)
        u_new = u + du
        if not strobe.stuck:
            u_new[1] = min(u_new[1], 0.0)
        Pu_new = strobe(u_new)
        r_new = Pu_new - u_new
        s, y = u_new - u, (Pu_new - Pu)
        if float(s @ s) > 0.0:
            J = J + np.outer(y - J @ s, s) / float(s @ s)  # Broyden: J s = y
            fresh = False
        u, Pu, r, previous_norm = u_new, Pu_new, r_new, norm
    return None


def _stability(strobe: _SectionMap, u: np.ndarray, Pu: np.ndarray, J: np.ndarray, fresh: bool):
    """The Jacobian behind the stability verdict and its spectral radius: near a bifurcation
    (modulus above ``FRESH_JACOBIAN_ABOVE``) a Broyden-updated Jacobian is replaced by a
    freshly differenced one."""
    rho = float(np.max(np.abs(np.linalg.eigvals(J))))
    if not fresh and rho > FRESH_JACOBIAN_ABOVE:
        J = strobe.jacobian(u, Pu)
        rho = float(np.max(np.abs(np.linalg.eigvals(J))))
    return J, rho
