"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: bifurcation diagram of
the impact velocities against the initial gap.

The paper has no such figure; its introduction says that with a negative gap the object and
suppressor "move together" at small forcing, work "with one impact per period" at large
forcing, and "several impacts per period" occur in between. Top panel: the upward sweep
(each point from its lower neighbour's motion); bottom: the downward sweep; grey: random
initial states; black line: Algorithm No. 1's one-impact orbit (solid where admissible and
stable, dotted where its gap goes negative). Dashed grey verticals: the analytic transitions
(lift-off of the persistent contact, Algorithm No. 1's orbit touching the stop between
impacts, first contact of the free forced response U1), each named at the top of the upper
panel; dash-dotted green verticals: the stated case (Delta0/x_st = -5.8) and the located case
of the replication verdict, named above the upper panel. Lowest panel: the largest Lyapunov
exponent lambda_1 T per forcing period of each point's motion (upward and downward sweep, each
point run again from its start state in the sweep; the Lyapunov stage's table), zero marked:
positive where the motion is chaotic. Every text is at least 7 pt at the report's text width.

Deviations: velocities are the closing relative velocities x2' - x1' before each impact over
x_st omega; for nonperiodic points they are the impacts of the last 8 periods simulated.
"""

import numpy as np

from impactdamper.studies.config import located_gap
from impactdamper.reporting.records import read_csv, read_json, run_stage, split_floats
from impactdamper.reporting.figures import outside_legend
from impactdamper.reporting.plotting import ANNOTATION_SIZE, dots, figure_size, finish_figure, use_style
from impactdamper.studies.vocabulary import SPEC


DOT = 1.2  # marker size of the sweep dots (points^2)
# Height of the exponent panel relative to each of the two diagram panels.
EXPONENT_PANEL = 0.75
# The analytic transitions drawn as dashed verticals (sweep_checks.json names) and their labels.
ANALYTIC = (("liftoff", "lift-off"), ("alg1_grazing", "Alg. 1 grazing"), ("first_contact", "$U_1$"))


def _scatter(rows):
    xs, ys = [], []
    for r in rows:
        v = split_floats(r["velocities"])
        xs.extend([float(r["value"])] * len(v))
        ys.extend(v)
    return np.array(xs), np.array(ys)


def main(
    sweep_csv, random_csv, alg1_csv, checks_json, located_json, lyapunov_csv, stated_gap: float, out_pdf, out_png
) -> None:
    plt = use_style()
    rows = read_csv(sweep_csv)
    rnd = read_csv(random_csv)
    alg1 = read_csv(alg1_csv)
    checks = {c["name"]: c for c in read_json(checks_json)["checks"]}
    located = located_gap(located_json)
    fig, panels = plt.subplots(
        3, 1, figsize=figure_size(6.4), sharex=True, height_ratios=(1.0, 1.0, EXPONENT_PANEL), layout="constrained"
    )
    axes, lower = panels[:2], panels[2]
    axes[1].sharey(axes[0])
    xr, yr = _scatter(rnd)
    g = np.array([float(r["value"]) for r in alg1])
    v = np.array([float(r["velocity"]) if r["velocity"] else np.nan for r in alg1])
    good = np.array([r["admissible"] == "1" and r["stable"] == "1" for r in alg1])
    for ax, direction, color in ((axes[0], "up", "C0"), (axes[1], "down", "C1")):
        dots(ax, xr, yr, s=DOT, color="0.75", label="random starts")
        x, y = _scatter([r for r in rows if r["direction"] == direction])
        dots(ax, x, y, s=DOT, color=color, label=f"{'upward' if direction == 'up' else 'downward'} sweep")
        ax.plot(g, np.where(good, v, np.nan), color="k", lw=0.8, label="Alg. No. 1 orbit")
        ax.plot(g, np.where(~good, v, np.nan), color="k", lw=0.8, ls=":", label="same, gap $<0$ between impacts")
        for name, text in ANALYTIC:
            if checks.get(name) and checks[name]["analytic"] is not None:
                ax.axvline(
                    checks[name]["analytic"],
                    color="0.3",
                    lw=0.7,
                    ls="--",
                    label="analytic transitions" if name == ANALYTIC[0][0] else None,
                )
                if direction == "up":
                    ax.annotate(
                        text,
                        (checks[name]["analytic"], 1.0),
                        xycoords=("data", "axes fraction"),
                        xytext=(2, -2),
                        textcoords="offset points",
                        ha="left",
                        va="top",
                        fontsize=ANNOTATION_SIZE,
                        bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.8),
                    )
        ax.set_ylabel("closing velocity $v/(x_{\\mathrm{st}}\\omega)$")
        ax.set_ylim(bottom=0.0)
    # The cases: named above the upper panel, each on the side away from the other.
    for x, text in ((stated_gap, "stated"), (located, "located")):
        right = x >= min(stated_gap, located) + 0.5 * abs(stated_gap - located)
        axes[0].annotate(
            f"{text} {x:g}",
            (x, 1.0),
            xycoords=("data", "axes fraction"),
            xytext=(2 if right else -2, 2),
            textcoords="offset points",
            ha="left" if right else "right",
            va="bottom",
            fontsize=ANNOTATION_SIZE,
        )
        for ax in panels:
            ax.axvline(x, color="C2", lw=0.7, ls="-.", label="stated and located cases" if text == "stated" else None)
    _exponent_panel(lower, read_csv(lyapunov_csv))
    lower.set_xlabel(SPEC["gap"].long_label)
    h0, l0 = axes[0].get_legend_handles_labels()
    h1, l1 = axes[1].get_legend_handles_labels()
    order = [
        "random starts",
        "upward sweep",
        "downward sweep",
        "Alg. No. 1 orbit",
        "same, gap $<0$ between impacts",
        "analytic transitions",
        "stated and located cases",
    ]
    found = dict(zip(l0 + l1, h0 + h1))
    outside_legend(
        fig, [found[k] for k in order], order, where="upper", ncol=4, markerscale=4, handlelength=2.0, columnspacing=0.8
    )
    finish_figure(fig, out_pdf, out_png)


def _exponent_panel(ax, rows) -> None:
    """The largest exponent along each sweep (the Lyapunov stage's table), zero marked."""
    ax.axhline(0.0, color="0.3", lw=0.6)
    for direction, color in (("up", "C0"), ("down", "C1")):
        chosen = [r for r in rows if r["direction"] == direction and r["exponent"] not in ("", "nan")]
        dots(ax, [float(r["value"]) for r in chosen], [float(r["exponent"]) for r in chosen], s=DOT, color=color)
    ax.set_ylabel("largest exponent $\\lambda_1 T$")


JOB = (
    "input.sweep input.random input.alg1 input.checks input.located input.lyapunov params.stated_gap:float "
    "output.pdf output.png"
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
