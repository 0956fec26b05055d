"""The orbits stage: the committed record (figures/orbit_*.csv, orbit_summary.json,
paper/generated/orbit_*.tex) against independent methods, and its regeneration.

* Special points against simulation: on both sides of the 2T cycle's period doubling and of
  its Neimark-Sacker point (``SIDE`` away), Algorithm No. 2 from a state on the cycle settles
  as the branch's stability says it must (a genuine 4T cycle past the period doubling,
  no settled motion past the Neimark-Sacker point).
* Special points against closed forms: the one-impact orbit's grazings and fold against
  Algorithm No. 1 (eq. 12's forced relative amplitude U1, its existence limit and its
  smallest gap).
* Multipliers of the cases against the finite-difference Jacobian of the simulated
  stroboscopic map.
* Regeneration: the branch rows next to each seed (legs capped at ``SHORT_POINTS`` orbits:
  the continuation is deterministic, so they are the committed rows) within ``RTOL``, with
  the special points found on them; the macros and the table exactly; the figure's pixels.
"""

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

import impactdamper as idp
from impactdamper.analysis.strobe import stroboscopic_jacobian

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "workflow" / "scripts"
FIGURES = ROOT / "figures"
GENERATED = ROOT / "paper" / "generated"
import fig_orbit_branches  # noqa: E402
import orbit_report  # noqa: E402
from impactdamper.reporting.records import cell_float, _csv_cell, read_csv, read_json, split_floats  # noqa: E402
from impactdamper.studies.sweeps import branches as st  # noqa: E402
from impactdamper.studies.config import parameters  # noqa: E402

# Numbers in the regenerated rows: far above run-to-run rounding, far below any change of the
# physics (the continuation converges to 1e-12).
RTOL = 1e-8
ATOL = 1e-10
# Distance in Delta0/x_st from a bifurcation at which simulation is asked to decide (close
# enough that nothing else happens between, far enough that the motion settles fast).
SIDE = 0.02
# Orbits per leg in the regeneration (enough to pass the 2T cycle's Neimark-Sacker point and
# the 3T cycle's grazing from their seeds).
SHORT_POINTS = 10
# Pixel tolerance of the regenerated figure (RMS on 0-255; style and fonts are pinned).
IMAGE_TOL = 0.01
REF = idp.Parameters()
D = np.array([REF.x_st, REF.x_st, REF.x_st * REF.omega, REF.x_st * REF.omega])


@pytest.fixture(scope="module")
def config() -> dict:
    return yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


@pytest.fixture(scope="module")
def special() -> list[dict]:
    return read_csv(FIGURES / "orbit_special_points.csv")


@pytest.fixture(scope="module")
def rows() -> list[dict]:
    return read_csv(FIGURES / "orbit_branches.csv")


@pytest.fixture(scope="module")
def summary() -> dict:
    return read_json(FIGURES / "orbit_summary.json")


def point(special, branch: str, kind: str) -> dict:
    (r,) = [r for r in special if r["branch"] == branch and r["kind"] == kind]
    return r


@pytest.fixture(scope="module")
def double10():
    """The 2T cycle with three impacts at Delta0/x_st = -10 (the seed of the double branch)."""
    p = REF.replace(gap=-10.0)
    return idp.solve_orbit(p, idp.steady_state(p, backend="python"))


def settle_from(orbit, gap: float):
    """Algorithm No. 2 at ``gap`` from the state of ``orbit`` (another gap) in its longest flight."""
    t = orbit.times[0] - 0.5 * (orbit.times[0] + orbit.cycle_duration - orbit.times[-1]) + orbit.cycle_duration
    return idp.steady_state(REF.replace(gap=gap), t0=t, state=orbit.state(t), backend="python")


def _sides(rows, sp) -> tuple[dict, dict]:
    i = int(sp["index"])
    b = [r for r in rows if r["branch"] == sp["branch"]]
    return b[i - 1], b[i]


# --- special points against simulation ------------------------------------------------------
def test_period_doubling_of_the_double_cycle_matches_simulation_on_both_sides(special, rows, double10):
    pd = point(special, "double", "period_doubling")
    g = cell_float(pd["gap"])
    assert g == pytest.approx(-9.488434, abs=1e-6)
    before, after = _sides(rows, pd)
    assert {before["stable"], after["stable"]} == {"0", "1"}  # the committed rows change there
    # Stable side (smaller gaps): the 3-impact 2T cycle, the branch's orbit.
    s = settle_from(double10, g - SIDE)
    assert (s.regime, s.period_multiple, s.impacts_per_cycle) == ("multi_impact", 2, 3)
    o = idp.solve_orbit(s.p, s)
    assert o.stable and o.admissible
    # Unstable side: a 4T cycle with six impacts that is not the 2T cycle repeated (the impact
    # velocities two periods apart differ far beyond the settling tolerance).
    s = settle_from(double10, g + SIDE)
    assert (s.regime, s.period_multiple, s.impacts_per_cycle) == ("multi_impact", 4, 6)
    v = np.array([i.velocity for i in s.impacts]) / (REF.x_st * REF.omega)
    assert np.max(np.abs(v[3:] - v[:3])) > 1e-2
    # ... and the 2T cycle is still there, unstable, with a real multiplier beyond -1.
    o = idp.orbit_from_cycle(s.p, 2, double10.times, double10.states_after)
    assert not o.stable and o.admissible
    assert o.multipliers[0].imag == 0.0 and o.multipliers[0].real < -1.0


@pytest.mark.slow
def test_neimark_sacker_point_of_the_double_cycle_matches_simulation_on_both_sides(special, rows, double10):
    ns = point(special, "double", "neimark_sacker")
    g = cell_float(ns["gap"])
    assert g == pytest.approx(-10.094962, abs=1e-6)
    before, after = _sides(rows, ns)
    assert {before["stable"], after["stable"]} == {"0", "1"}
    # Stable side (larger gaps): the motion settles on the 3-impact 2T cycle (slowly: |rho|
    # is close to 1 there).
    s = settle_from(double10, g + SIDE)
    assert (s.regime, s.period_multiple, s.impacts_per_cycle) == ("multi_impact", 2, 3)
    # Unstable side: the complex pair is outside the unit circle and no periodic motion settles.
    o = idp.orbit_from_cycle(REF.replace(gap=g - SIDE), 2, double10.times, double10.states_after)
    assert not o.stable and o.admissible
    assert abs(o.multipliers[0].imag) > 0.1 and abs(o.multipliers[0]) > 1.0
    s = settle_from(double10, g - SIDE)
    assert s.regime == "nonperiodic"


# --- special points against closed forms ------------------------------------------------------
def test_single_impact_grazings_and_fold_match_algorithm1(special):
    a1 = idp.algorithm1(REF)
    # The impact vanishes where the forced relative motion just reaches the stop: Delta0 = U1.
    high = max(
        (r for r in special if r["branch"] == "single" and r["kind"] == "grazing_velocity"),
        key=lambda r: cell_float(r["gap"]),
    )
    assert cell_float(high["gap"]) == pytest.approx(a1.U1 / REF.x_st, abs=1e-9)
    assert high["admissible"] == "1"
    # The fold is where Algorithm No. 1's orbit ceases to exist.
    fold = cell_float(point(special, "single", "fold")["gap"])
    assert idp.algorithm1(REF.replace(gap=fold + 1e-7)).exists
    assert not idp.algorithm1(REF.replace(gap=fold - 1e-7)).exists
    # The interior touch is where Algorithm No. 1's smallest gap changes sign.
    touch = cell_float(point(special, "single", "grazing_interior")["gap"])
    assert idp.algorithm1(REF.replace(gap=touch + 1e-7)).min_gap > 0
    assert idp.algorithm1(REF.replace(gap=touch - 1e-7)).min_gap < 0
    # The 2T and 3T cycles are born there: their vanishing impact is the 1/1 orbit's touch.
    for branch in ("double", "triple"):
        assert cell_float(point(special, branch, "grazing_velocity")["gap"]) == pytest.approx(touch, abs=1e-9)


# --- multipliers against the simulated map ------------------------------------------------------
@pytest.mark.parametrize("case", ["stated", "located", "example"])
def test_case_multipliers_match_finite_differences_of_the_simulated_map(case, summary):
    c = summary["cases"][case]
    o = idp.solve_orbit(REF.replace(gap=c["gap"]), "auto")
    assert (o.period_multiple, o.impacts_per_cycle, o.stable, o.admissible) == (
        c["k"],
        c["z"],
        c["stable"],
        c["admissible"],
    )
    flight = o.times[0] + o.cycle_duration - o.times[-1]
    t = o.times[0] - 0.5 * flight + o.cycle_duration
    J = stroboscopic_jacobian(o.p, t, o.state(t), o.period_multiple)
    fd = np.sort(np.abs(np.linalg.eigvals(J)))[::-1]
    assert fd == pytest.approx(c["multipliers"], abs=1e-6)


# --- regeneration ---------------------------------------------------------------------------
def _same_row(new: dict, old: dict) -> list[str]:
    bad = []
    for col in st.BRANCH_COLUMNS:
        if col == "index":
            continue  # the short run's rows are numbered from its own lower end
        a, b = _csv_cell(new[col], booleans="digits"), old[col]
        if col in ("velocities", "phases"):
            x, y = split_floats(a), split_floats(b)
            if len(x) != len(y) or not np.allclose(x, y, rtol=RTOL, atol=ATOL):
                bad.append(f"{col}: {a} != {b}")
        elif col in ("gap", "x1_max", "min_gap", "spectral_radius"):
            x, y = cell_float(a), cell_float(b)
            if not (math.isclose(x, y, rel_tol=RTOL, abs_tol=ATOL) or (math.isnan(x) and math.isnan(y))):
                bad.append(f"{col}: {a} != {b}")
        elif a != b:
            bad.append(f"{col}: {a} != {b}")
    return bad


@pytest.mark.parametrize("name", ["single", "double", "triple"])
def test_branch_rows_next_to_the_seed_regenerate(name, config, rows, special, summary):
    spec = next(b for b in config["orbits"]["branches"] if b["name"] == name)
    cont = dict(config["orbits"]["continuation"], max_points=SHORT_POINTS)
    b = st.follow(parameters(config["reference"]), spec, cont, config["solver"])
    committed = [r for r in rows if r["branch"] == name]
    seed = summary["branches"][name]["seed_index"]
    new = st.branch_rows(b)
    assert b["seed_index"] == SHORT_POINTS - 1 and len(new) == 2 * SHORT_POINTS - 1
    for j, r in enumerate(new):
        old = committed[seed - b["seed_index"] + j]
        assert not _same_row(r, old), (j, _same_row(r, old))
    # Special points met on the short legs are committed ones.
    found = st.special_rows(b)
    if name != "single":
        assert found  # the 2T cycle's Neimark-Sacker point, the 3T cycle's grazing
    for r in found:
        assert any(
            c["branch"] == name
            and c["kind"] == r["kind"]
            and math.isclose(cell_float(c["gap"]), r["gap"], abs_tol=1e-9)
            for c in special
        ), r


def test_macros_and_table_regenerate_exactly(tmp_path):
    orbit_report.main(
        FIGURES / "orbit_branches.csv",
        FIGURES / "orbit_special_points.csv",
        FIGURES / "orbit_summary.json",
        tmp_path / "record.json",
        tmp_path / "m.tex",
        tmp_path / "t.tex",
    )
    assert (tmp_path / "m.tex").read_text() == (GENERATED / "orbit_macros.tex").read_text()
    assert (tmp_path / "t.tex").read_text() == (GENERATED / "orbit_special_points_table.tex").read_text()


def test_macros_quote_the_special_points_and_stable_interval(special):
    text = (GENERATED / "orbit_macros.tex").read_text()
    macros = dict(__import__("re").findall(r"\\newcommand\{\\(\w+)\}\{([^}]*)\}", text))
    assert all(name.isalpha() for name in macros)
    ns, pd = (cell_float(point(special, "double", k)["gap"]) for k in ("neimark_sacker", "period_doubling"))
    assert float(macros["OrbitNSDouble"]) == pytest.approx(ns, abs=5e-7)
    assert float(macros["OrbitPDDouble"]) == pytest.approx(pd, abs=5e-7)
    assert (float(macros["OrbitStableDoubleLow"]), float(macros["OrbitStableDoubleHigh"])) == pytest.approx(
        (ns, pd), abs=5e-7
    )
    assert macros["OrbitStatedMultA"] == "0.711289" and macros["OrbitStatedMultC"] == "0.511990"
    assert macros["OrbitExampleMultA"] == "0.925912"


@pytest.mark.slow
def test_figure_regenerates(tmp_path):
    from matplotlib.testing.compare import compare_images

    fig_orbit_branches.main(
        FIGURES / "orbit_branches.csv",
        FIGURES / "orbit_special_points.csv",
        FIGURES / "orbit_summary.json",
        tmp_path / "f.pdf",
        tmp_path / "f.png",
    )
    assert compare_images(str(FIGURES / "orbit_branches.png"), str(tmp_path / "f.png"), tol=IMAGE_TOL) is None


# --- bad configuration --------------------------------------------------------------------------
def test_config_rejects_a_branch_name_that_cannot_name_a_macro(config):
    from snakemake.exceptions import WorkflowError
    from snakemake.utils import validate

    bad = yaml.safe_load(yaml.safe_dump(config))
    bad["orbits"]["branches"][0]["name"] = "branch2"
    with pytest.raises(WorkflowError, match=r"\['orbits'\]\['branches'\]\[0\]\['name'\]"):
        validate(bad, str(ROOT / "workflow" / "schemas" / "config.schema.yaml"))


def test_seed_outside_its_bounds_names_the_entry(config):
    spec = dict(config["orbits"]["branches"][0], gap_max=-6.0)
    with pytest.raises(ValueError, match=r"`orbits.branches` entry 'single': need gap_min <= gap <= gap_max"):
        st.follow(REF, spec, config["orbits"]["continuation"], config["solver"])


def test_regression_newton_polish_overflow_on_an_inadmissible_flight():
    """Bug guarded: after "Newton polish converges from either side" (events.py), the flight
    scan of an orbit whose gap is negative at its minimum (g = -1.8, g' = -2e-14 at the
    certified point) took a Newton step of ~1e14 s back and overflowed the exponentials
    (OverflowError: math range error) in the one-impact branch's continuation at
    Delta0/x_st = 8.2458 on its wrong-way (mirror) part."""
    from impactdamper.core.events import Segment, march
    from impactdamper.core.model import Model

    model = Model(REF.replace(gap=8.245772220993132))
    y0 = np.array([-6.3354571100981305, 1.9103151108950016, 9.162685774665176, 96.2287970472288])
    seg = Segment(model.free, 0.0762008458318722, y0)
    root, _ = march(seg, model.gap, 0.0762008458318722, 0.7045193765498308, 1e-12, (2, 1010.0878611289282))
    assert root is not None and model.gap_of(seg.state(root[0])) < 0  # the search started past the stop
