"""The design stage's booktabs tables, declared for :mod:`impactdamper.reporting.texrecord`: the
design table (one row per device), the impact suppressors' loads, the best gap against the
second parameter and the design command's times (part of the design stage's record,
:mod:`impactdamper.studies.design.record`).

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the numbers come from the design stage's records (figures/design_*.json). Used by
``workflow/scripts/design_report.py``.
"""

from __future__ import annotations

import dataclasses

from impactdamper.reporting.texrecord import TEXT, Column, Format, Table, fixed, fixed_columns
from impactdamper.studies.design.record_rows import DEVICE_KEYS, DIGITS, device_name
from impactdamper.studies.design.verdict import device
from impactdamper.studies.vocabulary import SPEC, tex

__all__ = ["design_table", "loads_table", "second_table", "benchmark_table"]

TABLE_COMMENTS = ["Written by the design stage's report job; do not edit."]
# The gap's symbol without its unit: the design table's columns are in x_st.
GAP_SHORT = SPEC["gap"].symbol.split("/")[0]


def _brace(text: str) -> str:
    """``text`` with its braces doubled, for a header that str.format fills."""
    return text.replace("{", "{{").replace("}", "}}")


DESIGN_TABLE = Table(
    colspec="lrrrrrrrrrrrr",
    header=(
        f"device & ${GAP_SHORT}$ & {tex('N')} & {tex('delta2')} & {tex('R')} & peak & band & detuned & force "
        f"& {tex('R')} drift & absorber & all & stroke"
    ),
    comments=TABLE_COMMENTS,
    columns=[
        Column(lambda d: d, Format(device_name)),
        *(Column(lambda d, k=k: d["parameters"].get(k), fixed(DIGITS[k], "")) for k in DIGITS),
        *fixed_columns({"peak": 3, "band_average": 3}),
        *fixed_columns({f"worst.{w}": 2 for w in ("detuning", "force", "restitution", "absorber", "together")}),
        Column(lambda d: None if d["device"] == "bare object" else d["stroke"], fixed(1, "---")),
    ],
)


def design_table(opt: dict) -> str:
    """The design table (booktabs): each row's name, parameters, located peak, band average,
    worst peaks over each uncertainty and over all together, and stroke (:data:`DEVICE_KEYS`'
    order; a whole-box row with its within-reach row's design left out: :func:`_distinct`)."""
    return DESIGN_TABLE.render(_distinct(opt))


def _distinct(opt: dict) -> list[dict]:
    """The table's rows, a whole-box row equal to its within-reach row left out."""
    rows = [device(opt, name) for name in DEVICE_KEYS.values()]
    twins = {"impact_peak": "impact_peak_reach", "impact_band_average": "impact_band_average_reach"}
    by_name = {d["device"]: d for d in rows}
    return [
        d for d in rows if not (d["device"] in twins and d["parameters"] == by_name[twins[d["device"]]]["parameters"])
    ]


LOADS_TABLE = Table(
    colspec="lrrrrr",
    header="device & stroke & pulse & impacts/period & impacts/hour & contact force",
    comments=TABLE_COMMENTS,
    columns=[
        Column(lambda d: d, Format(device_name)),
        *fixed_columns({"stroke": 1, "pulse": 2, "impacts_per_period": 1}),
        Column("impacts_per_hour", Format(lambda v: f"{v:,.0f}".replace(",", "\\,"))),
        Column("contact_force", fixed(0)),
    ],
)


def loads_table(opt: dict) -> str:
    """The impact suppressors' loads (booktabs): stroke, largest pulse (P0/omega1), impacts per
    period and per hour, peak contact force (P0); a design that never impacts left out."""
    return LOADS_TABLE.render([d for d in _distinct(opt) if d["kind"] == "impact" and d["impacts"]])


SECOND_TABLE = Table(
    colspec="rrrrrr",
    header=f"{{}} & best {_brace(tex('gap'))} & peak & {tex('theta')} of the peak & good gaps & pulse",
    comments=TABLE_COMMENTS,
    columns=[
        *fixed_columns({"second": 2, "gap": 2, "value": 2, "peak_theta": 3}),
        Column(lambda b: f"{fixed(2)(b['good_from'])} to {fixed(2)(b['good_to'])}"),
        Column("peak_impulse", fixed(2)),
    ],
)


def second_table(chart2: dict) -> str:
    """The booktabs table of the best gap (peak criterion) against the second parameter."""
    name = chart2["parameter"]
    symbol = f"${SPEC[name].symbol}$" if name in SPEC else name
    table = dataclasses.replace(SECOND_TABLE, header=SECOND_TABLE.header.format(symbol))
    return table.render([b for b in chart2["best"] if b["criterion"] == "peak"])


BENCHMARK_TABLE = Table(
    colspec="rrrrrrl",
    header=f"{tex('mu')} & {tex('delta1')} & wall (s) & processor (s) & longest silence (s) & evaluations & recommendation",
    comments=TABLE_COMMENTS,
    columns=[
        *fixed_columns({"mu": 2, "delta1": 2, "elapsed": 0}),
        Column("cpu", fixed(0, "---")),
        Column("longest_silence", fixed(1, "---")),
        Column("evaluations", TEXT),
        Column("first", TEXT),
    ],
)


def benchmark_table(bench: dict) -> str:
    """The design command's times at the benchmark's objects (booktabs)."""
    return BENCHMARK_TABLE.render(bench["objects"])
