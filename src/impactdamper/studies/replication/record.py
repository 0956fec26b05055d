"""The replication verdict's numbers for the report: every number ``paper/generated/verdict_macros.tex``
quotes, as macros of the stage's record (:class:`impactdamper.reporting.latex.MacroFile`).

The verdict is on the paper's Fig. 2 (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100):
claim by claim (:mod:`impactdamper.studies.replication.verdict`), what the stated parameters give and where
the claimed behaviour does occur: along the gap (the gap scan), beyond it (each parameter alone,
:mod:`impactdamper.studies.claims`), and under other readings of the paper
(:mod:`impactdamper.studies.replication.readings`). Numbers are bare (for math mode); ``MISSING`` where a
value does not exist.
"""

from __future__ import annotations

from impactdamper.core.parameters import Parameters
from impactdamper.reporting.latex import MISSING, MacroFile, fixed, sci
from impactdamper.studies.claims.search import SEARCH_PARAMETERS, SEARCH_SYMBOLS

__all__ = ["macros", "claims_macros", "MACRO_OF"]

# Macro names of the parameters (TeX macro names are letters only).
MACRO_OF = {"theta": "Theta", "mu": "Mu", "N": "N", "delta1": "DeltaOne", "delta2": "DeltaTwo", "R": "R"}


def claims_macros(b: dict) -> MacroFile:
    """Macros of the search beyond the gap (claims_by_parameter)."""
    m = [
        "% The claims searched beyond the gap (figures/claims_by_parameter.csv): each parameter alone at the\n",
        "% stated gap. *NearestBoth: the nearest value where both claims hold; *Distance: how far from the\n",
        "% stated value (absolute; *RelDistance relative, in per cent).\n",
    ]
    m = MacroFile(m)
    add = m.add
    add("ClaimsRelTol", sci(b["rel_tol"], 0))
    for name in SEARCH_PARAMETERS:
        d, tag = b["parameters"][name], "Claims" + MACRO_OF[name]
        add(tag + "Stated", fixed(d["stated"], 2))
        add(tag + "BothCount", str(d["intervals"]))
        add(tag + "NearestBoth", fixed(d["nearest"], 4) if d["nearest"] is not None else MISSING)
        add(tag + "Distance", fixed(d["distance"], 4) if d["distance"] is not None else MISSING)
        add(
            tag + "RelDistance",
            fixed(100 * d["relative_distance"], 1) if d["relative_distance"] is not None else MISSING,
        )
        iv = d["interval"]
        add(tag + "BothLo", fixed(iv[0], 4) if iv else MISSING)
        add(tag + "BothHi", fixed(iv[1], 4) if iv else MISSING)
        add(tag + "BothWidth", fixed(d["interval_width"], 4) if iv else MISSING)
        open_end = next((r for r in d["both"] if iv and r["lo"] == iv[0] and r["hi"] == iv[1]), {})
        add(tag + "BothOpen", _yes(open_end.get("lo_open", False) or open_end.get("hi_open", False)))
    near = b["nearest_parameter"]
    add("ClaimsNearestParameter", SEARCH_SYMBOLS[near] if near else MISSING)
    add("ClaimsNearestParameterName", near or MISSING)
    gap = b["gap"]
    add("ClaimsGapNearest", fixed(gap["nearest"], 3) if gap["nearest"] is not None else MISSING)
    add("ClaimsGapRelDistance", fixed(100 * gap["relative_distance"], 1) if gap["nearest"] is not None else MISSING)
    nd = b["parameters"][near] if near else None
    add("ClaimsNearestRelDistance", fixed(100 * nd["relative_distance"], 1) if nd else MISSING)
    add("ClaimsNearestWidth", fixed(nd["interval_width"], 4) if nd else MISSING)
    add("ClaimsNearestLo", fixed(nd["interval"][0], 4) if nd else MISSING)
    add("ClaimsNearestHi", fixed(nd["interval"][1], 4) if nd else MISSING)
    add("ClaimsNearestStated", fixed(nd["stated"], 2) if nd else MISSING)
    add("ClaimsNoneFound", str(len(b["none_found"])))
    add("ClaimsMapCells", str(b["map_cells"]))
    add("ClaimsMapBothCells", str(b["map_both_cells"]))
    add("ClaimsReferenceEvery", str(b["reference_check"]["every"]))
    add("ClaimsReferenceChecked", str(b["reference_check"]["points"]))
    add("ClaimsReferenceAgree", str(b["reference_check"]["agree"]))
    add("ClaimsReferenceSettling", str(b["reference_check"]["settling"]))
    add("ClaimsReferenceCycles", str(b["reference_check"]["cycles"]))
    return m


def _short(text: str) -> str:
    """The bifurcation's name, for prose (the part before the colon)."""
    return text.split(":")[0].replace("Neimark-Sacker", "Neimark--Sacker")


def _yes(flag) -> str:
    return "yes" if flag else "no"


def _range_of(ranges: list[dict], gap: float) -> dict | None:
    """The range of ``ranges`` ({"lo", "hi"}) that holds ``gap``, or None."""
    for r in ranges:
        if r["lo"] <= gap <= r["hi"]:
            return r
    return None


def macros(ref_s, ref_l, cc_s, cc_l, scan, rd, rows) -> MacroFile:
    """Every number the report quotes, as \\newcommand (bare numbers for math mode).

    Parameters
    ----------
    ref_s, ref_l : dict
        The stated and located cases' records (``figures/reference_{stated,located}.json``).
    cc_s, cc_l : dict
        Their cross-checks by ``solve_ivp`` (``figures/crosscheck_*.json``).
    scan, rd : dict
        The gap scan (``figures/gap_scan.json``) and the other readings
        (``figures/other_readings.json``).
    rows : list of dict
        The verdict's rows, claim by claim (:func:`impactdamper.studies.replication.verdict.verdict`).
    """
    p = ref_s["parameters"]
    m = [
        "% Replication verdict of the paper's Fig. 2 (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100).\n",
        "% Generated by workflow/scripts/verdict.py (Snakemake rule verdict); do not edit.\n",
        "% Numbers are bare (for math mode); \\mbox{--} where a value does not exist. Times are in units\n",
        "% of T since the impact (Algorithm No. 1) or since the cycle's first impact (Algorithm No. 2);\n",
        "% closing velocities relative to x_st omega, impulses relative to m1 x_st omega. *MinGap: the smallest\n",
        "% interior local minimum of Delta/x_st (0 when the gap has none). Ranges are in Delta0/x_st\n",
        "% (or R).\n",
    ]
    m = MacroFile(m)
    add = m.add
    for name, key, d in (
        ("Theta", "theta", 2),
        ("Mu", "mu", 2),
        ("N", "N", 2),
        ("DeltaOne", "delta1", 2),
        ("DeltaTwo", "delta2", 2),
        ("R", "R", 2),
        ("Gap", "gap", 1),
        ("Omega", "omega", 0),
        ("Xst", "x_st", 0),
    ):
        add("Stated" + name, fixed(p[key], d))
    add("StatedT", fixed(Parameters(**p).T, 4))
    verdict_text = {True: "reproduced", False: "not reproduced"}
    for r, name in zip(rows, ("ClaimA", "ClaimBPeriod", "ClaimBImpacts")):
        add(name + "Verdict", verdict_text[r["reproduced"]])
        add(name + "IvpConfirms", _yes(r["ivp_confirms"]))
    for tag, ref, cc in (("Stated", ref_s, cc_s), ("Located", ref_l, cc_l)):
        _case_macros(add, tag, ref, cc)
    _scan_macros(add, scan, cc_s, ref_l)
    _readings_macros(add, rd)
    return m


def _case_macros(add, tag: str, ref: dict, cc: dict) -> None:
    """One case's macros (``tag``: Stated or Located): Algorithm No. 1's orbit, Algorithm No. 2's
    cycle and its impacts, and their cross-checks by ``solve_ivp``."""
    a1, a2 = ref["algorithm1"], ref["algorithm2"]
    add(tag + "AlgOneExists", _yes(a1["exists"]))
    add(tag + "AlgOneImpactPhase", fixed(a1["impact_phase"], 5) if a1["exists"] else MISSING)
    # Closing velocities in units of x_st omega, impulses of m1 x_st omega.
    q = Parameters(**ref["parameters"])
    vscale, sscale = q.x_st * q.omega, q.m1 * q.x_st * q.omega
    add(tag + "AlgOneImpulse", fixed(a1["S"] / sscale, 4) if a1["exists"] else MISSING)
    add(tag + "AlgOneVelocity", fixed(a1["velocity"] / vscale, 3) if a1["exists"] else MISSING)
    add(tag + "AlgOneMinGap", fixed(a1["min_gap"], 3) if a1["exists"] else MISSING)
    neg = a1["negative_gap_intervals"]
    add(tag + "AlgOneNegativeIntervals", str(len(neg)))
    add(tag + "AlgOneTOne", fixed(neg[0][0], 4) if neg else MISSING)
    add(tag + "AlgOneTTwo", fixed(neg[0][1], 4) if neg else MISSING)
    i1 = cc["algorithm1"]
    add(tag + "IvpAlgOneResidual", sci(i1.get("periodicity_residual")))
    ineg = i1.get("negative_gap_intervals", [])
    add(tag + "IvpAlgOneTOne", fixed(ineg[0][0], 4) if ineg else MISSING)
    add(tag + "IvpAlgOneTTwo", fixed(ineg[0][1], 4) if ineg else MISSING)
    add(tag + "AlgTwoRegime", a2["regime"].replace("_", " "))
    add(tag + "AlgTwoPeriodMultiple", str(a2["period_multiple"]))
    add(tag + "AlgTwoImpacts", str(a2["impacts_per_cycle"]))
    add(tag + "AlgTwoPeriods", str(a2["periods_simulated"]))
    add(tag + "AlgTwoXOneMax", fixed(a2["x1_max"], 3))
    table = a2["impact_table"]
    for k, row in enumerate(table[:6]):
        word = ("One", "Two", "Three", "Four", "Five", "Six")[k]
        add(f"{tag}Impact{word}OverT", fixed(row["t_over_T"], 4))
        add(f"{tag}Impact{word}Phase", fixed(row["phase"], 4))
        add(f"{tag}Impact{word}Velocity", fixed(row["velocity"] / vscale, 3))
        add(f"{tag}Impact{word}Impulse", fixed(row["impulse"] / sscale, 4))
    i2 = cc["algorithm2"]
    add(tag + "IvpPeriodMultiple", str(i2["period_multiple"]))
    add(tag + "IvpImpacts", str(i2["impacts_per_cycle"]))
    add(tag + "IvpTimeDiff", sci(i2.get("max_time_difference_over_T")))
    add(tag + "IvpVelocityDiff", sci(i2.get("max_velocity_difference_rel")))
    add(tag + "IvpCycleAgree", _yes(i2["agree"]))
    c1 = cc["algorithm1_comparison"]
    end_diff = c1["max_interval_end_difference_over_T"]
    add(tag + "IvpAlgOneEndDiff", sci(end_diff) if end_diff and a1["negative_gap_intervals"] else MISSING)
    add(tag + "IvpAlgOneAgree", _yes(c1["agree"]))


def _scan_macros(add, scan: dict, cc_s: dict, ref_l: dict) -> None:
    """The cross-checks' tolerances, the gap scan's window and claim ranges, its end checks and
    the one-impact orbit's range along the gap."""
    cmp = cc_s["algorithm2"]["cycle_comparison"]
    add("CrosscheckTimeTol", sci(cmp["time_tol"], 0))
    add("CrosscheckVelocityTol", sci(cmp["velocity_tol"], 0))
    add("CrosscheckResidualTol", sci(cc_s["algorithm1_comparison"]["residual_tol"], 0))
    add("LocatedGap", fixed(ref_l["parameters"]["gap"], 2))
    w = scan["window"]
    add("ScanGapMin", fixed(w["gap_min"], 1))
    add("ScanGapMax", fixed(w["gap_max"], 1))
    add("ScanGapStep", fixed(w["alg2_gap_step"], 2))
    add("ScanAlgOneGapStep", fixed(w["alg1_gap_step"], 3))
    add("ScanBisectTol", sci(w["alg2_bisect_tol"], 0))
    add("LocatedMargin", fixed(w["located_margin"], 2))  # the rule that picks the located case
    add("AlgOneExistenceLimit", fixed(scan["alg1_existence_limit"], 3))
    g_loc = ref_l["parameters"]["gap"]
    for name, key, digits in (
        ("ClaimA", "claim_a_ranges", 3),
        ("ClaimB", "claim_b_ranges", 3),
        ("Both", "both_ranges", 3),
    ):
        rs = scan[key]
        add(name + "RangeCount", str(len(rs)))
        r = _range_of(rs, g_loc) or (rs[0] if rs else None)
        add(name + "RangeLo", fixed(r["lo"], digits) if r else MISSING)
        add(name + "RangeHi", fixed(r["hi"], digits) if r else MISSING)
    add("EndChecksAgree", _yes(all(c["agree"] for c in scan["end_checks"])))
    add("EndChecksCount", str(len(scan["end_checks"])))
    add("EndChecksAgreeCount", str(sum(bool(c["agree"]) for c in scan["end_checks"])))
    off = [c for c in scan["end_checks"] if not c["agree"]]
    worst = max(off, key=lambda c: c["details"].get("max_velocity_difference_rel") or 0.0) if off else None
    if worst is not None and "cycle_comparison" in worst["details"]:
        cmp = worst["details"]["cycle_comparison"]
        add("EndChecksOffGap", fixed(worst["gap"], 3))
        add("EndChecksOffRole", worst["role"])
        add("EndChecksOffPeriodMultiple", str(cmp["period_multiple"][0]))
        add("EndChecksOffImpacts", str(cmp["impacts"][0]))
        add("EndChecksOffTimeDiff", sci(cmp["max_time_difference_over_T"]))
        add("EndChecksOffVelocityDiff", sci(cmp["max_velocity_difference_rel"]))
        # A phrase, not "yes"/"no": the text reads "... with z impacts (both give the same verdict ...)".
        add(
            "EndChecksOffSameClaim",
            "both give the same verdict on the claim"
            if worst["exact"] == worst["independent"]
            else "yet they give different verdicts on the claim",
        )
    orbit = scan["orbit_range"]
    if orbit.get("found"):
        add("OrbitRangeLo", fixed(orbit["lo"], 4))
        add("OrbitRangeHi", fixed(orbit["hi"], 4))
        add("OrbitLoBifurcation", _short(orbit.get("lo_bifurcation", "")))
        add("OrbitHiBifurcation", _short(orbit.get("hi_bifurcation", "")))
        add("OrbitSeedGap", fixed(orbit["seed_gap"], 2))
        g_loc = ref_l["parameters"]["gap"]
        nearest = min(orbit["branch"], key=lambda b: abs(b[0] - g_loc))
        if abs(nearest[0] - g_loc) < 1e-9:
            add("LocatedSpectralRadius", fixed(nearest[1], 3))


def _readings_macros(add, rd: dict) -> None:
    """The other readings of the paper: how many reproduce the claims, eq. (13) as printed, R as a
    loss, the claims' ranges in R, the random initial states and the printed velocities."""
    readings = {r["id"]: r for r in rd["readings"]}
    add("ReadingsCount", str(len(readings) - 1))  # the stated baseline is not a reading
    add("ReadingsReproducing", str(sum(bool(r["reproduces"]) for k, r in readings.items() if k != "stated")))
    eq13 = readings.get("eq13_as_printed")
    if eq13:
        add("EqThirteenClaimA", _yes(eq13["claim_a"]))
        add("EqThirteenTOne", fixed(eq13["alg1_t1"], 4) if eq13["alg1_t1"] is not None else MISSING)
        add("EqThirteenTTwo", fixed(eq13["alg1_t2"], 4) if eq13["alg1_t2"] is not None else MISSING)
        add("EqThirteenMinGap", fixed(eq13["alg1_min_gap"], 3) if eq13["alg1_min_gap"] is not None else MISSING)
        ratio = rd["details"]["eq13_as_printed"].get("impact_law_ratio")
        add("EqThirteenImpactLawRatio", fixed(ratio, 3) if ratio is not None else MISSING)
    loss = readings.get("R_as_loss")
    if loss:
        add("RAsLossR", fixed(loss["R"], 2))
        add("RAsLossReproduces", _yes(loss["reproduces"]))
        add("RAsLossTOne", fixed(loss["alg1_t1"], 4) if loss["alg1_t1"] is not None else MISSING)
        add("RAsLossTTwo", fixed(loss["alg1_t2"], 4) if loss["alg1_t2"] is not None else MISSING)
        add("RAsLossMinGap", fixed(loss["alg1_min_gap"], 4) if loss["alg1_min_gap"] is not None else MISSING)
    rr = rd["R_ranges"]
    for name, key in (("RClaimA", "claim_a"), ("RClaimB", "claim_b"), ("RBoth", "both")):
        r = rr[key][0] if rr[key] else None
        add(name + "Lo", fixed(r["lo"], 3) if r else MISSING)
        add(name + "Hi", fixed(r["hi"], 3) if r else MISSING)
    rs = rd["random_states"]
    add("RandomStatesCount", str(rs["count"]))
    add("RandomStatesSeed", str(rs["seed"]))
    add("RandomStatesMotions", str(len(rs["motions"])))
    add("RandomStatesClaimB", _yes(rs["claim_b_found"]))
    pv = readings.get("printed_velocities")
    if pv:
        add("PrintedVelocitiesRegime", pv["alg2_regime"].replace("_", " "))
        add("PrintedVelocitiesPeriodMultiple", str(pv["alg2_period_multiple"]))
