"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in
the paper): the work-precision diagram.

Caption: "CPU time against error on the reference case (theta = 1, mu = 0.08, N = 0.5,
delta1 = delta2 = 0.05, R = 0.7, Delta0/x_st = -5.8). Left: the first impacts from
Algorithm No. 2's start (error: impact times, units of T). Right: ten periods on the settled
cycle (error: impact times and final state). Errors against a 40-digit mpmath reference.
Made by workflow/scripts/fig_work_precision.py."

Thin: reads figures/work_precision.csv (made by work_precision.py), plots with the shared
style. Runs that found the wrong number of impacts are left out (counted in the table).
Timings are CPU time on the machine that ran the workflow: the figure is not pixel-stable
across runs.
"""

import math

from impactdamper.reporting.plotting import ANNOTATION_SIZE, TEXT_WIDTH, figure_size, finish_figure, use_style
from impactdamper.reporting.records import read_csv, read_json, run_stage
from impactdamper.studies.performance.methods import METHODS


PANELS = (("first_impacts", "first impacts"), ("settled_cycle", "settled cycle"))
# Each panel's error and its unit: the impact times' in units of T; on the settled cycle the
# larger of that and the final state's, relative to x_st and x_st omega.
ERROR_LABELS = {
    "first_impacts": "error of the impact times ($T$)",
    "settled_cycle": "error of impact times ($T$) and state (rel.)",
}
# One colour, marker and line per method (:data:`impactdamper.studies.performance.methods.METHODS`, whose
# order is the legend's and whose plot labels name the lines), the same in both panels; a method
# without an entry here is drawn in DEFAULT_STYLE.
STYLE = {
    "exact": ("#1f4e79", "o", "-"),
    "alg1": ("#000000", "*", "none"),
    "RK45": ("#c0392b", "v", "--"),
    "DOP853": ("#2e8b57", "^", "--"),
    "Radau": ("#e67e22", "<", "--"),
    "LSODA": ("#7d3c98", ">", "--"),
    "RK4": ("#7f8c8d", "s", ":"),
    "Moreau-Jean": ("#b7950b", "D", ":"),
}
DEFAULT_STYLE = ("0.4", "x", "-.")
# Error axis: from order one down to below double precision's floor.
ERROR_LIMITS = (3.0, 1e-15)


def load(path) -> list[dict]:
    rows = read_csv(path)
    for r in rows:
        for k in ("value", "cpu_seconds", "error"):
            r[k] = float(r[k]) if r[k] not in ("", "nan") else math.nan
    return rows


def _fineness(r: dict) -> float:
    """Tolerances get finer as they fall, step counts as they grow."""
    v = r["value"]
    if not math.isfinite(v):
        return 0.0
    return v if METHODS[r["family"]].finer_when_larger else -v


def main(in_csv, out_stem, targets=(1e-6, 1e-10), siconos_available: bool | None = None) -> None:
    plt = use_style()
    rows = load(in_csv)
    fig, axes = plt.subplots(1, 2, figsize=figure_size(0.5 * TEXT_WIDTH), sharey=True, layout="constrained")
    for ax, (case, title) in zip(axes, PANELS):
        for fam, method in METHODS.items():
            label, (color, marker, ls) = method.plot_label, STYLE.get(fam, DEFAULT_STYLE)
            # In the order of the method's own setting, from coarse to fine.
            pts = sorted(
                (_fineness(r), r["error"], r["cpu_seconds"])
                for r in rows
                if r["case"] == case
                and r["family"] == fam
                and math.isfinite(r["error"])
                and math.isfinite(r["cpu_seconds"])
            )
            if not pts:
                continue
            _, xs, ys = zip(*pts)
            ax.plot(
                [max(x, ERROR_LIMITS[1]) for x in xs],
                ys,
                color=color,
                marker=marker,
                linestyle=ls,
                label=label,
                markersize=3.5,
                linewidth=0.8,
            )
        for t in targets:
            ax.axvline(t, color="0.7", linewidth=0.6, zorder=0)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(*ERROR_LIMITS)
        ax.set_title(title)
        ax.set_xlabel(ERROR_LABELS[case])
    axes[0].set_ylabel("CPU time per run (s)")
    labels = {}
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            labels.setdefault(lab, h)
    order = [m.plot_label for m in METHODS.values() if m.plot_label in labels]
    if siconos_available is False:
        axes[1].text(
            0.98, 0.02, "Siconos not available", transform=axes[1].transAxes, fontsize=ANNOTATION_SIZE, ha="right"
        )
    fig.legend([labels[k] for k in order], order, loc="outside lower center", ncols=4, fontsize="small")
    finish_figure(fig, out_stem)


JOB = (
    "input.csv",
    lambda j: str(j.output.pdf).removesuffix(".pdf"),
    lambda j: tuple(j.params.performance["targets"]),
    lambda j: bool(read_json(j.input.json)["siconos"]["available"]),
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
