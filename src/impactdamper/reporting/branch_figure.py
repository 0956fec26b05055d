"""Drawing of branch diagrams (periodic orbits against a swept parameter): the branches' line
styles and special-point markers, the spectral-radius axis, the special points' and the cases'
labels, and the legend.

Used by ``workflow/scripts/fig_orbit_branches.py`` (the figure extending Fig. 2 of Timofeev et
al. (2019), DOI 10.18698/0236-3941-2019-1-90-100). The study's data (branch labels, the special
points' names) are passed in: this module draws only.
"""

from __future__ import annotations

import math

from impactdamper.reporting.plotting import ANNOTATION_SIZE

# Line style of a branch's piece, by its state.
STYLE = {"stable": "-", "unstable": "--", "inadmissible": ":"}
# Marker of a special point, by its kind.
MARKER = {"period_doubling": "v", "neimark_sacker": "D", "fold": "s", "grazing_velocity": "o", "grazing_interior": "o"}
INADMISSIBLE_MARK = "0.55"  # grey of special points off the motions
ZOOM_SHADE = "0.9"  # the right column's window, shaded in the left column
# Spectral radius axis (log): the radius grows without bound at a vanishing impact.
RADIUS_LIMITS = (0.2, 5.0)
RADIUS_TICKS = (0.2, 0.5, 1.0, 2.0, 5.0)


def radius_axis(ax_r, xlabel: str) -> None:
    """Set up an axis of the spectral radius max|rho|: log scale over RADIUS_LIMITS, ticks at
    RADIUS_TICKS, the dashed unit line (below it the cycle is stable) and ``xlabel`` (the
    continued parameter's axis label)."""
    from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullLocator

    ax_r.axhline(1.0, color="0.2", lw=0.7, ls="--", zorder=1)
    ax_r.set_yscale("log")
    ax_r.set_ylim(*RADIUS_LIMITS)
    ax_r.yaxis.set_major_locator(FixedLocator(RADIUS_TICKS))
    ax_r.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax_r.yaxis.set_minor_locator(NullLocator())
    ax_r.set_xlabel(xlabel)


def mark_special(
    ax_x, ax_r, g: float, x1_max: float, radius: float, kind: str, color: str, on: bool, size: float
) -> None:
    """Mark a special point of kind ``kind`` at gap ``g``: at ``x1_max`` (``ax_x``) and, unless
    NaN, at ``radius`` clipped to RADIUS_LIMITS (``ax_r``), in the branch's ``color`` (filled,
    but for an interior grazing) where ``on`` a motion, else open and grey (INADMISSIBLE_MARK);
    ``size``: the marker size (points)."""
    mk = dict(
        marker=MARKER[kind],
        ms=size,
        ls="none",
        zorder=5,
        mfc=(color if on else "white") if kind != "grazing_interior" else "white",
        mec=color if on else INADMISSIBLE_MARK,
        mew=0.9,
    )
    ax_x.plot([g], [x1_max], **mk)
    if not math.isnan(radius):
        ax_r.plot([g], [min(max(radius, RADIUS_LIMITS[0]), RADIUS_LIMITS[1])], **mk)


def label_point(ax, text: str, xy: tuple[float, float], offset: tuple[float, float], on: bool) -> None:
    """Write a special point's short name ``text`` at ``offset`` points from ``xy``, aligned
    away from the point (centred where an offset is 0); grey (INADMISSIBLE_MARK) unless ``on``
    (the point is on a motion)."""
    dx, dy = offset
    ha = "center" if dx == 0 else ("left" if dx > 0 else "right")
    va = "bottom" if dy > 0 else ("top" if dy < 0 else "center")
    ax.annotate(
        text,
        xy,
        xytext=(dx, dy),
        textcoords="offset points",
        ha=ha,
        va=va,
        fontsize=ANNOTATION_SIZE,
        color="0.1" if on else INADMISSIBLE_MARK,
    )


def mark_case(ax_x, ax_r, g: float, x1_max: float, radius: float, name: str | None) -> None:
    """Mark a case at gap ``g``: dotted verticals on both axes, a gold star at ``x1_max`` (top,
    ``ax_x``) and at ``radius`` (bottom, ``ax_r``), and ``name`` (unless None) along the top
    vertical, on a white ground."""
    for ax in (ax_x, ax_r):
        ax.axvline(g, color="0.35", lw=0.6, ls=(0, (1, 2)), zorder=0)
    ax_x.plot([g], [x1_max], marker="*", ms=8, color="k", mfc="gold", mew=0.6, ls="none", zorder=6)
    ax_r.plot([g], [radius], marker="*", ms=8, color="k", mfc="gold", mew=0.6, ls="none", zorder=6)
    if name is not None:
        ax_x.annotate(
            name,
            (g, 1.0),
            xycoords=("data", "axes fraction"),
            xytext=(2, -3),
            textcoords="offset points",
            ha="left",
            va="top",
            rotation=90,
            fontsize=ANNOTATION_SIZE,
            color="0.2",
            # on a white ground: the branches' lines pass behind the name, not through it
            bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.85},
            zorder=7,
        )


def legend_rows(branches: list[tuple[str, str]], kind_legend: dict) -> list[list]:
    """The branch diagram's legend, row by row (for :func:`impactdamper.reporting.plotting.legend_in_rows`):
    the branches (``(colour, label)`` pairs) and the line styles; the special points' markers
    (``kind_legend``: kind -> name) and the case's star; the zoom window's shading and the unit line."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    line = lambda **kw: Line2D([], [], **kw)  # noqa: E731
    return [
        [line(color=color, lw=1.2, label=f"{label}") for color, label in branches]
        + [line(color="0.2", ls=STYLE[s], lw=1.0, label=s) for s in ("stable", "unstable", "inadmissible")],
        [
            line(
                color="0.2",
                marker=MARKER[k],
                mfc="0.2" if k != "grazing_interior" else "white",
                ls="none",
                ms=4,
                label=lab,
            )
            for k, lab in kind_legend.items()
        ]
        + [line(marker="*", ms=7, color="k", mfc="gold", mew=0.6, ls="none", label="case")],
        [
            Patch(facecolor=ZOOM_SHADE, edgecolor="0.6", lw=0.5, label="zoom window"),
            line(color="0.2", lw=0.7, ls="--", label="$|\\rho| = 1$"),
        ],
    ]


def column_ranges(axes, gaps: list[float], x1_max: list[float], zoom: tuple[float, float], margin: float) -> None:
    """The two columns' ranges: the left one over every gap with ``margin`` either side, the
    window ``zoom`` shaded there; the right one over the window, its y range the branches'
    values inside it (autoscaling would include the 1/1 branch outside the window)."""
    ys = [y for g, y in zip(gaps, x1_max) if zoom[0] <= g <= zoom[1]]
    pad = 0.06 * (max(ys) - min(ys))
    axes[0, 1].set(xlim=zoom, ylim=(min(ys) - 2 * pad, max(ys) + pad))
    axes[0, 0].set_xlim(min(gaps) - margin, max(gaps) + margin)
    for ax in axes[:, 0]:
        ax.axvspan(*zoom, color=ZOOM_SHADE, lw=0, zorder=0)
