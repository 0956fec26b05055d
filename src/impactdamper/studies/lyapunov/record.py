"""The Lyapunov stage's record for the report's section on Lyapunov exponents, declared for
:mod:`impactdamper.reporting.texrecord`: its macros, the table of Benettin's checks and the
benchmark's macros.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100 (no counterpart in the
paper): the numbers come from the stage's tables (figures/lyapunov_*.csv, .json) and the
config's run lengths; no number is typed by hand. Used by ``workflow/scripts/lyapunov_report.py``.
"""

from __future__ import annotations

from collections import Counter

from impactdamper.analysis.lyapunov import LABELS, SIGNIFICANCE, ZERO_BAND
from impactdamper.reporting import latex
from impactdamper.reporting.latex import MacroFile
from impactdamper.reporting.texrecord import (
    COUNT,
    Column,
    Format,
    Macro,
    Table,
    fixed,
    macro_lines,
    percent,
    tex_sci,
    time,
)

__all__ = ["RECORD_WHAT", "label_counts", "lyapunov_macros", "benettin_table", "timing"]

# What the stage's record holds (results/report/lyapunov.json).
RECORD_WHAT = "Macros of the report's section 'Lyapunov exponents' (Lyapunov stage)"
# The labels' macro-name parts.
LABEL_PARTS = {"chaotic": "Chaotic", "quasi-periodic": "Quasi", "periodic": "Periodic", "not settled": "Unsettled"}


def label_counts(rows: list[dict], former_np) -> dict:
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


def _gaps(values) -> str:
    """``$-5.8$, $-9.6$ and $-14$``."""
    shown = [f"${fixed(3)(v).rstrip('0').rstrip('.')}$" for v in values]
    return shown[0] if len(shown) == 1 else ", ".join(shown[:-1]) + " and " + shown[-1]


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
    "% Run lengths (config: lyapunov), forcing periods",
    Macro("LyapTransient", "run.transient", COUNT),
    Macro("LyapWarmup", "run.warmup", COUNT),
    Macro("LyapPeriods", "run.periods", COUNT),
    Macro("LyapClassifyWarmup", "run.classify_warmup", COUNT),
    Macro("LyapClassifyPeriods", "run.classify_periods", COUNT),
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
    Macro("LyapFloquetMax", lambda s: max(c["difference"] for c in s["checks"]["floquet"]), tex_sci(1, math_mode=True)),
    Macro("LyapBenettinCount", lambda s: len(s["checks"]["benettin"]), COUNT),
    Macro("LyapBenettinAgree", lambda s: sum(c["agrees"] for c in s["checks"]["benettin"]), COUNT),
    Macro(
        "LyapBenettinSameMax",
        lambda s: max(c["same_motion_difference"] for c in s["checks"]["benettin"]),
        tex_sci(1, math_mode=True),
    ),
    Macro("LyapBenettinFloor", "checks.benettin_floor", tex_sci(0, powers_of_ten=True, math_mode=True)),
    Macro("LyapSumRuleGaps", lambda s: _gaps([c["gap"] for c in s["checks"]["sum_rule"]])),
    Macro(
        "LyapSumRuleMax",
        lambda s: max(c["per_period_residual"] for c in s["checks"]["sum_rule"]),
        tex_sci(1, math_mode=True),
    ),
    Macro(
        "LyapSumRuleTotalMax",
        lambda s: max(c["total_residual"] for c in s["checks"]["sum_rule"]),
        tex_sci(1, math_mode=True),
    ),
    Macro("LyapBackendsRegularGap", "checks.backends.0.gap", fixed(1)),
    Macro("LyapBackendsRegular", "checks.backends.0.difference", tex_sci(1, math_mode=True)),
    Macro("LyapBackendsChaoticGap", "checks.backends.1.gap", fixed(1)),
    Macro("LyapBackendsChaoticSigma", "checks.backends.1.largest_in_errors", fixed(1)),
)


def lyapunov_macros(sweep_rows: list[dict], map_rows: list[dict], checks: dict, section: dict) -> MacroFile:
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
    """
    exponents = [r for r in sweep_rows if r["exponent"] not in ("", "nan")]
    top = max(exponents, key=lambda r: float(r["exponent"]))
    cells = [r for r in map_rows if r["exponent"] not in ("", "nan")]
    source = {
        "significance": SIGNIFICANCE,
        "zero_band": ZERO_BAND,
        "run": section,
        "map_grid": section["map"],
        "sweep": label_counts(sweep_rows, lambda r: r["label"] == "np"),
        "sweep_max": {"exponent": float(top["exponent"]), "value": float(top["value"])},
        "sweep_failed": len(sweep_rows) - len(exponents),
        "map": label_counts(map_rows, lambda r: r["regime"] == "nonperiodic"),
        "map_positive": sum(float(r["exponent"]) > 0.0 for r in cells) / len(cells),
        "checks": checks,
    }
    return MacroFile(macro_lines(MACROS, source))


def math_fixed(digits: int) -> Format:
    """Fixed decimals in math mode (a table's cell: ``$-16.000$``)."""
    return Format(lambda x: f"${latex.fixed(x, digits)}$", f"${latex.MISSING}$")


BENETTIN_TABLE = Table(
    colspec="rrrrrr",
    header=(
        r"$\Delta_0/x_{\mathrm{st}}$ & $\lambda_1 T$ & std.\ error & Benettin & std.\ error & "
        r"$|\mathrm{difference}|$"
    ),
    columns=(
        Column("gap", math_fixed(3)),
        Column("exponent", math_fixed(4)),
        Column("error", math_fixed(4)),
        Column("benettin", math_fixed(4)),
        Column("benettin_error", math_fixed(4)),
        Column("difference", math_fixed(4)),
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
)


def timing(speed: dict) -> str:
    """The benchmark's macros (``paper/generated/lyapunov_timing.tex``): TeX lines."""
    return MacroFile(macro_lines(TIMING, speed)).tex()
