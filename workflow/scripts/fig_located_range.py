"""Extends Fig. 2 of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: where, in
Delta0/x_st, the behaviour the paper reports for its reference case does occur (the other
parameters as stated).

The paper: "the gap Delta takes on negative values when t in (t1, t2)" (Algorithm No. 1,
Fig. 2a) and "T_c = 2T and during this period T_c there are three collisions" (Algorithm
No. 2, Fig. 2b), both at Delta0/x_st = -5.8.

Top: the smallest interior gap of Algorithm No. 1's orbit (negative where claim (a) holds;
no marker where the orbit does not exist or its gap has no interior minimum, i.e. it only
rises from the impact and falls to the next one). Bottom: the settled motion of Algorithm No. 2
from the paper's step 1, as T_c/T and impacts per cycle (0 where the motion did not settle
within ``max_periods``; more than ``Y_MAX`` impacts drawn at the top). Shaded: the bisected ranges of each claim; the dashed lines bound
the directly solved T_c = 2T orbit's stability range; the stated and located cases are
marked.

Deviations: a scan the paper does not have; the grid and the window come from the config's
``verdict`` section.
"""

import numpy as np

from impactdamper.reporting.records import read_csv, read_json, run_stage
from impactdamper.reporting.figures import label_above
from impactdamper.reporting.plotting import figure_size, finish_figure, use_style
from impactdamper.studies.vocabulary import SPEC


RANGE_COLOR = "#f4cccc"
# Top of the bottom panel's scale: chatter cycles with dozens of impacts are drawn as ^ there.
Y_MAX = 8


def main(scan_csv, scan_json, out_pdf, out_png) -> None:
    plt = use_style()
    rows = read_csv(scan_csv)
    scan = read_json(scan_json)
    g = np.array([float(r["gap"]) for r in rows])
    min_gap = np.array([float(r["alg1_min_gap"]) if r["alg1_min_gap"] else np.nan for r in rows])
    k = np.array([int(r["alg2_period_multiple"]) for r in rows])
    n = np.array([int(r["alg2_impacts_per_cycle"]) if r["alg2_period_multiple"] != "0" else 0 for r in rows])
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=figure_size(3.8))
    for r in scan["claim_a_ranges"]:
        ax1.axvspan(r["lo"], r["hi"], color=RANGE_COLOR, lw=0)
    for r in scan["claim_b_ranges"]:
        ax2.axvspan(r["lo"], r["hi"], color=RANGE_COLOR, lw=0)
    ax1.axhline(0.0, color="0.2", lw=0.6)
    ax1.plot(g, min_gap, ".", ms=3, label="Algorithm No. 1: smallest\ninterior gap (none: no marker)")
    ax1.set_ylabel("min $\\Delta/x_{\\mathrm{st}}$")
    ax2.plot(g, k, "o", ms=3, mfc="none", label="$T_c/T$ (0: not settled)")
    ax2.plot(g[n <= Y_MAX], n[n <= Y_MAX], ".", ms=3, label="impacts per cycle")
    off = n > Y_MAX
    if off.any():
        ax2.plot(g[off], np.full(off.sum(), Y_MAX + 0.2), "^", ms=3, color="C1", label=f"more than {Y_MAX} impacts")
    ax2.set_ylabel("Algorithm No. 2")
    ax2.set_xlabel(SPEC["gap"].label)
    orbit = scan.get("orbit_range", {})
    lo, hi = scan["window"]["gap_min"], scan["window"]["gap_max"]
    marks = [
        (gap, name)
        for gap, name in ((scan["stated_gap"], "stated"), (scan["located"]["gap"], "located"))
        if lo <= gap <= hi
    ]  # a case outside the scanned window is not drawn
    for axis in (ax1, ax2):
        for key in ("lo", "hi"):
            if orbit.get("found") and not orbit.get(key + "_open", True):
                axis.axvline(orbit[key], color="C3", lw=0.7, ls="--")
        for gap, _name in marks:
            axis.axvline(gap, color="0.3", lw=0.7, ls=":")
    for gap, name in marks:
        label_above(ax1, gap, f"{name}\n{gap:g}")
    ax1.plot([], [], color=RANGE_COLOR, lw=6, label="claim (a): gap negative")
    ax2.plot([], [], color=RANGE_COLOR, lw=6, label="claim (b): $T_c = 2T$, 3 impacts")
    if orbit.get("found"):
        ax2.plot([], [], color="C3", lw=0.7, ls="--", label="stable $2T$ orbit (direct solve)")
    ax1.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax2.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax2.set_ylim(-0.5, Y_MAX + 0.6)
    ax1.set_xlim(lo, hi)
    fig.suptitle("Where the paper's Fig. 2 behaviour occurs (other parameters as stated)", y=1.02)
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.csv input.json output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
