"""Codimension-one points of impacting cycles followed in two parameters: boundary curves.

A special point located on a branch by :func:`~impactdamper.analysis.continuation.continue_orbit`
(a fold, a period doubling, a Neimark-Sacker point, a grazing impact or a grazing touch of a
cycle of period k T with z impacts, Timofeev et al. 2019 eqs. 18-22) persists, as two fields of
:class:`Parameters` vary, along a curve of the plane. :func:`follow_curve` follows it.

Curve follower
--------------
The curve is the zero set of an augmented system in X = (u, a, b), the cycle's 5 z shooting
unknowns and the plane's two parameters: the shooting equations and one test function of the
kind (:class:`~impactdamper.analysis.curve_system.CurveSystem`, whose docstring tabulates them),
5 z + 1 equations in 5 z + 2 unknowns. It is followed from the seed both ways by
pseudo-arclength continuation: tangent predictor, bordered Newton corrector, the step grown
after fast convergence and halved on failure, in the metric where the 5 z unknowns count as
one and each parameter is scaled by the map's span.

Ends
----
Every curve ends with a recorded reason (:data:`END_REASONS`, read and located on each step
by :mod:`~impactdamper.analysis.curve_ends`): a codimension-two point located
on it (``cusp`` of folds: the curve's direction in the plane reverses; ``fold_flip``: a fold
and a period doubling meet; ``resonance_1_1`` / ``resonance_1_2`` / ``resonance_1_3`` on a
Neimark-Sacker curve: the pair's argument reaches 0, pi or 2 pi/3); ``map_edge`` (a bound of
the plane, the last point on it); ``inadmissible`` (another impact's velocity or another
flight's sampled interior gap minimum reaches zero: the cycle's impact sequence no longer
describes the motion there); ``newton_failure`` (the step fell below ``min_step``); ``closed``
(the curve came back to its start); ``max_points``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from impactdamper.analysis.curve_ends import CODIM2_REASONS, END_REASONS, codim2_tests, end_on_step, stable_side
from impactdamper.analysis.curve_system import KINDS, CurveSystem, curve_kind, tracked_index
from impactdamper.analysis.shooting import OrbitError, Shooting
from impactdamper.core.parameters import Parameters, ScaleMap

__all__ = ["Curve", "follow_curve", "curve_point", "curve_kind", "KINDS", "END_REASONS", "CODIM2_REASONS"]


@dataclass(frozen=True)
class Curve:
    """A followed boundary curve in the plane of two parameters.

    Attributes
    ----------
    kind : str
        One of :data:`KINDS`.
    names : (str, str)
        The plane's parameters (fields of :class:`Parameters`, or ``delta`` for delta1 = delta2).
    period_multiple, impacts_per_cycle : int
        k and z of the cycle.
    index : int
        The tracked impact (``grazing_velocity``: the impact ending flight ``index``) or the
        flight after impact ``index``
        (``grazing_touch``) in the cycle's order; -1 for the bifurcation kinds.
    points : ndarray, shape (n, 2)
        (a, b) along the curve, from the seed's end (``direction`` -1 leg reversed) to the other.
    stable_side : tuple of str
        Per point, the side of the curve where the cycle is stable (``"gap+"`` : larger gap,
        ``"theta-"`` : smaller theta, ...), ``"none"`` when the other multipliers make it
        unstable on both sides, ``""`` where it does not apply (fold and grazing kinds).
    ends : ((str, str), (str, str))
        Each end's reason (:data:`END_REASONS`) and what happens there, first end first.
    seed : (float, float)
        The seed's (a, b).
    p : Parameters
        The parameters off the plane (in the solver's units, see :meth:`Parameters.canonical`).
    unknowns : ndarray, shape (n, 5 z)
        The cycle's shooting unknowns at each point (:meth:`Shooting.pack`, in ``p``'s units).
    """

    kind: str
    names: tuple
    period_multiple: int
    impacts_per_cycle: int
    index: int
    points: np.ndarray = field(repr=False)
    stable_side: tuple = field(repr=False)
    ends: tuple
    seed: tuple
    p: Parameters = field(repr=False)
    unknowns: np.ndarray = field(repr=False)

    @property
    def label(self) -> str:
        return f"{self.impacts_per_cycle}/{self.period_multiple}"


def follow_curve(
    p: Parameters,
    k: int,
    times,
    states_after,
    kind: str,
    names: tuple = ("gap", "theta"),
    bounds: tuple = ((-40.0, 15.0), (0.5, 1.5)),
    *,
    step: float = 0.01,
    min_step: float = 1e-6,
    max_step: float = 0.05,
    max_points: int = 400,
) -> Curve:
    """Follow a codimension-one point of a cycle through the plane of two parameters, both ways.

    Parameters
    ----------
    p : Parameters
        The parameters at the seed (its ``names`` fields give the seed's (a, b)).
    k : int
        Period multiple of the cycle (T_c = k T).
    times : array_like, shape (z,)
        The cycle's impact times, s, in cycle order (e.g. ``SpecialPoint.point.times``).
    states_after : array_like, shape (z, 4)
        (x1, x2, x1', x2') just after each impact.
    kind : str
        One of :data:`KINDS` (or ``grazing_interior``, the one-parameter table's name of a touch).
    names : (str, str)
        The plane: two fields of :class:`Parameters` (or ``delta``: delta1 = delta2).
    bounds : ((float, float), (float, float))
        The plane's ranges (the map's edges); their spans scale the arclength.
    step, min_step, max_step : float
        Initial, smallest and largest arclength step (relative unknowns, parameters over their span).
    max_points : int
        Most points per direction.

    Returns
    -------
    Curve
    """
    kind = _checked(kind, names, step, min_step, max_step)
    q, times, states, (a0, b0) = _seed_in_solver_units(p, times, states_after, names, bounds)
    (alo, ahi), (blo, bhi) = bounds
    z = len(times)
    s0 = Shooting(q, k, z)
    u0 = s0.pack(times, states)
    index = tracked_index(s0, u0, kind)
    sysm = CurveSystem(q, names, k, z, kind, index, (ahi - alo, bhi - blo))
    x0, _ = sysm.correct(np.concatenate([u0, [a0, b0]]), np.zeros(len(u0) + 2), 0.0, fixed=-1)
    if x0 is None:
        raise OrbitError(f"the {kind} point of the {z}/{k} cycle does not solve at {names[1]} = {b0!r}")
    (xs_d, side_d, end_d), (xs_u, side_u, end_u) = _both_legs(sysm, x0, bounds, (step, min_step, max_step), max_points)
    xs = xs_d[::-1] + xs_u[1:]
    sides = side_d[::-1] + side_u[1:]
    X = np.array(xs)
    return Curve(
        kind=kind,
        names=tuple(names),
        period_multiple=k,
        impacts_per_cycle=z,
        index=index,
        points=X[:, -2:].copy(),
        stable_side=tuple(sides),
        ends=(end_d, end_u),
        seed=(float(x0[-2]), float(x0[-1])),
        p=q,
        unknowns=X[:, :-2].copy(),
    )


def _checked(kind: str, names, step: float, min_step: float, max_step: float) -> str:
    """The curve kind of ``kind``, the arguments checked (one line naming the argument)."""
    kind = curve_kind(kind)
    if kind not in KINDS:
        raise ValueError(f"`kind` = {kind!r} is not allowed: must be one of {', '.join(KINDS)}")
    if len(names) != 2 or names[0] == names[1]:
        raise ValueError(f"`names` = {names!r} is not allowed: must be two different parameters")
    if not (0 < min_step <= step <= max_step):
        raise ValueError(f"`step` = {step!r} is not allowed: need 0 < min_step <= step <= max_step")
    return kind


def _seed_in_solver_units(p: Parameters, times, states_after, names, bounds):
    """(parameters, impact times, states after) of the seed in the solver's units (the canonical
    scales where ``p``'s are not native), and its (a, b), checked inside ``bounds``."""
    times, states = np.asarray(times, float), np.asarray(states_after, float)
    q = p if p.native_scales() else p.canonical()
    if q is not p:
        sm = ScaleMap(p, q)
        times = np.array([sm.apply(float(t), "time") for t in times])
        states = np.array([sm.full(y) for y in states])
    a0, b0 = (float(_value(p, n)) for n in names)
    (alo, ahi), (blo, bhi) = bounds
    if not (alo <= a0 <= ahi and blo <= b0 <= bhi):
        raise ValueError(f"`bounds` = {bounds!r} is not allowed: must contain the seed ({a0!r}, {b0!r})")
    return q, times, states, (a0, b0)


def _both_legs(sysm: CurveSystem, x0: np.ndarray, bounds, steps, max_points) -> list:
    """The two legs from the seed x0: towards decreasing, then increasing second parameter."""
    legs = []
    for direction in (-1, +1):
        e = np.zeros(len(x0))
        e[-1] = direction
        t = sysm.tangent(x0, e)
        if t[-1] * direction < 0:
            t = -t
        legs.append(_leg(sysm, x0, t, bounds, steps, max_points))
    return legs


def _value(p: Parameters, name: str) -> float:
    return getattr(p, "delta1" if name == "delta" else name)


def _leg(sysm: CurveSystem, x: np.ndarray, t: np.ndarray, bounds, steps, max_points):
    """One direction from the seed: the points, their stable sides and (end reason, detail)."""
    h, min_step, max_step = steps
    start = x.copy()
    t_ref = t[-2:].copy()
    xs, sides = [x], [stable_side(sysm, x, t)]
    tests = codim2_tests(sysm, x, t[-2:], t_ref)
    for _ in range(max_points):
        x_new, its = sysm.correct(x, t, h)
        if x_new is None:
            h *= 0.5
            if h < min_step:
                return xs, sides, ("newton_failure", f"the corrector fails below step {min_step:g}")
            continue
        try:
            t_new = sysm.tangent(x_new, t)
            tests_new = codim2_tests(sysm, x_new, t_new[-2:], t_ref)
        except (OrbitError, ValueError, np.linalg.LinAlgError):
            h *= 0.5
            if h < min_step:
                return xs, sides, ("newton_failure", "the tangent or the tests fail")
            continue
        # The first end along the step: a bound of the plane or a test's zero.
        end = end_on_step(sysm, x, t, h, x_new, tests, tests_new, t_ref, bounds)
        if end is not None:
            x_end, reason = end
            if x_end is not None:
                xs.append(x_end)
                sides.append(stable_side(sysm, x_end, t_new))
            return xs, sides, reason
        xs.append(x_new)
        sides.append(stable_side(sysm, x_new, t_new))
        if len(xs) > 10 and sysm.norm(x_new - start) < 0.5 * h:
            return xs, sides, ("closed", "the curve comes back to its seed")
        x, t, tests = x_new, t_new, tests_new
        h = min(h * 1.5, max_step) if its <= 5 else (h * 0.7 if its >= 9 else h)
        h = max(h, min_step)
    return xs, sides, ("max_points", f"{max_points} points")


def curve_point(curve: Curve, value: float) -> tuple[float, np.ndarray]:
    """The curve's point with its second parameter at ``value`` (Newton from the nearest
    point with that parameter held): (first parameter, shooting unknowns)."""
    i = int(np.argmin(np.abs(curve.points[:, 1] - value)))
    sysm = CurveSystem(
        curve.p, curve.names, curve.period_multiple, curve.impacts_per_cycle, curve.kind, curve.index, (1, 1)
    )
    x0 = np.concatenate([curve.unknowns[i], [curve.points[i, 0], value]])
    x, _ = sysm.correct(x0, np.zeros(len(x0)), 0.0, fixed=-1, max_iterations=30)
    if x is None:
        raise OrbitError(f"no {curve.kind} point of the {curve.label} cycle at {curve.names[1]} = {value!r}")
    return float(x[-2]), x[:-2]
