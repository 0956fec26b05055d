"""Extends Fig. 2 of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: where the
behaviour the paper reports occurs over the pairs of parameters a reader asks about first,
(theta, N), (theta, Delta0/x_st), (N, Delta0/x_st) and (R, Delta0/x_st), the others as stated.

The paper: "the gap Delta takes on negative values when t in (t1, t2)" (Algorithm No. 1, the
paper's Fig. 2a) and "T_c = 2T and during this period T_c there are three collisions"
(Algorithm No. 2 from its step 1, the paper's Fig. 2b). Colour per cell: neither claim, (a)
only, (b) only, both; dots: the points the adaptive refinement added where a cell's corners
differ in label or do not settle (same colours, ``..._refined.csv``); star: the stated point;
diamond, in the maps over the gap: the located case (figures/located_case.json).
Each panel's title states its grid steps, the refinement's halvings and its floor.

Deviation: maps the paper does not have; each cell is Algorithm No. 2 from the paper's step 1
(no continuation from a neighbour), a cell not settled within the map's period cap counted as
nonperiodic. Data: ``figures/claims_map.csv`` and ``figures/claims_map_{name}.csv`` with their
settings JSON.
"""

from matplotlib.patches import Patch

from impactdamper.reporting.figures import CLAIM_CLASSES, class_image, class_points, claim_grid
from impactdamper.reporting.records import read_csv, read_json, run_stage
from impactdamper.reporting.plotting import figure_size, finish_figure, use_style
from impactdamper.studies.vocabulary import tex


def main(csvs, jsons, out_pdf, out_png, refined_csvs=None, located_json=None) -> None:
    plt = use_style()
    fig, axes = plt.subplots(2, 2, figsize=figure_size(5.4))
    order = sorted(range(len(csvs)), key=lambda i: read_json(jsons[i])["name"] != "theta_N")
    located = read_json(located_json)["located"]["gap"] if located_json else None
    for ax, i in zip(axes.flat, order):
        rows, settings = read_csv(csvs[i]), read_json(jsons[i])
        extra = read_csv(refined_csvs[i]) if refined_csvs else []
        m, ref = settings["map"], settings["reference"]
        xs, ys, z = claim_grid(rows)
        dx, dy = (xs[1] - xs[0]) / 2, (ys[1] - ys[0]) / 2
        class_image(ax, xs, ys, z)
        if extra:
            class_points(ax, extra, 1.5)
        ax.plot([ref[m["x"]]], [ref[m["y"]]], "*", ms=9, mec="k", mfc="w")
        if located is not None and m["y"] == "gap":
            # The located case: the stated parameters but a deeper gap.
            ax.plot([ref[m["x"]]], [located], "D", ms=5, mec="k", mfc="w")
        ax.set_xlabel(tex(m["x"]), labelpad=1)
        ax.set_ylabel(tex(m["y"]), labelpad=1)
        levels = int(m.get("refine_levels", 0)) if extra else 0
        refined = (
            f"\nfloor {2 * dx / 2**levels:.3g} $\\times$ {2 * dy / 2**levels:.3g} ({levels} halving{'s' * (levels > 1)}, "
            f"+{len(extra)} points)"
            if levels
            else ""
        )
        ax.set_title(
            f"steps {2 * dx:.3g} $\\times$ {2 * dy:.3g}; {int((z == 3).sum())} of {z.size} cells both{refined}",
            fontsize="small",
        )
    handles = [Patch(color=c, label=name) for name, c in CLAIM_CLASSES]
    handles.append(plt.Line2D([], [], ls="", marker="*", ms=9, mec="k", mfc="w", label="stated point"))
    if located is not None:
        handles.append(plt.Line2D([], [], ls="", marker="D", ms=5, mec="k", mfc="w", label="located case"))
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize="small", bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0, 0.08, 1, 1), h_pad=0.8)
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(
        snakemake,  # noqa: F821 (injected by Snakemake's script: directive)
        main,
        "input.csv:list input.json:list output.pdf output.png input.refined:list input.located",
    )
