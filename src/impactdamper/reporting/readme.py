"""The README's block of results: the pieces that figures/readme_summary.md is written from
(``workflow/scripts/readme_summary.py`` writes the text).

Every number comes from the report stages' records (:class:`impactdamper.reporting.latex.MacroFile`)
and the impact tables (figures/impacts_*.csv) of the replication of Timofeev et al. (2019), DOI
10.18698/0236-3941-2019-1-90-100.
"""

from __future__ import annotations

import csv

from impactdamper.reporting.latex import macro_texts
from impactdamper.reporting.records import read_json


def read_records(paths: list[str]) -> dict[str, str]:
    """The records' macros by name, as plain text."""
    return macro_texts(*(read_json(path) for path in paths))


def impact_table(path: str) -> list[str]:
    """A Markdown table of one cycle's impacts (figures/impacts_*.csv): time after the first
    impact, forcing phase, closing velocity and impulse, each relative."""
    with open(path, newline="") as f:  # closed: the tests turn a ResourceWarning into an error
        rows = list(csv.DictReader(f))
    lines = [
        "| impact | (t - t1)/T | forcing phase t/T mod 1 | closing velocity v/(x_st omega) | impulse S/(m1 x_st omega) |",
        "|---|---:|---:|---:|---:|",
    ]
    for r in rows:
        name = r["impact"] + (" (next cycle)" if r["next_cycle"] == "true" else "")
        lines.append(
            f"| {name} | {float(r['t_over_T']):.4f} | {float(r['phase']):.4f} | "
            f"{float(r['velocity_rel']):.3f} | {float(r['impulse_rel']):.4f} |"
        )
    return lines


def beyond(m: dict[str, str], key: str, name: str) -> str:
    """Where both claims hold nearest the stated value of one parameter searched alone
    (figures/claims_by_parameter.csv), in words: ``key`` is the parameter's part of the macro
    names (``DeltaOne``), ``name`` its plain name."""
    tag = "Claims" + key
    if m[tag + "NearestBoth"] == "–":
        return f"{name}: nowhere in the searched range (stated {m[tag + 'Stated']})"
    edge = ", reaching the end of the searched range" if m[tag + "BothOpen"] == "yes" else ""
    return (
        f"{name} in [{m[tag + 'BothLo']}, {m[tag + 'BothHi']}] (width {m[tag + 'BothWidth']}{edge}; stated "
        f"{m[tag + 'Stated']}, {m[tag + 'RelDistance']} % away)"
    )
