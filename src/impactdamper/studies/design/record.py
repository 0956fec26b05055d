"""The design stage's record for the report's section "Choosing a suppressor": its macros, the
design table and the table of the best gap against the second parameter, as TeX.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the numbers come from the design stage's records (figures/design_*.json), no number is
typed by hand. Used by ``workflow/scripts/design_report.py``.
"""

from __future__ import annotations

import numpy as np

from impactdamper.reporting.latex import MacroFile, fixed, tex_sci
from impactdamper.reporting.records import read_csv
from impactdamper.studies.design.design import bare_object_amplitude, runs_where, two_mass_amplitude
from impactdamper.studies.design.optimum import IMPACT_BOUNDS, device, impacting, recommendation
from impactdamper.studies.vocabulary import SPEC


def impact_better(response_csv, gap: float, tmd: dict) -> tuple[float, list]:
    """Share of the theta grid (and its runs) where the impact design at ``gap`` (worse direction)
    keeps max|x1| below the optimal TMD's."""
    rows = [r for r in read_csv(response_csv) if abs(float(r["gap"]) - gap) < 1e-12]
    thetas = sorted({float(r["theta"]) for r in rows})
    worst = np.array([max(float(r["max_abs_x1"]) for r in rows if float(r["theta"]) == t) for t in thetas])
    lin = two_mass_amplitude(tmd["mu"], tmd["N"], tmd["delta1"], tmd["delta2"], thetas)
    better = worst < lin
    return float(better.mean()), runs_where(thetas, better)


# What the stage's record holds (results/report/design.json).
RECORD_WHAT = "Macros of the report's section 'Choosing a suppressor' (design stage)"


def _sensitivity_text(sens: dict, names: dict) -> str:
    """``$N$: -0.012/+0.020, ...``: each parameter's move for a 5 % worse peak (">" where even
    the box's bound is not that much worse)."""
    parts = []
    for n in [k for k in names if k in sens]:
        sides = sens[n]
        text = "/".join(
            ("$>$bound" if v is None else f"{sign}{fixed(v, 3)}")
            for sign, v in (("$-$", sides["down"]), ("$+$", sides["up"]))
        )
        parts.append(f"${names[n]}$ {text}")
    return ", ".join(parts)


# The impact suppressor's designed parameters (the optimiser's, in its order) and their symbols,
# as the design section writes them (x_{st} without \\mathrm, as in its other macros).
SYMBOLS = {k: SPEC[k].symbol.replace("\\mathrm{st}", "st") for k in IMPACT_BOUNDS}


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


def design_table(optimum: dict) -> str:
    """The design table (booktabs): device; parameters; located peak; band average; worst case
    at each detuning; stroke; loads (impact suppressors)."""
    ds = [f"{100 * d:g}" for d in optimum["detunings"]]
    head = (
        "device & parameters & peak & band avg. & "
        + " & ".join(f"worst $\\pm{d}\\,\\%$" for d in ds)
        + " & stroke & pulse, impacts, force \\\\"
    )
    lines = [
        "% Written by workflow/scripts/design_report.py; do not edit.",
        "\\begin{tabular}{ll" + "r" * (4 + len(ds)) + "}",
        "\\toprule",
        head,
        "\\midrule",
    ]
    for d in optimum["devices"]:
        digits = {"gap": 2, "N": 3, "delta2": 3, "R": 2}
        pars = (
            ", ".join(f"${SYMBOLS[k]}={fixed(d['parameters'][k], digits[k])}$" for k in SYMBOLS if k in d["parameters"])
            or "---"
        )
        worst = " & ".join(fixed(d["worst_case"][f"{x:g}"], 2) for x in optimum["detunings"])
        loads = (
            f"{fixed(d['impulse_per_impact'], 2)}, {fixed(d['impacts_per_second'], 2)}, {fixed(d['mean_force'], 3)}"
            if d["kind"] == "impact"
            else "---"
        )
        lines.append(
            f"{tex_device(d['device'])} & {pars} & {fixed(d['peak'], 3)} & {fixed(d['band_average'], 3)} & "
            f"{worst} & {fixed(d['stroke'], 1)} & {loads} \\\\"
        )
    lines += ["\\bottomrule", "\\end{tabular}"]
    return "\n".join(lines) + "\n"


def optimum_macros(add, optimum: dict) -> None:
    """The design table's macros (``add(name, text)``)."""
    dmax = f"{max(optimum['detunings']):g}"
    dmin = f"{min(optimum['detunings']):g}"
    imp, tmd = device(optimum, "impact, optimal peak"), device(optimum, "TMD, optimal peak")
    impa, tmda = device(optimum, "impact, optimal band average"), device(optimum, "TMD, optimal band average")
    bare, absorber = device(optimum, "bare object"), device(optimum, "absorber without a stop")
    paper = next(d for d in optimum["devices"] if d["device"].startswith("impact, paper"))
    eq = device(optimum, "TMD, impact's stroke")
    rob_t = next(d for d in optimum["devices"] if d["device"].startswith("TMD, robust"))
    rob_i = next(d for d in optimum["devices"] if d["device"].startswith("impact, robust"))
    near = next(d for d in optimum["devices"] if d["device"].startswith("impact, optimal peak, gap"))
    add("DesignStep", fixed(optimum["step"], 2))
    add("DesignDetuneSmallPct", fixed(100 * min(optimum["detunings"]), 0))
    add("DesignDetuneLargePct", fixed(100 * max(optimum["detunings"]), 0))
    for key, d in (("Opt", imp), ("OptAvgCrit", impa), ("Chart", paper), ("RobImp", rob_i), ("Near", near)):
        for k, digits, name in (("gap", 2, "Gap"), ("N", 3, "N"), ("delta2", 3, "DeltaTwo"), ("R", 2, "R")):
            add(f"Design{key}{name}", fixed(d["parameters"][k], digits))
    for key, d in (("TmdOpt", tmd), ("TmdOptAvgCrit", tmda), ("Eq", eq), ("RobTmd", rob_t)):
        add(f"Design{key}N", fixed(d["parameters"]["N"], 3))
        add(f"Design{key}DeltaTwo", fixed(d["parameters"]["delta2"], 3))
    for key, d in (
        ("Opt", imp),
        ("OptAvgCrit", impa),
        ("Chart", paper),
        ("RobImp", rob_i),
        ("Near", near),
        ("TmdOpt", tmd),
        ("TmdOptAvgCrit", tmda),
        ("Eq", eq),
        ("RobTmd", rob_t),
        ("BareDev", bare),
        ("AbsorberDev", absorber),
    ):
        add(f"Design{key}LocPeak", fixed(d["peak"], 3))
        add(f"Design{key}LocTheta", fixed(d["peak_theta"], 3))
        add(f"Design{key}Avg", fixed(d["band_average"], 3))
        add(f"Design{key}WorstSmall", fixed(d["worst_case"][dmin], 2))
        add(f"Design{key}WorstLarge", fixed(d["worst_case"][dmax], 2))
        add(f"Design{key}Stroke", fixed(d["stroke"], 1))
    add("DesignRobTmdDampingWord", "more" if rob_t["parameters"]["delta2"] > tmd["parameters"]["delta2"] else "less")
    add("DesignChartGainBare", fixed(bare["peak"] / paper["peak"], 2))
    add("DesignChartGainAbsorber", fixed(absorber["peak"] / paper["peak"], 2))
    add("DesignChartRatioTmd", fixed(paper["peak"] / tmd["peak"], 2))
    add("DesignOptRatioTmd", fixed(imp["peak"] / tmd["peak"], 3))
    add("DesignOptRatioTmdAvg", fixed(impa["band_average"] / tmda["band_average"], 3))
    add("DesignOptRatioWorstLarge", fixed(imp["worst_case"][dmax] / tmd["worst_case"][dmax], 3))
    add("DesignOptGainBare", fixed(bare["peak"] / imp["peak"], 2))
    add("DesignNearRatioTmd", fixed(near["peak"] / tmd["peak"], 3))
    add("DesignNearImpulse", fixed(near["impulse_per_impact"], 2))
    add("DesignNearImpactsPerSecond", fixed(near["impacts_per_second"], 2))
    add("DesignNearMeanForce", fixed(near["mean_force"], 3))
    hit = impacting(optimum["devices"])
    add(
        "DesignOptStopText",
        (
            f"its gap lies beyond its own travel (stroke {fixed(imp['stroke'], 1)}), so that the "
            "stop is never reached: allowed that, the optimiser makes the impact suppressor a TMD"
            if imp["impacts_per_second"] == 0
            else f"its stop is reached, up to {fixed(imp['impacts_per_second'], 2)} impacts per natural period"
        ),
    )
    for k, digits, name in (("gap", 2, "Gap"), ("N", 3, "N"), ("delta2", 3, "DeltaTwo"), ("R", 2, "R")):
        add(f"DesignHit{name}", fixed(hit["parameters"][k], digits))
    for k, digits, name in (
        ("peak", 3, "LocPeak"),
        ("stroke", 1, "Stroke"),
        ("impulse_per_impact", 2, "Impulse"),
        ("impacts_per_second", 2, "ImpactsPerSecond"),
        ("mean_force", 3, "MeanForce"),
    ):
        add(f"DesignHit{name}", fixed(hit[k], digits))
    add("DesignHitWorstLarge", fixed(hit["worst_case"][dmax], 2))
    hita = impacting(optimum["devices"], "band_average")
    add("DesignHitAvgCritGap", fixed(hita["parameters"]["gap"], 2))
    add("DesignHitAvgCritAvg", fixed(hita["band_average"], 3))
    add("DesignHitRatioTmdAvg", fixed(hita["band_average"] / tmda["band_average"], 3))
    add("DesignHitRatioTmd", fixed(hit["peak"] / tmd["peak"], 3))
    add("DesignHitRatioWorstLarge", fixed(hit["worst_case"][dmax] / tmd["worst_case"][dmax], 3))
    add("DesignOptImpulse", fixed(imp["impulse_per_impact"], 2))
    add("DesignOptImpactsPerSecond", fixed(imp["impacts_per_second"], 2))
    add("DesignOptMeanForce", fixed(imp["mean_force"], 3))
    add("DesignOptGridPeak", fixed(imp["grid_peak"], 3))
    add("DesignChartGridPeak", fixed(paper["grid_peak"], 3))
    add("DesignOptAtBound", ", ".join(imp["at_bound"]) or "none")
    add("DesignStarts", optimum["budget"]["starts"])
    add("DesignKeep", optimum["budget"]["keep"])
    add("DesignLocalEvaluations", optimum["budget"]["local_evaluations"])
    add("DesignSensImpact", _sensitivity_text(optimum["sensitivity"]["impact"], SYMBOLS))
    add("DesignSensTmd", _sensitivity_text(optimum["sensitivity"]["tmd"], SYMBOLS))
    add("DesignSensWorsePct", fixed(100 * optimum["sensitivity_worse"], 0))
    add("DesignRecommendation", recommendation(optimum, pm="$\\pm$", pct="\\,\\%", xst="\\,$x_{st}$"))
    # For the README (never expanded in TeX, where its x_st would fail; no "%", which would end the
    # TeX line of its definition).
    add("DesignRecommendationPlain", recommendation(optimum, pct=" per cent"))


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
    bp, ba = chart["best"]["peak"], chart["best"]["band_average"]
    tmd, tmd_avg = base["tmd"]["peak"], base["tmd"]["band_average"]
    bare, absorber = base["references"]["bare"], base["references"]["absorber"]
    best_resp = next(r for r in resp["responses"] if r["role"] == "best")
    paper = {r["gap"]: r for r in resp["responses"]}
    paper_gap = -5.8 if -5.8 in paper else resp["responses"][-1]["gap"]
    share, runs = impact_better(response_csv, bp["gap"], tmd)
    dh = base["den_hartog_check"]
    m = MacroFile(["% Written by workflow/scripts/design_report.py; do not edit."])
    add = m.add
    add("DesignBandStart", fixed(base["band"][0], 2))
    add("DesignBandStop", fixed(base["band"][1], 2))
    add("DesignThetaPoints", chart["theta_points"])
    add("DesignGapStep", fixed(chart["gap_step"], 2))
    add("DesignTolerancePct", fixed(100 * bp["tolerance"], 0))
    add("DesignBestGap", fixed(bp["gap"], 2))
    add("DesignBestPeak", fixed(bp["value"], 2))
    add("DesignGoodFrom", fixed(bp["good_from"], 2))
    add("DesignGoodTo", fixed(bp["good_to"], 2))
    add("DesignBestImpulse", fixed(bp["peak_impulse"], 2))
    add("DesignBestImpacts", fixed(bp["impacts_per_period"], 0))
    one = chart["at_reference_theta"]
    add("DesignRefTheta", fixed(one["theta"], 2))
    add("DesignRefThetaGap", fixed(one["gap"], 2))
    add("DesignRefThetaValue", fixed(one["value"], 2))
    add("DesignRefThetaBare", fixed(float(bare_object_amplitude(base["parameters"]["delta1"], [one["theta"]])[0]), 2))
    add("DesignAvgBestGap", fixed(ba["gap"], 2))
    add("DesignAvgBest", fixed(ba["value"], 3))
    add("DesignAvgGoodFrom", fixed(ba["good_from"], 2))
    add("DesignAvgGoodTo", fixed(ba["good_to"], 2))
    add("DesignBestGapAvg", fixed(best_resp["band_average"], 3))
    add("DesignBarePeak", fixed(bare["peak"], 2))
    add("DesignBareAvg", fixed(bare["band_average"], 3))
    add("DesignAbsorberPeak", fixed(absorber["peak"], 2))
    add("DesignAbsorberAvg", fixed(absorber["band_average"], 3))
    add("DesignTmdPeak", fixed(tmd["peak"], 2))
    add("DesignTmdAvg", fixed(tmd["band_average"], 3))
    add("DesignTmdN", fixed(tmd["N"], 4))
    add("DesignTmdDeltaTwo", fixed(tmd["delta2"], 4))
    add("DesignTmdAvgOptAvg", fixed(tmd_avg["band_average"], 3))
    add("DesignTmdAvgOptN", fixed(tmd_avg["N"], 4))
    add("DesignTmdAvgOptDeltaTwo", fixed(tmd_avg["delta2"], 4))
    add("DesignGainBare", fixed(bare["peak"] / bp["value"], 2))
    add("DesignGainAbsorber", fixed(absorber["peak"] / bp["value"], 2))
    add("DesignRatioTmd", fixed(bp["value"] / tmd["peak"], 2))
    add("DesignRatioTmdAvg", fixed(best_resp["band_average"] / tmd["band_average"], 2))
    add("DesignImpactBetterPct", fixed(100 * share, 0))
    add(
        "DesignImpactBetterRuns",
        ", ".join(f"${fixed(a, 2)}$--${fixed(b, 2)}$" if b > a else f"${fixed(a, 2)}$" for a, b in runs) or "none",
    )
    add("DesignPaperGap", fixed(paper_gap, 1))
    add("DesignPaperPeak", fixed(paper[paper_gap]["peak"], 2))
    add("DesignPaperImpulse", fixed(paper[paper_gap]["peak_impulse"], 2))
    add("DesignPaperImpacts", fixed(paper[paper_gap]["impacts_per_period"], 0))
    add("DesignBestHysteresis", best_resp["hysteresis_points"])
    add("DesignResponsePoints", resp["points"])
    add("DesignBalanceMax", tex_sci(max(r["largest_balance"] for r in resp["responses"]), 1))
    add("DesignDriftMax", tex_sci(max(r["largest_drift_settled"] for r in resp["responses"]), 1))
    add("DesignDHPeak", fixed(dh["closed_form"]["peak"], 4))
    add("DesignDHPeakAtDH", fixed(dh["peak_at_closed_form"], 4))
    add("DesignDHOptPeak", fixed(dh["optimiser"]["peak"], 4))
    add("DesignDHExcessPct", fixed(100 * dh["peak_relative_excess"], 2))
    add("DesignDHN", fixed(dh["closed_form"]["N"], 4))
    add("DesignDHOptN", fixed(dh["optimiser"]["N"], 4))
    add("DesignDHNDiff", tex_sci(abs(dh["N_relative_difference"]), 1))
    add("DesignDHDeltaTwo", fixed(dh["closed_form"]["delta2"], 4))
    add("DesignDHOptDeltaTwo", fixed(dh["optimiser"]["delta2"], 4))
    add("DesignSecondName", chart2["parameter"])
    optimum_macros(add, optimum)
    return m


def second_table(chart2: dict) -> str:
    """The booktabs table of the best gap (peak criterion) against the second parameter."""
    sym = {"N": "$N$", "R": "$R$"}.get(chart2["parameter"], chart2["parameter"])
    lines = [
        "% Written by workflow/scripts/design_report.py; do not edit.",
        "\\begin{tabular}{rrrrrr}",
        "\\toprule",
        f"{sym} & best $\\Delta_0/x_{{st}}$ & peak $\\max|x_1|/x_{{st}}$ & good gaps & peak pulse & impacts/$T$ \\\\",
        "\\midrule",
    ]
    for b in chart2["best"]:
        if b["criterion"] != "peak":
            continue
        lines.append(
            f"{fixed(b['second'], 2)} & {fixed(b['gap'], 2)} & {fixed(b['value'], 2)} & "
            f"{fixed(b['good_from'], 2)} to {fixed(b['good_to'], 2)} & {fixed(b['peak_impulse'], 2)} & "
            f"{fixed(b['impacts_per_period'], 0)} \\\\"
        )
    lines += ["\\bottomrule", "\\end{tabular}"]
    return "\n".join(lines) + "\n"
