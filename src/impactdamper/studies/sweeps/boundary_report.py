"""The report's numbers on the boundary curves of the regime maps: the codimension-two points
where curves end, the macros (``paper/generated/boundaries_macros.tex``) and the table of those
points (``paper/generated/boundaries_codim2.tex``) from the check record
(``figures/boundaries_check.json``, workflow/scripts/boundaries_check.py)."""

from pathlib import Path

from impactdamper.analysis.curves import CODIM2_REASONS
from impactdamper.reporting.latex import MacroFile, fixed, render_macros, sci
from impactdamper.studies.vocabulary import tex

__all__ = ["codim2_points", "write_report"]

# The maps and the curves' kinds in the table.
PLANE_TEXT = {"theta": tex("theta"), "damping": f"{tex('delta1')} $=$ {tex('delta2')}"}
KIND_TEXT = {
    "fold": "fold",
    "period_doubling": "period doubling",
    "neimark_sacker": "Neimark--Sacker",
    "grazing_velocity": "zero-velocity grazing",
    "grazing_touch": "grazing touch",
}
# The codimension-two points' names in the table.
REASON_TEXT = {
    "cusp": "cusp of folds",
    "fold_flip": "fold-flip",
    "resonance_1_1": "1:1 resonance",
    "resonance_1_2": "1:2 resonance",
    "resonance_1_3": "1:3 resonance",
}


def percent(x) -> str:
    """A share as a percentage with one decimal, ``\\%`` included."""
    return fixed(None if x is None else 100.0 * x, 1) + "\\%"


def codim2_points(loaded: dict) -> list:
    """Every curve end at a codimension-two point, once per place (a fold-flip point ends both
    its fold and its period-doubling curve)."""
    out = {}
    for name, b in loaded.items():
        for c in b.curves:
            for (reason, _), (a, v) in zip(c.ends, (c.points[0], c.points[-1])):
                if reason in CODIM2_REASONS:
                    key = (name, c.label, reason, round(a, 5), round(v, 6))
                    out.setdefault(
                        key, {"plane": name, "cycle": c.label, "reason": reason, "gap": a, b.names[1]: v, "on": []}
                    )
                    out[key]["on"].append(c.kind)
    return list(out.values())


def write_report(record: dict, out_macros, out_table) -> None:
    """The macros and the table of codimension-two points of the check record."""
    th, dm = record["planes"]["theta"], record["planes"]["damping"]
    # The side checks' counts (analysis.boundary_checks.SIDE_COUNTS: the integers) of both planes.
    totals = (th["side_checks"]["total"], dm["side_checks"]["total"])
    side = {k: totals[0][k] + totals[1][k] for k, v in totals[0].items() if isinstance(v, int)}
    smallest = [
        p["side_checks"]["total"].get("smallest_reduced_distance")
        for p in (th, dm)
        if p["side_checks"]["total"].get("smallest_reduced_distance") is not None
    ]
    every = side["observed"] + side["reduced_observed"]
    pd = record["period_doubling_bisection"]
    m = MacroFile(["% Boundary curves of the regime maps (workflow/scripts/boundaries_check.py)."])
    m.extend(
        [
            ("BoundSeedRows", record["settings"]["seed_rows"]),
            ("BoundSeedGaps", record["settings"]["seed_gaps"]),
            ("BoundSideEvery", record["settings"]["side_points"]),
            ("BoundSideDistance", sci(record["settings"]["side_distance"], 0)),
            ("BoundCurvesTheta", th["curves"]),
            ("BoundCurvesDamping", dm["curves"]),
            ("BoundShareTheta", percent(th["map_reading"]["share"])),
            ("BoundShareDamping", percent(dm["map_reading"]["share"])),
            ("BoundShareNoNpTheta", percent(th["map_reading"]["share_without_np"])),
            ("BoundShareNoNpDamping", percent(dm["map_reading"]["share_without_np"])),
            ("BoundSidePoints", side["points"]),
            ("BoundSideObserved", side["observed"]),
            ("BoundSideChanged", side["changed"]),
            ("BoundSideAgree", side["agree"]),
            ("BoundSideDoubled", side["doubled"]),
            ("BoundSideAgreeTenth", side["agree_at_a_tenth"]),
            ("BoundSideCrossing", side["crossing"]),
            ("BoundSideShare", percent(side["agree"] / side["observed"] if side["observed"] else None)),
            # The crossing points checked again at half the distance to the nearest crossing.
            ("BoundSideReducedObserved", side["reduced_observed"]),
            ("BoundSideReducedAgree", side["reduced_agree"]),
            ("BoundSideReducedUnobserved", side["crossing"] - side["reduced_observed"]),
            ("BoundSideReducedSmallest", sci(min(smallest, default=None))),
            ("BoundSideEveryObserved", every),
            ("BoundSideEveryAgree", side["agree"] + side["reduced_agree"]),
            ("BoundSideShareEvery", percent((side["agree"] + side["reduced_agree"]) / every if every else None)),
            (
                "BoundFirstContactError",
                sci(
                    max(
                        (
                            e
                            for e in (th["first_contact"]["max_gap_error"], dm["first_contact"]["max_gap_error"])
                            if e is not None
                        ),
                        default=None,
                    )
                ),
            ),
            ("BoundPdBracketed", sum(r.get("bisected_gap") is not None for r in pd["rows"])),
            ("BoundPdValues", len(pd["rows"])),
            ("BoundPdMaxDifference", sci(pd["max_difference"])),
            ("BoundCpu", fixed(record["curves_cpu_s"], 1)),
            ("BoundCodimTwo", len(record["codim2"])),
        ]
    )
    # The paper's Fig. 2b motion (3/2) in theta: where its Neimark-Sacker and period-doubling curves run.
    for kind, name in (("neimark_sacker", "Ns"), ("period_doubling", "Pd")):
        c = next((c for c in th["curve_list"] if c["cycle"] == "3/2" and c["kind"] == kind), None)
        lo, hi = c["theta"] if c else (None, None)
        m.extend([(f"BoundThreeTwo{name}Low", fixed(lo, 3)), (f"BoundThreeTwo{name}High", fixed(hi, 3))])
    Path(out_macros).write_text(render_macros(m.record("")))
    Path(out_table).write_text(_codim2_table(record["codim2"]))


def _codim2_table(points: list) -> str:
    """The table of codimension-two points (booktabs): map, cycle, point, its curves, gap, value."""
    lines = [
        "\\begin{tabular}{llllrr}",
        "\\toprule",
        f"map & cycle & point & on curves & {tex('gap')} & value \\\\",
        "\\midrule",
    ]
    for r in points:
        v = r.get("theta", r.get("delta"))
        on = ", ".join(KIND_TEXT[k] for k in sorted(set(r["on"])))
        lines.append(
            f"{PLANE_TEXT[r['plane']]} & {r['cycle']} & {REASON_TEXT.get(r['reason'], r['reason'])} & {on} & ${fixed(r['gap'], 4)}$ & ${fixed(v, 4)}$ \\\\"
        )
    return "\n".join(lines + ["\\bottomrule", "\\end{tabular}"]) + "\n"
