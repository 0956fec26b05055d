"""The boundary curves of a regime map read against its cells, and checked by brute force.

Three readings (``figures/boundaries_check.json``):

* :func:`label_changes_near_curves`: the share of the map's label changes (adjacent cells of
  different labels, along either axis) that lie within one cell of a curve, and the curves along
  which no label change lies within one cell (a coexistence the one-way map cannot see, or a
  boundary of an unstable cycle).
* :func:`side_checks`: at points along each continued curve, the event-driven simulation
  (:func:`~impactdamper.core.steady.steady_state`, no shooting code) started on the curve's cycle
  run on each side at a distance of a fraction of the plane's span along the curve's normal.
  The cycle is observed on a side when the settled label is the cycle's own; the check agrees
  when it is observed on one side only and the other side's label differs as the kind says
  (period doubling: the period multiple doubled; grazing with zero velocity: fewer impacts per
  period; grazing touch: more, or chatter; fold and Neimark-Sacker: another label).
* :func:`period_doubling_bisection`: a period-doubling curve's gap at a few values of the second
  parameter against a bisection of the settled period multiple in the gap by simulation.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from impactdamper.analysis.curves import Curve, curve_point
from impactdamper.analysis.point import label_of
from impactdamper.analysis.shooting import Shooting
from impactdamper.analysis.sweeps import with_value
from impactdamper.core.events import Segment
from impactdamper.core.model import Model
from impactdamper.analysis.solve import steady_state

__all__ = ["label_changes_near_curves", "side_checks", "period_doubling_bisection", "settled_label"]

# The simulation of a side check: settled to this (relative), within this many periods, k <= 8.
# (Near a period doubling the new cycle's multiplier is near -1 too: 20000 periods, which the
# compiled kernels run in milliseconds, settle it at the side checks' distance.)
SETTLE_TOL, MAX_PERIODS, MAX_K = 1e-9, 20000, 8


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


def settled_label(p, t0: float, state: np.ndarray) -> str:
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


def _ratio(label: str):
    if label.startswith("c/"):
        return math.inf
    if "/" not in label:
        return None
    z, k = label.split("/")
    return Fraction(int(z), int(k))


def _as_kind_says(kind: str, cycle: str, other: str) -> bool:
    if other == cycle or other.startswith("err"):
        return False
    r0, r1 = _ratio(cycle), _ratio(other)
    if kind == "period_doubling":
        k0, k1 = int(cycle.split("/")[1]), (int(other.split("/")[1]) if r1 not in (None, math.inf) else 0)
        return k1 > 0 and k1 % (2 * k0) == 0
    if kind == "grazing_velocity":
        return other == "0/1" or (r1 is not None and r1 < r0)
    if kind == "grazing_touch":
        return r1 is not None and r1 > r0
    return True


def side_checks(curve: Curve, bounds, points: int = 20, distance: float = 1e-3) -> dict:
    """Brute-force runs on both sides of ``points`` points along a continued curve.

    The points are evenly spaced in index, ends excluded; each side point lies ``distance``
    times the plane's span (per axis) along the curve's normal, inside the plane.

    Returns
    -------
    dict
        ``points``, ``observed`` (the cycle settles on one side at least), ``changed`` (on one
        side only), ``agree`` (and the other side's label as the kind says) and ``disagree``
        (list of the observed points that do not agree: (gap, value), both sides' labels, and the
        labels and verdict of the runs a tenth as far from the curve), ``agree_at_a_tenth`` (of
        the disagreements), ``unobserved``.
    """
    spans = np.array([bounds[0][1] - bounds[0][0], bounds[1][1] - bounds[1][0]])
    n = len(curve.points)
    idx = sorted(set(np.linspace(0, n - 1, points + 2).round().astype(int)[1:-1])) if n > 2 else []
    out = {"points": 0, "observed": 0, "agree": 0, "changed": 0, "unobserved": 0, "disagree": []}
    for i in idx:
        P = curve.points / spans
        j0, j1 = max(i - 1, 0), min(i + 1, n - 1)
        tvec = P[j1] - P[j0]
        if not np.any(tvec):
            continue
        normal = np.array([-tvec[1], tvec[0]]) / np.hypot(*tvec)
        a, b = curve.points[i]
        t0, y0 = _start(curve, curve.unknowns[i], a, b)

        def sides(dist: float) -> list:
            labels = []
            for sign in (+1, -1):
                qa, qb = curve.points[i] + sign * dist * normal * spans
                p = with_value(with_value(curve.p, curve.names[0], qa), curve.names[1], qb)
                labels.append(settled_label(p, t0, y0))
            return labels

        labels = sides(distance)
        out["points"] += 1
        verdict = _verdict(curve, labels)
        if verdict is None:
            out["unobserved"] += 1
            continue
        out["observed"] += 1
        out["changed"] += int(verdict != "same")
        if verdict == "agree":
            out["agree"] += 1
        else:
            # The same point a tenth as far from the curve: a disagreement there too is the curve's.
            closer = sides(0.1 * distance)
            out["disagree"].append(
                {
                    "gap": float(a),
                    curve.names[1]: float(b),
                    "sides": labels,
                    "sides_at_a_tenth": closer,
                    "agree_at_a_tenth": _verdict(curve, closer) == "agree",
                }
            )
    out["agree_at_a_tenth"] = sum(d["agree_at_a_tenth"] for d in out["disagree"])
    return out


def _verdict(curve: Curve, labels: list):
    """None (the cycle is on neither side), ``same`` (on both), ``agree`` (on one, the other's
    label as the kind says) or ``other``."""
    own = [lab == curve.label for lab in labels]
    if not any(own):
        return None
    if all(own):
        return "same"
    other = labels[1] if own[0] else labels[0]
    return "agree" if _as_kind_says(curve.kind, curve.label, other) else "other"


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
            lab = settled_label(base.replace(gap=g), t0, y0)
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
