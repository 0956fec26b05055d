"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: amplitude against forcing
frequency, the curve the paper's motivation (a varying forcing frequency) asks for.

Top: max|x1|/x_st of the impact suppressor at the design chart's best gap and at the paper's
Delta0/x_st = -5.8 (upward sweep solid, downward dashed; crosses where they differ), beside the
bare object, the absorber without a stop (same mu, N, delta2) and the optimal linear TMD of the
same mu. Bottom: the loads at the best gap, largest pulse per impact over m1 x_st omega and
impacts per forcing period.

Deviations: none (the paper has no such figure).
"""

import numpy as np

from impactdamper.reporting.plotting import figure_size, finish_figure, use_style
from impactdamper.reporting.records import cell_float, read_csv, read_json, run_stage
from impactdamper.studies.vocabulary import SPEC


def main(response_csv, response_json, baselines_csv, out_pdf, out_png) -> None:
    plt = use_style()
    rows = read_csv(response_csv)
    base = read_csv(baselines_csv)
    summary = read_json(response_json)["responses"]
    fig, (ax, ax2) = plt.subplots(
        2, 1, figsize=figure_size(4.6), sharex=True, layout="constrained", gridspec_kw={"height_ratios": [2.2, 1]}
    )
    th = [float(r["theta"]) for r in base]
    for key, text, color, ls in (
        ("bare", "object alone", "0.3", ":"),
        ("absorber", "absorber, no stop", "C2", "-."),
        ("tmd_peak", "optimal linear TMD", "C3", "-"),
    ):
        ax.plot(th, [float(r[key]) for r in base], color=color, ls=ls, lw=0.9, label=text)
    colors = ["C0", "C1", "C4", "C5"]
    for s, color in zip(summary, colors):
        g = s["gap"]
        rs = [r for r in rows if float(r["gap"]) == g]
        for direction, ls in (("up", "-"), ("down", "--")):
            d = [r for r in rs if r["direction"] == direction]
            label = (
                f"impact, $\\Delta_0/x_{{\\mathrm{{st}}}} = {g:.2f}$" + (" (best)" if s["role"] == "best" else "")
                if direction == "up"
                else None
            )
            ax.plot(
                [float(r["theta"]) for r in d],
                [cell_float(r["max_abs_x1"]) for r in d],
                color=color,
                ls=ls,
                lw=1.1 if direction == "up" else 0.9,
                label=label,
            )
        hyst = [r for r in rs if r["direction"] == "up" and r["hysteresis"] == "1"]
        if hyst:
            ax.plot(
                [float(r["theta"]) for r in hyst],
                [cell_float(r["max_abs_x1"]) for r in hyst],
                "x",
                color=color,
                ms=3,
                mew=0.7,
            )
    ax.set_ylabel("$\\max|x_1|/x_{\\mathrm{st}}$")
    ax.set_ylim(0.0, None)
    ax.legend(fontsize="small", loc="upper left")
    best = summary[0]
    rs = [r for r in rows if float(r["gap"]) == best["gap"]]
    for direction, ls in (("up", "-"), ("down", "--")):
        d = [r for r in rs if r["direction"] == direction]
        ax2.plot(
            [float(r["theta"]) for r in d],
            [cell_float(r["peak_impulse"]) for r in d],
            color="C0",
            ls=ls,
            lw=0.9,
            label="peak pulse $S/(m_1 x_{\\mathrm{st}}\\omega)$" if direction == "up" else None,
        )
    ax2.set_ylim(0.0, None)
    ax2.set_ylabel("pulse per impact")
    ax2.set_xlabel("forcing frequency " + SPEC["theta"].label)
    ax3 = ax2.twinx()
    d = [r for r in rs if r["direction"] == "up"]
    ax3.step(
        [float(r["theta"]) for r in d],
        [cell_float(r["impacts_per_period"]) for r in d],
        where="mid",
        color="C1",
        lw=0.8,
        label="impacts per period (upward)",
    )
    ax3.set_ylabel("impacts per period")
    ax3.set_ylim(0.0, max(2.0, 1.15 * np.nanmax([cell_float(r["impacts_per_period"]) for r in d])))
    h1, l1 = ax2.get_legend_handles_labels()
    h2, l2 = ax3.get_legend_handles_labels()
    ax2.legend(h1 + h2, l1 + l2, fontsize="small", loc="upper left")
    ax2.set_title(f"loads at the best gap $\\Delta_0/x_{{\\mathrm{{st}}}} = {best['gap']:.2f}$")
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.response input.summary input.baselines output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
