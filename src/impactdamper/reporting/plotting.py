"""Shared, deterministic figure style and saving for every figure script.

``use_style()`` selects the non-interactive backend and the one style sheet
(``paper.mplstyle``, sized for the report's text width); ``save_figure`` writes PDF (for the
report) and PNG (for the README) with no timestamps or software stamps in their metadata, so
the same data give byte-identical files.
"""

from __future__ import annotations

from pathlib import Path

STYLE_FILE = Path(__file__).with_name("paper.mplstyle")
# Text width of the report in inches (article class, 1 in margins on A4 would be 6.27 in).
TEXT_WIDTH = 6.3

__all__ = ["use_style", "save_figure", "STYLE_FILE", "TEXT_WIDTH"]


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


def save_figure(fig, path: str | Path, formats: tuple[str, ...] | None = None) -> list[Path]:
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
        metadata = {"pdf": {"CreationDate": None, "ModDate": None, "Producer": None, "Creator": None},
                    "png": {"Software": None},
                    "svg": {"Date": None, "Creator": None}}.get(fmt, {})
        fig.savefig(out, format=fmt, metadata=metadata)
        written.append(out)
    return written
