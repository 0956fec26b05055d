"""Tests of the work-precision methods' table (:mod:`impactdamper.studies.performance.methods`): every
method answers through the one protocol (``impacts()``, ``state_at(t)``) on a short window of
the reference case, agreeing with the exact solver; the vocabulary the report, the figure and
the config schema use is the table's."""

from pathlib import Path

import numpy as np
import pytest
import yaml

from impactdamper import Parameters, simulate
from impactdamper.baselines.ivp import METHODS as IVP_METHODS
from impactdamper.studies.performance import methods as mt
from impactdamper.studies.performance import workprecision as wp

ROOT = Path(__file__).resolve().parents[2]
REF = Parameters()
# A coarse setting per method and how close (in units of T) its impacts come to the exact
# solver's over the first three impacts from the default start: loose enough for RK4 at 2000
# steps per period and the solve_ivp methods at rtol 1e-8.
COARSE = {"exact": 1e-9, "RK45": 1e-8, "DOP853": 1e-8, "Radau": 1e-8, "LSODA": 1e-8, "RK4": 2000}
TIME_TOL = {"exact": 1e-9, "RK45": 1e-5, "DOP853": 1e-5, "Radau": 1e-5, "LSODA": 1e-5, "RK4": 1e-4}


def test_the_table_holds_every_family_once_in_report_order():
    assert list(mt.METHODS) == ["exact", "alg1", *IVP_METHODS, "RK4", "Moreau-Jean"]
    assert mt._methods_of_family("solve_ivp") == IVP_METHODS
    assert wp.FAMILIES == tuple(mt.METHODS)
    assert mt.reported_alone() == ("alg1", "RK4", "Moreau-Jean")
    assert all(m.macro.isalpha() for m in mt.METHODS.values())
    assert len({m.macro for m in mt.METHODS.values()}) == len(mt.METHODS)


def test_config_schema_enums_are_the_tables_solve_ivp_methods():
    schema = yaml.safe_load((ROOT / "workflow" / "schemas" / "config.schema.yaml").read_text())
    perf = schema["properties"]["performance"]["properties"]
    assert perf["ivp_methods"]["items"]["enum"] == list(mt._methods_of_family("solve_ivp"))
    assert schema["properties"]["verdict"]["properties"]["ivp_method"]["enum"] == list(IVP_METHODS)
    for m in mt.METHODS.values():
        if m.settings_key is not None:
            assert m.settings_key in perf, m.name


def test_selected_follows_the_configs_ivp_methods():
    names = [m.name for m in mt.selected({"ivp_methods": ["DOP853"]})]
    assert names == ["exact", "alg1", "DOP853", "RK4", "Moreau-Jean"]


@pytest.mark.parametrize("name", list(COARSE))
def test_every_method_answers_through_one_protocol(name):
    # The first three impacts from the default start (the fourth starts a chattering sequence).
    first = [e.t for e in simulate(REF, REF.T).impacts()]
    t_end = 0.5 * (first[2] + first[3])
    exact = simulate(REF, t_end)
    want = np.array([e.t for e in exact.impacts()])
    state0 = exact.sample(0.0)[0]
    sol = mt.METHODS[name].solve(REF, t_end, 0.0, state0, COARSE[name])
    got = sol.impacts()
    assert len(want) > 0 and len(got) == len(want)
    assert np.max(np.abs(got - want)) / REF.T < TIME_TOL[name]
    end = sol.state_at(t_end)
    scale = np.array([REF.x_st, REF.x_st, REF.x_st * REF.omega, REF.x_st * REF.omega])
    assert end.shape == (4,) and np.max(np.abs(end - exact.sample(t_end)[0]) / scale) < 1e3 * TIME_TOL[name]


def test_a_time_stepping_run_knows_its_final_state_only():
    sol = mt.METHODS["RK4"].solve(REF, 0.5 * REF.T, 0.0, None, 500)
    assert sol.state_at(0.5 * REF.T).shape == (4,)
    with pytest.raises(ValueError, match="`t` = 0.1 is not allowed"):
        sol.state_at(0.1)


def test_algorithm1_gives_its_orbit_or_none():
    sol = mt.METHODS["alg1"].solve(REF, 3 * REF.T, 0.0, None)
    assert np.diff(sol.impacts()) == pytest.approx(REF.T, rel=1e-14)
    # The orbit repeats after one period.
    assert sol.state_at(0.3 * REF.T) == pytest.approx(sol.state_at(1.3 * REF.T), abs=1e-12)
