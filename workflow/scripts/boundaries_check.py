"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the boundary curves of both regime maps read against the maps' cells and checked.

For each map: the share of its label changes within one cell of a curve and the curves with no
label change along them (:func:`impactdamper.analysis.boundary_checks.label_changes_near_curves`);
at ``boundaries.side_points`` points along each continued curve a brute-force run on each side
(:func:`~impactdamper.analysis.boundary_checks.side_checks`). Independent checks: the continued
1/1 zero-velocity grazing curve against the first contact's closed form (U1/x_st,
:func:`impactdamper.analysis.transitions.no_contact_gap`), and the theta map's 1/1
period-doubling curve against a bisection of the simulation's period multiple in the gap at
``boundaries.bisection_values`` values of theta. The curves' processor time per map.

Writes ``figures/boundaries_check.json``, the report's macros
(``paper/generated/boundaries_macros.tex``) and its table of codimension-two points
(``paper/generated/boundaries_codim2.tex``).
"""

import pickle

import numpy as np

from impactdamper.analysis import boundary_checks as bc
from impactdamper.analysis.sweeps import with_value
from impactdamper.analysis.transitions import no_contact_gap
from impactdamper.studies.sweeps.boundary_report import codim2_points, write_report
from impactdamper.reporting.records import read_csv, read_json, run_stage, write_json
from impactdamper.studies.sweeps.results import read_map


def closed_form_curves(rows: list, slow: str) -> dict:
    out = {}
    for r in rows:
        if r["kind"] in ("first_contact", "liftoff"):
            out.setdefault(r["curve"], []).append((float(r["gap"]), float(r[slow])))
    return {k: np.array(v) for k, v in out.items()}


def first_contact_check(b) -> dict:
    curves = [c for c in b.curves if c.kind == "grazing_velocity" and c.label == "1/1"]
    errors = [abs(a - no_contact_gap(with_value(c.p, c.names[1], v))) for c in curves for a, v in c.points]
    return {
        "curves": len(curves),
        "points": len(errors),
        "max_gap_error": max(errors) if errors else None,
        "tolerance": 1e-8,
    }


def plane_check(name: str, b, rows: list, map_csv, timing: dict, settings: dict) -> dict:
    slow = b.names[1]
    s, gaps, labels = read_map(map_csv)
    bounds = ((float(gaps[0]), float(gaps[-1])), (float(s[0]), float(s[-1])))
    curves = {f"{n:02d} {c.label} {c.kind}": c.points for n, c in enumerate(b.curves, start=1)}
    curves.update(closed_form_curves(rows, slow))
    reading = bc.label_changes_near_curves(s, gaps, labels, curves)
    continued = {f"{n:02d} {c.label} {c.kind}": c for n, c in enumerate(b.curves, start=1)}
    sides = {
        cid: bc.side_checks(c, bounds, int(settings["side_points"]), float(settings["side_distance"]), continued)
        for cid, c in continued.items()
    }
    total = {k: sum(v[k] for v in sides.values()) for k in bc.SIDE_COUNTS}
    total["share_agree_of_observed"] = total["agree"] / total["observed"] if total["observed"] else None
    # Every point, at side_distance or, where another boundary of its cycle lies closer, at half that.
    total["smallest_reduced_distance"] = min(
        (v["smallest_reduced_distance"] for v in sides.values() if v["smallest_reduced_distance"] is not None),
        default=None,
    )
    every = total["observed"] + total["reduced_observed"]
    total["share_agree_with_reduced"] = (total["agree"] + total["reduced_agree"]) / every if every else None
    summary = [
        {
            "curve": f"{n:02d}",
            "cycle": c.label,
            "kind": c.kind,
            "points": len(c.points),
            "gap": [float(c.points[:, 0].min()), float(c.points[:, 0].max())],
            slow: [float(c.points[:, 1].min()), float(c.points[:, 1].max())],
            "ends": [list(e) for e in c.ends],
            "stable_sides": sorted(set(c.stable_side) - {""}),
        }
        for n, c in enumerate(b.curves, start=1)
    ]
    return {
        "parameter": slow,
        "curves": len(b.curves),
        "curve_list": summary,
        "kinds": sorted({c.kind for c in b.curves}),
        "map_reading": reading,
        "side_checks": {"total": total, "by_curve": sides},
        "first_contact": first_contact_check(b),
        "cpu_s": timing["cpu_s"],
    }


def pd_bisection(b, settings: dict) -> dict:
    pd = [c for c in b.curves if c.kind == "period_doubling" and c.label == "1/1"]
    if not pd or not any(side not in ("", "none") for c in pd for side in c.stable_side):
        return {"curve": None, "rows": [], "max_difference": None}

    # Points where the cycle is stable on one side (a bisection needs it there), evenly in index.
    def stable(c):
        return [i for i, side in enumerate(c.stable_side) if side not in ("", "none")]

    c = max(pd, key=lambda c: len(stable(c)))
    ok, n = stable(c), int(settings["bisection_values"])
    values = [c.points[ok[int(j)], 1] for j in (np.arange(n) + 0.5) * len(ok) / n]
    rows = bc.period_doubling_bisection(c, values)
    diffs = [r["difference"] for r in rows if r.get("bisected_gap") is not None]
    return {"curve": f"{c.label} {c.kind}", "xtol": 1e-5, "rows": rows, "max_difference": max(diffs) if diffs else None}


def main(
    boundaries: dict,
    names: list,
    map_csvs: list,
    csvs: list,
    curves: list,
    timings: list,
    out_json,
    out_macros=None,
    out_table=None,
) -> dict:
    record, loaded = {"settings": boundaries, "planes": {}}, {}
    for name, map_csv, csv, pkl, timing in zip(names, map_csvs, csvs, curves, timings):
        with open(pkl, "rb") as f:
            loaded[name] = pickle.load(f)
        record["planes"][name] = plane_check(name, loaded[name], read_csv(csv), map_csv, read_json(timing), boundaries)
    record["period_doubling_bisection"] = pd_bisection(loaded[names[0]], boundaries)
    record["curves_cpu_s"] = sum(p["cpu_s"] for p in record["planes"].values())
    record["kinds_found"] = sorted({k for p in record["planes"].values() for k in p["kinds"]})
    record["codim2"] = codim2_points(loaded)
    write_json(out_json, record)
    if out_macros is not None:
        write_report(record, out_macros, out_table)
    return record


JOB = (
    "params.boundaries params.names input.maps:list input.csvs:list input.curves:list input.timings:list "
    "output.json output.macros output.table"
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
