"""The design stage's record for the report's section "Choosing a suppressor", declared for
:mod:`impactdamper.reporting.texrecord`: its macros, those of the baselines, the design charts,
the responses, the located-peak checks and the sub-region checks here, those of the design table's rows
(:mod:`~impactdamper.studies.design.record_rows`) and of its comparisons and verdicts
(:mod:`~impactdamper.studies.design.record_summary`) gathered here; its tables are
:mod:`~impactdamper.studies.design.record_tables`.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the numbers come from the design stage's records (figures/design_*.json), none typed by
hand. Used by ``workflow/scripts/design_report.py``.
"""

from __future__ import annotations

from impactdamper.reporting.latex import MacroFile
from impactdamper.reporting.texrecord import TEXT, Macro, bound, fixed, macro_lines, percent, tex_sci
from impactdamper.analysis.linear_device import LinearDevice
from impactdamper.studies.design.record_rows import NAMES, SYMBOLS, row_macros, rows
from impactdamper.studies.design.record_summary import SUMMARY
from impactdamper.studies.vocabulary import SPEC

__all__ = ["RECORD_WHAT", "design_macros"]

RECORD_WHAT = "Macros of the report's section 'Choosing a suppressor' (design stage)"


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


def _half_words(parameter: str, half: str) -> str:
    """A half of a row's box in words (``the upper half in $N$``)."""
    return f"the {half} half in ${SYMBOLS[parameter]}$"


def _lower_text(sub: dict) -> str:
    """The halves lower than their row's search answer by more than the tolerance, in words
    (every one: row, half, both values, the half's answer and the margin; what the row adopted),
    or that there is none."""
    if not sub["lower"]:
        return f"No half is lower than its row's optimum by more than ${tex_sci(1)(sub['rtol'])}$ (relative)."
    adopted = {r["device"]: r["adopted"] for r in sub["rows"]}
    parts = []
    for h in sub["lower"]:
        name, (parameter, half) = NAMES[h["device"]], h["half"].split()
        x = ", ".join(f"${SYMBOLS[n]} = {fixed(3)(h['parameters'][n])}$" for n in SYMBOLS if n in h["parameters"])
        took = [a for a in adopted[h["device"]] if a["half"] == h["half"]]
        then = f"; adopted, the local search from it reaching {fixed(3)(took[0]['searched'])}" if took else ""
        parts.append(
            f"{name}: {_half_words(parameter, half)} holds {fixed(3)(h['value'])} against its search's "
            f"{fixed(3)(h['optimum'])} (${fixed(1)(100 * h['margin'])}$\\,\\%), at {x}{then}"
        )
    lead = "A half lower than its row's answer" if len(parts) == 1 else "Halves lower than their rows' answers"
    return f"{lead}: {'; '.join(parts)}."


# The sub-region checks (figures/design_subregions.json): every row's box halves searched.
SUBREGIONS = (
    Macro("DesignSubRows", "sub.rows_count", TEXT),
    Macro("DesignSubHalves", "sub.halves_count", TEXT),
    Macro("DesignSubHalvesSearched", "sub.halves_searched", TEXT),
    Macro("DesignSubPassedRows", lambda s: sum(bool(r["final"]["passed"]) for r in s["sub"]["rows"]), TEXT),
    Macro("DesignSubLowerCount", lambda s: len(s["sub"]["lower"]), TEXT),
    Macro("DesignSubAdoptedCount", lambda s: len(s["sub"]["adopted"]), TEXT),
    Macro("DesignSubSmallestMarginPct", "sub.smallest_margin", percent(2)),
    Macro("DesignSubSmallestRow", lambda s: NAMES[s["sub"]["smallest_row"]]),
    Macro("DesignSubSmallestHalf", lambda s: _half_words(*s["sub"]["smallest_half"].split())),
    Macro("DesignSubSamples", "sub.budget.samples", TEXT),
    Macro("DesignSubHalfSamples", lambda s: s["sub"]["budget"]["samples"] // 2, TEXT),
    Macro("DesignSubStarts", "sub.budget.starts", TEXT),
    Macro("DesignSubPolls", "sub.budget.polls", TEXT),
    Macro("DesignSubPolish", "sub.budget.polish", TEXT),
    Macro("DesignSubChecks", "sub.budget.checks", TEXT),
    Macro("DesignSubRtol", "sub.rtol", tex_sci(1)),
    Macro("DesignSubReproduced", "sub.largest_reproduced", bound(1)),
    Macro("DesignSubLowerText", lambda s: _lower_text(s["sub"])),
)


def _optimum_macros(opt: dict, bench: dict) -> list:
    """The table's macros: rows' parameters, criteria, strokes, loads, searches; the verdicts."""
    d = rows(opt)
    searched = [r for r in opt["devices"] if "search" in r]
    return row_macros(d) + macro_lines(SUMMARY, {"d": d, "opt": opt, "searched": searched, "bench": bench})


def design_macros(
    base: dict, chart: dict, chart2: dict, resp: dict, opt: dict, checks: dict, sub: dict, bench: dict
) -> MacroFile:
    """The design stage's macros (the record of ``paper/generated/design_macros.tex``).

    Parameters
    ----------
    base, chart, chart2, resp, opt, checks, sub, bench : dict
        The records of the baselines, the 1-D and 2-D design charts, the responses, the design
        table (:func:`~impactdamper.studies.design.optimum.design_optima`), the located-peak
        checks, the sub-region checks (:func:`~impactdamper.studies.design.subregions.summary`)
        and the benchmark (figures/design_*.json).
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
        "sub": sub,
    }
    m = MacroFile(["% Written by the design stage's report job; do not edit."])
    m.extend(macro_lines(CHART, source))
    m.extend(macro_lines(CHECKS, source))
    m.extend(macro_lines(SUBREGIONS, source))
    m.extend(_optimum_macros(opt, bench))
    return m
