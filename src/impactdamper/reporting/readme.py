"""The README's block of results: the pieces that figures/readme_summary.md is written from
(``workflow/scripts/readme_summary.py`` writes the rows).

Every number comes from the report stages' records (:class:`impactdamper.reporting.latex.MacroFile`)
of the replication of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100, and its
extension.
"""

from __future__ import annotations

from collections.abc import Sequence

from impactdamper.reporting.latex import macro_texts
from impactdamper.reporting.records import read_json

# The results table's columns.
RESULTS_HEADER = ("claim or question", "verdict or answer", "evidence", "in the report")


def read_records(paths: list[str]) -> dict[str, str]:
    """The records' macros by name, as plain text."""
    return macro_texts(*(read_json(path) for path in paths))


def _cell(text: str) -> str:
    """A Markdown table cell: its pipes escaped, on one line."""
    return " ".join(str(text).split()).replace("|", "\\|")


def results_table(rows: Sequence[Sequence[str]]) -> list[str]:
    """A Markdown table of results, one line per row (claim or question, verdict or answer,
    evidence, the report's section), with its header."""
    lines = ["| " + " | ".join(RESULTS_HEADER) + " |", "|" + "---|" * len(RESULTS_HEADER)]
    for row in rows:
        if len(row) != len(RESULTS_HEADER):
            raise ValueError(f"`rows` has a row of {len(row)} cells: a results row has {len(RESULTS_HEADER)}")
        lines.append("| " + " | ".join(_cell(c) for c in row) + " |")
    return lines
