"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design chart, which
gap to build. The sweeps stage gives max|x1| against the gap at theta = 1 only (the paper's
figures fix theta = 1 too); here the criterion is taken over the band of forcing frequencies.

The paper's suppressor (its N, delta2, R) only. Top: the worst branch's peak (solid) and band
average (dashed) over the band of max|x1|/x_st against Delta0/x_st, and the worst motion at the
reference theta alone (the gap sweep's reading; dotted), the located best gap of each criterion
marked and its band of good gaps shaded; the bare object, the absorber without a stop, the
optimal linear TMD and the design table's optimal impact suppressor (its own N, delta2, R) as
horizontal lines. Bottom: the loads, largest pulse per impact over P0/omega1 and impacts per
period, over the band.

Deviations: none (the paper has no such figure).
"""

from impactdamper.reporting.plotting import figure_size, finish_figure, use_style
from impactdamper.reporting.records import cell_float, read_csv, read_json, run_stage
from impactdamper.studies.vocabulary import GAP_AXIS_LABEL, SPEC


def main(chart_csv, chart_json, baselines_json, optimum_json, out_pdf, out_png) -> None:
    plt = use_style()
    rows = read_csv(chart_csv)
    best = read_json(chart_json)["best"]
    located = read_json(chart_json)["located"]
    base = read_json(baselines_json)
    opt = {d["device"]: d for d in read_json(optimum_json)["devices"]}
    g = [float(r["gap"]) for r in rows]
    fig, (ax, ax2) = plt.subplots(
        2, 1, figsize=figure_size(4.8), sharex=True, layout="constrained", gridspec_kw={"height_ratios": [2, 1]}
    )
    for key, crit, ls, text in (
        ("peak_max_abs_x1", "peak", "-", "peak over the band"),
        ("band_average_max_abs_x1", "band_average", "--", "band average"),
    ):
        ax.plot(g, [cell_float(r[key]) for r in rows], color="C0", ls=ls, lw=1.1, label=f"impact: {text}")
        b, x = best[crit], located[crit]
        ax.plot([x["gap"]], [x["value"]], "o", color="C0", ms=4)
        ax.axvspan(b["good_from"], b["good_to"], color="C0", alpha=0.12 if crit == "peak" else 0.06, lw=0)
    one = read_json(chart_json)["at_reference_theta"]
    ax.plot(
        g,
        [cell_float(r["max_abs_x1_at_theta"]) for r in rows],
        color="C4",
        ls=":",
        lw=1.0,
        label=f"impact: at ${SPEC['theta'].symbol} = {one['theta']:g}$ alone",
    )
    refs = base["references"]
    for value, text, color, ls in (
        (refs["bare"]["peak"], "object alone, peak", "0.3", ":"),
        (refs["absorber"]["peak"], "absorber no stop, peak", "C2", "-."),
        (opt["tmd_peak"]["peak"], "optimal TMD, peak", "C3", "-"),
        (opt["tmd_band_average"]["band_average"], "optimal TMD, its band average", "C3", "--"),
        (opt["impact_peak_reach"]["peak"], "optimal impact suppressor, peak", "C1", "-."),
    ):
        ax.axhline(value, color=color, ls=ls, lw=0.8, label=f"{text} ({value:.2f})")
    ax.set_ylabel("$\\max|x_1|/x_{\\mathrm{st}}$ over the band")
    ax.set_ylim(0.0, None)
    ax.legend(fontsize="small", ncol=3, loc="lower center", bbox_to_anchor=(0.5, 1.01))
    ax2.plot(
        g,
        [cell_float(r["peak_impulse"]) for r in rows],
        color="C0",
        lw=0.9,
        label="largest pulse per impact ($P_0/\\omega_1$)",
    )
    ax3 = ax2.twinx()
    ax3.plot(
        g,
        [cell_float(r["impacts_per_period"]) for r in rows],
        color="C1",
        lw=0.8,
        ls="--",
        label="most impacts per period",
    )
    ax2.set_ylim(0.0, None)
    ax3.set_ylim(0.0, None)
    ax2.set_ylabel("pulse ($P_0/\\omega_1$)")
    ax3.set_ylabel("impacts per period")
    ax2.set_xlabel(GAP_AXIS_LABEL)
    h1, l1 = ax2.get_legend_handles_labels()
    h2, l2 = ax3.get_legend_handles_labels()
    ax2.legend(h1 + h2, l1 + l2, fontsize="small", loc="lower left")
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.chart input.best input.baselines input.optimum output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
