"""The Lyapunov stage's record for the report's section on Lyapunov exponents, declared for
:mod:`impactdamper.reporting.texrecord`: its macros, the table of Benettin's checks and the
benchmark's macros.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the numbers come from the stage's tables (figures/lyapunov_*.csv, .json) and the
config's run lengths; no number is typed by hand. Used by ``workflow/scripts/lyapunov_report.py``.
"""

from __future__ import annotations

import math
from collections import Counter

from impactdamper.analysis.lyapunov import (
    DEFAULT_BLOCKS,
    DEFAULT_TRANSIENT,
    DEFAULT_WARMUP,
    LABELS,
    MAX_SETTLED_PERIOD,
    SETTLE_SPAN,
    SETTLE_TOL,
    SIGNIFICANCE,
    ZERO_BAND,
)
from impactdamper.reporting import latex
from impactdamper.reporting.latex import MacroFile
from impactdamper.studies.vocabulary import tex
from impactdamper.reporting.texrecord import (
    COUNT,
    TEXT,
    Column,
    Format,
    Macro,
    Table,
    fixed,
    macro_lines,
    percent,
    bound,
    tex_sci,
    time,
)

__all__ = ["RECORD_WHAT", "lyapunov_macros", "benettin_table", "timing"]

# What the stage's record holds (results/report/lyapunov.json).
RECORD_WHAT = "Macros of the report's section 'Lyapunov exponents' (Lyapunov stage)"
# The labels' macro-name parts.
LABEL_PARTS = {
    "chaotic": "Chaotic",
    "chaotic transient": "ChaoticTransient",
    "quasi-periodic": "Quasi",
    "periodic": "Periodic",
    "not settled": "Unsettled",
}


def _label_counts(rows: list[dict], former_np) -> dict:
    """Of the rows ``former_np`` selects (a predicate of a row): their number, and per label of
    :data:`~impactdamper.analysis.lyapunov.LABELS` the count and the share ("" labels: none)."""
    chosen = [r for r in rows if former_np(r)]
    counts = Counter(r["motion"] for r in chosen)
    n = len(chosen)
    return {
        "points": len(rows),
        "np": n,
        "np_share": n / len(rows) if rows else None,
        "unlabelled": n - sum(counts[label] for label in LABELS),
        **{label: {"count": counts[label], "share": counts[label] / n if n else None} for label in LABELS},
    }


def _numbers(values, digits: int) -> str:
    """``$0.8388$, $0.8310$ and $0.8208$``."""
    shown = [f"${fixed(digits)(v)}$" for v in values]
    return shown[0] if len(shown) == 1 else ", ".join(shown[:-1]) + " and " + shown[-1]


def _gaps(values) -> str:
    """``$-5.8$, $-9.6$ and $-14$``."""
    shown = [f"${fixed(3)(v).rstrip('0').rstrip('.')}$" for v in values]
    return shown[0] if len(shown) == 1 else ", ".join(shown[:-1]) + " and " + shown[-1]


def upper(digits: int = 1) -> Format:
    """:func:`~impactdamper.reporting.texrecord.bound` (the magnitude rounded up, so that "at
    most" holds) in math mode, for a macro used in text."""
    b = bound(digits)
    return Format(lambda x: rf"\ensuremath{{{b.render(x)}}}", rf"\ensuremath{{{b.missing}}}")


def _quasi_points(sweep_rows: list[dict], special_rows: list[dict]) -> dict:
    """The gap sweep's points labelled quasi-periodic, each with its second exponent and its
    distance to the nearest Neimark-Sacker point of an admissible branch
    (figures/orbit_special_points.csv), and those points."""
    ns = sorted(float(r["gap"]) for r in special_rows if r["kind"] == "neimark_sacker" and r["admissible"] == "1")
    points = []
    for r in sweep_rows:
        if r["motion"] != "quasi-periodic":
            continue
        gap = float(r["value"])
        near = min(ns, key=lambda g: abs(g - gap)) if ns else None
        points.append(
            {
                "direction": r["direction"],
                "gap": gap,
                "exponent": float(r["exponent"]),
                "error": float(r["error"]),
                "exponent2": float(r["exponent2"]),
                "error2": float(r["error2"]),
                "impacts_per_period": float(r["impacts_per_period"]),
                "ns_gap": near,
                "ns_distance": None if near is None else abs(gap - near),
            }
        )
    return {"ns_gaps": ns, "points": points}


def _settled_max(sweep_rows: list[dict], sweep_table: list[dict]) -> dict:
    """The point the sweep settled (not np) whose rerun has the largest exponent, with the
    sweep table's row for it (its label, how it was found, its largest multiplier): a rerun on
    a chaotic transient beside a stable cycle where the exponent is positive."""
    rows = [r for r in sweep_rows if r["label"] != "np" and r["exponent"] not in ("", "nan")]
    top = max(rows, key=lambda r: float(r["exponent"]))
    table = next(t for t in sweep_table if (t["direction"], t["index"]) == (top["direction"], top["index"]))
    numbers = ("value", "exponent", "error", "half1", "half2", "periods")
    return {
        "direction": top["direction"],
        "label": top["label"],
        **{k: float(top[k]) for k in numbers},
        "method": table["method"],
        "multiplier": float(table["multiplier"]) if table["multiplier"] else None,
    }


# A quasi-periodic point "near" a Neimark-Sacker point: within this many x_st of it.
NEAR_NS = 0.2


def _near(p: dict) -> bool:
    return p["ns_distance"] is not None and p["ns_distance"] <= NEAR_NS


def _quasi_list(q: dict, near: bool) -> str:
    """The quasi-periodic gaps within NEAR_NS of a Neimark-Sacker point (``near``) or not."""
    gaps = sorted({p["gap"] for p in q["points"] if _near(p) == near})
    return _gaps(gaps) if gaps else "none"


def _far_rates(q: dict) -> str:
    """The impacts per period of the quasi-periodic points far from a Neimark-Sacker point."""
    rates = {p["gap"]: p["impacts_per_period"] for p in q["points"] if not _near(p)}
    shown = [f"${latex.fixed(rates[g], 4)}$" for g in sorted(rates)]  # (in the order of _quasi_list)
    return shown[0] if len(shown) == 1 else ", ".join(shown[:-1]) + " and " + shown[-1] if shown else "none"


def _up_fixed(digits: int) -> Format:
    """Fixed decimals rounded up (an "at most" distance)."""
    return Format(lambda x: latex.fixed(math.ceil(x * 10**digits) / 10**digits, digits))


def _family(prefix: str, where: str, fields: str) -> list:
    """Macros ``prefix + name`` of the record's ``where + "." + key``, from ``fields``: triples
    "name key format", the format ``n`` (a count), ``t`` (text) or a number of decimals."""
    words = fields.split()
    formats = {"n": COUNT, "t": TEXT}
    return [
        Macro(prefix + name, f"{where}.{key}", formats[f] if f in formats else fixed(int(f)))
        for name, key, f in zip(words[::3], words[1::3], words[2::3])
    ]


def _label_macros(where: str, part: str) -> list:
    out = []
    for label, name in LABEL_PARTS.items():
        out.append(Macro(f"Lyap{part}{name}", f"{where}.{label}.count", COUNT))
        out.append(Macro(f"Lyap{part}{name}Pct", f"{where}.{label}.share", percent(1)))
    return out


MACROS = (
    "% The labels' thresholds (analysis/lyapunov.py), per forcing period",
    Macro("LyapSignificance", "significance", fixed(0)),
    Macro("LyapZeroBand", "zero_band", tex_sci(0, powers_of_ten=True, math_mode=True)),
    Macro("LyapSettleSpan", "settle.span", COUNT),
    Macro("LyapSettleMaxK", "settle.max_k", COUNT),
    Macro("LyapSettleTol", "settle.tol", tex_sci(0, powers_of_ten=True, math_mode=True)),
    Macro("LyapBlocks", "defaults.blocks", COUNT),
    Macro("LyapDefaultTransient", "defaults.transient", COUNT),
    Macro("LyapDefaultWarmup", "defaults.warmup", COUNT),
    "% Run lengths (config: lyapunov), forcing periods",
    Macro("LyapTransient", "run.transient", COUNT),
    Macro("LyapWarmup", "run.warmup", COUNT),
    Macro("LyapPeriods", "run.periods", COUNT),
    Macro("LyapClassifyWarmup", "run.classify_warmup", COUNT),
    Macro("LyapClassifyPeriods", "run.classify_periods", COUNT),
    Macro("LyapClassifyFrom", lambda s: s["run"]["transient"] + s["run"]["classify_warmup"], COUNT),
    Macro(
        "LyapClassifyTo",
        lambda s: s["run"]["transient"] + s["run"]["classify_warmup"] + s["run"]["classify_periods"],
        COUNT,
    ),
    "% The gap sweep: its points, the former np points and their labels",
    Macro("LyapSweepPoints", "sweep.points", COUNT),
    Macro("LyapSweepNp", "sweep.np", COUNT),
    *_label_macros("sweep", "Sweep"),
    Macro("LyapSweepMax", "sweep_max.exponent", fixed(2)),
    Macro("LyapSweepMaxGap", "sweep_max.value", fixed(2)),
    Macro("LyapSweepFailed", "sweep_failed", COUNT),
    "% The map: its grid, the cells left np after the rescue and their labels",
    Macro("LyapMapRows", "map_grid.points", COUNT),
    Macro("LyapMapColumns", "map_grid.gap_points", COUNT),
    Macro("LyapMapStart", "map_grid.start", fixed(2)),
    Macro("LyapMapStop", "map_grid.stop", fixed(2)),
    Macro("LyapMapGapStart", "map_grid.gap_start", fixed(0)),
    Macro("LyapMapGapStop", "map_grid.gap_stop", fixed(0)),
    Macro("LyapMapCells", "map.points", COUNT),
    Macro("LyapMapNp", "map.np", COUNT),
    Macro("LyapMapNpPct", "map.np_share", percent(1)),
    *_label_macros("map", "Map"),
    Macro("LyapMapPositivePct", "map_positive", percent(1)),
    "% The checks (figures/lyapunov_checks.json)",
    Macro("LyapFloquetGaps", lambda s: _gaps([c["gap"] for c in s["checks"]["floquet"]])),
    Macro("LyapFloquetMax", lambda s: max(c["difference"] for c in s["checks"]["floquet"]), upper(1)),
    Macro("LyapBenettinCount", lambda s: len(s["checks"]["benettin"]), COUNT),
    Macro("LyapBenettinAgree", lambda s: sum(c["agrees"] for c in s["checks"]["benettin"]), COUNT),
    Macro(
        "LyapBenettinSameMax",
        lambda s: max(c["same_motion_difference"] for c in s["checks"]["benettin"]),
        upper(1),
    ),
    Macro("LyapBenettinFloor", "checks.benettin_floor", tex_sci(0, powers_of_ten=True, math_mode=True)),
    Macro("LyapSumRuleGaps", lambda s: _gaps([c["gap"] for c in s["checks"]["sum_rule"]])),
    Macro(
        "LyapSumRuleMax",
        lambda s: max(c["per_period_residual"] for c in s["checks"]["sum_rule"]),
        upper(1),
    ),
    Macro(
        "LyapSumRuleTotalMax",
        lambda s: max(c["total_residual"] for c in s["checks"]["sum_rule"]),
        upper(1),
    ),
    Macro("LyapBackendsRegularGap", "checks.backends.0.gap", fixed(1)),
    Macro("LyapBackendsRegular", "checks.backends.0.difference", upper(1)),
    Macro("LyapBackendsChaoticGap", "checks.backends.1.gap", fixed(1)),
    Macro("LyapBackendsChaoticSigma", "checks.backends.1.largest_in_errors", _up_fixed(1)),
    "% The independent check (figures/lyapunov_independent.json): Benettin on solve_ivp",
    *_family(
        "LyapIndep",
        "independent",
        "Gap gap 1 Tangent tangent.exponent 3 TangentErr tangent.error 3 Ivp ivp.exponent 3 IvpErr ivp.error 3 "
        "Diff difference 3 Sigma in_combined_errors 2 Periods ivp.periods n Transient ivp.transient n",
    ),
    Macro("LyapIndepRtol", "independent.ivp.rtol", tex_sci(0, powers_of_ten=True, math_mode=True)),
    Macro("LyapIndepSeparation", "independent.ivp.separation", tex_sci(0, powers_of_ten=True, math_mode=True)),
    "% The window's effect: one point run with two lengths (figures/lyapunov_checks.json: windows)",
    Macro("LyapWindowGap", "checks.windows.0.gap", fixed(1)),
    *_family(
        "LyapWindowShort",
        "checks.windows.0",
        "Transient transient n Periods periods n Label label t Exponent exponent 3 Error error 3 "
        "HalfOne halves.0 3 HalfTwo halves.1 3 HalfErr half_errors.0 3 SettledK settled_period n "
        "SettledSince settled_since n",
    ),
    *_family(
        "LyapWindowLong",
        "checks.windows.1",
        "Transient transient n Periods periods n Label label t Exponent exponent 3",
    ),
    "% The torus: quasi-periodic motions' turn per k T against the cycle's multipliers (checks: torus)",
    Macro("LyapTorusOrbitGap", "checks.torus.orbit_gap", fixed(2)),
    Macro("LyapTorusAngle", "checks.torus.angle", fixed(4)),
    Macro("LyapTorusModulus", "checks.torus.modulus", fixed(3)),
    Macro("LyapTorusGaps", lambda s: _gaps([m["gap"] for m in s["checks"]["torus"]["motions"]])),
    Macro("LyapTorusTurns", lambda s: _numbers([m["rotation"] for m in s["checks"]["torus"]["motions"]], 4)),
    Macro("LyapTorusDiffMax", lambda s: max(m["difference"] for m in s["checks"]["torus"]["motions"]), _up_fixed(3)),
    "% The settled sweep point whose rerun has the largest exponent (figures/sweep_gap.csv)",
    *_family(
        "LyapSettledMax",
        "settled_max",
        "Gap value 3 Direction direction t Label label t Method method t Multiplier multiplier 3 "
        "Exponent exponent 3 Error error 3 HalfOne half1 3 HalfTwo half2 3 Periods periods n",
    ),
    "% The quasi-periodic points of the gap sweep and the Neimark-Sacker points (orbit_special_points.csv)",
    Macro("LyapQuasiCount", lambda s: len(s["quasi"]["points"]), COUNT),
    Macro("LyapQuasiErrMax", lambda s: max((p["error"] for p in s["quasi"]["points"]), default=None), upper(1)),
    Macro("LyapNsGap", lambda s: s["quasi"]["ns_gaps"][0] if s["quasi"]["ns_gaps"] else None, fixed(4)),
    Macro("LyapQuasiNearGaps", lambda s: _quasi_list(s["quasi"], True)),
    Macro("LyapQuasiFarGaps", lambda s: _quasi_list(s["quasi"], False)),
    Macro("LyapQuasiFarRates", lambda s: _far_rates(s["quasi"])),
    Macro(
        "LyapQuasiNearMax",
        lambda s: max((p["ns_distance"] for p in s["quasi"]["points"] if _near(p)), default=None),
        _up_fixed(3),
    ),
    Macro(
        "LyapQuasiNearSecond",
        lambda s: max((p["exponent2"] for p in s["quasi"]["points"] if _near(p)), default=None),
        fixed(4),
    ),
    Macro(
        "LyapQuasiNearSecondMin",
        lambda s: min((p["exponent2"] for p in s["quasi"]["points"] if _near(p)), default=None),
        fixed(3),
    ),
    Macro(
        "LyapQuasiSecondMax",
        lambda s: max((p["exponent2"] for p in s["quasi"]["points"]), default=None),
        fixed(3),
    ),
)


def lyapunov_macros(
    sweep_rows: list[dict],
    map_rows: list[dict],
    checks: dict,
    section: dict,
    independent: dict,
    special_rows: list[dict],
    sweep_table: list[dict],
) -> MacroFile:
    """The stage's macros (the record of ``paper/generated/lyapunov_macros.tex``).

    Parameters
    ----------
    sweep_rows, map_rows : list of dict
        The exponents along the gap sweep and over the map (figures/lyapunov_sweep.csv,
        figures/lyapunov_map.csv, cells as text).
    checks : dict
        figures/lyapunov_checks.json.
    section : dict
        The config's ``lyapunov`` section (run lengths, the map's grid).
    independent : dict
        figures/lyapunov_independent.json.
    special_rows : list of dict
        figures/orbit_special_points.csv (the Neimark-Sacker points).
    sweep_table : list of dict
        figures/sweep_gap.csv (the sweep's own labels and multipliers).
    """
    exponents = [r for r in sweep_rows if r["exponent"] not in ("", "nan")]
    top = max(exponents, key=lambda r: float(r["exponent"]))
    cells = [r for r in map_rows if r["exponent"] not in ("", "nan")]
    source = {
        "significance": SIGNIFICANCE,
        "zero_band": ZERO_BAND,
        "settle": {"span": SETTLE_SPAN, "max_k": MAX_SETTLED_PERIOD, "tol": SETTLE_TOL},
        "defaults": {"blocks": DEFAULT_BLOCKS, "transient": DEFAULT_TRANSIENT, "warmup": DEFAULT_WARMUP},
        "run": section,
        "map_grid": section["map"],
        "sweep": _label_counts(sweep_rows, lambda r: r["label"] == "np"),
        "sweep_max": {"exponent": float(top["exponent"]), "value": float(top["value"])},
        "sweep_failed": len(sweep_rows) - len(exponents),
        "map": _label_counts(map_rows, lambda r: r["regime"] == "nonperiodic"),
        "map_positive": sum(float(r["exponent"]) > 0.0 for r in cells) / len(cells),
        "checks": checks,
        "independent": independent,
        "quasi": _quasi_points(sweep_rows, special_rows),
        "settled_max": _settled_max(sweep_rows, sweep_table),
    }
    return MacroFile(macro_lines(MACROS, source))


def _math_fixed(digits: int) -> Format:
    """Fixed decimals in math mode (a table's cell: ``$-16.000$``)."""
    return Format(lambda x: f"${latex.fixed(x, digits)}$", f"${latex.MISSING}$")


def _math_bound(digits: int) -> Format:
    """An upper bound in math mode (a table's cell: ``$3.3\\times10^{-6}$``): :func:`bound`."""
    b = bound(digits)
    return Format(lambda x: f"${b.render(x)}$", f"${latex.MISSING}$")


BENETTIN_TABLE = Table(
    colspec="rrrrrrr",
    header=(
        tex("gap") + r" & $\lambda_1 T$ & std.\ error & Benettin & std.\ error & "
        r"$|\mathrm{difference}|$ & same motion"
    ),
    columns=(
        Column("gap", _math_fixed(3)),
        Column("exponent", _math_fixed(4)),
        Column("error", _math_fixed(4)),
        Column("benettin", _math_fixed(4)),
        Column("benettin_error", _math_fixed(4)),
        Column("difference", _math_fixed(4)),
        Column("same_motion_difference", _math_bound(2)),
    ),
    comments=("Benettin's two-trajectory estimate against the largest exponent (lyapunov stage)",),
)


def benettin_table(checks: dict) -> str:
    """The booktabs table of Benettin's checks, one row per point."""
    return BENETTIN_TABLE.render(checks["benettin"])


TIMING = (
    "% CPU times of one point's spectrum (results/benchmarks/lyapunov_speed.json): not deterministic",
    Macro("LyapSpeedPeriods", "speed.0.periods", COUNT),
    Macro("LyapSpeedStatedCompiled", lambda s: s["speed"][0]["compiled_ms"] / 1e3, time()),
    Macro("LyapSpeedStatedPython", lambda s: s["speed"][0]["python_ms"] / 1e3, time()),
    Macro("LyapSpeedStatedSpeedup", "speed.0.speedup", fixed(0)),
    Macro("LyapSpeedChaoticGap", "speed.1.gap", fixed(1)),
    Macro("LyapSpeedChaoticCompiled", lambda s: s["speed"][1]["compiled_ms"] / 1e3, time()),
    Macro("LyapSpeedChaoticSpeedup", "speed.1.speedup", fixed(0)),
    Macro("LyapSpeedChatterGap", "speed.2.gap", fixed(1)),
    Macro("LyapSpeedChatterCompiled", lambda s: s["speed"][2]["compiled_ms"] / 1e3, time()),
    Macro("LyapSpeedChatterImpacts", "speed.2.impacts_per_period", fixed(0)),
    Macro("LyapCommandWall", "command_wall_s", time()),
    Macro("LyapSweepCpu", "sweep_cpu_s", time()),
    Macro("LyapMapCpu", "map_cpu_s", time()),
    Macro("LyapIndepCpu", "independent_cpu_s", time()),
)


def timing(speed: dict) -> str:
    """The benchmark's macros (``paper/generated/lyapunov_timing.tex``): TeX lines."""
    return MacroFile(macro_lines(TIMING, speed)).tex()
