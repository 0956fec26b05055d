"""The augmented shooting system of a codimension-one point, one per kind (Timofeev et al. 2019
eqs. 18-22), and the pseudo-arclength steps on it: what :mod:`~impactdamper.analysis.curves`
follows.

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
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper.analysis.shooting import ORBIT_TOL, OrbitError, Shooting, monodromy_matrix
from impactdamper.analysis.sweeps import with_value
from impactdamper.core.events import Segment
from impactdamper.core.linear import free_mode
from impactdamper.core.model import Model
from impactdamper.core.parameters import Parameters

KINDS = ("fold", "period_doubling", "neimark_sacker", "grazing_velocity", "grazing_touch")
# The one-parameter table's names of the kinds (SpecialPoint.kind) -> the curve kinds.
_FROM_SPECIAL = {"grazing_interior": "grazing_touch"}
# Forward-difference steps: in the relative unknowns u, and relative to max(1, |parameter|).
FD_STEP_U, FD_STEP_P = 1e-7, 1e-6
# Corrector: converged when the last step's max norm is below this (relative) and the residual
# below 100 ORBIT_TOL. The iteration is a chord one with a finite-difference row (linear
# convergence): the error left is about the last step times the contraction.
CORRECTOR_TOL = 1e-8
# Samples per flight of a gap minimum's search and of the admissibility check (an interior
# minimum narrower than 1/128 of a flight can be missed).
FLIGHT_SAMPLES = 128


def curve_kind(special_kind: str) -> str:
    """The curve kind of a one-parameter special point's kind (``grazing_interior`` is a
    grazing touch)."""
    return _FROM_SPECIAL.get(special_kind, special_kind)


class _FlightModel:
    """What the shooting equations read of a :class:`Model` (``p``, the free mode, the gap of
    eq. 20), without the rest: a curve moves both parameters at every corrector iteration, so
    each :class:`Shooting` needs a new model, and the stuck mode and the event functionals that
    :class:`Model` also builds (unused by the shooting) were about half of its cost, a sixth of
    the curves' processor time (profiled, theta plane)."""

    gap_of = Model.gap_of

    def __init__(self, p: Parameters):
        self.p, self.free = p, free_mode(p)


class CurveSystem:
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
            pair = complex_pair(np.linalg.eigvals(self.monodromy(x)))
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

    def multipliers(self, x: np.ndarray) -> np.ndarray:
        return np.linalg.eigvals(self.monodromy(x))


def complex_pair(mult: np.ndarray):
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


def tracked_index(s: Shooting, u: np.ndarray, kind: str) -> int:
    """The impact with the least closing velocity, or the flight with the least interior gap."""
    if kind == "grazing_velocity":
        _, _, _, before, _ = s.flights(u)
        return int(np.argmin(before[:, 3] - before[:, 2]))
    if kind == "grazing_touch":
        return int(np.argmin([_flight_minimum(s, u, i) for i in range(s.z)]))
    return -1
