"""The hard-case suite (src/impactdamper/studies/performance/hardcases.py and its checks,
hardcase_checks.py): every case passes its checks, and the checks themselves catch what they are meant to catch (an overlap, a wrong impact law, a hang).

The solver's behaviour in hard cases is tested in test_steady.py; here the subject is the
suite: its case definitions, its runner and its checks. CPU times are recorded by the runner,
never asserted."""

import dataclasses
import time

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.studies.performance import hardcase_checks as checks
from impactdamper.studies.performance import hardcases as hc
from impactdamper.baselines import highprecision as hp
from impactdamper.core.events import Segment
from impactdamper.core.linear import forced_amplitudes
from impactdamper.core.model import FREE
from impactdamper.core.trajectory import Event

REF = idp.Parameters()
CASES = {c.name: c for c in hc._hard_cases()}


@pytest.fixture(scope="module")
def results():
    """Every case run once (~10 s in all: the tests that use it are marked slow)."""
    return {name: hc._run_case(case) for name, case in CASES.items()}


# --- the case definitions ---------------------------------------------------------------------
def test_the_suite_covers_the_issue():
    changes = [c.changes for c in CASES.values()]
    assert len(CASES) == len(changes) >= 15
    for wanted in (
        {"R": 0.0},
        {"R": 1.0},
        {"delta1": 0.0, "delta2": 0.0},
        {"mu": 1e-4},
        {"N": 50.0},
        {"theta": 0.1},
        {"theta": 10.0},
        {"gap": 0.0},
        {"gap": 1e3},
        {"gap": -1e3},
    ):
        assert wanted in changes
    assert all(c.stresses and c.label for c in CASES.values())


def test_no_contact_threshold_is_the_forced_relative_amplitude():
    x1p, x2p = forced_amplitudes(REF)
    assert hc._no_contact_threshold(REF) == pytest.approx(abs(x2p - x1p) / REF.x_st, rel=1e-14)


def test_onset_gap_is_where_algorithm1_touches_the_stop():
    g = hc._alg1_onset_gap(REF)
    assert -10.0 < g < -5.8
    a = idp.algorithm1(REF.replace(gap=g))
    assert a.exists and abs(a.min_gap) < 1e-10
    # a little lower the orbit crosses the stop, a little higher it clears it
    assert idp.algorithm1(REF.replace(gap=g - 1e-6)).min_gap < 0 < idp.algorithm1(REF.replace(gap=g + 1e-6)).min_gap


def test_repeated_roots_case_has_a_double_root():
    p = CASES["repeated_roots"].parameters()
    roots = np.sort_complex(np.array([complex(r) for r in hp.algorithm1_mp(p).roots]))
    gaps = np.abs(np.diff(roots))
    assert gaps.min() < 1e-7 * np.abs(roots).max()


def test_grazing_starts_lie_on_their_orbits():
    p = CASES["grazing_no_contact"].parameters()
    t0, y0 = CASES["grazing_no_contact"].initial(p)
    model = idp.simulate(p, p.T, t0=t0, state=y0, backend="python").model
    # on the forced response, the gap's minimum over a period is zero (the threshold)
    ts = np.linspace(0.0, p.T, 20001)
    gap = model.gap_of(model.free.forced(ts))
    assert abs(gap.min()) < 1e-6 * p.x_st
    p = CASES["grazing_alg1_onset"].parameters()
    t0, y0 = CASES["grazing_alg1_onset"].initial(p)
    a = idp.algorithm1(p)
    assert t0 == pytest.approx(a.t_impact, abs=1e-12 * p.T)
    assert np.allclose(y0, a.state_after, rtol=1e-10, atol=1e-10)


def test_unknown_case_names_are_refused():
    with pytest.raises(ValueError, match="`names`"):
        hc.run_suite(names=["no_such_case"], log=lambda s: None)
    with pytest.raises(ValueError, match="`start`"):
        dataclasses.replace(CASES["chatter"], start="somewhere").initial(REF)


# --- every case passes ------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(CASES))
def test_case_passes_every_check(results, name):
    r = results[name]
    assert r.checks == {c: True for c in hc.CHECKS}, r.details
    assert r.regime in idp.REGIMES
    assert r.passed
    row = r.row()
    assert row["case"] == name and row["passed"] is True and row["cpu_seconds"] >= 0.0


@pytest.mark.slow
def test_outcomes_are_the_expected_regimes(results):
    expected = {
        "plastic": "chatter",
        "elastic": "single_impact",
        "chatter": "chatter",
        "conservative": "nonperiodic",
        "large_positive_gap": "no_contact",
        "large_negative_gap": "stuck",
        "stiff_suppressor": "stuck",
        "slow_forcing": "stuck",
        "fast_forcing": "stuck",
        "zero_gap": "single_impact",
        "tiny_mass": "single_impact",
    }
    for name, regime in expected.items():
        assert results[name].regime == regime, name


@pytest.mark.slow
def test_grazing_cases_touch_at_the_closed_form_tangency(results):
    for name in ("grazing_no_contact", "grazing_alg1_onset"):
        r = results[name]
        assert r.touches >= 1
        assert r.details["touch_time_diff"] < checks.TOUCH_TIME_TOL
        assert "mp tangency" in r.details["reference_kind"]


@pytest.mark.slow
def test_references_are_the_independent_ones(results):
    assert "mp settled cycle" in results["elastic"].details["reference_kind"]
    assert "mp forced response" in results["large_negative_gap"].details["reference_kind"]
    assert "mp forced response" in results["large_positive_gap"].details["reference_kind"]
    for r in results.values():
        assert "solve_ivp window" in r.details["reference_kind"]


# --- the checks catch violations --------------------------------------------------------------
def _reference_trajectory():
    return idp.simulate(REF, 2 * REF.T, backend="python")


def test_gap_check_catches_an_overlap():
    traj = _reference_trajectory()
    assert checks.check_gap_nonnegative(traj, 2 * REF.T)[0]
    # move the suppressor 1e-6 x_st into the stop during the first flight
    mode, seg = traj.segments[0]
    y0 = seg.y0.copy()
    y0[1] += 1e-6 * REF.x_st
    traj.segments[0] = (mode, Segment(seg.mode, seg.t0, y0))
    ok, worst = checks.check_gap_nonnegative(traj, 2 * REF.T)
    assert not ok and worst < -1e-7


def test_gap_check_allows_only_the_time_resolution():
    # an overlap of 1e-12 x_st at t ~ 1 s is within the allowance, 1e-8 is not
    traj = _reference_trajectory()
    mode, seg = traj.segments[0]
    for shift, ok in ((1e-13, True), (1e-7, False)):
        y0 = seg.y0.copy()
        y0[1] += shift * REF.x_st
        traj.segments[0] = (mode, Segment(seg.mode, seg.t0, y0))
        assert checks.check_gap_nonnegative(traj, 2 * REF.T)[0] is ok


def test_impact_law_check_catches_a_wrong_restitution_and_momentum():
    traj = _reference_trajectory()
    assert checks.check_impact_law(traj)[0]
    e = next(e for e in traj.events if e.kind == "impact")
    i = traj.events.index(e)
    bad = e.after.copy()
    bad[3] += 1e-3 * REF.x_st * REF.omega  # the suppressor's velocity off: restitution and momentum
    traj.events[i] = Event(e.t, e.kind, e.velocity, e.impulse, e.before, bad, e.t_accumulation)
    ok, worst = checks.check_impact_law(traj)
    assert not ok and worst["restitution"] > 1e-6 and worst["momentum"] > 1e-8


def test_impact_law_check_catches_an_impact_off_the_stop():
    traj = _reference_trajectory()
    e = next(e for e in traj.events if e.kind == "impact")
    i = traj.events.index(e)
    before = e.before.copy()
    before[0] += 1e-6 * REF.x_st
    traj.events[i] = Event(e.t, e.kind, e.velocity, e.impulse, before, e.after, e.t_accumulation)
    ok, worst = checks.check_impact_law(traj)
    assert not ok and worst["gap"] > 1e-8


def test_ivp_comparison_catches_a_different_motion():
    ok, info = checks._compare_with_ivp(REF, 0.0, None, 1.5 * REF.T)
    assert ok and info["event_time_diff"] < checks.IVP_TIME_TOL
    # a different restitution changes the motion: the comparison of the two must fail
    exact = idp.simulate(REF, 1.5 * REF.T, backend="python")
    other = idp.simulate(REF.replace(R=0.69), 1.5 * REF.T, backend="python")
    assert [e.kind for e in exact.events] != [e.kind for e in other.events] or max(
        abs(a.t - b.t) for a, b in zip(exact.events, other.events)
    ) / REF.T > checks.IVP_TIME_TOL


def test_a_hang_becomes_a_failed_case(monkeypatch):
    def never_returns(*args, **kwargs):
        while True:
            time.sleep(0.05)

    monkeypatch.setattr(hc, "steady_state", never_returns)
    r = hc._run_case(CASES["elastic"], wall_limit=1)
    assert r.regime == "timeout" and not r.passed
    assert all(v is False for v in r.checks.values())


def test_free_segments_only_are_gap_checked():
    traj = idp.simulate(REF.replace(gap=-13.0), 2 * REF.T, backend="python")  # chatter: stuck segments too
    modes = {m for m, _ in traj.segments}
    assert modes == {FREE, "stuck"}
    assert checks.check_gap_nonnegative(traj, 2 * REF.T)[0]
