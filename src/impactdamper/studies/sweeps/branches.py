"""Branches of periodic orbits followed in Delta0/x_st, their special points and stable
stretches: the orbits stage's study (``workflow/scripts/orbit_*.py`` write its records).

The paper is Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100; it
computes no periodic orbits directly, so everything here extends it.

How a branch is followed
------------------------
Each branch of the config's ``orbits.branches`` is seeded at its own gap (by Algorithm
No. 1's one-impact orbit, or by the cycle Algorithm No. 2 settles on, solved by Newton
shooting) and followed both ways in Delta0/x_st by :func:`impactdamper.continue_orbit`
(pseudo-arclength, special points located by Brent's method) within the branch's bounds.
The leg going down in the gap is bounded by ``[gap_min, gap]``, the one going up by ``[gap,
gap_max]`` (a leg that turns at a fold must not come back to the seed's gap; the seed is
chosen so). The orbit is followed on past a grazing (``stop_at_grazing=False``), inadmissible
beyond it (the gap would go negative between impacts: not a motion, drawn dotted), so that the
branch's whole solution set in the bounds is shown, e.g. Algorithm No. 1's orbit down to its
fold. A leg ends at

* the first impact whose closing velocity reaches zero (``grazing_velocity``): beyond it the
  shooting equations describe an impact from the wrong side of the stop, which is no motion
  of any kind. The grazing orbit itself is not a row of the branch table (its multipliers grow
  like 1/v there and are not reproducible); the special point gives its place. A coinciding
  interior touch (the vanishing impact is a tangency, seen by both test functions) is not
  listed twice;
* the bound, or a Newton failure below the least step (the leg's ``end``).
"""

from __future__ import annotations

import logging
import math
import re

import numpy as np

from impactdamper import Parameters, continue_orbit, solve_orbit, steady_state
from impactdamper.reporting.records import cell_float, joined
from impactdamper.studies.intervals import true_runs
from impactdamper.studies.config import steady_options, tolerances

PAPER = "Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100"
# The continuation parameter of the stage (the library follows any field of Parameters).
PARAMETER = "gap"
# Columns of figures/orbit_branches.csv. Rows are in order along each branch (``index``).
BRANCH_COLUMNS = [
    "branch",
    "label",
    "index",
    "gap",
    "x1_max",
    "min_gap",
    "spectral_radius",
    "stable",
    "admissible",
    "velocities",
    "phases",
]
# Columns of figures/orbit_special_points.csv, rows in order of the branches then of the gap.
# ``admissible``: the special point lies on, or bounds, a stretch of admissible orbits (a
# motion of the suppressor); 0 for points found on the inadmissible continuation.
# ``index``: the point lies between the branch's rows index-1 and index (0: before its first
# row, the number of rows: after its last); ``spectral_radius`` is left empty at a vanishing
# impact (the saltation matrix grows like 1/v there).
# ``leg`` and ``detail``: the library's description is worded in the direction the point was
# passed, "down" or "up" in the gap from the branch's seed (e.g. "loses stability").
SPECIAL_COLUMNS = [
    "branch",
    "label",
    "kind",
    "gap",
    "index",
    "x1_max",
    "spectral_radius",
    "admissible",
    "leg",
    "detail",
]
# Significant digits of the joined velocities and phases in the committed CSVs (the record
# test compares at a relative 1e-8; the continuation converges to 1e-12).
JOINED_FORMAT = "{:.12g}"
# The special points' vocabulary, once: each kind the continuation reports
# (:data:`impactdamper.analysis.branch.SPECIAL_KINDS`) with its short name in tables
# ("short"), its letter on the branches' figure ("mark"), its name in prose ("text") and its
# part of a TeX macro name ("macro", letters only) and in the figure's legend ("legend", in
# this order). The two grazings share names in prose and tables; the macros and the legend tell
# them apart.
SPECIAL_POINT_NAMES = {
    "period_doubling": {"short": "PD", "mark": "PD", "text": "period doubling", "macro": "PD", "legend": "PD"},
    "neimark_sacker": {"short": "NS", "mark": "NS", "text": "Neimark--Sacker", "macro": "NS", "legend": "NS"},
    "fold": {"short": "fold", "mark": "fold", "text": "fold", "macro": "Fold", "legend": "fold"},
    "grazing_interior": {
        "short": "grazing",
        "mark": "G",
        "text": "grazing",
        "macro": "GrazingTouch",
        "legend": "G: new impact",
    },
    "grazing_velocity": {
        "short": "grazing",
        "mark": "G",
        "text": "grazing",
        "macro": "GrazingVanish",
        "legend": "G: impact vanishes",
    },
}
KIND_SHORT = {k: v["short"] for k, v in SPECIAL_POINT_NAMES.items()}
KIND_TEXT = {k: v["text"] for k, v in SPECIAL_POINT_NAMES.items()}
KIND_MARK = {k: v["mark"] for k, v in SPECIAL_POINT_NAMES.items()}
KIND_MACRO = {k: v["macro"] for k, v in SPECIAL_POINT_NAMES.items()}
KIND_LEGEND = {k: v["legend"] for k, v in SPECIAL_POINT_NAMES.items()}


# --- config --------------------------------------------------------------------------------
def label(k: int, z: int) -> str:
    """Peterka's z/k label: z impacts in k forcing periods."""
    return f"{int(z)}/{int(k)}"


# --- following a branch ---------------------------------------------------------------------
def _seed_orbit(reference: Parameters, spec: dict, solver: dict):
    """The branch's starting orbit, checked against the config's expected k and z."""
    p = reference.replace(**{PARAMETER: float(spec["gap"])})
    if spec["seed"] == "alg1":
        o = solve_orbit(p, "alg1", tolerances=tolerances(solver))
    else:
        o = solve_orbit(p, steady_state(p, **steady_options(solver)), tolerances=tolerances(solver))
    want = (int(spec["period_multiple"]), int(spec["impacts"]))
    if not o.solved or (o.period_multiple, o.impacts_per_cycle) != want or not o.admissible:
        raise ValueError(
            f"`orbits.branches` entry {spec['name']!r}: the {spec['seed']} seed at gap {spec['gap']} gives "
            f"{label(o.period_multiple, o.impacts_per_cycle)} (admissible {o.admissible}), not the admissible "
            f"{label(want[0], want[1])} cycle asked for"
        )
    return o


def _leg(orbit, direction: int, bounds: tuple, cont: dict, solver: dict) -> dict:
    """One way along a branch: points, special points (with their index into ``points``:
    between points index-1 and index) and why the leg ends."""
    b = continue_orbit(
        orbit,
        PARAMETER,
        bounds,
        direction=direction,
        step=float(cont["step"]),
        min_step=float(cont["min_step"]),
        max_step=float(cont["max_step"]),
        max_points=int(cont["max_points"]),
        stop_at_grazing=False,
        tolerances=tolerances(solver),
    )
    points, special = list(b.points), []
    end = {"reason": b.end_reason, "value": float(b.end_value)}
    for s in b.special:
        special.append(s)
        if s.kind == "grazing_velocity":
            points = points[: s.index]
            end = {"reason": "grazing_velocity", "value": float(s.value)}
            break
    return {"points": points, "special": special, "end": end}


def follow(reference: Parameters, spec: dict, cont: dict, solver: dict, log=None) -> dict:
    """Follow one branch both ways from its seed within ``[spec.gap_min, spec.gap_max]``
    (``gap_min <= gap <= gap_max``).

    Returns
    -------
    dict
        ``name``, ``label``, ``k``, ``z``, ``points`` (BranchPoint, in order of increasing
        arclength from the lower end), ``special`` (list of (SpecialPoint, lo, hi, leg): it
        lies between joined points lo and hi, None beyond an end; found on the leg "down" or
        "up" from the seed), ``ends`` (low and high end: the
        end reason and value of each leg), ``seed_index`` (the seed's joined point).
    """
    log = log or logging.getLogger(__name__)
    g0 = float(spec["gap"])
    lo, hi = float(spec["gap_min"]), float(spec["gap_max"])
    if not lo <= g0 <= hi:
        raise ValueError(
            f"`orbits.branches` entry {spec['name']!r}: need gap_min <= gap <= gap_max, got {lo} <= {g0} <= {hi}"
        )
    o = _seed_orbit(reference, spec, solver)
    # Each leg ends at the seed's gap if it comes back there past a fold: the other leg covers
    # the far side. Beyond a vanishing impact the continuation goes on (only to be cut), so
    # this bound also keeps a leg from following a mirror branch of wrong-way impacts across
    # the whole range (the one-impact orbit's solution set is a closed loop).
    down = _leg(o, -1, (lo, g0), cont, solver)
    up = _leg(o, +1, (g0, hi), cont, solver)
    for name, leg in (("down", down), ("up", up)):
        if leg["end"]["reason"] == "bound" and leg["end"]["value"] == g0:
            raise ValueError(
                f"`orbits.branches` entry {spec['name']!r}: the {name} leg turns at a fold and comes "
                f"back to the seed's gap {g0} before it ends: seed the branch outside the part "
                "that turns back"
            )
    nd = len(down["points"])
    points = down["points"][::-1] + up["points"][1:]
    special = []
    for s in down["special"]:
        # Down leg point j is joined point nd-1-j; s lies between its points index-1 and index.
        a = nd - 1 - s.index
        special.append((s, a if a >= 0 else None, nd - s.index, "down"))
    for s in up["special"]:
        b = nd - 1 + s.index
        special.append((s, nd - 2 + s.index, b if b < len(points) else None, "up"))
    special.sort(key=lambda e: (e[1] if e[1] is not None else -1, e[0].value))
    log.info(
        "branch %s (%s): %d points from %.6f (%s) to %.6f (%s), %d special points",
        spec["name"],
        label(o.period_multiple, o.impacts_per_cycle),
        len(points),
        down["end"]["value"],
        down["end"]["reason"],
        up["end"]["value"],
        up["end"]["reason"],
        len(special),
    )
    return {
        "name": spec["name"],
        "label": label(o.period_multiple, o.impacts_per_cycle),
        "k": o.period_multiple,
        "z": o.impacts_per_cycle,
        "points": points,
        "special": special,
        "seed_index": nd - 1,
        "ends": {"low": down["end"], "high": up["end"]},
    }


def _on_motion(branch: dict, lo, hi) -> bool:
    """Whether the points on either side of a special point include an admissible one."""
    pts = branch["points"]
    return any(pts[i].admissible for i in (lo, hi) if i is not None)


def stretches(branch: dict, which: str) -> list[dict]:
    """Maximal runs of ``which`` ("stable": stable and admissible; "admissible") orbits on a
    branch, each end the special point bounding it (or the branch's end).

    Returns a list of {"lo", "hi", "lo_kind", "hi_kind"}: the run's extent in Delta0/x_st
    (past a fold inside the run, the fold is an end of the extent) and what bounds it there
    (a special point's kind, ``bound``, ``newton_failure``, or ``sampled`` for a run's last
    point without a located special point beyond it).
    """
    pts = branch["points"]
    ok = [q.admissible and (q.stable or which == "admissible") for q in pts]
    out, n = [], len(pts)
    for i, j in true_runs(ok):
        ends = []
        for edge, outside in ((i, i - 1), (j, j + 1)):
            hit = [s for s, a, b, _ in branch["special"] if {a, b} == {edge, outside if 0 <= outside < n else None}]
            if hit:
                # Several at once (e.g. a velocity grazing and the touch it is): the first listed.
                ends.append((float(hit[0].value), hit[0].kind))
            else:
                side = "low" if edge == 0 and outside < 0 else "high" if outside >= n else None
                ends.append((float(pts[edge].value), branch["ends"][side]["reason"] if side else "sampled"))
        # The run's extent in the gap: its ends, its points and any special point inside it
        # (a fold inside an admissible run is its extreme gap).
        inside = [
            (float(s.value), s.kind)
            for s, a, b, _ in branch["special"]
            if a is not None and b is not None and i <= a and b <= j
        ]
        cand = ends + inside + [(float(q.value), "sampled") for q in pts[i : j + 1]]
        (va, ka), (vb, kb) = min(cand), max(cand)
        out.append({"lo": va, "hi": vb, "lo_kind": ka, "hi_kind": kb})
    return out


# --- tables ---------------------------------------------------------------------------------
def branch_rows(branch: dict) -> list[dict]:
    rows = []
    for i, q in enumerate(branch["points"]):
        rows.append(
            {
                "branch": branch["name"],
                "label": branch["label"],
                "index": i,
                "gap": q.value,
                "x1_max": q.x1_max,
                "min_gap": q.min_gap,
                "spectral_radius": abs(q.multipliers[0]),
                "stable": q.stable,
                "admissible": q.admissible,
                "velocities": joined(q.velocities, JOINED_FORMAT),
                "phases": joined(q.phases, JOINED_FORMAT),
            }
        )
    return rows


def special_rows(branch: dict) -> list[dict]:
    rows = []
    for s, a, b, leg in branch["special"]:
        radius = math.nan if s.kind == "grazing_velocity" else abs(s.point.multipliers[0])
        rows.append(
            {
                "branch": branch["name"],
                "label": branch["label"],
                "kind": s.kind,
                "gap": s.value,
                "index": 0 if a is None else a + 1,
                "x1_max": s.point.x1_max,
                "spectral_radius": radius,
                "admissible": _on_motion(branch, a, b),
                "leg": leg,
                "detail": s.detail,
            }
        )
    return sorted(rows, key=lambda r: r["gap"])


# --- a branch drawn: runs of one state ---------------------------------------------------------
def _state(r: dict) -> str:
    """A branch row's state: stable, unstable (both admissible) or inadmissible."""
    if r["admissible"] != "1":
        return "inadmissible"
    return "stable" if r["stable"] == "1" else "unstable"


def _branch_sequence(rows: list[dict], special: list[dict], key: str) -> list[tuple]:
    """The branch as (gap, y, state or None) in order along it, special points inserted at
    their places (state None); y is ``key`` (nan where a special point has no value).

    ``rows`` and ``special``: one branch's rows of ``figures/orbit_branches.csv`` and
    ``figures/orbit_special_points.csv`` (:func:`branch_rows`, :func:`special_rows`), as
    strings; a state is "stable" (and admissible), "unstable" (admissible) or "inadmissible".
    """
    items = [(float(i), cell_float(r["gap"]), cell_float(r[key]), _state(r)) for i, r in enumerate(rows)]
    for s in special:
        i = int(s["index"])
        ref = cell_float(rows[i - 1]["gap"]) if i > 0 else cell_float(rows[0]["gap"])
        # Between rows i-1 and i; two between the same rows in order of distance from row i-1.
        items.append(
            (
                i - 0.5 + 1e-3 * math.tanh(abs(cell_float(s["gap"]) - ref)),
                cell_float(s["gap"]),
                cell_float(s[key]),
                None,
            )
        )
    items.sort(key=lambda t: t[0])
    return [(g, y, state) for _, g, y, state in items]


def run_pieces(rows: list[dict], special: list[dict], key: str) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """A branch split into polylines of one state each (stable, unstable, inadmissible), for
    drawing: (state, gaps, ``key`` values). The special points are vertices; a segment takes
    the state of its regular end (:func:`branch_sequence`). Where :func:`stretches` gives a run's
    extent, this gives its drawn line."""
    seq = _branch_sequence(rows, special, key)
    out = []
    for (g0, y0, s0), (g1, y1, s1) in zip(seq[:-1], seq[1:]):
        state = s0 or s1 or "unstable"
        if math.isnan(y0) or math.isnan(y1):
            continue
        if out and out[-1][0] == state and out[-1][1][-1] == g0 and out[-1][2][-1] == y0:
            out[-1][1].append(g1)
            out[-1][2].append(y1)
        else:
            out.append((state, [g0, g1], [y0, y1]))
    return [(s, np.array(g), np.array(y)) for s, g, y in out]


def multi_impact_window(rows: list[dict], special: list[dict], summary: dict, margin: float) -> tuple[float, float]:
    """The gaps (Delta0/x_st) of the branches' rows and special points of the cycles other than
    the one-impact orbit (k > 1 or z > 1, ``summary["branches"]``), widened by ``margin``."""
    multi = {n for n, b in summary["branches"].items() if b["k"] > 1 or b["z"] > 1}
    gaps = [cell_float(r["gap"]) for n in multi for r in rows if r["branch"] == n] + [
        cell_float(s["gap"]) for n in multi for s in special if s["branch"] == n
    ]
    return min(gaps) - margin, max(gaps) + margin


# --- the special points' table ----------------------------------------------------------------
def _stability(r: dict, rows: list[dict]) -> str:
    """Which side of a bifurcation is stable, from the branch rows on either side of it
    (the library's own wording follows the direction of continuation)."""
    i = int(r["index"])
    near = [rows[j] for j in (i - 1, i) if 0 <= j < len(rows)]
    flags = {q["stable"] == "1" for q in near}
    if len(near) < 2 or len(flags) == 1:
        return "; stable on both sides" if flags == {True} else "; unstable on both sides"
    if r["kind"] == "fold":
        return "; a stable and an unstable leg meet"
    stable_row = next(q for q in near if q["stable"] == "1")
    return "; stable for " + ("larger" if cell_float(stable_row["gap"]) > cell_float(r["gap"]) else "smaller") + " gaps"


def describe_special(r: dict, rows: list[dict]) -> str:
    """What happens at a special point, in a few words of TeX for the special points' table.

    Parameters
    ----------
    r : dict
        The special point's row (``figures/orbit_special_points.csv``, :func:`special_rows`, as
        strings): kind, label, index, gap, detail.
    rows : list of dict
        Its branch's rows (``figures/orbit_branches.csv``, :func:`branch_rows`, as strings):
        which side is stable is read from the rows on either side of the point.
    """
    d = r["detail"]
    after = re.search(r"-> (\d+/\d+)", d)
    change = f" ({r['label']} $\\to$ {after.group(1)})" if after else ""
    kind = r["kind"]
    if kind == "period_doubling":
        m = re.search(r"a (\d+/\d+) \(", d)
        return f"multiplier $-1$, a {m.group(1) if m else 'doubled'} cycle branches off{_stability(r, rows)}"
    if kind == "neimark_sacker":
        return f"complex pair of multipliers on the unit circle{_stability(r, rows)}"
    if kind == "fold":
        return f"multiplier $+1$, turning point{_stability(r, rows)}"
    if kind == "grazing_velocity":
        m = re.search(r"impact (\d+) of", d)
        return f"impact {m.group(1) if m else ''} arrives with zero closing velocity{change}"
    return f"the gap touches zero between impacts: a new impact{change}"
