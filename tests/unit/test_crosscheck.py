"""The independent solve_ivp cross-check (crosscheck.py): its own closed-form checks first, then
agreement with the exact event-driven solver in every regime and hard case."""

import functools
import math

import numpy as np
import pytest

from helpers import REF, check_impact_laws, check_no_penetration, gap
from test_linear import REPEATED

import impactdamper as idp
from impactdamper.baselines.ivp import METHODS, _IvpTrajectory, methods, simulate_ivp
from impactdamper.core.linear import forced_amplitudes, free_mode

RTOL = 1e-10
# Agreement bounds, scaled by the integrator's tolerance: global error after a few periods of
# ~1e2 steps, each within rtol, and event times carrying that error.
TIME_TOL = 1e3 * RTOL  # in units of T
STATE_TOL = 1e3 * RTOL  # relative to each component's largest magnitude


# --- closed forms first ----------------------------------------------------------------------


def test_methods_are_listed():
    assert METHODS == methods == ("RK45", "DOP853", "Radau", "LSODA")


def test_stuck_motion_is_the_one_mass_oscillator_closed_form():
    """Bodies pressed together at rest on the stop: captured at t0, then
    x1 = Im(X e^{i w t}) + e^{-h t}(A cos wd t + B sin wd t) for (m1 + m2) x'' + k1 x' + c1 x = P0 sin."""
    p = REF.replace(gap=-100.0)
    m = p.m1 + p.m2
    x0, v0 = 2.0, -5.0
    traj = simulate_ivp(p, 3 * p.T, state=[x0, x0 + p.Delta0, v0, v0])
    assert [e.kind for e in traj.events] == ["stick"]
    X = p.P0 / (p.c1 - m * p.omega**2 + 1j * p.omega * p.k1)
    h, wd = p.k1 / (2 * m), math.sqrt(p.c1 / m - (p.k1 / (2 * m)) ** 2)
    A = x0 - X.imag
    B = (v0 - (1j * p.omega * X).imag + h * A) / wd
    t = np.linspace(0, 3 * p.T, 61)
    x_exact = (X * np.exp(1j * p.omega * t)).imag + np.exp(-h * t) * (A * np.cos(wd * t) + B * np.sin(wd * t))
    full, modes = traj.sample(t)
    assert set(modes) == {"stuck"}
    assert np.max(np.abs(full[:, 0] - x_exact)) <= 1e3 * RTOL * np.max(np.abs(x_exact))
    assert np.array_equal(full[:, 1], full[:, 0] + p.Delta0) and np.array_equal(full[:, 2], full[:, 3])


@pytest.mark.parametrize("p", [REF, REF.replace(gap=2.0), REF.replace(gap=0.0, R=1.0), REF.replace(theta=0.8, gap=2.0)])
def test_repeats_algorithm1s_orbit(p):
    """From Algorithm No. 1's post-impact state the impacts come every T with its velocity (eq. 17)."""
    r = idp.algorithm1(p)
    assert r.admissible
    traj = simulate_ivp(p, r.t_impact + 3.5 * p.T, t0=r.t_impact, state=r.state_after)
    impacts = traj.impacts(r.t_impact + 0.5 * p.T)
    assert len(impacts) == 3
    for k, e in enumerate(impacts, start=1):
        assert abs(e.t - r.t_impact - k * p.T) <= TIME_TOL * p.T
        assert e.velocity == pytest.approx(r.velocity, rel=1e3 * RTOL)
    check_impact_laws(p, traj.events)


@pytest.mark.parametrize("method", METHODS)
def test_every_method_repeats_the_orbit(method):
    r = idp.algorithm1(REF)
    traj = simulate_ivp(REF, r.t_impact + 2.5 * REF.T, t0=r.t_impact, state=r.state_after, method=method)
    impacts = traj.impacts(r.t_impact + 0.5 * REF.T)
    assert len(impacts) == 2
    # LSODA's error control is looser than rtol suggests (its norm is an RMS): 1e2 times looser.
    slack = 1e2 if method == "LSODA" else 1.0
    for k, e in enumerate(impacts, start=1):
        assert abs(e.t - r.t_impact - k * REF.T) <= slack * TIME_TOL * REF.T
        assert e.velocity == pytest.approx(r.velocity, rel=slack * 1e3 * RTOL)
    assert traj.nfev == sum(leg.nfev for leg in traj.legs) > 0


@pytest.mark.parametrize("method", METHODS)
def test_every_method_follows_a_chatter_into_contact(method):
    """A cycle of the gap -13 chatter: the bounces accumulate, the bodies are captured, then lift
    off. The last bounces (velocities ~1e-3 x_st omega) are ill-conditioned, and LSODA at
    rtol = 1e-10 captures one bounce early; the capture and lift-off times still agree."""
    p = REF.replace(gap=-13.0)
    s = settled("chatter_k3")
    t0 = math.floor(s.cycle_start / p.T) * p.T
    state = s.trajectory.sample(t0)[0]
    exact = idp.simulate(p, t0 + p.T, t0=t0, state=state, backend="python")
    ivp = simulate_ivp(p, t0 + p.T, t0=t0, state=state, method=method)
    contact = lambda traj: [e for e in traj.events if e.kind != "impact"]  # noqa: E731
    assert [e.kind for e in contact(exact)] == [e.kind for e in contact(ivp)] == ["stick", "liftoff"]
    for a, b in zip(contact(exact), contact(ivp)):
        assert abs(a.t - b.t) <= 1e-5 * p.T
    assert abs(len(exact.events) - len(ivp.events)) <= (1 if method == "LSODA" else 0)
    check_impact_laws(p, ivp.events)


@pytest.mark.parametrize("rel, expected", [(+1e-7, 0), (-1e-7, 1)])
def test_grazing_dip_inside_one_step_is_found(rel, expected):
    """The forced orbit grazing the stop (Delta0 = U1 (1 + rel)): the dip below the stop lasts
    ~2 sqrt(2e-7)/omega, far shorter than a step; the recorded gap minimum catches it."""
    x1p, x2p = forced_amplitudes(REF)
    U1 = abs(x2p - x1p)
    p = REF.replace(gap=U1 * (1 + rel) / REF.x_st)
    traj = simulate_ivp(p, 1.0 * p.T, state=free_mode(p).forced(0.0))
    assert len(traj.impacts()) == expected
    if expected:
        e = traj.impacts()[0]
        assert e.velocity == pytest.approx(U1 * p.omega * math.sqrt(1 - (1 + rel) ** 2), rel=1e-2)


# --- the exact solver and the cross-check agree in every regime ---------------------------------

CASES = {
    # name: (parameters, steady_state kwargs, regime expected)
    "no_contact": (REF.replace(gap=20.0), {}, "no_contact"),
    "stuck": (REF.replace(gap=-100.0), {}, "stuck"),
    "chatter": (REF.replace(gap=-30.0), {}, "chatter"),
    "chatter_k3": (REF.replace(gap=-13.0), {}, "chatter"),
    "single_impact": (REF, {}, "single_impact"),
    "multi_impact": (REF.replace(gap=-10.0), {}, "multi_impact"),
    "nonperiodic": (REF.replace(gap=-11.0), {"max_periods": 300}, "nonperiodic"),
    "R=0": (REF.replace(R=0.0), {}, "chatter"),
    "R=1": (REF.replace(R=1.0), {}, "single_impact"),
    "R=1 gap 2": (REF.replace(R=1.0, gap=2.0), {}, "single_impact"),
    "R=0 gap 2": (REF.replace(R=0.0, gap=2.0), {}, "single_impact"),
    "zero damping": (REF.replace(delta1=0.0, delta2=0.0), {}, "single_impact"),
    "repeated roots": (REPEATED.replace(gap=2.0), {}, "single_impact"),
    "gap 0": (REF.replace(gap=0.0), {}, "single_impact"),
    "light damping": (REF.replace(delta1=1e-3, delta2=1e-3), {}, "single_impact"),
    "mu=1e-4": (REF.replace(mu=1e-4), {}, "single_impact"),
    "N=50": (REF.replace(N=50.0), {}, "stuck"),
    "theta=0.1": (REF.replace(theta=0.1), {}, "stuck"),
    "theta=10": (REF.replace(theta=10.0), {}, "stuck"),
}


@functools.cache
def settled(name):
    p, kwargs, _ = CASES[name]
    return idp.steady_state(p, **kwargs, backend="python")


def _compare(p, exact, ivp, t0, t1):
    ke = [e.kind for e in exact.events if t0 <= e.t <= t1]
    ki = [e.kind for e in ivp.events if t0 <= e.t <= t1]
    assert ke == ki
    vscale = p.x_st * max(p.omega, p.omega1)
    for a, b in zip(exact.events, ivp.events):
        assert abs(a.t - b.t) <= TIME_TOL * p.T, (a, b)
        # velocities and pulses: relative to the largest velocity of the run
        assert abs(a.velocity - b.velocity) <= 1e4 * RTOL * vscale, (a, b)
    ts = np.linspace(t0, t1, 1001)
    ev = np.array([e.t for e in exact.events] + [e.t for e in ivp.events])
    if ev.size:  # the states jump at events: compare away from them
        ts = ts[np.min(np.abs(ts[:, None] - ev[None, :]), axis=1) > 1e-6 * p.T]
    a, ma = exact.sample(ts)
    b, mb = ivp.sample(ts)
    assert np.array_equal(ma, mb)
    scale = np.max(np.abs(a), axis=0)
    scale[:2] = max(scale[:2].max(), p.x_st)
    scale[2:] = max(scale[2:].max(), vscale)
    assert np.all(np.max(np.abs(a - b), axis=0) <= STATE_TOL * scale)


@pytest.mark.parametrize("name", CASES)
def test_exact_solver_and_crosscheck_agree(name):
    p, _, regime = CASES[name]
    s = settled(name)
    assert s.regime == regime
    T = p.T
    t0 = math.floor(s.cycle_start / T) * T  # a section of the settled motion (not an event)
    state = s.trajectory.sample(t0)[0]
    span = min(3 * max(s.period_multiple, 1), 3) * T
    exact = idp.simulate(p, t0 + span, t0=t0, state=state, backend="python")
    ivp = simulate_ivp(p, t0 + span, t0=t0, state=state, rtol=RTOL, atol=RTOL * p.x_st)
    _compare(p, exact, ivp, t0, t0 + span)
    check_impact_laws(p, ivp.events)
    # the cross-check's own gap: never below its event shift plus its integration error
    check_no_penetration(p, ivp, t0, t0 + span, per_period=200, gap_tol=1e3 * RTOL)


def test_agree_through_the_transient_from_step1():
    """The reference case from Algorithm No. 2's step 1: the transient's chatter, its capture
    and lift-off, then the impacts converging on the orbit."""
    t1 = 6 * REF.T
    exact = idp.simulate(REF, t1, backend="python")
    ivp = simulate_ivp(REF, t1)
    assert {"impact", "stick", "liftoff"} <= {e.kind for e in exact.events}
    _compare(REF, exact, ivp, 0.0, t1)


# --- arguments ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"p": "reference"}, "p"),
        ({"t_end": 0.0}, "t_end"),
        ({"t_end": math.inf}, "t_end"),
        ({"t_end": "1"}, "t_end"),
        ({"t0": math.nan}, "t0"),
        ({"method": "BDF"}, "method"),
        ({"method": "dop853"}, "method"),
        ({"rtol": 0.0}, "rtol"),
        ({"rtol": 1e-20}, "rtol"),
        ({"rtol": 1.0}, "rtol"),
        ({"rtol": math.nan}, "rtol"),
        ({"atol": 0.0}, "atol"),
        ({"atol": -1e-10}, "atol"),
        ({"atol": math.inf}, "atol"),
        ({"tolerances": {"gap_tol": 1e-12}}, "tolerances"),
        ({"max_events": 0}, "max_events"),
        ({"max_events": 2.5}, "max_events"),
        ({"state": [0.0, 0.0]}, "state"),
        ({"state": [0.0, -5.8, math.nan, 0.0]}, "state"),
        ({"state": ["a", 0, 0, 0]}, "state"),
        ({"state": [0.0, -5.0, 0.0, 0.0]}, "state"),
        ({"sample_times": [0.5, 0.2]}, "sample_times"),
        ({"sample_times": [0.0, 2.0]}, "sample_times"),
        ({"sample_times": [math.nan]}, "sample_times"),
    ],
)
def test_bad_arguments_raise_one_line(kwargs, name):
    args = {"p": REF, "t_end": 1.0}
    args.update(kwargs)
    with pytest.raises(ValueError) as info:
        simulate_ivp(**args)
    message = str(info.value)
    assert f"`{name}`" in message and "\n" not in message


def test_max_events_guards_the_loop():
    with pytest.raises(RuntimeError, match="max_events"):
        simulate_ivp(REF.replace(gap=-30.0), 2 * REF.T, max_events=5)


def test_sample_outside_the_run_is_refused():
    traj = simulate_ivp(REF, 0.5 * REF.T)
    assert isinstance(traj, _IvpTrajectory)
    with pytest.raises(ValueError, match="`t`"):
        traj.sample(np.array([0.6 * REF.T]))
    full, modes = traj.sample(np.array([0.0, 0.5 * REF.T]))
    assert full.shape == (2, 4) and modes.shape == (2,)
    assert gap(REF, full[0]) == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("p", [REF, REF.replace(gap=-20.0), REF.replace(gap=-31.0), REF.replace(gap=2.0)])
def test_sample_times_are_the_states_sampled_afterwards(p):
    """States recorded during the run at sample_times (free flight, chatter, persistent contact)
    are those its legs, integrated again with dense output, give afterwards: the same steps,
    except a leg's last one, clipped at its event (then within the integrator's tolerance)."""
    times = p.T * np.arange(41)
    traj = simulate_ivp(p, 41 * p.T, sample_times=times)
    full, modes = traj.sample(times)
    scale = np.array([p.x_st, p.x_st, p.x_st * p.omega, p.x_st * p.omega])
    assert np.all(np.isfinite(traj.samples))
    assert np.max(np.abs(traj.samples - full) / scale) <= 1e-9
    assert list(traj.sample_modes) == list(modes)


def test_sample_times_do_not_change_the_run():
    """Recording samples leaves the events as they are (t_eval does not change the steps)."""
    p = REF.replace(gap=-20.0)
    a = simulate_ivp(p, 20 * p.T)
    b = simulate_ivp(p, 20 * p.T, sample_times=p.T * np.arange(21))
    assert [(e.kind, e.t) for e in a.events] == [(e.kind, e.t) for e in b.events]


def _random_parameters(rng):
    return idp.Parameters(
        theta=float(rng.uniform(0.5, 2.0)),
        mu=float(10 ** rng.uniform(-2, -0.5)),
        N=float(rng.uniform(0.3, 2.0)),
        delta1=float(rng.uniform(0, 0.2)),
        delta2=float(rng.uniform(0, 0.2)),
        R=float(rng.choice([0.0, 0.3, 0.7, 1.0])),
        gap=float(rng.uniform(-20, 5)),
    )


@pytest.mark.parametrize("seed", range(12))
def test_agree_on_random_parameters_from_step1(seed):
    """Random cases (fixed seeds) through their transients. With R = 1 and a negative gap the
    bodies rattle (hundreds of elastic impacts per period); the integrator's error then grows
    along the sequence, so only the first 300 events are compared, to 1e-6 T."""
    p = _random_parameters(np.random.default_rng(seed))
    t1 = 4 * p.T
    exact = idp.simulate(p, t1, backend="python")
    ivp = simulate_ivp(p, t1)
    n = min(len(exact.events), len(ivp.events), 300)
    if n < 300:
        assert len(exact.events) == len(ivp.events)
    assert [e.kind for e in exact.events[:n]] == [e.kind for e in ivp.events[:n]]
    for a, b in zip(exact.events[:n], ivp.events[:n]):
        assert abs(a.t - b.t) <= 1e-6 * p.T
        assert abs(a.velocity - b.velocity) <= 1e-5 * p.x_st * max(p.omega, p.omega1)
