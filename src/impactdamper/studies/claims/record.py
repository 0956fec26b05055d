"""The claims stage's record for the report, declared for :mod:`impactdamper.reporting.texrecord`:
where the paper's Fig. 2 claims hold beyond the gap, i.e. the macros of the nearest reproducing
set in all seven parameters and the round values, the refinement of the one-parameter search,
the pair maps, and the located range's end checks counted by what they rest on; and the table
of the nearest interval where both claims hold, per parameter.

Replication of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (beyond its
stated point). Used by ``workflow/scripts/claims_macros.py`` and ``claims_gather.py``.
"""

from __future__ import annotations

from impactdamper.reporting.latex import MacroFile
from impactdamper.reporting.texrecord import COUNT, YES_NO, Column, Format, Macro, Table, fixed, macro_lines, percent
from impactdamper.reporting.texrecord import general, macros_named_by_path, sci
from impactdamper.studies.claims.claims_evaluator import NEAREST_NAMES
from impactdamper.studies.claims.search import SEARCH_PARAMETERS
from impactdamper.studies.replication.gapscan import count_end_checks
from impactdamper.studies.vocabulary import SPEC, tex

NORM_TAG = {"max": "Max", "euclidean": "Euclid"}

# The nearest set's search (figures/claims_nearest.json: st, its settings; joint, its answers).
SEARCH = (
    Macro("NearestMarginPct", lambda n: float(n["st"]["margin"]), percent(1)),
    Macro("NearestRays", "joint.rays.count", COUNT),
    Macro("NearestRandomRays", "joint.rays.random", COUNT),
    Macro("NearestRayStepPct", lambda n: float(n["st"]["ray_step"]), percent(1)),
    Macro("NearestRayMaxPct", lambda n: float(n["st"]["ray_max"]), percent(0)),
    Macro("NearestRayHits", "joint.rays.hits", COUNT),
    Macro("NearestPoints", lambda n: n["joint"].get("points", 0), COUNT),
    Macro("NearestStarts", "st.starts", COUNT),
    Macro("NearestCompassFloorPct", lambda n: float(n["st"]["compass_floor"]), percent(2)),
    Macro("NearestScreenPeriods", "st.max_periods", COUNT),
)
# Each parameter's value and relative change in one norm's answer ({N}: Max or Euclid, {P} the
# parameter's macro part; the answer None where the norm found none).
VALUE = (Macro("Nearest{N}{P}", "value", fixed(4)), Macro("Nearest{N}{P}Pct", "u", percent(1)))
GAP_VALUE = (Macro("Nearest{N}{P}", "value", fixed(3)), Macro("Nearest{N}{P}Pct", "u", percent(1)))
# One norm's answer: its distance, the margin ball and the verification by the other methods.
ANSWER = (
    Macro("Nearest{N}DistMaxPct", "distance.max", percent(1)),
    Macro("Nearest{N}DistEuclidPct", "distance.euclidean", percent(1)),
    Macro("Nearest{N}BallHold", lambda a: (a or {}).get("margin_check", {}).get("hold", 0), COUNT),
    Macro("Nearest{N}BallPoints", lambda a: (a or {}).get("margin_check", {}).get("points", 0), COUNT),
    Macro("Nearest{N}AlgOneEndDiff", "verification.claim_a.interval_end_difference_over_T", sci()),
    Macro("Nearest{N}AlgOneResidual", "verification.claim_a.periodicity_residual", sci()),
    Macro("Nearest{N}IvpTimeDiff", "verification.claim_b.max_time_difference_over_T", sci()),
    Macro("Nearest{N}IvpVelocityDiff", "verification.claim_b.max_velocity_difference_rel", sci()),
    Macro("Nearest{N}ReferencePeriods", "verification.claim_b.reference_periods", COUNT),
    Macro(
        "Nearest{N}Verified",
        lambda a: bool(a and (v := a["verification"]) and v["both_hold_every_method"] and v["agree"]),
        YES_NO,
    ),
)


def _round_text(rows: list[dict], tex: bool) -> str:
    """The reproducing round values, nearest first: "theta = 0.9 (10.0 %), ..." with a note
    where the margin ball fails."""
    parts = []
    for r in rows:
        ((name, v),) = r["changes"].items()
        note = "" if r["robust"] else ", not at the margin"
        if tex:
            parts.append(f"${SPEC[name].symbol}={v:g}$ (${percent(1)(r['distance']['max'])}\\,\\%${note})")
        else:
            parts.append(f"{SPEC[name].plain} = {v:g} ({100 * r['distance']['max']:.1f} %{note})")
    return ", ".join(parts) if parts else "none"


# The round values one digit away (rows: those reproducing both claims; off: those whose methods
# differ). A list of TeX symbols has its own README text.
ROUND = (
    Macro("RoundCandidates", "candidates", COUNT),
    Macro("RoundReproducing", lambda rv: len(rv["rows"]), COUNT),
    Macro("RoundList", lambda rv: _round_text(rv["rows"], True), text=lambda rv: _round_text(rv["rows"], False)),
    Macro(
        "RoundTuningList", lambda rv: _round_text(rv["tuning"], True), text=lambda rv: _round_text(rv["tuning"], False)
    ),
    Macro("RoundAgreeCount", lambda rv: sum(r["verification"]["agree"] for r in rv["rows"]), COUNT),
    Macro("RoundOffList", lambda rv: _round_text(rv["off"], True) if rv["off"] else "none"),
    # compared with a tolerance: three digits, so that a value just above it never prints as it
    Macro("RoundOffVelocityDiff", "off.0?.verification.claim_b.max_velocity_difference_rel", sci(2)),
)
# The one-parameter search's refinement (per: its parameters' records; dep: the solver-dependent
# ends as (name, value)).
REFINEMENT = (
    Macro("ClaimsRefineLevels", "refine_levels", COUNT),
    Macro("ClaimsRefineAdded", lambda s: sum(d["refinement"]["added"] for d in s["per"]), COUNT),
    Macro("ClaimsRefinePoints", lambda s: sum(d["refinement"]["points"] for d in s["per"]), COUNT),
    Macro("ClaimsRefineRescued", lambda s: sum(d["refinement"]["rescued"] for d in s["per"]), COUNT),
    Macro("ClaimsRefineNonperiodic", lambda s: sum(d["refinement"]["nonperiodic"] for d in s["per"]), COUNT),
    Macro("ClaimsSolverDependentCount", lambda s: len(s["dep"]), COUNT),
    Macro(
        "ClaimsSolverDependentList",
        lambda s: ", ".join(f"${SPEC[n].symbol}={x:.4f}$" for n, x in s["dep"]) if s["dep"] else "none",
    ),
    Macro("ClaimsBothIntervals", lambda s: sum(len(d["intervals"]["both"]) for d in s["per"]), COUNT),
)
# Each pair map's cells ({M}: the map's parameters' macro parts, RGap).
MAP = (
    Macro("Map{M}Cells", len, COUNT),
    Macro("Map{M}BothCells", lambda rows: sum(r["both"] == "true" for r in rows), COUNT),
)
# How a map's grid was computed (its settings' ``grid``, studies/claims/maps.adaptive_claims_map).
GRID = (
    Macro("Map{M}ComputedCells", "computed", COUNT),
    Macro("Map{M}ComputedShare", lambda g: 100 * g["computed_share"], general(r"{:.1f}\,\%")),
    *macros_named_by_path(
        "Map{M}", ("coarse_step", "check.rows", "check.filled", "check.differences", "check.label_differences"), COUNT
    ),
)


# The filled points of every map's check rows (computed in full as well), in words.
def _filled_check_text(grids: dict) -> str:
    """How many filled points of the maps' check rows differ from their computed values, in
    words (``none of the 495 ...`` rather than a row of zeros)."""
    filled = sum(g["check"]["filled"] for g in grids.values())
    differ = sum(g["check"]["differences"] for g in grids.values())
    head = "none" if differ == 0 else f"${differ}$"
    return f"{head} of the ${filled}$ filled points of the rows also computed in full as a check {'differs' if differ < 2 else 'differ'}"


# The located range's end checks, by what they rest on (count_end_checks).
END_CHECKS = (
    Macro("EndChecksTotal", "checks", COUNT),
    Macro("EndChecksWithinCount", "compared_within", COUNT),
    Macro("EndChecksNothingCount", "nothing_to_compare", COUNT),
    Macro("EndChecksOutsideCount", "outside_tolerance", COUNT),
    Macro("EndChecksDifferentCount", "different_verdict", COUNT),
)


def _map_tag(name: str) -> str:
    """A pair map's part of the macro names: its parameters' (``theta_gap`` -> ``ThetaGap``)."""
    parts = name.split("_")
    return "".join(SPEC[p].macro for p in parts) if all(p in SPEC for p in parts) else name.replace("_", "")


def macros(nearest: dict, search: dict, maps: dict, located: dict, grids: dict | None = None) -> MacroFile:
    """The macros of where the claims hold beyond the gap.

    Parameters
    ----------
    nearest : dict
        figures/claims_nearest.json: the nearest reproducing set (max and Euclidean norms) and
        the round values.
    search : dict
        figures/claims_by_parameter_settings.json: the one-parameter search and its refinement.
    maps : dict
        The pair maps' rows (figures/claims_map*.csv) by map name.
    located : dict
        figures/located_case.json: the located range's end checks.
    grids : dict, optional
        How each map's grid was computed (its settings' ``grid``) by map name.

    Returns
    -------
    MacroFile
        The macros, in the order the report's record lists them.
    """
    m = MacroFile(
        ["% Where the claims hold beyond the gap. Generated by workflow/scripts/claims_macros.py; do not edit."]
    )
    joint = nearest["joint"]
    m.extend(macro_lines(SEARCH, {"st": nearest["settings"], "joint": joint}))
    for which, tag in NORM_TAG.items():
        a = joint["answers"].get(which)
        for name in NEAREST_NAMES:
            value = {"value": a["values"][name], "u": a["u"][name]} if a else None
            m.extend(macro_lines(GAP_VALUE if name == "gap" else VALUE, value, N=tag, P=SPEC[name].macro))
        m.extend(macro_lines(ANSWER, a, N=tag))
    rows = nearest["round_values"]["reproducing"]
    rv = {
        "candidates": nearest["round_values"]["candidates"],
        "rows": rows,
        "tuning": [r for r in rows if r["keeps_tuning_condition"]],
        "off": [r for r in rows if not r["verification"]["agree"]],
    }
    m.extend(macro_lines(ROUND, rv))
    per = [search["parameters"][n] for n in SEARCH_PARAMETERS]
    dep = [(n, x) for n in SEARCH_PARAMETERS for x in search["parameters"][n]["solver_dependent_ends"]]
    m.extend(macro_lines(REFINEMENT, {"refine_levels": search["refine_levels"], "per": per, "dep": dep}))
    for name, map_rows in maps.items():
        m.extend(macro_lines(MAP, map_rows, M=_map_tag(name)))
        if grids and name in grids:
            m.extend(macro_lines(GRID, grids[name], M=_map_tag(name)))
    if grids:
        m.add("MapsFilledCheckText", _filled_check_text(grids))
    m.extend(macro_lines(END_CHECKS, count_end_checks(located["end_checks"])))
    return m


# --- the table of the nearest interval where both claims hold, per parameter --------------------
def _end(iv: dict, side: str, flagged: list) -> str:
    """An interval's end: ``*`` where it reaches the searched range's end, a dagger where the
    solvers disagree in its final bracket."""
    x = iv[side]
    return f"{x:.4f}" + ("^{*}" if iv[side + "_open"] else "") + ("^{\\dagger}" if x in flagged else "")


TABLE = Table(
    colspec="lrllllr",
    header="parameter & stated & searched & step / floor & both claims hold on & width & distance",
    comments=[
        "Where both claims of the paper's Fig. 2 hold, each parameter alone at the stated gap.",
        "Generated by workflow/scripts/claims_gather.py (Snakemake rule claims_by_parameter); do not edit.",
    ],
    columns=[
        Column("name", Format(tex)),
        Column("near.stated", Format("${:g}$".format)),
        Column("range", Format(lambda r: f"${r['start']:g}$--${r['stop']:g}$")),
        Column("refinement", Format(lambda r: f"${r['step']:.3g}$ / ${r['floor']:.2g}$" if r else "")),
        Column("interval", Format(lambda iv: f"$[{iv[0]}, {iv[1]}]$")),
        Column("width", Format("${:.4f}$".format)),
        Column("near", Format(lambda n: f"${n['distance']:.4f}$ (${100 * n['relative_distance']:.1f}\\,\\%$)")),
    ],
)


def table(per: dict) -> str:
    """Booktabs table: per parameter, the searched range, the interval where both claims hold
    nearest the stated value (an end at the range's edge marked), its width and distance
    (figures/claims_by_parameter_settings.json's parameters)."""
    rows = []
    for name in SEARCH_PARAMETERS:
        d = per[name]
        near = d["nearest_both"]
        iv = next(
            (
                r
                for r in d["intervals"]["both"]
                if near["nearest"] is not None and r["lo"] <= near["nearest"] <= r["hi"]
            ),
            None,
        )
        row = {"name": name, "near": near, "range": d["range"], "refinement": d.get("refinement") or {}}
        if iv is None:
            rows.append(" & ".join(TABLE.cells(row, 4)) + " & nowhere & & \\\\")
            continue
        flagged = d["solver_dependent_ends"]
        rows.append(
            {**row, "interval": (_end(iv, "lo", flagged), _end(iv, "hi", flagged)), "width": iv["hi"] - iv["lo"]}
        )
    return TABLE.render(rows)
