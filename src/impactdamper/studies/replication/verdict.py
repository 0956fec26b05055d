"""The replication verdict of the paper's Fig. 2 claims (Timofeev, Lyuminarskiy & Lyuminarskiy
2019, DOI 10.18698/0236-3941-2019-1-90-100): each claim at the stated and the located case, by
the exact solver and confirmed (or not) by the independent ``solve_ivp`` integrator, with the
scan of the gap, the other readings and the search beyond the gap.

``workflow/scripts/verdict.py`` reads the stage's records, calls :func:`verdict` and writes the
verdict and its macros.
"""

from __future__ import annotations

from impactdamper.studies.replication.claims import CLAIM_B_IMPACTS, CLAIM_B_PERIOD_MULTIPLE
from impactdamper.studies.intervals import Interval, distance_to
from impactdamper.studies.replication.cases import PAPER

__all__ = ["PAPER_CLAIMS", "claims", "beyond_the_gap", "verdict"]


def _difference(cc: dict, claim: str) -> str:
    """The measured difference between the exact solver and solve_ivp behind a claim's
    "confirms", with its tolerance."""
    if claim == "a":
        c = cc["algorithm1_comparison"]
        if c["periodicity_residual"] is None:
            return "no orbit by either method"
        return (
            f"interval ends {c['max_interval_end_difference_over_T']:.1e} T, residual "
            f"{c['periodicity_residual']:.1e} (tol {c['time_tol']:.0e}, {c['residual_tol']:.0e})"
        )
    c = cc["algorithm2"]["cycle_comparison"]
    if c["reason"] and c["max_time_difference_over_T"] is None:
        return c["reason"]
    return (
        f"aligned cycles: times {c['max_time_difference_over_T']:.1e} T, velocities "
        f"{c['max_velocity_difference_rel']:.1e} (tol {c['time_tol']:.0e}, {c['velocity_tol']:.0e})"
    )


def _period(k: int) -> str:
    return "T" if k == 1 else f"{k}T"


def claims(ref: dict, cc: dict) -> dict:
    """The three claims' results for one case (exact and independent)."""
    a1, a2 = ref["algorithm1"], ref["algorithm2"]
    i1, i2 = cc["algorithm1"], cc["algorithm2"]
    neg = a1["negative_gap_intervals"]
    ineg = i1.get("negative_gap_intervals", [])
    fmt_iv = lambda ivs: ", ".join(f"({x:.4f}, {y:.4f}) T" for x, y in ivs)  # noqa: E731
    return {
        "a": {
            "holds": bool(a1["claim_a"]),
            "result": (
                f"gap negative on {fmt_iv(neg)}"
                if neg
                else ("no negative gap: the orbit is admissible" if a1["exists"] else "no orbit: " + a1["reason"])
            ),
            "ivp_holds": bool(i1["claim_a"]),
            "ivp_result": (f"gap negative on {fmt_iv(ineg)}" if ineg else "no negative gap")
            + (f"; periodicity residual {i1['periodicity_residual']:.1e}" if "periodicity_residual" in i1 else ""),
        },
        "b_period": {
            "holds": a2["period_multiple"] == CLAIM_B_PERIOD_MULTIPLE and a2["regime"] == "multi_impact",
            "result": (
                f"{a2['regime'].replace('_', ' ')}, T_c = {_period(a2['period_multiple'])}"
                if a2["period_multiple"]
                else "no settled period"
            ),
            "ivp_holds": i2["period_multiple"] == CLAIM_B_PERIOD_MULTIPLE,
            "ivp_result": f"T_c = {_period(i2['period_multiple'])}" if i2["period_multiple"] else "no period found",
        },
        "b_impacts": {
            "holds": a2["impacts_per_cycle"] == CLAIM_B_IMPACTS and a2["regime"] == "multi_impact",
            "result": f"{a2['impacts_per_cycle']} impact(s) per cycle",
            "ivp_holds": i2["impacts_per_cycle"] == CLAIM_B_IMPACTS and not i2["contact_in_cycle"],
            "ivp_result": f"{i2['impacts_per_cycle']} impact(s) per cycle",
        },
    }


PAPER_CLAIMS = {
    "a": "Algorithm No. 1: the gap is negative on (t1, t2)",
    "b_period": "Algorithm No. 2: T_c = 2T",
    "b_impacts": "Algorithm No. 2: three impacts per cycle",
}


def beyond_the_gap(search: dict, cmap: list[dict], scan: dict) -> dict:
    """Where, along each parameter alone (at the stated gap), both claims hold nearest the
    stated value; which parameter gets there with the smallest relative change; and the
    two-parameter map's share of cells where both hold."""
    names = list(search["parameters"])  # the parameters searched, in the search's order
    per = {}
    for name in names:
        d = search["parameters"][name]
        both = d["intervals"]["both"]
        near = d["nearest_both"]
        iv = next((r for r in both if near["nearest"] is not None and r["lo"] <= near["nearest"] <= r["hi"]), None)
        per[name] = {
            **near,
            "interval": [iv["lo"], iv["hi"]] if iv else None,
            "interval_width": (iv["hi"] - iv["lo"]) if iv else None,
            "a": d["intervals"]["a"],
            "b": d["intervals"]["b"],
            "both": both,
        }
    found = [n for n in names if per[n]["relative_distance"] is not None]
    nearest = min(found, key=lambda n: per[n]["relative_distance"]) if found else None
    cells = len(cmap)
    both_cells = sum(r["both"] == "true" for r in cmap)
    # Along the gap (the scan of gap_scan.py), for comparison.
    stated_gap = float(scan["stated_gap"])
    gd, gx = distance_to(
        [Interval(r["lo"], r["hi"], r["lo_open"], r["hi_open"], None, None) for r in scan["both_ranges"]], stated_gap
    )
    gap = {
        "stated": stated_gap,
        "nearest": gx,
        "distance": gd if gx is not None else None,
        "relative_distance": gd / abs(stated_gap) if gx is not None else None,
    }
    return {
        "parameters": per,
        "nearest_parameter": nearest,
        "gap": gap,
        "none_found": [n for n in names if n not in found],
        "rel_tol": search["rel_tol"],
        "map_cells": cells,
        "map_both_cells": both_cells,
        "reference_check": {
            k: search["reference_check"][k] for k in ("every", "points", "agree", "settling", "cycles")
        },
    }


def verdict(
    ref_s: dict, ref_l: dict, cc_s: dict, cc_l: dict, scan: dict, rd: dict, search: dict, cmap: list[dict]
) -> tuple[list[dict], dict]:
    """The verdict from the stage's records: the stated and located cases (``ref_*``, as
    solve_case.py writes them) and their cross-checks (``cc_*``), the gap scan, the other
    readings (``rd``), the search beyond the gap and the claims map's rows.

    Returns
    -------
    rows : list of dict
        One row per claim of :data:`PAPER_CLAIMS`.
    result : dict
        The whole verdict (figures/verdict.json).
    """
    cs, cl = claims(ref_s, cc_s), claims(ref_l, cc_l)
    rows = []
    for key, text in PAPER_CLAIMS.items():
        rows.append(
            {
                "claim": key,
                "paper": text,
                "stated_gap": ref_s["parameters"]["gap"],
                "stated_result": cs[key]["result"],
                "stated_ivp_result": cs[key]["ivp_result"],
                "stated_ivp_difference": _difference(cc_s, key[0]),
                # Confirmed: the same verdict and, measured, the same motion within tolerance.
                "ivp_confirms": cs[key]["holds"] == cs[key]["ivp_holds"] and cc_s["agree_" + key[0]],
                "reproduced": cs[key]["holds"] and cs[key]["ivp_holds"],
                "located_gap": ref_l["parameters"]["gap"],
                "located_result": cl[key]["result"],
                "located_ivp_result": cl[key]["ivp_result"],
                "located_ivp_difference": _difference(cc_l, key[0]),
                "located_ivp_confirms": cl[key]["holds"] == cl[key]["ivp_holds"] and cc_l["agree_" + key[0]],
            }
        )
    reproducing = [r["id"] for r in rd["readings"] if r["reproduces"]]
    partial = [r["id"] for r in rd["readings"] if (r["claim_a"] or r["claim_b"]) and not r["reproduces"]]
    result = {
        "paper": PAPER,
        "claims": rows,
        "stated": {"parameters": ref_s["parameters"], "claims": cs, "crosscheck": cc_s},
        "located": {
            "parameters": ref_l["parameters"],
            "claims": cl,
            "crosscheck": cc_l,
            "rule": scan["located"]["rule"],
            "range": scan["located"]["range"],
        },
        "ranges": {
            "alg1_existence_limit": scan["alg1_existence_limit"],
            "claim_a": scan["claim_a_ranges"],
            "claim_b": scan["claim_b_ranges"],
            "both": scan["both_ranges"],
            "window": scan["window"],
            "orbit": scan["orbit_range"],
            "end_checks_agree": all(c["agree"] for c in scan["end_checks"]),
        },
        "other_readings": {
            "reproducing": reproducing,
            "partial": partial,
            "R_ranges": rd["R_ranges"],
            "random_states": rd["random_states"],
        },
        "beyond_the_gap": beyond_the_gap(search, cmap, scan),
        "eq13_note": (
            "Eq. (13) as printed gives x21s' = x1s' - x2s', the opposite of eq. (12)'s x21s = x2s - x1s; "
            "the library uses eq. (12)'s sign. With the printed sign Algorithm No. 1's orbit violates the "
            "impact law (S/(D v) != 1), see other_readings: eq13_as_printed."
        ),
    }
    return rows, result
