"""Extends Fig. 2 of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: where the
behaviour the paper reports occurs over two parameters at once (config ``claims_search.map``,
default the restitution R against the gap Delta0/x_st), the others as stated.

The paper: "the gap Delta takes on negative values when t in (t1, t2)" (Algorithm No. 1, the
paper's Fig. 2a) and "T_c = 2T and during this period T_c there are three collisions"
(Algorithm No. 2 from its step 1, the paper's Fig. 2b). Colour per cell: neither claim, (a)
only, (b) only, both; dots: the points the adaptive refinement added where a cell's corners
differ in label or do not settle (``figures/claims_map_refined.csv``, same colours). Star: the
stated point; diamond: the located case (stated R).

Deviation: a map the paper does not have; each cell is Algorithm No. 2 from the paper's step
1 (no continuation from a neighbour), as in the verdict.
"""

from matplotlib.patches import Patch

from impactdamper.reporting.figures import CLAIM_CLASSES, class_image, class_points, claim_grid
from impactdamper.reporting.records import read_csv, read_json, run_stage
from impactdamper.reporting.plotting import figure_size, finish_figure, use_style
from impactdamper.studies.vocabulary import SPEC


def main(map_csv, settings_json, located_json, out_pdf, out_png, refined_csv=None) -> None:
    plt = use_style()
    rows = read_csv(map_csv)
    settings = read_json(settings_json)
    m, ref = settings["map"], settings["reference"]
    xs, ys, z = claim_grid(rows)
    fig, ax = plt.subplots(figsize=figure_size(3.6))
    dx, dy = (xs[1] - xs[0]) / 2, (ys[1] - ys[0]) / 2
    class_image(ax, xs, ys, z)
    extra = read_csv(refined_csv) if refined_csv else []
    if extra:
        class_points(ax, extra, 2)
    ax.plot([ref[m["x"]]], [ref[m["y"]]], "*", ms=11, mec="k", mfc="w", label="stated point")
    located = read_json(located_json)["located"]["gap"]
    if m["y"] == "gap":
        ax.plot([ref[m["x"]]], [located], "D", ms=6, mec="k", mfc="w", label="located case")
    ax.set_xlabel(SPEC[m["x"]].label)
    ax.set_ylabel(SPEC[m["y"]].label)
    # The grid, as the caption promises: the steps in both parameters.
    levels = int(m.get("refine_levels", 0)) if extra else 0
    ax.set_title(
        (
            f"steps {2 * dx:.3g} in {m['x']} and {2 * dy:.3g} in the gap"
            if m["y"] == "gap"
            else f"steps {2 * dx:.3g} $\\times$ {2 * dy:.3g}"
        )
        + (
            f"\nrefined by {levels} halving{'s' * (levels > 1)} to a floor of "
            f"{2 * dx / 2**levels:.3g} $\\times$ {2 * dy / 2**levels:.3g}"
            if levels
            else ""
        )
    )
    handles = [Patch(color=c, label=name) for name, c in CLAIM_CLASSES] + ax.get_legend_handles_labels()[0]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.csv input.json input.located output.pdf output.png input.refined")  # noqa: F821 (injected by Snakemake's script: directive)
