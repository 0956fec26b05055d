"""Algorithm No. 1 (eqs. 7-8, 13-17): closed-form checks, periodicity, admissibility, and
agreement with Algorithm No. 2 wherever its orbit is admissible."""

import json
import math

import numpy as np
import pytest
import scipy.integrate
import scipy.optimize

from helpers import REF, free_rhs, gap, phase_difference

import impactdamper as idp
from impactdamper.core.algorithm1 import unit_pulse_response
from impactdamper.core.linear import free_mode

# --- closed forms first ----------------------------------------------------------------------


@pytest.mark.parametrize("gap_value", [-5.8, -10.0, 0.0, 2.0])
def test_both_roots_of_eq17_solve_eq16_and_the_positive_pulse_is_chosen(gap_value):
    p = REF.replace(gap=gap_value)
    r = idp.algorithm1(p)
    assert r.exists and len(r.candidates) == 2
    for eps, _S in r.candidates:
        lhs = r.U1 * math.sin(eps + r.eps21) + r.U2 * math.cos(eps + r.eps21)
        assert lhs == pytest.approx(p.Delta0, abs=1e-12 * math.hypot(r.U1, r.U2))
    assert r.S > 0 and (r.eps, r.S) in r.candidates
    assert sum(S > 0 for _, S in r.candidates) >= 1
    D = p.reduced_mass * (1 + p.R)
    assert r.S == pytest.approx(D * r.velocity, rel=1e-14)  # eq. (14)
    assert 0.0 <= r.eps < 2 * math.pi and r.impact_phase == pytest.approx(r.eps / (2 * math.pi), rel=1e-15)


@pytest.mark.parametrize("p", [REF, REF.replace(delta1=2.0, delta2=5.0), REF.replace(theta=0.7, mu=0.3)])
def test_unit_pulse_response_satisfies_the_periodicity_conditions_eq7(p):
    z0 = unit_pulse_response(p)
    assert unit_pulse_response(p, modal=True) == pytest.approx(z0, rel=1e-10)
    assert unit_pulse_response(p, modal=False) == pytest.approx(z0, rel=1e-10)
    # Independent: integrate the unforced eqs. (2) over T from z0.
    f0 = free_rhs(p.replace(x_st=1e-300))  # P0 = c1 x_st: no forcing to rounding level
    sol = scipy.integrate.solve_ivp(f0, (0, p.T), z0, method="DOP853", rtol=1e-13, atol=1e-16)
    zT = sol.y[:, -1]
    s = np.max(np.abs(z0))
    assert zT[0] == pytest.approx(z0[0], abs=1e-10 * s)
    assert zT[1] == pytest.approx(z0[1], abs=1e-10 * s)
    assert p.m1 * zT[2] == pytest.approx(p.m1 * z0[2] - 1.0, abs=1e-10 * p.m1 * s)
    assert p.m2 * zT[3] == pytest.approx(p.m2 * z0[3] + 1.0, abs=1e-10 * p.m1 * s)


@pytest.mark.parametrize(
    "p",
    [
        REF,
        REF.replace(gap=-10.0),
        REF.replace(gap=2.0, R=1.0),
        REF.replace(gap=0.0, R=0.0),
        REF.replace(theta=0.8, gap=2.0),
    ],
)
def test_the_orbit_is_periodic_through_the_impact_law(p):
    """Flowing the post-impact state for T returns to the stop with the same pre-impact
    velocity: the impact law maps it onto the post-impact state again."""
    r = idp.algorithm1(p)
    assert r.exists
    t0 = r.t_impact
    after = r.state_after
    before = r.sample(p.T)  # exact flow, just before the next impact
    sol = scipy.integrate.solve_ivp(free_rhs(p), (t0, t0 + p.T), after, method="DOP853", rtol=1e-13, atol=1e-13)
    scale = np.max(np.abs(after))
    assert np.max(np.abs(sol.y[:, -1] - before)) <= 1e-9 * scale
    assert abs(gap(p, before)) <= 1e-11 * scale
    v = before[3] - before[2]
    assert v == pytest.approx(r.velocity, rel=1e-10)
    S = p.reduced_mass * (1 + p.R) * v
    kicked = before + np.array([0, 0, S / p.m1, -S / p.m2])
    assert np.max(np.abs(kicked - after)) <= 1e-10 * scale


# --- the negative-gap intervals (Fig. 2a) and the minimum gap ---------------------------------


def test_gap_minus_10_goes_negative_inside_the_reported_interval():
    p = REF.replace(gap=-10.0)
    r = idp.algorithm1(p)
    assert r.exists and not r.admissible
    ((a, b),) = r.negative_gap_intervals
    assert (a, b) == pytest.approx((0.2467, 0.6319), abs=1e-4)  # the briefing's numbers
    tau = np.linspace(0, 1, 4001)
    g = gap(p, r.sample(tau * p.T)) / p.x_st
    inside = (tau > a + 1e-6) & (tau < b - 1e-6)
    outside = ((tau < a - 1e-6) | (tau > b + 1e-6)) & (tau > 1e-6) & (tau < 1 - 1e-6)
    assert np.all(g[inside] < 0) and np.all(g[outside] > 0)
    for edge in (a, b):  # the ends are roots of the gap
        assert abs(gap(p, r.sample(edge * p.T))) <= 1e-10 * p.x_st
    assert r.min_gap == pytest.approx(g.min(), abs=1e-4)
    assert r.min_gap <= g.min() + 1e-12
    assert a < r.t_min_gap < b


@pytest.mark.parametrize("gap_value", [-5.8, -2.0, 2.0])
def test_admissible_orbits_never_cross_the_stop(gap_value):
    p = REF.replace(gap=gap_value)
    r = idp.algorithm1(p)
    assert r.admissible and r.negative_gap_intervals == ()
    tau = np.linspace(0, 1, 4001)[1:-1]
    assert np.all(gap(p, r.sample(tau * p.T)) > 0)


def test_no_solution_case_is_clean():
    p = REF.replace(gap=-12.0)
    r = idp.algorithm1(p)
    assert not r.exists and not r.admissible
    assert "no solution" in r.reason and "eq. (16)" in r.reason
    assert abs(p.Delta0) / math.hypot(r.U1, r.U2) > 1
    assert math.isnan(r.eps) and math.isnan(r.S) and r.candidates == ()
    d = r.to_dict()
    assert d["exists"] is False and d["eps"] is None and d["impact_phase"] is None
    json.dumps(d, allow_nan=False)
    with pytest.raises(ValueError, match="no orbit"):
        r.sample(0.0)


# --- Algorithm No. 1 against Algorithm No. 2 ---------------------------------------------------

AGREE = [(1.0, g) for g in (-5.8, -2.0, 0.0, 2.0)] + [
    (0.6, 0.0),
    (0.6, 2.0),
    (0.8, 0.0),
    (0.8, 2.0),
    (1.2, -2.0),
    (1.5, -2.0),
]


@pytest.mark.parametrize("theta, gap_value", AGREE)
def test_algorithms_1_and_2_agree_where_alg1_is_admissible(theta, gap_value):
    p = REF.replace(theta=theta, gap=gap_value)
    r = idp.algorithm1(p)
    assert r.admissible
    s = idp.steady_state(p, backend="python")  # from Algorithm No. 2's step 1
    assert (s.regime, s.period_multiple, s.impacts_per_cycle) == ("single_impact", 1, 1)
    (imp,) = s.impacts
    assert abs(phase_difference(imp.phase, r.impact_phase)) <= 1e-9
    assert imp.velocity == pytest.approx(r.velocity, rel=1e-8)
    assert imp.impulse == pytest.approx(r.S, rel=1e-8)


def test_admissible_but_unstable_orbit_is_not_the_settled_motion():
    """A finding: at theta = 1.2, gap = 2 Algorithm No. 1's orbit is admissible (no negative
    gap) and periodic, but Algorithm No. 2 settles elsewhere (T_c = 2T): admissibility is not
    stability."""
    p = REF.replace(theta=1.2, gap=2.0)
    r = idp.algorithm1(p)
    assert r.admissible
    traj = idp.simulate(p, r.t_impact + 2.5 * p.T, t0=r.t_impact, state=r.state_after, backend="python")
    first = traj.impacts(r.t_impact + 0.5 * p.T)[:2]
    for k, e in enumerate(first, start=1):  # the orbit itself repeats to rounding at first
        assert e.t == pytest.approx(r.t_impact + k * p.T, abs=1e-9 * p.T)
    s = idp.steady_state(p, backend="python")
    assert (s.regime, s.period_multiple) == ("multi_impact", 2)


def onset_gap() -> float:
    """Gap where Algorithm No. 1's orbit first grazes the stop between impacts (min gap 0)."""
    return scipy.optimize.brentq(lambda g: idp.algorithm1(REF.replace(gap=g)).min_gap, -8.8, -9.3, xtol=1e-13)


def test_onset_of_alg1_crossing_inside_and_outside():
    gc = onset_gap()
    inside = REF.replace(gap=gc + 1e-6)
    r = idp.algorithm1(inside)
    assert r.admissible and 0 < r.min_gap < 1e-5
    s = idp.steady_state(inside, t0=r.t_impact, state=r.state_after, backend="python")
    assert s.regime == "single_impact"
    assert abs(phase_difference(s.impacts[0].phase, r.impact_phase)) <= 1e-9

    outside = REF.replace(gap=gc - 1e-6)
    r = idp.algorithm1(outside)
    assert r.exists and not r.admissible and -1e-5 < r.min_gap < 0
    traj = idp.simulate(outside, r.t_impact + 0.9 * outside.T, t0=r.t_impact, state=r.state_after, backend="python")
    (graze,) = traj.impacts()  # the orbit's minimum now dips below the stop: one extra impact
    t_graze = (graze.t - r.t_impact) / outside.T
    ((a, b),) = r.negative_gap_intervals
    assert a == pytest.approx(t_graze, abs=1e-9)
    # closing velocity of a shallow crossing: sqrt(2 |Delta''| depth)
    y = r.sample(r.t_min_gap * outside.T)
    acc = free_rhs(outside)(r.t_impact + r.t_min_gap * outside.T, y)
    v_expected = math.sqrt(2 * abs(acc[2] - acc[3]) * abs(r.min_gap) * outside.x_st)
    assert graze.velocity == pytest.approx(v_expected, rel=1e-2)
    s = idp.steady_state(outside, t0=r.t_impact, state=r.state_after, backend="python")
    assert s.regime != "single_impact"


@pytest.mark.parametrize("gap_value", [-5.8, -10.0, 2.0])
def test_relative_results_do_not_depend_on_m1(gap_value):
    a = idp.algorithm1(REF.replace(gap=gap_value))
    b = idp.algorithm1(REF.replace(gap=gap_value, m1=37.5))
    p, q = a.p, b.p
    assert b.impact_phase == pytest.approx(a.impact_phase, abs=1e-12)
    assert b.velocity / (q.x_st * q.omega) == pytest.approx(a.velocity / (p.x_st * p.omega), rel=1e-9)
    assert b.S / (q.m1 * q.x_st * q.omega) == pytest.approx(a.S / (p.m1 * p.x_st * p.omega), rel=1e-9)
    assert b.min_gap == pytest.approx(a.min_gap, rel=1e-9, abs=1e-12)
    assert np.allclose(b.negative_gap_intervals, a.negative_gap_intervals, rtol=0, atol=1e-9)


def test_repeated_roots_use_the_matrix_form():
    from test_linear import REPEATED

    p = REPEATED.replace(gap=2.0)
    assert not free_mode(p).modal
    r = idp.algorithm1(p)
    assert r.admissible
    s = idp.steady_state(p, backend="python")
    assert s.regime == "single_impact"
    assert abs(phase_difference(s.impacts[0].phase, r.impact_phase)) <= 1e-9


def test_undamped_algorithm1_denominator_is_half_of_one_minus_R():
    """Undamped, the T-periodic pulse response is time-symmetric: the denominator of eq. (15) is
    (1 - R)/2 at every theta, so R = 1 without damping is singular everywhere (the CLI names R)."""
    from impactdamper import Parameters
    from impactdamper.core.algorithm1 import Model, unit_pulse_response

    for R, theta in ((0.0, 0.7), (0.5, 1.1), (0.9, 1.37)):
        p = Parameters(R=R, delta1=0.0, delta2=0.0, theta=theta)
        model = Model(p)
        zT = model.free.free(p.T, unit_pulse_response(p, model))
        assert 1.0 - p.reduced_mass * (1.0 + R) * (zT[3] - zT[2]) == pytest.approx((1.0 - R) / 2.0, abs=1e-12)
