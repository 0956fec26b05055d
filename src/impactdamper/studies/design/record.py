"""The design stage's record for the report's section "Choosing a suppressor", declared for
:mod:`impactdamper.reporting.texrecord`: its macros, the design table, the loads table, the
table of the best gap against the second parameter and the benchmark table.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the numbers come from the design stage's records (figures/design_*.json), none typed by
hand. Used by ``workflow/scripts/design_report.py``.
"""

from __future__ import annotations

import dataclasses

from impactdamper.reporting.latex import MacroFile
from impactdamper.reporting.texrecord import (
    TEXT,
    Column,
    Format,
    Macro,
    Table,
    fixed,
    fixed_columns,
    macro_lines,
    percent,
    pick,
    bound,
    tex_sci,
)
from impactdamper.analysis.linear_device import LinearDevice
from impactdamper.studies.design.devices import IMPACT_NAMES, STROKE_PENALTY
from impactdamper.studies.design.abstract import abstract_answer, abstract_short
from impactdamper.studies.design.verdict import device, recommendation
from impactdamper.studies.vocabulary import SPEC, tex

__all__ = [
    "RECORD_WHAT",
    "DEVICE_KEYS",
    "design_macros",
    "design_table",
    "loads_table",
    "second_table",
    "benchmark_table",
    "_device_name",
]

# What the stage's record holds (results/report/design.json).
RECORD_WHAT = "Macros of the report's section 'Choosing a suppressor' (design stage)"

# The impact suppressor's designed parameters, their decimals, and their symbols as the design
# section writes them.
DIGITS = dict(zip(IMPACT_NAMES, (2, 3, 3, 2)))
SYMBOLS = {k: SPEC[k].symbol for k in DIGITS}

# The design table's rows by their macro part (the record's ``device`` keys).
DEVICE_KEYS = {
    "BareDev": "bare object",
    "TmdOpt": "tmd_peak",
    "Hit": "impact_peak_reach",
    "Opt": "impact_peak",
    "TmdAvgOpt": "tmd_band_average",
    "HitAvg": "impact_band_average_reach",
    "OptAvg": "impact_band_average",
    "RobTmd": "tmd_detuning",
    "RobImp": "impact_detuning",
    "ForceImp": "impact_force",
    "RestImp": "impact_restitution",
    "StrokeTmd": "tmd_stroke",
    "StrokeImp": "impact_stroke",
}
# How the report names each row: the device and the criterion it is optimal for.
NAMES = {
    "bare object": "bare object",
    "tmd_peak": "TMD, peak",
    "impact_peak_reach": "impact, peak",
    "impact_peak": "impact, peak, whole box",
    "tmd_band_average": "TMD, band average",
    "impact_band_average_reach": "impact, band average",
    "impact_band_average": "impact, band avg., whole box",
    "tmd_detuning": "TMD, detuned",
    "impact_detuning": "impact, detuned",
    "impact_force": "impact, force",
    "impact_restitution": "impact, $R$ drift",
    "tmd_stroke": "TMD, travel limit",
    "impact_stroke": "impact, travel limit",
}


def _device_name(d: dict) -> str:
    """A row's name in the report: a row that never reaches its stop is the TMD limit."""
    name = NAMES[d["device"]]
    if d.get("tmd_limit"):
        name += ": TMD limit"
    if d.get("feasible") is False:
        name += " (over the limit)"
    return name


def _branch_words(branch: str) -> str:
    """A worst branch's description (``up, 1/1, branch end``; ``linear``) in words."""
    if branch == "linear":
        return "the linear response's resonance"
    source, label, kind = (part.strip() for part in branch.split(","))
    if source == "no contact":
        return "the motion without contact" + (", where it first touches the stop" if kind == "first contact" else "")
    where = {"maximum": "a smooth maximum", "branch end": "the end of its branch", "sample": "a sample"}[kind]
    who = {"up": "the upward sweep's", "down": "the downward sweep's", "random": "a random start's"}[source]
    return f"{who} {label} motion, {where}"


def _ratio(a: str, b: str):
    """The value at path ``a`` over the value at path ``b`` of the source."""
    from impactdamper.reporting.texrecord import pick

    return lambda s: pick(s, a) / pick(s, b)


def _pct_more(a: str, b: str):
    """100 (a/b - 1): how much more the value at ``a`` is than the one at ``b``, per cent."""
    from impactdamper.reporting.texrecord import pick

    return lambda s: 100.0 * (pick(s, a) / pick(s, b) - 1.0)


# The baselines, the chart, the responses, the Den Hartog check and the located-peak checks.
CHART = (
    Macro("DesignBandStart", "base.band.0", fixed(2)),
    Macro("DesignBandStop", "base.band.1", fixed(2)),
    Macro("DesignStep", "chart.step", fixed(2)),
    Macro("DesignGapStart", "chart.gaps.0", fixed(1)),
    Macro("DesignGapStop", "chart.gaps.-1", fixed(1)),
    Macro("DesignGapStep", "chart.gap_step", fixed(2)),
    Macro("DesignTolerancePct", "bp.tolerance", percent(0)),
    Macro("DesignBestGap", "located.peak.gap", fixed(3)),
    Macro("DesignBestPeak", "located.peak.value", fixed(3)),
    Macro("DesignBestTheta", "located.peak.peak_theta", fixed(3)),
    Macro("DesignBestGridGap", "bp.gap", fixed(2)),
    Macro("DesignGoodFrom", "bp.good_from", fixed(2)),
    Macro("DesignGoodTo", "bp.good_to", fixed(2)),
    Macro("DesignBestImpulse", "bp.peak_impulse", fixed(2)),
    Macro("DesignAvgBestGap", "located.band_average.gap", fixed(3)),
    Macro("DesignAvgBest", "located.band_average.value", fixed(3)),
    Macro("DesignAvgGoodFrom", "ba.good_from", fixed(2)),
    Macro("DesignAvgGoodTo", "ba.good_to", fixed(2)),
    Macro("DesignAvgImpacts", "ba.impacts_per_period", fixed(0)),
    Macro("DesignGapXtol", "located.peak.xtol", tex_sci(1)),
    Macro("DesignRefTheta", "one.theta", fixed(2)),
    Macro("DesignRefThetaGap", "one.gap", fixed(2)),
    Macro("DesignRefThetaValue", "one.value", fixed(2)),
    Macro(
        "DesignRefThetaBare",
        lambda s: float(LinearDevice.bare(s["base"]["parameters"]["delta1"]).amplitude([s["one"]["theta"]])[0]),
        fixed(2),
    ),
    Macro("DesignPaperN", "base.parameters.N", fixed(2)),
    Macro("DesignPaperDeltaTwo", "base.parameters.delta2", fixed(2)),
    Macro("DesignPaperR", "base.parameters.R", fixed(2)),
    Macro("DesignPaperMu", "base.parameters.mu", fixed(2)),
    Macro("DesignPaperDeltaOne", "base.parameters.delta1", fixed(2)),
    Macro("DesignPaperGap", "paper.gap", fixed(1)),
    Macro("DesignPaperPeak", "paper.peak", fixed(2)),
    Macro("DesignPaperImpacts", "paper.impacts_per_period", fixed(0)),
    Macro("DesignResponsePoints", "resp.points", TEXT),
    Macro("DesignBalanceMax", lambda s: max(r["largest_balance"] for r in s["resp"]["responses"]), bound(1)),
    Macro("DesignDriftMax", lambda s: max(r["largest_drift_settled"] for r in s["resp"]["responses"]), bound(1)),
    Macro("DesignDHPeak", "dh.closed_form.peak", fixed(4)),
    Macro("DesignDHOptPeak", "dh.search.value", fixed(4)),
    Macro("DesignDHPeakDiff", lambda s: abs(s["dh"]["peak_relative_difference"]), bound(1)),
    Macro("DesignDHN", "dh.closed_form.N", fixed(4)),
    Macro("DesignDHOptN", "dh.search.parameters.N", fixed(4)),
    Macro("DesignDHNDiff", lambda s: abs(s["dh"]["N_relative_difference"]), bound(1)),
    Macro("DesignDHDeltaTwo", "dh.closed_form.delta2", fixed(4)),
    Macro("DesignDHOptDeltaTwo", "dh.search.parameters.delta2", fixed(4)),
    Macro("DesignDHDeltaTwoDiff", lambda s: abs(s["dh"]["delta2_relative_difference"]), bound(1)),
    Macro("DesignSecondName", lambda s: f"${SPEC[s['chart2']['parameter']].symbol}$"),
)

# The located-peak checks (figures/design_checks.json).
CHECKS = (
    Macro("DesignCheckCases", "checks.cases_count", TEXT),
    Macro("DesignCheckFineStep", "checks.fine_step", fixed(3)),
    Macro("DesignCheckFineMax", "checks.fine_largest_excess", tex_sci(1)),
    Macro(
        "DesignCheckGapTwoFine",
        lambda s: 1.0 - s["checks"]["gap_two"]["fine"]["largest"] / s["checks"]["gap_two"]["peak"],
        tex_sci(1),
    ),
    Macro("DesignCheckFloorDiff", "checks.floor_largest_difference", bound(1)),
    Macro("DesignCheckIvpDiff", "checks.ivp_largest_difference", bound(1)),
    Macro("DesignCheckIvpCount", "checks.ivp_count", TEXT),
    Macro("DesignCheckThetaTol", "checks.theta_tol", tex_sci(1)),
    Macro("DesignCheckGapTwoPeak", "checks.gap_two.peak", fixed(4)),
    Macro("DesignCheckGapTwoTheta", "checks.gap_two.peak_theta", fixed(4)),
    Macro("DesignCheckGapTwoGrid", "checks.gap_two.grid_peak", fixed(4)),
    Macro("DesignCheckIssueFloor", "checks.branch_end.no_contact_floor", fixed(4)),
    Macro("DesignCheckIssueTheta", "checks.branch_end.peak_theta", fixed(4)),
    Macro("DesignCheckIssueGrid", "checks.branch_end.grid_peak", fixed(4)),
)

# A row's macros ({D}: the row's macro part): designed parameters, criteria, stroke.
PARAMETER = {k: Macro("Design{D}{P}", f"parameters.{k}", fixed(d)) for k, d in DIGITS.items()}
ROW = (
    Macro("Design{D}LocPeak", "peak", fixed(3)),
    Macro("Design{D}LocTheta", "peak_theta", fixed(3)),
    Macro("Design{D}Avg", "band_average", fixed(3)),
    Macro("Design{D}WorstLarge", "worst.detuning", fixed(2)),
    Macro("Design{D}WorstForce", "worst.force", fixed(2)),
    Macro("Design{D}WorstRest", "worst.restitution", fixed(2)),
    Macro("Design{D}WorstAll", "worst.together", fixed(2)),
    Macro("Design{D}WorstAbsorber", "worst.absorber", fixed(2)),
    Macro("Design{D}Stroke", "stroke", fixed(1)),
    Macro("Design{D}Branch", "peak_branch", Format(_branch_words)),
)
# An impact row's loads and search record.
IMPACT_ROW = (
    Macro("Design{D}Pulse", "pulse", fixed(2)),
    Macro("Design{D}ImpactsPerPeriod", "impacts_per_period", fixed(1)),
    Macro("Design{D}ImpactsPerHour", "impacts_per_hour", Format(lambda v: f"{v:,.0f}".replace(",", "\\,"))),
    Macro("Design{D}ContactForce", "contact_force", fixed(0)),
    Macro("Design{D}MeanForce", "mean_force", fixed(2)),
    Macro("Design{D}Floor", "no_contact_floor", fixed(3)),
)
SEARCH = (
    Macro("Design{D}Evaluations", lambda d: sum(d["search"]["evaluations"].values()), TEXT),
    Macro("Design{D}CheckGain", lambda d: max(d["search"]["check"]["largest_gain"], 0.0), tex_sci(1)),
    Macro("Design{D}AtBound", lambda d: _at_bound_text(d["search"]["at_bound"])),
    Macro("Design{D}Spread", lambda d: 100 * d["search"]["starts"]["spread"], fixed(2)),
    Macro("Design{D}StartCount", "search.starts.starts", TEXT),
)


def _literature_verdict(s: dict) -> str:
    """Whether this study's numbers bear out the impact dampers' credited robustness to
    detuning, in one sentence (``s``: the rows by macro part under ``d``)."""
    d = s["d"]
    nominal = d["Hit"]["worst"]["detuning"] < d["TmdOpt"]["worst"]["detuning"]
    robust = d["RobImp"]["worst"]["detuning"] < d["RobTmd"]["worst"]["detuning"]
    force = d["ForceImp"]["worst"]["force"] < d["TmdOpt"]["peak"]
    if robust and force:
        return "In this study's numbers it holds: designed for the detuning or the force, the impact suppressor is the lower."
    if robust:
        return (
            "In this study's numbers it holds for the detuning (designed for it, the impact suppressor is the lower), "
            "but not for the force amplitude."
        )
    if nominal:
        return (
            "In this study's numbers it holds only between the nominal optima: a TMD designed for the detuning "
            "reverses it, and a force that is not what was assumed costs the impact suppressor alone."
        )
    return "In this study's numbers it does not hold, not even between the nominal optima."


def _lower(a: str, b: str):
    """``lower`` where the value at path ``a`` is below the one at ``b``, else ``higher``."""
    return lambda s: "lower" if pick(s, a) < pick(s, b) else "higher"


def _checks_text(searched: list) -> str:
    """How the searches' 2 % checks ended, in words."""
    failed = [d for d in searched if not d["search"]["check"]["passed"]]
    if not failed:
        return f"All {len(searched)} searches end on a passed check."
    gain = max(d["search"]["check"]["largest_gain"] for d in failed)
    return (
        f"Of the {len(searched)} searches, {len(searched) - len(failed)} end on a passed check; in the others a "
        f"move still lowers the answer by at most ${tex_sci(1)(gain)}$ (relative) when the budget ends."
    )


def _certifies_text(searched: list) -> str:
    """What the searches certify, in words: a local minimum no 2 % move improves (or not), the
    best over the global samples, and which searches' starts disagree by more than 0.5 % (the
    answer then the best found, with the spread)."""
    samples = sorted({d["search"]["starts"]["samples"] for d in searched if d["search"].get("starts")})
    apart = [d for d in searched if d["search"].get("starts", {}).get("best_found")]
    words = (
        f"Each answer is therefore certified as a local minimum that no move of {fixed(0)(100 * searched[0]['search']['check']['move'])}\\,\\% "
        f"along an axis improves (where its check passed), and as the best design reached from "
        f"the {max(samples)}-design global sample (those of it inside each search's box: {min(samples)} to "
        f"{max(samples)}); no more."
    )
    if not apart:
        return words + " Every search's starts end within 0.5\\,\\% of each other."
    listed = "; ".join(f"{_device_name(d)} ({_spread_words(d['search']['starts']['spread'])})" for d in apart)
    return words + f" Where the starts end more than 0.5\\,\\% apart the answer is the best found, not more: {listed}."


def _spread_words(spread: float) -> str:
    """A spread of the starts' ends in words (over 100 %: a start ended over a travel limit)."""
    return "over 100\\,\\%" if spread > 1 else f"{fixed(1)(100 * spread)}\\,\\%"


def _value_table_diff(d: dict) -> float:
    """A search's final value against its row's of the same criterion in the table, relative."""
    c = d["criterion"]
    table = d["peak"] if c in ("peak", "stroke") else d["band_average"] if c == "band_average" else d["worst"][c]
    v = d["search"]["value"]
    if c == "stroke" or not (table == table) or v is None:
        return 0.0  # (the travel-limited value carries the limit's penalty: not the same number)
    return abs(table / v - 1.0)


def _at_bound_list(searched: list) -> str:
    """Every searched row with a parameter at a bound of its box, in words (``none`` if none)."""
    parts = [
        f"{_device_name(d)} ({_at_bound_text(d['search']['at_bound'])})" for d in searched if d["search"]["at_bound"]
    ]
    return "; ".join(parts) or "none"


def _bound_text(names) -> str:
    """The parameters at a bound of the box, in words."""
    if not names:
        return "none of its parameters is at a bound"
    return "at a bound: " + ", ".join(f"${SYMBOLS[n]}$" for n in names)


def _at_bound_text(names) -> str:
    return ", ".join(f"${SYMBOLS[n]}$" for n in names) or "none"


def _stop_text(d: dict) -> str:
    """Whether the whole box's peak optimum reaches its stop, in words."""
    if d.get("tmd_limit"):
        return "its stop lies beyond its own travel and is never reached: it is the TMD limit"
    return f"its stop is reached, up to {fixed(1)(d['impacts_per_period'])} impacts per period"


# The record's comparisons and settings.
SUMMARY = (
    Macro("DesignDetuneLargePct", "opt.uncertainty.detuning", percent(0)),
    Macro("DesignForceLow", "opt.uncertainty.force.0", fixed(1)),
    Macro("DesignForceHigh", "opt.uncertainty.force.1", fixed(0)),
    Macro("DesignRestDrift", "opt.uncertainty.restitution", fixed(2)),
    Macro("DesignTmdStrokeBound", "opt.tmd_stroke", fixed(2)),
    Macro("DesignMaxStroke", "opt.max_stroke", fixed(2)),
    Macro("DesignStopStiffness", "opt.stop_stiffness", fixed(0)),
    Macro("DesignNaturalFrequency", "opt.natural_frequency", fixed(0)),
    Macro("DesignGapLow", "opt.bounds.impact.gap.0", fixed(2)),
    Macro("DesignGapHigh", "opt.bounds.impact.gap.1", fixed(2)),
    Macro("DesignGapReach", "opt.bounds.impact_reach.gap.1", fixed(2)),
    Macro("DesignNLow", "opt.bounds.impact.N.0", fixed(2)),
    Macro("DesignNHigh", "opt.bounds.impact.N.1", fixed(2)),
    Macro("DesignDeltaTwoHigh", "opt.bounds.impact.delta2.1", fixed(2)),
    Macro("DesignRLow", "opt.bounds.impact.R.0", fixed(2)),
    Macro("DesignRHigh", "opt.bounds.impact.R.1", fixed(2)),
    Macro("DesignSamples", "opt.budget.samples", TEXT),
    Macro("DesignStarts", "opt.budget.starts", TEXT),
    Macro("DesignPolls", "opt.budget.polls", TEXT),
    Macro("DesignPolish", "opt.budget.polish", TEXT),
    Macro("DesignRobustPolls", "opt.robust_budget.polls", TEXT),
    Macro("DesignRobustPolish", "opt.robust_budget.polish", TEXT),
    Macro("DesignCheckMovePct", lambda s: 100 * s["d"]["Hit"]["search"]["check"]["move"], fixed(0)),
    Macro("DesignSettleTol", "opt.settings.settle_tol", tex_sci(1)),
    Macro("DesignMaxPeriods", "opt.settings.max_periods", TEXT),
    Macro("DesignElapsed", "opt.elapsed", fixed(0)),
    Macro("DesignOptStopText", "d.Opt", Format(_stop_text)),
    Macro(
        "DesignStrokeImpStopText",
        lambda s: (
            "never reaches its stop: it is the TMD limit, its stop marking the limit"
            if s["d"]["StrokeImp"].get("tmd_limit")
            else f"reaches its stop, up to {fixed(1)(s['d']['StrokeImp']['impacts_per_period'])} impacts per period"
        ),
    ),
    Macro("DesignChecksPassed", lambda s: sum(bool(d["search"]["check"]["passed"]) for d in s["searched"]), TEXT),
    Macro("DesignChecksTotal", lambda s: len(s["searched"]), TEXT),
    Macro("DesignChecksText", lambda s: _checks_text(s["searched"])),
    Macro("DesignCertifiesText", lambda s: _certifies_text(s["searched"])),
    Macro("DesignStrokeFractionPct", lambda s: 100 * s["opt"]["max_stroke"] / s["opt"]["tmd_stroke"], fixed(0)),
    Macro("DesignStrokePenalty", lambda s: STROKE_PENALTY, fixed(0)),
    Macro(
        "DesignTmdSpringForce",
        lambda s: s["opt"]["mu"] * s["d"]["TmdOpt"]["parameters"]["N"] ** 2 * s["d"]["TmdOpt"]["stroke"],
        fixed(2),
    ),
    Macro("DesignValueTableDiff", lambda s: max(_value_table_diff(d) for d in s["searched"]), bound(1)),
    Macro(
        "DesignGlobalSearches", lambda s: sum(d["search"]["starts"].get("samples", 0) > 0 for d in s["searched"]), TEXT
    ),
    Macro("DesignStiffDriftPct", lambda s: 100 * s["opt"]["uncertainty"].get("stiffness", 0.0), fixed(0)),
    Macro("DesignDampDriftPct", lambda s: 100 * s["opt"]["uncertainty"].get("damping", 0.0), fixed(0)),
    Macro("DesignTmdEqualPeaks", lambda s: abs(s["opt"]["tmd_equal_peaks"]["relative_difference"]), bound(1)),
    Macro("DesignTmdRefine", lambda s: s["d"]["TmdOpt"]["search"]["evaluations"]["refine"], TEXT),
    Macro("DesignTmdStrokeRatio", _ratio("d.Hit.stroke", "d.TmdOpt.stroke"), fixed(2)),
    Macro("DesignHitBoundText", lambda s: _bound_text(s["d"]["Hit"]["search"]["at_bound"])),
    Macro("DesignAtBoundList", lambda s: _at_bound_list(s["searched"])),
    Macro("DesignOptForceMorePct", _pct_more("d.Opt.worst.force", "d.TmdOpt.peak"), fixed(0)),
    Macro("DesignLoadAverage", lambda s: s["bench"]["machine"]["load_average"][0], fixed(1)),
    Macro(
        "DesignLargestGain",
        lambda s: max(max(d["search"]["check"]["largest_gain"], 0.0) for d in s["searched"]),
        tex_sci(1),
    ),
    Macro("DesignAtBoundRows", lambda s: sum(bool(d["search"]["at_bound"]) for d in s["searched"]), TEXT),
    Macro("DesignHitRatioTmd", _ratio("d.Hit.peak", "d.TmdOpt.peak"), fixed(3)),
    Macro("DesignHitAvgRatioTmd", _ratio("d.HitAvg.band_average", "d.TmdAvgOpt.band_average"), fixed(3)),
    Macro("DesignRobRatio", _ratio("d.RobImp.worst.detuning", "d.RobTmd.worst.detuning"), fixed(3)),
    Macro("DesignForceRatio", _ratio("d.ForceImp.worst.force", "d.TmdOpt.peak"), fixed(3)),
    Macro("DesignRestRatio", _ratio("d.RestImp.worst.restitution", "d.TmdOpt.peak"), fixed(3)),
    Macro("DesignStrokeRatio", _ratio("d.StrokeImp.peak", "d.StrokeTmd.peak"), fixed(3)),
    Macro("DesignHitForceMorePct", _pct_more("d.Hit.worst.force", "d.Hit.peak"), fixed(0)),
    Macro("DesignHitRestMorePct", _pct_more("d.Hit.worst.restitution", "d.Hit.peak"), fixed(0)),
    Macro("DesignHitDetuneMorePct", _pct_more("d.Hit.worst.detuning", "d.Hit.peak"), fixed(0)),
    Macro("DesignTmdDetuneMorePct", _pct_more("d.TmdOpt.worst.detuning", "d.TmdOpt.peak"), fixed(0)),
    Macro("DesignOptDetuneMorePct", _pct_more("d.Opt.worst.detuning", "d.TmdOpt.worst.detuning"), fixed(0)),
    Macro("DesignGainBare", _ratio("d.BareDev.peak", "d.TmdOpt.peak"), fixed(2)),
    Macro("DesignNominalDetuneWord", _lower("d.Hit.worst.detuning", "d.TmdOpt.worst.detuning")),
    Macro("DesignRobDetuneWord", _lower("d.RobImp.worst.detuning", "d.RobTmd.worst.detuning")),
    Macro("DesignForceWord", _lower("d.ForceImp.worst.force", "d.TmdOpt.peak")),
    Macro("DesignLiteratureVerdict", _literature_verdict),
    Macro("DesignSnubberLowPct", lambda s: 100 * (s["opt"]["snubber"][0]["ratio"] - 1), fixed(0)),
    Macro("DesignSnubberHighPct", lambda s: 100 * (s["opt"]["snubber"][-1]["ratio"] - 1), fixed(0)),
    Macro("DesignSnubberLowFraction", lambda s: s["opt"]["snubber"][0]["fraction"], fixed(2)),
    Macro("DesignSnubberHighFraction", lambda s: s["opt"]["snubber"][-1]["fraction"], fixed(2)),
    Macro("DesignSnubberR", lambda s: s["opt"]["snubber"][0]["parameters"]["R"], fixed(1)),
    Macro("DesignAbstractAnswer", lambda s: abstract_answer(s["opt"])),
    Macro("DesignAbstractShort", lambda s: abstract_short(s["opt"])),
    Macro(
        "DesignRecommendation",
        lambda s: recommendation(
            s["opt"],
            pm="$\\pm$",
            pct="\\,\\%",
            xst="\\,$x_{\\mathrm{st}}$",
            p0="\\,$P_0$",
            f1="$f_1$",
            sep="\\,",
        ),
    ),
    # For the README (never expanded in TeX; no "%", which would end the TeX line of its definition).
    Macro("DesignRecommendationPlain", lambda s: recommendation(s["opt"], pct=" per cent")),
)


def _rows(opt: dict) -> dict[str, dict]:
    return {key: device(opt, name) for key, name in DEVICE_KEYS.items()}


def _optimum_macros(opt: dict, bench: dict) -> list:
    """The table's macros: rows' parameters, criteria, strokes, loads, searches; the verdicts."""
    d = _rows(opt)
    out = []
    for key, row in d.items():
        for k in DIGITS:
            if k in row["parameters"]:
                out += macro_lines([PARAMETER[k]], row, D=key, P=SPEC[k].macro)
        out += macro_lines(ROW, row, D=key)
        if row["kind"] == "impact":
            out += macro_lines(IMPACT_ROW, row, D=key)
        if "search" in row:
            out += macro_lines(SEARCH, row, D=key)
    searched = [r for r in opt["devices"] if "search" in r]
    return out + macro_lines(SUMMARY, {"d": d, "opt": opt, "searched": searched, "bench": bench})


def design_macros(base: dict, chart: dict, chart2: dict, resp: dict, opt: dict, checks: dict, bench: dict) -> MacroFile:
    """The design stage's macros (the record of ``paper/generated/design_macros.tex``).

    Parameters
    ----------
    base, chart, chart2, resp, opt, checks, bench : dict
        The records of the baselines, the 1-D and 2-D design charts, the responses, the design
        table (:func:`~impactdamper.studies.design.optimum.design_optima`), the located-peak
        checks and the benchmark (figures/design_*.json).
    """
    paper = next(r for r in resp["responses"] if r["role"] == "paper")
    source = {
        "base": base,
        "chart": chart,
        "chart2": chart2,
        "resp": resp,
        "bp": chart["best"]["peak"],
        "ba": chart["best"]["band_average"],
        "located": chart["located"],
        "one": chart["at_reference_theta"],
        "paper": paper,
        "dh": base["den_hartog_check"],
        "checks": checks,
    }
    m = MacroFile(["% Written by the design stage's report job; do not edit."])
    m.extend(macro_lines(CHART, source))
    m.extend(macro_lines(CHECKS, source))
    m.extend(_optimum_macros(opt, bench))
    return m


# --- the tables -----------------------------------------------------------------------------
TABLE_COMMENTS = ["Written by the design stage's report job; do not edit."]
# The gap's symbol without its unit: the design table's columns are in x_st.
GAP_SHORT = SPEC["gap"].symbol.split("/")[0]


def _brace(text: str) -> str:
    """``text`` with its braces doubled, for a header that str.format fills."""
    return text.replace("{", "{{").replace("}", "}}")


DESIGN_TABLE = Table(
    colspec="lrrrrrrrrrrrr",
    header=(
        f"device & ${GAP_SHORT}$ & {tex('N')} & {tex('delta2')} & {tex('R')} & peak & band & detuned & force "
        f"& {tex('R')} drift & absorber & all & stroke"
    ),
    comments=TABLE_COMMENTS,
    columns=[
        Column(lambda d: d, Format(_device_name)),
        *(Column(lambda d, k=k: d["parameters"].get(k), fixed(DIGITS[k], "")) for k in DIGITS),
        *fixed_columns({"peak": 3, "band_average": 3}),
        *fixed_columns({f"worst.{w}": 2 for w in ("detuning", "force", "restitution", "absorber", "together")}),
        Column(lambda d: None if d["device"] == "bare object" else d["stroke"], fixed(1, "---")),
    ],
)


def design_table(opt: dict) -> str:
    """The design table (booktabs): each row's name, parameters, located peak, band average,
    worst peaks over each uncertainty and over all together, and stroke (:data:`DEVICE_KEYS`'
    order; a whole-box row with its within-reach row's design left out: :func:`_distinct`)."""
    return DESIGN_TABLE.render(_distinct(opt))


def _distinct(opt: dict) -> list[dict]:
    """The table's rows, a whole-box row equal to its within-reach row left out."""
    rows = [device(opt, name) for name in DEVICE_KEYS.values()]
    twins = {"impact_peak": "impact_peak_reach", "impact_band_average": "impact_band_average_reach"}
    by_name = {d["device"]: d for d in rows}
    return [
        d for d in rows if not (d["device"] in twins and d["parameters"] == by_name[twins[d["device"]]]["parameters"])
    ]


LOADS_TABLE = Table(
    colspec="lrrrrr",
    header="device & stroke & pulse & impacts/period & impacts/hour & contact force",
    comments=TABLE_COMMENTS,
    columns=[
        Column(lambda d: d, Format(_device_name)),
        *fixed_columns({"stroke": 1, "pulse": 2, "impacts_per_period": 1}),
        Column("impacts_per_hour", Format(lambda v: f"{v:,.0f}".replace(",", "\\,"))),
        Column("contact_force", fixed(0)),
    ],
)


def loads_table(opt: dict) -> str:
    """The impact suppressors' loads (booktabs): stroke, largest pulse (P0/omega1), impacts per
    period and per hour, peak contact force (P0); a design that never impacts left out."""
    return LOADS_TABLE.render([d for d in _distinct(opt) if d["kind"] == "impact" and d["impacts"]])


SECOND_TABLE = Table(
    colspec="rrrrrr",
    header=f"{{}} & best {_brace(tex('gap'))} & peak & {tex('theta')} of the peak & good gaps & pulse",
    comments=TABLE_COMMENTS,
    columns=[
        *fixed_columns({"second": 2, "gap": 2, "value": 2, "peak_theta": 3}),
        Column(lambda b: f"{fixed(2)(b['good_from'])} to {fixed(2)(b['good_to'])}"),
        Column("peak_impulse", fixed(2)),
    ],
)


def second_table(chart2: dict) -> str:
    """The booktabs table of the best gap (peak criterion) against the second parameter."""
    name = chart2["parameter"]
    symbol = f"${SPEC[name].symbol}$" if name in SPEC else name
    table = dataclasses.replace(SECOND_TABLE, header=SECOND_TABLE.header.format(symbol))
    return table.render([b for b in chart2["best"] if b["criterion"] == "peak"])


BENCHMARK_TABLE = Table(
    colspec="rrrrrrl",
    header=f"{tex('mu')} & {tex('delta1')} & wall (s) & processor (s) & longest silence (s) & evaluations & recommendation",
    comments=TABLE_COMMENTS,
    columns=[
        *fixed_columns({"mu": 2, "delta1": 2, "elapsed": 0}),
        Column("cpu", fixed(0, "---")),
        Column("longest_silence", fixed(1, "---")),
        Column("evaluations", TEXT),
        Column("first", TEXT),
    ],
)


def benchmark_table(bench: dict) -> str:
    """The design command's times at the benchmark's objects (booktabs)."""
    return BENCHMARK_TABLE.render(bench["objects"])
