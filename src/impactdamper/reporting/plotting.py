"""Shared, deterministic figure style and saving for every figure script.

``use_style()`` selects the non-interactive backend and the one style sheet
(``paper.mplstyle``, sized for the report's text width); ``save_figure`` writes PDF (for the
report) and PNG (for the README) with no timestamps or software stamps in their metadata, so
the same data give byte-identical files.
"""

from __future__ import annotations

import re
from pathlib import Path

STYLE_FILE = Path(__file__).with_name("paper.mplstyle")
# Text width of the report in inches (article class, 1 in margins on A4 would be 6.27 in): the
# style's figure width (figure.figsize), so that every figure is printed at its own size.
TEXT_WIDTH = 6.3
# Text on the plot itself (notes at curves and points, labels on regions and bands): matplotlib's
# relative size "small", 0.833 of the style's font.size (9 pt: 7.5 pt printed), so that the
# style alone sets every text size. Titles, legends and ticks take the style's own sizes.
ANNOTATION_SIZE = "small"

__all__ = [
    "use_style",
    "finish_figure",
    "dots",
    "figure_size",
    "STYLE_FILE",
    "TEXT_WIDTH",
    "ANNOTATION_SIZE",
    "CASE_LABELS",
    "REGIME_COLORS",
    "REGIME_TEXT",
    "REGIME_NAMES",
]

# One colour per regime class in every sweep and map figure (labels z/k are written on them).
# Chosen so that classes that border each other stay apart in print, in greyscale and for
# red-green colour-blind readers (CIELAB distance >= 28 under simulated deuteranopia and
# protanopia for every bordering pair): np, which only says "not settled within the cap", is a
# pale cream, far from the orange of the z/k motions.
REGIME_COLORS = {
    "stuck": "#404040",  # persistent contact: dark grey
    "chatter": "#c994c7",  # contact phases reached by chatter: light purple
    "multi_impact": "#f0a830",  # several impacts or k > 1: orange
    "single_impact": "#1f4e79",  # one impact per period: dark blue
    "no_contact": "#a6cee3",  # no contact: light blue
    "nonperiodic": "#fff2cc",  # not settled within the cap: pale cream
    "failed": "#ffffff",  # the simulation raised (label err): white
}
# How the figures name the reference stage's two cases (the paper's stated parameters; the
# located gap where its Fig. 2 behaviour occurs).
CASE_LABELS = {"stated": "stated case", "located": "located case"}
# Text written on a band or region of each class: white on the dark ones, black elsewhere.
REGIME_TEXT = {"stuck": "white", "single_impact": "white"}
REGIME_NAMES = {
    "stuck": "persistent contact (S)",
    "chatter": "chatter, c/k",
    "multi_impact": "z/k impacts",
    "single_impact": "1/1 (one impact)",
    "no_contact": "no contact (0/1)",
    "nonperiodic": "np: not settled within the cap",
    "failed": "solver failed (err)",
}


def use_style(backend: str | None = "Agg"):
    """Select the project style (and a backend: the non-interactive Agg by default, for the
    workflow's scripts; ``None`` keeps the current one, e.g. Jupyter's inline backend).
    Returns matplotlib.pyplot."""
    import matplotlib

    if backend is not None:
        matplotlib.use(backend)
    import matplotlib.pyplot as plt

    plt.style.use(str(STYLE_FILE))
    return plt


def figure_size(height: float) -> tuple[float, float]:
    """``figsize`` of a figure ``height`` inches high at the style's width (the report's text
    width, :data:`TEXT_WIDTH`): figures are included at 100 %, so their fonts print at the
    style's sizes."""
    return (TEXT_WIDTH, float(height))


def _save_figure(fig, path: str | Path, formats: tuple[str, ...] | None = None) -> list[Path]:
    """Save ``fig`` deterministically. ``path`` with a suffix saves that format only;
    without one, saves ``path.pdf`` and ``path.png``. Returns the written paths."""
    path = Path(path)
    if formats is None:
        formats = (path.suffix.lstrip("."),) if path.suffix else ("pdf", "png")
    stem = path.with_suffix("") if path.suffix else path
    written = []
    for fmt in formats:
        out = stem.with_suffix("." + fmt)
        out.parent.mkdir(parents=True, exist_ok=True)
        metadata = {
            "pdf": {"CreationDate": None, "ModDate": None, "Producer": None, "Creator": None},
            "png": {"Software": None},
            "svg": {"Date": None, "Creator": None},
        }.get(fmt, {})
        fig.savefig(out, format=fmt, metadata=metadata)
        written.append(out)
    return written


# A hyphen-minus before a number, outside mathtext and not inside a word or a range ("1-2"):
# the sign of a negative number, which the report's text typesets as a minus sign (U+2212), as
# matplotlib's tick labels do (axes.unicode_minus).
_SIGN = re.compile(r"(?<![\w)\]])-(?=\.?\d)")


def _typeset_minus(text: str) -> str:
    """``text`` with the sign of every negative number outside ``$...$`` as a minus sign."""
    parts = text.split("$")
    return "$".join(_SIGN.sub("\u2212", part) if i % 2 == 0 else part for i, part in enumerate(parts))


def finish_figure(fig, *paths: str | Path, log=None) -> list[Path]:
    """The end of every figure script: save ``fig`` to each of ``paths`` (as :func:`save_figure`:
    a path with a suffix in that format, one without as PDF and PNG), close it, and say what was
    written through ``log`` (a callable taking one line, e.g. ``logger.info``) if given.
    Returns the written paths."""
    import matplotlib.pyplot as plt
    from matplotlib.text import Text

    for text in fig.findobj(Text):  # titles, labels, legends, annotations: one rule for the signs
        if text.get_text():
            text.set_text(_typeset_minus(text.get_text()))
    written = [out for path in paths for out in _save_figure(fig, path)]
    plt.close(fig)
    if log is not None:
        log("wrote " + ", ".join(str(p) for p in written))
    return written


def dots(ax, x, y, **kwargs):
    """Points of a sweep or of random starts: a scatter without marker edges, rasterized (a
    figure of thousands of points stays light in the PDF). ``kwargs`` as ``Axes.scatter``."""
    return ax.scatter(x, y, lw=0, rasterized=True, **kwargs)


def legend_in_rows(fig, rows: list[list], **kwargs):
    """A figure legend written row by row (matplotlib fills a legend column by column): each
    of ``rows`` is a list of handles, shorter rows padded with blank entries. ``kwargs`` go to
    ``fig.legend`` (``ncol`` is the longest row's length)."""
    from matplotlib.lines import Line2D

    ncol = max(len(r) for r in rows)
    blank = Line2D([], [], ls="none", label=" ")
    rows = [r + [blank] * (ncol - len(r)) for r in rows]
    handles = [rows[i][j] for j in range(ncol) for i in range(len(rows))]
    return fig.legend(handles=handles, ncol=ncol, **kwargs)


# Labels are written on connected regions of one label that cover at least this share of the
# map (60 cells of a 200 x 200 map), and at least REGION_LABEL_CELLS cells: the same regions are
# labelled whatever the resolution.
REGION_LABEL_SHARE = 0.0015
REGION_LABEL_CELLS = 4
# Least distance between two labels' centres, in axes fractions (x, y): about a label's width
# and height at ANNOTATION_SIZE on the text-width figure.
REGION_LABEL_CLEARANCE = (0.05, 0.045)


def label_regions(ax, slow, gaps, labels, regime_of, size=ANNOTATION_SIZE) -> None:
    """Write each larger region's label (z/k, "S" for stuck) on a regime map, the largest first.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The map's axes.
    slow, gaps : numpy.ndarray
        The map's row values (y) and gaps (x).
    labels : numpy.ndarray of str
        The cells' labels, shape (len(slow), len(gaps)).
    regime_of : callable
        A label's regime class (a key of REGIME_COLORS), for the label's box colour.
    size : str or float
        The labels' font size.

    Notes
    -----
    A connected region of one label is labelled where it covers at least REGION_LABEL_SHARE of
    the map and REGION_LABEL_CELLS cells; a label too close to one already written
    (REGION_LABEL_CLEARANCE) is left out, so that none overlap however fine the map.
    """
    import numpy as np
    import scipy.ndimage

    least = max(REGION_LABEL_SHARE * labels.size, REGION_LABEL_CELLS)
    candidates = []
    for lab in sorted(set(labels.ravel())):
        regions, n = scipy.ndimage.label(labels == lab)
        for k in range(1, n + 1):
            ii, jj = np.nonzero(regions == k)
            if len(ii) >= least:
                # The region's cell nearest its centroid (a non-convex region's centroid may lie outside).
                c = int(np.argmin((ii - ii.mean()) ** 2 / len(slow) ** 2 + (jj - jj.mean()) ** 2 / len(gaps) ** 2))
                candidates.append((len(ii), lab, ii[c], jj[c]))
    placed = []
    for _, lab, i, j in sorted(candidates, key=lambda c: -c[0]):
        x, y = j / max(len(gaps) - 1, 1), i / max(len(slow) - 1, 1)  # axes fractions
        if any(
            abs(x - px) < REGION_LABEL_CLEARANCE[0] and abs(y - py) < REGION_LABEL_CLEARANCE[1] for px, py in placed
        ):
            continue
        placed.append((x, y))
        regime = regime_of(lab)
        ax.text(
            gaps[j],
            slow[i],
            "S" if lab == "stuck" else lab,
            ha="center",
            va="center",
            fontsize=size,
            zorder=6,
            color=REGIME_TEXT.get(regime, "black"),
            bbox=dict(boxstyle="square,pad=0.15", fc=REGIME_COLORS[regime], ec="none"),
        )


# Least gap (points) between neighbouring labels of one row of bands, and between a label and its band's edge.
BAND_LABEL_PAD = 1.0


def label_bands(ax, y, bands, renderer, regime_of, height, short=None, size=ANNOTATION_SIZE) -> None:
    """Write each band's label where it fits inside the band, without touching the previous
    label of the row (widest bands first, so that the main regimes are named).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes, with its final x limits and layout (draw the figure first).
    y : float
        The row's centre (data coordinates).
    bands : list of (float, float, str)
        Each band's centre, width (data coordinates) and label.
    renderer : matplotlib.backend_bases.RendererBase
        The figure's renderer, to measure the labels.
    regime_of : callable
        A label's regime class (a key of REGIME_COLORS), for the text's colour.
    height : float
        The band's height (data coordinates): a label must fit within it.
    short : dict, optional
        Shorter texts of some labels (label -> text).
    size : str or float
        The labels' font size.

    Notes
    -----
    A label is written horizontally where it fits with BAND_BAND_LABEL_PAD points to spare, else
    upright, else not at all.
    """
    to_px = ax.transData.transform
    x0, x1 = ax.get_xlim()
    placed = []  # (left, right) in display pixels
    pad = BAND_LABEL_PAD * ax.figure.dpi / 72.0
    bottom_edge, top_edge = (to_px((x0, y + s * height / 2))[1] for s in (-1, 1))
    for centre, width, lab in sorted(bands, key=lambda b: -b[1]):
        left_edge = to_px((max(centre - width / 2, x0), y))[0]
        right_edge = to_px((min(centre + width / 2, x1), y))[0]
        if right_edge - left_edge <= 0:
            continue
        mid = to_px((0.5 * (max(centre - width / 2, x0) + min(centre + width / 2, x1)), y))[0]
        x_mid = ax.transData.inverted().transform((mid, 0))[0]
        regime = regime_of(lab)
        for rotation in (0, 90):  # upright only where the band is too narrow
            t = ax.text(
                x_mid,
                y,
                (short or {}).get(lab, lab),
                ha="center",
                va="center",
                fontsize=size,
                rotation=rotation,
                color=REGIME_TEXT.get(regime, "black"),
                clip_on=True,
            )
            bb = t.get_window_extent(renderer)
            fits = bb.x0 - pad >= left_edge and bb.x1 + pad <= right_edge and bb.y0 >= bottom_edge and bb.y1 <= top_edge
            free = all(bb.x1 + pad <= l or bb.x0 - pad >= r for l, r in placed)
            if fits and free:
                placed.append((bb.x0, bb.x1))
                break
            t.remove()
