"""Branches of periodic impacting cycles in one parameter: pseudo-arclength continuation.

A cycle of period T_c = k T with z impacts, solved by the Newton shooting of
:mod:`impactdamper.analysis.orbits` (the exact flow of eq. 18 of Timofeev et al. 2019 between
impacts, the impact law of eqs. 21-22), is followed as one field of :class:`Parameters` varies
(typically the gap Delta0/x_st of the paper's Fig. 2), and the points where it changes are
located.

:func:`continue_orbit` follows a cycle in any field of :class:`Parameters` by pseudo-arclength
continuation (tangent predictor, bordered Newton corrector, adaptive step). Between
consecutive points it watches test functions and locates their zeros by Brent's method along
the arclength: the tangent's parameter component (fold), det(I + M_c) (period doubling), the
modulus of complex multipliers minus one (Neimark-Sacker), the least closing velocity
(grazing impact: it vanishes) and the least interior gap minimum (grazing touch: a new impact).
A located bifurcation is kept only if a multiplier is on the unit circle there. A grazing is
where the branch's impact sequence stops describing the motion: the branch ends there
(unless asked to go on) with the reason. The branch and its points are the types of
:mod:`impactdamper.analysis.branch`.
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper.analysis.branch import Branch, SpecialPoint, branch_point, rescale_branch
from impactdamper.analysis.cycle import PeriodicOrbit, flight_scan, least_period, orbit_from_solution, rescale_orbit
from impactdamper.analysis.shooting import ORBIT_TOL, OrbitError, Shooting
from impactdamper.core.parameters import PARAMETER_TABLE, Parameters, ScaleMap
from impactdamper.core.simulate import Tolerances
from impactdamper.core.validation import check_tolerances, finite_argument, integer_argument

__all__ = ["continue_orbit", "MAX_BRANCH_POINTS"]

# Relative step of the finite-difference derivative in the continuation parameter.
PARAMETER_FD_STEP = 1e-6
# Bound on a branch's points (continue_orbit's max_points).
MAX_BRANCH_POINTS = 1_000_000
# Each parameter's row of the one parameter table: its range (the continuation's bounds must lie
# in it) and its role (the free scales are continued in the user's units).
_SPEC = {s.name: s for s in PARAMETER_TABLE}
_SCALES = tuple(s.name for s in PARAMETER_TABLE if s.role == "scale")


class _Continuation:
    """Pseudo-arclength continuation of the shooting equations in one parameter."""

    def __init__(self, p: Parameters, parameter: str, k: int, z: int, gap_tol: float):
        self.p0, self.parameter, self.k, self.z, self.gap_tol = p, parameter, k, z, gap_tol
        self._cache: dict = {}
        # Arclength metric: the 5 z unknowns count as one (their mean square), the parameter as
        # one, so a step moves the parameter by a similar amount whatever z is.
        n = 5 * z
        self.W = np.append(np.full(n, 1.0 / n), 1.0)

    def norm(self, v: np.ndarray) -> float:
        return float(np.sqrt(v @ (self.W * v)))

    def shooting(self, lam: float) -> Shooting:
        s = self._cache.get(lam)
        if s is None:
            s = Shooting(self.p0.replace(**{self.parameter: float(lam)}), self.k, self.z)
            if len(self._cache) > 64:
                self._cache.clear()
            self._cache[lam] = s
        return s

    def F(self, x: np.ndarray, jacobian: bool = True):
        """Residual and [J | dF/dlam] at x = (u, lam)."""
        u, lam = x[:-1], float(x[-1])
        F, J = self.shooting(lam).residual(u, jacobian)
        if not jacobian:
            return F, None
        h = PARAMETER_FD_STEP * max(1.0, abs(lam))

        def side(lam_side: float):
            try:
                return self.shooting(lam_side).residual(u, False)[0], h
            except ValueError:  # beyond the parameter's range: a one-sided difference
                return F, 0.0

        (Fp, h_p), (Fm, h_m) = side(lam + h), side(lam - h)
        if h_p + h_m == 0.0:
            raise OrbitError(f"cannot vary `{self.parameter}` at {lam!r}")
        dF = (Fp - Fm) / (h_p + h_m)
        return F, np.column_stack([J, dF])

    def tangent(self, x: np.ndarray, previous: np.ndarray) -> np.ndarray:
        _, A = self.F(x)
        B = np.vstack([A, self.W * previous])
        rhs = np.zeros(len(x))
        rhs[-1] = 1.0
        t = np.linalg.solve(B, rhs)
        return t / self.norm(t)

    def correct(self, x0: np.ndarray, t0: np.ndarray, h: float, max_iterations: int = 10):
        """Newton on F = 0, <t0, x - x0>_W = h from the predictor x0 + h t0."""
        x = x0 + h * t0
        row = self.W * t0
        for it in range(1, max_iterations + 1):
            try:
                F, A = self.F(x)
            except (OrbitError, ValueError):
                return None, it
            G = np.append(F, row @ (x - x0) - h)
            B = np.vstack([A, row])
            try:
                dx = np.linalg.solve(B, -G)
            except np.linalg.LinAlgError:
                return None, it
            x = x + dx
            if not np.all(np.isfinite(x)):
                return None, it
            if np.max(np.abs(dx)) <= ORBIT_TOL * max(1.0, abs(h)):
                try:
                    F, _ = self.F(x, jacobian=False)
                except (OrbitError, ValueError):
                    return None, it
                if np.max(np.abs(F)) <= 10 * ORBIT_TOL:
                    return x, it
        return None, max_iterations

    def orbit(self, x: np.ndarray) -> PeriodicOrbit:
        s = self.shooting(float(x[-1]))
        t, y = s.times_states(x[:-1])
        F, _ = s.residual(x[:-1], False)
        return orbit_from_solution(s.p, s.model, self.k, t, y, "orbit", 0, float(np.max(np.abs(F))), 0, self.gap_tol)


def _tests(o: PeriodicOrbit, tangent_lam: float) -> dict:
    """Test functions whose sign changes mark special points."""
    mono = o.monodromy()
    n = mono.shape[0]
    mult = o.multipliers
    complex_moduli = [abs(m) for m in mult if abs(m.imag) > 1e-12 * max(abs(m), 1.0)]
    return {
        "fold": tangent_lam,
        "period_doubling": float(np.linalg.det(np.eye(n) + mono)),
        "neimark_sacker": (max(complex_moduli) - 1.0) if complex_moduli else math.nan,
        "grazing_velocity": o.min_velocity,
        "grazing_interior": o.min_gap if math.isfinite(o.min_gap) else math.nan,
    }


def continue_orbit(
    orbit: PeriodicOrbit,
    parameter: str = "gap",
    bounds: tuple[float, float] | None = None,
    *,
    direction: int = +1,
    step: float = 0.01,
    min_step: float = 1e-7,
    max_step: float = 0.25,
    max_points: int = 5000,
    stop_at_grazing: bool = True,
    tolerances: Tolerances | None = None,
) -> Branch:
    """Follow a solved impacting cycle as one parameter varies (pseudo-arclength continuation).

    Parameters
    ----------
    orbit : PeriodicOrbit
        The starting cycle (solved, with at least one impact).
    parameter : str
        A field of :class:`Parameters` (``gap`` is Delta0/x_st).
    bounds : (float, float)
        The parameter range; the branch ends at its edge (a last point exactly there).
    direction : {+1, -1}
        Initial direction of the parameter.
    step, min_step, max_step : float
        Initial, smallest and largest arclength step (in the scaled unknowns and the
        parameter). The step grows after fast corrector convergence and shrinks on failure;
        the branch ends with ``newton_failure`` below ``min_step``.
    stop_at_grazing : bool
        End the branch at the first grazing (where its impact sequence stops being the
        motion's); otherwise follow the (then inadmissible) orbit on.

    Returns
    -------
    Branch
        Points, located special points and the reason the branch ends.
    """
    lo, hi, step, min_step, max_step, max_points = _checked(
        orbit, parameter, bounds, direction, step, min_step, max_step, max_points
    )
    tol = check_tolerances(tolerances)
    steps = (step, min_step, max_step)
    if not orbit.p.native_scales() and parameter not in _SCALES:
        # The same relative problem in the reference case's units, converted back.
        q = orbit.p.canonical()
        canonical = rescale_orbit(orbit, ScaleMap(orbit.p, q))
        branch = _branch(canonical, parameter, (lo, hi), direction, steps, max_points, stop_at_grazing, tol)
        return rescale_branch(branch, ScaleMap(q, orbit.p))
    return _branch(orbit, parameter, (lo, hi), direction, steps, max_points, stop_at_grazing, tol)


def _branch(orbit, parameter, bounds, direction, steps, max_points, stop_at_grazing, tol) -> Branch:
    """:func:`continue_orbit` on checked arguments, in ``orbit``'s own scales (``steps``: step,
    min_step, max_step; ``tol``: the checked tolerances)."""
    cont = _Continuation(orbit.p, parameter, orbit.period_multiple, orbit.impacts_per_cycle, tol.gap_tol)
    points, special, end_reason, end_value = _follow(cont, orbit, bounds, direction, steps, max_points, stop_at_grazing)
    return Branch(
        parameter=parameter,
        period_multiple=orbit.period_multiple,
        impacts_per_cycle=orbit.impacts_per_cycle,
        points=tuple(points),
        special=tuple(special),
        end_reason=end_reason,
        end_value=float(end_value),
    )


def _checked(orbit, parameter, bounds, direction, step, min_step, max_step, max_points):
    """continue_orbit's arguments checked, in order: (low, high, step, min_step, max_step,
    max_points), or a one-line error naming the first bad one."""
    if not (isinstance(parameter, str) and parameter in Parameters.names()):
        raise ValueError(f"`parameter` = {parameter!r} is not allowed: must be one of {', '.join(Parameters.names())}")
    if not isinstance(orbit, PeriodicOrbit) or not orbit.solved or not orbit.impacts:
        raise ValueError("`orbit` is not allowed: must be a solved PeriodicOrbit with impacts")
    if isinstance(direction, bool) or direction not in (1, -1):
        raise ValueError(f"`direction` = {direction!r} is not allowed: must be +1 or -1")
    step, min_step, max_step = (
        finite_argument(name, value) for name, value in (("step", step), ("min_step", min_step), ("max_step", max_step))
    )
    if not (0 < min_step <= step <= max_step):
        raise ValueError(f"`step` = {step!r} is not allowed: need 0 < min_step <= step <= max_step")
    max_points = integer_argument("max_points", max_points, 1, MAX_BRANCH_POINTS)
    lam0 = float(getattr(orbit.p, parameter))
    if bounds is None:
        raise ValueError("`bounds` is not allowed: must be given as (low, high)")
    try:
        lo, hi = (finite_argument("bounds", b) for b in bounds)
    except (TypeError, ValueError):
        raise ValueError(f"`bounds` = {bounds!r} is not allowed: must be two finite numbers (low, high)") from None
    if not (lo < hi and lo <= lam0 <= hi):
        raise ValueError(f"`bounds` = {bounds!r} is not allowed: need low < high around {parameter} = {lam0!r}")
    bounds_error = _domain_error(parameter, lo, hi)
    if bounds_error:
        raise ValueError(f"`bounds` = {bounds!r} is not allowed: {bounds_error}")
    return lo, hi, step, min_step, max_step, max_points


def _domain_error(parameter: str, lo: float, hi: float) -> str:
    """Why the finite bounds ``lo < hi`` of a continuation in ``parameter`` leave its range (the
    parameter table's ``allowed``), or ``""`` if both lie in it."""
    spec = _SPEC[parameter]
    return "" if spec.ok(lo) and spec.ok(hi) else f"`{parameter}` must be {spec.allowed}, so must both bounds"


def _follow(cont: _Continuation, orbit: PeriodicOrbit, bounds, direction, steps, max_points, stop_at_grazing):
    """The continuation loop from ``orbit``: predictor, corrector, adaptive step, a last point
    exactly on a bound, the special points located between points. Returns (points, special
    points, end reason, end value)."""
    (lo, hi), (h, min_step, max_step) = bounds, steps
    lam0 = float(getattr(orbit.p, cont.parameter))
    x = np.append(cont.shooting(lam0).pack(orbit.times, orbit.states_after), lam0)
    e = np.zeros(len(x))
    e[-1] = float(direction)
    t = cont.tangent(x, e)
    if t[-1] * direction < 0:
        t = -t
    o = cont.orbit(x)
    points = [branch_point(lam0, o)]
    tests = _tests(o, t[-1])
    special: list[SpecialPoint] = []
    seq = _sequence(orbit.period_multiple, orbit.impacts_per_cycle)
    while len(points) < max_points:
        x_new, its = cont.correct(x, t, h)
        h_taken, edge = h, None
        if x_new is not None and not lo <= float(x_new[-1]) <= hi:
            # Land exactly on the bound: secant in the step length.
            edge = hi if float(x_new[-1]) > hi else lo
            h_taken = h * ((edge - float(x[-1])) / (float(x_new[-1]) - float(x[-1])))
            x_new = _locate_parameter(cont, x, t, h_taken, edge)
        if x_new is None:
            h *= 0.5
            if h < min_step:
                return points, special, "newton_failure", float(x[-1])
            continue
        lam_new = float(x_new[-1]) if edge is None else edge
        o_new = cont.orbit(x_new)
        t_new = cont.tangent(x_new, t)
        tests_new = _tests(o_new, t_new[-1])
        stop = _detect(cont, x, t, h_taken, tests, tests_new, points, bool(o_new.stable), special, seq, stop_at_grazing)
        if stop is not None:
            return points, special, *stop
        points.append(branch_point(lam_new, o_new))
        if edge is not None:
            return points, special, "bound", edge
        x, t, tests = x_new, t_new, tests_new
        h = min(h * 1.5, max_step) if its <= 3 else (h * 0.7 if its >= 6 else h)
        h = max(h, min_step)
    return points, special, "max_points", lam0


def _sequence(k: int, z: int) -> str:
    return f"{z}/{k} ({z} impact{'s' if z != 1 else ''} in {k} T)"


def _locate_parameter(cont: _Continuation, x0: np.ndarray, t0: np.ndarray, h_guess: float, target: float):
    """The branch point with the parameter exactly ``target``, by Newton with lam fixed."""
    x, _ = cont.correct(x0, t0, h_guess)
    if x is None:
        return None
    u = x[:-1].copy()
    s = cont.shooting(target)
    try:
        u, _, _ = s.newton(u)
    except OrbitError:
        return None
    return np.append(u, target)


def _locate(cont: _Continuation, x0: np.ndarray, t0: np.ndarray, h: float, key: str, f0: float):
    """Zero of test function ``key`` between the arclength 0 and h from x0 (Brent's method)."""
    cache = {}

    def g(s: float) -> float:
        if s == 0.0:
            return f0
        x, _ = cont.correct(x0, t0, s)
        if x is None:
            raise OrbitError("corrector failed while locating a special point")
        o = cont.orbit(x)
        tl = cont.tangent(x, t0)[-1]
        v = _tests(o, tl)[key]
        cache[s] = (x, o, v)
        return v

    try:
        import scipy.optimize  # (loaded on first use: the package import stays light)

        s_star = scipy.optimize.brentq(g, 0.0, h, xtol=1e-13 * max(1.0, h), rtol=4 * np.finfo(float).eps, maxiter=100)
        if s_star not in cache:
            g(s_star)
        x, o, _ = cache[s_star]
        return x, o
    except (OrbitError, ValueError, RuntimeError):
        x, _ = cont.correct(x0, t0, h)
        if x is None:
            return None, None
        return x, cont.orbit(x)


# A located bifurcation is kept only if a multiplier really sits on the unit circle there
# (distance below this): a test function can also change sign through a pole, as det(I + M_c)
# does at a grazing impact, where the saltation matrix grows like 1/v.
MULTIPLIER_CHECK = 1e-6


def _multiplier_check(key: str, o: PeriodicOrbit) -> bool:
    mult = o.multipliers
    if key == "period_doubling":
        return bool(np.min(np.abs(mult + 1.0)) < MULTIPLIER_CHECK)
    if key == "fold":
        return bool(np.min(np.abs(mult - 1.0)) < MULTIPLIER_CHECK)
    if key == "neimark_sacker":
        pairs = [abs(m) for m in mult if abs(m.imag) > 1e-12]
        return bool(pairs and min(abs(np.array(pairs) - 1.0)) < MULTIPLIER_CHECK)
    return True


def _detect(cont, x, t, h, tests, tests_new, points, stable_after, special, seq, stop_at_grazing):
    """Locate special points between the last point and the new one; return (reason, value)
    if the branch ends there."""
    found = []
    for key in ("grazing_velocity", "grazing_interior", "period_doubling", "neimark_sacker", "fold"):
        a, b = tests[key], tests_new[key]
        if not (math.isfinite(a) and math.isfinite(b)) or (a > 0) == (b > 0):
            continue
        xs, o = _locate(cont, x, t, h, key, a)
        if o is None or not _multiplier_check(key, o):
            continue
        found.append((key, xs, o))
    if not found:
        return None
    # A turning point at a grazing impact is the grazing itself (the impact time folds there).
    if any(f[0] == "grazing_velocity" for f in found):
        found = [f for f in found if f[0] != "fold"]
    # In order along the step; coinciding points (a velocity grazing is often an interior touch
    # of the neighbouring flight too) with the velocity grazing first.
    priority = {"grazing_velocity": 0, "grazing_interior": 1, "period_doubling": 2, "neimark_sacker": 3, "fold": 4}
    found.sort(key=lambda f: (round(float((cont.W * t) @ (f[1] - x)) / (1e-9 * max(h, 1e-12))), priority[f[0]]))
    k, z = cont.k, cont.z
    stability = ""
    if points[-1].stable != stable_after:
        stability = "; the orbit " + ("gains" if stable_after else "loses") + " stability"
    stop = None
    for key, xs, o in found:
        value = float(xs[-1])
        if stop is not None and abs(value - stop[1]) > 1e-9 * (1.0 + abs(value)):
            break  # beyond the end of the branch
        if key == "grazing_velocity":
            i = int(np.argmin([imp.velocity for imp in o.impacts]))
            kk, zz = _reduced(o, i)
            detail = (
                f"impact {i + 1} of the {seq} cycle reaches zero closing velocity at phase "
                f"{o.impacts[i].phase:.6f}: the impact sequence changes, {seq} -> "
                f"{_sequence(kk, zz)} if the cycle persists"
            )
        elif key == "grazing_interior":
            j = min(range(z), key=lambda i: _flight_min(o, i))
            detail = (
                f"the gap's interior minimum touches the stop in the flight after impact {j + 1}: "
                f"the impact sequence changes, {seq} -> {_sequence(k, z + 1)} if the cycle persists"
            )
        elif key == "period_doubling":
            detail = f"a multiplier passes through -1: a {_sequence(2 * k, 2 * z)} cycle branches off" + stability
        elif key == "neimark_sacker":
            detail = "a complex pair of multipliers crosses the unit circle" + stability
        else:
            detail = "turning point of the branch: a multiplier passes through +1" + stability
        special.append(
            SpecialPoint(kind=key, value=value, index=len(points), point=branch_point(value, o), detail=detail)
        )
        if stop is None and stop_at_grazing and key.startswith("grazing"):
            stop = (key, value)
    return stop


def _reduced(o: PeriodicOrbit, drop: int) -> tuple[int, int]:
    """(k, z) of the cycle left when impact ``drop`` vanishes, reduced to its least period
    (e.g. a 3/2 cycle whose middle impact vanishes may be a 1/1 cycle repeated)."""
    keep = [i for i in range(len(o.times)) if i != drop]
    k = least_period(o.p, o.period_multiple, o.times[keep], o.states_after[keep], 1e-6)
    return k, len(keep) * k // o.period_multiple


def _flight_min(o: PeriodicOrbit, i: int) -> float:
    """Smallest interior gap minimum (relative) of flight i of a solved orbit (inf if none)."""
    model = o.trajectory.model
    z, Tc = len(o.times), o.cycle_duration
    t_b = o.times[i + 1] if i + 1 < z else o.times[0] + Tc
    v_end = o.states_before[(i + 1) % z]
    _, _, minima, _ = flight_scan(model, o.times[i], o.states_after[i], t_b, float(v_end[3] - v_end[2]), 1e-12)
    return min((m[1] for m in minima), default=math.inf)
