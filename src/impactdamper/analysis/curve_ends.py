"""Where a followed boundary curve ends, and what each of its points tells.

Along a curve of :mod:`~impactdamper.analysis.curves`, each point is read for the side of the
curve where its cycle is stable (:func:`stable_side`) and for the test functions whose sign
change ends the curve (:func:`codim2_tests`): a codimension-two point (``cusp`` of folds: the
curve's direction in the plane reverses; ``fold_flip``: a fold and a period doubling meet;
``resonance_1_1`` / ``resonance_1_2`` / ``resonance_1_3`` on a Neimark-Sacker curve: the
pair's argument reaches 0, pi or 2 pi/3) or an inadmissible cycle (another impact's velocity or
another flight's sampled interior gap minimum reaches zero). A step
across one of them or across a bound of the plane is cut at the first such end, located by
Brent's method on the arclength (:func:`end_on_step`). Every end's reason is one of
:data:`END_REASONS`.
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper.analysis.curve_system import FLIGHT_SAMPLES, CurveSystem, complex_pair
from impactdamper.analysis.shooting import OrbitError

CODIM2_REASONS = ("cusp", "fold_flip", "resonance_1_1", "resonance_1_2", "resonance_1_3")
END_REASONS = CODIM2_REASONS + ("map_edge", "inadmissible", "newton_failure", "closed", "max_points")
# The negative gap (relative) that counts as a crossing in the admissibility check.
CROSSING_TOL = 1e-9


def _admissibility(sysm: CurveSystem, x: np.ndarray) -> float:
    """Least closing velocity (over x_st omega) and sampled interior gap minimum (over
    x_st) of the impacts and flights other than the tracked one: negative where the
    cycle's impact sequence no longer describes the motion."""
    s = sysm.shooting(x[-2], x[-1])
    t, _, y, before, t_next = s.flights(x[:-2])
    v = (before[:, 3] - before[:, 2]) / (s.p.x_st * s.p.omega)
    if sysm.kind == "grazing_velocity":
        v = np.delete(v, sysm.index)
    least = float(np.min(v)) if len(v) else math.inf
    for i in range(sysm.z):
        if sysm.kind == "grazing_touch" and i == sysm.index:
            continue
        ts = np.linspace(t[i], t_next[i], FLIGHT_SAMPLES + 1)[1:-1]
        gaps = s.model.gap_of(s.mode.states_from(ts, np.full(len(ts), t[i]), np.tile(y[i], (len(ts), 1)))) / s.p.x_st
        least = min(least, float(np.min(gaps)) + CROSSING_TOL)
    return least


def codim2_tests(sysm: CurveSystem, x: np.ndarray, plane_tangent: np.ndarray, t_ref: np.ndarray) -> dict:
    """The functions whose zeros end the curve at a codimension-two point."""
    tests = {"inadmissible": _admissibility(sysm, x)}
    if sysm.kind == "fold":
        tests["fold_flip"] = float(np.linalg.det(sysm.monodromy(x) + np.eye(4)))
        tests["cusp"] = float(plane_tangent @ t_ref)
    elif sysm.kind == "period_doubling":
        tests["fold_flip"] = float(np.linalg.det(sysm.monodromy(x) - np.eye(4)))
    elif sysm.kind == "neimark_sacker":
        pair = complex_pair(sysm.multipliers(x))
        if pair is None:
            tests["resonance_1_1"] = -1.0
        else:
            angle = abs(math.atan2(pair.imag, pair.real))
            tests["resonance_1_1"] = angle
            tests["resonance_1_2"] = math.pi - angle
            tests["resonance_1_3"] = angle - 2 * math.pi / 3
    return tests


def stable_side(sysm: CurveSystem, x: np.ndarray, t: np.ndarray) -> str:
    """The side of the curve (in the plane, along the axis nearer its normal) where the
    cycle is stable; ``none`` if unstable on both; ``""`` for folds and grazings."""
    if sysm.kind not in ("period_doubling", "neimark_sacker"):
        return ""
    mult = sysm.multipliers(x)
    crit = (
        int(np.argmin(np.abs(mult + 1.0)))
        if sysm.kind == "period_doubling"
        else int(np.argmin(np.abs(np.abs(mult) - 1.0)))
    )
    others = np.delete(mult, crit)
    if sysm.kind == "neimark_sacker":
        others = others[np.argsort(np.abs(others - np.conj(mult[crit])))[1:]]
    if np.any(np.abs(others) >= 1.0):
        return "none"
    # g's sign on the stable side: det(I + M) = (1 + lambda_c) prod(1 + lambda_others).
    stable_sign = np.sign(np.prod(1.0 + others).real) if sysm.kind == "period_doubling" else -1.0
    scale = 1.0 / np.sqrt(sysm.W[-2:])
    tp = t[-2:] / scale
    normal = np.array([-tp[1], tp[0]]) * scale  # in the parameters' own units
    _, A = sysm.jacobian(x)
    n = 5 * sysm.z
    du = np.linalg.lstsq(A[:n, :n], -(A[:n, n:] @ normal), rcond=None)[0]
    dg = A[n, :n] @ du + A[n, n:] @ normal
    axis = 0 if abs(normal[0] / scale[0]) >= abs(normal[1] / scale[1]) else 1
    sign = np.sign(normal[axis]) * np.sign(dg) * stable_sign
    return sysm.names[axis] + ("+" if sign > 0 else "-")


def end_on_step(sysm: CurveSystem, x, t, h: float, x_new, tests: dict, tests_new: dict, t_ref, bounds):
    """The first end on the step of arclength ``h`` from x (tangent t) to x_new, whose tests
    are ``tests`` and ``tests_new``: a bound of the plane crossed or a test's sign change,
    located. None where the step crosses none; else (the end's point, or None where the curve
    ends at x, inadmissible without a zero to locate; (reason, detail))."""
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
        return None, ("inadmissible", f"between ({x[-2]:.8g}, {x[-1]:.8g}) and the next step")
    if located:
        s_hit, key, x_hit, detail = min(located, key=lambda e: e[0])
        where = f" at ({x_hit[-2]:.8g}, {x_hit[-1]:.8g})"
        return x_hit, (key, detail + where)
    return None


def _test(sysm: CurveSystem, key: str, t_ref: np.ndarray):
    def fn(x: np.ndarray) -> float:
        t = sysm.tangent(x, np.append(np.zeros(len(x) - 2), t_ref)) if key == "cusp" else None
        if t is not None and t[-2:] @ t_ref < 0:
            t = -t
        return codim2_tests(sysm, x, t[-2:] if t is not None else t_ref, t_ref)[key]

    return fn


def _locate(sysm: CurveSystem, x0: np.ndarray, t0: np.ndarray, h: float, fn):
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
