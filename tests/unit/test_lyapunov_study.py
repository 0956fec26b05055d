"""The Lyapunov stage's study (impactdamper.studies.lyapunov): the sweep's exponents and labels
from the sweep table's rows, the map's rows with their labels, the record's counts and macros,
and the config's checks of the stage's keys."""

import math
import re
from pathlib import Path

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.analysis.lyapunov import LABELS
from impactdamper.analysis.point import SweepSettings
from impactdamper.studies.lyapunov.exponent_map import map_rows
from impactdamper.studies.lyapunov.record import MACROS, TIMING, _label_counts, lyapunov_macros
from impactdamper.studies.lyapunov.sweep import COLUMNS, RunLengths, start_state, sweep_exponents

REF = idp.Parameters()
ROOT = Path(__file__).resolve().parents[2]
SHORT = RunLengths(transient=100, warmup=20, periods=100, classify_warmup=100, classify_periods=500)
# The stated case's Floquet exponent log|mu_1| per period (the orbit solver's, test_lyapunov.py)
# and how close these short runs come to it: 100 periods after a warm-up of 20 leave the frame's
# turn within the complex pair's plane unaveraged to ~3e-5 (measured 2.6e-5); 1e-4.
STATED_FLOQUET = -0.3406762
SHORT_RUN_TOL = 1e-4


def sweep_row(direction, index, gap, label, state):
    x1, x2, v1, v2 = (repr(float(x)) for x in state)
    return dict(direction=direction, index=str(index), value=repr(gap), label=label, x1_0=x1, x2_0=x2, v1_0=v1, v2_0=v2)


def test_a_start_on_the_stop_read_from_its_digits_stays_on_the_stop():
    p = REF.replace(gap=-12.0)
    row = sweep_row("up", 0, -12.0, "1/1", [0.1, 0.1 + p.Delta0 + 1e-12, 0.0, 0.0])
    y = start_state(p, row)
    assert p.Delta0 - (y[1] - y[0]) == 0.0 and y[0] == 0.1


def test_sweep_rows_get_exponents_and_the_np_rows_labels():
    """A periodic row (the stated case) and an np row (gap -16, chaotic): the periodic one's
    largest exponent is its Floquet exponent's, unlabelled; the np one labelled chaotic."""
    start = idp.default_initial_state(REF)
    rows = [
        sweep_row("up", 0, -5.8, "1/1", start),
        sweep_row("up", 1, -16.0, "np", idp.default_initial_state(REF.replace(gap=-16.0))),
    ]
    out = sweep_exponents(REF, rows, SHORT, idp.Tolerances())
    assert [r["motion"] for r in out] == ["", "chaotic"]
    assert out[0]["exponent"] == pytest.approx(STATED_FLOQUET, abs=SHORT_RUN_TOL)
    assert out[1]["exponent"] > 0.5 and out[1]["periods"] == SHORT.classify_periods
    assert all(set(r) == set(COLUMNS) for r in out)


def test_map_rows_label_their_np_cells():
    """One row of the map (theta = 1): the np cell labelled and its exponent the labelling
    run's, every other cell an exponent of its own (negative: periodic)."""
    gaps = np.array([-16.0, -5.8])
    settings = SweepSettings(continuation=False, rescue=False, max_periods=150, max_periods_after_nonperiodic=150)
    out = map_rows(REF, "theta", [1.0], gaps, [0], settings, SHORT)
    assert [r["regime"] for r in out] == ["nonperiodic", "single_impact"]
    assert [r["motion"] for r in out] == ["chaotic", ""]
    assert out[0]["exponent"] > 0.5 and out[0]["periods"] == SHORT.classify_periods
    assert out[1]["exponent"] == pytest.approx(STATED_FLOQUET, abs=SHORT_RUN_TOL) and out[1]["periods"] == SHORT.periods


def test_label_counts():
    rows = [
        {"motion": m, "label": lab}
        for m, lab in [("chaotic", "np"), ("chaotic", "np"), ("", "1/1"), ("periodic", "np")]
    ]
    c = _label_counts(rows, lambda r: r["label"] == "np")
    assert (c["points"], c["np"], c["unlabelled"]) == (4, 3, 0)
    assert c["chaotic"] == {"count": 2, "share": 2 / 3} and c["quasi-periodic"]["count"] == 0
    assert math.isclose(sum(c[label]["share"] for label in LABELS), 1.0)


def test_every_macro_the_section_uses_is_declared():
    """paper/sections/lyapunov.tex uses only macros the stage's record declares."""
    text = (ROOT / "paper" / "sections" / "lyapunov.tex").read_text()
    used = set(re.findall(r"\\(Lyap[A-Za-z]+)", text))
    declared = {m.name for m in MACROS + TIMING if not isinstance(m, str)}
    assert used <= declared, sorted(used - declared)


def test_the_record_renders_from_small_tables():
    sweep = [
        {"direction": "up", "index": "0", "value": "-16", "label": "np", "motion": "chaotic", "exponent": "0.8"},
        {"direction": "up", "index": "1", "value": "-5.8", "label": "1/1", "motion": "", "exponent": "-0.34",
         "error": "1e-4", "half1": "-0.34", "half2": "-0.34", "periods": "200"},
        {"direction": "down", "value": "-10.1", "label": "np", "motion": "quasi-periodic", "exponent": "0.0",
         "error": "1e-5", "exponent2": "-0.02", "error2": "1e-4", "impacts_per_period": "1.5"},
    ]  # fmt: skip
    cells = [
        {"regime": "nonperiodic", "motion": "quasi-periodic", "exponent": "0.0"},
        {"regime": "single_impact", "motion": "", "exponent": "-0.3"},
    ]
    check = {"gap": -5.8, "difference": 1e-12, "per_period_residual": 1.15e-14, "total_residual": 1e-15}
    checks = {
        "floquet": [check],
        "sum_rule": [check],
        "benettin": [{"gap": -16.0, "agrees": True, "same_motion_difference": 1e-6}],
        "benettin_floor": 1e-6,
        "backends": [{"gap": -5.8, "difference": 7.27e-15}, {"gap": -16.0, "largest_in_errors": 0.5}],
        "windows": [
            {"gap": -10.6, "transient": 500, "periods": 2000, "label": "chaotic transient", "exponent": 0.18,
             "error": 0.024, "halves": [0.18, 0.12], "half_errors": [0.03, 0.03], "settled_period": 7,
             "settled_since": 2630},
            {"gap": -10.6, "transient": 3000, "periods": 4000, "label": "periodic", "exponent": -0.038},
        ],
        "torus": {"orbit_gap": -10.05, "k": 2, "angle": 0.839, "modulus": 0.967,
                  "motions": [{"gap": -10.144, "rotation": 0.831, "difference": 0.0081}]},
    }  # fmt: skip
    run = {"exponent": 0.85, "error": 0.02, "periods": 2000, "transient": 100, "rtol": 1e-12, "separation": 1e-7}
    independent = {"gap": -16.0, "difference": 0.04, "in_combined_errors": 1.15, "ivp": run, "tangent": run}
    special = [
        {"kind": "neimark_sacker", "admissible": "1", "gap": "-10.0949615567"},
        {"kind": "fold", "admissible": "1", "gap": "-11.0"},
    ]
    section = {
        "transient": 100,
        "warmup": 50,
        "periods": 200,
        "classify_warmup": 200,
        "classify_periods": 2000,
        "map": {"points": 2, "gap_points": 1, "start": 0.5, "stop": 1.5, "gap_start": -40.0, "gap_stop": 15.0},
    }
    table = [
        {"direction": "up", "index": "0", "method": "simulation", "multiplier": "0.3"},
        {"direction": "up", "index": "1", "method": "continuation", "multiplier": "0.854"},
    ]
    tex = lyapunov_macros(sweep, cells, checks, section, independent, special, table).tex()
    assert r"\newcommand{\LyapSettledMaxMultiplier}{0.854}" in tex
    assert r"\newcommand{\LyapSweepChaoticPct}{50.0}" in tex
    # "at most" bounds round up: 1.15e-14 is not printed as 1e-14, nor 7.27e-15 as 7e-15
    assert r"\newcommand{\LyapSumRuleMax}{\ensuremath{2\times10^{-14}}}" in tex
    assert r"\newcommand{\LyapBackendsRegular}{\ensuremath{8\times10^{-15}}}" in tex
    assert r"\newcommand{\LyapWindowShortLabel}{chaotic transient}" in tex
    assert r"\newcommand{\LyapNsGap}{-10.0950}" in tex and r"\newcommand{\LyapQuasiNearGaps}{$-10.1$}" in tex
    assert r"\newcommand{\LyapQuasiFarGaps}{none}" in tex
    assert r"\newcommand{\LyapTorusDiffMax}{0.009}" in tex  # 0.0081 rounded up
    assert r"\newcommand{\LyapMapQuasiPct}{100.0}" in tex
    assert r"\newcommand{\LyapMapPositivePct}{0.0}" in tex
    assert r"\newcommand{\LyapSweepMaxGap}{-16.00}" in tex


@pytest.mark.parametrize(
    "change, path",
    [
        ({"lyapunov": {"periods": 205}}, "['lyapunov']['periods']"),
        ({"lyapunov": {"map": {"chunks": 200}}}, "['lyapunov']['map']['chunks']"),
        ({"lyapunov": {"map": {"points": 5000, "gap_points": 5000}}}, "['lyapunov']['map']"),
        ({"lyapunov": {"map": {"start": -1.0}}}, "['lyapunov']['map']['start']"),
    ],
)
def test_the_config_refuses_a_bad_lyapunov_key(change, path):
    import yaml

    from impactdamper.studies import config_check

    schema = config_check.read_schema(ROOT / "workflow" / "schemas" / "config.schema.yaml")
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())

    def merge(a, b):
        for k, v in b.items():
            if isinstance(v, dict) and isinstance(a.get(k), dict):
                merge(a[k], v)
            else:
                a[k] = v

    merge(config, change)
    with pytest.raises(config_check.ConfigError) as err:
        config_check.check(config, schema)
    assert path in str(err.value) and "\n" not in str(err.value), str(err.value)


# ----------------------------------------------------------------------------------------
# The committed record: the sweep's and the map's np points carry the labels
# ----------------------------------------------------------------------------------------
def test_the_committed_sweep_labels_its_np_points_and_only_those():
    from impactdamper.reporting.records import read_csv

    sweep = read_csv(ROOT / "figures" / "sweep_gap.csv")
    rows = read_csv(ROOT / "figures" / "lyapunov_sweep.csv")
    assert [(r["direction"], r["index"], r["label"]) for r in rows] == [
        (r["direction"], r["index"], r["label"]) for r in sweep
    ]
    for r in rows:
        assert (r["motion"] in LABELS) == (r["label"] == "np"), r
        assert r["motion"] != "chaotic" or float(r["exponent"]) > 3 * float(r["error"]), r
    assert sum(r["motion"] == "chaotic" for r in rows) > 0


def test_the_committed_map_labels_its_np_cells_and_only_those():
    from impactdamper.reporting.records import read_csv

    cells = read_csv(ROOT / "figures" / "lyapunov_map.csv")
    assert len(cells) == 100 * 100
    for c in cells:
        assert (c["motion"] in LABELS) == (c["regime"] == "nonperiodic"), c
    assert all(math.isfinite(float(c["exponent"])) for c in cells if c["regime"] != "failed")


def test_rotation_per_cycle_reads_a_known_turn():
    """Sections turning by 0.7 rad a period about a centre, in a tilted plane of the 4 states,
    with a small third direction: 0.7 per period, 1.4 per 2 T (the mean of the two interleaved
    series). On the 2:1 ellipse the polar angle differs from the phase by at most
    atan(sqrt 2) - atan(1/sqrt 2) = 0.34 rad at either end, so the mean turn is off by at most
    0.68 / 399 (1.7e-3) and 0.68 / 199 (3.4e-3)."""
    from impactdamper.studies.lyapunov.checks import _rotation_per_cycle

    n = np.arange(400)
    plane = np.linalg.qr(np.random.default_rng(3).normal(size=(4, 3)))[0].T
    z = np.column_stack([2.0 * np.cos(0.7 * n), 1.0 * np.sin(0.7 * n), 1e-3 * np.cos(0.1 * n)]) @ plane
    y = z + np.array([1.0, -5.0, 0.3, 0.2])
    assert _rotation_per_cycle(y, 1) == pytest.approx(0.7, abs=1.7e-3)
    assert _rotation_per_cycle(y, 2) == pytest.approx(1.4, abs=3.4e-3)
    assert _rotation_per_cycle(y, 1) != pytest.approx(0.69, abs=1.7e-3)


@pytest.mark.slow
def test_torus_turns_by_the_neimark_sacker_angle():
    """Just past the 3/2 cycle's Neimark-Sacker point (-10.0950) the motion's sections turn per
    2 T by the angle of the cycle's complex multipliers at -10.05 (0.8391): measured 0.8388 at
    -10.096 (bound 0.005: the angle drifts by 0.001 between -10.0 and -10.05) and 0.8310 at
    -10.144 (bound 0.02)."""
    from impactdamper.studies.lyapunov.checks import torus_check

    t = torus_check(-10.05, [-10.096, -10.144], 2000, REF)
    assert t["k"] == 2 and t["modulus"] < 1.0
    assert t["motions"][0]["difference"] <= 0.005 and t["motions"][1]["difference"] <= 0.02, t
