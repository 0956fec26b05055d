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

from impactdamper.core.linear import LinearMode

__all__ = ["LinearFunctional", "Segment", "march", "SearchLimitError", "StepBudget"]

# Newton polishing after the certified march: the march already converges quadratically,
# so a few iterations reach rounding level.
NEWTON_ITERATIONS = 6
# Longest Newton step, in forcing periods: from a point within tol of a transversal root the
# step is ~tol/|g'|, far below this.
NEWTON_MAX_STEP = 1e-6
# No search may take more certified steps than this (a guard; typical searches take 5-50).
MAX_STEPS = 200_000
# Floor of a derivative bound: a zero bound (no forcing, no free motion) would give an
# infinite step, which is right (g is then constant) but must not divide by zero.
MIN_BOUND = 1e-300


class SearchLimitError(RuntimeError):
    """The event search exceeded its step budget, or its bounds left the floating-point range.

    Never expected for ordinary parameters; a bound on the work, so that a motion too fast or
    too stiff for the forcing period ends in this error instead of a hang.
    """


class StepBudget:
    """A bound on the certified steps of many searches together (one run's work).

    Parameters
    ----------
    limit : int
        Steps allowed; the owner may raise it as the run goes on.
    message : callable
        ``message(t)`` gives the :class:`SearchLimitError`'s text when the budget runs out at t.
    """

    def __init__(self, limit: int, message):
        self.limit, self.used, self.message = int(limit), 0, message

    @property
    def remaining(self) -> int:
        return max(self.limit - self.used, 0)


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
        object.__setattr__(self, "cV", c @ self.mode.eigenvectors)  # c.V_j, for the modal sums
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
        self._evaluators: dict = {}

    def free(self, t: float) -> np.ndarray:
        """Free part z(t - t0), shape (n,); scalar t (the hot path of the search)."""
        if self._alpha is not None:
            e = self._alpha * np.exp(self.mode.roots * (t - self.t0))
            return (self.mode.eigenvectors @ e).real
        return self.mode.free(t - self.t0, self.z0)

    def state(self, t: np.ndarray | float) -> np.ndarray:
        """State y(t), shape t.shape + (n,)."""
        if self._alpha is None:
            return self.mode.state(t, self.t0, self.y0)
        return self.mode.state_modal(t, self.t0, self._alpha)  # (LinearMode.state's numbers, to the bit)

    def evaluator(self, fn: LinearFunctional):
        """A function t -> (g(t), g'(t)) for this motion, the event search's hot path.

        In modal form c.z(tau) = Re sum_j beta_j e^{lambda_j tau} with beta_j = (c.V_j) alpha_j,
        so an evaluation is four complex exponentials in plain Python (no array overhead)."""
        cached = self._evaluators.get(id(fn))
        if cached is None:  # (made apart: a closure's cells cost every call of the maker, hit or miss)
            cached = self._evaluators[id(fn)] = self._new_evaluator(fn)
        return cached

    def _new_evaluator(self, fn: LinearFunctional):
        w, G, g0, t0 = self.mode.omega, fn.G, fn.g0, self.t0
        exp = cmath.exp
        if self._alpha is not None:
            # M is real, so its complex roots come in conjugate pairs with conjugate
            # coefficients: each pair contributes 2 Re(beta e^{lambda tau}); keep one of each.
            beta = (fn.cV * self._alpha).tolist()
            terms = [(2.0 * beta[j] if pair else beta[j], lam) for j, lam, pair in self.mode.pair_roots]

            if len(terms) == 2:  # (a complex pair per body, the free mode: the loop below unrolled)
                (b1, lam1), (b2, lam2) = terms

                def evaluate(t: float) -> tuple[float, float]:
                    tau = t - t0
                    e1, e2 = b1 * exp(lam1 * tau), b2 * exp(lam2 * tau)
                    rot = exp(1j * w * t) * G
                    # (summed as the loop sums, from 0j: the same numbers to the bit)
                    return g0 + rot.imag + (0j + e1 + e2).real, w * rot.real + (0j + lam1 * e1 + lam2 * e2).real

                return evaluate

            def evaluate(t: float) -> tuple[float, float]:
                tau = t - t0
                s0 = s1 = 0j
                for b, lam in terms:
                    e = b * exp(lam * tau)
                    s0 += e
                    s1 += lam * e
                rot = exp(1j * w * t) * G
                return g0 + rot.imag + s0.real, w * rot.real + s1.real
        else:
            cM0, cM1 = fn.cM[0], fn.cM[1]

            def evaluate(t: float) -> tuple[float, float]:
                z = self.free(t)
                rot = exp(1j * w * t) * G
                return g0 + rot.imag + float(cM0 @ z), w * rot.real + float(cM1 @ z)

        return evaluate


def _lower_bound_root(g: float, g1: float, K: float) -> float:
    """Positive root of g + g1 s - K s^2/2 (g >= 0, K > 0), computed without cancellation."""
    disc = math.sqrt(g1 * g1 + 2.0 * K * g)
    if disc == math.inf:  # K g overflowed (gap = 1e300 x_st): the same root without the squares
        disc = math.hypot(g1, math.sqrt(2.0 * K) * math.sqrt(g))
    if g1 <= 0.0:
        return 2.0 * g / (disc - g1) if disc - g1 > 0.0 else 0.0
    return (g1 + disc) / K


def march(
    segment: Segment,
    fn: LinearFunctional,
    t_from: float,
    t_to: float,
    tol: float,
    departure: tuple[int, float] | None = None,
    budget: StepBudget | None = None,
) -> tuple[tuple[float, float] | None, float]:
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
    budget : StepBudget, optional
        A run's shared bound on the steps; this search takes at most what is left of it (and
        never more than ``MAX_STEPS``), and adds the steps it took.

    Returns
    -------
    root : (t, dg) or None
        The root time and g'(t) there (<= 0), or None if (t_from, t_to] is certified free of
        roots.
    reached : float
        Without a root: the point up to which the march certified g > 0 (>= t_to; its last
        step may go past t_to, and a later search can start there). With a root: its time.

    Raises
    ------
    SearchLimitError
        More than ``MAX_STEPS`` steps (or the budget's), or a bound or value of g that is not
        a finite number (a motion beyond the floating-point range).
    """
    mode = fn.mode
    w = mode.omega
    # The free motion's energy never grows, so its value at t_from bounds the whole search.
    energy = math.sqrt(max(_energy_form(segment.free(float(t_from)), mode.energy_weight), 0.0))
    a = float(t_from)
    if departure is not None:
        a = _past_departure(fn, energy, a, t_from, departure)
        if a >= t_to:
            return None, a
    K = max(abs(fn.G) * w * w + fn.kappa[2] * energy, MIN_BOUND)
    # An infinite bound would give zero steps (a false root at once); a NaN, no progress at all.
    _require_finite(K, t_from)
    return _certified_steps(segment, fn, a, t_from, t_to, tol, K, budget)


def _past_departure(fn: LinearFunctional, energy: float, a: float, t_from: float, departure: tuple[int, float]):
    """The time up to which a g leaving zero at ``a`` (its first non-zero derivative of order m,
    g_m > 0) is certified positive, from the bound K on g^(m+1) that ``energy`` gives."""
    m, gm = departure
    K = max(abs(fn.G) * fn.mode.omega ** (m + 1) + fn.kappa[m + 1] * energy, MIN_BOUND)
    _require_finite(K, t_from)
    # g(a+s) >= g_m s^m/m! - K s^(m+1)/(m+1)! = s^m/m! (g_m - K s/(m+1)) > 0 below this.
    return a + (m + 1) * gm / K


def _certified_steps(
    segment: Segment,
    fn: LinearFunctional,
    a: float,
    t_from: float,
    t_to: float,
    tol: float,
    K: float,
    budget: StepBudget | None,
) -> tuple[tuple[float, float] | None, float]:
    """March's steps from ``a``: each as long as g'' <= ``K`` certifies g stays positive
    (:func:`_lower_bound_root`), until g reaches ``tol`` falling (the root, polished) or t_to
    (None); the return value and the raised limits as :func:`march`'s."""
    evaluate = segment.evaluator(fn)
    limit = MAX_STEPS if budget is None else min(MAX_STEPS, budget.remaining)
    steps = 0
    try:
        for steps in range(1, limit + 1):
            g, g1 = evaluate(a)
            if g <= tol and g1 <= 0.0:
                root = _polish(segment, fn, a, g, g1)
                return root, root[0]
            step = _lower_bound_root(max(g, 0.0), g1, K)
            if a + step <= a:
                # The certified step fell below the time resolution: g is at rounding level.
                return (a, g1), a
            if step != step:  # NaN: g or g' is not a number (never for a finite motion)
                _require_finite(math.nan, t_from)
            a += step
            if a >= t_to:
                return None, a
    finally:
        if budget is not None:
            budget.used += steps
    if budget is not None and limit < MAX_STEPS:
        raise SearchLimitError(budget.message(a))
    raise SearchLimitError(f"event search took more than {MAX_STEPS} steps from t = {t_from!r}")


@np.errstate(over="ignore", invalid="ignore")  # (an overflow is refused in march, by name)
def _energy_form(z: np.ndarray, weight: np.ndarray) -> float:
    """z^T W z, twice the free motion's energy (numpy's errstate as a decorator: per call, and
    cheaper than entering a new context on the march's hot path)."""
    return float(z @ weight @ z)


def _require_finite(value: float, t_from: float) -> None:
    if not math.isfinite(value):
        raise SearchLimitError(
            f"event search from t = {t_from!r}: the derivative bound or the function is "
            f"{value!r}: the motion is beyond the floating-point range"
        )


def _polish(segment: Segment, fn: LinearFunctional, t: float, g: float, g1: float) -> tuple[float, float]:
    """Newton from the certified point (g <= tol, g' <= 0) to the root at rounding level;
    stops where the slope vanishes (a grazing touch is kept at the certified point).

    The compiled kernels' march (``core/compiled/march.py``) repeats this polish line for line:
    a deliberate mirror, the readable reference of the two (``tests/unit/test_compiled.py``
    holds them to the same events)."""
    evaluate = segment.evaluator(fn)
    max_step = NEWTON_MAX_STEP * 2.0 * math.pi / fn.mode.omega
    for _ in range(NEWTON_ITERATIONS):
        if g1 >= 0.0 or g == 0.0:
            break
        dt = -g / g1
        # The certified point is within tol of a root: a transversal root is then a tiny step
        # away. A long step means the slope is ~0 there (a touch, or a point with g < 0 and
        # g' ~ 0 in the flight scan of an inadmissible orbit, where the step was 1e14 s and
        # overflowed the exponentials): keep the point.
        if t + dt == t or abs(dt) > max_step:
            break
        t_new = t + dt
        g_new, g1_new = evaluate(t_new)
        # Accept only a step that shrinks the residual (from either side of a transversal
        # root, where Newton converges quadratically): near a gap maximum below tol (a bounce
        # lower than the resolution) the slope is ~0 and Newton would jump far past the root.
        # Nor one that lands where g already rises: at a near-double root (a grazing touch)
        # that is past the minimum, and the first root has g' <= 0 (else the touch would be
        # recorded with an opening velocity).
        if abs(g_new) >= abs(g) or g1_new > 0.0:
            break
        t, g, g1 = t_new, g_new, g1_new
    return t, g1
