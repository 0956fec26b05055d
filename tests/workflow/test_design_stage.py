"""The design stage ("Choosing a suppressor"): its committed records (figures/design_*,
paper/generated/design_*) are present and consistent with each other and with the library.

* The best gap of each criterion is the chart's smallest value, its good band the contiguous
  run within the stated tolerance, and its loads the chart's row.
* The linear baselines regenerate byte for byte (closed forms and the TMD optimiser are cheap).
* Every cycle of the frequency response closes its energy balance; cycles without contact
  equal the linear response; the hysteresis flag matches the two directions' rows.
* The macros quote the records.
* The design table (figures/design_optimum.*): every linear row's located peak, band average,
  worst cases and stroke recomputed in closed form; the optima no worse than the designs they
  started from; the equal-stroke TMD within its stroke; the table and recommendation
  regenerate from the record.
"""

import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

import design_baselines
import design_report
from impactdamper.reporting.records import cell_float, read_csv, read_json
from impactdamper.studies.design.design import CRITERIA, good_band

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
]
# The settled cycles are periodic to the sweep's settle tolerance (1e-9 x_st): ten times that.
LINEAR_ATOL = 1e-8
# The quadrature closes the balance to rounding (~1e-13): 1e-10 leaves margin.
BALANCE_TOL = 1e-10


def test_records_are_present():
    for name in RECORDS:
        assert (FIGURES / name).stat().st_size > 0, name
    for name in ("design_macros.tex", "design_second_table.tex", "design_table.tex"):
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
            good_band(gaps, values, CONFIG["design"]["tolerance"])
        )
        assert best[c]["peak_impulse"] == pytest.approx(float(rows[i]["peak_impulse"]), rel=1e-10)


def test_baselines_regenerate_byte_for_byte(tmp_path):
    design_baselines.main(CONFIG["reference"], CONFIG["design"], tmp_path / "b.csv", tmp_path / "b.json")
    assert (tmp_path / "b.csv").read_bytes() == (FIGURES / "design_baselines.csv").read_bytes()
    assert (tmp_path / "b.json").read_bytes() == (FIGURES / "design_baselines.json").read_bytes()


def test_tmd_beats_the_untuned_absorber_and_den_hartog_check_holds():
    base = read_json(FIGURES / "design_baselines.json")
    tmd = base["tmd"]["peak"]
    assert tmd["peak"] < base["references"]["absorber"]["peak"] < base["references"]["bare"]["peak"]
    check = base["den_hartog_check"]
    assert 0.0 <= check["peak_relative_excess"] <= 0.005
    assert abs(check["N_relative_difference"]) <= 1e-3


def test_frequency_response_records_are_consistent():
    rows = read_csv(FIGURES / "design_response.csv")
    best = read_json(FIGURES / "design_chart.json")["best"]["peak"]["gap"]
    summary = read_json(FIGURES / "design_response.json")["responses"]
    assert summary[0]["role"] == "best" and summary[0]["gap"] == best
    assert {float(r["gap"]) for r in rows} == {s["gap"] for s in summary}
    for r in rows:
        if r["regime"] == "failed":
            continue
        assert cell_float(r["balance"]) <= BALANCE_TOL, r
        if r["regime"] == "no_contact":
            assert abs(cell_float(r["max_abs_x1"]) - cell_float(r["linear_max_abs_x1"])) <= LINEAR_ATOL
            assert abs(cell_float(r["max_abs_x2"]) - cell_float(r["linear_max_abs_x2"])) <= LINEAR_ATOL
    pairs = {}
    for r in rows:
        pairs.setdefault((r["gap"], r["theta"]), {})[r["direction"]] = r
    for pair in pairs.values():
        up, down = pair["up"], pair["down"]
        assert up["hysteresis"] == down["hysteresis"]
        differ = up["label"] != down["label"] or not math.isclose(
            cell_float(up["max_abs_x1"]), cell_float(down["max_abs_x1"]), rel_tol=1e-4
        )
        assert (up["hysteresis"] == "1") == differ
    for s in summary:
        worst = [
            max(cell_float(p["up"]["max_abs_x1"]), cell_float(p["down"]["max_abs_x1"]))
            for (g, _), p in pairs.items()
            if float(g) == s["gap"]
        ]
        assert s["peak"] == pytest.approx(max(worst), rel=1e-10)


def test_macros_quote_the_records(tmp_path):
    text = (GENERATED / "design_macros.tex").read_text()
    macros = dict(re.findall(r"\\newcommand\{\\(\w+)\}\{(.*)\}", text))
    best = read_json(FIGURES / "design_chart.json")["best"]["peak"]
    base = read_json(FIGURES / "design_baselines.json")
    assert float(macros["DesignBestGap"]) == pytest.approx(best["gap"], abs=0.005)
    assert float(macros["DesignBestPeak"]) == pytest.approx(best["value"], abs=0.005)
    assert float(macros["DesignTmdPeak"]) == pytest.approx(base["tmd"]["peak"]["peak"], abs=0.005)
    assert float(macros["DesignRatioTmd"]) == pytest.approx(best["value"] / base["tmd"]["peak"]["peak"], abs=0.005)
    # The report's text says the optimal TMD has the lower peak, and that the criterion at theta = 1
    # alone picks another gap than the band: both must hold in the records it quotes.
    assert best["value"] > base["tmd"]["peak"]["peak"]
    one = read_json(FIGURES / "design_chart.json")["at_reference_theta"]
    assert one["gap"] != best["gap"]
    # And the report step regenerates them exactly from the records.
    design_report.main(
        FIGURES / "design_baselines.json",
        FIGURES / "design_chart.json",
        FIGURES / "design_chart_2d.json",
        FIGURES / "design_response.json",
        FIGURES / "design_response.csv",
        FIGURES / "design_optimum.json",
        tmp_path / "r.json",
        tmp_path / "m.tex",
        tmp_path / "t.tex",
        tmp_path / "d.tex",
    )
    assert (tmp_path / "m.tex").read_text() == text
    assert (tmp_path / "t.tex").read_text() == (GENERATED / "design_second_table.tex").read_text()
    assert (tmp_path / "d.tex").read_text() == (GENERATED / "design_table.tex").read_text()


def test_a_chart_row_regenerates():
    """The chart's row at the best gap, recomputed on its own (every gap's response starts
    afresh, so one row is the committed one), within the settle tolerance's reach."""
    from impactdamper.studies.config import sweep_settings
    from impactdamper.studies.design.design import design_band, design_parameters, gap_chart

    design = CONFIG["design"]
    best = read_json(FIGURES / "design_chart.json")["best"]["peak"]
    row = next(r for r in read_csv(FIGURES / "design_chart.csv") if float(r["gap"]) == best["gap"])
    chart = gap_chart(
        design_parameters(CONFIG["reference"], design),
        [best["gap"]],
        design_band(design),
        int(design["theta_points"]),
        settings=sweep_settings(CONFIG["sweep"], CONFIG["solver"]),
    )
    new = chart.rows()[0]
    for key in ("peak_max_abs_x1", "band_average_max_abs_x1", "peak_impulse", "impacts_per_period"):
        assert new[key] == pytest.approx(float(row[key]), rel=1e-8, abs=1e-8), key


def test_figures_regenerate_deterministically(tmp_path):
    import fig_design_chart

    for run in ("a", "b"):
        fig_design_chart.main(
            FIGURES / "design_chart.csv",
            FIGURES / "design_chart.json",
            FIGURES / "design_baselines.json",
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

    cfg = shipped_config(config)  # ci.yaml merged over config.yaml, as a run reads it
    band = np.linspace(cfg["design"]["theta_start"], cfg["design"]["theta_stop"], cfg["design"]["theta_points"])
    assert np.any(np.abs(band - cfg["reference"]["theta"]) < 1e-9)
    design = {**cfg["design"], "theta_points": 6}  # 0.5, 0.7, ..., 1.5: theta = 1 is not a grid point
    with pytest.raises(ValueError, match=r"^`design.theta_points` = 6 is not allowed: .* reference theta = 1$"):
        design_chart.main(
            cfg["reference"], cfg["solver"], cfg["sweep"], design, tmp_path / "c.csv", tmp_path / "c.json"
        )
    assert not (tmp_path / "c.csv").exists()


def test_design_table_linear_rows_recompute_in_closed_form():
    from impactdamper.studies.design.design import LinearDevice

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
        assert dev.band_average(band, rec["step"]) == pytest.approx(d["band_average"], rel=1e-12)
        assert (0.0 if bare else dev.stroke_peak(band)[1]) == pytest.approx(d["stroke"], rel=1e-12)
        # A worst case is over detunings that include none: never below the nominal peak.
        for w in d["worst_case"].values():
            assert w >= d["peak"] * (1 - 1e-12)


def test_design_table_optima_are_no_worse_than_their_starts():
    from impactdamper.studies.design.optimum import device

    rec = read_json(FIGURES / "design_optimum.json")
    imp, tmd = device(rec, "impact, optimal peak"), device(rec, "TMD, optimal peak")
    paper = next(d for d in rec["devices"] if d["device"].startswith("impact, paper"))
    absorber = device(rec, "absorber without a stop")
    # The optimiser started from the paper's design among others: its located peak is no higher.
    assert imp["peak"] <= paper["peak"] * (1 + 1e-4)
    assert tmd["peak"] < absorber["peak"] < device(rec, "bare object")["peak"]
    assert device(rec, "TMD, optimal band average")["band_average"] <= tmd["band_average"] * (1 + 1e-9)
    eq = device(rec, "TMD, impact's stroke")
    assert eq["stroke"] <= eq["max_stroke"] * (1 + 1e-3)
    # The robust TMD's worst case at the largest detuning is no worse than the nominal optimum's.
    key = f"{max(rec['detunings']):g}"
    rob = next(d for d in rec["devices"] if d["device"].startswith("TMD, robust"))
    assert rob["worst_case"][key] <= tmd["worst_case"][key] * (1 + 1e-9)
    # Located peaks are never below the grid's.
    for d in rec["devices"]:
        if d["kind"] == "impact":
            assert d["peak"] >= d["grid_peak"]
