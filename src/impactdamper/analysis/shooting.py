"""The shooting equations of a periodic impacting cycle, their Newton solve and stability.

A cycle of period T_c = k T with z impacts of the two-mass system of Timofeev et al. (2019) is
the solution of 5 z equations in 5 z unknowns, built from the exact flow between impacts
(eq. 18, :mod:`impactdamper.core.linear`) and the impact law of eqs. (21)-(22). This module
owns those equations (:class:`Shooting`, with exact Jacobian and damped Newton) and the
saltation and monodromy matrices that give the cycle's Floquet multipliers; the impact map and
pulse are the impact law's (:mod:`impactdamper.core.impact_law`). :mod:`impactdamper.analysis.orbits` (one cycle from a seed) and
:mod:`impactdamper.analysis.continuation` (branches of cycles) both solve these equations, and
:mod:`impactdamper.analysis.cycle` checks a solution.

Unknowns and equations (multiple shooting on the impact-to-impact map)
------------------------------------------------------------------------
The unknowns are the impact times and the states just after each impact,

    u = (t_1/T, ..., t_z/T, y_1^+/D, ..., y_z^+/D),    D = diag(x_st, x_st, x_st w, x_st w),

(5 z numbers; w = omega). Flight i is the exact free motion from (t_i, y_i^+) to t_{i+1}
(t_{z+1} = t_1 + k T), ending in the state y_i^-. The equations are, for each flight,

    Delta(y_i^-) / x_st = 0                     (the flight ends on the stop, eq. 20)
    (J_R y_i^- - y_{i+1}^+) / D = 0             (the impact law, eqs. 21-22; y_{z+1}^+ = y_1^+),

with J_R the impact map (linear: the pulse is proportional to the closing velocity). The
forcing is T-periodic, so closing the cycle after k T is periodicity. The Jacobian is exact:
d y_i^-/d y_i^+ = e^{M tau_i}, d y_i^-/d t_i = -e^{M tau_i} f(t_i, y_i^+),
d y_i^-/d t_{i+1} = f(t_{i+1}, y_i^-), with f the vector field of the free mode. Newton
stops when the step is below ``ORBIT_TOL`` (phases in units of T, states relative to D) and
the residual is below ``ORBIT_TOL`` too.

Stability
---------
The Floquet multipliers are the eigenvalues of the monodromy matrix

    M_c = S_1 e^{M tau_z} S_z ... S_2 e^{M tau_1},

with the saltation matrix of each impact,

    S = J_R + (f^+ - J_R f^-) n^T / (n^T f^-),     n = grad Delta = (1, -1, 0, 0),

which corrects the impact map's Jacobian for the perturbed impact time (Leine & Nijmeijer 2004;
Di Bernardo et al. 2008, ch. 2). The orbit is stable when every multiplier has modulus < 1.
:func:`impactdamper.analysis.strobe.stroboscopic_jacobian` is the independent check: the
finite-difference Jacobian of the map y(t_s) -> y(t_s + k T) computed with the event-driven
solver.
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper.core.impact_law import impact_matrix
from impactdamper.core.model import Model
from impactdamper.core.parameters import Parameters
from impactdamper.core.parameters import state_scale

__all__ = [
    "Shooting",
    "OrbitError",
    "monodromy_matrix",
    "ORBIT_TOL",
]

# Newton's convergence threshold on the step and the residual, relative (phases in units of
# T, positions to x_st, velocities to x_st omega): rounding of the exact flow is ~1e-15
# relative, so 1e-12 is reached with room.
ORBIT_TOL = 1e-12
# Newton iterations allowed from a seed (quadratic convergence needs 3-6 from a settled cycle).
NEWTON_MAX_ITERATIONS = 40
# At a fold the Jacobian is singular and the orbit is determined only to ~sqrt(rounding) along
# its null direction: with the residual at ORBIT_TOL, Newton steps that stall below this after
# this many iterations are accepted.
NEWTON_STALL, NEWTON_STALL_STEP = 6, 1e-7


class OrbitError(ValueError):
    """The direct solve failed (Newton did not converge) or does not apply."""


class Shooting:
    """The 5 z shooting equations of a cycle with z impacts in k T, with exact Jacobian.

    The unknowns u = (t_i/T, y_i^+/D) and the equations (the gap of eq. 20 at each flight's end,
    the impact law of eqs. 21-22 between flights) are those of the module docstring; the flight
    between impacts is the exact free motion of eq. (18).

    Parameters
    ----------
    p : Parameters
    k : int
        Period multiple, T_c = k T.
    z : int
        Impacts per cycle.
    model : Model, optional
        ``Model(p)``, if already built.
    """

    def __init__(self, p: Parameters, k: int, z: int, model: Model | None = None):
        self.p, self.k, self.z = p, int(k), int(z)
        self.model = model or Model(p)
        self.mode = self.model.free
        self.T = p.T
        self.D = state_scale(p)
        self.n = np.array([1.0, -1.0, 0.0, 0.0])
        self.JR = impact_matrix(p)

    def times_states(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Absolute impact times (shape (z,), s) and states after them (shape (z, 4)) of u."""
        z = self.z
        return u[:z] * self.T, u[z:].reshape(z, 4) * self.D

    def pack(self, times: np.ndarray, states: np.ndarray) -> np.ndarray:
        """The unknowns u, shape (5 z,), of impact times and states after them (inverse of
        :meth:`times_states`)."""
        return np.concatenate([np.asarray(times, float) / self.T, (np.asarray(states, float) / self.D).ravel()])

    def flights(self, u: np.ndarray):
        """Start times, durations, states after and before the impacts ending each flight."""
        t, y = self.times_states(u)
        t_next = np.append(t[1:], t[0] + self.k * self.T)
        tau = t_next - t
        before = self.mode.states_from(t_next, t, y)
        return t, tau, y, before, t_next

    def residual(self, u: np.ndarray, jacobian: bool = True):
        """Shooting residual F (shape (5 z,)) and its Jacobian (shape (5 z, 5 z)) at u."""
        try:
            with np.errstate(over="raise", invalid="raise"):
                return self._residual(u, jacobian)
        except FloatingPointError:
            raise OrbitError("the shooting equations overflow at this guess") from None

    def _residual(self, u: np.ndarray, jacobian: bool):
        z, T, D, mode = self.z, self.T, self.D, self.mode
        if not np.all(np.isfinite(u)):
            raise OrbitError("non-finite guess")
        t, tau, y, before, t_next = self.flights(u)
        if np.any(tau <= 0.0):
            raise OrbitError("impact times out of order (a flight of non-positive duration)")
        F = np.empty(5 * z)
        F[:z] = self.model.gap_of(before) / self.p.x_st
        after_next = before @ self.JR.T
        F[z:] = ((after_next - np.roll(y, -1, axis=0)) / D).ravel()
        if not jacobian:
            return F, None
        J = np.zeros((5 * z, 5 * z))
        Phis, f_starts, f_ends = mode.propagator(tau), mode.rhs(t, y), mode.rhs(t_next, before)  # (all flights)
        # d before_i / d u for every flight i at once (j = i + 1, cyclically): columns of phase i,
        # phase j and state i. Added with np.add.at, which sums repeated indices (z = 1: i = j).
        i = np.arange(z)
        j = (i + 1) % z
        d_phase_i = -np.einsum("mrc,mc->mr", Phis, f_starts) * T
        d_phase_j = f_ends * T
        d_state_i = Phis * D[None, None, :]
        rows_state = z + 4 * i[:, None] + np.arange(4)[None, :]  # (z, 4)
        cols_state_i = rows_state  # state i's unknowns sit in the same positions as its rows
        cols_state_j = z + 4 * j[:, None] + np.arange(4)[None, :]
        for d_before, cols in ((d_phase_i, i), (d_phase_j, j)):
            np.add.at(J, (i, cols), d_before @ self.n / self.p.x_st)
            np.add.at(J, (rows_state, cols[:, None]), (d_before @ self.JR.T) / D)
        J[i[:, None], cols_state_i] += np.einsum("r,mrc->mc", self.n, d_state_i) / self.p.x_st
        J[rows_state[:, :, None], cols_state_i[:, None, :]] += (
            np.einsum("ar,mrc->mac", self.JR, d_state_i) / D[None, :, None]
        )
        J[rows_state[:, :, None], cols_state_j[:, None, :]] -= np.eye(4)
        return F, J

    def newton(self, u: np.ndarray, max_iterations: int = NEWTON_MAX_ITERATIONS) -> tuple[np.ndarray, int, float]:
        """Damped Newton on the shooting equations from the guess ``u``.

        The step is halved (down to 1e-3) until the residual's max norm falls; the iteration
        stops when the residual and the step are below ``ORBIT_TOL`` (or, at a fold, the step
        stalls below ``NEWTON_STALL_STEP`` after ``NEWTON_STALL`` iterations).

        Returns
        -------
        u : ndarray, shape (5 z,)
            The solution (see :meth:`pack`).
        iterations : int
        residual : float
            Max norm of the final residual.

        Raises
        ------
        OrbitError
            Singular Jacobian, impact times out of order, or no convergence.
        """
        F, J = self.residual(u)
        norm = float(np.max(np.abs(F)))
        for it in range(1, max_iterations + 1):
            try:
                du = np.linalg.solve(J, -F)
            except np.linalg.LinAlgError as err:
                raise OrbitError(f"singular shooting Jacobian ({err})") from None
            lam = 1.0
            while True:
                u_new = u + lam * du
                try:
                    F_new, J_new = self.residual(u_new)
                    norm_new = float(np.max(np.abs(F_new)))
                except OrbitError:
                    norm_new = math.inf
                if norm_new < norm or norm_new <= ORBIT_TOL or lam < 1e-3:
                    break
                lam *= 0.5
            if not math.isfinite(norm_new):
                raise OrbitError("Newton left the region where the impact times are ordered")
            step = float(np.max(np.abs(lam * du)))
            u, F, J, norm = u_new, F_new, J_new, norm_new
            if norm <= ORBIT_TOL and (step <= ORBIT_TOL or (it >= NEWTON_STALL and step <= NEWTON_STALL_STEP)):
                return u, it, norm
        raise OrbitError(f"Newton did not converge in {max_iterations} iterations (residual {norm:.3g})")


def _saltation_matrix(model: Model, t: float, before: np.ndarray) -> np.ndarray:
    """Saltation matrix S = J_R + (f^+ - J_R f^-) n^T / (n^T f^-) of the impact at (t, before),
    shape (4, 4) (see the module docstring)."""
    JR = impact_matrix(model.p)
    n = np.array([1.0, -1.0, 0.0, 0.0])
    f_minus = model.free.rhs(t, before)
    f_plus = model.free.rhs(t, JR @ before)
    return JR + np.outer(f_plus - JR @ f_minus, n) / (n @ f_minus)


def monodromy_matrix(
    model: Model, times: np.ndarray, before: np.ndarray, Tc: float, t_section: float | None = None
) -> np.ndarray:
    """Monodromy matrix M_c of a cycle: the product of exact flows and saltation matrices
    around it from the section ``t_section`` (default: just after the first impact).

    Parameters
    ----------
    model : Model
    times : ndarray, shape (z,)
        Impact times, s, in cycle order.
    before : ndarray, shape (z, 4)
        States just before each impact (for the saltation matrices; the flows between are linear).
    Tc : float
        Cycle duration k T, s.
    t_section : float, optional
        Absolute section time, s (not an impact time).

    Returns
    -------
    ndarray, shape (4, 4)
    """
    z = len(times)
    t_next = np.append(times[1:], times[0] + Tc)
    mode = model.free
    if t_section is None:
        start, ts = 0, times[0]
    else:
        s = times[0] + (t_section - times[0]) % Tc
        start = int(np.searchsorted(times, s, side="right") - 1)
        ts = s
    # From the section (inside flight `start`) to the end of that flight, then around.
    M = mode.propagator(t_next[start] - ts)
    for m in range(1, z + 1):
        i = (start + m) % z
        M = _saltation_matrix(model, times[i], before[i]) @ M  # impact i (times mod T_c)
        if m == z:
            break
        M = mode.propagator(t_next[i] - times[i]) @ M
    # Back in flight `start` (one cycle later): from its impact to the section.
    M = mode.propagator(ts - times[start]) @ M
    return M
