"""The replication verdict's numbers for the report: every number ``paper/generated/verdict_macros.tex``
quotes, as macros of the stage's record, declared for :mod:`impactdamper.reporting.texrecord`.

The verdict is on the paper's Fig. 2 (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100):
claim by claim (:mod:`impactdamper.studies.replication.verdict`), what the stated parameters give
and where the claimed behaviour does occur: along the gap (the gap scan), beyond it (each
parameter alone, the claims stage's record), and under other readings of the
paper (:mod:`impactdamper.studies.replication.readings`). Numbers are bare (for math mode);
``MISSING`` where a value does not exist.
"""

from __future__ import annotations

from impactdamper.core.parameters import Parameters
from impactdamper.reporting.latex import MacroFile
from impactdamper.reporting.texrecord import COUNT, TEXT, WORDS, YES_NO, Format, Macro, fixed, macro_lines, percent
from impactdamper.reporting.texrecord import macros_named_by_path, sci
from impactdamper.studies.vocabulary import SPEC, tex

__all__ = ["macros", "claims_macros"]

# --- the search beyond the gap (figures/verdict.json's beyond_the_gap) ---------------------------
CLAIMS_COMMENTS = [
    "% The claims searched beyond the gap (figures/claims_by_parameter.csv): each parameter alone at the",
    "% stated gap. *NearestBoth: the nearest value where both claims hold; *Distance: how far from the",
    "% stated value (absolute; *RelDistance relative, in per cent).",
]


def _open_end(d: dict) -> bool:
    """Whether the nearest interval where both claims hold reaches the searched range's end."""
    iv = d["interval"]
    end = next((r for r in d["both"] if iv and r["lo"] == iv[0] and r["hi"] == iv[1]), {})
    return end.get("lo_open", False) or end.get("hi_open", False)


# Per searched parameter ({P}: its macro part).
SEARCHED = (
    Macro("Claims{P}Stated", "stated", fixed(2)),
    Macro("Claims{P}BothCount", "intervals", COUNT),
    Macro("Claims{P}NearestBoth", "nearest", fixed(4)),
    Macro("Claims{P}Distance", "distance", fixed(4)),
    Macro("Claims{P}RelDistance", "relative_distance", percent(1)),
    Macro("Claims{P}BothLo", "interval.0", fixed(4), when="interval"),
    Macro("Claims{P}BothHi", "interval.1", fixed(4), when="interval"),
    Macro("Claims{P}BothWidth", "interval_width", fixed(4), when="interval"),
    Macro("Claims{P}BothOpen", _open_end, YES_NO),
)
# The search as a whole (the parameter nearest its stated value: "near", None where none).
SEARCH = (
    Macro("ClaimsNearestParameter", "nearest_parameter", Format(tex)),
    Macro("ClaimsNearestParameterName", "nearest_parameter"),
    Macro("ClaimsGapNearest", "gap.nearest", fixed(3)),
    Macro("ClaimsGapRelDistance", "gap.relative_distance", percent(1), when=lambda b: b["gap"]["nearest"] is not None),
    Macro("ClaimsNearestRelDistance", "near.relative_distance", percent(1)),
    Macro("ClaimsNearestWidth", "near.interval_width", fixed(4)),
    Macro("ClaimsNearestLo", "near.interval.0", fixed(4)),
    Macro("ClaimsNearestHi", "near.interval.1", fixed(4)),
    Macro("ClaimsNearestStated", "near.stated", fixed(2)),
    Macro("ClaimsNearestFarRelDistance", lambda b: _far_relative_distance(b["near"]), percent(1)),
    Macro("ClaimsNearestEndNote", lambda b: _nearer_end_note(b["nearest_parameter"], b["near"], b["dependent"])),
    Macro("ClaimsNoneFound", lambda b: len(b["none_found"]), COUNT),
    *macros_named_by_path("Claims", ("map_cells", "map_both_cells"), COUNT),
    Macro("ClaimsReferenceEvery", "reference_check.every", COUNT),
    Macro("ClaimsReferenceChecked", "reference_check.points", COUNT),
    *macros_named_by_path("ClaimsReference", ("agree", "settling", "cycles"), COUNT, root="reference_check."),
)


def _far_relative_distance(near: dict | None) -> float | None:
    """How far, relative to the stated value, the farther end of the nearest interval where both
    claims hold lies (the nearer end's distance is the search's own)."""
    if not near or not near.get("interval"):
        return None
    return max(abs(x - near["stated"]) for x in near["interval"]) / abs(near["stated"])


def _nearer_end_note(name: str | None, near: dict | None, dependent: dict) -> str:
    """A clause for the nearest reproducing change where its nearer end depends on the solver
    (the pure-Python solver does not reproduce the compiled solver's verdict in its final
    bracket), else nothing."""
    if not near or near.get("nearest") is None or near["nearest"] not in dependent.get(name, ()):
        return ""
    return f" (the nearer end, ${SPEC[name].symbol}={near['nearest']:.4f}$, depends on the solver)"


def claims_macros(b: dict, dependent: dict | None = None) -> MacroFile:
    """Macros of the search beyond the gap (claims_by_parameter); ``dependent``: the interval
    ends that depend on the solver, by parameter (the search's ``solver_dependent_ends``)."""
    m = MacroFile(CLAIMS_COMMENTS + [("ClaimsRelTol", sci(0)(b["rel_tol"]))])
    for name, d in b["parameters"].items():  # the parameters searched, in the search's order
        m.extend(macro_lines(SEARCHED, d, P=SPEC[name].macro))
    near = b["nearest_parameter"]
    m.extend(macro_lines(SEARCH, {**b, "near": b["parameters"][near] if near else None, "dependent": dependent or {}}))
    return m


# --- the verdict: the stated point, the two cases, the gap scan, the readings -------------------
COMMENTS = [
    "% Replication verdict of the paper's Fig. 2 (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100).",
    "% Generated by workflow/scripts/verdict.py (Snakemake rule verdict); do not edit.",
    "% Numbers are bare (for math mode); \\mbox{--} where a value does not exist. Times are in units",
    "% of T since the impact (Algorithm No. 1) or since the cycle's first impact (Algorithm No. 2);",
    "% closing velocities relative to x_st omega, impulses relative to m1 x_st omega. *MinGap: the smallest",
    "% interior local minimum of Delta/x_st (0 when the gap has none). Ranges are in Delta0/x_st",
    "% (or R).",
]
# The stated parameters: (name, decimals).
STATED_DIGITS = (("theta", 2), ("mu", 2), ("N", 2), ("delta1", 2), ("delta2", 2), ("R", 2), ("gap", 1))
STATED_DIGITS += (("omega", 0), ("x_st", 0))
VERDICT_WORDS = Format({True: "reproduced", False: "not reproduced"}.get)
CLAIM_ROWS = (Macro("{C}Verdict", "reproduced", VERDICT_WORDS), Macro("{C}IvpConfirms", "ivp_confirms", YES_NO))

# One case ({T}: Stated or Located): Algorithm No. 1's orbit (a1), Algorithm No. 2's cycle (a2),
# their cross-checks by solve_ivp (i1, i2, c1); v and s: the units of closing velocities
# (x_st omega) and impulses (m1 x_st omega).
CASE = (
    Macro("{T}AlgOneExists", "a1.exists", YES_NO),
    Macro("{T}AlgOneImpactPhase", "a1.impact_phase", fixed(5), when="a1.exists"),
    Macro("{T}AlgOneImpulse", lambda c: c["a1"]["S"] / c["s"], fixed(4), when="a1.exists"),
    Macro("{T}AlgOneVelocity", lambda c: c["a1"]["velocity"] / c["v"], fixed(3), when="a1.exists"),
    Macro("{T}AlgOneMinGap", "a1.min_gap", fixed(3), when="a1.exists"),
    Macro("{T}AlgOneNegativeIntervals", lambda c: len(c["a1"]["negative_gap_intervals"]), COUNT),
    Macro("{T}AlgOneTOne", "a1.negative_gap_intervals.0?.0", fixed(4)),
    Macro("{T}AlgOneTTwo", "a1.negative_gap_intervals.0?.1", fixed(4)),
    Macro("{T}IvpAlgOneResidual", "i1.periodicity_residual?", sci()),
    Macro("{T}IvpAlgOneTOne", "i1.negative_gap_intervals?.0?.0", fixed(4)),
    Macro("{T}IvpAlgOneTTwo", "i1.negative_gap_intervals?.0?.1", fixed(4)),
    Macro("{T}AlgTwoRegime", "a2.regime", WORDS),
    Macro("{T}AlgTwoPeriodMultiple", "a2.period_multiple", COUNT),
    # The settled period as the text writes it: T, 2T, ... (T_c = T, never 1 T).
    Macro("{T}AlgTwoPeriod", "a2.period_multiple", Format(lambda k: "T" if k == 1 else f"{k}T")),
    Macro("{T}AlgTwoImpacts", "a2.impacts_per_cycle", COUNT),
    Macro("{T}AlgTwoPeriods", "a2.periods_simulated", COUNT),
    Macro("{T}AlgTwoXOneMax", "a2.x1_max", fixed(3)),
)
# Each of the cycle's first six impacts ({W}: One ... Six).
IMPACT = (
    Macro("{T}Impact{W}OverT", "row.t_over_T", fixed(4)),
    Macro("{T}Impact{W}Phase", "row.phase", fixed(4)),
    Macro("{T}Impact{W}Velocity", lambda c: c["row"]["velocity"] / c["v"], fixed(3)),
    Macro("{T}Impact{W}Impulse", lambda c: c["row"]["impulse"] / c["s"], fixed(4)),
)
ORDINALS = ("One", "Two", "Three", "Four", "Five", "Six")
CASE_CHECKS = (
    Macro("{T}IvpPeriodMultiple", "i2.period_multiple", COUNT),
    Macro("{T}IvpImpacts", "i2.impacts_per_cycle", COUNT),
    Macro("{T}IvpTimeDiff", "i2.max_time_difference_over_T?", sci()),
    Macro("{T}IvpVelocityDiff", "i2.max_velocity_difference_rel?", sci()),
    Macro("{T}IvpCycleAgree", "i2.agree", YES_NO),
    Macro(
        "{T}IvpAlgOneEndDiff",
        "c1.max_interval_end_difference_over_T",
        sci(),
        when=lambda c: c["c1"]["max_interval_end_difference_over_T"] and c["a1"]["negative_gap_intervals"],
    ),
    Macro("{T}IvpAlgOneAgree", "c1.agree", YES_NO),
)


def _case_macros(tag: str, ref: dict, cc: dict) -> list:
    """One case's macros (``tag``: Stated or Located): Algorithm No. 1's orbit, Algorithm No. 2's
    cycle and its impacts, and their cross-checks by ``solve_ivp``."""
    q = Parameters(**ref["parameters"])
    units = {"v": q.x_st * q.omega, "s": q.m1 * q.x_st * q.omega}
    source = {
        "a1": ref["algorithm1"],
        "a2": ref["algorithm2"],
        "i1": cc["algorithm1"],
        "i2": cc["algorithm2"],
        "c1": cc["algorithm1_comparison"],
        **units,
    }
    out = macro_lines(CASE, source, T=tag)
    for word, row in zip(ORDINALS, ref["algorithm2"]["impact_table"]):
        out += macro_lines(IMPACT, {"row": row, **units}, T=tag, W=word)
    return out + macro_lines(CASE_CHECKS, source, T=tag)


def _range_of(ranges: list[dict], gap: float) -> dict | None:
    """The range of ``ranges`` ({"lo", "hi"}) that holds ``gap``, or None."""
    for r in ranges:
        if r["lo"] <= gap <= r["hi"]:
            return r
    return None


# The cross-checks' tolerances and the gap scan (the located gap: g).
SCAN = (
    Macro("CrosscheckTimeTol", "cc.algorithm2.cycle_comparison.time_tol", sci(0)),
    Macro("CrosscheckVelocityTol", "cc.algorithm2.cycle_comparison.velocity_tol", sci(0)),
    Macro("CrosscheckResidualTol", "cc.algorithm1_comparison.residual_tol", sci(0)),
    Macro("LocatedGap", "g", fixed(2)),
    Macro("ScanGapMin", "scan.window.gap_min", fixed(1)),
    Macro("ScanGapMax", "scan.window.gap_max", fixed(1)),
    Macro("ScanGapStep", "scan.window.alg2_gap_step", fixed(2)),
    Macro("ScanAlgOneGapStep", "scan.window.alg1_gap_step", fixed(3)),
    Macro("ScanBisectTol", "scan.window.alg2_bisect_tol", sci(0)),
    Macro("LocatedMargin", "scan.window.located_margin", fixed(2)),  # the rule that picks the located case
    Macro("AlgOneExistenceLimit", "scan.alg1_existence_limit", fixed(3)),
)
# Each claim's ranges along the gap ({R}: ClaimA, ClaimB, Both): the one holding the located
# gap, else the first.
RANGES = (
    Macro("{R}RangeCount", lambda s: len(s["ranges"]), COUNT),
    Macro("{R}RangeLo", "range.lo", fixed(3)),
    Macro("{R}RangeHi", "range.hi", fixed(3)),
)
NUMBER_WORDS = ("none", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine")


def _count_clause(n: int, one: str, many: str) -> str:
    """A count and its verb as words: "none gives a different verdict", "one gives ...", "12 give
    ..." (``one``: the clause after a count of one or none, ``many``: after a larger count)."""
    word = NUMBER_WORDS[n] if n < len(NUMBER_WORDS) else str(n)
    return f"{word} {one if n <= 1 else many}"


END_CHECKS = (
    Macro("EndChecksAgree", lambda checks: all(c["agree"] for c in checks), YES_NO),
    Macro("EndChecksCount", len, COUNT),
    Macro("EndChecksAgreeCount", lambda checks: sum(bool(c["agree"]) for c in checks), COUNT),
    # The end checks where the two methods give different verdicts on the claim, in words.
    Macro(
        "EndChecksDifferentText",
        lambda checks: _count_clause(
            sum(c["exact"] != c["independent"] for c in checks), "gives a different verdict", "give different verdicts"
        ),
    ),
)
# The end check whose methods differ most (where one differs).
END_CHECK_OFF = (
    Macro("EndChecksOffGap", "gap", fixed(3)),
    Macro("EndChecksOffRole", "role"),
    Macro("EndChecksOffPeriodMultiple", "details.cycle_comparison.period_multiple.0", COUNT),
    Macro("EndChecksOffImpacts", "details.cycle_comparison.impacts.0", COUNT),
    Macro("EndChecksOffTimeDiff", "details.cycle_comparison.max_time_difference_over_T", sci()),
    Macro("EndChecksOffVelocityDiff", "details.cycle_comparison.max_velocity_difference_rel", sci()),
    # A phrase, not "yes"/"no": the text reads "... with z impacts (both give the same verdict ...)".
    Macro(
        "EndChecksOffSameClaim",
        lambda c: c["exact"] == c["independent"],
        Format(
            lambda same: (
                "both give the same verdict on the claim" if same else "yet they give different verdicts on the claim"
            )
        ),
    ),
)


def _short(text: str) -> str:
    """The bifurcation's name, for prose (the part before the colon)."""
    return text.split(":")[0].replace("Neimark-Sacker", "Neimark--Sacker")


# The one-impact orbit's range along the gap (where the scan found it).
ORBIT = (
    Macro("OrbitRangeLo", "lo", fixed(4)),
    Macro("OrbitRangeHi", "hi", fixed(4)),
    Macro("OrbitLoBifurcation", lambda o: o.get("lo_bifurcation", ""), Format(_short)),
    Macro("OrbitHiBifurcation", lambda o: o.get("hi_bifurcation", ""), Format(_short)),
    Macro("OrbitSeedGap", "seed_gap", fixed(2)),
)


def _scan_macros(scan: dict, cc_s: dict, ref_l: dict) -> list:
    """The cross-checks' tolerances, the gap scan's window and claim ranges, its end checks and
    the one-impact orbit's range along the gap."""
    g = ref_l["parameters"]["gap"]
    out = macro_lines(SCAN, {"cc": cc_s, "scan": scan, "g": g})
    for name, key in (("ClaimA", "claim_a_ranges"), ("ClaimB", "claim_b_ranges"), ("Both", "both_ranges")):
        rs = scan[key]
        out += macro_lines(RANGES, {"ranges": rs, "range": _range_of(rs, g) or (rs[0] if rs else None)}, R=name)
    out += macro_lines(END_CHECKS, scan["end_checks"])
    off = [c for c in scan["end_checks"] if not c["agree"]]
    worst = max(off, key=lambda c: c["details"].get("max_velocity_difference_rel") or 0.0) if off else None
    if worst is not None and "cycle_comparison" in worst["details"]:
        out += macro_lines(END_CHECK_OFF, worst)
    orbit = scan["orbit_range"]
    if orbit.get("found"):
        out += macro_lines(ORBIT, orbit)
        nearest = min(orbit["branch"], key=lambda b: abs(b[0] - g))
        if abs(nearest[0] - g) < 1e-9:
            out.append(("LocatedSpectralRadius", fixed(3)(nearest[1])))
    return out


# The other readings of the paper (figures/other_readings.json): each where it was evaluated.
EQ13 = (
    Macro("EqThirteenClaimA", "reading.claim_a", YES_NO),
    Macro("EqThirteenTOne", "reading.alg1_t1", fixed(4)),
    Macro("EqThirteenTTwo", "reading.alg1_t2", fixed(4)),
    Macro("EqThirteenMinGap", "reading.alg1_min_gap", fixed(3)),
    Macro("EqThirteenImpactLawRatio", "details.eq13_as_printed.impact_law_ratio?", fixed(3)),
)
R_AS_LOSS = (
    Macro("RAsLossR", "R", fixed(2)),
    Macro("RAsLossReproduces", "reproduces", YES_NO),
    Macro("RAsLossTOne", "alg1_t1", fixed(4)),
    Macro("RAsLossTTwo", "alg1_t2", fixed(4)),
    Macro("RAsLossMinGap", "alg1_min_gap", fixed(4)),
)
# The claims' ranges in R ({R}: RClaimA, RClaimB, RBoth): the first.
R_RANGE = (Macro("{R}Lo", "0.lo", fixed(3)), Macro("{R}Hi", "0.hi", fixed(3)))
RANDOM_STATES = (
    Macro("RandomStatesCount", "count", COUNT),
    Macro("RandomStatesSeed", "seed", TEXT),
    Macro("RandomStatesMotions", lambda rs: len(rs["motions"]), COUNT),
    Macro("RandomStatesClaimB", "claim_b_found", YES_NO),
    # solve_ivp from the same starts (independent): how many agree, the largest impact-time gap
    Macro("RandomStatesIvpAgree", "ivp_agree", COUNT),
    Macro("RandomStatesIvpTimeDiff", "ivp_max_time_difference_over_T", sci()),
    Macro("RandomStatesIvpTimeTol", "ivp_time_tol", sci(0)),
)
PRINTED_VELOCITIES = (
    Macro("PrintedVelocitiesRegime", "alg2_regime", WORDS),
    Macro("PrintedVelocitiesPeriodMultiple", "alg2_period_multiple", COUNT),
)


def _readings_macros(rd: dict) -> list:
    """The other readings of the paper: how many reproduce the claims, eq. (13) as printed, R as a
    loss, the claims' ranges in R, the random initial states and the printed velocities."""
    readings = {r["id"]: r for r in rd["readings"]}
    out = [
        ("ReadingsCount", str(len(readings) - 1)),  # the stated baseline is not a reading
        ("ReadingsReproducing", str(sum(bool(r["reproduces"]) for k, r in readings.items() if k != "stated"))),
    ]
    if "eq13_as_printed" in readings:
        out += macro_lines(EQ13, {"reading": readings["eq13_as_printed"], "details": rd["details"]})
    if "R_as_loss" in readings:
        out += macro_lines(R_AS_LOSS, readings["R_as_loss"])
    for name, key in (("RClaimA", "claim_a"), ("RClaimB", "claim_b"), ("RBoth", "both")):
        out += macro_lines(R_RANGE, rd["R_ranges"][key] or None, R=name)
    out += macro_lines(RANDOM_STATES, rd["random_states"])
    if "printed_velocities" in readings:
        out += macro_lines(PRINTED_VELOCITIES, readings["printed_velocities"])
    return out


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
    m = MacroFile(COMMENTS)
    m.extend(("Stated" + SPEC[key].macro, fixed(d)(p[key])) for key, d in STATED_DIGITS)
    m.add("StatedT", fixed(4)(Parameters(**p).T))
    for r, name in zip(rows, ("ClaimA", "ClaimBPeriod", "ClaimBImpacts")):
        m.extend(macro_lines(CLAIM_ROWS, r, C=name))
    for tag, ref, cc in (("Stated", ref_s, cc_s), ("Located", ref_l, cc_l)):
        m.extend(_case_macros(tag, ref, cc))
    m.extend(_scan_macros(scan, cc_s, ref_l))
    m.extend(_readings_macros(rd))
    return m
