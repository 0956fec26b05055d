"""Reproduces Fig. 2a of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100.

Caption: "Fig. 2. The laws of motion of an object x1(t) and a suppressor x2(t), obtained
using algorithm No. 1 (a) and No. 2 (b)". The text: "the gap Delta takes on negative values
when t in (t1, t2)".

Plots x1_bar = x1/x_st and x2_bar = (x2 - Delta0)/x_st of Algorithm No. 1's orbit over one
forcing period, time t/T counted from the impact (the paper's t = t* - t*_y). The gap is
Delta = (x1_bar - x2_bar) x_st, so it is negative where x2_bar lies above x1_bar: that
stretch is shaded and its ends marked t1, t2.

Deviations: the paper's figure is lost in the available text (only the caption remains), so
axis ranges and styling are ours; the figure is drawn twice, for the stated case
(Delta0/x_st = -5.8, where the gap never goes negative) and for the located case (where it
does), each labelled in its title.
"""

import numpy as np

from impactdamper.reporting.records import read_json, run_stage
from impactdamper.reporting.figures import label_above, motion_figure, plot_motion
from impactdamper.reporting.plotting import CASE_LABELS, finish_figure
from impactdamper.studies.vocabulary import SPEC


# Light red of the shaded negative-gap stretch.
NEGATIVE_GAP_COLOR = "#f4cccc"


def main(case: str, curve_csv, case_json, out_pdf, out_png) -> None:
    data = read_json(case_json)
    a = data["algorithm1"]
    gap = data["parameters"]["gap"]
    fig, ax, axg = motion_figure()
    label = CASE_LABELS[case]
    title = f"The paper's Fig. 2a, {label}: Algorithm No. 1, ${SPEC['gap'].symbol} = {gap:g}$"
    if not a["exists"]:
        ax.text(
            0.5, 0.5, "Algorithm No. 1 has no orbit:\n" + a["reason"], ha="center", va="center", transform=ax.transAxes
        )
    else:
        t, x1, x2, g = np.loadtxt(curve_csv, delimiter=",", skiprows=1, unpack=True)
        intervals = a["negative_gap_intervals"]
        for k, (t1, t2) in enumerate(intervals):
            for axis in (ax, axg):
                axis.axvspan(
                    t1, t2, color=NEGATIVE_GAP_COLOR, lw=0, label="gap $\\Delta < 0$" if k == 0 and axis is ax else None
                )
            for name, x in ((2 * k + 1, t1), (2 * k + 2, t2)):
                for axis in (ax, axg):
                    axis.axvline(x, color="0.35", lw=0.7, ls=":")
                label_above(ax, x, f"$t_{{{name}}} = {x:.4f}\\,T$")
        plot_motion(ax, axg, t, x1, x2, g, "$\\Delta/x_{\\mathrm{st}} = \\bar x_1 - \\bar x_2$")
        note = "" if intervals else "gap $\\Delta \\geq 0$ over\nthe whole period:\nno interval $(t_1, t_2)$"
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), title=note or None, alignment="left")
        axg.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
        axg.set_xlim(0.0, 1.0)
    axg.set_xlabel("time since the impact, in units of $T$")
    ax.set_ylabel("relative coordinate")
    axg.set_ylabel("gap")
    ax.set_title(title, pad=14, loc="left", x=-0.1)
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "wildcards.case input.csv input.json output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
