"""The design table's rows as the report names and quotes them (part of the design stage's
record, :mod:`impactdamper.studies.design.record`): each row's macro part and name, its worst
branch in words, and the macros every row gets (its designed parameters, located peak, band
average, worst peaks, stroke), an impact suppressor's loads and a searched row's search.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the numbers come from the design table (figures/design_optimum.json).
"""

from __future__ import annotations

from impactdamper.reporting.texrecord import TEXT, Format, Macro, fixed, macro_lines, tex_sci
from impactdamper.studies.design.devices import IMPACT_NAMES
from impactdamper.studies.design.verdict import device
from impactdamper.studies.vocabulary import SPEC

__all__ = ["DIGITS", "SYMBOLS", "DEVICE_KEYS", "device_name", "at_bound_text", "rows", "row_macros"]


# The impact suppressor's designed parameters, their decimals, and their symbols as the design
# section writes them.
DIGITS = dict(zip(IMPACT_NAMES, (2, 3, 3, 2)))
SYMBOLS = {k: SPEC[k].symbol for k in DIGITS}

# The design table's rows by their macro part (the record's ``device`` keys).
DEVICE_KEYS = {
    "BareDev": "bare object",
    "TmdOpt": "tmd_peak",
    "Hit": "impact_peak_reach",
    "Opt": "impact_peak",
    "TmdAvgOpt": "tmd_band_average",
    "HitAvg": "impact_band_average_reach",
    "OptAvg": "impact_band_average",
    "RobTmd": "tmd_detuning",
    "RobImp": "impact_detuning",
    "ForceImp": "impact_force",
    "RestImp": "impact_restitution",
    "StrokeTmd": "tmd_stroke",
    "StrokeImp": "impact_stroke",
}
# How the report names each row: the device and the criterion it is optimal for.
NAMES = {
    "bare object": "bare object",
    "tmd_peak": "TMD, peak",
    "impact_peak_reach": "impact, peak",
    "impact_peak": "impact, peak, whole box",
    "tmd_band_average": "TMD, band average",
    "impact_band_average_reach": "impact, band average",
    "impact_band_average": "impact, band avg., whole box",
    "tmd_detuning": "TMD, detuned",
    "impact_detuning": "impact, detuned",
    "impact_force": "impact, force",
    "impact_restitution": "impact, $R$ drift",
    "tmd_stroke": "TMD, travel limit",
    "impact_stroke": "impact, travel limit",
}


def device_name(d: dict) -> str:
    """A row's name in the report: a row that never reaches its stop is the TMD limit."""
    name = NAMES[d["device"]]
    if d.get("tmd_limit"):
        name += ": TMD limit"
    if d.get("feasible") is False:
        name += " (over the limit)"
    return name


def _branch_words(branch: str) -> str:
    """A worst branch's description (``up, 1/1, branch end``; ``linear``) in words."""
    if branch == "linear":
        return "the linear response's resonance"
    source, label, kind = (part.strip() for part in branch.split(","))
    if source == "no contact":
        return "the motion without contact" + (", where it first touches the stop" if kind == "first contact" else "")
    where = {"maximum": "a smooth maximum", "branch end": "the end of its branch", "sample": "a sample"}[kind]
    who = {"up": "the upward sweep's", "down": "the downward sweep's", "random": "a random start's"}[source]
    return f"{who} {label} motion, {where}"


# A row's macros ({D}: the row's macro part): designed parameters, criteria, stroke.
PARAMETER = {k: Macro("Design{D}{P}", f"parameters.{k}", fixed(d)) for k, d in DIGITS.items()}
ROW = (
    Macro("Design{D}LocPeak", "peak", fixed(3)),
    Macro("Design{D}LocTheta", "peak_theta", fixed(3)),
    Macro("Design{D}Avg", "band_average", fixed(3)),
    Macro("Design{D}WorstLarge", "worst.detuning", fixed(2)),
    Macro("Design{D}WorstForce", "worst.force", fixed(2)),
    Macro("Design{D}WorstRest", "worst.restitution", fixed(2)),
    Macro("Design{D}WorstAll", "worst.together", fixed(2)),
    Macro("Design{D}WorstAbsorber", "worst.absorber", fixed(2)),
    Macro("Design{D}Stroke", "stroke", fixed(1)),
    Macro("Design{D}Branch", "peak_branch", Format(_branch_words)),
)
# An impact row's loads and search record.
IMPACT_ROW = (
    Macro("Design{D}Pulse", "pulse", fixed(2)),
    Macro("Design{D}ImpactsPerPeriod", "impacts_per_period", fixed(1)),
    Macro("Design{D}ImpactsPerHour", "impacts_per_hour", Format(lambda v: f"{v:,.0f}".replace(",", "\\,"))),
    Macro("Design{D}ContactForce", "contact_force", fixed(0)),
    Macro("Design{D}MeanForce", "mean_force", fixed(2)),
    Macro("Design{D}Floor", "no_contact_floor", fixed(3)),
)
SEARCH = (
    Macro("Design{D}Evaluations", lambda d: sum(d["search"]["evaluations"].values()), TEXT),
    Macro("Design{D}CheckGain", lambda d: max(d["search"]["check"]["largest_gain"], 0.0), tex_sci(1)),
    Macro("Design{D}AtBound", lambda d: at_bound_text(d["search"]["at_bound"])),
    Macro("Design{D}Spread", lambda d: 100 * d["search"]["starts"]["spread"], fixed(2)),
    Macro("Design{D}StartCount", "search.starts.starts", TEXT),
)


def at_bound_text(names) -> str:
    """The parameters at a bound of a box as symbols (``none`` if none)."""
    return ", ".join(f"${SYMBOLS[n]}$" for n in names) or "none"


def rows(opt: dict) -> dict[str, dict]:
    """The design table's rows by their macro part (:data:`DEVICE_KEYS`)."""
    return {key: device(opt, name) for key, name in DEVICE_KEYS.items()}


def row_macros(d: dict[str, dict]) -> list:
    """The rows' macros (``d``: the rows by macro part, :func:`rows`): designed parameters,
    criteria, stroke; an impact row's loads; a searched row's search."""
    out = []
    for key, row in d.items():
        for k in DIGITS:
            if k in row["parameters"]:
                out += macro_lines([PARAMETER[k]], row, D=key, P=SPEC[k].macro)
        out += macro_lines(ROW, row, D=key)
        if row["kind"] == "impact":
            out += macro_lines(IMPACT_ROW, row, D=key)
        if "search" in row:
            out += macro_lines(SEARCH, row, D=key)
    return out
