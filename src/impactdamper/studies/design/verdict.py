"""The verdict of a design table (:func:`impactdamper.studies.design.optimum.design_optima`):
its rows by name, the headline pair of one criterion (the impact suppressor against the TMD,
each optimal for it) and their ratio, each criterion's comparison and the one plain
recommendation they make, differences within :data:`TIE` counted as equal.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): it reads the record's numbers only, it computes none.
"""

from __future__ import annotations

__all__ = ["TIE", "WHAT", "device", "headline", "comparisons", "recommendation"]

# Two devices whose criteria differ by less than this (relative) are equal for a designer.
TIE = 0.02


def device(record: dict, key: str) -> dict:
    """The row ``key`` of a design table (a :func:`~impactdamper.studies.design.optimum.design_optima`
    record; ValueError naming it if absent)."""
    for d in record["devices"]:
        if d["device"] == key:
            return d
    keys = ", ".join(repr(d["device"]) for d in record["devices"])
    raise ValueError(f"`device` = {key!r} is not allowed: must be one of {keys}")


def _value(row: dict, criterion: str) -> float:
    """A row's value of ``criterion``: its peak, band average or worst peak."""
    if criterion in ("peak", "stroke"):
        return row["peak"]
    if criterion == "band_average":
        return row["band_average"]
    return row["worst"][criterion]


def headline(record: dict, criterion: str) -> dict:
    """``impact`` (the impact suppressor with its stop within reach, optimal for ``criterion``),
    ``tmd`` (the TMD optimal for it: for the force and restitution, the nominal one, which
    they leave unchanged), ``tmd_equal_stroke`` and ``ratio`` (impact over TMD)."""
    key_i = {"peak": "impact_peak_reach", "band_average": "impact_band_average_reach"}.get(
        criterion, f"impact_{criterion}"
    )
    key_t = {"band_average": "tmd_band_average", "detuning": "tmd_detuning"}.get(criterion, "tmd_peak")
    imp, tmd = device(record, key_i), device(record, key_t)
    return {
        "impact": imp,
        "tmd": tmd,
        "tmd_equal_stroke": device(record, "tmd_stroke"),
        "ratio": {
            "criterion": _value(imp, criterion) / _value(tmd, criterion),
            "peak": imp["peak"] / tmd["peak"],
            "band_average": imp["band_average"] / tmd["band_average"],
            "worst_case": imp["worst"]["detuning"] / tmd["worst"]["detuning"],
        },
    }


def _compare(imp: float, tmd: float) -> str:
    if abs(imp - tmd) <= TIE * min(imp, tmd):
        return "tie"
    return "TMD" if tmd < imp else "impact"


def comparisons(record: dict) -> list[dict]:
    """The recommendation's comparisons, one per criterion: the impact suppressor with its stop
    within reach against the TMD, each optimal for that criterion (for the force and the
    restitution the TMD is its nominal optimum, unchanged by them), their values and the winner
    (``tie`` within TIE)."""
    pairs = (
        ("peak", "impact_peak_reach", "tmd_peak"),
        ("band_average", "impact_band_average_reach", "tmd_band_average"),
        ("detuning", "impact_detuning", "tmd_detuning"),
        ("force", "impact_force", "tmd_peak"),
        ("restitution", "impact_restitution", "tmd_peak"),
        ("absorber", "impact_peak_reach", "tmd_peak"),
        ("together", "impact_peak_reach", "tmd_peak"),
        ("stroke", "impact_stroke", "tmd_stroke"),
    )
    out = []
    present = {d["device"] for d in record["devices"]}
    for c, ki, kt in pairs:
        if ki not in present or kt not in present:
            continue  # (a robust row not searched: the command's nominal answer)
        i, t = device(record, ki), device(record, kt)
        if c in i["worst"] and c in t["worst"] or c not in ("absorber", "together"):
            vi, vt = _value(i, c), _value(t, c)
            if vi != vi or vt != vt:
                continue  # (a worst case not evaluated, NaN: the nominal answer's robust columns)
            out.append({"criterion": c, "impact": vi, "tmd": vt, "winner": _winner(c, i, t, vi, vt)})
            if c == "stroke" and i["feasible"] != t["feasible"]:  # decided by the limit, not the peaks
                loser = t if i["feasible"] else i
                out[-1].update(only=True, other_stroke=loser["stroke"], other_at_bound=list(loser.get("at_bound", [])))
    return out


def _winner(c: str, i: dict, t: dict, vi: float, vt: float) -> str:
    """The winner of one comparison; under the travel limit only designs that keep it count
    (``infeasible`` when neither does), and an impact design that never reaches its stop is the
    TMD limit (``tmd_limit``), not an impact suppressor."""
    if c != "stroke":
        return _compare(vi, vt)
    if not (i["feasible"] or t["feasible"]):
        return "infeasible"
    if not t["feasible"]:
        return "impact"
    if not i["feasible"]:
        return "TMD"
    return "tmd_limit" if not i["impacts"] else _compare(vi, vt)


WHAT = {
    "peak": "tuned to a known frequency, at the peak",
    "band_average": "on the band average",
    "detuning": "with the object's frequency off by up to {pm}{d}{pct}, in the worst case",
    "force": "with the force between {a0} and {a1} times the design force, in the worst case",
    "restitution": "with the restitution drifting by up to {pm}{r}, in the worst case",
    "absorber": "with the absorber's spring off by up to {pm}{k}{pct} and its damper by {pm}{c}{pct}, "
    "the nominal optima in the worst case",
    "together": "with all of these at once, the nominal optima in the worst case",
    "stroke": "with the travel limited to {S}{xst}",
}


def recommendation(
    record: dict, pm: str = "+-", pct: str = " %", xst: str = " x_st", p0: str = " P0", f1: str = "f1", sep: str = ","
) -> str:
    """One plain recommendation from a design table (a
    :func:`~impactdamper.studies.design.optimum.design_optima` record): which device to build, on
    each criterion's pair of optima (:func:`comparisons`), differences within TIE counted as
    equal (``pm``, ``pct``, ``xst``, ``p0``, ``f1``, ``sep``: how to write plus-minus, per cent, the
    units x_st and P0, the object's natural frequency and the thousands separator)."""
    u = record["uncertainty"]
    fmt = dict(
        pm=pm,
        pct=pct,
        d=f"{100 * u['detuning']:g}",
        a0=f"{u['force'][0]:g}",
        a1=f"{u['force'][1]:g}",
        r=f"{u['restitution']:g}",
        k=f"{100 * u.get('stiffness', 0.0):g}",
        c=f"{100 * u.get('damping', 0.0):g}",
        S=f"{record['max_stroke']:.2f}",
        xst=xst,
    )
    cs = comparisons(record)
    wins = {c["criterion"]: c["winner"] for c in cs}
    # (the criteria each device is optimised for: the absorber's and the combined worst cases
    # compare the nominal optima, and are reported beside them)
    robust = [wins[c] for c in ("detuning", "force", "restitution") if c in wins]
    if wins["peak"] != "impact" and "impact" not in robust:
        first = "Build the linear TMD"
    elif wins["peak"] == "impact" and "TMD" not in robust:
        first = "Build the impact suppressor"
    else:
        first = "Neither device wins everywhere"
    parts = []
    for c in cs:
        what = WHAT[c["criterion"]].format(**fmt)
        if c["winner"] == "infeasible":
            parts.append(f"{what} no design meets the limit")
        elif c["winner"] in ("TMD", "impact") and c.get("only"):
            name = "TMD" if c["winner"] == "TMD" else "impact suppressor"
            other = c["impact"] if c["winner"] == "TMD" else c["tmd"]
            parts.append(
                f"{what} only the {name} meets the limit ({c[c['winner'].lower()]:.2f}; the best other design "
                f"found, {other:.2f}, travels {c['other_stroke']:.2f}{xst}{_bounds_words(c['other_at_bound'])})"
            )
        elif c["winner"] == "tmd_limit":
            parts.append(
                f"{what} no impacting design beats the TMD: the best impact design keeps its stop out of reach "
                f"(the TMD limit, {c['impact']:.2f}; TMD {c['tmd']:.2f})"
            )
        elif c["winner"] == "tie":
            parts.append(
                f"{what} they are equal within {100 * TIE:g}{pct} (impact {c['impact']:.2f}, TMD {c['tmd']:.2f})"
            )
        else:
            lo, hi = (c["tmd"], c["impact"]) if c["winner"] == "TMD" else (c["impact"], c["tmd"])
            parts.append(
                f"{what} the {'TMD' if c['winner'] == 'TMD' else 'impact suppressor'} is lower ({lo:.2f} against {hi:.2f})"
            )
    missing = [c for c in ("detuning", "force", "restitution") if c not in wins]
    note = (
        f" Not searched: the optima for the {', '.join(missing)} (a robust criterion asks for them)." if missing else ""
    )
    return f"{first}: " + "; ".join(parts) + "." + _costs(record, xst, p0, f1, sep) + note


def _bounds_words(names) -> str:
    """', at a bound of its box: gap, N' (empty without one)."""
    return f", at a bound of its box: {', '.join(names)}" if names else ""


def _costs(record: dict, xst: str, p0: str, f1: str, sep: str) -> str:
    """What the impact suppressor optimal at the peak costs beside the TMD: its stroke, its stop
    force and its impacts per hour ('' when it does not impact)."""
    i, t = device(record, "impact_peak_reach"), device(record, "tmd_peak")
    if not i.get("impacts"):
        return ""
    per_hour = f"{round(i['impacts_per_hour'], -2):,.0f}".replace(",", sep)
    hertz = f"{f1} of {i['natural_frequency']:g} Hz"
    return (
        f" The impact suppressor optimal at the peak travels {i['stroke']:.1f}{xst} (the TMD {t['stroke']:.1f}{xst}, "
        f"{i['stroke'] / t['stroke']:.2f} times), meets its stop with up to {i['contact_force']:.0f}{p0} "
        f"(a stop {i['stop_stiffness']:g} times the object's spring) and {per_hour} times an hour "
        f"at a natural frequency {hertz}."
    )
