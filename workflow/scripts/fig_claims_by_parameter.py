"""Extends Fig. 2 of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: where, along
each other parameter, the behaviour the paper reports at Delta0/x_st = -5.8 occurs.

The paper: "the gap Delta takes on negative values when t in (t1, t2)" (Algorithm No. 1, the
paper's Fig. 2a) and "T_c = 2T and during this period T_c there are three collisions"
(Algorithm No. 2, the paper's Fig. 2b).

One panel per parameter (theta, mu, N, delta1, delta2, R), varied alone at the stated gap with
the others as stated: bars where claim (a), claim (b) and both hold (ends bisected,
``claims_search.rel_tol``); dotted line: the stated value; diamond: the nearest value where
both hold. Each axis label states Algorithm No. 2's grid step and the floor its adaptive
refinement reached down to. Data: ``figures/claims_by_parameter.csv`` and its settings JSON.

Deviation: a search the paper does not have.
"""

from impactdamper.reporting.records import read_csv, read_json, run_stage
from impactdamper.reporting.plotting import figure_size, finish_figure, use_style
from impactdamper.studies.vocabulary import SPEC


LANES = (
    ("a", "claim (a): gap negative (Alg. No. 1)", "#e67e22"),
    ("b", "claim (b): $T_c = 2T$, 3 impacts (Alg. No. 2)", "#1f4e79"),
    ("both", "both", "#c0392b"),
)


def main(csv_path, settings_json, out_pdf, out_png) -> None:
    plt = use_style()
    rows = read_csv(csv_path)
    settings = read_json(settings_json)
    names = list(settings["parameters"])  # the searched parameters, in the record's order
    fig, axes = plt.subplots(len(names), 1, figsize=figure_size(6.6))
    for ax, name in zip(axes, names):
        d = settings["parameters"][name]
        lo, hi = d["range"]["start"], d["range"]["stop"]
        for lane, (claim, label, color) in enumerate(LANES):
            spans = [
                (float(r["lo"]), float(r["hi"]) - float(r["lo"]))
                for r in rows
                if r["parameter"] == name and r["claim"] == claim
            ]
            # A very narrow interval is still drawn at least 0.4 % of the axis wide.
            spans = [(x, max(w, 0.004 * (hi - lo))) for x, w in spans]
            ax.broken_barh(spans, (2 - lane - 0.35, 0.7), color=color, label=label if name == names[0] else None)
        near = d["nearest_both"]
        ax.axvline(near["stated"], color="0.2", lw=0.8, ls=":")
        if near["nearest"] is not None:
            ax.plot(
                [near["nearest"]],
                [0],
                "D",
                ms=4,
                color="k",
                zorder=5,
                label="nearest value where both hold" if name == names[0] else None,
            )
        ax.set_xlim(lo, hi)
        ax.set_ylim(-0.6, 2.6)
        ax.set_yticks([2, 1, 0], ["(a)", "(b)", "both"])
        ax.grid(axis="y", visible=False)
        ref = d.get("refinement")
        steps = f"  (Alg. No. 2 step {ref['step']:.3g}, refined to {ref['floor']:.2g})" if ref else ""
        ax.set_xlabel(SPEC[name].label + steps, labelpad=1)
        ax.tick_params(axis="y", length=0)
    axes[0].plot([], [], color="0.2", lw=0.8, ls=":", label="stated value")
    axes[0].legend(loc="lower left", bbox_to_anchor=(0.0, 1.02), ncol=3, fontsize="small")
    fig.tight_layout(h_pad=0.6)
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.csv input.json output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
