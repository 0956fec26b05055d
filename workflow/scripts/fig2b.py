"""Reproduces Fig. 2b of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100.

Caption: "Fig. 2. The laws of motion of an object x1(t) and a suppressor x2(t), obtained
using algorithm No. 1 (a) and No. 2 (b)". The text: "the oscillation period of the system
is equal to two periods of external influence T_c = 2T and during this period T_c there are
three collisions of the object and suppressor at times t1, t2, t3, [with] t = t4 the next
cycle of interaction of the indicated bodies begins".

Plots x1_bar and x2_bar of the motion Algorithm No. 2 settles to (from the paper's step 1)
over one full cycle T_c plus the next cycle's first impact, time (t - t1)/T counted from the
cycle's first impact; the impacts are marked t1, t2, ... and the next cycle's start.

Deviations: the paper's figure is lost in the available text; which impact is t1 is ours
(the one ending the cycle's longest free flight). The figure is drawn for the stated case
(Delta0/x_st = -5.8, which settles to one impact per period) and for the located case (which
settles to the paper's T_c = 2T with three impacts), each labelled in its title.
"""

import numpy as np

from impactdamper.reporting.records import read_json, run_stage
from impactdamper.reporting.figures import label_above, motion_figure, plot_motion
from impactdamper.reporting.plotting import CASE_LABELS, finish_figure
from impactdamper.studies.vocabulary import SPEC


CYCLE_COLOR = "#e8eef6"


def main(case: str, curve_csv, case_json, out_pdf, out_png) -> None:
    data = read_json(case_json)
    s = data["algorithm2"]
    gap = data["parameters"]["gap"]
    k = s["period_multiple"]
    n = s["impacts_per_cycle"]
    label = CASE_LABELS[case]
    period = "T" if k == 1 else f"{k}T"
    cycle = f"$T_c = {period}$, {n} impact{'s' if n != 1 else ''} per cycle" if k else "no settled period"
    title = f"The paper's Fig. 2b, {label}: Algorithm No. 2, ${SPEC['gap'].symbol} = {gap:g}$: {cycle}"
    t, x1, x2, g = np.loadtxt(curve_csv, delimiter=",", skiprows=1, unpack=True)
    fig, ax, axg = motion_figure()
    if k:
        for axis in (ax, axg):
            axis.axvspan(0.0, k, color=CYCLE_COLOR, lw=0, label=f"one cycle $T_c = {period}$" if axis is ax else None)
    plot_motion(ax, axg, t, x1, x2, g, "$\\Delta/x_{\\mathrm{st}}$")
    for row in s["impact_table"]:
        x = row["t_over_T"]
        nxt = row["next_cycle"]
        for axis in (ax, axg):
            axis.axvline(x, color="0.35", lw=0.7, ls="--" if nxt else ":")
        y = float(np.interp(x, t, x1))
        ax.plot([x], [y], "o", color="k", ms=3.5, zorder=5)
        name = row["label"].replace("t", "t_")
        text = f"${name}$" + (" (next cycle)" if nxt else "")  # one line: clear of the title above
        label_above(ax, x, text)
    ax.plot([], [], "o", color="k", ms=3.5, label="impacts")
    ax.set_xlim(t[0], t[-1])
    ax.set_ylabel("relative coordinate")
    axg.set_ylabel("gap")
    axg.set_xlabel("time since the cycle's first impact, $(t - t_1)/T$")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axg.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(title, pad=24, loc="left", x=-0.1)
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "wildcards.case input.csv input.json output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
