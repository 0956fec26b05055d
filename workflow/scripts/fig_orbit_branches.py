"""Extends Fig. 2 of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the
branches of periodic orbits of the reference case against the initial gap Delta0/x_st.

The paper's Fig. 2 caption: "Dependence of the relative displacements x1_bar, x2_bar of the
object and the suppressor on time t" (a: Algorithm No. 1, b: Algorithm No. 2), at
Delta0/x_st = -5.8; the prose says Algorithm No. 1's orbit crosses the stop and Algorithm
No. 2 gives "T_c = 2T and ... three collisions". The paper has no continuation; this figure
shows where each of those motions exists, and where it is stable.

Top: max |x1|/x_st of the one-impact orbit (1/1, Algorithm No. 1's), the 2T cycle with three
impacts (3/2, the paper's Fig. 2b motion) and the 3T cycle with four impacts (4/3); solid
where stable and admissible, dashed where admissible but unstable, dotted where inadmissible
(the gap goes negative between impacts: not a motion). Special points: PD period doubling,
NS Neimark-Sacker, fold, G grazing (open: the gap touches the stop between impacts, a new
impact appears; filled: an impact's closing velocity reaches zero and it vanishes); grey
where the orbit is not a motion. Left column ("full range"): every branch over its whole
range, with the window of the right column shaded grey; right column ("zoom near the located
case"): that window, where the multi-impact cycles live. Bottom: the spectral radius max |rho|
of the cycle, rho being its Floquet multipliers (eigenvalues of the monodromy matrix over kT,
saltation matrices included); below the dashed unit line the cycle is stable. The stated case
and the located case (figures/located_case.json) are starred and named along their dotted
verticals (each once: the stated case on the left, the located case on the right).

Deviations: none (the paper has no such figure). Data: figures/orbit_branches.csv and
figures/orbit_special_points.csv (workflow/scripts/orbit_branches.py).
"""

import numpy as np

from impactdamper.reporting.records import cell_float, read_csv, read_json, run_stage
from impactdamper.studies.sweeps.branches import KIND_LEGEND, KIND_MARK, multi_impact_window, run_pieces
from impactdamper.reporting.branch_figure import (
    RADIUS_LIMITS,
    STYLE,
    column_ranges,
    label_point,
    legend_rows,
    mark_case,
    mark_special,
    radius_axis,
)
from impactdamper.reporting.plotting import figure_size, finish_figure, legend_in_rows, use_style
from impactdamper.studies.vocabulary import SPEC


# The zoom window (right column), Delta0/x_st: the multi-impact branches with some margin.
ZOOM_MARGIN = 0.25
FULL_RANGE_MARGIN = 0.8  # the left column's, either side of the branches' gaps
# Label offsets (points) of the special points, by (branch, kind) or, where one branch has two
# points of a kind, (branch, kind, leg), so that labels where branches meet do not overlap and
# each label sits beside its own marker; default above the marker.
LABEL_OFFSET = {
    # The one-impact branch's period doubling (triangle) just below its grazing at first contact
    # (filled circle): the doubling's label to the left of its marker, the grazing's above its own.
    ("single", "period_doubling", "up"): (-5, -1),
    ("single", "grazing_velocity", "up"): (0, 6),
    ("single", "grazing_interior"): (-4, 6),
    ("double", "grazing_velocity"): (0, -11),
    ("triple", "grazing_velocity"): (4, -11),
    ("triple", "period_doubling"): (0, 6),
    ("triple", "fold"): (0, -9),
    ("double", "period_doubling"): (7, -6),
    ("double", "neimark_sacker"): (0, -12),
    ("triple", "grazing_interior"): (-5, 5),
    ("double", "grazing_interior"): (0, 6),
    ("single", "fold"): (6, 0),
    ("single", "grazing_velocity"): (0, -11),
}


def main(branches_csv, special_csv, summary_json, out_pdf, out_png) -> None:
    plt = use_style()
    rows, special, summary = read_csv(branches_csv), read_csv(special_csv), read_json(summary_json)
    names = list(dict.fromkeys(r["branch"] for r in rows))  # the config's order
    color = {n: f"C{i}" for i, n in enumerate(names)}
    by = {n: [r for r in rows if r["branch"] == n] for n in names}
    sp = {n: [s for s in special if s["branch"] == n] for n in names}
    zoom = multi_impact_window(rows, special, summary, ZOOM_MARGIN)

    fig, axes = plt.subplots(
        2,
        2,
        figsize=figure_size(5.3),
        sharex="col",
        layout="constrained",
        gridspec_kw={"width_ratios": [1.0, 1.55], "height_ratios": [1.5, 1.0]},
    )
    labelled = (set(), set())
    for col, (ax_x, ax_r) in enumerate(zip(axes[0], axes[1])):
        for n in names:
            for key, ax in (("x1_max", ax_x), ("spectral_radius", ax_r)):
                for state, g, y in run_pieces(by[n], sp[n], key):
                    ax.plot(
                        g,
                        np.clip(y, *RADIUS_LIMITS) if key == "spectral_radius" else y,
                        STYLE[state],
                        color=color[n],
                        lw=1.1 if state == "stable" else 0.9,
                    )
            for s in sp[n]:
                on = s["admissible"] == "1"
                g = cell_float(s["gap"])
                mark_special(
                    ax_x,
                    ax_r,
                    g,
                    cell_float(s["x1_max"]),
                    cell_float(s["spectral_radius"]),
                    s["kind"],
                    color[n],
                    on,
                    4.5 if col else 3.5,
                )
                inside = zoom[0] <= g <= zoom[1]
                if (col == 1 and inside) or (col == 0 and not inside):
                    where = (round(g, 6), round(cell_float(s["x1_max"]), 4))
                    if where in labelled[col]:
                        continue  # branches meeting at one point: one label
                    labelled[col].add(where)
                    offset = LABEL_OFFSET.get((n, s["kind"], s["leg"]), LABEL_OFFSET.get((n, s["kind"]), (0, 6)))
                    label_point(ax_x, KIND_MARK[s["kind"]], (g, cell_float(s["x1_max"])), offset, on)
        radius_axis(ax_r, SPEC["gap"].label)
        # The cases.
        for case in ("stated", "located"):
            c = summary["cases"][case]
            g = float(c["gap"])
            lim = ax_x.get_xlim() if col == 0 else zoom
            if not lim[0] <= g <= lim[1]:
                continue
            named = col == 1 or not zoom[0] <= g <= zoom[1]  # each case named once, along its vertical
            mark_case(ax_x, ax_r, g, c["x1_max"], c["multipliers"][0], f"{case} case {g:g}" if named else None)
    gaps, x1_max = [cell_float(r["gap"]) for r in rows], [cell_float(r["x1_max"]) for r in rows]
    column_ranges(axes, gaps, x1_max, zoom, FULL_RANGE_MARGIN)
    axes[0, 0].set_ylabel("max $|x_1|/x_{\\mathrm{st}}$")
    axes[1, 0].set_ylabel("spectral radius $\\max|\\rho|$")
    axes[0, 0].set_title("full range", loc="left")
    axes[0, 1].set_title("zoom near the located case (grey window on the left)", loc="left")
    # Legend in rows (branches and line styles; special points and the case; the shading and
    # the unit line), written row by row although matplotlib fills a legend column by column.
    rows = legend_rows([(color[n], summary["branches"][n]["label"]) for n in names], KIND_LEGEND)
    legend_in_rows(
        fig, rows, loc="outside lower center", handlelength=1.8, columnspacing=0.9, handletextpad=0.4, fontsize="small"
    )
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.branches input.special input.summary output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
