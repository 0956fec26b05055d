"""The stroboscopic map and Newton's method on it (impactdamper.analysis.strobe).

Closed forms first (the section coordinates and their inverse, the persistent-contact motion's
fixed point and multipliers, both the forced response of one linear mode); then Algorithm
No. 1's orbit, whose state and multipliers the saltation-matrix shooting gives independently.
"""

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.analysis.transitions import stuck_liftoff_gap
from impactdamper.core.model import FREE, STUCK, Model
from impactdamper.core.parameters import state_scale
from impactdamper.analysis.strobe import (
    STROBE_FD_STEP,
    STROBE_TOL,
    _section_coordinates,
    _section_state,
    strobe_newton,
    stroboscopic_jacobian,
    _stroboscopic_map,
    stroboscopic_step,
)

REF = idp.REFERENCE
TOL = idp.Tolerances()
# Offset of the Newton start from the fixed point, relative (x_st, x_st omega): well outside
# STROBE_TOL, well inside Newton's basin.
START_OFFSET = 1e-3


@pytest.fixture(scope="module")
def single():
    """Algorithm No. 1's orbit at the reference case, solved by shooting (stable, 1 impact)."""
    return idp.solve_orbit(REF, "alg1")


@pytest.fixture(scope="module")
def stuck_case():
    """A gap 2 x_st below the lift-off threshold: the joined bodies' forced response."""
    p = REF.replace(gap=stuck_liftoff_gap(REF) - 2.0)
    model = Model(p)
    return p, model, model.full_state(STUCK, model.stuck.forced(0.0))


# --- closed forms ---------------------------------------------------------------------------
def test_state_scale_is_x_st_and_x_st_omega():
    p = REF.replace(x_st=2.5, omega=7.0)
    assert state_scale(p).tolist() == [2.5, 2.5, 17.5, 17.5]


@pytest.mark.parametrize("stuck", [False, True])
def test_section_coordinates_round_trip(stuck):
    p = REF
    x1, v1 = -3.0 * p.x_st, 2.0 * p.x_st * p.omega
    full = (
        np.array([x1, x1 + p.Delta0, v1, v1])
        if stuck
        else np.array([x1, x1 + p.Delta0 - 0.4 * p.x_st, v1, v1 + 0.3 * p.x_st * p.omega])
    )
    u = _section_coordinates(p, full, stuck)
    assert u.shape == ((2,) if stuck else (4,))
    if not stuck:
        assert u[1] == pytest.approx(-0.4, rel=1e-14)  # minus the gap of eq. (20), over x_st
    back = _section_state(p, u, stuck)
    assert np.max(np.abs((back - full) / state_scale(p))) <= 1e-14


def test_section_state_never_closes_the_gap():
    u = np.array([0.0, 0.25, 0.0, 0.0])  # a positive coordinate is an overlap of the bodies
    full = _section_state(REF, u, False)
    assert REF.Delta0 - (full[1] - full[0]) == 0.0


def test_stroboscopic_map_is_the_step_without_its_mode(single):
    y = single.state(0.0)
    state, mode = stroboscopic_step(REF, 0.0, y, 1, TOL)
    assert mode == FREE
    assert np.array_equal(state, _stroboscopic_map(REF, 0.0, y, 1, TOL))


def test_newton_on_the_stop_finds_the_forced_response(stuck_case):
    p, model, fixed = stuck_case
    start = fixed + START_OFFSET * state_scale(p)
    res = strobe_newton(p, start, STUCK, 1, TOL)
    assert res is not None
    assert res.jacobian.shape == (2, 2)  # (x1, v1): the state on the stop
    err = np.max(np.abs((res.state - fixed) / state_scale(p)))
    assert err <= 1e3 * STROBE_TOL, err
    # Multipliers of the joined bodies: the eigenvalues of e^{M T} of the stuck mode.
    exact = float(np.max(np.abs(np.linalg.eigvals(model.stuck.propagator(p.T)))))
    assert abs(res.spectral_radius - exact) <= 1e3 * STROBE_FD_STEP, (res.spectral_radius, exact)
    assert res.periods >= 4  # the map, a 2-column difference Jacobian, at least one step


# --- against the saltation-matrix shooting -------------------------------------------------
def test_newton_converges_to_algorithm1_orbit(single):
    y = single.state(0.0)
    res = strobe_newton(REF, y + START_OFFSET * state_scale(REF), FREE, 1, TOL)
    assert res is not None
    err = np.max(np.abs((res.state - y) / state_scale(REF)))
    assert err <= 1e3 * STROBE_TOL, err
    # The Broyden-updated Jacobian carries the start's offset: its multiplier to ~START_OFFSET.
    assert abs(res.spectral_radius - single.spectral_radius) <= 0.1 * START_OFFSET


def test_fresh_jacobian_multipliers_match_saltation(single):
    y = single.state(0.0)
    res = strobe_newton(REF, y, FREE, 1, TOL)
    # Forward differences of step STROBE_FD_STEP: error ~STROBE_FD_STEP (curvature) plus rounding.
    assert abs(res.spectral_radius - single.spectral_radius) <= 10 * STROBE_FD_STEP
    assert res.periods == 5  # the residual (converged already) and 4 difference columns
    # The central-difference check of the same map, to its step squared.
    J = stroboscopic_jacobian(REF, 0.0, y, 1, tolerances=TOL)
    assert abs(float(np.max(np.abs(np.linalg.eigvals(J)))) - single.spectral_radius) <= 1e-7


def test_a_reused_jacobian_costs_one_map_evaluation(single):
    first = strobe_newton(REF, single.state(0.0), FREE, 1, TOL)
    again = strobe_newton(REF, first.state, FREE, 1, TOL, jacobian=first.jacobian)
    assert again.periods == 1
    assert again.spectral_radius == first.spectral_radius
    assert np.array_equal(again.state, first.state)


def test_failure_is_none_not_an_exception():
    assert strobe_newton(REF, np.array([np.nan, 0.0, 0.0, 0.0]), FREE, 1, TOL) is None
