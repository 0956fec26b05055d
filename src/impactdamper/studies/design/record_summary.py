"""The design table's comparisons, settings and verdicts as the report quotes them (part of the
design stage's record, :mod:`impactdamper.studies.design.record`): the uncertainties, boxes and
budgets searched under, what the searches certify, the rows against each other (ratios, per
cent more, lower or higher), the snubber, the literature's claim and the recommendation.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the numbers come from the design table and the benchmark (figures/design_*.json).
"""

from __future__ import annotations

from impactdamper.reporting.texrecord import TEXT, Format, Macro, bound, fixed, percent, pick, tex_sci
from impactdamper.studies.design.abstract import abstract_answer, abstract_short
from impactdamper.studies.design.devices import RANGES, STROKE_PENALTY
from impactdamper.studies.design.record_rows import SYMBOLS, at_bound_text, device_name
from impactdamper.studies.design.verdict import recommendation

__all__ = ["SUMMARY"]


def _ratio(a: str, b: str):
    """The value at path ``a`` over the value at path ``b`` of the source."""
    return lambda s: pick(s, a) / pick(s, b)


def _pct_more(a: str, b: str):
    """100 (a/b - 1): how much more the value at ``a`` is than the one at ``b``, per cent."""
    return lambda s: 100.0 * (pick(s, a) / pick(s, b) - 1.0)


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
    return words + (
        f" In {len(apart)} of the {len(searched)} searches the starts end more than 0.5\\,\\% apart (each "
        f"search's starts, their ends and spread are in the record, \\texttt{{search.starts}}): there the answer "
        f"is the best found, not more."
    )


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
        f"{device_name(d)} ({at_bound_text(d['search']['at_bound'])})" for d in searched if d["search"]["at_bound"]
    ]
    return "; ".join(parts) or "none"


def _bound_text(names) -> str:
    """The parameters at a bound of the box, in words."""
    if not names:
        return "none of its parameters is at a bound"
    return "at a bound: " + ", ".join(f"${SYMBOLS[n]}$" for n in names)


def _stop_text(d: dict) -> str:
    """Whether the whole box's peak optimum reaches its stop, in words."""
    if d.get("tmd_limit"):
        return "its stop lies beyond its own travel and is never reached: it is the TMD limit"
    return f"its stop is reached, up to {fixed(1)(d['impacts_per_period'])} impacts per period"


# A number as Python's general format writes it (0.005, 2, 1e+06): the ranges as documented.
_GENERAL = Format(lambda v: f"{v:g}")

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
    Macro("DesignRestImpStopText", "d.RestImp", Format(_stop_text)),
    # The command's documented ranges (devices.RANGES: what `impactdamper design` accepts).
    Macro("DesignRangeMuLow", lambda s: RANGES["mu"][0], _GENERAL),
    Macro("DesignRangeMuHigh", lambda s: RANGES["mu"][1], _GENERAL),
    Macro("DesignRangeDeltaOneLow", lambda s: RANGES["delta1"][0], _GENERAL),
    Macro("DesignRangeDeltaOneHigh", lambda s: RANGES["delta1"][1], _GENERAL),
    Macro("DesignRangeWidthLow", lambda s: RANGES["band_width"][0], _GENERAL),
    Macro("DesignRangeWidthHigh", lambda s: RANGES["band_width"][1], _GENERAL),
    Macro("DesignRangeThetaLow", lambda s: RANGES["theta_start"][0], _GENERAL),
    Macro("DesignRangeThetaHigh", lambda s: RANGES["theta_stop"][1], _GENERAL),
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
