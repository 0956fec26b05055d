"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the regimes along the
gap sweep, as bands labelled with Peterka's z/k.

The paper's introduction names three regimes for a negative gap (moving together, several
impacts per period, one impact per period); this figure shows every one the sweep meets. Rows:
the upward and downward sweeps, then each random initial state; colour: the regime class;
text: the label z/k (z impacts in k forcing periods; S persistent contact, c/k chatter with
contact phases, 0/1 no contact, np not settled within the sweep's cap of periods) on every
band wide enough to hold it at print size (turned upright on narrow bands); a thin line
parts neighbouring bands of one colour. Lower panels: the two sweeps again, zoomed (windows
outlined in the top panel) on the periodic windows inside the long nonperiodic band (zoom a,
the full width), on the bands around the located case (b) and on the end of the one-impact
motion near first contact (c).

Deviations: none (the paper has no such figure).
"""

import numpy as np
from matplotlib.patches import Patch, Rectangle

from impactdamper.studies.sweeps import gapsweep as gs
from impactdamper.reporting.plotting import REGIME_COLORS, REGIME_NAMES
from impactdamper.reporting.records import read_csv, run_stage
from impactdamper.reporting.plotting import ANNOTATION_SIZE, figure_size, finish_figure, label_bands, use_style
from impactdamper.studies.vocabulary import SPEC


SHORT = {"stuck": "S", "np": "np"}
# The zooms of the lower panels (Delta0/x_st): the periodic windows inside the long
# nonperiodic band (3/1, and 2/1 doubling to 4/2), those around the located case up to the
# one-impact motion, and the end of the one-impact motion near first contact (U1/x_st = 11.33
# in the reference case). Zoom a takes a row of its own, the full width, so that the narrow 3/1
# band holds its label; zooms b and c share the next row, in these widths.
ZOOMS = ((-18.0, -13.1), (-10.4, -7.9), (9.9, 11.7))
ZOOM_WIDTHS = (1.35, 1.0)
# Height of a row's band, as a share of the row pitch.
BAND_HEIGHT = 0.8


def _bands(ax, y, values, labels, step):
    """Draw one row's bands; return the (centre, band width, label) of each, in order."""
    out = []
    for lab, a, b, _ in gs.runs(values, labels):
        regime = gs.regime_of_label(lab)
        ax.barh(y, b - a + step, left=a - step / 2, height=BAND_HEIGHT, color=REGIME_COLORS[regime], lw=0)
        if out and gs.regime_of_label(out[-1][2]) == regime:  # same colour: a thin parting line
            ax.plot([a - step / 2] * 2, [y - BAND_HEIGHT / 2, y + BAND_HEIGHT / 2], color="0.25", lw=0.5)
        out.append((0.5 * (a + b), b - a + step, lab))
    return out


def _panel(ax, rows, rnd, xlim, with_random: bool):
    ax.set_xlim(*xlim)
    names, drawn = [], []
    for y, direction in enumerate(("up", "down")):
        rs = [r for r in rows if r["direction"] == direction]
        values = np.array([float(r["value"]) for r in rs])
        step = float(np.median(np.diff(values)))
        drawn.append((-y, _bands(ax, -y, values, [r["label"] for r in rs], step)))
        names.append("upward" if direction == "up" else "downward")
    if with_random:
        for j in sorted({int(r["start_index"]) for r in rnd}):
            rs = sorted((r for r in rnd if int(r["start_index"]) == j), key=lambda r: float(r["value"]))
            values = np.array([float(r["value"]) for r in rs])
            step = float(np.median(np.diff(values))) if len(values) > 1 else 0.1
            drawn.append((-len(names), _bands(ax, -len(names), values, [r["label"] for r in rs], step)))
            names.append(f"random {j + 1}")
    ax.set_yticks(-np.arange(len(names)), names)
    ax.set_ylim(-len(names) + 0.5, 0.5)
    ax.tick_params(axis="y", length=0)
    ax.grid(False)
    return drawn


def main(sweep_csv, random_csv, out_pdf, out_png) -> None:
    plt = use_style()
    rows = read_csv(sweep_csv)
    rnd = read_csv(random_csv)
    values = [float(r["value"]) for r in rows]
    n_random = len({r["start_index"] for r in rnd})
    fig = plt.figure(figsize=figure_size(1.2 + 0.3 * (2 + n_random) + 2 * (0.45 * 2 + 0.5)), layout="constrained")
    grid = fig.add_gridspec(3, 2, height_ratios=[2 + n_random, 3, 3], width_ratios=ZOOM_WIDTHS)
    top = fig.add_subplot(grid[0, :])
    zooms = [fig.add_subplot(grid[1, :]), fig.add_subplot(grid[2, 0]), fig.add_subplot(grid[2, 1])]
    drawn = [(top, _panel(top, rows, rnd, (min(values), max(values)), True))]
    top.set_title("whole sweep", loc="left")
    for i, (ax, window) in enumerate(zip(zooms, ZOOMS)):
        drawn.append((ax, _panel(ax, rows, rnd, window, False)))
        ax.set_title(f"zoom {'abc'[i]}", loc="left")
        ax.set_xlabel(SPEC["gap"].long_label)
        if i == 2:
            ax.set_yticklabels([])
        # The window, outlined and named in the top panel.
        top.add_patch(
            Rectangle(
                (window[0], -1.5 - n_random + 0.02),
                window[1] - window[0],
                2 + n_random - 0.04,
                fill=False,
                ec="k",
                lw=0.8,
                zorder=5,
            )
        )
        top.annotate(
            f"zoom {'abc'[i]}",
            (0.5 * sum(window), 0.5),
            xytext=(0, 1),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=ANNOTATION_SIZE,
        )
    top.set_xlabel(SPEC["gap"].long_label)
    present = {gs.regime_of_label(r["label"]) for r in rows + rnd}
    fig.legend(
        handles=[
            Patch(facecolor=c, edgecolor="0.4", lw=0.5, label=REGIME_NAMES[k])
            for k, c in REGIME_COLORS.items()
            if k in present
        ],
        loc="outside lower center",
        ncol=3,
    )
    # Labels are fitted to their bands once the layout is final.
    fig.canvas.draw()
    fig.set_layout_engine("none")
    renderer = fig.canvas.get_renderer()
    for ax, rows_drawn in drawn:
        for y, bands in rows_drawn:
            label_bands(ax, y, bands, renderer, gs.regime_of_label, BAND_HEIGHT, SHORT)
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.sweep input.random output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
