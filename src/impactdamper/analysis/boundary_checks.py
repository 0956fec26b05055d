"""The boundary curves of a regime map read against its cells, and checked by brute force.

Three readings (``figures/boundaries_check.json``):

* :func:`label_changes_near_curves`: the share of the map's label changes (adjacent cells of
  different labels, along either axis) that lie within one cell of a curve, and the curves along
  which no label change lies within one cell (a coexistence the one-way map cannot see, or a
  boundary of an unstable cycle).
* :func:`side_checks`: at points along each continued curve, the event-driven simulation
  (:func:`~impactdamper.analysis.solve.steady_state`, :func:`~impactdamper.analysis.solve.simulate`)
  run on each side at a distance of a fraction of the plane's span along the curve's normal,
  started on the curve's cycle (re-solved there by Newton where it converges) slightly perturbed.
  A point whose side offset crosses another boundary of the same cycle (:func:`crossed_curve`)
  tests that boundary as well as its own: it is run and reported, but counted apart
  (``crossing``), not among the observed points; it is run again at half the distance to the
  nearest such crossing, where the side segment crosses none, and that verdict is counted apart
  too (``reduced_observed``, ``reduced_agree``).
  Fold, period doubling, Neimark-Sacker: the check agrees when the cycle comes back on one side
  only (the stable side the curve states, where it states one) and is lost on the other. Grazing
  with zero velocity or touch: when one cycle of the simulation has the cycle's impacts (as many,
  at its times) on one side only; on the other it loses or gains an impact.
* :func:`period_doubling_bisection`: a period-doubling curve's gap at a few values of the second
  parameter against a bisection of the settled period multiple in the gap by simulation.
"""

from __future__ import annotations

import math

import numpy as np

from impactdamper.analysis.curves import Curve, curve_point
from impactdamper.analysis.point import label_of
from impactdamper.analysis.shooting import OrbitError, Shooting
from impactdamper.core.parameters import state_scale
from impactdamper.analysis.sweeps import with_value
from impactdamper.core.events import Segment
from impactdamper.core.model import Model
from impactdamper.analysis.solve import simulate, steady_state

__all__ = ["label_changes_near_curves", "side_checks", "period_doubling_bisection", "SIDE_COUNTS"]

# The counts of side_checks' result, summed over curves and planes in the record.
SIDE_COUNTS = (
    "points",
    "observed",
    "changed",
    "agree",
    "doubled",
    "agree_at_a_tenth",
    "unobserved",
    "crossing",
    "reduced_observed",
    "reduced_agree",
)

# The simulation of a side check: settled to this (relative), within this many periods, k <= 8.
# (Near a period doubling the new cycle's multiplier is near -1 too: 20000 periods, which the
# compiled kernels run in milliseconds, settle it at the side checks' distance.)
SETTLE_TOL, MAX_PERIODS, MAX_K = 1e-9, 20000, 8
# A side run starts this far (in the state scale) off the followed cycle, and has returned to it
# when its last sections are within RETURN_TOL of the cycle's state at the start's phase.
PERTURBATION, RETURN_TOL = 1e-6, 1e-4
# A grazing side run reproduces the cycle when its impacts are at the cycle's within this (of T).
IMPACT_TIME_TOL = 1e-6
# The cycle continued to a side point (_on_cycle): the first step this fraction of the way; a
# step halved on failure down to this fraction of the way done (of the first step at the start).
PATH_FIRST, PATH_SMALLEST = 1e-3, 1e-2
# Newton iterations of a path step (from the secant predictor it converges in a few; a step that
# does not within this many is halved, rather than iterated to Shooting.newton's default 40).
PATH_NEWTON_ITERATIONS = 10
# Another curve is a boundary of the same cycle where its cycle has the same z/k and, at the
# crossing, its impact phases (times mod k T, over T, up to a shift by whole periods) are within
# this of the followed cycle's: distinct cycles of one z/k differ by far more, the same cycle
# 1e-3 of the span away by about that.
SAME_CYCLE_PHASE_TOL = 0.05
# A point whose side segment crosses another boundary of its cycle is checked again at half the
# distance to that crossing; the halving is repeated at most this many times (_reduced_distance).
REDUCE_TRIES = 4
_DIRECTION = np.array([0.5, -0.5, 0.5, -0.5])


def _polyline_distance(P: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Distance from each point X (m, 2) to the polyline P (n, 2), same units."""
    if len(P) == 1:
        return np.hypot(*(X - P[0]).T)
    best = np.full(len(X), np.inf)
    A, D = P[:-1], P[1:] - P[:-1]
    dd = np.maximum(np.einsum("ij,ij->i", D, D), 1e-300)
    for start in range(0, len(A), 256):
        a, d, w = A[start : start + 256], D[start : start + 256], dd[start : start + 256]
        t = np.clip(((X[:, None, :] - a[None]) * d[None]).sum(-1) / w[None], 0.0, 1.0)
        q = a[None] + t[..., None] * d[None]
        best = np.minimum(best, np.hypot(*(q - X[:, None, :]).transpose(2, 0, 1)).min(axis=1))
    return best


def label_changes_near_curves(slow: np.ndarray, gaps: np.ndarray, labels: np.ndarray, curves: dict) -> dict:
    """The map's label changes against the curves, distances in cells.

    Parameters
    ----------
    slow : ndarray, shape (rows,)
    gaps : ndarray, shape (columns,)
    labels : ndarray of str, shape (rows, columns)
    curves : dict
        Curve id -> ndarray, shape (n, 2), of (gap, slow) points.

    Returns
    -------
    dict
        ``changes`` (count), ``within_one_cell`` (count and ``share``), the same without changes
        to or from ``np`` cells, and ``curves_without_change`` (ids).
    """
    cell = np.array([gaps[1] - gaps[0], slow[1] - slow[0]])
    G, S = np.meshgrid(gaps, slow)
    mids, involves_np = [], []
    for axis in (1, 0):
        a, b = (labels[:, :-1], labels[:, 1:]) if axis == 1 else (labels[:-1], labels[1:])
        g = 0.5 * ((G[:, :-1] + G[:, 1:]) if axis == 1 else (G[:-1] + G[1:]))
        s = 0.5 * ((S[:, :-1] + S[:, 1:]) if axis == 1 else (S[:-1] + S[1:]))
        m = a != b
        mids.append(np.column_stack([g[m], s[m]]))
        involves_np.append((a[m] == "np") | (b[m] == "np"))
    X = np.vstack(mids) / cell
    np_mask = np.concatenate(involves_np)
    near = np.zeros(len(X), bool)
    without = []
    for cid, P in curves.items():
        d = _polyline_distance(np.asarray(P) / cell, X)
        hit = d <= 1.0
        near |= hit
        if not hit.any():
            without.append(cid)
    n, n_np = len(X), int((~np_mask).sum())
    return {
        "changes": n,
        "within_one_cell": int(near.sum()),
        "share": float(near.sum() / n) if n else math.nan,
        "changes_without_np": n_np,
        "within_one_cell_without_np": int((near & ~np_mask).sum()),
        "share_without_np": float((near & ~np_mask).sum() / n_np) if n_np else math.nan,
        "curves_without_change": without,
    }


def _settled_label(p, t0: float, state: np.ndarray) -> str:
    """Peterka's label of the motion the simulation settles on from (t0, state)."""
    try:
        s = steady_state(
            p, t0=t0, state=state, settle_tol=SETTLE_TOL, max_periods=MAX_PERIODS, max_period_multiple=MAX_K
        )
    except ValueError as err:
        return "err: " + str(err).split(":")[0]
    return label_of(s.regime, s.period_multiple, len(s.impacts))


def _start(curve: Curve, unknowns: np.ndarray, a: float, b: float):
    """(t0, state) on the cycle where its gap is widest (of 64 samples per flight): a start that
    stays valid when the side checks move the stop."""
    p = with_value(with_value(curve.p, curve.names[0], a), curve.names[1], b)
    s = Shooting(p, curve.period_multiple, curve.impacts_per_cycle)
    t, tau, y, _, _ = s.flights(unknowns)
    model, best = Model(p), (-np.inf, 0.0, None)
    for i in range(len(t)):
        seg = Segment(model.free, float(t[i]), y[i])
        ts = t[i] + tau[i] * np.linspace(0.05, 0.95, 64)
        states = seg.state(ts)
        gaps = model.gap_of(states)
        j = int(np.argmax(gaps))
        if gaps[j] > best[0]:
            best = (gaps[j], float(ts[j]), states[j])
    return best[1], best[2]


def _side_params(curve: Curve, q: np.ndarray):
    return with_value(with_value(curve.p, curve.names[0], float(q[0])), curve.names[1], float(q[1]))


def _on_cycle(curve: Curve, u: np.ndarray, start: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, bool]:
    """The followed cycle's unknowns at the plane's point ``q``, continued from ``u`` at the
    curve's point ``start`` along the straight path between them (and whether it was solved at
    ``q``; else ``u`` itself).

    Newton from ``u`` at ``q`` directly can land on another cycle or fail: along a grazing curve
    the cycle moves by ~1e4 of its unknowns per span (its saltation matrix ~ 1/v), so at 1e-3 of
    the span it is far from ``u``. The path takes a first step of :data:`PATH_FIRST` of the way,
    then each three times the last, with a secant predictor, halving a step Newton fails on; where
    the path stops short (the cycle folds or turns singular on the way), Newton at ``q`` from ``u``.
    """
    s, v, last, target = 0.0, np.array(u, float), None, PATH_FIRST
    while s < 1.0:
        s_new = min(1.0, target)
        guess = v if last is None else v + (v - last[1]) * (s_new - s) / (s - last[0])
        try:
            w, _, _ = Shooting(
                _side_params(curve, start + s_new * (q - start)), curve.period_multiple, curve.impacts_per_cycle
            ).newton(guess, PATH_NEWTON_ITERATIONS)
        except (OrbitError, ValueError, np.linalg.LinAlgError):
            if s_new - s < PATH_SMALLEST * (1.0 if s == 0.0 else s):
                break
            target = s + 0.5 * (s_new - s)
            continue
        last, s, v, target = (s, v), s_new, w, 3.0 * s_new
    if s == 1.0:
        return v, True
    # The path stops (the cycle folds or becomes singular on the way): Newton at q from u.
    try:
        v, _, _ = Shooting(_side_params(curve, q), curve.period_multiple, curve.impacts_per_cycle).newton(
            np.array(u, float)
        )
        return v, True
    except (OrbitError, ValueError, np.linalg.LinAlgError):
        return np.array(u, float), False


def _reproduces(curve: Curve, v: np.ndarray, p, t0: float, y0: np.ndarray) -> bool:
    """The simulation over one cycle (k T) from the cycle ``v``'s state at ``t0`` has the
    cycle's impacts: as many, each at its time within :data:`IMPACT_TIME_TOL` T (modulo k T).
    False where the cycle gains an impact (a flight that crosses the stop) or loses one (an
    impact the motion reaches otherwise, or not at all)."""
    z, Tc = curve.impacts_per_cycle, curve.period_multiple * p.T
    try:
        found = np.array([e.t for e in simulate(p, t0 + Tc, t0=t0, state=y0).impacts()])
    except ValueError:
        return False
    if len(found) != z:
        return False
    own = np.asarray(v[:z]) * p.T
    d = np.abs(((found[:, None] - own[None, :]) + 0.5 * Tc) % Tc - 0.5 * Tc).min(axis=1)
    return bool(np.all(d < IMPACT_TIME_TOL * p.T))


def _followed_run(curve: Curve, u: np.ndarray, q: np.ndarray, start: np.ndarray) -> dict:
    """A brute-force run at the plane's point ``q`` started on the followed cycle (continued to
    ``q`` from ``u`` at the curve's point ``start``, :func:`_on_cycle`, else ``u``'s) plus a
    perturbation of :data:`PERTURBATION` of the state scale.

    Returns
    -------
    dict
        ``label`` (settled), ``impacts_per_period`` (settled, or over the nonperiodic window;
        inf for chatter), ``returns`` (settled on the followed cycle: its label and, at the
        start's phase, within :data:`RETURN_TOL` of its state in the state scale), ``solved``.
    """
    p = _side_params(curve, q)
    v, solved = _on_cycle(curve, u, np.asarray(start, float), np.asarray(q, float))
    t0, y0 = _start(curve, v, float(q[0]), float(q[1]))
    D = state_scale(p)
    start = y0 + PERTURBATION * D * _DIRECTION
    try:
        s = steady_state(
            p, t0=t0, state=start, settle_tol=SETTLE_TOL, max_periods=MAX_PERIODS, max_period_multiple=MAX_K
        )
    except ValueError as err:
        label, rate, distance = "err: " + str(err).split(":")[0], None, math.inf
        return {"label": label, "reproduced": False, "impacts_per_period": rate, "returns": False, "solved": solved}
    label = label_of(s.regime, s.period_multiple, len(s.impacts))
    k = curve.period_multiple
    sec = np.asarray(s.sections)
    # The last section a whole number of cycles after the start (section j is at t0 + (j + 1) T).
    last = [j for j in range(len(sec) - 1, -1, -1) if (j + 1) % k == 0][:1]
    distance = float(np.max(np.abs(sec[last[0]] - y0) / D)) if last else math.inf
    # Returned: settled on the cycle, or (a multiplier near the unit circle: slow) still on the
    # way back, the perturbation shrunk to under half its start.
    back = distance < (RETURN_TOL if label == curve.label else 0.5 * PERTURBATION * np.max(np.abs(_DIRECTION)))
    if s.regime == "chatter":
        rate = math.inf
    else:
        rate = len(s.impacts) / max(round(s.cycle_duration / p.T), 1)
    return {
        "label": label,
        "reproduced": _reproduces(curve, v, p, t0, y0) if solved else False,
        "impacts_per_period": rate,
        "returns": bool(back),
        "solved": solved,
    }


def _expected_return(curve: Curve, i: int, side_vec: np.ndarray):
    """True/False: the cycle is stable on the side ``side_vec`` (a vector in the plane's spans
    from the curve) by the curve's ``stable_side``; None where that does not apply."""
    tag = curve.stable_side[i] if i < len(curve.stable_side) else ""
    if tag in ("", "none"):
        return None
    axis = 0 if tag[:-1] == curve.names[0] else 1
    return bool(np.sign(side_vec[axis]) == (1 if tag.endswith("+") else -1))


def _verdict(curve: Curve, i: int, runs: list, normal: np.ndarray):
    """Of the two sides' runs (+normal, -normal): None (the followed cycle returns on neither:
    not stable there, unobservable by simulation; ``other`` where ``stable_side`` says it is
    stable on one side), ``same`` (it returns on both: no boundary),
    ``agree`` or ``other`` (it returns on one side only; agree when that side is the stable one
    of ``stable_side`` where stated, and, for the grazing kinds, the other side's impacts per
    period differ from the cycle's z/k)."""
    if curve.kind in ("grazing_velocity", "grazing_touch"):
        real = [r["reproduced"] for r in runs]
        return "same" if all(real) else ("agree" if any(real) else "other")
    back = [r["returns"] for r in runs]
    if not any(back):
        # Unobservable, unless the curve says the cycle is stable on one side here.
        return "other" if curve.stable_side[i] not in ("", "none") else None
    if all(back):
        return "same"
    ret = 0 if back[0] else 1
    expected = _expected_return(curve, i, (1 - 2 * ret) * normal)
    if expected is False:
        return "other"
    return "agree"


def _segment_crossings(a: np.ndarray, b: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Indices j where the segment a-b crosses the polyline's piece Q[j]-Q[j+1] (2-D)."""
    if len(Q) < 2:
        return np.zeros(0, int)
    c, d = Q[:-1], Q[1:]

    def side(p, q, r):  # sign of the turn p -> q -> r
        return np.sign(
            (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])
        )

    hit = (side(a, b, c) * side(a, b, d) <= 0) & (side(c, d, a) * side(c, d, b) <= 0)
    return np.flatnonzero(hit)


def _same_cycle(curve: Curve, u: np.ndarray, other: Curve, v: np.ndarray) -> bool:
    """Whether ``other``'s cycle ``v`` is ``curve``'s cycle ``u`` (see :data:`SAME_CYCLE_PHASE_TOL`)."""
    if (other.period_multiple, other.impacts_per_cycle) != (curve.period_multiple, curve.impacts_per_cycle):
        return False
    k, z = curve.period_multiple, curve.impacts_per_cycle
    mine, theirs = np.asarray(u[:z]) % k, np.asarray(v[:z]) % k
    for shift in range(k):
        d = np.abs((mine[:, None] + shift - theirs[None, :]) % k)
        if np.max(np.min(np.minimum(d, k - d), axis=1)) < SAME_CYCLE_PHASE_TOL:
            return True
    return False


def _crossing_distance(p: np.ndarray, normal: np.ndarray, Q: np.ndarray, j: int) -> float:
    """The distance from ``p`` along the line through it with direction ``normal`` (unit, both
    2-D, in the plane's spans) to the polyline's piece Q[j]-Q[j+1] that crosses that line."""
    c, e = Q[j], Q[j + 1] - Q[j]
    den = normal[0] * e[1] - normal[1] * e[0]
    if den == 0.0:  # the piece lies along the side segment: its nearer end
        return float(min(abs(np.dot(c - p, normal)), abs(np.dot(Q[j + 1] - p, normal))))
    return float(abs(((c - p)[0] * e[1] - (c - p)[1] * e[0]) / den))


def _crossed_curve(curve: Curve, i: int, a: np.ndarray, b: np.ndarray, others: dict, spans: np.ndarray):
    """(id, distance) of the nearest crossing, along the side segment a-b (plane units) through
    point ``i`` from its middle (in the plane's spans), of another curve of the same cycle, or
    None where none crosses: there the side runs meet that boundary too (e.g. a period
    doubling 1e-5 of the span from the cycle's fold: on the fold's far side the cycle is lost
    whatever the period doubling says). A grazing curve of the other grazing kind that passes
    within a tenth of the half segment of the point is the same tangency, not another boundary:
    an impact at zero velocity is a flight that touches the stop at its end (the touch curves
    found so coincide with the zero-velocity ones to ~1e-6 of the span)."""
    grazings = ("grazing_velocity", "grazing_touch")
    mid, half = 0.5 * (a + b) / spans, 0.5 * float(np.hypot(*((b - a) / spans)))
    direction = (b - a) / spans / (2.0 * half) if half > 0 else np.zeros(2)
    nearest = None
    for cid, other in others.items():
        if other is curve:
            continue
        if (
            curve.kind in grazings
            and other.kind in grazings
            and other.kind != curve.kind
            and _polyline_distance(other.points / spans, mid[None])[0] <= 0.1 * half
        ):
            continue
        for j in _segment_crossings(a / spans, b / spans, other.points / spans):
            if _same_cycle(curve, curve.unknowns[i], other, other.unknowns[j]) or _same_cycle(
                curve, curve.unknowns[i], other, other.unknowns[j + 1]
            ):
                d = _crossing_distance(mid, direction, other.points / spans, j)
                if nearest is None or d < nearest[1]:
                    nearest = (cid, d)
    return nearest


def _reduced_distance(curve: Curve, i: int, normal: np.ndarray, spans: np.ndarray, nearest: float, others: dict):
    """The side distance (of the span) for a point whose side segment crosses another boundary of
    its cycle ``nearest`` (of the span) from it: half that, so that the shorter segment crosses
    none (halved again, at most REDUCE_TRIES times, should a closer one appear: a grazing of the
    other kind is told apart by its distance relative to the segment). Returns (distance, the
    nearest crossing left or None)."""
    reduced = 0.5 * nearest
    for _ in range(REDUCE_TRIES):
        offset = reduced * normal * spans
        left = _crossed_curve(curve, i, curve.points[i] - offset, curve.points[i] + offset, others, spans)
        if left is None or reduced <= 0:
            return reduced, left
        reduced = 0.5 * left[1]
    return reduced, left


def side_checks(curve: Curve, bounds, points: int = 20, distance: float = 1e-3, others: dict | None = None) -> dict:
    """Brute-force runs on both sides of ``points`` points along a continued curve.

    The points are evenly spaced in index, ends excluded; each side point lies ``distance``
    times the plane's span (per axis) along the curve's normal, inside the plane. Each side's run
    starts on the followed cycle (:func:`followed_run`) and the verdict (:func:`_verdict`) asks
    whether the cycle changes across the curve as its kind says: it persists and returns on one
    side only (a lost cycle: fold, period doubling, Neimark-Sacker, on the side ``stable_side``
    says where it is stated), and, for a grazing, the other side's settled motion has another
    number of impacts per period. A point whose side segment crosses another curve of ``others``
    (id -> :class:`Curve`, the plane's) of the same cycle (:func:`crossed_curve`) is run and
    reported but counted apart, and run again at half the distance to the nearest such crossing
    (:func:`_reduced_distance`), where its side segment crosses none: its genuine verdict.

    Returns
    -------
    dict
        ``points``, ``observed`` (the cycle returns on one side at least), ``changed`` (on one
        side only), ``agree``, ``doubled`` (period doublings whose other side settled on 2k),
        ``unobserved`` (returns on neither side), and ``disagree`` (every observed point that
        does not agree: (gap, value), both sides' labels and returns, and the same a tenth as far
        from the curve), ``agree_at_a_tenth`` (of the disagreements), ``crossing`` (points whose
        side segment crosses another curve of the same cycle, not counted above) and ``crossings``
        (each: (gap, value), the other curve's id, the crossing's distance, the verdict at
        ``distance``, the reduced distance and the verdict there); ``reduced_observed`` and
        ``reduced_agree`` (of the crossing points, at the reduced distance) and
        ``smallest_reduced_distance``.
    """
    spans = np.array([bounds[0][1] - bounds[0][0], bounds[1][1] - bounds[1][0]])
    n = len(curve.points)
    idx = sorted(set(np.linspace(0, n - 1, points + 2).round().astype(int)[1:-1])) if n > 2 else []
    out = {
        "points": 0,
        "observed": 0,
        "agree": 0,
        "changed": 0,
        "doubled": 0,
        "unobserved": 0,
        "crossing": 0,
        "reduced_observed": 0,
        "reduced_agree": 0,
        "disagree": [],
        "crossings": [],
    }
    P = curve.points / spans
    for i in idx:
        j0, j1 = max(i - 1, 0), min(i + 1, n - 1)
        tvec = P[j1] - P[j0]
        if not np.any(tvec):
            continue
        normal = np.array([-tvec[1], tvec[0]]) / np.hypot(*tvec)

        def sides(dist: float) -> list:
            return [
                _followed_run(curve, curve.unknowns[i], curve.points[i] + sg * dist * normal * spans, curve.points[i])
                for sg in (1, -1)
            ]

        runs = sides(distance)
        out["points"] += 1
        verdict = _verdict(curve, i, runs, normal)
        offset = distance * normal * spans
        crossed = _crossed_curve(curve, i, curve.points[i] - offset, curve.points[i] + offset, others or {}, spans)
        if crossed is not None:
            _count_crossing(out, curve, i, crossed, verdict, sides, normal, spans, others)
            continue
        _count_point(out, curve, i, runs, verdict, lambda: sides(0.1 * distance), normal)
    out["agree_at_a_tenth"] = sum(d["agree_at_a_tenth"] for d in out["disagree"])
    out["smallest_reduced_distance"] = min((c["reduced_distance"] for c in out["crossings"]), default=None)
    return out


def _count_crossing(out: dict, curve: Curve, i: int, crossed, verdict, sides, normal, spans, others) -> None:
    """Point ``i``, whose side segment crosses ``crossed`` = (another curve's id, the distance of
    the crossing), counted apart in ``out`` (see :func:`side_checks`), with its verdict run again
    at half the distance to the closest crossing (``sides(distance)``: the two side runs)."""
    a, b = curve.points[i]
    out["crossing"] += 1
    reduced, _ = _reduced_distance(curve, i, normal, spans, crossed[1], others)
    verdict_near = _verdict(curve, i, sides(reduced), normal) if reduced > 0 else None
    out["crossings"].append(
        {
            "gap": float(a),
            curve.names[1]: float(b),
            "crosses": crossed[0],
            "crossing_distance": crossed[1],
            "verdict": verdict or "unobserved",
            "reduced_distance": reduced,
            "reduced_verdict": verdict_near or "unobserved",
        }
    )
    out["reduced_observed"] += int(verdict_near is not None)
    out["reduced_agree"] += int(verdict_near == "agree")


def _count_point(out: dict, curve: Curve, i: int, runs: list, verdict, closer_runs, normal) -> None:
    """Point ``i``'s side runs and verdict counted into ``out`` (see :func:`side_checks`) as
    observed or not, and a disagreement with the runs a tenth as far from the curve
    (``closer_runs()``)."""
    if verdict is None:
        out["unobserved"] += 1
        return
    out["observed"] += 1
    out["changed"] += int(verdict != "same")
    if verdict == "agree":
        out["agree"] += 1
        k = curve.period_multiple
        other = runs[1] if runs[0]["returns"] else runs[0]
        out["doubled"] += int(curve.kind == "period_doubling" and other["label"].endswith(f"/{2 * k}"))
    else:
        closer = closer_runs()
        a, b = curve.points[i]
        out["disagree"].append(
            {
                "gap": float(a),
                curve.names[1]: float(b),
                "verdict": verdict,
                "sides": [r["label"] for r in runs],
                "returns": [r["returns"] for r in runs],
                "sides_at_a_tenth": [r["label"] for r in closer],
                "agree_at_a_tenth": _verdict(curve, i, closer, normal) == "agree",
            }
        )


def period_doubling_bisection(curve: Curve, values, offset: float = 1e-3, xtol: float = 1e-5) -> list:
    """The curve's gap at each value of the second parameter against a bisection in the gap of
    the settled period multiple (k against 2k) by simulation started on the curve's cycle.

    Returns
    -------
    list of dict
        ``value``, ``curve_gap``, ``bisected_gap`` (None when ``offset`` either side does not
        bracket k against 2k), ``difference``.
    """
    k = curve.period_multiple
    rows = []
    for v in values:
        gap, u = curve_point(curve, float(v))
        t0, y0 = _start(curve, u, gap, float(v))
        base = with_value(curve.p, curve.names[1], float(v))

        def kk(g: float) -> int:
            lab = _settled_label(base.replace(gap=g), t0, y0)
            return int(lab.split("/")[1]) if "/" in lab and not lab.startswith("c/") else -1

        lo, hi = gap - offset, gap + offset
        klo, khi = kk(lo), kk(hi)
        if {klo, khi} != {k, 2 * k}:
            rows.append({"value": float(v), "curve_gap": gap, "bisected_gap": None, "sides_k": [klo, khi]})
            continue
        while hi - lo > xtol:
            mid = 0.5 * (lo + hi)
            if kk(mid) == klo:
                lo = mid
            else:
                hi = mid
        g_b = 0.5 * (lo + hi)
        rows.append({"value": float(v), "curve_gap": gap, "bisected_gap": g_b, "difference": abs(g_b - gap)})
    return rows
