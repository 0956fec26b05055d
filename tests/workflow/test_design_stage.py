"""The design stage ("Choosing a suppressor"): its committed records (figures/design_*,
paper/generated/design_*) are present and consistent with each other and with the library.

* The chart's best gap of the grid is the chart's smallest value, its good band the contiguous
  run within the stated tolerance, and its loads the chart's row; the located best gap is no
  worse than the grid's.
* The linear baselines regenerate byte for byte (closed forms and the search are cheap), and
  the design search reaches Den Hartog's optimum on an undamped object (measured differences).
* Every cycle of the frequency response closes its energy balance; cycles without contact
  equal the linear response; the hysteresis flag matches the two directions' rows; the located
  peak is never below the grid's.
* The macros quote the records, and the report step regenerates them exactly.
* The design table (figures/design_optimum.*): every linear row recomputed in closed form; the
  whole box's answer never worse than the answer within reach; every impact row at least its own
  closed-form floor; the travel-limited rows within their limit where feasible; the table and
  recommendation regenerate from the record; the located-peak checks within their tolerances.
"""

import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

import design_baselines
import design_report
from impactdamper.analysis.linear_device import LinearDevice, no_contact_floor
from impactdamper.analysis.response import UNSETTLED
from impactdamper.reporting.records import cell_float, read_csv, read_json
from impactdamper.studies.design.design import CRITERIA, _good_band
from impactdamper.studies.design.devices import impact_parameters
from impactdamper.studies.design.verdict import device

ROOT = Path(__file__).resolve().parents[2]
FIGURES = ROOT / "figures"
GENERATED = ROOT / "paper" / "generated"
CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
RECORDS = [
    "design_baselines.csv",
    "design_baselines.json",
    "design_chart.csv",
    "design_chart.json",
    "design_chart_2d.csv",
    "design_chart_2d.json",
    "design_response.csv",
    "design_response.json",
    "design_response.pdf",
    "design_response.png",
    "design_chart.pdf",
    "design_chart.png",
    "design_chart_2d.pdf",
    "design_chart_2d.png",
    "design_optimum.json",
    "design_optimum.csv",
    "design_checks.json",
    "design_subregions.json",
    "design_benchmark.json",
]
GENERATED_FILES = [
    "design_macros.tex",
    "design_second_table.tex",
    "design_table.tex",
    "design_loads_table.tex",
    "design_benchmark_table.tex",
]
# The settled cycles are periodic to the sweep's settle tolerance (1e-9 x_st): ten times that.
LINEAR_ATOL = 1e-8
# The quadrature closes the balance to rounding (~1e-13): 1e-10 leaves margin.
BALANCE_TOL = 1e-10


def test_records_are_present():
    for name in RECORDS:
        assert (FIGURES / name).stat().st_size > 0, name
    for name in GENERATED_FILES:
        assert (GENERATED / name).stat().st_size > 0, name


def test_best_gap_and_good_band_follow_from_the_chart():
    rows = read_csv(FIGURES / "design_chart.csv")
    best = read_json(FIGURES / "design_chart.json")["best"]
    gaps = np.array([float(r["gap"]) for r in rows])
    assert len(gaps) == CONFIG["design"]["gap_points"]
    for c, column in zip(CRITERIA, ("peak_max_abs_x1", "band_average_max_abs_x1")):
        values = np.array([float(r[column]) for r in rows])
        i = int(np.argmin(values))
        assert best[c]["gap"] == pytest.approx(gaps[i], abs=1e-12)
        assert best[c]["value"] == pytest.approx(values[i], rel=1e-10)
        assert (best[c]["good_from"], best[c]["good_to"]) == pytest.approx(
            _good_band(gaps, values, CONFIG["design"]["tolerance"])
        )
        assert best[c]["peak_impulse"] == pytest.approx(float(rows[i]["peak_impulse"]), rel=1e-10)
        located = read_json(FIGURES / "design_chart.json")["located"][c]
        assert located["value"] <= values[i] * (1 + 1e-6)  # located: no worse than the grid's best
        assert abs(located["gap"] - gaps[i]) <= np.max(np.diff(gaps)) + 1e-12


def test_baselines_regenerate_byte_for_byte(tmp_path):
    design_baselines.main(CONFIG["reference"], CONFIG["design"], tmp_path / "b.csv", tmp_path / "b.json")
    assert (tmp_path / "b.csv").read_bytes() == (FIGURES / "design_baselines.csv").read_bytes()
    assert (tmp_path / "b.json").read_bytes() == (FIGURES / "design_baselines.json").read_bytes()


def test_tmd_beats_the_untuned_absorber_and_den_hartog_check_holds():
    base = read_json(FIGURES / "design_baselines.json")
    tmd = base["tmd"]["peak"]
    assert tmd["peak"] < base["references"]["absorber"]["peak"] < base["references"]["bare"]["peak"]
    check = base["den_hartog_check"]
    assert 0.0 <= check["peak_relative_difference"] <= 0.005
    assert abs(check["N_relative_difference"]) <= 1e-3 and abs(check["delta2_relative_difference"]) <= 1.5e-2


def test_frequency_response_records_are_consistent():
    rows = read_csv(FIGURES / "design_response.csv")
    best = read_json(FIGURES / "design_chart.json")["located"]["peak"]["gap"]
    summary = read_json(FIGURES / "design_response.json")["responses"]
    roles = {s["role"]: s for s in summary}
    assert roles["best"]["gap"] == best and "optimal" in roles and "paper" in roles
    opt = device(read_json(FIGURES / "design_optimum.json"), "impact_peak_reach")["parameters"]
    assert {k: roles["optimal"][k] for k in opt} == opt
    for r in rows:
        if r["regime"] == "failed":
            continue
        assert cell_float(r["balance"]) <= BALANCE_TOL, r
        if r["regime"] == "no_contact":
            assert abs(cell_float(r["max_abs_x1"]) - cell_float(r["linear_max_abs_x1"])) <= LINEAR_ATOL
            assert abs(cell_float(r["max_abs_x2"]) - cell_float(r["linear_max_abs_x2"])) <= LINEAR_ATOL
    pairs = {}
    for r in rows:
        pairs.setdefault((r["role"], r["theta"]), {})[r["direction"]] = r
    for pair in pairs.values():
        up, down = pair["up"], pair["down"]
        assert up["hysteresis"] == down["hysteresis"]
        differ = up["label"] != down["label"] or not math.isclose(
            cell_float(up["max_abs_x1"]), cell_float(down["max_abs_x1"]), rel_tol=1e-4
        )
        assert (up["hysteresis"] == "1") == differ
    for s in summary:
        # (the grid peak is the settled samples': a nonperiodic sample's max|x1| is a transient's)
        worst = [
            cell_float(r["max_abs_x1"])
            for (role, _), p in pairs.items()
            for r in p.values()
            if role == s["role"] and r["regime"] not in UNSETTLED
        ]
        assert s["grid_peak"] == pytest.approx(max(worst), rel=1e-10)
        assert s["peak"] >= s["grid_peak"]


def test_macros_quote_the_records(tmp_path):
    text = (GENERATED / "design_macros.tex").read_text()
    macros = dict(re.findall(r"\\newcommand\{\\(\w+)\}\{(.*)\}", text))
    located = read_json(FIGURES / "design_chart.json")["located"]["peak"]
    opt = read_json(FIGURES / "design_optimum.json")
    assert float(macros["DesignBestGap"]) == pytest.approx(located["gap"], abs=5e-4)
    assert float(macros["DesignBestPeak"]) == pytest.approx(located["value"], abs=5e-4)
    assert float(macros["DesignTmdOptLocPeak"]) == pytest.approx(device(opt, "tmd_peak")["peak"], abs=5e-4)
    assert float(macros["DesignHitLocPeak"]) == pytest.approx(device(opt, "impact_peak_reach")["peak"], abs=5e-4)
    assert macros["DesignRecommendation"].startswith(opt["recommendation"].split(":")[0])
    # The text says a gap tuned to theta = 1 alone is not the gap for the band: it must hold.
    one = read_json(FIGURES / "design_chart.json")["at_reference_theta"]
    assert abs(one["gap"] - located["gap"]) > 0.1
    # And the report step regenerates them exactly from the records.
    names = ("baselines", "chart", "chart_2d", "response", "optimum", "checks", "subregions", "benchmark")
    design_report.main(
        *(FIGURES / f"design_{n}.json" for n in names),
        *(tmp_path / n for n in ("r.json", "m.tex", "t.tex", "d.tex", "l.tex", "b.tex")),
    )
    assert (tmp_path / "m.tex").read_text() == text
    for mine, name in zip(("t", "d", "l", "b"), GENERATED_FILES[1:]):
        assert (tmp_path / f"{mine}.tex").read_text() == (GENERATED / name).read_text(), name


def test_a_chart_row_regenerates():
    """The chart's row at the grid's best gap, recomputed on its own (every gap's worst branch is
    settled afresh, independent of the others of its batch): the same numbers."""
    from impactdamper.studies.design.design import design_band, design_parameters, gap_chart
    from impactdamper.studies.design.devices import DESIGN_SETTINGS

    design = CONFIG["design"]
    best = read_json(FIGURES / "design_chart.json")["best"]["peak"]
    row = next(r for r in read_csv(FIGURES / "design_chart.csv") if float(r["gap"]) == best["gap"])
    chart = gap_chart(
        design_parameters(CONFIG["reference"], design),
        [best["gap"]],
        design_band(design),
        float(design["band_step"]),
        settings=DESIGN_SETTINGS,
    )
    new = chart.rows()[0]
    for key in ("peak_max_abs_x1", "band_average_max_abs_x1", "peak_impulse", "impacts_per_period"):
        assert new[key] == pytest.approx(float(row[key]), rel=1e-10, abs=1e-12), key  # (the CSV keeps 12 digits)


def test_figures_regenerate_deterministically(tmp_path):
    import fig_design_chart

    for run in ("a", "b"):
        fig_design_chart.main(
            FIGURES / "design_chart.csv",
            FIGURES / "design_chart.json",
            FIGURES / "design_baselines.json",
            FIGURES / "design_optimum.json",
            tmp_path / f"{run}.pdf",
            tmp_path / f"{run}.png",
        )
    assert (tmp_path / "a.pdf").read_bytes() == (tmp_path / "b.pdf").read_bytes()
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()
    from matplotlib.testing.compare import compare_images

    assert compare_images(str(FIGURES / "design_chart.png"), str(tmp_path / "a.png"), tol=0.01) is None


@pytest.mark.parametrize("config", ["config.yaml", "ci.yaml"])
def test_chart_grid_must_hold_the_reference_theta(config, tmp_path):
    """A theta grid without the reference theta stops the chart before its sweeps, with one line
    naming the key; both shipped configs have it on their grid."""
    import design_chart

    from helpers import shipped_config
    from impactdamper.analysis.peaks import band_points

    cfg = shipped_config(config)  # ci.yaml merged over config.yaml, as a run reads it
    d = cfg["design"]
    band = np.linspace(
        d["theta_start"], d["theta_stop"], band_points([(d["theta_start"], d["theta_stop"])], d["band_step"])
    )
    assert np.any(np.abs(band - cfg["reference"]["theta"]) < 1e-9)
    design = {**d, "band_step": 0.4}  # 0.5, 0.83, 1.17, 1.5: theta = 1 is not a grid point
    with pytest.raises(ValueError, match=r"^`design.band_step` = 0.4 is not allowed: .* reference theta = 1$"):
        design_chart.main(cfg["reference"], design, tmp_path / "c.csv", tmp_path / "c.json")
    assert not (tmp_path / "c.csv").exists()


def test_design_table_linear_rows_recompute_in_closed_form():
    rec = read_json(FIGURES / "design_optimum.json")
    band = tuple(rec["band"])
    for d in rec["devices"]:
        if d["kind"] != "linear":
            continue
        bare = not d["parameters"]
        dev = LinearDevice(
            0.0 if bare else rec["mu"], d["parameters"].get("N", 1.0), rec["delta1"], d["parameters"].get("delta2", 0.0)
        )
        assert dev.peak(band)[1] == pytest.approx(d["peak"], rel=1e-12), d["device"]
        assert (0.0 if bare else dev.stroke_peak(band)[1]) == pytest.approx(d["stroke"], rel=1e-12)
        # A worst case is over scenarios that include the nominal one: never below the nominal peak.
        for w in d["worst"].values():
            assert w >= d["peak"] * (1 - 1e-12)


def test_design_table_answers_vouch_for_themselves():
    rec = read_json(FIGURES / "design_optimum.json")
    for c in ("peak", "band_average"):
        whole, reach = device(rec, f"impact_{c}"), device(rec, f"impact_{c}_reach")
        assert whole["search"]["value"] <= reach["search"]["value"]  # a box is never worse than a box inside it
    tmd = device(rec, "tmd_peak")
    assert tmd["peak"] < device(rec, "bare object")["peak"]
    assert device(rec, "tmd_band_average")["band_average"] <= tmd["band_average"] * (1 + 1e-9)
    assert device(rec, "tmd_detuning")["worst"]["detuning"] <= tmd["worst"]["detuning"] * (1 + 1e-9)
    for key in ("tmd_stroke", "impact_stroke"):
        d = device(rec, key)
        assert d["feasible"] == (d["stroke"] <= d["max_stroke"] * (1 + 1e-6))
    for d in rec["devices"]:
        if d["kind"] != "impact":
            continue
        p = impact_parameters(rec["mu"], rec["delta1"], d["parameters"])
        assert d["peak"] >= no_contact_floor(p, tuple(rec["band"])).value  # at least its own floor
        assert d["peak"] >= d["grid_peak"]
        assert d.get("tmd_limit", False) == (not d["impacts"])
        assert d["worst"]["together"] >= max(d["worst"][k] for k in ("detuning", "force", "restitution", "absorber"))
    headline = rec["impact"]
    assert headline["device"] == "impact_peak_reach" and headline["search"]["check"]["passed"]


# Halves the sub-region check found lower than their row's search answer (row, half): findings of
# the record, each adopted by the design search (the table's answer) and checked again.
KNOWN_LOWER = {("impact_restitution", "N upper")}


def _halves_searched(check: dict) -> set:
    """One sub-region check of figures/design_subregions.json: every half of its box without its
    answer searched (one per design variable) within its half, its margin its value against the
    answer's; the halves lower than the answer by more than the tolerance."""
    from impactdamper.studies.design.search import halves

    expected = {(n, side): half for n, side, half in halves(check["bounds"], check["parameters"])}
    assert len(expected) == len(check["bounds"]) == len(check["halves"])
    assert abs(check["reproduced"]) <= 1e-9 and check["budget"]["samples"] > 0
    lower = set()
    for h in check["halves"]:
        n, side = h["parameter"], h["half"]
        assert h["bounds"] == {k: list(v) for k, v in expected.pop((n, side)).items()}
        assert all(a <= h["parameters"][k] <= b for k, (a, b) in h["bounds"].items())
        assert h["margin"] == pytest.approx(h["value"] / check["value"] - 1.0, rel=1e-9, abs=1e-15)
        if h["margin"] < -check["rtol"]:
            lower.add(f"{n} {side}")
    assert check["passed"] == (not lower)
    return lower


def test_every_design_optimum_vouches_for_itself_against_its_boxs_halves():
    """figures/design_subregions.json: every row of the design table (both devices) has every
    half of its box without its search's answer searched (one per design variable), with the
    stated budget, by its own criterion (the answer's value reproduced); a half found lower is
    named (KNOWN_LOWER) and adopted: the table's answer is the local search from it, checked
    again; and no half is lower than the table's answer by more than the search's tolerance."""
    from impactdamper.studies.design.optimum import ROWS
    from impactdamper.studies.design.search import CHECK_RTOL
    from impactdamper.studies.design.subregions import SUBREGION_BUDGET

    sub, opt = read_json(FIGURES / "design_subregions.json"), read_json(FIGURES / "design_optimum.json")
    assert [r["device"] for r in sub["rows"]] == [key for key, *_ in ROWS]
    assert sub["budget"] == SUBREGION_BUDGET.to_dict() and sub["rtol"] == CHECK_RTOL
    found = set()
    for r in sub["rows"]:
        d = device(opt, r["device"])
        box = opt["bounds"]["tmd"] if r["device"].startswith("tmd") else d["search"]["bounds"]
        checks = [r, *r["rechecks"]]
        assert len(checks) == len(r["adopted"]) + 1, r["device"]
        for c in checks:
            assert c["budget"] == sub["budget"] and c["bounds"] == {n: box[n] for n in c["bounds"]}
        found |= {(r["device"], h) for h in _halves_searched(r)}
        for c, a, after in zip(checks, r["adopted"], checks[1:]):  # each adoption: no worse than its half
            assert a["searched"] <= a["value"] < c["value"] * (1 - CHECK_RTOL) and after["value"] == a["searched"]
            _halves_searched(after)
        # The table's answer is the last one checked, and it passed.
        last = checks[-1]
        assert r["final"]["value"] == last["value"] == d["search"]["value"], r["device"]
        assert last["parameters"] == {n: d["search"]["parameters"][n] for n in last["bounds"]}
        assert r["final"]["passed"] and last["passed"], r["device"]
        assert (d["search"]["source"] == "subregion") == bool(r["adopted"]), r["device"]
        assert min(h["margin"] for h in last["halves"]) >= -CHECK_RTOL
    assert found == KNOWN_LOWER == {(h["device"], h["half"]) for h in sub["lower"]}
    assert sub["adopted"] == [r["device"] for r in sub["rows"] if r["adopted"]]
    assert sub["halves_count"] == sum(len(r["halves"]) for r in sub["rows"]) == 40
    assert sub["passed"] and sub["smallest_margin"] >= -CHECK_RTOL


def test_located_peak_checks_hold():
    checks = read_json(FIGURES / "design_checks.json")
    assert checks["fine_largest_excess"] <= checks["sample_rtol"]
    for name in ("gap_two", "branch_end", "optimal_peak"):  # one branch each: the fine sweeps reach it
        assert checks[name]["fine"]["largest"] >= checks[name]["swept_peak"] * (1 - 2e-3), name
    assert checks["floor_largest_difference"] <= 1e-12
    assert checks["ivp_count"] >= 3 and checks["ivp_largest_difference"] <= 1e-7
    assert checks["gap_two"]["peak"] == pytest.approx(4.15, abs=1e-3)


def test_the_benchmark_page_gives_the_design_commands_times():
    """docs/BENCHMARKS.md (rule benchmarks_doc) holds the design command's wall and processor time
    per benchmark object, and the machine's load, as figures/design_benchmark.json records them."""
    import benchmarks_doc

    record = read_json(FIGURES / "design_benchmark.json")
    text = benchmarks_doc.design_section(record)
    assert len(record["objects"]) == len(CONFIG["design"]["benchmark_objects"])
    for o in record["objects"]:
        row = f"| {o['mu']:g}, {o['delta1']:g} | {o['how']} | {o['elapsed']:.0f} s | {o['cpu']:.0f} s |"
        assert row in text, text
    load = ", ".join(f"{x:.1f}" for x in record["machine"]["load_average"])
    assert f"the load average (1, 5, 15 min) at the end: {load}" in text
    assert text in (ROOT / "docs" / "BENCHMARKS.md").read_text()
