"""The high-precision (mpmath) reference, and the double-precision library against it."""

import math

import mpmath
import numpy as np
import pytest
from mpmath import mp

import impactdamper as I
from impactdamper.core.model import Model
from impactdamper.baselines import highprecision as H
from impactdamper.core.linear import characteristic_roots

P = I.Parameters()
N_IMPACTS = 10
# Agreement asked of the double-precision library in impact phase (units of T).
PHASE_TOL = 1e-12
# Repeated roots of eq. (4): the double root (N, delta2) solved in mpmath, rounded to double.
REPEATED = I.Parameters(N=0.9, delta2=0.8829865207640838, gap=2.0)


@pytest.fixture(scope="module")
def reference_impacts():
    traj = I.simulate(P, 0.695 * P.T)
    est = [e.t for e in traj.impacts()][:N_IMPACTS]
    return est, H.first_impacts(P, N_IMPACTS, estimates=est)


@pytest.fixture(scope="module")
def cycle():
    return H.settled_cycle(P)


# --- the mpmath closed form itself ---------------------------------------------------------
def test_mp_eigenvalues_are_roots_of_eq4():
    m = H.MPModel(P)
    a1 = H.algorithm1_mp(P)
    with mp.workdps(m.dps):
        for lam in m.roots:
            assert min(abs(lam - r) for r in a1.roots) < mp.mpf(10) ** (-30)
    np.testing.assert_allclose(
        np.sort_complex(np.array([complex(r) for r in m.roots])), np.sort_complex(characteristic_roots(P)), rtol=1e-13
    )


@pytest.mark.parametrize("p", [P, REPEATED], ids=["reference", "repeated_roots"])
def test_mp_flow_satisfies_the_ode(p):
    m = H.MPModel(p)
    y0 = [0.3, p.Delta0 - 0.2, 1.5, -2.0]
    seg = m.segment(0.1, y0)
    with mp.workdps(m.dps):
        t = mp.mpf("0.37")
        y = seg.state(t)
        # central difference: truncation ~h^2 |y'''| / 6 ~ 1e-23, rounding ~1e-40 / h ~ 1e-27
        h = mp.mpf(10) ** (-13)
        up, down = seg.state(t + h), seg.state(t - h)
        dy = [(up[i] - down[i]) / (2 * h) for i in range(4)]
        rhs = m.M * y + m.b * mp.sin(m.omega * t)
        assert max(abs(dy[i] - rhs[i]) for i in range(4)) < mp.mpf(10) ** (-18)
        assert max(abs(seg.state(seg.t0)[i] - mp.mpf(y0[i])) for i in range(4)) < mp.mpf(10) ** (-30)
        # the gap and its rate are those of the state
        assert abs(seg.gap(t) - m.gap_of(y)) < mp.mpf(10) ** (-30)
        assert abs(seg.gap_rate(t) - (dy[0] - dy[1])) < mp.mpf(10) ** (-18)


def test_matrix_exponential_path_agrees_with_the_modal_form():
    m = H.MPModel(P)
    y0 = [0.3, P.Delta0 - 0.2, 1.5, -2.0]
    modal = m.segment(0.1, y0)
    m_expm = H.MPModel(P)
    m_expm.modal = False  # force mpmath.expm (what an ill-conditioned eigenbasis would use)
    expm = m_expm.segment(0.1, y0)
    with mp.workdps(m.dps):
        t = mp.mpf("0.45")
        assert max(abs(modal.state(t)[i] - expm.state(t)[i]) for i in range(4)) < mp.mpf(10) ** (-30)
        assert abs(modal.gap_rate(t) - expm.gap_rate(t)) < mp.mpf(10) ** (-30)
        assert expm.K > 0
    # and its certified search finds the same first impact
    r1, _ = modal.certified_first_root(0.1, 0.1 + P.T)
    r2, _ = expm.certified_first_root(0.1, 0.1 + P.T)
    assert (r1 is None) == (r2 is None)
    if r1 is not None:
        assert abs(r1 - r2) < mp.mpf(10) ** (-30)


def test_repeated_roots_take_the_matrix_exponential_only_where_needed():
    # In mpmath the 1e-8 split of the double root costs 8 of 40 digits: the modal form stays.
    assert H.MPModel(REPEATED).modal
    assert not Model(REPEATED).free.modal  # double precision switches to expm


def test_mp_impacts_obey_the_impact_law(reference_impacts):
    _, imps = reference_impacts
    m = H.MPModel(P)
    with mp.workdps(m.dps):
        for e in imps:
            assert abs(m.gap_of(e.before)) < mp.mpf(10) ** (-35)
            v_after = e.after[3] - e.after[2]
            assert abs(v_after + m.R * e.velocity) < mp.mpf(10) ** (-35)
            mom = lambda y: m.m1 * y[2] + m.m2 * y[3]  # noqa: E731
            assert abs(mom(e.after) - mom(e.before)) < mp.mpf(10) ** (-35)
            assert e.velocity > 0


def test_estimates_only_bracket_the_roots(reference_impacts):
    est, imps = reference_impacts
    assert all(e.estimate_confirmed for e in imps)
    free = H.first_impacts(P, 4)  # the certified scan alone
    assert max(abs(a.t - b.t) for a, b in zip(free, imps)) < mpmath.mpf(10) ** (-35)


def test_a_wrong_estimate_does_not_fool_the_reference(reference_impacts):
    # Give the second impact's time as the estimate of the first: the scan finds the first.
    est, imps = reference_impacts
    wrong = H.first_impacts(P, 1, estimates=[est[1]])
    assert wrong[0].estimate_confirmed is False
    assert abs(wrong[0].t - imps[0].t) < mpmath.mpf(10) ** (-35)


def test_bad_arguments_name_the_parameter():
    with pytest.raises(ValueError, match="`dps`"):
        H.MPModel(P, dps=10)
    with pytest.raises(ValueError, match="`n`"):
        H.first_impacts(P, 0)


# --- the double-precision library against the reference -------------------------------------
def test_first_impacts_agree_to_1e12_in_phase(reference_impacts):
    est, imps = reference_impacts
    assert len(est) == N_IMPACTS
    errors = [abs(float(e.t) - t) / P.T for e, t in zip(imps, est)]
    assert max(errors) < PHASE_TOL
    # and the velocities, relative to x_st omega
    traj_v = [e.velocity for e in I.simulate(P, 0.695 * P.T).impacts()][:N_IMPACTS]
    v_err = [abs(float(e.velocity) - v) / (P.x_st * P.omega) for e, v in zip(imps, traj_v)]
    assert max(v_err) < 1e-11


def test_settled_cycle_two_routes_agree(cycle):
    assert cycle.alg1_difference < mpmath.mpf(10) ** (-30)
    assert cycle.newton_residual < mpmath.mpf(10) ** (-30)


def test_steady_state_matches_the_mp_cycle(cycle):
    s = I.steady_state(P)
    assert s.regime == "single_impact"
    assert abs(s.impacts[0].phase - float(cycle.impact_phase)) < PHASE_TOL
    # the state on the settled orbit, half a period after the impact
    t = s.impacts[0].t + 0.5 * P.T
    full, _ = s.trajectory.sample(t)
    ref = H.to_float(cycle.state(t))
    scale = np.array([1.0, 1.0, P.omega, P.omega]) * P.x_st
    # what is left of the transient is of the order of the settling tolerance (1e-10)
    assert np.max(np.abs(full - ref) / scale) < 1e-8


@pytest.mark.parametrize("gap", [-5.8, -10.0, -3.0, 0.0, 1.0, -20.0])
def test_algorithm1_double_vs_mp(gap):
    p = P.replace(gap=gap)
    a = I.algorithm1(p)
    b = H.algorithm1_mp(p)
    assert a.exists == b.exists
    if not a.exists:
        return
    assert abs(a.impact_phase - float(b.impact_phase)) < PHASE_TOL
    assert math.isclose(a.S, float(b.S), rel_tol=1e-11)
    for (e1, s1), (e2, s2) in zip(a.candidates, b.candidates):
        assert abs(e1 - float(e2)) < 2 * math.pi * PHASE_TOL and math.isclose(
            s1, float(s2), rel_tol=1e-10, abs_tol=1e-12
        )
    scale = np.array([1.0, 1.0, p.omega, p.omega]) * p.x_st
    assert np.max(np.abs(a.state_after - H.to_float(b.state_after)) / scale) < 1e-11


def test_algorithm1_near_repeated_roots_double_vs_mp():
    # Double precision takes the matrix form of eq. (7) there; mpmath keeps the paper's modal
    # form of eq. (8), the 1e-8 split of the roots costing 8 of its 40 digits.
    a = I.algorithm1(REPEATED)
    b = H.algorithm1_mp(REPEATED)
    assert a.exists and b.exists
    assert abs(a.impact_phase - float(b.impact_phase)) < PHASE_TOL
    assert math.isclose(a.S, float(b.S), rel_tol=1e-10)
