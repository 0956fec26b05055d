"""Event location: the first root of a gap-like function, never missing one.

Every event of the model is the first root of a function that is linear in the state of the
current mode plus a sinusoid of the forcing (eq. 20 for the gap; the contact force for
lift-off):

    g(t) = g0 + Im(G e^{i omega t}) + c . z(t - t0),      z(tau) = Phi(tau) z0,

where z is the free response of the mode. Its derivatives are exact in closed form, and
they are bounded: the free motion's mechanical energy z^T W z / 2 never grows (damping is
non-negative), so for t >= a

    |g^(k)(t)| <= K_k(a) = |G| omega^k + |c M^k L^-T| sqrt(z(a)^T W z(a)).

How no root is missed
---------------------
From a point a with g(a) > 0, Taylor's theorem gives the lower bound
g(a + s) >= g(a) + g'(a) s - K_2(a) s^2 / 2, which stays positive up to its positive root s*.
So (a, a + s*) holds no root, and the search steps there: each step is certified. The step
shrinks near a root (converging quadratically to a transversal root, from the left, so the
root found is the first one) and near a close approach (a grazing contact, found as the gap
falling below ``tol`` with a non-positive slope). A near miss whose minimum stays above
``tol`` is stepped over in a bounded number of steps and is not counted. Leaving a contact
(g = 0 exactly), the caller gives the order m of the first non-zero Taylor coefficient g_m
(1 after an impact, 2 for a plastic separation, 3 at lift-off), and the first step is the
certified s* = (m + 1) g_m / K_{m+1}.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import numpy as np

from .linear import LinearMode

__all__ = ["LinearFunctional", "Segment", "first_root", "SearchLimitError"]

# Newton polishing after the certified march: the march already converges quadratically,
# so a few iterations reach rounding level.
NEWTON_ITERATIONS = 4
# No search may take more certified steps than this (a guard; typical searches take 5-50).
MAX_STEPS = 200_000


class SearchLimitError(RuntimeError):
    """The event search exceeded its step budget (never expected; a guard against loops)."""


@dataclass(frozen=True)
class LinearFunctional:
    """g(t, y) = g0 + d_s sin(omega t) + c . y, a function of one mode's state.

    Parameters
    ----------
    mode : LinearMode
        The mode whose state y the functional reads.
    c : ndarray, shape (n,)
        Weights of the state.
    g0 : float
        Constant part.
    d_s : float
        Weight of the forcing sin(omega t) (the contact force feels the force directly).
    """

    mode: LinearMode
    c: np.ndarray
    g0: float
    d_s: float = 0.0

    def __post_init__(self) -> None:
        c = np.asarray(self.c, dtype=float)
        object.__setattr__(self, "c", c)
        # Complex amplitude of the periodic part: Im(G e^{i w t}) = c.Y(t) + d_s sin(w t).
        object.__setattr__(self, "G", complex(c @ self.mode.Yhat + self.d_s))
        object.__setattr__(self, "cM", [c @ P for P in self.mode.M_powers])
        object.__setattr__(
            self, "kappa", [self.mode.derivative_bound_factor(c, k) for k in range(len(self.mode.M_powers))]
        )

    def of_state(self, t: np.ndarray | float, y: np.ndarray, derivative: int = 0) -> np.ndarray:
        """g^(derivative)(t) from full states y (shape (..., n)), using y' = M y + b sin."""
        t = np.asarray(t, dtype=float)
        w = self.mode.omega
        if derivative == 0:
            return self.g0 + self.d_s * np.sin(w * t) + y @ self.c
        # d^k/dt^k (c.y) = c M^k y + sum_j c M^(k-1-j) b d^j/dt^j sin(w t)
        value = y @ self.cM[derivative]
        for j in range(derivative):
            value = value + (self.cM[derivative - 1 - j] @ self.mode.b) * w**j * np.sin(w * t + j * math.pi / 2)
        return value + self.d_s * w**derivative * np.sin(w * t + derivative * math.pi / 2)


class Segment:
    """The exact motion of one mode from (t0, y0): the paper's eq. (18) with alpha_j of (19).

    Parameters
    ----------
    mode : LinearMode
    t0 : float
        Start time, s.
    y0 : ndarray, shape (n,)
        State at t0.
    """

    def __init__(self, mode: LinearMode, t0: float, y0: np.ndarray):
        self.mode = mode
        self.t0 = float(t0)
        self.y0 = np.asarray(y0, dtype=float)
        self.z0 = self.y0 - mode.forced(self.t0)
        self._alpha = mode.eigenvectors_inv @ self.z0 if mode.modal else None

    def free(self, t: float) -> np.ndarray:
        """Free part z(t - t0), shape (n,); scalar t (the hot path of the search)."""
        if self._alpha is not None:
            e = self._alpha * np.exp(self.mode.roots * (t - self.t0))
            return (self.mode.eigenvectors @ e).real
        return self.mode.free(t - self.t0, self.z0)

    def state(self, t: np.ndarray | float) -> np.ndarray:
        """State y(t), shape t.shape + (n,)."""
        return self.mode.state(t, self.t0, self.y0)


def _lower_bound_root(g: float, g1: float, K: float) -> float:
    """Positive root of g + g1 s - K s^2/2 (g >= 0, K > 0), computed without cancellation."""
    disc = math.sqrt(g1 * g1 + 2.0 * K * g)
    if g1 <= 0.0:
        return 2.0 * g / (disc - g1) if disc - g1 > 0.0 else 0.0
    return (g1 + disc) / K


def first_root(
    segment: Segment,
    fn: LinearFunctional,
    t_from: float,
    t_to: float,
    tol: float,
    departure: tuple[int, float] | None = None,
) -> tuple[float, float] | None:
    """First t in (t_from, t_to] where g(t) <= tol with g'(t) <= 0, found without skipping any.

    Parameters
    ----------
    segment : Segment
        The motion; ``fn`` must read the same mode.
    fn : LinearFunctional
        The function g, positive on the side where the mode holds.
    t_from, t_to : float
        Search interval, s. g(t_from) >= 0 is assumed (the caller's mode holds there).
    tol : float
        A value of g at or below ``tol`` with a non-positive slope counts as reaching zero:
        the grazing resolution, in g's units.
    departure : (int, float), optional
        If g(t_from) = 0 exactly (leaving a contact): the order m >= 1 of the first non-zero
        Taylor coefficient and that derivative g^(m)(t_from) > 0.

    Returns
    -------
    (t, dg) or None
        The root time and g'(t) there (<= 0), or None if (t_from, t_to] is certified free of
        roots.
    """
    mode, c_forced = fn.mode, fn.G
    w = mode.omega
    kappa1, kappa2 = fn.kappa[1], fn.kappa[2]
    Gabs = abs(c_forced)
    W = mode.energy_weight
    a = float(t_from)
    if departure is not None:
        m, gm = departure
        z = segment.free(a)
        energy = math.sqrt(max(float(z @ W @ z), 0.0))
        K = Gabs * w ** (m + 1) + fn.kappa[m + 1] * energy
        # g(a+s) >= g_m s^m/m! - K s^(m+1)/(m+1)! = s^m/m! (g_m - K s/(m+1)) > 0 below this.
        a += (m + 1) * gm / K
        if a >= t_to:
            return None
    cM0, cM1 = fn.cM[0], fn.cM[1]
    for _ in range(MAX_STEPS):
        z = segment.free(a)
        rot = cmath.exp(1j * w * a) * c_forced
        g = fn.g0 + rot.imag + float(cM0 @ z)
        g1 = w * rot.real + float(cM1 @ z)
        if g <= tol and g1 <= 0.0:
            return _polish(segment, fn, a, g, g1)
        energy = math.sqrt(max(float(z @ W @ z), 0.0))
        K = Gabs * w * w + kappa2 * energy
        step = _lower_bound_root(max(g, 0.0), g1, K)
        if a + step <= a:
            # The certified step fell below the time resolution: g is at rounding level.
            return a, g1
        a += step
        if a >= t_to:
            return None
    raise SearchLimitError(f"event search took more than {MAX_STEPS} steps from t = {t_from!r}")


def _polish(segment: Segment, fn: LinearFunctional, t: float, g: float, g1: float) -> tuple[float, float]:
    """Newton from the certified point (g <= tol, g' <= 0) to the root at rounding level;
    stops where the slope vanishes (a grazing touch is kept at the certified point)."""
    for _ in range(NEWTON_ITERATIONS):
        if g1 >= 0.0 or g <= 0.0:
            break
        dt = -g / g1
        if t + dt == t:
            break
        t_new = t + dt
        y = segment.state(t_new)
        g_new = float(fn.of_state(t_new, y))
        g1_new = float(fn.of_state(t_new, y, 1))
        # Accept only a step that shrinks the residual and stays inside the tolerance band:
        # near a gap maximum below tol (a bounce lower than the resolution) the slope is ~0
        # and Newton would jump far past the root.
        if abs(g_new) >= abs(g) or g_new < -abs(g):
            break
        t, g, g1 = t_new, g_new, g1_new
    return t, g1
