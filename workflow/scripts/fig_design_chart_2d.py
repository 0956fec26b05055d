"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the design chart against a
second parameter (N or R, config ``design.second``) of the paper's suppressor: the worst
branch's peak over the band of max|x1|/x_st against Delta0/x_st, one curve per value, each
curve's best gap of the grid marked; the optimal linear TMD of the same mu as a horizontal
line.

Deviations: none (the paper has no such figure).
"""

from impactdamper.reporting.plotting import figure_size, finish_figure, use_style
from impactdamper.reporting.records import cell_float, read_csv, read_json, run_stage
from impactdamper.studies.vocabulary import GAP_AXIS_LABEL, SPEC


def main(chart_csv, chart_json, baselines_json, out_pdf, out_png) -> None:
    plt = use_style()
    rows = read_csv(chart_csv)
    info = read_json(chart_json)
    base = read_json(baselines_json)
    name = info["parameter"]
    symbol = SPEC[name].symbol
    fig, ax = plt.subplots(figsize=figure_size(2.9), layout="constrained")
    values = sorted({float(r["value"]) for r in rows})
    for i, v in enumerate(values):
        rs = [r for r in rows if float(r["value"]) == v]
        ax.plot(
            [float(r["gap"]) for r in rs],
            [cell_float(r["peak_max_abs_x1"]) for r in rs],
            color=f"C{i}",
            lw=1.0,
            label=f"${symbol} = {v:g}$",
        )
        b = next(b for b in info["best"] if b["second"] == v and b["criterion"] == "peak")
        ax.plot([b["gap"]], [b["value"]], "o", color=f"C{i}", ms=4)
    tmd = base["tmd"]["peak"]["peak"]
    ax.axhline(tmd, color="0.3", ls="--", lw=0.8, label=f"optimal TMD ({tmd:.2f})")
    ax.set_xlabel(GAP_AXIS_LABEL)
    ax.set_ylabel("peak $\\max|x_1|/x_{\\mathrm{st}}$ over the band")
    ax.set_ylim(0.0, None)
    ax.legend(fontsize="small", ncol=3, loc="lower left")
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.chart input.best input.baselines output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
