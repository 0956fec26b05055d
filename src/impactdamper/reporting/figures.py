"""Pieces several of the workflow's figures draw alike, in the one style of
:mod:`impactdamper.reporting.plotting`: the two panels of the paper's Fig. 2 (the bodies'
coordinates over the gap), a label above a marked time or gap, the claims maps' classes, and a
legend outside the axes.

The figures replicate and extend Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100;
each script (``workflow/scripts/fig*.py``) says which of the paper's figures it draws.
"""

from __future__ import annotations

from impactdamper.reporting.plotting import ANNOTATION_SIZE, figure_size, use_style

__all__ = [
    "motion_figure",
    "plot_motion",
    "label_above",
    "CLAIM_CLASSES",
    "claim_grid",
    "class_image",
    "class_points",
    "outside_legend",
]


# The paper's Fig. 2 panels: height (inches) at the style's width, and the share of that width
# the axes take, the rest holding the legends, so that the figure prints at its own size (its
# fonts at the style's sizes) within the report's text width.
MOTION_HEIGHT = 2.7
MOTION_AXES_RIGHT = 0.74


def motion_figure():
    """The paper's Fig. 2 layout: the two bodies' coordinates (top) over the gap (bottom), one
    time axis, the legends to the right within the figure's width. Returns the figure and the
    two axes."""
    plt = use_style()
    fig, (ax, axg) = plt.subplots(2, 1, sharex=True, height_ratios=(3, 1), figsize=figure_size(MOTION_HEIGHT))
    fig.subplots_adjust(left=0.1, right=MOTION_AXES_RIGHT, bottom=0.15, top=0.86, hspace=0.12)
    return fig, ax, axg


def plot_motion(ax, axg, t, x1, x2, gap, gap_label: str) -> None:
    """The object's and the suppressor's relative coordinates (eq. 9's x1, x2 over x_st) and the
    gap, with the gap's zero line."""
    ax.plot(t, x1, label="$\\bar x_1$ (object)")
    ax.plot(t, x2, ls="--", label="$\\bar x_2$ (suppressor)")
    axg.axhline(0.0, color="0.2", lw=0.6)
    axg.plot(t, gap, color="C2", label=gap_label)


def label_above(ax, x: float, text: str) -> None:
    """``text`` just above the axes at data ``x`` (a marked impact time, a case's gap)."""
    ax.annotate(
        text,
        (x, 1.0),
        xycoords=("data", "axes fraction"),
        xytext=(0, 2),
        textcoords="offset points",
        ha="center",
        va="bottom",
        fontsize=ANNOTATION_SIZE,
    )


# The claims maps' classes (claim (a) + 2 claim (b)): legend text and colour.
CLAIM_CLASSES = (
    ("neither claim", "#eeeeee"),
    ("(a) only: gap negative", "#f5c28b"),
    ("(b) only: $T_c = 2T$, 3 impacts", "#8fb3d9"),
    ("both claims", "#c0392b"),
)


def _claim_class(row: dict) -> int:
    """A map row's class, the index into :data:`CLAIM_CLASSES`: claim (a) + 2 claim (b) (the
    record's "true"/"false")."""
    return int(row["claim_a"] == "true") + 2 * int(row["claim_b"] == "true")


def claim_grid(rows: list[dict]):
    """A claims map's grid: the x and y values, sorted, and the class of each cell (rows of y)."""
    import numpy as np

    xs = sorted({float(r["x"]) for r in rows})
    ys = sorted({float(r["y"]) for r in rows})
    z = np.zeros((len(ys), len(xs)), dtype=int)
    for r in rows:
        z[ys.index(float(r["y"])), xs.index(float(r["x"]))] = _claim_class(r)
    return xs, ys, z


def class_image(ax, xs, ys, classes) -> None:
    """A map of classes (index into :data:`CLAIM_CLASSES`, rows of ``ys`` by columns of ``xs``),
    each cell centred on its grid point."""
    from matplotlib.colors import ListedColormap

    dx, dy = (xs[1] - xs[0]) / 2, (ys[1] - ys[0]) / 2
    ax.imshow(
        classes,
        origin="lower",
        aspect="auto",
        interpolation="nearest",
        vmin=-0.5,
        vmax=3.5,
        cmap=ListedColormap([c for _, c in CLAIM_CLASSES]),
        extent=(xs[0] - dx, xs[-1] + dx, ys[0] - dy, ys[-1] + dy),
    )
    ax.grid(False)


def class_points(ax, rows: list[dict], size: float) -> None:
    """Points added by a map's refinement (rows with ``x``, ``y`` and the claims), coloured by
    class, of marker size ``size``."""
    import numpy as np

    colours = np.array([c for _, c in CLAIM_CLASSES])
    ax.scatter(
        [float(r["x"]) for r in rows],
        [float(r["y"]) for r in rows],
        s=size,
        c=colours[np.array([_claim_class(r) for r in rows], dtype=int)],
        marker="s",
        linewidths=0,
        rasterized=True,
    )


def outside_legend(fig, handles, labels=None, *, where: str, ncol: int, **style) -> None:
    """The figure's legend outside its axes (``where``: ``upper`` or ``lower``), centred, in the
    small font; ``style``: matplotlib's legend options (handle length, spacing)."""
    if labels is not None:
        style["labels"] = labels  # else the handles' own
    fig.legend(handles=handles, loc=f"outside {where} center", ncol=ncol, fontsize="small", **style)
