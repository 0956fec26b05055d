"""The parameter set nearest to the stated one at which both of the paper's Fig. 2 claims hold,
searched in all seven relative parameters at once.

Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100, state the
reference case theta = 1, mu = 0.08, N = 0.5, delta1 = delta2 = 0.05, R = 0.7,
Delta0/x_st = -5.8 and claim there (a) Algorithm No. 1 (eqs. 7-17) gives a negative gap on
(t1, t2) and (b) Algorithm No. 2, from its step 1, settles to T_c = 2T with three impacts.
Neither holds at the stated point (:mod:`impactdamper.studies.replication.claims`). Here:

* **Distance.** A point is u in R^7, the relative changes u_i = x_i/x_i,stated - 1 of
  (theta, mu, N, delta1, delta2, R, Delta0/x_st), all weighted alike: every one is a
  dimensionless ratio the paper states to one or two significant digits, none more precisely
  than another, so a slip or another normalisation of any of them is a relative change; a
  relative change does not depend on the units or on how the ratio is defined (mu or 1/mu
  would differ only at second order). The answer is reported for the max-norm (the largest
  single relative change) and the Euclidean norm.
* **Margin.** The answer must reproduce both claims on the Euclidean ball of radius ``margin``
  around it (in either norm's answer): not a point on the boundary of a window,
  where the motion settles slowly and the verdict depends on the solver. During the search a
  point is *robust* when both claims hold at it and at its 14 axis points u +- margin e_i; the
  answer is then checked at ``ball_points`` random points on the ball's surface too.
* **Method.** (1) Rays: ``rays`` random directions (seeded), each stepped outward from the
  stated point by ``ray_step`` (Euclidean) up to ``ray_max``, all rays at once per step on the
  compiled batch (:func:`impactdamper.steady_states`, each point from the
  paper's step 1); the first step where both claims hold is bisected to ``ray_tol``. (2) For
  each norm, the ``starts`` rays with the nearest hits: a robust point is sought just beyond
  the hit along the ray, then a compass search (moves +-s e_i, a radial shrink, and for the
  max-norm a shrink of the largest changes) lowers the norm (ties broken by the other norm)
  while the point stays robust, s halved from ``compass_step`` down to ``compass_floor``.
* **Verification** at each answer by the independent methods
  (:mod:`impactdamper.studies.claims.answer_check`); the stated set at round values beside it
  (:mod:`impactdamper.studies.claims.round_changes`). The claims at many points, the norms and
  the robustness test are :mod:`impactdamper.studies.claims.claims_evaluator`.

Deviation from the paper: the paper has no such search; it reports one parameter set.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from impactdamper.analysis.compass import compass
from impactdamper.studies.claims.claims_evaluator import (
    NEAREST_NAMES,
    NORMS,
    ClaimsEvaluator,
    ball_offsets,
    norm,
    robust,
)

__all__ = ["nearest_set"]


def _key(u: np.ndarray, which: str) -> tuple:
    """Lexicographic objective: the norm, ties broken by the other norm."""
    other = "euclidean" if which == "max" else "max"
    return (round(float(norm(u, which)), 12), round(float(norm(u, other)), 12))


def _ray_directions(rays: int, seed: int) -> np.ndarray:
    """The rays' directions: the 14 axes +-e_i (one parameter alone), the 84 diagonals
    (+-e_i +-e_j)/sqrt 2 (two parameters alike), then ``rays`` random directions (seeded,
    uniform on the sphere), each of unit Euclidean length."""
    d = len(NEAREST_NAMES)
    eye = np.eye(d)
    out = [s * e for e in eye for s in (1.0, -1.0)]
    out += [
        (sa * eye[i] + sb * eye[j]) / math.sqrt(2.0)
        for i in range(d)
        for j in range(i + 1, d)
        for sa in (1.0, -1.0)
        for sb in (1.0, -1.0)
    ]
    v = np.random.default_rng(int(seed)).normal(size=(int(rays), d))
    out += list(v / np.linalg.norm(v, axis=1, keepdims=True))
    return np.array(out)


def _ray_search(ev: ClaimsEvaluator, directions: np.ndarray, step: float, t_max: float, tol: float) -> list[dict]:
    """First point along each ray u = t d (d unit Euclidean) where both claims hold: all rays
    stepped together by ``step`` up to ``t_max``, the first hit bisected to ``tol``.

    Returns
    -------
    list of dict
        One per ray that hits: ``ray`` (index), ``t`` (the bisected inner end), ``bracket``
        (outside, inside), ``u`` (the point at the inside end).
    """
    D = np.asarray(directions, float)
    D = D / np.linalg.norm(D, axis=1, keepdims=True)
    hit_k = np.full(len(D), -1)
    for k in range(1, int(math.floor(t_max / step + 1e-9)) + 1):
        live = np.flatnonzero(hit_k < 0)
        if not len(live):
            break
        flags = ev.both(k * step * D[live])
        hit_k[live[flags]] = k
    rays = np.flatnonzero(hit_k > 0)
    lo = (hit_k[rays] - 1) * step  # claims fail (or the stated point)
    hi = hit_k[rays] * float(step)  # claims hold
    while len(rays) and np.max(hi - lo) > tol:
        mid = 0.5 * (lo + hi)
        flags = ev.both(mid[:, None] * D[rays])
        hi = np.where(flags, mid, hi)
        lo = np.where(flags, lo, mid)
    return [
        {"ray": int(r), "t": float(h), "bracket": [float(a), float(h)], "u": (h * D[r]).tolist()}
        for r, a, h in zip(rays, lo, hi)
    ]


def _robust_start(ev: ClaimsEvaluator, u_hit: np.ndarray, margin: float, tries: int = 24) -> np.ndarray | None:
    """A robust point just beyond a ray's first hit: u_hit (1 + j margin / (2 |u_hit|)),
    j = 1..``tries``, the first robust one (None: none)."""
    u_hit = np.asarray(u_hit, float)
    r = np.linalg.norm(u_hit)
    cands = np.array([u_hit * (1.0 + 0.5 * j * margin / r) for j in range(1, tries + 1)])
    ok = robust(ev, cands, margin)
    return cands[int(np.argmax(ok))] if ok.any() else None


def _compass_search(
    ev: ClaimsEvaluator, u0: np.ndarray, which: str, margin: float, step: float, floor: float, max_iterations: int = 200
) -> tuple[np.ndarray, int]:
    """Lower the ``which`` norm of a robust point while it stays robust (:func:`robust`), by the
    compass poll (:func:`impactdamper.analysis.compass.compass`): moves +-s e_i, +-s (e_i +-
    e_j)/sqrt 2 among the three largest changes, a radial shrink by s, and (max-norm) every
    change within s of the largest shrunk by s; the best robust move that lowers the objective
    (:func:`_key`) is taken, else s is halved, until s < ``floor``. Returns the point and the
    iterations made."""
    d = len(u0)

    def moves(u: np.ndarray, s: float, last: np.ndarray) -> list:
        out = [u + sg * s * e for e in np.eye(d) for sg in (1.0, -1.0)]
        # Diagonal moves among the three largest changes: the reproducing windows are thin
        # and run obliquely (theta and N together), where axis moves alone stall.
        top = np.argsort(-np.abs(u), kind="stable")[:3]
        for a in range(len(top)):
            for b in range(a + 1, len(top)):
                for sa in (1.0, -1.0):
                    for sb in (1.0, -1.0):
                        v = u.copy()
                        v[top[a]] += sa * s / math.sqrt(2.0)
                        v[top[b]] += sb * s / math.sqrt(2.0)
                        out.append(v)
        r = np.linalg.norm(u)
        if r > s:
            out.append(u * (1.0 - s / r))
        if which == "max":
            m = np.max(np.abs(u))
            big = np.abs(u) >= m - s
            out.append(np.where(big, np.sign(u) * np.maximum(np.abs(u) - s, 0.0), u))
        return out

    def judge(idx: np.ndarray, u: np.ndarray, s: np.ndarray, candidates: list) -> list:
        here = _key(u[0], which)
        lower = [k for k, v in enumerate(candidates[0]) if _key(v, which) < here]
        if not lower:
            return [None]
        ok = robust(ev, np.array([candidates[0][k] for k in lower]), margin)
        if not ok.any():
            return [None]
        return [min((k for k, o in zip(lower, ok) if o), key=lambda k: _key(candidates[0][k], which))]

    u, it = compass(np.asarray(u0, float)[None, :], float(step), floor, moves, judge, max_iterations)
    return u[0], it


def _margin_check(ev: ClaimsEvaluator, u: np.ndarray, margin: float, which: str, random_points: int, seed: int) -> dict:
    """Both claims at ``u``'s centre, its 14 axis points and ``random_points`` random points on
    the ball (cube for the max-norm) of radius ``margin``: how many hold."""
    off = ball_offsets(margin, which, random_points, seed)
    flags = ev.both(np.asarray(u, float)[None, :] + off)
    return {
        "radius": margin,
        "shape": "cube" if which == "max" else "Euclidean ball",
        "points": int(len(off)),
        "axis_points": 2 * len(NEAREST_NAMES),
        "random_points": int(random_points),
        "hold": int(flags.sum()),
        "held": bool(flags.all()),
        "failed_offsets": [o.tolist() for o, f in zip(off, flags) if not f],
    }


def nearest_set(
    ev: ClaimsEvaluator,
    *,
    check: ClaimsEvaluator | None = None,
    rays: int,
    seed: int,
    ray_step: float,
    ray_max: float,
    ray_tol: float,
    margin: float,
    starts: int,
    compass_step: float,
    compass_floor: float,
    ball_points: int,
    log: Callable[[str], None] | None = None,
) -> dict:
    """The nearest robust reproducing set in each norm (the module docstring's method): the
    search on ``ev``, the final margin check on ``check`` (the full solver settings, where
    ``ev`` may cap the periods lower to screen; a run settled within the lower cap settles
    identically within the higher one, so the screening can only miss points, never add them).

    Returns
    -------
    dict
        ``rays`` (count, hits, the nearest hit in each norm), and per norm in ``answers``:
        ``u`` (relative changes), ``values`` (absolute), ``distance`` (both norms),
        ``iterations``, ``margin_check`` (:func:`margin_check`); ``points`` evaluated.
    """
    say = log or (lambda msg: None)
    D = _ray_directions(rays, seed)
    hits = _ray_search(ev, D, ray_step, ray_max, ray_tol)
    say(f"rays: {len(hits)} of {rays} reach both claims within {ray_max:g}; {ev.points} points")
    out = {
        "rays": {
            "count": len(D),
            "random": int(rays),
            "hits": len(hits),
            "step": ray_step,
            "max": ray_max,
            "tol": ray_tol,
            "seed": int(seed),
        },
        "answers": {},
    }
    if not hits:
        return out
    for which in NORMS:
        ranked = sorted(hits, key=lambda h: _key(np.array(h["u"]), which))
        nearest_hit = ranked[0]
        out["rays"]["nearest_hit_" + which] = {
            "u": nearest_hit["u"],
            "distance": float(norm(np.array(nearest_hit["u"]), which)),
        }
        best, best_it = None, 0
        for h in ranked[: int(starts)]:
            u0 = _robust_start(ev, np.array(h["u"]), margin)
            if u0 is None:
                say(f"{which}: ray {h['ray']} has no robust point just beyond its hit")
                continue
            u, it = _compass_search(ev, u0, which, margin, compass_step, compass_floor)
            say(
                f"{which}: ray {h['ray']} hit at {norm(np.array(h['u']), which):.4f}, refined to "
                f"{norm(u, which):.4f} in {it} iterations; {ev.points} points"
            )
            if best is None or _key(u, which) < _key(best, which):
                best, best_it = u, it
        if best is None:
            out["answers"][which] = None
            continue
        best = np.round(best, 12)
        out["answers"][which] = {
            "u": dict(zip(NEAREST_NAMES, map(float, best))),
            "values": dict(zip(NEAREST_NAMES, map(float, ev.values(best)[0]))),
            "distance": {"max": float(norm(best, "max")), "euclidean": float(norm(best, "euclidean"))},
            "iterations": int(best_it),
            "margin_check": _margin_check(check or ev, best, margin, "euclidean", ball_points, seed),
        }
    out["points"] = ev.points
    out["batch_points"] = ev.batch_points
    return out
