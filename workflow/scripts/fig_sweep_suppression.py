"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: what the suppressor
does to the object's amplitude, against the initial gap.

The paper's purpose is vibration suppression; it shows no amplitude curve. Plotted: the largest
|x1|/x_st of the settled motion along the upward and downward sweeps (grey dots: random
initial states), beside three references in closed form: the object alone (no suppressor,
1/|1 - theta^2 + 2 i delta1 theta|), the suppressor rigidly attached (m1 + m2 on c1, k1,
1/|1 - (1 + mu) theta^2 + 2 i delta1 theta|; the limit of persistent contact), and the
suppressor as a linear absorber that never reaches the stop (|x1p_hat|/x_st, eq. 10); each
reference is a horizontal line, named with its value in the legend.

Deviations: none (the paper has no such figure).
"""

from impactdamper.studies.config import parameters
from impactdamper.reporting.records import cell_float, read_csv, run_stage
from impactdamper.core.linear import forced_amplitudes
from impactdamper.reporting.plotting import dots, figure_size, finish_figure, use_style
from impactdamper.analysis.linear_device import LinearDevice
from impactdamper.analysis.transitions import rigid_amplitude
from impactdamper.studies.vocabulary import SPEC


def main(reference: dict, sweep_csv, random_csv, out_pdf, out_png) -> None:
    plt = use_style()
    p = parameters(reference)
    rows = read_csv(sweep_csv)
    rnd = read_csv(random_csv)
    fig, ax = plt.subplots(figsize=figure_size(3.0), layout="constrained")
    dots(
        ax,
        [float(r["value"]) for r in rnd],
        [cell_float(r["x1_max"]) for r in rnd],
        s=1.5,
        color="0.7",
        label="random initial states",
    )
    for direction, color, ls in (("up", "C0", "-"), ("down", "C1", "--")):
        rs = [r for r in rows if r["direction"] == direction]
        ax.plot(
            [float(r["value"]) for r in rs],
            [cell_float(r["x1_max"]) for r in rs],
            color=color,
            ls=ls,
            lw=0.9,
            label=f"{'upward' if direction == 'up' else 'downward'} sweep",
        )
    refs = (
        (float(LinearDevice.bare(p.delta1).amplitude([p.theta])[0]), "object alone", "0.2", ":"),
        (rigid_amplitude(p), "suppressor rigidly attached", "C4", "-."),
        (abs(forced_amplitudes(p)[0]) / p.x_st, "suppressor never reaching the stop", "C2", (0, (5, 2))),
    )
    for value, text, color, ls in refs:
        ax.axhline(value, color=color, ls=ls, lw=0.8, label=f"{text} ({value:.2f})")
    ax.set_xlabel(SPEC["gap"].long_label)
    ax.set_ylabel("$\\max|x_1|/x_{\\mathrm{st}}$")
    ax.set_ylim(0.0, 1.12 * max(r[0] for r in refs))
    ax.legend(loc="lower left", fontsize="small", ncol=2, markerscale=4)
    finish_figure(fig, out_pdf, out_png)


if __name__ == "__main__":
    run_stage(snakemake, main, "params.reference input.sweep input.random output.pdf output.png")  # noqa: F821 (injected by Snakemake's script: directive)
