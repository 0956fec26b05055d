"""Reading the sweeps' and regime maps' results: the main regime runs of a sweep, its
transitions identified with a special point of a continued branch or with the other sweep
direction, the overlaps of the two directions (hysteresis), the labels met only where the other
direction did not settle, and the bistable rows of a regime map.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100, whose introduction
describes the sequence of regimes along the gap; the paper shows no sweep. The inputs are the
committed records' rows (``figures/sweep_gap.csv``, ``figures/sweep_transitions.csv``,
``figures/orbit_special_points.csv``, ``figures/map_{map}.csv`` and its curves), as
:func:`impactdamper.reporting.records.read_csv` reads them (strings).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdamper.reporting.records import cell_float, read_csv
from impactdamper.studies.sweeps.branches import KIND_SHORT
from impactdamper.studies.sweeps.gapsweep import runs

__all__ = [
    "MIN_RUN",
    "MATCH_STEPS",
    "BISTABLE_MIN_CELLS",
    "BISTABLE_STEADY_ROWS",
    "read_map",
    "main_runs",
    "CHECK_MATCH",
    "main_transitions",
    "overlaps",
    "np_only_labels",
    "bistable_rows",
]

# A run of one label shorter than this many sweep points is not a "main" regime (the chaotic
# bands flicker between np and narrow periodic windows).
MIN_RUN = 5
# A transition is identified with a special point of a continued branch, or with the same
# change located by the other sweep direction, when they are within this share of the sweep
# step (the step is the sweep's resolution; the bisections are 1000 times finer).
MATCH_STEPS = 0.05
# Cells of the bistable label a map row must hold beyond U1/x_st to count as on it.
BISTABLE_MIN_CELLS = 3
# Rows in a row all on the bistable label that end the alternating stretch.
BISTABLE_STEADY_ROWS = 5
# Labels that are no periodic motion (no period settled; the solver failed).
LOOSE = ("np", "err")


def read_map(path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A regime map's CSV (``figures/map_{map}.csv``: a header row of gaps, then per row the
    slow parameter's value and the cells' z/k labels).

    Returns
    -------
    slow : ndarray, shape (rows,)
    gaps : ndarray, shape (columns,)
        Delta0/x_st.
    labels : ndarray of str, shape (rows, columns)
    """
    lines = [ln.split(",") for ln in Path(path).read_text().splitlines()]
    gaps = np.array([float(x) for x in lines[0][1:]])
    slow = np.array([float(ln[0]) for ln in lines[1:]])
    return slow, gaps, np.array([ln[1:] for ln in lines[1:]])


def main_runs(rows: list[dict], direction: str, min_run: int = MIN_RUN) -> list[tuple]:
    """The runs (label, first value, last value, points) of one sweep direction's labels that
    hold at least ``min_run`` points, in order of the gap."""
    rs = [r for r in rows if r["direction"] == direction]
    return [r for r in runs([float(r["value"]) for r in rs], [r["label"] for r in rs]) if r[3] >= min_run]


def _special_match(t: dict, special: list[dict], tol: float) -> tuple[str, float] | None:
    """The special point of a continued branch labelled like either side of transition ``t``,
    nearest to it and within ``tol``: (its short name "PD of 3/2", its gap), or None."""
    value = float(t["value"])
    cands = [s for s in special if s["label"] in (t["before"], t["after"]) and abs(cell_float(s["gap"]) - value) <= tol]
    if not cands:
        return None
    s = min(cands, key=lambda s: abs(cell_float(s["gap"]) - value))
    return f"{KIND_SHORT.get(s['kind'], s['kind'])} of {s['label']}", cell_float(s["gap"])


def _mirror_match(t: dict, trans: list[dict], tol: float) -> dict | None:
    """The same change located by the other sweep direction (labels swapped) within ``tol``."""
    value = float(t["value"])
    other = "down" if t["direction"] == "up" else "up"
    cands = [
        u
        for u in trans
        if u["direction"] == other
        and u["before"] == t["after"]
        and u["after"] == t["before"]
        and abs(float(u["value"]) - value) <= tol
    ]
    if not cands:
        return None
    return min(cands, key=lambda u: abs(float(u["value"]) - value))


# The sweep changes the closed-form checks (figures/sweep_checks.json) explain: the direction
# and the label the sweep leaves.
CHECK_MATCH = {"liftoff": ("up", "stuck"), "first_contact": ("down", "0/1"), "alg1_grazing": ("down", "1/1")}


def _check_match(t: dict, before: str, checks: dict) -> str | None:
    """The closed-form check that explains transition ``t`` (leaving ``before``), or None: its
    direction and label, a located value, and an analytic value within 0.5 of the change."""
    for name, (direction, label) in CHECK_MATCH.items():
        c = checks.get(name, {})
        if (
            direction == t["direction"]
            and label == before
            and c.get("analytic") is not None
            and c.get("located") is not None
            and abs(c["analytic"] - float(t["value"])) < 0.5
        ):
            return name
    return None


def main_transitions(rows: list[dict], trans: list[dict], checks_doc: dict, special: list[dict]) -> list[dict]:
    """Where a main run (:func:`main_runs`) ends and the next one begins, direction by direction
    in sweep order: the bisected transition found between them and what identifies it.

    Returns
    -------
    list of dict
        ``transition`` (the row of ``trans``), ``next`` (the next main run's label, where the
        change passes through others), and the first that explains it: ``check`` (a closed-form
        check's name, :data:`CHECK_MATCH`), ``special`` ((name, gap) of a special point of a
        continued branch, :func:`special_match`), ``mirror`` (the other direction's row,
        :func:`mirror_match`, for a change to or from np), or ``budget`` (a change to or from np
        that nothing explains: an edge of the settling budget); the others None or False. Both
        matches are within :data:`MATCH_STEPS` of the sweep step.
    """
    checks = {c["name"]: c for c in checks_doc["checks"]}
    values = sorted({float(r["value"]) for r in rows})
    tol = MATCH_STEPS * (values[-1] - values[0]) / (len(values) - 1)
    out = []
    for direction in ("up", "down"):
        ordered = main_runs(rows, direction)
        ordered = ordered if direction == "up" else ordered[::-1]
        for a, b in zip(ordered[:-1], ordered[1:]):
            if a[0] == b[0]:
                continue
            lo, hi = sorted((a[2], b[1]) if direction == "up" else (a[1], b[2]))
            cands = [
                t
                for t in trans
                if t["direction"] == direction and lo <= float(t["value"]) <= hi and t["before"] == a[0]
            ]
            if not cands:
                continue
            t = cands[0] if direction == "up" else cands[-1]
            found = {"transition": t, "next": b[0], "check": None, "special": None, "mirror": None, "budget": False}
            loose = "np" in (t["before"], t["after"])
            if (check := _check_match(t, a[0], checks)) is not None:
                found["check"] = check
            elif (sp := _special_match(t, special, tol)) is not None:
                found["special"] = sp
            elif loose and (u := _mirror_match(t, trans, tol)) is not None:
                found["mirror"] = u
            elif loose:
                found["budget"] = True
            out.append(found)
    return out


def _run_intervals(rows: list[dict], trans: list[dict], direction: str) -> list[tuple]:
    """Runs of the direction's labels, each (label, lo, hi, first, last): lo and hi are the
    bisected transitions at its ends (the midpoint to the neighbour where none was bisected)."""
    rs = sorted((r for r in rows if r["direction"] == direction), key=lambda r: float(r["value"]))
    values = [float(r["value"]) for r in rs]
    at = [float(t["value"]) for t in trans if t["direction"] == direction]
    out = []
    for lab, a, b, _ in runs(values, [r["label"] for r in rs]):
        i, j = values.index(a), values.index(b)
        lo = values[0] if i == 0 else next((v for v in at if values[i - 1] < v <= a), 0.5 * (values[i - 1] + a))
        hi = (
            values[-1]
            if j == len(values) - 1
            else next((v for v in at if b <= v < values[j + 1]), 0.5 * (b + values[j + 1]))
        )
        out.append((lab, lo, hi, a, b))
    return out


def overlaps(rows: list[dict], trans: list[dict]) -> list[dict]:
    """Where the two directions settle on different periodic motions (np and err left out):
    list of {"down": labels, "up": labels, "lo", "hi"}, adjacent pieces sharing a label merged."""
    up, down = _run_intervals(rows, trans, "up"), _run_intervals(rows, trans, "down")
    pieces = []
    for lu, ulo, uhi, ua, ub in up:
        for ld, dlo, dhi, da, db in down:
            if lu == ld or lu in LOOSE or ld in LOOSE or max(ua, da) > min(ub, db):
                continue  # the same motion, or no sweep point shared
            pieces.append({"up": [lu], "down": [ld], "lo": max(ulo, dlo), "hi": min(uhi, dhi)})
    pieces.sort(key=lambda p: p["lo"])
    merged = []
    for p in pieces:
        q = merged[-1] if merged else None
        if q and abs(q["hi"] - p["lo"]) < 1e-12 and (q["up"][-1] == p["up"][0] or q["down"][-1] == p["down"][0]):
            for side in ("up", "down"):
                q[side] += [lab for lab in p[side] if lab not in q[side]]
            q["hi"] = p["hi"]
        else:
            merged.append(p)
    return merged


def np_only_labels(rows: list[dict]) -> list[str]:
    """Periodic labels met in one direction at sweep points where the other did not settle
    (np), on runs of at least two points, in order of the gap."""
    up = {float(r["value"]): r["label"] for r in rows if r["direction"] == "up"}
    down = {float(r["value"]): r["label"] for r in rows if r["direction"] == "down"}
    values = sorted(set(up) & set(down))
    out = []
    for key, _a, _b, n in runs(values, [f"{up[v]}|{down[v]}" for v in values]):
        u, d = key.split("|")
        if n >= 2 and (u == "np") != (d == "np"):
            lab = d if u == "np" else u
            if lab not in ("err",) and lab not in out:
                out.append(lab)
    return out


def bistable_rows(map_csv, curves_csv) -> dict | None:
    """Rows of a map that alternate between the no-contact motion 0/1 and an impacting motion
    where both exist (gap above U1/x_st, where 0/1 always exists).

    The impacting label is the one (other than 0/1, np, err) with most cells beyond U1. A row is
    on it with at least BISTABLE_MIN_CELLS such cells. The alternating stretch runs from the
    first row on it to the last row off it before BISTABLE_STEADY_ROWS rows in a row are on it.
    Returns {"label", "lo", "hi", "on", "off", "first"} (slow-parameter values, row counts; "first"
    the first row on the label; "lo" and "hi" None where no row after it is off it) or None.
    """
    slow, gaps, labels = read_map(map_csv)
    u1 = np.array([float(r["first_contact"]) for r in read_csv(curves_csv)])
    beyond = gaps[None, :] > u1[:, None]
    counts: dict[str, int] = {}
    for lab in labels[beyond]:
        if lab not in ("0/1",) + LOOSE:
            counts[lab] = counts.get(lab, 0) + 1
    if not counts:
        return None
    lab = max(sorted(counts), key=counts.get)
    on = [int(np.sum((labels[i] == lab) & beyond[i])) >= BISTABLE_MIN_CELLS for i in range(len(slow))]
    if True not in on:
        return None
    first = on.index(True)
    last_off = None
    steady = 0
    for i in range(first, len(slow)):
        steady = steady + 1 if on[i] else 0
        if not on[i]:
            last_off = i
        if steady >= BISTABLE_STEADY_ROWS and last_off is not None:
            break
    if last_off is None:  # no row off it after the first on it: no alternation
        return {"label": lab, "lo": None, "hi": None, "on": 0, "off": 0, "first": float(slow[first])}
    stretch = on[first : last_off + 1]
    return {
        "label": lab,
        "lo": float(slow[first]),
        "hi": float(slow[last_off]),
        "on": sum(stretch),
        "off": len(stretch) - sum(stretch),
        "first": float(slow[first]),
    }
