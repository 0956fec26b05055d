"""The settled motion does not depend on ``settle_tol`` beyond its refinement, in both backends.

Closed forms first (the forced amplitudes at large theta, stuck and without contact), then the
regression tests of the bugs this guards (each named), then the property test over random
parameters and tolerances.
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from helpers import REF

import impactdamper as idp
from impactdamper.analysis.orbits import solve_orbit
from impactdamper.analysis.ladder import solve_point
from impactdamper.analysis.point import SweepSettings
from impactdamper.core.backends import get_backend
from impactdamper.core.linear import forced_amplitudes
from impactdamper.core.model import Model
from impactdamper.core.periodicity import X1_MAX_FACTOR
from impactdamper.core.steady import steady_state
from impactdamper.core.validation import SETTLE_TOL_FLOOR, check_settle_call


# The backends: the pure-Python reference, the compiled loop with its compiled description, and
# the compiled loop with the reference's description (the sweeps' ladder's).
def steady_state_compiled(p, **kwargs):
    """The public call on the kernels (the settled cycle described in them)."""
    return idp.steady_state(p, **kwargs, backend="compiled")


def steady_state_described_by_the_reference(p, settle_tol=1e-10, max_periods=4000):
    """The kernels' period loop, the cycle described by the reference (as the ladder asks)."""
    checked = check_settle_call(
        p, 0.0, None, None, settle_tol=settle_tol, max_periods=max_periods, describe="reference"
    )
    return get_backend("compiled")[0].settle(*checked)


BACKENDS = {
    "reference": steady_state,
    "compiled": steady_state_compiled,
    "hybrid": steady_state_described_by_the_reference,
}


def summary(s) -> tuple:
    return s.regime, s.period_multiple, s.impacts_per_cycle


def phases_of(s) -> np.ndarray:
    """The cycle's impact phases."""
    return np.array([i.phase for i in s.impacts])


# --- closed forms: x1_max within the stated factor of settle_tol --------------------------------
def stuck_amplitude(p: idp.Parameters) -> float:
    """|x1| of the joined bodies' forced response (the stuck mode's), over x_st."""
    return abs(Model(p).stuck.Yhat[0]) / p.x_st


def free_amplitude(p: idp.Parameters) -> float:
    """|x1| of the no-contact forced response, over x_st."""
    return abs(forced_amplitudes(p)[0]) / p.x_st


# At theta = 50 the slow mode turns by 0.12 rad per period and decays by 0.6 % per period: the
# period test alone stopped at a turning point of its section differences (stuck: x1_max
# 3.7e-8 x_st = 430 settle_tol off; without contact 2.6e-9).
LARGE_THETA = [
    ("stuck", REF.replace(theta=50.0), stuck_amplitude),
    ("no_contact", REF.replace(theta=50.0, gap=5.8), free_amplitude),
    ("stuck", REF.replace(theta=20.0), stuck_amplitude),
]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("regime, p, amplitude", LARGE_THETA)
@pytest.mark.parametrize("settle_tol", [1e-6, 1e-10])
def test_settle_test_cannot_stop_on_a_turning_point(backend, regime, p, amplitude, settle_tol):
    s = BACKENDS[backend](p, settle_tol=settle_tol)
    assert s.regime == regime
    assert abs(s.x1_max - amplitude(p)) <= X1_MAX_FACTOR * settle_tol


# --- regressions --------------------------------------------------------------------------------
@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize(
    "gap, settle_tol, expected",
    [
        (-5.8, 1e-5, ("single_impact", 1, 1)),
        (-5.8, 1e-4, ("single_impact", 1, 1)),
        (-5.8, 1e-3, ("single_impact", 1, 1)),
        (-10.0, 1e-5, ("multi_impact", 2, 3)),
        (-10.0, 1e-6, ("multi_impact", 2, 3)),
        (-10.0, 1e-7, ("multi_impact", 2, 3)),
    ],
)
def test_loose_settle_tol_does_not_count_an_impact_twice(backend, gap, settle_tol, expected):
    """The cycle's events were taken from [start - 1e-9 T, start + T_c - 1e-9 T), while a cycle
    settled to a loose settle_tol drifts by more than 1e-9 T per period: at the reference case
    and settle_tol 1e-5 one impact was counted twice (phases 2e-8 T apart, multi_impact with 2
    impacts), at gap -10 with 1e-5 to 1e-7 four impacts in 2T instead of 3."""
    s = BACKENDS[backend](REF.replace(gap=gap), settle_tol=settle_tol)
    assert summary(s) == expected
    exact = BACKENDS[backend](REF.replace(gap=gap))
    # A less refined cycle, not a different one: its impacts within the drift of the exact ones.
    assert np.max(np.abs(phases_of(s) - phases_of(exact))) <= 1e3 * settle_tol
    assert abs(s.x1_max - exact.x1_max) <= X1_MAX_FACTOR * settle_tol


@pytest.mark.parametrize("backend", ["compiled", "python"])
def test_response_point_label_does_not_depend_on_settle_tol(backend):
    """``response --settle-tol 1e-5`` labelled theta = 1 as 2/1 (the same impact twice)."""
    point = solve_point(REF, settings=SweepSettings(settle_tol=1e-5, backend=backend))
    assert point.label == "1/1"
    assert len(point.phases) == 1


def test_orbit_seeded_by_a_loosely_settled_simulation_is_the_one_impact_orbit():
    """``orbit --seed simulate --settle-tol 1e-5`` seeded Newton with a phantom second impact
    and returned a 2-impact cycle with closing velocity -7.55, not admissible."""
    o = solve_orbit(REF, "simulate", settle_tol=1e-5)
    exact = idp.algorithm1(REF)
    assert summary(o) == ("single_impact", 1, 1)
    assert o.solved and o.admissible and o.stable
    assert abs(o.impacts[0].phase - exact.impact_phase) <= 1e-9


# --- property: regime, k and z do not depend on settle_tol --------------------------------------
PROPERTY = settings(
    derandomize=True, database=None, deadline=None, max_examples=60, suppress_health_check=[HealthCheck.too_slow]
)


@st.composite
def cases(draw):
    p = REF.replace(
        theta=draw(st.floats(0.5, 2.0)),
        mu=draw(st.floats(0.04, 0.3)),
        N=draw(st.floats(0.3, 1.5)),
        delta1=draw(st.floats(0.02, 0.1)),
        delta2=draw(st.floats(0.02, 0.1)),
        R=draw(st.floats(0.3, 0.9)),
        gap=draw(st.floats(-12.0, 2.0)),
    )
    # (raised to the floor where drawn below it: the calls refuse a settle_tol below SETTLE_TOL_FLOOR)
    settle_tol = max(draw(st.floats(1.0, 9.9)) * 10.0 ** draw(st.integers(-12, -4)), SETTLE_TOL_FLOOR)
    return p, settle_tol


def check_tolerance_independence(settle, p, settle_tol):
    default = settle(p, max_periods=3000)
    if default.regime == "nonperiodic":
        return
    s = settle(p, settle_tol=settle_tol, max_periods=3000)
    assert summary(s) == summary(default), (p, settle_tol)
    assert abs(s.x1_max - default.x1_max) <= X1_MAX_FACTOR * max(settle_tol, 1e-10), (p, settle_tol)


@PROPERTY
@given(case=cases())
def test_regime_k_z_do_not_depend_on_settle_tol_compiled(case):
    check_tolerance_independence(steady_state_compiled, *case)


@pytest.mark.slow
@settings(PROPERTY, max_examples=12)
@given(case=cases())
def test_regime_k_z_do_not_depend_on_settle_tol_reference(case):
    check_tolerance_independence(steady_state, *case)
