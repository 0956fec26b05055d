"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: amplitude against forcing
frequency of the two optimal devices, the curves the paper's motivation (a varying forcing
frequency) asks for.

Top: max|x1|/x_st of the design table's optimal impact suppressor (optimal for the peak, its
stop within reach; upward sweep solid, downward dashed, its located peak marked) and of the
optimal linear TMD (closed form), beside the bare object and the paper's suppressor at the
design chart's located best gap (thin). Bottom: the optimal impact suppressor's loads, largest
pulse per impact over P0/omega1 and impacts per forcing period, both sweep directions.

Deviations: none (the paper has no such figure).
"""

import numpy as np

from impactdamper.reporting.plotting import figure_size, finish_figure, use_style
from impactdamper.reporting.records import cell_float, read_csv, read_json, run_stage
from impactdamper.analysis.linear_device import LinearDevice
from impactdamper.studies.vocabulary import SPEC


def _curve(rows, role, direction, key):
    d = [r for r in rows if r["role"] == role and r["direction"] == direction]
    return np.array([float(r["theta"]) for r in d]), np.array([cell_float(r[key]) for r in d])


def main(response_csv, response_json, baselines_csv, optimum_json, out_pdf, out_png) -> None:
    plt = use_style()
    rows = read_csv(response_csv)
    base = read_csv(baselines_csv)
    summary = {s["role"]: s for s in read_json(response_json)["responses"]}
    opt = read_json(optimum_json)
    tmd = next(d for d in opt["devices"] if d["device"] == "tmd_peak")
    fig, (ax, ax2) = plt.subplots(
        2, 1, figsize=figure_size(4.6), sharex=True, layout="constrained", gridspec_kw={"height_ratios": [2.2, 1]}
    )
    th = np.array([float(r["theta"]) for r in base])
    ax.plot(th, [float(r["bare"]) for r in base], color="0.3", ls=":", lw=0.9, label="object alone")
    lin = LinearDevice(opt["mu"], tmd["parameters"]["N"], opt["delta1"], tmd["parameters"]["delta2"]).amplitude(th)
    ax.plot(th, lin, color="C3", lw=1.2, label=f"optimal linear TMD (peak {tmd['peak']:.2f})")
    best = summary["best"]
    for direction, ls in (("up", "-"), ("down", "--")):
        t, y = _curve(rows, "best", direction, "max_abs_x1")
        label = f"paper's suppressor, ${SPEC['gap'].symbol} = {best['gap']:.2f}$" if direction == "up" else None
        ax.plot(t, y, color="C2", ls=ls, lw=0.7, label=label)
    s = summary["optimal"]
    for direction, ls in (("up", "-"), ("down", "--")):
        t, y = _curve(rows, "optimal", direction, "max_abs_x1")
        label = f"optimal impact suppressor, sweep {direction}ward" if direction else None
        ax.plot(t, y, color="C0", ls=ls, lw=1.3 if direction == "up" else 1.0, label=label)
    ax.plot([s["peak_theta"]], [s["peak"]], "o", color="C0", ms=4, label=f"its worst branch's peak ({s['peak']:.2f})")
    ax.set_ylabel("$\\max|x_1|/x_{\\mathrm{st}}$")
    ax.set_ylim(0.0, None)
    ax.legend(fontsize="small", loc="upper left")
    tallest = 0.0
    for direction, ls in (("up", "-"), ("down", "--")):
        t, pulse = _curve(rows, "optimal", direction, "peak_impulse")
        ax2.plot(t, pulse * t, color="C0", ls=ls, lw=0.9, label=f"largest pulse, {direction}ward")
        tallest = max(tallest, float(np.nanmax(pulse * t)))
    ax2.set_ylim(0.0, 1.8 * tallest if tallest > 0 else 1.0)  # (room above the curves for the legend)
    ax2.set_ylabel("pulse per impact ($P_0/\\omega_1$)")
    ax2.set_xlabel("forcing frequency " + SPEC["theta"].label)
    ax3 = ax2.twinx()
    for direction, ls in (("up", "-"), ("down", "--")):
        t, z = _curve(rows, "optimal", direction, "impacts_per_period")
        ax3.step(t, z, where="mid", color="C1", ls=ls, lw=0.8, label=f"impacts per period, {direction}ward")
    ax3.set_ylabel("impacts per period")
    top = np.nanmax([cell_float(r["impacts_per_period"]) for r in rows if r["role"] == "optimal"])
    ax3.set_ylim(0.0, 1.8 * max(1.0, top))
    h1, l1 = ax2.get_legend_handles_labels()
    h2, l2 = ax3.get_legend_handles_labels()
    ax2.legend(h1 + h2, l1 + l2, fontsize="small", loc="upper center", ncol=2)
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "input.response input.summary input.baselines input.optimum output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
