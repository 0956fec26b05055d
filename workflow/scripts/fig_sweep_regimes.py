"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the regimes along the
gap sweep, as bands labelled with Peterka's z/k.

The paper's introduction names three regimes for a negative gap (moving together, several
impacts per period, one impact per period); this figure shows every one the sweep meets. Rows:
the upward and downward sweeps, then each random initial state; colour: the regime class;
text: the label z/k (z impacts in k forcing periods; S persistent contact, c/k chatter with
contact phases, 0/1 no contact, np nonperiodic) on bands wide enough to hold it. Lower panel:
the two sweeps again, zoomed on the bands between chatter and the one-impact motion.
"""

import numpy as np
from matplotlib.patches import Patch

import sweepstage as st
from impactdamper.plotting import TEXT_WIDTH, save_figure, use_style

# A band's label is written if the band is at least this share of the axis' range wide and
# its centre is at least twice that from the previous label's in the same row.
MIN_LABEL_SHARE = 0.012
SHORT = {"stuck": "S", "np": "np"}
# The zoom of the lower panel: the bands between chatter and the one-impact motion.
ZOOM = (-21.5, -7.5)


def _bands(ax, y, values, labels, step, span):
    last = -np.inf
    for lab, a, b, _ in st.runs(values, labels):
        ax.barh(y, b - a + step, left=a - step / 2, height=0.8, color=st.REGIME_COLORS[st.regime_of_label(lab)],
                lw=0)
        centre = 0.5 * (a + b)
        if b - a + step >= MIN_LABEL_SHARE * span and centre - last >= 2 * MIN_LABEL_SHARE * span \
                and ax.get_xlim()[0] <= centre <= ax.get_xlim()[1]:
            ax.text(centre, y, SHORT.get(lab, lab), ha="center", va="center", fontsize=5.5, clip_on=True,
                    color="white" if st.regime_of_label(lab) in ("stuck", "chatter", "single_impact", "nonperiodic") else "k")
            last = centre


def _panel(ax, rows, rnd, xlim, with_random: bool):
    ax.set_xlim(*xlim)
    span = xlim[1] - xlim[0]
    names = []
    for y, direction in enumerate(("up", "down")):
        rs = [r for r in rows if r["direction"] == direction]
        values = np.array([float(r["value"]) for r in rs])
        step = float(np.median(np.diff(values)))
        _bands(ax, -y, values, [r["label"] for r in rs], step, span)
        names.append("upward" if direction == "up" else "downward")
    if with_random:
        for j in sorted({int(r["start_index"]) for r in rnd}):
            rs = sorted((r for r in rnd if int(r["start_index"]) == j), key=lambda r: float(r["value"]))
            values = np.array([float(r["value"]) for r in rs])
            step = float(np.median(np.diff(values))) if len(values) > 1 else 0.1
            _bands(ax, -len(names), values, [r["label"] for r in rs], step, span)
            names.append(f"random {j + 1}")
    ax.set_yticks(-np.arange(len(names)), names)
    ax.grid(False)


def main(sweep_csv, random_csv, out_pdf, out_png) -> None:
    plt = use_style()
    rows = st.read_csv(sweep_csv)
    rnd = st.read_csv(random_csv)
    values = [float(r["value"]) for r in rows]
    n_random = len({r["start_index"] for r in rnd})
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(TEXT_WIDTH, 2.2 + 0.28 * n_random + 1.0),
                                      gridspec_kw={"height_ratios": [2 + n_random, 2], "hspace": 0.5})
    _panel(top, rows, rnd, (min(values), max(values)), True)
    _panel(bottom, rows, rnd, ZOOM, False)
    bottom.set_title(f"zoom: $\\Delta_0/x_{{st}}$ in [{ZOOM[0]:g}, {ZOOM[1]:g}]", fontsize=8)
    bottom.set_xlabel("initial gap $\\Delta_0/x_{st}$")
    present = {st.regime_of_label(r["label"]) for r in rows + rnd}
    bottom.legend(handles=[Patch(facecolor=c, edgecolor="0.5", lw=0.4, label=st.REGIME_NAMES[k])
                           for k, c in st.REGIME_COLORS.items() if k in present],
                  loc="upper center", bbox_to_anchor=(0.5, -0.45), ncol=3, fontsize=7)
    save_figure(fig, out_pdf, formats=("pdf",))
    save_figure(fig, out_png, formats=("png",))
    plt.close(fig)


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    import sys

    sys.stderr = open(sm.log[0], "w")
    main(sm.input.sweep, sm.input.random, sm.output.pdf, sm.output.png)
