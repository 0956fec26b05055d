"""The ``boundaries`` command: every boundary of a regime map's plane as curves
(:func:`impactdamper.analysis.boundaries.plane_boundaries`) for one's own parameters."""

from __future__ import annotations

import argparse

from impactdamper.analysis.boundaries import BoundarySettings, plane_boundaries
from impactdamper.analysis.curves import CODIM2_REASONS
from impactdamper.core.parameters import Parameters

__all__ = ["add_boundaries_flags", "boundaries_answer", "print_boundaries", "PLANES"]

# The planes: the second parameter and the default ranges (the workflow's regime maps').
PLANES = {
    "theta": {"parameter": "theta", "gap": (-40.0, 15.0), "range": (0.5, 1.5)},
    "damping": {"parameter": "delta", "gap": (-50.0, 30.0), "range": (0.02, 0.2)},
}
# Seed rows by default: the command stays within a minute on two cores (the workflow uses 5).
DEFAULT_SEED_ROWS = 3


def add_boundaries_flags(cmd: argparse.ArgumentParser) -> None:
    """The ``boundaries`` command's own flags (the plane) on ``cmd``, which has the parameters'."""
    g = cmd.add_argument_group("plane")
    g.add_argument(
        "--plane", choices=sorted(PLANES), default="theta", help="gap against theta or delta = delta1 = delta2"
    )
    g.add_argument("--gap-min", type=float, default=None, help="the plane's lowest Delta0/x_st (default: the map's)")
    g.add_argument("--gap-max", type=float, default=None, help="the plane's highest Delta0/x_st (default: the map's)")
    g.add_argument(
        "--min", dest="lo", type=float, default=None, help="the second parameter's lowest value (default: the map's)"
    )
    g.add_argument(
        "--max", dest="hi", type=float, default=None, help="the second parameter's highest value (default: the map's)"
    )
    g.add_argument(
        "--seed-rows",
        type=int,
        default=DEFAULT_SEED_ROWS,
        help=f"rows whose branches seed curves (default {DEFAULT_SEED_ROWS})",
    )


def boundaries_answer(args: argparse.Namespace, p: Parameters) -> dict:
    """The curves of the plane ``args.plane`` at the parameters ``p`` (off the plane)."""
    plane = PLANES[args.plane]
    gap = (
        plane["gap"][0] if args.gap_min is None else args.gap_min,
        plane["gap"][1] if args.gap_max is None else args.gap_max,
    )
    rng = (plane["range"][0] if args.lo is None else args.lo, plane["range"][1] if args.hi is None else args.hi)
    if not gap[0] < gap[1]:
        raise ValueError(f"`--gap-min` = {gap[0]!r} is not allowed: must be below --gap-max = {gap[1]!r}")
    if not (0 < rng[0] < rng[1]):
        raise ValueError(f"`--min` = {rng[0]!r} is not allowed: need 0 < --min < --max = {rng[1]!r}")
    if not 1 <= args.seed_rows <= 100:
        raise ValueError(f"`--seed-rows` = {args.seed_rows!r} is not allowed: must be in 1..100")
    slow = plane["parameter"]
    b = plane_boundaries(p, slow, gap, rng, BoundarySettings(seed_rows=args.seed_rows))
    curves = []
    for n, c in enumerate(b.curves, start=1):
        curves.append(
            {
                "curve": f"{n:02d}",
                "cycle": c.label,
                "kind": c.kind,
                "seed": list(c.seed),
                "ends": [{"reason": r, "detail": d} for r, d in c.ends],
                "points": c.points.tolist(),
                "stable_side": list(c.stable_side),
            }
        )
    closed = {}
    for r in b.rows:
        if r["curve"] in ("first_contact", "liftoff"):
            closed.setdefault(r["curve"], []).append([r["gap"], r[slow]])
    codim2 = [
        {"cycle": c["cycle"], "kind": c["kind"], "reason": e["reason"], "detail": e["detail"]}
        for c in curves
        for e in c["ends"]
        if e["reason"] in CODIM2_REASONS
    ]
    return {
        "plane": args.plane,
        "parameter": slow,
        "gap_range": list(gap),
        "range": list(rng),
        "seed_rows": args.seed_rows,
        "curves": curves,
        "closed_form": closed,
        "codim2": codim2,
        "failures": b.failures,
        "parameters": p.to_dict(),
    }


def print_boundaries(r: dict) -> None:
    print(f"boundaries of the plane gap x {r['parameter']}: {len(r['curves'])} continued curves")
    for c in r["curves"]:
        ends = "; ".join(f"{e['reason']} ({e['detail']})" for e in c["ends"])
        print(f"  {c['curve']} {c['cycle']:>5} {c['kind']:<17} {len(c['points']):4d} points, ends: {ends}")
    for name, pts in r["closed_form"].items():
        print(f"  {name}: {len(pts)} points (closed form)")
