"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the largest Lyapunov
exponent over the plane of the theta map, the initial gap Delta0/x_st against theta =
omega/omega1.

The paper has no such figure. Colour: the largest exponent of the motion each cell settles on
(each row a gap sweep upward, cell from cell; the cells left nonperiodic after the Newton
rescue from the labelling run) in the object's time, lambda_1 / omega1 = lambda_1 T theta /
(2 pi): per forcing period the same rate would scale as 1/theta along the theta axis. On a
scale symmetric about zero and clipped at its ends; white: zero (a neutral direction). Markers
on the cells left nonperiodic, by their label (analysis/lyapunov.py): chaotic (positive beyond
its error in both halves of the window, not settled by its end), chaotic transient, quasi-
periodic (zero within its error, the next negative), periodic (a transient slower than the cap)
and not settled. Star: the paper's reference point (Delta0/x_st = -5.8, theta = 1).

Deviation: none (no counterpart in the paper).
"""

import numpy as np

from impactdamper.reporting.figures import outside_legend
from impactdamper.reporting.plotting import figure_size, finish_figure, use_style
from impactdamper.reporting.records import read_csv, run_stage
from impactdamper.studies.vocabulary import SPEC

# The colour scale's ends, lambda_1 / omega1: the chaotic bands reach ~0.25, the periodic
# motions' slowest decay is ~-0.05 to -0.1; beyond +-CLIP the colour saturates.
CLIP = 0.2
# Markers of the former np cells by label (the labels of analysis/lyapunov.py).
MARKERS = {
    "chaotic": ("x", "k", "chaotic"),
    "chaotic transient": ("+", "0.35", "chaotic transient"),
    "quasi-periodic": ("o", "k", "quasi-periodic"),
    "periodic": ("^", "0.35", "periodic (slow transient)"),
    "not settled": ("s", "0.35", "not settled"),
}


def main(reference: dict, lyapunov: dict, map_csv, out_pdf, out_png) -> None:
    plt = use_style()
    rows = read_csv(map_csv)
    slow = np.array(sorted({float(r["slow"]) for r in rows}))
    gaps = np.array(sorted({float(r["gap"]) for r in rows}))
    lam = np.full((len(slow), len(gaps)), np.nan)
    by_theta = lyapunov["map"]["parameter"] == "theta"
    for r in rows:
        theta = float(r["slow"]) if by_theta else float(reference["theta"])
        per_period = float(r["exponent"]) if r["exponent"] not in ("", "nan") else np.nan
        lam[int(r["i"]), int(r["j"])] = per_period * theta / (2.0 * np.pi)
    fig, ax = plt.subplots(figsize=figure_size(4.5), layout="constrained")
    mesh = ax.pcolormesh(
        gaps, slow, np.clip(lam, -CLIP, CLIP), cmap="RdBu_r", vmin=-CLIP, vmax=CLIP, shading="nearest", rasterized=True
    )
    bar = fig.colorbar(mesh, ax=ax, extend="both", pad=0.02)
    bar.set_label("largest exponent $\\lambda_1/\\omega_1$")
    handles, names = [], []
    for label, (marker, color, name) in MARKERS.items():
        cells = [r for r in rows if r["motion"] == label]
        if not cells:
            continue
        h = ax.scatter(
            [float(r["gap"]) for r in cells],
            [float(r["slow"]) for r in cells],
            marker=marker,
            s=6,
            lw=0.5,
            facecolors="none" if marker not in ("x", "+") else color,
            edgecolors=color,
            zorder=3,
        )
        handles.append(h)
        names.append(f"np: {name}")
    star = ax.scatter(
        [float(reference["gap"])], [float(reference["theta"])], marker="*", s=60, color="gold", ec="k", lw=0.6, zorder=4
    )
    handles.append(star)
    names.append("stated case")
    ax.set_xlabel(SPEC["gap"].long_label)
    ax.set_ylabel(SPEC["theta"].long_label)
    outside_legend(fig, handles, names, where="lower", ncol=3, markerscale=2)
    finish_figure(fig, out_pdf, out_png)


JOB = "params.reference params.lyapunov input.map output.pdf output.png"

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
