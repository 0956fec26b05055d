"""The abstract's answer of the design study, from its design table (a
:func:`~impactdamper.studies.design.optimum.design_optima` record): which device to build and the
comparisons behind it, in brief (``DesignAbstractAnswer``) and in one clause
(``DesignAbstractShort``)."""

from __future__ import annotations

from impactdamper.reporting.texrecord import fixed
from impactdamper.studies.design.verdict import comparisons, device, recommendation


def abstract_answer(opt: dict) -> str:
    """The abstract's answer (TeX): which device, and the comparisons behind it in brief."""
    u = opt["uncertainty"]
    what = {
        "peak": "at the nominal peak",
        "band_average": "on the band average",
        "detuning": f"with the object's natural frequency off by $\\pm{100 * u['detuning']:g}\\,\\%$",
        "force": f"with the force between {u['force'][0]:g} and {u['force'][1]:g} times its design value",
        "restitution": f"with the stop's restitution drifting by $\\pm{u['restitution']:g}$",
        "absorber": "with the absorber's own spring and damper off",
        "together": "with all of these at once",
        "stroke": "with the travel limited",
    }
    first = recommendation(opt).split(":")[0]
    parts = []
    for c in comparisons(opt):
        if c["winner"] == "infeasible":
            continue
        verb = {
            "tie": "they are equal",
            "TMD": "the TMD is lower",
            "impact": "the impact suppressor is lower",
            "tmd_limit": "no impacting design beats the TMD",
        }
        parts.append(
            f"{what[c['criterion']]} {verb[c['winner']]} (impact {fixed(2)(c['impact'])}, TMD {fixed(2)(c['tmd'])})"
        )
    return f"{first[0].lower()}{first[1:]}, since " + "; ".join(parts)


def abstract_short(opt: dict) -> str:
    """The abstract's answer in one clause (TeX): the recommendation's first words, on how many
    compared criteria the impact suppressor is lower, and what the impact optimum of the nominal
    peak costs beside the TMD's (travel, stop force, impacts an hour)."""
    first = recommendation(opt).split(":")[0]
    cs = [c for c in comparisons(opt) if c["winner"] != "infeasible"]
    lower = [c["criterion"] for c in cs if c["winner"] == "impact"]
    hit, tmd = device(opt, "impact_peak_reach"), device(opt, "tmd_peak")
    per_hour = f"{hit['impacts_per_hour']:,.0f}".replace(",", r"\,")
    wins = (
        "on none of them" if not lower else f"on {len(lower)} ({', '.join(CRITERION_WORDS.get(c, c) for c in lower)})"
    )
    return (
        f"{first[0].lower()}{first[1:]}: of {len(cs)} criteria compared the impact suppressor is lower {wins}, "
        f"and its nominal optimum travels {fixed(1)(hit['stroke'])} against the TMD's {fixed(1)(tmd['stroke'])}"
        rf"\,$x_{{\mathrm{{st}}}}$, with stop forces of {fixed(0)(hit['contact_force'])}\,$P_0$ and "
        f"{per_hour} impacts an hour"
    )


# Short names of the criteria, for the abstract.
CRITERION_WORDS = {
    "peak": "the nominal peak",
    "band_average": "the band average",
    "detuning": "detuning",
    "force": "the force",
    "restitution": "the restitution",
    "absorber": "the absorber's mistuning, between the nominal optima",
    "together": "all together",
    "stroke": "the travel limit",
}
