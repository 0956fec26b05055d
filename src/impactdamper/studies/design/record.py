"""The design stage's record for the report's section "Choosing a suppressor", declared for
:mod:`impactdamper.reporting.texrecord`: its macros, the design table and the table of the best
gap against the second parameter.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the numbers come from the design stage's records (figures/design_*.json), no number is
typed by hand. Used by ``workflow/scripts/design_report.py``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactdamper.reporting.latex import MacroFile
from impactdamper.reporting.records import read_csv
from impactdamper.reporting.texrecord import TEXT, Column, Format, Macro, Table, fixed, macro_lines, percent, pick
from impactdamper.reporting.texrecord import bound, tex_sci
from impactdamper.studies.design.design import bare_object_amplitude, runs_where, two_mass_amplitude
from impactdamper.studies.design.optimum import IMPACT_BOUNDS, device, impacting, recommendation
from impactdamper.studies.vocabulary import SPEC

# What the stage's record holds (results/report/design.json).
RECORD_WHAT = "Macros of the report's section 'Choosing a suppressor' (design stage)"

# The impact suppressor's designed parameters (the optimiser's, in its order), their decimals,
# and their symbols (the report's: x_{\mathrm{st}}, as in the text).
DIGITS = {"gap": 2, "N": 3, "delta2": 3, "R": 2}
SYMBOLS = {k: SPEC[k].symbol for k in IMPACT_BOUNDS}


def impact_better(response_csv, gap: float, tmd: dict) -> tuple[float, list]:
    """Share of the theta grid (and its runs) where the impact design at ``gap`` (worse direction)
    keeps max|x1| below the optimal TMD's."""
    rows = [r for r in read_csv(response_csv) if abs(float(r["gap"]) - gap) < 1e-12]
    thetas = sorted({float(r["theta"]) for r in rows})
    worst = np.array([max(float(r["max_abs_x1"]) for r in rows if float(r["theta"]) == t) for t in thetas])
    lin = two_mass_amplitude(tmd["mu"], tmd["N"], tmd["delta1"], tmd["delta2"], thetas)
    better = worst < lin
    return float(better.mean()), runs_where(thetas, better)


def _ratio(a: str, b: str):
    """The value at path ``a`` over the value at path ``b`` of the source."""
    return lambda s: pick(s, a) / pick(s, b)


# The charts, the baselines, the responses and the Den Hartog check (bp, ba: the chart's best
# gaps by peak and band average; best: the response at the best gap; paper: at the paper's gap).
CHART = (
    Macro("DesignBandStart", "base.band.0", fixed(2)),
    Macro("DesignBandStop", "base.band.1", fixed(2)),
    Macro("DesignThetaPoints", "chart.theta_points", TEXT),
    Macro("DesignGapStep", "chart.gap_step", fixed(2)),
    Macro("DesignTolerancePct", "bp.tolerance", percent(0)),
    Macro("DesignBestGap", "bp.gap", fixed(2)),
    Macro("DesignBestPeak", "bp.value", fixed(2)),
    Macro("DesignGoodFrom", "bp.good_from", fixed(2)),
    Macro("DesignGoodTo", "bp.good_to", fixed(2)),
    Macro("DesignBestImpulse", "bp.peak_impulse", fixed(2)),
    Macro("DesignBestImpacts", "bp.impacts_per_period", fixed(0)),
    Macro("DesignRefTheta", "one.theta", fixed(2)),
    Macro("DesignRefThetaGap", "one.gap", fixed(2)),
    Macro("DesignRefThetaValue", "one.value", fixed(2)),
    Macro(
        "DesignRefThetaBare",
        lambda s: float(bare_object_amplitude(s["base"]["parameters"]["delta1"], [s["one"]["theta"]])[0]),
        fixed(2),
    ),
    Macro("DesignAvgBestGap", "ba.gap", fixed(2)),
    Macro("DesignAvgBest", "ba.value", fixed(3)),
    Macro("DesignAvgGoodFrom", "ba.good_from", fixed(2)),
    Macro("DesignAvgGoodTo", "ba.good_to", fixed(2)),
    Macro("DesignBestGapAvg", "best.band_average", fixed(3)),
    Macro("DesignBarePeak", "bare.peak", fixed(2)),
    Macro("DesignBareAvg", "bare.band_average", fixed(3)),
    Macro("DesignAbsorberPeak", "absorber.peak", fixed(2)),
    Macro("DesignAbsorberAvg", "absorber.band_average", fixed(3)),
    Macro("DesignTmdPeak", "tmd.peak", fixed(2)),
    Macro("DesignTmdAvg", "tmd.band_average", fixed(3)),
    Macro("DesignTmdN", "tmd.N", fixed(4)),
    Macro("DesignTmdDeltaTwo", "tmd.delta2", fixed(4)),
    Macro("DesignTmdAvgOptAvg", "tmd_avg.band_average", fixed(3)),
    Macro("DesignTmdAvgOptN", "tmd_avg.N", fixed(4)),
    Macro("DesignTmdAvgOptDeltaTwo", "tmd_avg.delta2", fixed(4)),
    Macro("DesignGainBare", _ratio("bare.peak", "bp.value"), fixed(2)),
    Macro("DesignGainAbsorber", _ratio("absorber.peak", "bp.value"), fixed(2)),
    Macro("DesignRatioTmd", _ratio("bp.value", "tmd.peak"), fixed(2)),
    Macro("DesignRatioTmdAvg", _ratio("best.band_average", "tmd.band_average"), fixed(2)),
    Macro("DesignImpactBetterPct", "share", percent(0)),
    Macro(
        "DesignImpactBetterRuns",
        lambda s: (
            ", ".join(f"${fixed(2)(a)}$--${fixed(2)(b)}$" if b > a else f"${fixed(2)(a)}$" for a, b in s["runs"])
            or "none"
        ),
    ),
    Macro("DesignPaperGap", "paper_gap", fixed(1)),
    Macro("DesignPaperPeak", "paper.peak", fixed(2)),
    Macro("DesignPaperImpulse", "paper.peak_impulse", fixed(2)),
    Macro("DesignPaperImpacts", "paper.impacts_per_period", fixed(0)),
    Macro("DesignBestHysteresis", "best.hysteresis_points", TEXT),
    Macro("DesignResponsePoints", "resp.points", TEXT),
    # Bounds the text states ("to within", "at most"): rounded up, never below the data.
    Macro("DesignBalanceMax", lambda s: max(r["largest_balance"] for r in s["resp"]["responses"]), bound(2)),
    Macro("DesignDriftMax", lambda s: max(r["largest_drift_settled"] for r in s["resp"]["responses"]), bound(2)),
    Macro("DesignDHPeak", "dh.closed_form.peak", fixed(4)),
    Macro("DesignDHPeakAtDH", "dh.peak_at_closed_form", fixed(4)),
    Macro("DesignDHOptPeak", "dh.optimiser.peak", fixed(4)),
    Macro("DesignDHExcessPct", "dh.peak_relative_excess", percent(2)),
    Macro("DesignDHN", "dh.closed_form.N", fixed(4)),
    Macro("DesignDHOptN", "dh.optimiser.N", fixed(4)),
    Macro("DesignDHNDiff", lambda s: abs(s["dh"]["N_relative_difference"]), tex_sci(1)),
    Macro("DesignDHDeltaTwo", "dh.closed_form.delta2", fixed(4)),
    Macro("DesignDHOptDeltaTwo", "dh.optimiser.delta2", fixed(4)),
    Macro("DesignSecondName", "chart2.parameter", TEXT),
)

# The design table's devices by their macro part and their names in the record (a name ending in
# "..." is the start of one): the impact suppressors, the linear ones, the references.
DEVICE_NAMES = {
    "Opt": "impact, optimal peak",
    "OptAvgCrit": "impact, optimal band average",
    "Chart": "impact, paper...",
    "RobImp": "impact, robust...",
    "Near": "impact, optimal peak, gap...",
    "TmdOpt": "TMD, optimal peak",
    "TmdOptAvgCrit": "TMD, optimal band average",
    "Eq": "TMD, impact's stroke",
    "RobTmd": "TMD, robust...",
    "BareDev": "bare object",
    "AbsorberDev": "absorber without a stop",
}
IMPACT_DEVICES = ("Opt", "OptAvgCrit", "Chart", "RobImp", "Near")
TMD_DEVICES = ("TmdOpt", "TmdOptAvgCrit", "Eq", "RobTmd")
# A device's designed parameter ({D}: the device, {P}: the parameter's macro part).
PARAMETER = {k: Macro("Design{D}{P}", f"parameters.{k}", fixed(d)) for k, d in DIGITS.items()}
# A device's located peak, band average, worst cases at the two detunings and stroke.
DEVICE = (
    Macro("Design{D}LocPeak", "peak", fixed(3)),
    Macro("Design{D}LocTheta", "peak_theta", fixed(3)),
    Macro("Design{D}Avg", "band_average", fixed(3)),
    Macro("Design{D}WorstSmall", "worst_small", fixed(2)),
    Macro("Design{D}WorstLarge", "worst_large", fixed(2)),
    Macro("Design{D}Stroke", "stroke", fixed(1)),
)


def _sensitivity_text(sens: dict) -> str:
    """``$N$ down by $0.012$, up by $0.020$; ...``: each parameter's move down and up for a 5 %
    worse peak ("to its bound" where even the box's bound is not that much worse)."""
    parts = []
    for n in [k for k in SYMBOLS if k in sens]:
        moves = [
            f"{side} " + ("to its bound" if v is None else f"by ${fixed(3)(abs(v))}$")
            for side, v in (("down", sens[n]["down"]), ("up", sens[n]["up"]))
        ]
        parts.append(f"${SYMBOLS[n]}$ " + ", ".join(moves))
    return "; ".join(parts)


def _at_bound_text(names: list[str]) -> str:
    """Which of the impact optimum's parameters lie at a bound of the optimiser's box, as a clause."""
    symbols = [f"${SYMBOLS[k]}$" for k in names if k in SYMBOLS]
    if not symbols:
        return "no parameter of the impact optimum lies at a bound of its box"
    listed = symbols[0] if len(symbols) == 1 else ", ".join(symbols[:-1]) + " and " + symbols[-1]
    return f"the impact optimum's {listed} {'lies' if len(symbols) == 1 else 'lie'} at a bound of its box"


def _stop_text(imp: dict) -> str:
    """Whether the optimal impact suppressor reaches its stop, in words."""
    if imp["impacts_per_second"] == 0:
        return (
            f"its gap lies beyond its own travel (stroke {fixed(1)(imp['stroke'])}), so that the "
            "stop is never reached: allowed that, the optimiser makes the impact suppressor a TMD"
        )
    return f"its stop is reached, up to {fixed(2)(imp['impacts_per_second'])} impacts per natural period"


# The comparisons between devices (d: the devices by macro part; hit, hita: the impacting optima
# by peak and band average; large: the largest detuning's key).
COMPARISONS = (
    Macro(
        "DesignRobTmdDampingWord",
        lambda s: (
            "more" if s["d"]["RobTmd"]["parameters"]["delta2"] > s["d"]["TmdOpt"]["parameters"]["delta2"] else "less"
        ),
    ),
    Macro("DesignChartGainBare", _ratio("d.BareDev.peak", "d.Chart.peak"), fixed(2)),
    Macro("DesignChartGainAbsorber", _ratio("d.AbsorberDev.peak", "d.Chart.peak"), fixed(2)),
    Macro("DesignChartRatioTmd", _ratio("d.Chart.peak", "d.TmdOpt.peak"), fixed(2)),
    Macro("DesignOptRatioTmd", _ratio("d.Opt.peak", "d.TmdOpt.peak"), fixed(3)),
    Macro("DesignOptRatioTmdAvg", _ratio("d.OptAvgCrit.band_average", "d.TmdOptAvgCrit.band_average"), fixed(3)),
    Macro("DesignOptRatioWorstLarge", _ratio("d.Opt.worst_large", "d.TmdOpt.worst_large"), fixed(3)),
    Macro("DesignOptGainBare", _ratio("d.BareDev.peak", "d.Opt.peak"), fixed(2)),
    Macro("DesignNearRatioTmd", _ratio("d.Near.peak", "d.TmdOpt.peak"), fixed(3)),
    Macro("DesignNearImpulse", "d.Near.impulse_per_impact", fixed(2)),
    Macro("DesignNearImpactsPerSecond", "d.Near.impacts_per_second", fixed(2)),
    Macro("DesignNearMeanForce", "d.Near.mean_force", fixed(3)),
    Macro("DesignOptStopText", "d.Opt", Format(_stop_text)),
)
HIT = (
    Macro("DesignHitLocPeak", "hit.peak", fixed(3)),
    Macro("DesignHitStroke", "hit.stroke", fixed(1)),
    Macro("DesignHitImpulse", "hit.impulse_per_impact", fixed(2)),
    Macro("DesignHitImpactsPerSecond", "hit.impacts_per_second", fixed(2)),
    Macro("DesignHitMeanForce", "hit.mean_force", fixed(3)),
    Macro("DesignHitWorstLarge", "hit.worst_large", fixed(2)),
    Macro("DesignHitAvgCritGap", "hita.parameters.gap", fixed(2)),
    Macro("DesignHitAvgCritAvg", "hita.band_average", fixed(3)),
    Macro("DesignHitRatioTmdAvg", _ratio("hita.band_average", "d.TmdOptAvgCrit.band_average"), fixed(3)),
    Macro("DesignHitRatioTmd", _ratio("hit.peak", "d.TmdOpt.peak"), fixed(3)),
    Macro("DesignHitRatioWorstLarge", _ratio("hit.worst_large", "d.TmdOpt.worst_large"), fixed(3)),
    Macro("DesignOptImpulse", "d.Opt.impulse_per_impact", fixed(2)),
    Macro("DesignOptImpactsPerSecond", "d.Opt.impacts_per_second", fixed(2)),
    Macro("DesignOptMeanForce", "d.Opt.mean_force", fixed(3)),
    Macro("DesignOptGridPeak", "d.Opt.grid_peak", fixed(3)),
    Macro("DesignChartGridPeak", "d.Chart.grid_peak", fixed(3)),
    Macro("DesignOptAtBound", lambda s: _at_bound_text(s["d"]["Opt"]["at_bound"])),
    Macro("DesignStarts", "optimum.budget.starts", TEXT),
    Macro("DesignKeep", "optimum.budget.keep", TEXT),
    Macro("DesignLocalEvaluations", "optimum.budget.local_evaluations", TEXT),
    Macro("DesignSensImpact", "optimum.sensitivity.impact", Format(_sensitivity_text)),
    Macro("DesignSensTmd", "optimum.sensitivity.tmd", Format(_sensitivity_text)),
    Macro("DesignSensWorsePct", "optimum.sensitivity_worse", percent(0)),
    Macro(
        "DesignRecommendation",
        lambda s: recommendation(
            s["optimum"],
            pm="$\\pm$",
            pct="\\,\\%",
            xst="\\,$x_{\\mathrm{st}}$",
            clearance="$\\Delta_0={gap:.2f}\\,P_0/c_1$",
            force="$P_0$",
        ),
    ),
    # For the README (never expanded in TeX, where its x_st would fail; no "%", which would end the
    # TeX line of its definition).
    Macro("DesignRecommendationPlain", lambda s: recommendation(s["optimum"], pct=" per cent")),
)


def _devices(optimum: dict) -> dict[str, dict]:
    """The design table's devices by macro part (:data:`DEVICE_NAMES`), each with its worst cases
    at the smallest and largest detuning (``worst_small``, ``worst_large``)."""
    out = {}
    for key, name in DEVICE_NAMES.items():
        if name.endswith("..."):
            d = next(d for d in optimum["devices"] if d["device"].startswith(name.removesuffix("...")))
        else:
            d = device(optimum, name)
        out[key] = _with_worst(d, optimum)
    return out


def _with_worst(d: dict, optimum: dict) -> dict:
    """``d`` with its worst cases at the smallest and largest detuning."""
    small, large = (f"{f(optimum['detunings']):g}" for f in (min, max))
    return {**d, "worst_small": d["worst_case"][small], "worst_large": d["worst_case"][large]}


def optimum_macros(optimum: dict) -> list:
    """The design table's macros."""
    d = _devices(optimum)
    out = [
        ("DesignStep", fixed(2)(optimum["step"])),
        ("DesignDetuneSmallPct", percent(0)(min(optimum["detunings"]))),
        ("DesignDetuneLargePct", percent(0)(max(optimum["detunings"]))),
    ]
    for key in IMPACT_DEVICES:
        out += [line for k in DIGITS for line in macro_lines([PARAMETER[k]], d[key], D=key, P=SPEC[k].macro)]
    for key in TMD_DEVICES:
        out += [line for k in ("N", "delta2") for line in macro_lines([PARAMETER[k]], d[key], D=key, P=SPEC[k].macro)]
    for key in d:
        out += macro_lines(DEVICE, d[key], D=key)
    hit = _with_worst(impacting(optimum["devices"]), optimum)
    source = {"d": d, "hit": hit, "hita": impacting(optimum["devices"], "band_average"), "optimum": optimum}
    out += macro_lines(COMPARISONS, source)
    out += [line for k in DIGITS for line in macro_lines([PARAMETER[k]], hit, D="Hit", P=SPEC[k].macro)]
    return out + macro_lines(HIT, source)


def design_macros(base: dict, chart: dict, chart2: dict, resp: dict, optimum: dict, response_csv) -> MacroFile:
    """The design stage's macros (the record of ``paper/generated/design_macros.tex``).

    Parameters
    ----------
    base, chart, chart2, resp, optimum : dict
        The records of the baselines, the 1-D and 2-D design charts, the responses and the
        optimum (figures/design_*.json).
    response_csv : path
        The responses' table (the impact design's max|x1| on the theta grid).

    Returns
    -------
    MacroFile
        The macros, in the order the report's record lists them.
    """
    bp, tmd = chart["best"]["peak"], base["tmd"]["peak"]
    paper = {r["gap"]: r for r in resp["responses"]}
    paper_gap = -5.8 if -5.8 in paper else resp["responses"][-1]["gap"]
    share, runs = impact_better(response_csv, bp["gap"], tmd)
    source = {
        "base": base,
        "chart": chart,
        "chart2": chart2,
        "resp": resp,
        "bp": bp,
        "ba": chart["best"]["band_average"],
        "one": chart["at_reference_theta"],
        "best": next(r for r in resp["responses"] if r["role"] == "best"),
        "paper": paper[paper_gap],
        "paper_gap": paper_gap,
        "tmd": tmd,
        "tmd_avg": base["tmd"]["band_average"],
        "bare": base["references"]["bare"],
        "absorber": base["references"]["absorber"],
        "share": share,
        "runs": runs,
        "dh": base["den_hartog_check"],
    }
    m = MacroFile(["% Written by workflow/scripts/design_report.py; do not edit."])
    m.extend(macro_lines(CHART, source))
    m.extend(optimum_macros(optimum))
    return m


# --- the tables -----------------------------------------------------------------------------
def tex_device(name: str) -> str:
    """A device's name of the record as TeX."""
    for plain, tex in (
        ("<=", "$\\le$"),
        ("+-", "$\\pm$"),
        (" %", "\\,\\%"),
        ("delta2", "$\\delta_2$"),
        ("paper's N", "paper's $N$"),
        (", R", ", $R$"),
    ):
        name = name.replace(plain, tex)
    return name


def _parameters_text(parameters: dict) -> str:
    """A device's designed parameters, ``$N=0.500$, ...`` (--- where it has none)."""
    text = ", ".join(f"${SYMBOLS[k]}={fixed(DIGITS[k])(parameters[k])}$" for k in SYMBOLS if k in parameters)
    return text or "---"


def _loads_text(d: dict) -> str:
    """An impact suppressor's pulse, impacts and mean force (--- for a linear device)."""
    if d["kind"] != "impact":
        return "---"
    return f"{fixed(2)(d['impulse_per_impact'])}, {fixed(2)(d['impacts_per_second'])}, {fixed(3)(d['mean_force'])}"


def design_table(optimum: dict) -> str:
    """The design table (booktabs): device; parameters; located peak; band average; worst case
    at each detuning; stroke; loads (impact suppressors)."""
    detunings = optimum["detunings"]
    worst = [Column(lambda d, k=f"{x:g}": d["worst_case"][k], fixed(2)) for x in detunings]
    table = Table(
        # Text columns that wrap, so that the table fits the text width at the caption's size.
        colspec=r">{\raggedright\arraybackslash}p{0.17\linewidth}>{\raggedright\arraybackslash}p{0.2\linewidth}"
        + "r" * (3 + len(detunings))
        + r">{\raggedright\arraybackslash}p{0.1\linewidth}",
        header="device & parameters & peak & band avg. & "
        + " & ".join(f"worst $\\pm{100 * x:g}\\,\\%$" for x in detunings)
        + " & stroke & pulse, impacts, force",
        comments=["Written by workflow/scripts/design_report.py; do not edit."],
        columns=[
            Column("device", Format(tex_device)),
            Column("parameters", Format(_parameters_text)),
            Column("peak", fixed(3)),
            Column("band_average", fixed(3)),
            *worst,
            # The bare object has no suppressor, hence no stroke.
            Column(lambda d: None if not d["parameters"] else d["stroke"], fixed(1, missing="---")),
            Column(lambda d: d, Format(_loads_text)),
        ],
    )
    return table.render(optimum["devices"])


# A table's number in math mode (a true minus sign).
MATH2 = Format(lambda x: f"${fixed(2)(x)}$")
SECOND_TABLE = Table(
    colspec="rrrrrr",
    header="{} & best $\\Delta_0/x_{{\\mathrm{{st}}}}$ & peak $\\max|x_1|/x_{{\\mathrm{{st}}}}$ & good gaps & peak pulse & "
    "impacts/$T$",
    comments=["Written by workflow/scripts/design_report.py; do not edit."],
    columns=[
        Column("second", MATH2),
        Column("gap", MATH2),
        Column("value", MATH2),
        Column(lambda b: f"{MATH2(b['good_from'])} to {MATH2(b['good_to'])}"),
        Column("peak_impulse", MATH2),
        Column("impacts_per_period", Format(lambda x: f"${fixed(0)(x)}$")),
    ],
)


def second_table(chart2: dict) -> str:
    """The booktabs table of the best gap (peak criterion) against the second parameter."""
    name = chart2["parameter"]
    symbol = f"${SPEC[name].symbol}$" if name in SPEC else name
    table = dataclasses.replace(SECOND_TABLE, header=SECOND_TABLE.header.format(symbol))
    return table.render([b for b in chart2["best"] if b["criterion"] == "peak"])
