"""Codimension-one points of impacting cycles followed in two parameters: boundary curves.

A special point located on a branch by :func:`~impactdamper.analysis.continuation.continue_orbit`
(a fold, a period doubling, a Neimark-Sacker point, a grazing impact or a grazing touch of a
cycle of period k T with z impacts, Timofeev et al. 2019 eqs. 18-22) persists, as two fields of
:class:`Parameters` vary, along a curve of the plane. :func:`follow_curve` follows it.

Augmented system
----------------
The unknowns are X = (u, a, b): the 5 z shooting unknowns u of
:class:`~impactdamper.analysis.shooting.Shooting` and the plane's two parameters. The equations
are the 5 z shooting equations F(u; a, b) = 0 and one test function of the kind, g = 0:

==================  =====================================================================
kind                g(u; a, b)
==================  =====================================================================
fold                det(M_c - I) (a Floquet multiplier at +1)
period_doubling     det(M_c + I) (a multiplier at -1)
neimark_sacker      |lambda|^2 - 1 of the complex pair nearest the unit circle
grazing_velocity    closing velocity of the tracked impact over x_st omega (it vanishes)
grazing_touch       interior minimum of the gap over x_st in the tracked flight (it touches)
==================  =====================================================================

with M_c the monodromy matrix of saltation matrices and exact flows
(:func:`~impactdamper.analysis.shooting.monodromy_matrix`). The Jacobian is the shooting's exact
one in u, exact in the gap (an offset of eq. 20), forward differences in the other parameter
and for the row of g. 5 z + 1 equations in 5 z + 2
unknowns: a curve, followed by pseudo-arclength continuation (tangent predictor, bordered
Newton corrector, step grown after fast convergence and halved on failure) in the metric where
the 5 z unknowns count as one and each parameter is scaled by its ``scales`` (the map's span).

Ends
----
Every curve ends with a recorded reason (:data:`END_REASONS`): a codimension-two point located
on it (``cusp`` of folds: the curve's direction in the plane reverses; ``fold_flip``: a fold
and a period doubling meet; ``resonance_1_1`` / ``resonance_1_2`` / ``resonance_1_3`` on a
Neimark-Sacker curve: the pair's argument reaches 0, pi or 2 pi/3); ``map_edge`` (a bound of
the plane, the last point on it); ``inadmissible`` (another impact's velocity or another
flight's sampled interior gap minimum reaches zero: the cycle's impact sequence no longer
describes the motion there); ``newton_failure`` (the step fell below ``min_step``); ``closed``
(the curve came back to its start); ``max_points``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.analysis.shooting import ORBIT_TOL, OrbitError, Shooting, monodromy_matrix
from impactdamper.analysis.sweeps import with_value
from impactdamper.core.events import Segment
from impactdamper.core.linear import free_mode
from impactdamper.core.model import Model
from impactdamper.core.parameters import Parameters, ScaleMap

__all__ = ["Curve", "follow_curve", "curve_point", "curve_kind", "KINDS", "END_REASONS", "CODIM2_REASONS"]

KINDS = ("fold", "period_doubling", "neimark_sacker", "grazing_velocity", "grazing_touch")
CODIM2_REASONS = ("cusp", "fold_flip", "resonance_1_1", "resonance_1_2", "resonance_1_3")
END_REASONS = CODIM2_REASONS + ("map_edge", "inadmissible", "newton_failure", "closed", "max_points")
# The one-parameter table's names of the kinds (SpecialPoint.kind) -> the curve kinds.
_FROM_SPECIAL = {"grazing_interior": "grazing_touch"}
# Forward-difference steps: in the relative unknowns u, and relative to max(1, |parameter|).
FD_STEP_U, FD_STEP_P = 1e-7, 1e-6
# Corrector: converged when the last step's max norm is below this (relative) and the residual
# below 100 ORBIT_TOL. The iteration is a chord one with a finite-difference row (linear
# convergence): the error left is about the last step times the contraction.
CORRECTOR_TOL = 1e-8
# Samples per flight of the admissibility check (an interior minimum narrower than 1/128 of a
# flight can be missed) and the negative gap (relative) that counts as a crossing.
FLIGHT_SAMPLES = 128
CROSSING_TOL = 1e-9


def curve_kind(special_kind: str) -> str:
    """The curve kind of a one-parameter special point's kind (``grazing_interior`` is a
    grazing touch)."""
    return _FROM_SPECIAL.get(special_kind, special_kind)


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


class _FlightModel:
    """What the shooting equations read of a :class:`Model` (``p``, the free mode, the gap of
    eq. 20), without the rest: a curve moves both parameters at every corrector iteration, so
    each :class:`Shooting` needs a new model, and the stuck mode and the event functionals that
    :class:`Model` also builds (unused by the shooting) were about half of its cost, a sixth of
    the curves' processor time (profiled, theta plane)."""

    gap_of = Model.gap_of

    def __init__(self, p: Parameters):
        self.p, self.free = p, free_mode(p)


class _System:
    """The augmented system F(u; a, b) = 0, g(u; a, b) = 0 of one kind."""

    def __init__(self, p: Parameters, names, k: int, z: int, kind: str, index: int, scales):
        self.p0, self.names, self.k, self.z, self.kind, self.index = p, tuple(names), k, z, kind, index
        self._cache: dict = {}
        self._last = None
        n = 5 * z
        self.W = np.concatenate([np.full(n, 1.0 / n), 1.0 / np.asarray(scales, float) ** 2])

    def norm(self, v: np.ndarray) -> float:
        return float(np.sqrt(v @ (self.W * v)))

    def params(self, a: float, b: float) -> Parameters:
        return with_value(with_value(self.p0, self.names[0], a), self.names[1], b)

    def shooting(self, a: float, b: float) -> Shooting:
        key = (float(a), float(b))
        s = self._cache.get(key)
        if s is None:
            p = self.params(a, b)
            s = Shooting(p, self.k, self.z, model=_FlightModel(p))
            if len(self._cache) > 256:
                self._cache.clear()
            self._cache[key] = s
        return s

    # --- the test functions -----------------------------------------------------------
    def monodromy(self, x: np.ndarray) -> np.ndarray:
        s = self.shooting(x[-2], x[-1])
        t, _, _, before, _ = s.flights(x[:-2])
        # (flights() gives the state before the impact ending each flight: impact i ends flight i - 1.)
        return monodromy_matrix(s.model, t, np.roll(before, 1, axis=0), self.k * s.T)

    def g(self, x: np.ndarray) -> float:
        kind = self.kind
        if kind in ("fold", "period_doubling"):
            return float(np.linalg.det(self.monodromy(x) + (1.0 if kind == "period_doubling" else -1.0) * np.eye(4)))
        if kind == "neimark_sacker":
            pair = _pair(np.linalg.eigvals(self.monodromy(x)))
            return abs(pair) ** 2 - 1.0 if pair is not None else math.nan
        s = self.shooting(x[-2], x[-1])
        if kind == "grazing_velocity":
            _, _, _, before, _ = s.flights(x[:-2])
            i = self.index
            return float((before[i, 3] - before[i, 2]) / (s.p.x_st * s.p.omega))
        return _flight_minimum(s, x[:-2], self.index)

    def G(self, x: np.ndarray) -> np.ndarray:
        F, _ = self.shooting(x[-2], x[-1]).residual(x[:-2], False)
        return np.append(F, self.g(x))

    def jacobian(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G(x) and its Jacobian, shape (5 z + 1, 5 z + 2) (the last one kept: the tangent, the
        tests and the stable side ask at the same point)."""
        key = x.tobytes()
        if self._last is None or self._last[0] != key:
            self._last = (key, *self._jacobian(x))
        return self._last[1], self._last[2]

    def _jacobian(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        u, a, b = x[:-2], float(x[-2]), float(x[-1])
        F, J = self.shooting(a, b).residual(u, True)
        n = len(u)
        cols, grad, g0 = [], np.empty(len(x)), self.g(x)
        for j, v in ((0, a), (1, b)):
            if self.names[j] == "gap":
                # Exact: at fixed u the gap Delta0/x_st enters the equations only as the offset of
                # each flight's end gap (eq. 20) and of a grazing touch's gap minimum.
                cols.append(np.concatenate([np.ones(self.z), np.zeros(4 * self.z)]))
                grad[n + j] = 1.0 if self.kind == "grazing_touch" else 0.0
                continue
            h = FD_STEP_P * max(1.0, abs(v))
            xs = [a, b]
            xs[j] = v + h
            cols.append((self.shooting(*xs).residual(u, False)[0] - F) / h)
            e = np.zeros(len(x))
            e[n + j] = h
            grad[n + j] = (self.g(x + e) - g0) / h
        A = np.column_stack([J, *cols])
        for j in range(n):  # forward differences in u
            e = np.zeros(len(x))
            e[j] = FD_STEP_U
            grad[j] = (self.g(x + e) - g0) / FD_STEP_U
        return np.append(F, g0), np.vstack([A, grad])

    # --- continuation steps -----------------------------------------------------------
    def tangent(self, x: np.ndarray, previous: np.ndarray) -> np.ndarray:
        _, A = self.jacobian(x)
        rhs = np.zeros(len(x))
        rhs[-1] = 1.0
        t = np.linalg.solve(np.vstack([A, self.W * previous]), rhs)
        return t / self.norm(t)

    def correct(self, x0: np.ndarray, t0: np.ndarray, h: float, fixed: int | None = None, max_iterations=12):
        """Newton on G = 0 and <t0, x - x0>_W = h from x0 + h t0, or with parameter ``fixed``
        (-2: a, -1: b) held at x0's value instead of the arclength condition. A chord iteration
        (the Jacobian at the start); converged when the last step is below ``CORRECTOR_TOL``
        (relative) and the residual below 100 ORBIT_TOL."""
        x = x0 + h * t0 if fixed is None else x0.copy()
        A, step = None, math.inf
        if fixed is None:
            row = self.W * t0
        else:
            row = np.zeros(len(x))
            row[fixed] = 1.0
        for it in range(1, max_iterations + 1):
            try:
                G = None
                if A is None:
                    G, A = self.jacobian(x)
                if G is None:
                    G = self.G(x)
                if step <= CORRECTOR_TOL * max(1.0, abs(x[-2]), abs(x[-1])) and np.max(np.abs(G)) <= 100 * ORBIT_TOL:
                    # The chord Jacobian stands for the solution's (the tangent and the stable
                    # side are read from it: one Jacobian per step).
                    self._last = (x.tobytes(), None, A)
                    return x, it
                extra = row @ (x - x0) - h if fixed is None else x[fixed] - x0[fixed]
                dx = np.linalg.solve(np.vstack([A, row]), -np.append(G, extra))
            except (OrbitError, ValueError, np.linalg.LinAlgError):
                return None, it
            x = x + dx
            step = float(np.max(np.abs(dx)))
            if not np.all(np.isfinite(x)):
                return None, it
        return None, max_iterations

    # --- what happens along the curve -------------------------------------------------
    def admissibility(self, x: np.ndarray) -> float:
        """Least closing velocity (over x_st omega) and sampled interior gap minimum (over
        x_st) of the impacts and flights other than the tracked one: negative where the
        cycle's impact sequence no longer describes the motion."""
        s = self.shooting(x[-2], x[-1])
        t, _, y, before, t_next = s.flights(x[:-2])
        v = (before[:, 3] - before[:, 2]) / (s.p.x_st * s.p.omega)
        if self.kind == "grazing_velocity":
            v = np.delete(v, self.index)
        least = float(np.min(v)) if len(v) else math.inf
        for i in range(self.z):
            if self.kind == "grazing_touch" and i == self.index:
                continue
            ts = np.linspace(t[i], t_next[i], FLIGHT_SAMPLES + 1)[1:-1]
            gaps = (
                s.model.gap_of(s.mode.states_from(ts, np.full(len(ts), t[i]), np.tile(y[i], (len(ts), 1)))) / s.p.x_st
            )
            least = min(least, float(np.min(gaps)) + CROSSING_TOL)
        return least

    def multipliers(self, x: np.ndarray) -> np.ndarray:
        return np.linalg.eigvals(self.monodromy(x))

    def codim2_tests(self, x: np.ndarray, plane_tangent: np.ndarray, t_ref: np.ndarray) -> dict:
        """The functions whose zeros end the curve at a codimension-two point."""
        tests = {"inadmissible": self.admissibility(x)}
        if self.kind == "fold":
            tests["fold_flip"] = float(np.linalg.det(self.monodromy(x) + np.eye(4)))
            tests["cusp"] = float(plane_tangent @ t_ref)
        elif self.kind == "period_doubling":
            tests["fold_flip"] = float(np.linalg.det(self.monodromy(x) - np.eye(4)))
        elif self.kind == "neimark_sacker":
            pair = _pair(self.multipliers(x))
            if pair is None:
                tests["resonance_1_1"] = -1.0
            else:
                angle = abs(math.atan2(pair.imag, pair.real))
                tests["resonance_1_1"] = angle
                tests["resonance_1_2"] = math.pi - angle
                tests["resonance_1_3"] = angle - 2 * math.pi / 3
        return tests

    def stable_side(self, x: np.ndarray, t: np.ndarray) -> str:
        """The side of the curve (in the plane, along the axis nearer its normal) where the
        cycle is stable; ``none`` if unstable on both; ``""`` for folds and grazings."""
        if self.kind not in ("period_doubling", "neimark_sacker"):
            return ""
        mult = self.multipliers(x)
        crit = (
            int(np.argmin(np.abs(mult + 1.0)))
            if self.kind == "period_doubling"
            else int(np.argmin(np.abs(np.abs(mult) - 1.0)))
        )
        others = np.delete(mult, crit)
        if self.kind == "neimark_sacker":
            others = others[np.argsort(np.abs(others - np.conj(mult[crit])))[1:]]
        if np.any(np.abs(others) >= 1.0):
            return "none"
        # g's sign on the stable side: det(I + M) = (1 + lambda_c) prod(1 + lambda_others).
        stable_sign = np.sign(np.prod(1.0 + others).real) if self.kind == "period_doubling" else -1.0
        scale = 1.0 / np.sqrt(self.W[-2:])
        tp = t[-2:] / scale
        normal = np.array([-tp[1], tp[0]]) * scale  # in the parameters' own units
        _, A = self.jacobian(x)
        n = 5 * self.z
        du = np.linalg.lstsq(A[:n, :n], -(A[:n, n:] @ normal), rcond=None)[0]
        dg = A[n, :n] @ du + A[n, n:] @ normal
        axis = 0 if abs(normal[0] / scale[0]) >= abs(normal[1] / scale[1]) else 1
        sign = np.sign(normal[axis]) * np.sign(dg) * stable_sign
        return self.names[axis] + ("+" if sign > 0 else "-")


def _pair(mult: np.ndarray):
    """The complex multiplier (positive imaginary part) of the pair nearest the unit circle."""
    c = [m for m in mult if m.imag > 1e-12 * max(abs(m), 1.0)]
    return min(c, key=lambda m: abs(abs(m) - 1.0)) if c else None


def _flight_minimum(s: Shooting, u: np.ndarray, i: int) -> float:
    """Interior minimum of the gap over x_st in flight i (after impact i) of the cycle u."""
    import scipy.optimize  # (loaded on first use: the package import stays light)

    t, _, y, _, t_next = s.flights(u)
    seg = Segment(s.mode, t[i], y[i])
    ts = np.linspace(t[i], t_next[i], FLIGHT_SAMPLES + 1)
    gaps = s.model.gap_of(seg.state(ts))
    j = 1 + int(np.argmin(gaps[1:-1]))
    res = scipy.optimize.minimize_scalar(
        lambda q: float(s.model.gap_of(seg.state(q))),
        bounds=(ts[j - 1], ts[j + 1]),
        method="bounded",
        options={"xatol": 1e-13 * s.T},
    )
    return float(res.fun) / s.p.x_st


def _tracked_index(s: Shooting, u: np.ndarray, kind: str) -> int:
    """The impact with the least closing velocity, or the flight with the least interior gap."""
    if kind == "grazing_velocity":
        _, _, _, before, _ = s.flights(u)
        return int(np.argmin(before[:, 3] - before[:, 2]))
    if kind == "grazing_touch":
        return int(np.argmin([_flight_minimum(s, u, i) for i in range(s.z)]))
    return -1


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
    kind = curve_kind(kind)
    if kind not in KINDS:
        raise ValueError(f"`kind` = {kind!r} is not allowed: must be one of {', '.join(KINDS)}")
    if len(names) != 2 or names[0] == names[1]:
        raise ValueError(f"`names` = {names!r} is not allowed: must be two different parameters")
    if not (0 < min_step <= step <= max_step):
        raise ValueError(f"`step` = {step!r} is not allowed: need 0 < min_step <= step <= max_step")
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
    z = len(times)
    s0 = Shooting(q, k, z)
    u0 = s0.pack(times, states)
    index = _tracked_index(s0, u0, kind)
    sysm = _System(q, names, k, z, kind, index, (ahi - alo, bhi - blo))
    x0, _ = sysm.correct(np.concatenate([u0, [a0, b0]]), np.zeros(len(u0) + 2), 0.0, fixed=-1)
    if x0 is None:
        raise OrbitError(f"the {kind} point of the {z}/{k} cycle does not solve at {names[1]} = {b0!r}")
    legs = []
    for direction in (-1, +1):
        e = np.zeros(len(x0))
        e[-1] = direction
        t = sysm.tangent(x0, e)
        if t[-1] * direction < 0:
            t = -t
        legs.append(_leg(sysm, x0, t, bounds, (step, min_step, max_step), max_points))
    (xs_d, side_d, end_d), (xs_u, side_u, end_u) = legs
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


def _value(p: Parameters, name: str) -> float:
    return getattr(p, "delta1" if name == "delta" else name)


def _leg(sysm: _System, x: np.ndarray, t: np.ndarray, bounds, steps, max_points):
    """One direction from the seed: the points, their stable sides and (end reason, detail)."""
    h, min_step, max_step = steps
    start = x.copy()
    t_ref = t[-2:].copy()
    xs, sides = [x], [sysm.stable_side(x, t)]
    tests = sysm.codim2_tests(x, t[-2:], t_ref)
    for _ in range(max_points):
        x_new, its = sysm.correct(x, t, h)
        if x_new is None:
            h *= 0.5
            if h < min_step:
                return xs, sides, ("newton_failure", f"the corrector fails below step {min_step:g}")
            continue
        try:
            t_new = sysm.tangent(x_new, t)
            tests_new = sysm.codim2_tests(x_new, t_new[-2:], t_ref)
        except (OrbitError, ValueError, np.linalg.LinAlgError):
            h *= 0.5
            if h < min_step:
                return xs, sides, ("newton_failure", "the tangent or the tests fail")
            continue
        # The first event along the step: a bound of the plane or a test's zero.
        events = []
        for j, (lo, hi) in ((-2, bounds[0]), (-1, bounds[1])):
            for edge in (lo, hi):
                if (x[j] - edge) * (x_new[j] - edge) < 0:
                    events.append(("map_edge", (j, edge), f"{sysm.names[j + 2]} = {edge:g}"))
        for key, v in tests_new.items():
            if math.isfinite(v) and math.isfinite(tests[key]) and (v > 0) != (tests[key] > 0):
                events.append((key, _test(sysm, key, t_ref), key.replace("_", " ")))
        located = []
        for key, fn, detail in events:
            edge = fn if key == "map_edge" else None
            hit = _locate(sysm, x, t, h, (lambda y, e=edge: y[e[0]] - e[1]) if edge else fn)
            if hit is not None and edge:
                # On the bound exactly: Newton with that parameter held there.
                y = hit[1].copy()
                y[edge[0]] = edge[1]
                hit = (hit[0], sysm.correct(y, np.zeros(len(y)), 0.0, fixed=edge[0])[0])
            if hit is not None and hit[1] is not None:
                located.append((hit[0], key, hit[1], detail))
        if not located and any(e[0] == "inadmissible" for e in events):
            # (The least velocity or gap can jump, e.g. a new interior gap minimum: no zero to
            # locate; the curve ends at its last admissible point.)
            return xs, sides, ("inadmissible", f"between ({x[-2]:.8g}, {x[-1]:.8g}) and the next step")
        if located:
            s_hit, key, x_hit, detail = min(located, key=lambda e: e[0])
            xs.append(x_hit)
            sides.append(sysm.stable_side(x_hit, t_new))
            where = f" at ({x_hit[-2]:.8g}, {x_hit[-1]:.8g})"
            return xs, sides, (key, detail + where)
        xs.append(x_new)
        sides.append(sysm.stable_side(x_new, t_new))
        if len(xs) > 10 and sysm.norm(x_new - start) < 0.5 * h:
            return xs, sides, ("closed", "the curve comes back to its seed")
        x, t, tests = x_new, t_new, tests_new
        h = min(h * 1.5, max_step) if its <= 5 else (h * 0.7 if its >= 9 else h)
        h = max(h, min_step)
    return xs, sides, ("max_points", f"{max_points} points")


def _test(sysm: _System, key: str, t_ref: np.ndarray):
    def fn(x: np.ndarray) -> float:
        t = sysm.tangent(x, np.append(np.zeros(len(x) - 2), t_ref)) if key == "cusp" else None
        if t is not None and t[-2:] @ t_ref < 0:
            t = -t
        return sysm.codim2_tests(x, t[-2:] if t is not None else t_ref, t_ref)[key]

    return fn


def _locate(sysm: _System, x0: np.ndarray, t0: np.ndarray, h: float, fn):
    """(arclength, point) of a zero of fn between x0 and the step h along t0 (Brent), or None."""
    import scipy.optimize  # (loaded on first use: the package import stays light)

    cache = {}

    def f(s: float) -> float:
        x, _ = sysm.correct(x0, t0, s) if s > 0 else (x0, 0)
        if x is None:
            raise OrbitError("corrector failed while locating an end")
        cache[s] = x
        return fn(x)

    try:
        s_star = scipy.optimize.brentq(f, 0.0, h, xtol=1e-12 * max(1.0, h))
        if s_star not in cache:
            f(s_star)
        return s_star, cache[s_star]
    except (OrbitError, ValueError, RuntimeError, np.linalg.LinAlgError):
        return None


def curve_point(curve: Curve, value: float) -> tuple[float, np.ndarray]:
    """The curve's point with its second parameter at ``value`` (Newton from the nearest
    point with that parameter held): (first parameter, shooting unknowns)."""
    i = int(np.argmin(np.abs(curve.points[:, 1] - value)))
    sysm = _System(
        curve.p, curve.names, curve.period_multiple, curve.impacts_per_cycle, curve.kind, curve.index, (1, 1)
    )
    x0 = np.concatenate([curve.unknowns[i], [curve.points[i, 0], value]])
    x, _ = sysm.correct(x0, np.zeros(len(x0)), 0.0, fixed=-1, max_iterations=30)
    if x is None:
        raise OrbitError(f"no {curve.kind} point of the {curve.label} cycle at {curve.names[1]} = {value!r}")
    return float(x[-2]), x[:-2]
