"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in
the paper): the exact solver's cost growth.

Caption: "Cost of Algorithm No. 2 with the exact flow from its default start. Left: CPU time
against the simulated span. Right: CPU time per impact against the number of impacts, for
Delta0/x_st = -5.8 (reference case), -10 and -13 (chatter). Made by
workflow/scripts/fig_cost_growth.py."

Thin: reads figures/cost_growth.csv (made by cost_growth.py), plots with the shared style.
Timings are CPU time on the machine that ran the workflow: not pixel-stable across runs.
"""

from impactdamper.reporting.plotting import TEXT_WIDTH, figure_size, finish_figure, use_style
from impactdamper.reporting.records import read_csv, run_stage
from impactdamper.studies.vocabulary import SPEC


MARKERS = ("o", "s", "^", "v", "D")


def load(path) -> list[dict]:
    return [{k: float(v) for k, v in r.items()} for r in read_csv(path)]


def main(in_csv, out_stem) -> None:
    plt = use_style()
    rows = load(in_csv)
    gaps = sorted({r["gap"] for r in rows}, reverse=True)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=figure_size(0.4 * TEXT_WIDTH), layout="constrained")
    for gap, marker in zip(gaps, MARKERS):
        rs = sorted((r for r in rows if r["gap"] == gap), key=lambda r: r["periods"])
        label = f"${SPEC['gap'].symbol} = {gap:g}$"
        ax1.plot(
            [r["periods"] for r in rs],
            [r["cpu_seconds"] for r in rs],
            marker=marker,
            markersize=3.5,
            linewidth=0.8,
            label=label,
        )
        ax2.plot(
            [r["impacts"] for r in rs],
            [r["per_impact"] * 1e6 for r in rs],
            marker=marker,
            markersize=3.5,
            linewidth=0.8,
            label=label,
        )
    ax1.set_xscale("log")
    ax1.set_yscale("log")
    ax1.set_xlabel("simulated span (periods $T$)")
    ax1.set_ylabel("CPU time (s)")
    ax2.set_xscale("log")
    ax2.set_xlabel("impacts")
    ax2.set_ylabel(r"CPU time per impact ($\mu$s)")
    ax2.set_ylim(bottom=0)
    ax1.legend(fontsize="small")
    finish_figure(fig, out_stem)


JOB = (
    "input.csv",
    lambda j: str(j.output.pdf).removesuffix(".pdf"),
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
