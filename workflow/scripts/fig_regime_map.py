"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: a regime map,
Peterka-style: the initial gap Delta0/x_st against theta = omega/omega1 (map ``theta``) or
against the damping ratio delta = delta1 = delta2 (map ``damping``).

Each row is a one-way sweep of the gap (cell from cell, see ``maps.direction``); colour: the
regime class of the settled motion, with Peterka's z/k written on the larger regions (np: no
period k <= 8 settled within the map's cap of periods per cell). Lines (closed form,
``map_curves``): the lift-off threshold of the persistent contact (dashed cyan) and the first
contact of the free forced response U1/x_st (dashed black). Thin lines (``boundaries``):
every other boundary continued in two parameters, by kind (fold, period doubling,
Neimark-Sacker: solid; an impact lost or gained: dotted). The ends of the range where
Algorithm No. 1's orbit is admissible are among them (its gap touching the stop: the 1/1
touch curve; its impact grazing: a zero-velocity curve or the 1/1 fold), so the scan of that
range that ``map_curves`` once drew in white is not drawn twice.
Star: the paper's reference point (Delta0/x_st = -5.8, theta = 1, delta = 0.05); diamond:
the located case of the replication verdict. Legend below the map, so that the figure is the
report's text width and no text is under 7 pt in print.

Deviation: the paper shows no map; its introduction describes the sequence along the gap.
"""

import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch

from impactdamper.studies.sweeps import gapsweep as gs
from impactdamper.studies.sweeps.results import read_map
from impactdamper.studies.config import located_gap
from impactdamper.reporting.plotting import REGIME_COLORS, REGIME_NAMES
from impactdamper.reporting.records import read_csv, run_stage
from impactdamper.reporting.figures import outside_legend
from impactdamper.reporting.plotting import figure_size, finish_figure, label_regions, use_style
from impactdamper.studies.vocabulary import SPEC


CLASSES = list(REGIME_COLORS)
AXIS_LABEL = {
    "theta": SPEC["theta"].long_label,
    "damping": f"damping ratios ${SPEC['delta1'].symbol} = {SPEC['delta2'].symbol} = \\delta$",
}
REFERENCE_VALUE = {"theta": "theta", "damping": "delta1"}
# The lift-off line: bright cyan, visible on the dark persistent-contact region and on chatter.
LIFTOFF_COLOR = "#33bbee"
# Height of a map (inches) at the style's width: the two maps and their captions share one page.
MAP_HEIGHT = 3.9
# The continued boundary curves (figures/boundaries_{map}.csv), one colour and style per kind.
CURVE_STYLE = {
    "fold": ("#ee3377", "-", "fold (multiplier +1)"),
    "period_doubling": ("#ee7733", "-", "period doubling (-1)"),
    "neimark_sacker": ("#009988", "-", "Neimark-Sacker"),
    "grazing_velocity": ("#aaaaaa", ":", "impact lost (zero velocity)"),
    "grazing_touch": ("#0077bb", ":", "new impact (gap touches)"),
}


def draw_boundaries(ax, rows: list) -> None:
    """The continued curves, each leg a line, one legend entry per kind present."""
    legs, slow = {}, list(rows[0])[4]  # (columns: curve, cycle, kind, gap, the second parameter, ...)
    for r in rows:
        if r["kind"] in CURVE_STYLE:
            legs.setdefault(r["curve"], (r["kind"], []))[1].append((float(r["gap"]), float(r[slow])))
    seen = set()
    for kind, pts in legs.values():
        color, ls, text = CURVE_STYLE[kind]
        g, y = np.array(pts).T
        ax.plot(g, y, color=color, ls=ls, lw=0.9, zorder=5, label=None if kind in seen else text)
        seen.add(kind)


def main(name: str, reference: dict, map_csv, curves_csv, located_json, out_pdf, out_png, boundaries_csv=None) -> None:
    plt = use_style()
    slow, gaps, labels = read_map(map_csv)
    codes = np.vectorize(lambda s: CLASSES.index(gs.regime_of_label(s)))(labels)
    fig, ax = plt.subplots(figsize=figure_size(MAP_HEIGHT), layout="constrained")
    ax.pcolormesh(
        gaps,
        slow,
        codes,
        cmap=ListedColormap([REGIME_COLORS[c] for c in CLASSES]),
        vmin=-0.5,
        vmax=len(CLASSES) - 0.5,
        shading="nearest",
        rasterized=True,
    )
    label_regions(ax, slow, gaps, labels, gs.regime_of_label)
    curves = read_csv(curves_csv)
    s = np.array([float(r["slow"]) for r in curves])
    ax.plot(
        [float(r["liftoff"]) for r in curves],
        s,
        color=LIFTOFF_COLOR,
        lw=1.2,
        ls="--",
        zorder=4,
        label="lift-off threshold",
    )
    ax.plot(
        [float(r["first_contact"]) for r in curves],
        s,
        color="k",
        lw=1.0,
        ls="--",
        zorder=4,
        label="first contact, $\\Delta_0 = U_1$",
    )
    if boundaries_csv is not None:
        draw_boundaries(ax, read_csv(boundaries_csv))
    ref = float(reference[REFERENCE_VALUE[name]])
    # The two cases: a yellow star at the stated gap, a white diamond at the located one.
    for case, gap, style in (
        ("stated", float(reference["gap"]), {"marker": "*", "ms": 9, "color": "#f1c40f"}),
        ("located", located_gap(located_json), {"marker": "D", "ms": 5, "color": "w"}),
    ):
        label = f"{case} case (${SPEC['gap'].symbol}$ = {gap:g})"
        ax.plot([gap], [ref], **style, mec="k", mew=0.6, ls="none", label=label)
    ax.set_xlim(gaps[0], gaps[-1])
    ax.set_ylim(slow[0], slow[-1])
    ax.set_xlabel(SPEC["gap"].long_label)
    ax.set_ylabel(AXIS_LABEL[name])
    ax.grid(False)
    handles, _ = ax.get_legend_handles_labels()
    present = {CLASSES[c] for c in np.unique(codes)}
    patches = [
        Patch(facecolor=REGIME_COLORS[c], edgecolor="0.4", lw=0.5, label=REGIME_NAMES[c])
        for c in CLASSES
        if c in present
    ]
    # Under the map: the regime colours, then the lines and markers, filled column by column.
    outside_legend(fig, patches + handles, where="lower", ncol=3, handlelength=2.4, columnspacing=1.0)
    finish_figure(fig, out_pdf, out_png)


JOB = "wildcards.map params.reference input.map input.curves input.located output.pdf output.png input.boundaries"

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
