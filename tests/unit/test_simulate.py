"""Algorithm No. 2 with the exact flow (simulate.py): the impact law at every impact, no
penetration between events, grazing contacts found and near misses not counted, contact modes."""

import math

import numpy as np
import pytest
import scipy.optimize

from helpers import REF, check_impact_laws, check_no_penetration, contact_force, gap

import impactdamper as idp
from impactdamper.core.linear import forced_amplitudes, free_mode
from impactdamper.core.simulate import default_initial_state

# --- closed forms first ----------------------------------------------------------------------


@pytest.mark.parametrize("m1", [1.0, 37.5])
@pytest.mark.parametrize("gap_value", [-5.8, 2.0])
def test_default_start_is_algorithm2_step1(m1, gap_value):
    p = REF.replace(m1=m1, gap=gap_value)
    x1, x2, v1, v2 = default_initial_state(p)
    assert (x1, x2) == (0.0, p.Delta0)  # gap zero
    assert p.m1 * v1 == pytest.approx(-p.m2 * v2, rel=1e-15)  # equal and opposite momenta
    assert v1 - v2 > 0  # that open the gap (Delta' = x1' - x2' > 0)
    assert p.m1 * v1 == pytest.approx(0.1 * p.m1 * p.omega1 * p.x_st, rel=1e-15)  # 1 N s at m1 = 1


def test_free_flight_without_contact_is_the_linear_flow():
    p = REF.replace(gap=50.0)
    y0 = np.array([0.5, 1.0, -2.0, 3.0])
    traj = idp.simulate(p, 3 * p.T, state=y0, backend="python")
    assert traj.events == []
    t = np.linspace(0, 3 * p.T, 31)
    assert np.array_equal(traj.sample(t)[0], free_mode(p).state(t, 0.0, y0))
    assert set(traj.sample(t)[1]) == {"free"}


@pytest.mark.parametrize("rel", [1e-9, 1e-11])
def test_grazing_forced_orbit_closed_form(rel):
    """The forced periodic response has x2 - x1 = U1 sin(...) (eq. 12): with Delta0 = U1 (1 + rel)
    it misses the stop by rel U1, with Delta0 = U1 (1 - rel) it crosses it with the closing
    velocity U1 omega sqrt(1 - (1 - rel)^2)."""
    x1p, x2p = forced_amplitudes(REF)
    U1 = abs(x2p - x1p)
    for sign in (+1, -1):
        p = REF.replace(gap=U1 * (1 + sign * rel) / REF.x_st)
        y0 = free_mode(p).forced(0.0)
        traj = idp.simulate(p, 1.0 * p.T, state=y0, backend="python")
        if sign > 0:
            assert traj.events == []
            continue
        (e,) = traj.events
        assert e.kind == "impact"
        v = U1 * p.omega * math.sqrt(1 - (1 - rel) ** 2)
        assert e.velocity == pytest.approx(v, rel=1e-3)
        # the crossing is where U1 sin(w t + eps21) = Delta0, just before its maximum
        eps21 = np.angle(x2p - x1p)
        t_max = ((math.pi / 2 - eps21) % (2 * math.pi)) / p.omega
        assert t_max - e.t == pytest.approx(math.sqrt(2 * rel) / p.omega, rel=1e-3)


def _max_relative_displacement(p, y0, t0, t1):
    """Largest x2 - x1 of the free flight on (t0, t1), with its time (exact flow, refined)."""
    mode = free_mode(p)
    ts = np.linspace(t0, t1, 4001)
    d = np.diff(mode.state(ts, t0, y0)[:, :2], axis=1)[:, 0]
    i = int(np.argmax(d))
    if not 20 < i < len(ts) - 20:
        return None
    # the rest of the window must stay clear of the top by far (one touch only)
    far = np.abs(ts - ts[i]) > 0.05 * p.T
    if d[far].max() > d[i] - 1e-3 * p.x_st:
        return None
    res = scipy.optimize.minimize_scalar(
        lambda t: -np.diff(mode.state(t, t0, y0)[:2])[0],
        bounds=(ts[i - 1], ts[i + 1]),
        method="bounded",
        options={"xatol": 1e-13 * p.T},
    )
    return -float(res.fun), float(res.x)


@pytest.mark.parametrize("R", [0.0, 0.7, 1.0])
def test_event_search_never_misses_a_grazing_impact(R):
    """Free flights from random states; Delta0 shifted so that the gap's minimum is +-1e-9 x_st
    (the free motion does not depend on Delta0): the touch is counted, the near miss is not."""
    rng = np.random.default_rng(20190101)
    p0 = REF.replace(R=R, gap=100.0)
    used = 0
    for _ in range(20):
        y0 = rng.uniform(-1, 1, 4) * np.array([5, 5, 80, 80]) * p0.x_st * np.array([1, 1, 1, 1])
        t0 = rng.uniform(0, p0.T)
        found = _max_relative_displacement(p0, y0, t0, t0 + 1.5 * p0.T)
        if found is None:
            continue
        used += 1
        d_max, t_max = found
        for shift, expected in ((+1e-9, 0), (-1e-9, 1)):
            p = p0.replace(gap=(d_max + shift * p0.x_st) / p0.x_st)
            traj = idp.simulate(p, t0 + 1.5 * p.T, t0=t0, state=y0, backend="python")
            assert len(traj.impacts()) == expected, (y0, t0, shift)
            if expected:
                e = traj.impacts()[0]
                assert abs(e.t - t_max) <= 1e-3 * p.T
                assert 0 < e.velocity <= 1e-2 * p.x_st * p.omega
    assert used >= 8


# --- the impact law at every impact, no penetration between events --------------------------

LAW_CASES = [(R, g) for R in (0.0, 0.7, 1.0) for g in (-5.8, 2.0)] + [
    (0.7, -10.0),
    (0.7, -13.0),
    (0.7, -30.0),
    (0.7, -100.0),
    (0.0, -30.0),
]


@pytest.mark.parametrize("R, gap_value", LAW_CASES)
def test_every_event_obeys_the_impact_law_and_the_gap_stays_open(R, gap_value):
    p = REF.replace(R=R, gap=gap_value)
    t_end = 30 * p.T
    traj = idp.simulate(p, t_end, backend="python")
    n = check_impact_laws(p, traj.events)
    assert n > 0 or gap_value == -100.0
    check_no_penetration(p, traj, 0.0, t_end)
    # The gap really was zero at each impact: evaluate the segment that ends there.
    starts = np.array([seg.t0 for _, seg in traj.segments])
    for e in traj.events:
        if e.kind != "impact" or e.t == 0.0:
            continue
        k = int(np.searchsorted(starts, e.t, side="left")) - 1
        mode, seg = traj.segments[k]
        assert mode == "free" and seg.t0 < e.t
        y = seg.state(e.t)
        assert abs(gap(p, y)) <= 1e-12 * p.x_st + 1e-15 * np.max(np.abs(y[:2]))
        assert np.max(np.abs(y[2:] - e.before[2:])) <= 1e-13 * np.max(np.abs(y[2:]))


@pytest.mark.parametrize("gap_value", [-13.0, -30.0])
def test_chatter_sticks_and_lifts_off_where_the_force_vanishes(gap_value):
    p = REF.replace(gap=gap_value)
    traj = idp.simulate(p, 20 * p.T, backend="python")
    kinds = [e.kind for e in traj.events]
    assert "stick" in kinds and "liftoff" in kinds
    fscale = p.m2 * p.x_st * p.omega1**2
    for i, e in enumerate(traj.events):
        if e.kind == "stick":
            # captured only when pressed together, after a rebound below chatter_tol x_st
            prev = traj.events[i - 1]
            F = contact_force(p, e.t, e.after[0], e.after[2])
            assert F > 0
            if prev.kind == "impact" and prev.t == e.t:
                apex = (p.R * prev.velocity) ** 2 / (2 * F / p.reduced_mass)
                assert apex <= 1e-9 * p.x_st
                assert e.t_accumulation >= e.t
        if e.kind == "liftoff":
            assert abs(contact_force(p, e.t, e.before[0], e.before[2])) <= 1e-9 * fscale
            # the gap opens after lift-off
            y = traj.sample(e.t + 1e-3 * p.T)[0]
            assert gap(p, y) > 0


def test_R0_impacts_stick_or_separate_by_the_contact_force():
    p = REF.replace(R=0.0, gap=-5.8)
    traj = idp.simulate(p, 20 * p.T, backend="python")
    ev = traj.events
    for i, e in enumerate(ev):
        if e.kind != "impact":
            continue
        F = contact_force(p, e.t, e.after[0], e.after[2])
        nxt = ev[i + 1] if i + 1 < len(ev) else None
        if F > 1e-9 * p.c2 * p.x_st:
            assert nxt is not None and nxt.kind == "stick" and nxt.t == e.t
        elif F < -1e-9 * p.c2 * p.x_st:
            assert nxt is None or nxt.t > e.t


def test_stuck_regime_never_separates():
    p = REF.replace(gap=-100.0)
    traj = idp.simulate(p, 10 * p.T, backend="python")
    kinds = [e.kind for e in traj.events]
    # the step-1 kick opens the gap, the bounces die out in a chatter, and contact holds
    assert kinds[-1] == "stick" and set(kinds[:-1]) == {"impact"} and len(kinds) > 10
    t0 = traj.events[-1].t
    assert t0 < p.T
    t = np.linspace(t0, 10 * p.T, 2001)
    full, modes = traj.sample(t)
    assert set(modes) == {"stuck"}
    assert np.all(contact_force(p, t, full[:, 0], full[:, 2]) > 0)


def test_start_on_the_stop_closing_is_an_impact_at_t0():
    p = REF.replace(gap=2.0)
    state = np.array([0.1, 0.1 + p.Delta0, -1.0, 4.0])
    traj = idp.simulate(p, p.T, t0=0.3, state=state, backend="python")
    e = traj.events[0]
    assert (e.kind, e.t, e.velocity) == ("impact", 0.3, 5.0)
    check_impact_laws(p, traj.events)


def test_start_inside_gap_tol_is_put_on_the_stop():
    p = REF.replace(gap=2.0)
    state = np.array([0.1, 0.1 + p.Delta0 + 5e-13, -1.0, 4.0])  # overlap below gap_tol
    traj = idp.simulate(p, p.T, state=state, backend="python")
    assert traj.events[0].kind == "impact" and gap(p, traj.events[0].before) == 0.0


@pytest.mark.parametrize("gap_value", [-5.8, -13.0])
def test_events_do_not_depend_on_m1(gap_value):
    a = idp.simulate(REF.replace(gap=gap_value), 15 * REF.T, backend="python")
    b = idp.simulate(REF.replace(gap=gap_value, m1=37.5), 15 * REF.T, backend="python")
    assert [e.kind for e in a.events] == [e.kind for e in b.events]
    # Rounding differs with the scale; the geometric bounce sequences of a chatter amplify it
    # (each bounce's timing error feeds the next), hence 1e-8 on the last bounces' velocities.
    for ea, eb in zip(a.events, b.events):
        assert eb.t == pytest.approx(ea.t, abs=1e-9 * REF.T)
        assert eb.velocity == pytest.approx(ea.velocity, abs=1e-8 * REF.x_st * REF.omega)


# --- validation ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"t_end": 0.0}, "t_end"),
        ({"t_end": math.nan}, "t_end"),
        ({"t_end": 1.0, "state": [0, 0, 0]}, "state"),
        ({"t_end": 1.0, "state": [0, 0, math.nan, 0]}, "state"),
        ({"t_end": 1.0, "state": [0.0, -5.0, 0, 0]}, "state"),
        ({"t_end": 1.0, "t0": math.inf}, "t_end"),
    ],
)
def test_bad_arguments_raise_one_line(kwargs, name):
    with pytest.raises(ValueError) as info:
        idp.simulate(REF, **kwargs, backend="python")
    assert f"`{name}`" in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize("name", ["gap_tol", "chatter_tol", "force_tol"])
@pytest.mark.parametrize("value", [0.0, 1.0, -1e-3, math.nan])
def test_bad_tolerances_raise_one_line(name, value):
    with pytest.raises(ValueError, match=f"^`{name}` = .* must be in \\(0, 1\\)$"):
        idp.Tolerances(**{name: value})


@pytest.mark.parametrize("name", ["gap_tol", "chatter_tol", "force_tol"])
@pytest.mark.parametrize("value", [1e-300, 5e-324, 9.9e-15])
def test_tolerances_below_the_rounding_are_refused_naming_the_floor(name, value):
    """A tolerance below the rounding of the state decides its answer at the last bits (chatter_tol
    1e-300 at gap -28 settled on one CPU and reached the work bound on another): refused up front."""
    with pytest.raises(ValueError, match=f"^`{name}` = {value!r} is not allowed: must be at least 1e-14, the floor"):
        idp.Tolerances(**{name: value})
    assert getattr(idp.Tolerances(**{name: 1e-14}), name) == 1e-14
